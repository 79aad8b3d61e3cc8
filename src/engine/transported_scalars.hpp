// The transported scalars that [[source]], [[reaction]] and [buoyancy] name by their particle field:
// eDPD's "temp", tDPD's "conc1" .. "conc4". Checks shared by those modules.
#pragma once
#include <string>

#include "core/particle_data.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

// Refuses (a SpecError naming `key`) a field that is neither "temp" nor "conc<k>", k <= 4, or one the
// run's pair style does not transport ("temp" needs edpd, "conc<k>" tdpd).
void check_scalar_field(const std::string& field, const SimulationSpec& spec, const std::string& key);

// Refuses a field the particles do not hold (a solute beyond [tdpd] solutes), naming `key` = `value`.
void require_held(const ParticleData& p, const std::string& field, const std::string& key, const std::string& value);

// The solutes a tDPD run carries ([tdpd] solutes, 1 without the section); 0 for another pair style.
// Defined with the tDPD model (engine/install_tdpd.cpp).
int tdpd_solutes(const SimulationSpec& spec);

// The number density of the mobile (not frozen) species: the fluid a transported scalar moves in.
double mobile_density(const SimulationSpec& spec);

// The mean-field diffusivity of an exchange -k w (X_i - X_j) with w = (1 - r/r_c)^s on a fluid of
// density n (g(r) = 1): (2 pi / 3) n k Int_0^rc w r^4 dr = 16 pi n k r_c^5 Gamma(s+1) / Gamma(s+6), which
// is 2 pi n k r_c^5 / 315 for s = 2 (docs/physics.md, "eDPD" and "tDPD").
double exchange_diffusivity(double n, double k, double rc, double s);

// The mean-field exchange diffusivity of `field` in the first species' fluid: exchange_diffusivity with
// eDPD's C_v kappa over r_cT and s_T for "temp", tDPD's kappa<k> over r_cc and s_C<k> for "conc<k>".
double field_exchange_diffusivity(const SimulationSpec& spec, const std::string& field);

// The first species' fluid by kinetic theory (seed 000 Eq. 16, g(r) = 1, unit mass): its kinematic
// viscosity and self-diffusion, both above what the a = 25 fluid shows (docs/validation.md 4).
struct KineticFluid {
  double nu = 0, d_self = 0;
};
KineticFluid kinetic_fluid(const SimulationSpec& spec);

// The lines `mesodpd check` prints for a transported scalar of the first species' fluid: its mean-field
// exchange diffusivity `d_kin`, what the particles' motion adds, and the dimensionless number
// `number` (Prandtl or Schmidt) = nu / D with nu from seed 000 Eq. 16 (kinetic theory).
std::string scalar_numbers_line(const SimulationSpec& spec, const std::string& what, double d_kin,
                                const std::string& number);

}  // namespace mesodpd
