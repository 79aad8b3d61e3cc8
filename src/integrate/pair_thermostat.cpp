// The pair sweeps of [thermostat] and their per-pair updates (formulas: docs/physics.md, "Pairwise
// thermostats").
#include "integrate/pair_thermostat.hpp"

#include <algorithm>
#include <cmath>

#include "core/philox.hpp"
#include "core/adjacent_bins.hpp"

namespace mesodpd {

double lowe_andersen_update(double u, double mu, double rate_dt, double kT, const std::uint32_t bits[4]) {
  // Lowe 1999: with probability Gamma dt the pair's relative velocity along e is drawn afresh from the
  // Maxwell distribution of its reduced mass (variance kT / mu; 2 kT / m for equal masses m).
  if (u01_open(bits[0]) >= rate_dt) return u;
  return std::sqrt(kT / mu) * gaussian_unit(bits[1], bits[2]);
}

double shardlow_update(double u, double mu, double gamma_wd_dt, double kT, const std::uint32_t bits[4]) {
  // Shardlow's S1 step for the pair's stochastic ODE mu du = -gamma w_D u dt + sigma w_R dW along e
  // (sigma^2 = 2 gamma kT, w_R^2 = w_D): half a step explicit, half a step implicit in the friction,
  // one Gaussian xi shared by the two halves. With A = gamma w_D dt / (2 mu) and
  // B = sigma w_R sqrt(dt) xi / (2 mu):  u1 = (1 - A) u + B,  u' = (u1 + B) / (1 + A).
  const double a = 0.5 * gamma_wd_dt / mu;
  const double b = std::sqrt(2.0 * gamma_wd_dt * kT) * gaussian_unit(bits[0], bits[1]) / (2.0 * mu);
  const double u1 = (1.0 - a) * u + b;
  return (u1 + b) / (1.0 + a);
}

double peters_update(double u, double mu, double gamma_wd_dt, double kT, const std::uint32_t bits[4]) {
  // Peters 2004 as we derived it (docs/physics.md): the friction impulse -gamma w_D dt u and a Gaussian
  // one whose variance makes N(0, kT/mu) exactly invariant: with a = gamma w_D dt / mu,
  // u' = (1 - a) u + sqrt(a (2 - a) kT / mu) xi.  [thermostat] refuses gamma dt / mu > 1 (a <= 1).
  const double a = gamma_wd_dt / mu;
  return (1.0 - a) * u + std::sqrt(a * (2.0 - a) * kT / mu) * gaussian_unit(bits[0], bits[1]);
}

double stoyanov_groot_update(double u, double mu, double rate_dt, double feedback, double kT,
                             const std::uint32_t bits[4]) {
  // Stoyanov & Groot 2005 (seed 002 ref. 26): each pair is thermostatted either by Lowe-Andersen (with
  // probability Gamma dt, the same draw as lowe_andersen_update) or else by a pairwise Nose-Hoover
  // force alpha w_D (kT / T_kin - 1) u e on i (its opposite on j), applied as one impulse over dt.
  if (u01_open(bits[0]) < rate_dt) return std::sqrt(kT / mu) * gaussian_unit(bits[1], bits[2]);
  return u * (1.0 + feedback / mu);
}

double stoyanov_groot_feedback(double kT, double t_kin) {
  return t_kin > 0.0 ? std::min(1.0, kT / t_kin - 1.0) : 1.0;
}

double PairThermostat::kinetic_temperature(const ParticleData& p, const Box& box,
                                           const std::vector<double>& species_mass) const {
  // Two passes (mean, then spread) in the sweep order (bin() first), which depends on the positions and
  // ids alone: the same bits on any thread count, storage order and after a restart.
  const int skip = box.sheared() ? box.shear.flow : -1;
  double mass = 0, mom[3] = {0, 0, 0};
  for (const std::uint32_t i : order_) {
    const double m = species_mass[static_cast<std::size_t>(p.species[i])];
    mass += m;
    mom[0] += m * p.vx[i];
    mom[1] += m * p.vy[i];
    mom[2] += m * p.vz[i];
  }
  if (p.n_local < 2 || mass <= 0.0) return 0.0;
  const double v0[3] = {mom[0] / mass, mom[1] / mass, mom[2] / mass};
  double twice_ke = 0;
  for (const std::uint32_t i : order_) {
    const double m = species_mass[static_cast<std::size_t>(p.species[i])];
    const double v[3] = {p.vx[i] - v0[0], p.vy[i] - v0[1], p.vz[i] - v0[2]};
    for (int d = 0; d < 3; ++d)
      if (d != skip) twice_ke += m * v[d] * v[d];
  }
  const double dof = (3.0 * static_cast<double>(p.n_local) - 3.0) * (skip >= 0 ? 2.0 / 3.0 : 1.0);
  return twice_ke / dof;
}

void PairThermostat::bin(const ParticleData& p, const Box& box) {
  const std::size_t n = p.n_local;
  for (int d = 0; d < 3; ++d)
    dims_[static_cast<std::size_t>(d)] =
        std::max(1, static_cast<int>(std::floor(box.length(d) / params_.rc)));
  const std::size_t cells = static_cast<std::size_t>(dims_[0]) * static_cast<std::size_t>(dims_[1]) *
                            static_cast<std::size_t>(dims_[2]);
  cell_of_.resize(n);
  cell_start_.assign(cells + 1, 0);
  const auto coord = [&](double x, int d) {
    const int nd = dims_[static_cast<std::size_t>(d)];
    const int c = static_cast<int>(x * nd / box.length(d));
    return std::clamp(c, 0, nd - 1);
  };
  for (std::size_t i = 0; i < n; ++i) {
    const int c = (coord(p.x[i], 0) * dims_[1] + coord(p.y[i], 1)) * dims_[2] + coord(p.z[i], 2);
    cell_of_[i] = static_cast<std::uint32_t>(c);
    ++cell_start_[static_cast<std::size_t>(c) + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
  order_.resize(n);
  std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) order_[fill[cell_of_[i]]++] = static_cast<std::uint32_t>(i);
  const auto by_id = [&](std::uint32_t a, std::uint32_t b) { return p.id[a] < p.id[b]; };
  for (std::size_t c = 0; c < cells; ++c)
    std::sort(order_.begin() + cell_start_[c], order_.begin() + cell_start_[c + 1], by_id);
}

void PairThermostat::sweep(ParticleData& p, const Box& box, const std::vector<double>& species_mass,
                           std::uint64_t step, double dt) {
  bin(p, box);
  const double rc = params_.rc, rc2 = rc * rc, kT = params_.kT;
  // The distinct neighbouring cell coordinates of c along axis d (fewer than three when the axis has
  // fewer than three cells, or at the faces of a bounded axis), and whether each wrapped round.
  const auto near = [&](int c, int d, int out[3], bool wrapped[3]) {
    return adjacent_bins(c, dims_[static_cast<std::size_t>(d)], box.periodic[static_cast<std::size_t>(d)], out, wrapped);
  };
  // With Lees-Edwards images a neighbour row across the gradient faces takes the whole flow axis (its
  // image is shifted there); the gradient axis has at least three cells (validated), so the relation
  // "is a neighbour cell" stays symmetric and each pair is met once. Without shear the axes' roles
  // are only names.
  const bool sheared = box.sheared();
  const int ga = sheared ? box.shear.gradient : 0, fa = sheared ? box.shear.flow : 1, oa = 3 - ga - fa;
  std::vector<int> whole_row(static_cast<std::size_t>(dims_[static_cast<std::size_t>(fa)]));
  for (std::size_t k = 0; k < whole_row.size(); ++k) whole_row[k] = static_cast<int>(k);
  std::uint64_t pairs = 0;
  std::array<double, 6> virial{};
  const bool sg = params_.kind == PairThermostatKind::StoyanovGroot;
  last_temperature_ = sg ? kinetic_temperature(p, box, species_mass) : 0.0;
  const double sg_factor = sg ? params_.alpha * dt * stoyanov_groot_feedback(kT, last_temperature_) : 0.0;
  for (std::size_t k = 0; k < p.n_local; ++k) {
    const std::uint32_t i = order_[k];
    const int c = static_cast<int>(cell_of_[i]);
    const int q[3] = {c / (dims_[2] * dims_[1]), (c / dims_[2]) % dims_[1], c % dims_[2]};
    int nb[3][3];
    bool wrapped[3][3];
    int m[3];
    for (int d = 0; d < 3; ++d) m[d] = near(q[d], d, nb[d], wrapped[d]);
    // Partners later in the sweep order, closer than rc, by id. Later means a neighbouring cell of a
    // higher index, or this cell after i: the cells of lower index are skipped whole.
    partners_.clear();
    for (int bg = 0; bg < m[ga]; ++bg) {
      const bool whole = sheared && wrapped[ga][bg];
      const int* fl = whole ? whole_row.data() : nb[fa];
      const int mf = whole ? static_cast<int>(whole_row.size()) : m[fa];
      for (int af = 0; af < mf; ++af)
        for (int ao = 0; ao < m[oa]; ++ao) {
          int cc[3];
          cc[ga] = nb[ga][bg];
          cc[fa] = fl[af];
          cc[oa] = nb[oa][ao];
          const int cell = (cc[0] * dims_[1] + cc[1]) * dims_[2] + cc[2];
          if (cell < c) continue;
          const std::uint32_t first =
              cell == c ? static_cast<std::uint32_t>(k) + 1 : cell_start_[static_cast<std::size_t>(cell)];
          for (std::uint32_t qq = first; qq < cell_start_[static_cast<std::size_t>(cell) + 1]; ++qq) {
            const std::uint32_t j = order_[qq];
            double d[3] = {p.x[i] - p.x[j], p.y[i] - p.y[j], p.z[i] - p.z[j]};
            box_displacement(box, d);
            if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < rc2) partners_.push_back(j);
          }
        }
    }
    std::sort(partners_.begin(), partners_.end(),
              [&](std::uint32_t a, std::uint32_t b) { return p.id[a] < p.id[b]; });
    const double mi = species_mass[static_cast<std::size_t>(p.species[i])];
    for (const std::uint32_t j : partners_) {
      double d[3] = {p.x[i] - p.x[j], p.y[i] - p.y[j], p.z[i] - p.z[j]};
      const double n_img = box_displacement(box, d);
      const double dx = d[0], dy = d[1], dz = d[2];
      const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
      if (r == 0.0) continue;  // no line of centres
      const double ex = dx / r, ey = dy / r, ez = dz / r;
      const double mj = species_mass[static_cast<std::size_t>(p.species[j])];
      const double mu = mi * mj / (mi + mj);
      double dv[3] = {p.vx[i] - p.vx[j], p.vy[i] - p.vy[j], p.vz[i] - p.vz[j]};
      if (sheared) dv[fa] -= n_img * box.shear.velocity;  // j's Lees-Edwards image moves faster
      const double u = ex * dv[0] + ey * dv[1] + ez * dv[2];
      const Philox4x32 bits =
          pair_random_bits(params_.seed, step, p.id[i], p.id[j], RngStream::PairThermostat);
      double u_new = u;
      if (params_.kind == PairThermostatKind::LoweAndersen) {
        u_new = lowe_andersen_update(u, mu, params_.rate * dt, kT, bits.v);
      } else {
        const double om = 1.0 - r / rc;
        const double wd = params_.s == 2.0 ? om * om : std::pow(om, params_.s);
        u_new = sg ? stoyanov_groot_update(u, mu, params_.rate * dt, sg_factor * wd, kT, bits.v)
                : params_.kind == PairThermostatKind::Shardlow
                    ? shardlow_update(u, mu, params_.gamma * wd * dt, kT, bits.v)
                    : peters_update(u, mu, params_.gamma * wd * dt, kT, bits.v);
      }
      ++pairs;
      if (u_new == u) continue;
      const double impulse = mu * (u_new - u);  // +impulse e on i, -impulse e on j
      const double fr = impulse / (dt * r);     // the impulse as a force over the step, per unit r
      virial[0] += dx * dx * fr;
      virial[1] += dy * dy * fr;
      virial[2] += dz * dz * fr;
      virial[3] += dx * dy * fr;
      virial[4] += dx * dz * fr;
      virial[5] += dy * dz * fr;
      const double di = impulse / mi, dj = impulse / mj;
      p.vx[i] += di * ex;
      p.vy[i] += di * ey;
      p.vz[i] += di * ez;
      p.vx[j] -= dj * ex;
      p.vy[j] -= dj * ey;
      p.vz[j] -= dj * ez;
    }
  }
  last_pairs_ = pairs;
  last_virial_ = virial;
}

}  // namespace mesodpd
