"""Every spec problem reaching Python is a SpecError naming its key, and Ctrl-C stops a long run."""
import os
import signal
import subprocess
import sys
import time

import pytest

import mesodpd
from conftest import SMALL


@pytest.mark.parametrize("value", [2**70, 2**63, -(2**63) - 1])
def test_an_integer_too_large_for_toml_names_its_key(value):
    with pytest.raises(mesodpd.SpecError) as e:
        mesodpd.Spec(run={"steps": value}).validate()
    assert e.value.key == "run.steps" and str(value) in str(e.value)
    with pytest.raises(mesodpd.SpecError) as e:
        mesodpd.Spec(system={"box": [8, 8, 2**64]}).to_toml()
    assert e.value.key == "system.box[2]"


def test_steps_argument_out_of_range_names_run_steps():
    with pytest.raises(mesodpd.SpecError) as e:
        mesodpd.Simulation.from_string(SMALL, steps=2**70)
    assert e.value.key == "run.steps"
    sim = mesodpd.Simulation.from_string(SMALL)
    with pytest.raises(ValueError):
        sim.step(2**70)
    with pytest.raises(ValueError):
        sim.run(2**64)


def test_a_binary_file_is_a_spec_error(tmp_path):
    path = tmp_path / "image.toml"
    path.write_bytes(bytes(range(256)))
    with pytest.raises(mesodpd.SpecError) as e:
        mesodpd.Spec.from_toml(path)
    assert "not UTF-8" in str(e.value) and str(path) in str(e.value) and e.value.key is None


def test_a_restart_with_another_seed_or_dt_names_the_key(tmp_path):
    sim = mesodpd.Simulation.from_string(SMALL)
    sim.step(5)
    sim.write_checkpoint(tmp_path / "c.mdpd")
    for section, key, value in (("system", "seed", 8), ("integrator", "dt", 0.03)):
        spec = mesodpd.Spec.from_string(SMALL)
        spec[section][key] = value
        with pytest.raises(mesodpd.SpecError) as e:
            mesodpd.Simulation(spec, restart=tmp_path / "c.mdpd")
        assert e.value.key == f"{section}.{key}", str(e.value)


def test_two_simulations_with_the_same_output_folder_are_refused(tmp_path):
    first = mesodpd.Simulation.from_string(SMALL, out=tmp_path / "S")
    with pytest.raises(mesodpd.SpecError) as e:
        mesodpd.Simulation.from_string(SMALL, out=tmp_path / "S")
    assert "is in use by another simulation of this process" in str(e.value), str(e.value)
    first.step(2)  # the first one keeps its folder and runs on
    first.close()
    with mesodpd.Simulation.from_string(SMALL, out=tmp_path / "S") as again:  # free again once it is closed
        again.step(1)
    mesodpd.Simulation.from_string(SMALL, out=tmp_path / "S").step(1)


CTRL_C_RUN = """
import mesodpd
spec = mesodpd.Spec(system={"box": [15.0, 15.0, 15.0], "seed": 1}, species=[{"name": "A", "density": 3.0}],
                    pair={"a": 25.0, "gamma": 4.5}, integrator={"dt": 0.04}, run={"steps": 10**8})
sim = mesodpd.Simulation(spec, threads=1)
print("running", sim.n_particles, flush=True)
sim.run()
print("finished", flush=True)
"""


def test_ctrl_c_stops_a_run_without_callbacks():
    env = dict(os.environ, OMP_NUM_THREADS="1")
    proc = subprocess.Popen([sys.executable, "-c", CTRL_C_RUN], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, env=env)
    try:
        line = proc.stdout.readline()
        assert line.startswith("running 10125"), line + proc.stderr.read()
        time.sleep(1.0)
        sent = time.monotonic()
        proc.send_signal(signal.SIGINT)
        try:
            out, err = proc.communicate(timeout=15)
        except subprocess.TimeoutExpired:
            pytest.fail("the run ignored SIGINT for 15 s")
        waited = time.monotonic() - sent
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    assert "KeyboardInterrupt" in err and "finished" not in out, err
    assert proc.returncode != 0 and waited < 5, (proc.returncode, waited)
