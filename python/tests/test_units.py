"""The units mapper against hand-computed values (seed 002 Eqs. 12-13, seed 003 steps 1-3)."""
import math

import pytest

from mesodpd import units

KB = 1.380649e-23
NA = 6.02214076e23


def test_groot_warren_water_at_nm_1():
    # kappa^-1 = 16 (water), N_m = 1, alpha = 0.101: a = (16 - 1) / (2 alpha rho) = 74.26 / rho ~ 75 / rho.
    for rho in (3.0, 4.0, 5.0):
        m = units.map(coarse_graining=1, inverse_compressibility=16, alpha=0.101, dpd_density=rho,
                      molar_mass=18.015e-3, mass_density=996.5)
        assert m.a_ii == pytest.approx(15 / (2 * 0.101 * rho), rel=1e-12)
        assert m.a_ii * rho == pytest.approx(75, rel=0.01)
        assert m.alpha_source == "given"


def test_water_300k_nm_3_by_hand():
    m = units.water(coarse_graining=3)
    w = units.WATER_300K
    kt = KB * 300
    m_mol = w["molar_mass"] / NA
    v_mol = m_mol / w["mass_density"]
    kappa_inv = v_mol / (kt * w["isothermal_compressibility"])
    assert kappa_inv == pytest.approx(16.1, abs=0.1)                 # the textbook 16 for water
    assert m.inverse_compressibility == pytest.approx(kappa_inv, rel=1e-12)
    assert m.alpha == pytest.approx(0.09176, rel=1e-12)                # measured at rho = 3, not 0.101
    assert m.a_ii == pytest.approx((kappa_inv * 3 - 1) / (2 * 0.09176 * 3), rel=1e-12)
    assert 85 < m.a_ii < 86
    rc = (3 * 3 * v_mol) ** (1 / 3)                                    # seed 003 step 2
    assert m.length == pytest.approx(rc, rel=1e-12)
    assert m.length == pytest.approx(6.46e-10, rel=2e-3)               # Groot-Rabone: 3.107 (rho N_m)^(1/3) A
    assert m.mass == pytest.approx(3 * m_mol, rel=1e-12)
    assert m.energy == pytest.approx(kt, rel=1e-12)
    # seed 003 step 3: tau = nu_dpd r_c^2 / nu_water with kinetic-theory eta for gamma = 4.5, rho = 3.
    d = 45 / (2 * math.pi * 4.5 * 3)
    eta_d = 2 * math.pi * 4.5 * 9 / 15 * (1 / 3 - 4 / 4 + 6 / 5 - 4 / 6 + 1 / 7)
    eta = 3 * d / 2 + eta_d
    assert m.dpd_viscosity == pytest.approx(eta, rel=1e-12)
    tau = (eta / 3) * rc ** 2 / (w["viscosity"] / w["mass_density"])
    assert m.time == pytest.approx(tau, rel=1e-12)
    assert m.thermal_time == pytest.approx(rc * math.sqrt(3 * m_mol / kt), rel=1e-12)


def test_time_from_diffusion_and_thermal():
    md = units.water(coarse_graining=3, time_from="diffusion", dpd_diffusion=0.29)
    assert md.time == pytest.approx(3 * 0.29 * md.length ** 2 / units.WATER_300K["self_diffusion"], rel=1e-12)
    mt = units.water(coarse_graining=3, time_from="thermal")
    assert mt.time == mt.thermal_time


def test_chi_to_delta_a():
    m = units.water(coarse_graining=3, chi=1.0)
    assert m.delta_a == pytest.approx(1 / 0.286, rel=1e-12)
    assert m.a_ij == pytest.approx(m.a_ii + 1 / 0.286, rel=1e-12)
    with pytest.raises(ValueError, match="dpd_density"):
        units.water(coarse_graining=3, chi=1.0, dpd_density=4.0)


def test_conversion_round_trips():
    m = units.water(coarse_graining=3)
    for q in units.quantities():
        for v in (1e-3, 0.86, 42.0):
            assert m.from_si(m.to_si(v, q), q) == pytest.approx(v, rel=1e-14)
    # Units are consistent: viscosity = mass / (length time), velocity = length / time, ...
    assert m.unit("viscosity") == pytest.approx(m.mass / (m.length * m.time), rel=1e-14)
    assert m.unit("velocity") * m.unit("time") == pytest.approx(m.length, rel=1e-14)
    assert m.unit("thermal_pressure") == pytest.approx(KB * 300 / m.length ** 3, rel=1e-14)
    # The matched viscosity comes back: eta_dpd in SI is water's viscosity.
    assert m.to_si(m.dpd_viscosity, "viscosity") == pytest.approx(units.WATER_300K["viscosity"], rel=1e-12)
    with pytest.raises(ValueError, match="not known"):
        m.unit("colour")


def test_heat_and_solute_quantities():
    """eDPD's C_v, conductivity and diffusivities (docs/units.md, "Heat and solutes"): a temperature of 1 is
    the mapping's 300 K; C_v counts k_B per particle, so water's specific heat 4181 J/(kg K) is
    c m / k_B = 27.2 for a bead of three molecules; a conductivity k = n C_v D (reduced) converts as
    k_B / (r_c tau) and agrees with the SI product of its parts."""
    m = units.water(coarse_graining=3)
    assert m.to_si(1.0, "temperature") == pytest.approx(300.0, rel=1e-12)
    assert m.unit("heat_capacity") == KB
    cv = m.from_si(4181.0, "specific_heat")
    assert cv == pytest.approx(4181.0 * m.mass / KB, rel=1e-12)
    assert cv == pytest.approx(27.18, rel=1e-3)
    n, d = 3.0, 0.4
    k_si = m.to_si(n * cv * d, "thermal_conductivity")
    n_si, d_si = m.to_si(n, "number_density"), m.to_si(d, "thermal_diffusivity")
    assert k_si == pytest.approx(n_si * cv * KB * d_si, rel=1e-12)
    assert m.unit("thermal_diffusivity") == m.unit("diffusion")
    assert m.unit("heat_flux") == pytest.approx(m.unit("thermal_conductivity") * m.unit("temperature") / m.length,
                                                rel=1e-12)
    assert m.unit("power") == pytest.approx(m.unit("energy") / m.time, rel=1e-12)


def test_measured_alpha_table():
    assert units.measured_alpha(3) == pytest.approx(0.09176)
    assert units.measured_alpha(3.5) == pytest.approx((0.09176 + 0.09575) / 2)
    assert units.measured_alpha(8) == pytest.approx(0.101)
    assert units.measured_alpha(12) == 0.101
    with pytest.raises(ValueError, match="rho >= 3"):
        units.measured_alpha(2.5)


def test_bad_inputs_name_the_input():
    with pytest.raises(ValueError, match="two of molar_mass"):
        units.map(inverse_compressibility=16)
    with pytest.raises(ValueError, match="compressibility"):
        units.map(molar_mass=18e-3, mass_density=1000)
    with pytest.raises(ValueError, match="viscosity"):
        units.map(molar_mass=18e-3, mass_density=1000, inverse_compressibility=16, viscosity=-1)
    with pytest.raises(ValueError, match="unknown input 'visc'"):
        units.map(visc=1)


def test_command_line_units_uses_the_same_mapper(mesodpd_bin):
    import subprocess
    r = subprocess.run([mesodpd_bin, "units", "--water", "--nm", "3", "--to-si", "viscosity=0.86"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert r.stdout == units.water(coarse_graining=3).text() + \
        f"viscosity = 0.86 (DPD) = {units.water(coarse_graining=3).to_si(0.86, 'viscosity'):.6g} Pa s\n"
    bad = subprocess.run([mesodpd_bin, "units", "--nm", "0.5"], capture_output=True, text=True)
    assert bad.returncode == 2 and "coarse_graining" in bad.stderr


def test_sdpd_water_at_half_a_micron_by_hand(tmp_path):
    # Water at 300 K resolved at 0.5 um: the particle's mass, the time unit, eta and c in reduced units,
    # and a config built from them that the engine accepts (its dt limits are the same formulas).
    s = units.sdpd(mass_density=996.5, viscosity=8.5e-4, temperature=300, spacing=0.5e-6, flow_speed=1e-3)
    m = 996.5 * 0.5e-6 ** 3
    tau = 0.5e-6 * math.sqrt(m / (KB * 300))
    assert s.mass == pytest.approx(m, rel=1e-12)
    assert s.time == pytest.approx(tau, rel=1e-12)
    assert s.pair["eta"] == pytest.approx(8.5e-4 * 0.5e-6 * tau / m, rel=1e-12)
    assert 280 < s.pair["eta"] < 310                                   # very viscous at this scale
    # c: the larger of 10 flow speeds (1 cm/s) and 10 thermal speeds sqrt(kT/m) = 5.8 mm/s: the latter.
    assert s.pair["c"] == pytest.approx(10.0, rel=1e-12)
    assert s.to_si(s.pair["c"], "velocity") == pytest.approx(10 * math.sqrt(KB * 300 / m), rel=1e-12)
    assert s.mach == pytest.approx(1e-3 / s.to_si(s.pair["c"], "velocity"))
    fast = units.sdpd(mass_density=996.5, viscosity=8.5e-4, temperature=300, spacing=0.5e-6, flow_speed=1e-2)
    assert fast.pair["c"] == pytest.approx(0.1 * tau / 0.5e-6, rel=1e-12)  # 10 flow speeds of 1 cm/s
    assert s.to_si(s.from_si(3e-3, "velocity"), "velocity") == pytest.approx(3e-3, rel=1e-12)
    assert 4 * math.pi / 3 * s.pair["rc"] ** 3 == pytest.approx(100, rel=1e-12)
    assert s.pair["kernel"] == "lucy"
    assert s.dt == pytest.approx(0.5 * min(0.25 * s.pair["rc"] / s.pair["c"], 0.05 * s.pair["rc"] ** 2 / s.pair["eta"]))
    import mesodpd
    text = s.toml().replace("[system]\n", "[system]\nbox = [8.0, 8.0, 8.0]\n")
    with mesodpd.Simulation.from_string(text, out=str(tmp_path / "o"), steps=2) as sim:
        sim.step(2)
        assert sim.n_particles == 512
    with pytest.raises(ValueError, match="viscosity"):
        units.sdpd(mass_density=996.5, viscosity=-1, temperature=300, spacing=0.5e-6, flow_speed=1e-3)
    with pytest.raises(ValueError, match="sound_speed"):
        units.sdpd(mass_density=996.5, viscosity=8.5e-4, temperature=300, spacing=0.5e-6)


def test_membrane_of_a_red_cell_gives_the_keys_of_the_stretch_example():
    # examples/rbc_stretch/stretch.toml and recovery.toml were written by hand from the same inputs
    # (um, k_BT at 310 K, ms): the mapper must give their numbers.
    c = units.membrane(shear_modulus=6.3e-6, bending_rigidity=2.4e-19, diameter=7.82e-6, membrane_viscosity=0.5e-6)
    assert c.keys["diameter"] == pytest.approx(7.82, rel=1e-12)
    assert c.keys["shear_modulus"] == pytest.approx(1471.96, rel=1e-5)
    assert c.keys["kappa"] == pytest.approx(56.0746, rel=1e-5)
    assert c.keys["ka"] == pytest.approx(72126.0, rel=1e-5)
    assert c.keys["kv"] == pytest.approx(73598.0, rel=1e-5)
    assert c.keys["viscosity"] == pytest.approx(116820.0, rel=1e-4)
    assert c.from_si(193e-12, "force") == pytest.approx(45093.3, rel=1e-5)
    assert c.to_si(c.from_si(109e-12, "force"), "force") == pytest.approx(109e-12, rel=1e-14)
    # The network's area modulus K = 2 mu0 + ka + kd = 52 mu0, Young's modulus 4 K mu0 / (K + mu0).
    assert c.area_modulus == pytest.approx(52 * 6.3e-6, rel=1e-9)
    assert c.young_modulus == pytest.approx(4 * 52 * 6.3e-6 / 53, rel=1e-9)
    assert "shear_modulus = 1471.96" in c.toml()
    with pytest.raises(ValueError, match="bending_rigidity"):
        units.membrane(shear_modulus=6.3e-6, bending_rigidity=-1, diameter=7.82e-6)
    with pytest.raises(ValueError, match="unknown quantity"):
        c.to_si(1.0, "charge")
