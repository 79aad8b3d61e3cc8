// Pairwise thermostats that act after a conservative velocity-Verlet step ([thermostat], issue 27):
// Lowe-Andersen, Shardlow's S1 splitting, Peters' scheme and Stoyanov-Groot's Nose-Hoover-Lowe-Andersen
// combination. Each visits every pair closer than r_c once
// per step and changes only the pair's relative velocity along the line of centres, e_ij, by an impulse
// +P e_ij on i and -P e_ij on j: linear and angular momentum are kept pair by pair.
//
// The sweep is serial and visits the pairs in a fixed order that depends on the positions and ids alone
// (cells of at least r_c numbered (c_x n_y + c_y) n_z + c_z; within a cell by id; each particle's later
// partners by id), and every random number is a pure function of (seed, step, min id, max id)
// (core/philox.hpp, stream PairThermostat). The result is therefore the same on any thread count, in
// any storage order, and after a restart. The formulas are in docs/physics.md, section "Pairwise
// thermostats".
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "core/box.hpp"
#include "core/particle_data.hpp"

namespace mesodpd {

enum class PairThermostatKind : int { LoweAndersen = 0, Shardlow = 1, Peters = 2, StoyanovGroot = 3 };

struct PairThermostatParams {
  PairThermostatKind kind = PairThermostatKind::LoweAndersen;
  double rate = 0.0;   // Gamma, collisions per pair per unit time (Lowe-Andersen, Stoyanov-Groot)
  double gamma = 0.0;  // friction of the dissipative force (Shardlow, Peters)
  double alpha = 0.0;  // coupling of the pairwise Nose-Hoover term (Stoyanov-Groot)
  double rc = 1.0;     // cutoff of the thermostat's pairs
  double s = 2.0;      // weight exponent: w_D = w_R^2 = (1 - r/rc)^s (Shardlow, Peters, Stoyanov-Groot)
  double kT = 1.0;
  std::uint64_t seed = 1;
};

// The new relative velocity along e_ij, u' from u = e_ij . (v_i - v_j), of one pair with reduced mass
// mu = m_i m_j / (m_i + m_j) and weight w_D (Shardlow, Peters); `bits` are the pair's four random words.
// Lowe-Andersen draws u' from the pair's Maxwell distribution N(0, kT/mu) with probability rate dt and
// otherwise returns u. All three leave N(0, kT/mu) invariant exactly, at any dt.
double lowe_andersen_update(double u, double mu, double rate_dt, double kT, const std::uint32_t bits[4]);
double shardlow_update(double u, double mu, double gamma_wd_dt, double kT, const std::uint32_t bits[4]);
double peters_update(double u, double mu, double gamma_wd_dt, double kT, const std::uint32_t bits[4]);
// Stoyanov-Groot: a Lowe-Andersen collision with probability rate dt, otherwise the pairwise Nose-Hoover
// kick u' = u (1 + feedback / mu), feedback = alpha w_D dt (kT / T_kin - 1) with the sweep's kinetic
// temperature (docs/physics.md). Unlike the three above it does not keep N(0, kT/mu) invariant by itself:
// it steers the measured temperature.
double stoyanov_groot_update(double u, double mu, double rate_dt, double feedback, double kT,
                             const std::uint32_t bits[4]);
// The factor kT / T_kin - 1 of the Nose-Hoover kick, capped at +1 so that a cold start heats at a bounded
// rate (the cooling side is at least -1 by itself). T_kin <= 0 gives the cap.
double stoyanov_groot_feedback(double kT, double t_kin);

class PairThermostat {
 public:
  explicit PairThermostat(PairThermostatParams params) : params_(params) {}

  // One sweep over the particles [0, p.n_local) of `box` (all of the system: one rank). `species_mass`
  // by species index; `step` keys the random numbers.
  void sweep(ParticleData& p, const Box& box, const std::vector<double>& species_mass, std::uint64_t step,
             double dt);

  const PairThermostatParams& params() const { return params_; }
  // Under MPI only rank 0 sweeps (the whole system, gathered there); the other ranks take its pair count,
  // virial and temperature so that every rank reports the same.
  void adopt(std::uint64_t pairs, const std::array<double, 6>& virial, double temperature) {
    last_pairs_ = pairs;
    last_virial_ = virial;
    last_temperature_ = temperature;
  }
  // The kinetic temperature the last Stoyanov-Groot sweep steered by (0 for the other types): the peculiar
  // velocities' sum m |v - V|^2 / (3N - 3), V the mean velocity; under Lees-Edwards the two axes across
  // the flow only, as thermo's temperature_transverse.
  double last_temperature() const { return last_temperature_; }
  // Pairs closer than rc in the last sweep (for tests and the cost notes).
  std::uint64_t last_pairs() const { return last_pairs_; }
  // The virial of the last sweep's impulses as forces over the step, sum over pairs of r_ij (x) P e_ij /
  // dt: xx, yy, zz, xy, xz, yz (the order of PairSums::virial). The sweep's friction and noise carry
  // momentum between pairs, so a stress that leaves it out misses the thermostat's share of the
  // viscosity (all of it at high Lowe-Andersen rates).
  const std::array<double, 6>& last_virial() const { return last_virial_; }

 private:
  // Sorts the particles into cells of at least rc, by (cell, id): order_ (the sweep order), cell_start_.
  void bin(const ParticleData& p, const Box& box);

  PairThermostatParams params_;
  std::array<int, 3> dims_{1, 1, 1};
  std::vector<std::uint32_t> cell_of_, cell_start_, order_, partners_;
  // The kinetic temperature of the peculiar velocities (see last_temperature()), summed in the order of
  // the last bin().
  double kinetic_temperature(const ParticleData& p, const Box& box, const std::vector<double>& species_mass) const;

  std::uint64_t last_pairs_ = 0;
  double last_temperature_ = 0.0;
  std::array<double, 6> last_virial_{};
};

}  // namespace mesodpd
