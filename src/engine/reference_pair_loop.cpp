// Brute-force pair loops over the shared force laws and density kernels (the test oracle).
#include "engine/reference_pair_loop.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <variant>

#include "core/adjacent_bins.hpp"
#include "engine/fixed_point.hpp"
#include "engine/pair_contribution.hpp"

namespace mesodpd {

namespace {
// Calls visit(i, j, dx, dy, dz, r) for every pair i < j of local particles within `cutoff` (minimum
// image on periodic axes only; with Lees-Edwards images, box_displacement()).
template <class Visit>
void for_each_pair(const ParticleData& p, const Box& box, double cutoff, Visit&& visit) {
  const double lx = box.image_len(0), ly = box.image_len(1), lz = box.image_len(2);
  const double hx = box.half_image_len(0), hy = box.half_image_len(1), hz = box.half_image_len(2);
  for (std::size_t i = 0; i < p.n_local; ++i)
    for (std::size_t j = i + 1; j < p.n_local; ++j) {
      if (box.sheared()) {
        double d[3] = {p.x[i] - p.x[j], p.y[i] - p.y[j], p.z[i] - p.z[j]};
        box_displacement(box, d);
        const double r = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (r < cutoff) visit(i, j, d[0], d[1], d[2], r);
        continue;
      }
      const double dx = minimum_image(p.x[i] - p.x[j], lx, hx);
      const double dy = minimum_image(p.y[i] - p.y[j], ly, hy);
      const double dz = minimum_image(p.z[i] - p.z[j], lz, hz);
      const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
      if (r < cutoff) visit(i, j, dx, dy, dz, r);
    }
}

// The same pairs, visited in the same order (i ascending, then j ascending) with the same arithmetic,
// found through cells at least `cutoff` wide instead of by trying every pair: O(N) for the analyses
// that run this loop during a simulation. An axis with fewer than three cells (a thin box) visits each
// distinct neighbour cell once (through the periodic wrap the cells -1 and +1 can be the same one). Falls
// back to the double loop with Lees-Edwards images (whose shifted neighbour cells this binning does not
// follow).
template <class Visit>
void for_each_pair_binned(const ParticleData& p, const Box& box, double cutoff, Visit&& visit) {
  const std::size_t n = p.n_local;
  if (box.sheared()) return for_each_pair(p, box, cutoff, visit);
  int nc[3];
  double inv_w[3];
  for (int d = 0; d < 3; ++d) {
    // Cells a little wider than the cutoff, so that rounding in the cell index can never put two
    // particles closer than the cutoff two cells apart.
    const double cells = cutoff > 0 ? std::floor(box.length(d) / cutoff * (1.0 - 1e-9)) : 0.0;
    nc[d] = std::max(1, static_cast<int>(std::min(cells, 1e6)));
  }
  // A few particles in a large box: wider cells, so that the cell arrays stay of the order of the
  // particle count (wider cells only add candidates).
  const double limit = 8.0 * static_cast<double>(n) + 4096.0;
  const double total = static_cast<double>(nc[0]) * nc[1] * nc[2];
  if (total > limit) {
    const double f = std::cbrt(total / limit);
    for (int d = 0; d < 3; ++d) nc[d] = std::max(std::min(nc[d], 3), static_cast<int>(nc[d] / f));
  }
  for (int d = 0; d < 3; ++d) inv_w[d] = nc[d] / box.length(d);
  auto coord = [&](double v, int d) {  // positions may sit a hair outside a bounded box
    const double t = v * inv_w[d];
    return t >= nc[d] ? nc[d] - 1 : (t >= 0 ? static_cast<int>(t) : 0);
  };
  const std::size_t ncell = static_cast<std::size_t>(nc[0]) * static_cast<std::size_t>(nc[1]) * static_cast<std::size_t>(nc[2]);
  std::vector<std::array<int, 3>> at(n);
  std::vector<std::uint32_t> start(ncell + 1, 0), members(n);
  auto cell = [&](int cx, int cy, int cz) {
    return (static_cast<std::size_t>(cz) * static_cast<std::size_t>(nc[1]) + static_cast<std::size_t>(cy)) *
               static_cast<std::size_t>(nc[0]) + static_cast<std::size_t>(cx);
  };
  for (std::size_t i = 0; i < n; ++i) {
    at[i] = {coord(p.x[i], 0), coord(p.y[i], 1), coord(p.z[i], 2)};
    ++start[cell(at[i][0], at[i][1], at[i][2]) + 1];
  }
  for (std::size_t c = 0; c < ncell; ++c) start[c + 1] += start[c];
  {
    std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) members[next[cell(at[i][0], at[i][1], at[i][2])]++] = static_cast<std::uint32_t>(i);
  }
  const double lx = box.image_len(0), ly = box.image_len(1), lz = box.image_len(2);
  const double hx = box.half_image_len(0), hy = box.half_image_len(1), hz = box.half_image_len(2);
  struct Near {
    std::uint32_t j;
    double dx, dy, dz, r;
  };
  std::vector<Near> near;
  for (std::size_t i = 0; i < n; ++i) {
    near.clear();
    // The distinct neighbour cell coordinates along each axis (none beyond a bounded face).
    int nb[3][3], count[3];
    for (int d = 0; d < 3; ++d)
      count[d] = adjacent_bins(at[i][static_cast<std::size_t>(d)], nc[d], box.periodic[static_cast<std::size_t>(d)], nb[d]);
    for (int az = 0; az < count[2]; ++az)
      for (int ay = 0; ay < count[1]; ++ay)
        for (int ax = 0; ax < count[0]; ++ax) {
          const std::size_t k = cell(nb[0][ax], nb[1][ay], nb[2][az]);
          for (std::uint32_t m = start[k]; m < start[k + 1]; ++m) {
            const std::uint32_t j = members[m];
            if (j <= i) continue;
            const double dx = minimum_image(p.x[i] - p.x[j], lx, hx);
            const double dy = minimum_image(p.y[i] - p.y[j], ly, hy);
            const double dz = minimum_image(p.z[i] - p.z[j], lz, hz);
            const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
            if (r < cutoff) near.push_back({j, dx, dy, dz, r});
          }
        }
    std::sort(near.begin(), near.end(), [](const Near& a, const Near& b) { return a.j < b.j; });
    for (const Near& q : near) visit(i, q.j, q.dx, q.dy, q.dz, q.r);
  }
}
// The part of a pair's input that its geometry gives: r, r_hat . v_ij (with the Lees-Edwards velocity
// of j's image, from the image count along the gradient axis) and, for a non-central law, d = r_i - r_j
// and v_ij as vectors. Shared by the reference loops so that they build the same inputs.
template <class Law>
PairInput<double> geometry_input(const ParticleData& p, const Box& box, std::size_t i, std::size_t j, double dx,
                                 double dy, double dz, double r) {
  PairInput<double> in;
  in.r = r;
  double raw[3] = {p.x[i] - p.x[j], p.y[i] - p.y[j], p.z[i] - p.z[j]};
  const double n_img = box_displacement(box, raw);
  double dv[3] = {p.vx[i] - p.vx[j], p.vy[i] - p.vy[j], p.vz[i] - p.vz[j]};
  if (box.sheared()) dv[box.shear.flow] -= n_img * box.shear.velocity;
  in.rv = (dx * dv[0] + dy * dv[1] + dz * dv[2]) * (r > 0 ? 1.0 / r : 0.0);
  if constexpr (law_non_central<Law>) {
    in.d[0] = dx, in.d[1] = dy, in.d[2] = dz;
    for (int c = 0; c < 3; ++c) in.dv[c] = dv[c];
  }
  return in;
}

}  // namespace

void reference_pairs(const ParticleData& p, const Box& box, double cutoff, bool binned,
                     const std::function<void(std::size_t, std::size_t, double, double, double, double)>& visit) {
  if (binned)
    for_each_pair_binned(p, box, cutoff, visit);
  else
    for_each_pair(p, box, cutoff, visit);
}

void reference_forces(const ParticleData& p, const Box& box, const PairLawTables& laws, NoiseSettings noise,
                      std::uint64_t step, double dt, std::vector<std::array<double, 3>>& f, PairSums& sums,
                      const double* rho, std::vector<double>* rate) {
  std::vector<std::array<std::int64_t, 3>> q(p.n_local, {0, 0, 0});
  std::vector<std::array<std::int64_t, kMaxScalars>> qh(p.n_local, {0, 0, 0, 0});  // scalar rates (kScalars)
  int ns = 0;  // the law's scalars that p holds (a leading subset, as in the shared loop)
  std::int64_t total[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  std::visit(
      [&](const auto& lt) {
        using Law = typename std::decay_t<decltype(lt)>::LawType;
        const std::vector<double>* sc[kMaxScalars] = {};
        if constexpr (law_scalars<Law> > 0)
          for (int c = 0; c < law_scalars<Law>; ++c) {
            sc[c] = p.doubles(Law::kScalarFields[static_cast<std::size_t>(c)]);
            if (sc[c] == nullptr) break;
            ns = c + 1;
          }
        Law::with_evaluator(lt.table.params, [&](auto eval) {
          for_each_pair(p, box, lt.table.max_cutoff, [&](std::size_t i, std::size_t j, double dx, double dy,
                                                          double dz, double r) {
            // Two frozen wall particles never interact (neither moves), as in the shared loop.
            if (p.body[i] != 0 && p.body[j] != 0) return;
            const auto& pp = lt.table(p.species[i], p.species[j]);
            const double inv_r = r > 0 ? 1.0 / r : 0.0;
            PairInput<double> in = geometry_input<Law>(p, box, i, j, dx, dy, dz, r);
            in.inv_sqrt_dt = 1.0 / std::sqrt(dt);
            if (rho != nullptr) {
              in.rho_i = rho[i];
              in.rho_j = rho[j];
            }
            if constexpr (law_scalars<Law> > 0) {
              pair_noise_with_scalars(noise.seed, step, p.id[i], p.id[j], noise.kind, in.xi, in.xs, ns);
              for (int c = 0; c < ns; ++c) {
                in.si[c] = (*sc[c])[i];
                in.sj[c] = (*sc[c])[j];
              }
            } else {
              in.xi = pair_noise(noise.seed, step, p.id[i], p.id[j], noise.kind);
            }
            if constexpr (law_noise_words<Law> > 0)
              pair_noise_words(noise.seed, step, p.id[i], p.id[j], noise.kind, in.xm, law_noise_words<Law>);
            const PairForceT<double> pf = eval(pp, in);
            for (int c = 0; c < ns; ++c) {
              qh[i][c] += to_fixed(pf.qi[c], kForceScale);
              qh[j][c] += to_fixed(pf.qj[c], kForceScale);
            }
            const PairForceVector fv = pair_force_vector<law_non_central<Law>>(pf, inv_r, dx, dy, dz);
            const PairForceFixed fq = to_fixed(fv);
            q[i][0] += fq.x;
            q[i][1] += fq.y;
            q[i][2] += fq.z;
            q[j][0] -= fq.x;
            q[j][1] -= fq.y;
            q[j][2] -= fq.z;
            add_pair_sums<law_non_central<Law>>(total, pf, fv, r, dx, dy, dz, pp.rcut2);
          });
        });
      },
      laws);
  f.assign(p.n_local, {0.0, 0.0, 0.0});
  for (std::size_t i = 0; i < p.n_local; ++i)
    for (std::size_t c = 0; c < 3; ++c) f[i][c] = static_cast<double>(q[i][c]) * kForceUnscale;
  if (rate != nullptr) {
    rate->assign(static_cast<std::size_t>(ns) * p.n_local, 0.0);
    for (int c = 0; c < ns; ++c)
      for (std::size_t i = 0; i < p.n_local; ++i)
        (*rate)[static_cast<std::size_t>(c) * p.n_local + i] = static_cast<double>(qh[i][c]) * kForceUnscale;
  }
  for (std::size_t c = 0; c < 6; ++c) sums.virial[c] = static_cast<double>(total[c]) * kVirialUnscale;
  sums.virial_conservative = static_cast<double>(total[6]) * kVirialUnscale;
  sums.potential_energy = static_cast<double>(total[7]) * kVirialUnscale;
  sums.pairs_in_range = static_cast<std::uint64_t>(total[8]);
}

namespace {
// Calls visit(i, j, dx, dy, dz, r, fc) for every pair of local particles within range of the law,
// with fc the conservative force magnitude (along r-hat, positive repulsive); frozen-frozen pairs are
// skipped as in the shared loop.
template <class Visit>
void for_each_conservative_pair(const ParticleData& p, const Box& box, const PairLawTables& laws, const double* rho,
                                Visit&& visit) {
  std::visit(
      [&](const auto& lt) {
        using Law = typename std::decay_t<decltype(lt)>::LawType;
        const std::vector<double>* sc[kMaxScalars] = {};
        if constexpr (law_scalars<Law> > 0)
          for (int c = 0; c < law_scalars<Law>; ++c)
            if ((sc[c] = p.doubles(Law::kScalarFields[static_cast<std::size_t>(c)])) == nullptr) break;
        Law::with_evaluator(lt.table.params, [&](auto eval) {
          for_each_pair_binned(p, box, lt.table.max_cutoff, [&](std::size_t i, std::size_t j, double dx, double dy,
                                                                 double dz, double r) {
            if (p.body[i] != 0 && p.body[j] != 0) return;
            PairInput<double> in;
            in.r = r;
            if (rho != nullptr) {
              in.rho_i = rho[i];
              in.rho_j = rho[j];
            }
            for (int c = 0; c < kMaxScalars && sc[c] != nullptr; ++c) {  // eDPD's amplitude depends on T
              in.si[c] = (*sc[c])[i];
              in.sj[c] = (*sc[c])[j];
            }
            visit(i, j, dx, dy, dz, r, eval(lt.table(p.species[i], p.species[j]), in).fc);
          });
        });
      },
      laws);
}
}  // namespace

void reference_conservative_virial(const ParticleData& p, const Box& box, const PairLawTables& laws,
                                   std::vector<double>& w, const double* rho) {
  w.assign(p.n_local, 0.0);
  for_each_conservative_pair(p, box, laws, rho,
                             [&](std::size_t i, std::size_t j, double, double, double, double r, double fc) {
                               // r_ij . F^C_ij = r fc (a central force along r-hat).
                               const double half = 0.5 * fc * r;
                               w[i] += half;
                               w[j] += half;
                             });
}

void reference_conservative_virial_terms(const ParticleData& p, const Box& box, const PairLawTables& laws,
                                         VirialTerms& terms, const double* rho, const ExcludedPair& excluded) {
  for_each_conservative_pair(p, box, laws, rho,
                             [&](std::size_t i, std::size_t j, double dx, double dy, double dz, double r, double fc) {
                               if (fc == 0.0 || (excluded && excluded(p.id[i], p.id[j]))) return;
                               const double s = r > 0 ? fc / r : 0.0;
                               VirialTerm t;
                               t.i = static_cast<std::uint32_t>(i);
                               t.j = static_cast<std::uint32_t>(j);
                               t.d[0] = dx, t.d[1] = dy, t.d[2] = dz;
                               t.f[0] = s * dx, t.f[1] = s * dy, t.f[2] = s * dz;
                               terms.push_back(t);
                             });
}

std::function<void(const ParticleData&, const Box&, std::vector<double>&)> make_local_virial(
    PairLawTables laws, std::optional<DensitySettings> density) {
  return [laws = std::move(laws), density = std::move(density)](const ParticleData& p, const Box& box,
                                                                 std::vector<double>& w) {
    std::vector<double> rho;
    if (density) reference_density(p, box, *density, rho);
    reference_conservative_virial(p, box, laws, w, density ? rho.data() : nullptr);
  };
}

void reference_scalar_exchange(const ParticleData& p, const Box& box, const PairLawTables& laws, int channel,
                               const std::vector<double>& capacity,
                               const std::function<bool(std::size_t, std::size_t, double, double, double)>& want,
                               const std::function<void(std::size_t, std::size_t, double)>& visit) {
  std::visit(
      [&](const auto& lt) {
        using Law = typename std::decay_t<decltype(lt)>::LawType;
        if constexpr (law_scalars<Law> == 0) {
          throw std::invalid_argument("reference_scalar_exchange: the pair law transports no scalar");
        } else {
          if (channel < 0 || channel >= law_scalars<Law>)
            throw std::invalid_argument("reference_scalar_exchange: no such scalar channel");
          const std::vector<double>* sc[kMaxScalars] = {};
          for (int c = 0; c <= channel; ++c)
            if ((sc[c] = p.doubles(Law::kScalarFields[static_cast<std::size_t>(c)])) == nullptr)
              throw std::invalid_argument("reference_scalar_exchange: the particles do not hold the scalar");
          Law::with_evaluator(lt.table.params, [&](auto eval) {
            for_each_pair_binned(p, box, lt.table.max_cutoff, [&](std::size_t i, std::size_t j, double dx,
                                                                   double dy, double dz, double r) {
              const bool wi = p.body[i] != 0, wj = p.body[j] != 0;
              if ((wi && wj) || !want(i, j, dx, dy, dz)) return;
              // xi, xs and xm stay 0: the random terms' mean.
              PairInput<double> in = geometry_input<Law>(p, box, i, j, dx, dy, dz, r);
              in.inv_sqrt_dt = 1.0;
              for (int c = 0; c <= channel; ++c) {
                in.si[c] = (*sc[c])[i];
                in.sj[c] = (*sc[c])[j];
              }
              const PairForceT<double> pf = eval(lt.table(p.species[i], p.species[j]), in);
              const double qi = capacity[static_cast<std::size_t>(p.species[i])] * pf.qi[channel];
              const double qj = capacity[static_cast<std::size_t>(p.species[j])] * pf.qj[channel];
              visit(i, j, wi ? qi : (wj ? -qj : 0.5 * (qi - qj)));
            });
          });
        }
      },
      laws);
}

void reference_density(const ParticleData& p, const Box& box, const DensitySettings& density, std::vector<double>& rho) {
  std::vector<std::int64_t> q(p.n_local, 0);
  auto run = [&](auto kernel) {
    for_each_pair_binned(p, box, density.table.max_cutoff, [&](std::size_t i, std::size_t j, double, double, double,
                                                               double r) {
      const std::int64_t v = to_fixed(kernel(density.table(p.species[i], p.species[j]), r), kForceScale);
      q[i] += v;
      q[j] += v;
    });
  };
  with_density_kernel(density.kernel, run);
  rho.assign(p.n_local, 0.0);
  for (std::size_t i = 0; i < p.n_local; ++i) rho[i] = static_cast<double>(q[i]) * kForceUnscale;
}

}  // namespace mesodpd
