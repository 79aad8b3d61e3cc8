"""The spec from Python: TOML round trip, dicts and kwargs, validation errors naming the key,
dimensionless numbers."""
import math

import pytest

import mesodpd
from conftest import REPO, SMALL


def test_toml_python_toml_round_trip():
    path = REPO / "examples" / "poiseuille" / "poiseuille.toml"
    spec = mesodpd.Spec.from_toml(path)
    text = spec.to_toml()
    again = mesodpd.Spec.from_string(text, source=str(path))
    assert again.data == spec.data
    assert again.to_toml() == text
    # The C++ reader sees the same run in both texts.
    assert again.resolved() == spec.resolved()
    assert spec.resolved()["species"][0]["count"] == 6000  # 3 x 10 x 10 x 20, derived by validate()


def test_dict_and_kwargs_give_the_same_spec_as_toml():
    from_text = mesodpd.Spec.from_string(SMALL)
    from_dict = mesodpd.Spec(from_text.data)
    from_kwargs = mesodpd.Spec(**from_text.data)
    assert from_dict == from_text and from_kwargs == from_text
    r = from_text.resolved()
    assert from_dict.resolved()["pairs"] == r["pairs"]
    # None leaves a key out: its default applies.
    spec = mesodpd.Spec(from_text.data)
    spec["integrator"]["lambda"] = None
    assert "lambda" not in spec.to_toml()
    spec.validate()


def test_update_merges_sections():
    spec = mesodpd.Spec.from_string(SMALL)
    spec.update(run={"steps": 5}, system={"seed": 9})
    assert spec["run"]["steps"] == 5 and spec["system"]["seed"] == 9 and spec["system"]["kT"] == 1.0
    assert spec.resolved()["steps"] == 5


@pytest.mark.parametrize("edit, key, text", [
    (lambda d: d["integrator"].update(dt=0.7), "integrator.dt", "must be in"),
    (lambda d: d["integrator"].update(dtt=0.01), "integrator.dtt", "did you mean"),
    (lambda d: d["system"].update(box="big"), "system.box", "expected"),
    (lambda d: d["species"][0].update(mass=-1.0), "species[0].mass", ""),
    (lambda d: d["analysis"]["rdf"].update(rmax=10.0), "analysis.rdf.rmax", ""),
])
def test_validation_errors_name_the_key(edit, key, text):
    spec = mesodpd.Spec.from_string(SMALL)
    edit(spec.data)
    with pytest.raises(mesodpd.SpecError) as err:
        spec.validate()
    assert err.value.key == key
    assert key in str(err.value) and text in str(err.value)
    assert isinstance(err.value, ValueError)
    with pytest.raises(mesodpd.SpecError):
        mesodpd.Simulation(spec)


def test_errors_in_an_unchanged_file_give_its_line(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(SMALL.replace("dt = 0.04", "dt = -1.0"))
    with pytest.raises(mesodpd.SpecError) as err:
        mesodpd.Spec.from_toml(path).validate()
    line = SMALL.replace("dt = 0.04", "dt = -1.0").splitlines().index("dt = -1.0") + 1
    assert f"{path}:{line}:" in str(err.value) and err.value.key == "integrator.dt"


def test_toml_syntax_error_and_missing_file(tmp_path):
    with pytest.raises(mesodpd.SpecError) as err:
        mesodpd.Spec.from_string("[system\nbox = 1", source="x.toml")
    assert "x.toml:1" in str(err.value) and err.value.key is None
    with pytest.raises(mesodpd.SpecError):
        mesodpd.Spec.from_toml(tmp_path / "missing.toml")


def test_values_python_cannot_write_as_toml_are_refused():
    with pytest.raises(mesodpd.SpecError) as err:
        mesodpd.Spec(system={"box": [6, 6, object()]}).to_toml()
    assert err.value.key == "system.box[2]"


def test_numpy_values_are_accepted():
    np = pytest.importorskip("numpy")
    spec = mesodpd.Spec.from_string(SMALL)
    spec["system"]["box"] = np.array([6.0, 6.0, 8.0])
    spec["run"]["steps"] = np.int64(60)
    assert spec.resolved()["box"] == [6.0, 6.0, 8.0] and spec.resolved()["steps"] == 60


def test_dimensionless_numbers_and_warnings():
    spec = mesodpd.Spec.from_string(SMALL)
    n = spec.numbers()
    # Speed of sound from p = rho kT + alpha(rho) a rho^2 with the measured alpha(3) = 0.09176 and its
    # slope (0.09575 - 0.09176) per unit density: c^2 = 1 + 2 alpha a rho + alpha' a rho^2.
    c2 = 1 + 2 * 0.09176 * 25 * 3 + (0.09575 - 0.09176) * 25 * 9
    assert n["sound_speed"] == pytest.approx(math.sqrt(c2), rel=1e-12)
    # Kinetic theory (seed 000 Table 1) for s = 2: D = 45 / (2 pi gamma rho), Sc = nu / D.
    d = 45 / (2 * math.pi * 4.5 * 3)
    assert n["diffusion"] == pytest.approx(d, rel=1e-12)
    assert n["schmidt"] == pytest.approx(n["viscosity"] / (3 * d), rel=1e-12)
    sc_table = 0.5 + (2 * math.pi * 4.5 * 3) ** 2 / 70875  # seed 000 Table 1, s = 2, r_c = 1
    assert n["schmidt"] == pytest.approx(sc_table, rel=1e-12)
    # Reverse Poiseuille: U = rho g L^2 / (32 eta), Re = rho U (L/2) / eta, Ma = U / c.
    u = 3 * 0.05 * 64 / (32 * n["viscosity"])
    assert n["flow_speed"] == pytest.approx(u, rel=1e-12)
    assert n["reynolds"] == pytest.approx(3 * u * 4 / n["viscosity"], rel=1e-12)
    assert n["mach"] == pytest.approx(u / n["sound_speed"], rel=1e-12)
    assert n["warnings"] == []
    # A strong drive is compressible, a big dt too coarse for the thermostat.
    spec["poiseuille"]["force"] = 1.0
    spec["integrator"]["dt"] = 0.08
    w = spec.numbers()["warnings"]
    assert any("Mach" in x for x in w) and any("integrator.dt" in x for x in w)
    assert "warning: " in spec.check()


def test_command_line_check_prints_the_same_numbers(small_toml, mesodpd_bin):
    import subprocess
    r = subprocess.run([mesodpd_bin, "check", str(small_toml)], capture_output=True, text=True)
    assert r.returncode == 0
    assert mesodpd.Spec.from_toml(small_toml).numbers()["text"] in r.stdout
    assert "Reynolds" in r.stdout and "Mach" in r.stdout and "Schmidt" in r.stdout
