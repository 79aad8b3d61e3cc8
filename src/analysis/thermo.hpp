// Instantaneous thermodynamic state: temperature, pressure tensor (kinetic + virial), momentum, energy.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/box.hpp"
#include "core/particle_data.hpp"
#include "core/pair_sums.hpp"
#include "parallel/comm.hpp"

namespace mesodpd {

struct ThermoState {
  std::uint64_t step = 0;
  double time = 0.0;
  double temperature = 0.0;               // sum m v^2 / (3N - 3): total momentum is conserved
  // Temperature from the velocity components across a driven flow only (the flow axis excluded), so a
  // streaming velocity does not count as heat; equals `temperature` when there is no flow axis.
  double temperature_transverse = 0.0;
  double pressure = 0.0;                  // trace/3 of the pressure tensor (seed 000 Eqs. 11-12)
  std::array<double, 6> p_tensor{};       // xx yy zz xy xz yz: (sum m v v + sum r_ij F_ij) / V
  double pressure_conservative = 0.0;     // kinetic + conservative virial only (seed 003 EOS)
  std::array<double, 3> momentum{};
  double potential_energy = 0.0;
  double kinetic_energy = 0.0;
  std::uint64_t neighbor_builds = 0;
};

// flow_axis: 0, 1, 2 for a driven flow along x, y, z (reverse Poiseuille), -1 for none. The kinetic
// sums run over the local particles of every rank of `comm` (exact integer sums); `sums` are global.
// Particles of species with frozen[species] != 0 (wall particles) are left out of the kinetic sums.
ThermoState compute_thermo(const ParticleData& p, const std::vector<double>& mass, const Box& box,
                           const PairSums& sums, int flow_axis = -1, const Comm& comm = Comm::serial(),
                           const std::vector<std::uint8_t>& frozen = {});

// Temperature of the peculiar velocities: each mobile particle's velocity minus the mass-weighted mean
// velocity of its bin (bins[0] x bins[1] x bins[2] equal bins over the box), so a flow that varies over
// more than a bin (channel, pillar) does not count as heat; sum over bins of sum m |v - u_bin|^2 divided
// by 3 (N - occupied bins), the degrees of freedom left once each bin's mean is taken out (exact for
// thermal velocities). The per-bin sums are 128-bit integers summed over the ranks of `comm`: the same
// value on every rank whatever the rank count or storage order.
double peculiar_temperature(const ParticleData& p, const std::vector<double>& mass, const Box& box,
                            const std::array<int, 3>& bins, const Comm& comm, const std::vector<std::uint8_t>& frozen);

// The header of thermo.csv and one row, at full precision.
std::string thermo_csv_header();
std::string thermo_csv_row(const ThermoState& s);

}  // namespace mesodpd
