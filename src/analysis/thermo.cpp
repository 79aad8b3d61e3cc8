// Kinetic sums for the thermodynamic output (virial sums come from the force loop).
#include "analysis/thermo.hpp"

#include <fmt/format.h>

namespace mesodpd {

namespace {
// Kinetic sums are accumulated as 128-bit fixed-point integers (2^40 units), so they do not depend on
// the storage order of the particles, which changes with spatial sorting, restarts and (later) ranks.
__extension__ using Int128 = __int128;
constexpr double kKineticScale = 1099511627776.0;  // 2^40
Int128 fixed128(double v) { return static_cast<Int128>(v * kKineticScale); }
double unfixed128(Int128 q) { return static_cast<double>(q) / kKineticScale; }
}  // namespace

ThermoState compute_thermo(const ParticleData& p, const std::vector<double>& mass, const Box& box,
                           const PairSums& sums, int flow_axis, const Comm& comm,
                           const std::vector<std::uint8_t>& frozen) {
  ThermoState s;
  Int128 kq[6] = {0, 0, 0, 0, 0, 0}, mq[3] = {0, 0, 0};
  Int128 counted = 0;
  for (std::size_t i = 0; i < p.n_local; ++i) {
    if (!frozen.empty() && frozen[static_cast<std::size_t>(p.species[i])]) continue;
    ++counted;
    const double m = mass[static_cast<std::size_t>(p.species[i])];
    const double vx = p.vx[i], vy = p.vy[i], vz = p.vz[i];
    kq[0] += fixed128(m * vx * vx);
    kq[1] += fixed128(m * vy * vy);
    kq[2] += fixed128(m * vz * vz);
    kq[3] += fixed128(m * vx * vy);
    kq[4] += fixed128(m * vx * vz);
    kq[5] += fixed128(m * vy * vz);
    mq[0] += fixed128(m * vx);
    mq[1] += fixed128(m * vy);
    mq[2] += fixed128(m * vz);
  }
  Int128 all[10] = {kq[0], kq[1], kq[2], kq[3], kq[4], kq[5], mq[0], mq[1], mq[2], counted};
  comm.sum(std::span<Int128>(all, 10));
  for (int q = 0; q < 6; ++q) kq[q] = all[q];
  for (int q = 0; q < 3; ++q) mq[q] = all[6 + q];
  std::array<double, 6> k{};
  for (std::size_t q = 0; q < 6; ++q) k[q] = unfixed128(kq[q]);
  const std::array<double, 3> mom{unfixed128(mq[0]), unfixed128(mq[1]), unfixed128(mq[2])};
  const double n = static_cast<double>(all[9]);
  const double dof = n > 1 ? 3.0 * n - 3.0 : 3.0;
  const double v = box.volume();
  s.kinetic_energy = 0.5 * (k[0] + k[1] + k[2]);
  s.temperature = (k[0] + k[1] + k[2]) / dof;
  s.temperature_transverse =
      flow_axis < 0 ? s.temperature : (k[0] + k[1] + k[2] - k[static_cast<std::size_t>(flow_axis)]) / (dof * 2.0 / 3.0);
  for (std::size_t q = 0; q < 6; ++q) s.p_tensor[q] = (k[q] + sums.virial[q]) / v;
  s.pressure = (s.p_tensor[0] + s.p_tensor[1] + s.p_tensor[2]) / 3.0;
  s.pressure_conservative = (k[0] + k[1] + k[2] + sums.virial_conservative) / (3.0 * v);
  s.momentum = mom;
  s.potential_energy = sums.potential_energy;
  return s;
}

double peculiar_temperature(const ParticleData& p, const std::vector<double>& mass, const Box& box,
                            const std::array<int, 3>& bins, const Comm& comm, const std::vector<std::uint8_t>& frozen) {
  const std::size_t nb = static_cast<std::size_t>(bins[0]) * static_cast<std::size_t>(bins[1]) * static_cast<std::size_t>(bins[2]);
  // Per bin: mass, momentum (3), twice the kinetic energy; then the particle count.
  std::vector<Int128> q(5 * nb + 1, 0);
  const double len[3] = {box.len.x, box.len.y, box.len.z};
  for (std::size_t i = 0; i < p.n_local; ++i) {
    if (!frozen.empty() && frozen[static_cast<std::size_t>(p.species[i])]) continue;
    const double r[3] = {p.x[i], p.y[i], p.z[i]};
    std::size_t bin = 0;
    for (int d = 2; d >= 0; --d) {
      const int n = bins[static_cast<std::size_t>(d)];
      const double t = r[d] / len[d] * n;  // compared in double first: NaN or far values stay in range
      const int k = t >= n ? n - 1 : (t >= 0 ? static_cast<int>(t) : 0);
      bin = bin * static_cast<std::size_t>(n) + static_cast<std::size_t>(k);
    }
    const double m = mass[static_cast<std::size_t>(p.species[i])];
    const double vx = p.vx[i], vy = p.vy[i], vz = p.vz[i];
    Int128* b = &q[5 * bin];
    b[0] += fixed128(m);
    b[1] += fixed128(m * vx);
    b[2] += fixed128(m * vy);
    b[3] += fixed128(m * vz);
    b[4] += fixed128(m * (vx * vx + vy * vy + vz * vz));
    ++q[5 * nb];
  }
  comm.sum(std::span<Int128>(q));
  double heat = 0;
  std::uint64_t occupied = 0;
  for (std::size_t b = 0; b < nb; ++b) {
    if (q[5 * b] == 0) continue;
    ++occupied;
    const double m = unfixed128(q[5 * b]), px = unfixed128(q[5 * b + 1]), py = unfixed128(q[5 * b + 2]),
                 pz = unfixed128(q[5 * b + 3]);
    heat += unfixed128(q[5 * b + 4]) - (px * px + py * py + pz * pz) / m;
  }
  const double n = static_cast<double>(q[5 * nb]);
  const double dof = 3.0 * (n - static_cast<double>(occupied));
  return dof > 0 ? heat / dof : 0.0;
}

std::string thermo_csv_header() {
  return "step,time,temperature,pressure,pxx,pyy,pzz,pxy,pxz,pyz,momentum_x,momentum_y,momentum_z,"
         "potential_energy,kinetic_energy,pressure_conservative,neighbor_builds,temperature_transverse";
}

std::string thermo_csv_row(const ThermoState& s) {
  return fmt::format("{},{:.10g},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},{:.12g},{:.6e},{:.6e},{:.6e},"
                     "{:.12g},{:.12g},{:.12g},{},{:.12g}",
                     s.step, s.time, s.temperature, s.pressure, s.p_tensor[0], s.p_tensor[1], s.p_tensor[2],
                     s.p_tensor[3], s.p_tensor[4], s.p_tensor[5], s.momentum[0], s.momentum[1], s.momentum[2],
                     s.potential_energy, s.kinetic_energy, s.pressure_conservative, s.neighbor_builds,
                     s.temperature_transverse);
}

}  // namespace mesodpd
