"""Simulation from Python: same bits as the command line, particle state, callbacks, checkpoints,
results as arrays."""
import filecmp
import os
import subprocess

import numpy as np
import pytest

import mesodpd
from conftest import SMALL


def _files(d):
    # Leaves out the lock file that a live run holds in its output folder (mesodpd.lock).
    return sorted(f for f in os.listdir(d) if os.path.isfile(os.path.join(d, f)) and f != "mesodpd.lock")


def test_python_and_command_line_write_the_same_bytes(small_toml, tmp_path, mesodpd_bin):
    cli = tmp_path / "cli"
    subprocess.run([mesodpd_bin, "run", str(small_toml), "--out", str(cli), "--no-progress", "--threads", "1"],
                   check=True, capture_output=True)
    py = tmp_path / "py"
    sim = mesodpd.Simulation.from_toml(small_toml, out=py, threads=2)
    # Reading the state from callbacks must not change the trajectory.
    sim.add_callback(lambda s: (s.thermo(), s.snapshot(), s.rdf(), s.particles.x.sum()) and None, every=7)
    summary = sim.run()
    assert "viscosity" in summary
    names = _files(cli)
    assert names == _files(py)
    assert {"thermo.csv", "checkpoint.mdpd", "trajectory.gsd", "rdf.csv", "msd.csv", "viscosity.json",
            "poiseuille_profile.csv", "velocity_profile.svg"} <= set(names)
    _, mismatch, errors = filecmp.cmpfiles(cli, py, names, shallow=False)
    assert mismatch == [] and errors == []


def test_a_spec_built_from_dicts_runs_the_same_as_the_file(small_toml, tmp_path):
    a = mesodpd.Simulation.from_toml(small_toml, out=tmp_path / "a")
    a.run()
    data = mesodpd.Spec.from_toml(small_toml).data
    b = mesodpd.Simulation(mesodpd.Spec(**data), out=tmp_path / "b")
    b.run()
    assert (tmp_path / "a" / "checkpoint.mdpd").read_bytes() == (tmp_path / "b" / "checkpoint.mdpd").read_bytes()


def test_local_arrays_follow_the_run():
    sim = mesodpd.Simulation.from_string(SMALL)
    p = sim.particles
    x0 = p.x
    assert x0.dtype == np.float64 and len(x0) == len(p) == sim.n_particles == 864
    assert not x0.flags.writeable
    assert np.shares_memory(p.x, p.x)  # two reads in one step: one copy (test_views.py has the rest)
    with pytest.raises(ValueError):
        x0[0] = 1.0
    before = dict(zip(p.id.tolist(), p.x.tolist()))
    sim.step(3)
    # Read after the steps, the arrays show the new state, which the gathered id-ordered copy confirms.
    snap = sim.snapshot()
    assert np.array_equal(snap["id"], np.arange(1, 865, dtype=np.uint32))
    order = np.argsort(p.id)
    for name in ("x", "y", "z", "vx", "vy", "vz", "fx", "fy", "fz", "ix"):
        assert np.array_equal(getattr(p, name)[order], snap[name]), name
    after = dict(zip(p.id.tolist(), p.x.tolist()))
    assert sum(before[i] != after[i] for i in before) > 800
    assert p.position.shape == (864, 3) and np.array_equal(p.position[:, 0], p.x)
    # Momentum across the driven flow is conserved to round-off (antisymmetric pair forces).
    assert np.abs(sim.thermo()["momentum"][1:]).max() < 1e-9


def test_a_callback_stops_the_run():
    sim = mesodpd.Simulation.from_string(SMALL)
    seen = []

    def cb(s):
        seen.append(s.current_step)
        return np.bool_(s.current_step >= 30)  # a true value stops, numpy's too

    first = sim.add_callback(cb, every=10)
    assert sim.run() is None and sim.stopped
    assert sim.current_step == 30 and seen == [10, 20, 30]

    def stop(s):
        raise mesodpd.StopRun

    h = sim.add_callback(stop, every=5)
    sim.step(100)
    assert sim.current_step == 35 and sim.stopped
    sim.remove_callback(h)
    sim.remove_callback(first)
    sim.run()
    assert sim.current_step == sim.final_step == 60 and not sim.stopped


def test_checkpoint_and_restart_continue_bit_identically(tmp_path):
    full = mesodpd.Simulation.from_string(SMALL, record=False)
    full.run()
    end = full.snapshot()

    first = mesodpd.Simulation.from_string(SMALL)
    first.step(25)
    first.write_checkpoint(tmp_path / "c.mdpd")
    second = mesodpd.Simulation.from_string(SMALL, restart=tmp_path / "c.mdpd")
    assert second.current_step == 25
    second.run()
    again = second.snapshot()
    for k in end:
        assert np.array_equal(end[k], again[k]), k


def test_thermo_history_and_analyses_as_arrays():
    sim = mesodpd.Simulation.from_string(SMALL)  # record=True: results without an output directory
    sim.run()
    h = sim.thermo_history()
    assert list(h["step"]) == list(range(0, 61, 10))
    assert h["pressure_tensor"].shape == (7, 6) and h["momentum"].shape == (7, 3)
    # The random start heats the fluid; it cools back towards kT = 1.
    assert np.all(np.diff(h["temperature"][1:]) < 0) and abs(h["temperature"][-1] - 1) < 0.1
    t = sim.thermo()
    assert t["step"] == 60 and t["temperature"] == pytest.approx(h["temperature"][-1], rel=1e-12)
    prof = sim.profile()
    assert prof["samples"] == 50 and len(prof["z"]) == 8 and np.isfinite(prof["eta"])
    g = sim.rdf()
    assert g["samples"] == 7 and len(g["r"]) == 30
    assert g["g"][0] < 0.2 and abs(g["g"][-5:].mean() - 1) < 0.1  # excluded core, flat far away
    m = sim.msd()
    assert m["time"][0] == 0 and np.all(np.diff(m["msd"]) > 0)
    f = sim.fields()["layers"]
    assert f["bins"] == (1, 1, 8) and f["samples"] == 7 and f["density"].shape == (1, 1, 8)
    assert f["density"].mean() == pytest.approx(3.0, rel=1e-12)  # every particle in some layer
    assert np.allclose(f["z"][0, 0], np.arange(8) + 0.5)
    none = mesodpd.Simulation.from_string(SMALL, record=False)
    none.step(10)
    assert len(none.thermo_history()["step"]) == 0 and none.rdf() is None


def test_blow_up_is_a_python_exception():
    spec = mesodpd.Spec.from_string(SMALL)
    spec["run"]["max_velocity"] = 0.5  # thermal speeds exceed it at once
    sim = mesodpd.Simulation(spec)
    with pytest.raises(mesodpd.BlowUpError) as err:
        sim.step(5)
    assert err.value.step == 1 and err.value.particle_id >= 1 and "blew up" in str(err.value)


def test_plot_helpers_draw(tmp_path):
    pytest.importorskip("matplotlib")
    sim = mesodpd.Simulation.from_string(SMALL)
    sim.run()
    from mesodpd import plot
    for fn, name in ((plot.velocity_profile, "v.png"), (plot.thermo, "t.png"), (plot.rdf, "g.png"),
                     (plot.msd, "m.png"), (plot.fields, "f.png")):
        fig = fn(sim, path=tmp_path / name)
        assert (tmp_path / name).stat().st_size > 1000
        import matplotlib.pyplot as plt
        plt.close(fig)


def test_a_2d_field_map_is_drawn(tmp_path):
    pytest.importorskip("matplotlib")
    spec = mesodpd.Spec.from_string(SMALL)
    spec["analysis"]["fields"] = {"name": "map", "bins": [6, 1, 8], "every": 5}
    sim = mesodpd.Simulation(spec)
    sim.step(20)
    f = sim.fields()["map"]
    assert f["density"].shape == (6, 1, 8) and f["samples"] == 5
    # Centres: x varies along the first index, z along the last.
    assert np.allclose(f["x"][:, 0, 0], np.arange(6) + 0.5) and np.allclose(f["z"][0, 0, :], np.arange(8) + 0.5)
    from mesodpd import plot
    import matplotlib.pyplot as plt
    plt.close(plot.fields(sim, quantity="vx", path=tmp_path / "map.png"))
    assert (tmp_path / "map.png").stat().st_size > 1000


TDPD = """
[system]
box = [6.0, 6.0, 6.0]
seed = 5

[[species]]
name = "fluid"
density = 3.0
conc1 = 1.0
conc2 = 0.0

[pair]
style = "tdpd"
kappa1 = 2.0
kappa2 = 2.0

[tdpd]
solutes = 2

[integrator]
dt = 0.01

[run]
steps = 10

[output]
progress = false
"""


def test_model_scalars_are_read_and_set_as_arrays():
    sim = mesodpd.Simulation.from_string(TDPD)
    p = sim.particles
    assert np.all(p.conc1 == 1.0) and np.all(p.conc2 == 0.0) and len(p.conc1) == len(p)
    with pytest.raises(AttributeError):
        p.temp  # an eDPD field, not held by this run
    with pytest.raises(ValueError):
        p.set("conc1", np.zeros(3))  # one value per owned particle
    with pytest.raises(ValueError):
        p.set("conc_rate1", np.zeros(len(p)))  # rates are the force stage's
    # Solute 2 only on the particles with x < 3: the Fick flux then spreads it, conserving the amount.
    c2 = np.where(p.x < 3.0, 2.0, 0.0)
    p.set("conc2", c2)
    assert np.array_equal(p.conc2, c2)
    total = c2.sum()
    sim.step(10)
    after = sim.particles.conc2
    assert abs(after.sum() - total) < 1e-9 * total
    assert after[sim.particles.x >= 3.0].max() > 0.05  # it spread


SPDPD = """
[system]
box = [5.0, 5.0, 5.0]
seed = 3

[[species]]
name = "S"
density = 3.0
radius = 0.5

[[species]]
name = "B"
count = 10
mass = 2.0
radius = 1.0
inertia = 0.5

[pair]
style = "spdpd"
gamma_perp = 4.5

[output]
progress = false
"""


def test_spins_of_single_particle_dpd_are_an_n_by_3_array():
    sim = mesodpd.Simulation.from_string(SPDPD)
    species = sim.spec.resolved()["species"]
    assert species[1]["radius"] == 1.0 and species[1]["inertia"] == 0.5 and species[0]["inertia"] == 0.0
    p = sim.particles
    w = p.angular_velocity
    assert w.shape == (len(p), 3) and np.array_equal(w[:, 2], p.omega_z)
    # Drawn at kT: I <Omega_a^2> = kT (I = 2 m R^2 / 5 = 0.1 for S), within the sampling error of 375 x 3.
    s = p.species == 0
    assert abs(0.1 * np.mean(w[s] ** 2) - 1.0) < 0.15
    # Setting the spins to zero: the friction across e spins them up again from the noise.
    for name in ("omega_x", "omega_y", "omega_z"):
        p.set(name, np.zeros(len(p)))
    sim.step(20)
    assert np.mean(sim.particles.angular_velocity[s] ** 2) > 1.0
    with pytest.raises(KeyError):
        mesodpd.Simulation.from_string(TDPD).particles.angular_velocity


BODY = """
[system]
box = [10, 10, 10]
seed = 3
[[species]]
name = "S"
density = 3
[[species]]
name = "W"
frozen = true
[[solid]]
name = "ball"
species = "W"
shape = "sphere"
center = [5, 5, 5]
radius = 1.5
[[body]]
solid = "ball"
motion = "towed"
velocity = [0.5, 0, 0]
angular_velocity = [0, 0, 1.0]
[integrator]
dt = 0.02
[run]
steps = 50
[output]
progress = false
"""


def test_rigid_bodies_are_read_as_arrays(tmp_path):
    sim = mesodpd.Simulation.from_string(BODY.replace('velocity = [0.5, 0, 0]', 'velocity = [0.5, 0, 0]\noutput_every = 10'),
                                         out=tmp_path)
    sim.step(50)
    (b,) = sim.bodies()
    assert b["solid"] == "ball" and b["particles"] > 0
    assert abs(b["mass"] - 3.0 * 4.0 / 3.0 * np.pi * 1.5 ** 3) < 1e-9
    # Towed: 50 steps of 0.02 at 0.5 along x, turned by 1 radian about z.
    assert np.allclose(b["position"], [5.5, 5.0, 5.0], atol=1e-9)
    assert np.allclose(b["orientation"], [np.cos(0.5), 0, 0, np.sin(0.5)], atol=1e-9)
    assert b["force"].shape == (3,) and np.all(np.isfinite(b["torque"]))
    # The fluid's pressure pushes in on the sphere: the stresslet's trace is negative (about -3 p V).
    assert b["stresslet"].shape == (6,) and b["stresslet"][:3].sum() < 0
    assert mesodpd.Simulation.from_string(SPDPD).bodies() == []
    # bodies.gsd: one particle per body, with its orientation, so OVITO draws it turned.
    gsd_hoomd = pytest.importorskip("gsd.hoomd")
    with gsd_hoomd.open(str(tmp_path / "bodies.gsd")) as t:
        frame = t[-1]
        assert frame.configuration.step == 50 and frame.particles.N == 1
        assert np.allclose(frame.particles.orientation[0], b["orientation"], atol=1e-6)
        assert np.allclose(frame.particles.position[0], np.array(b["position"]) - 5.0, atol=1e-5)
