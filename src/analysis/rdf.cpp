// Radial distribution function g(r) of an orthorhombic box (periodic or bounded per axis), and the virial EOS from it.
#include "analysis/rdf.hpp"
#include "parallel/comm.hpp"
#include "io/atomic_file.hpp"

#include "physics/dpd_pair.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace mesodpd {

namespace {

// Distinct neighbour-cell shifts {-1, 0, +1} modulo nc, added as nc - 1, 0, 1 (mod nc). With nc = 1
// or 2 the shifts alias, and visiting an aliased cell twice would double-count its pairs.
std::vector<std::size_t> unique_shifts(std::size_t nc) {
  std::vector<std::size_t> s;
  for (std::size_t k : {nc - 1, std::size_t{0}, std::size_t{1}}) {
    const std::size_t m = k % nc;
    if (std::find(s.begin(), s.end(), m) == s.end()) s.push_back(m);
  }
  return s;
}

// True when cell (c + shift) mod nc is a neighbour of c: always on a periodic axis; on a bounded one
// only when it lies within one cell of c without crossing a face.
bool reaches(std::size_t c, std::size_t shift, std::size_t nc, bool periodic) {
  const std::size_t to = (c + shift) % nc;
  return periodic || (to > c ? to - c : c - to) <= 1;
}

// Cell index of coordinate u along an axis of length len split into nc cells. Wrapping here (not
// in the distance) keeps distances identical to a plain minimum-image computation.
std::size_t cell_index(double u, double len, std::size_t nc) {
  double w = u - len * std::floor(u / len);
  auto c = static_cast<std::size_t>(w / len * static_cast<double>(nc));
  return std::min(c, nc - 1);  // w / len can round up to 1
}

}  // namespace

RadialDistribution::RadialDistribution(std::size_t bins, double rmax)
    : bins_(bins), rmax_(rmax), dr_(rmax / static_cast<double>(bins)), counts_(bins, 0) {
  if (bins == 0) throw std::invalid_argument("RadialDistribution: bins must be > 0");
  if (!(rmax > 0.0)) throw std::invalid_argument("RadialDistribution: rmax must be > 0");
}

void RadialDistribution::sample(const double* x, const double* y, const double* z, std::size_t n,
                                std::array<double, 3> box_len, std::array<bool, 3> periodic) {
  const double lmin = std::min({box_len[0], box_len[1], box_len[2]});
  if (!(rmax_ < 0.5 * lmin)) {
    throw std::invalid_argument(
        fmt::format("RadialDistribution: rmax = {} must be < min(box_len)/2 = {}", rmax_, 0.5 * lmin));
  }

  // Cells at least rmax wide so every pair within rmax lies in adjacent cells; capped at about
  // 2n cells in total so a sparse sample in a big box does not pay for empty cells.
  std::array<std::size_t, 3> nc{};
  for (int d = 0; d < 3; ++d) nc[d] = std::max<std::size_t>(1, static_cast<std::size_t>(box_len[d] / rmax_));
  const std::size_t cap = 2 * n + 27;
  while (nc[0] * nc[1] * nc[2] > cap) {
    auto it = std::max_element(nc.begin(), nc.end());
    *it = std::max<std::size_t>(1, *it / 2);
  }
  const std::size_t ncell = nc[0] * nc[1] * nc[2];

  // Counting sort of particles by cell: order_[cell_start_[c] .. cell_start_[c+1]) are cell c.
  cell_of_.resize(n);
  cell_start_.assign(ncell + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t c =
        (cell_index(z[i], box_len[2], nc[2]) * nc[1] + cell_index(y[i], box_len[1], nc[1])) * nc[0] +
        cell_index(x[i], box_len[0], nc[0]);
    cell_of_[i] = c;
    ++cell_start_[c + 1];
  }
  for (std::size_t c = 0; c < ncell; ++c) cell_start_[c + 1] += cell_start_[c];
  order_.resize(n);
  {
    std::vector<std::size_t> fill(cell_start_.begin(), cell_start_.end() - 1);
    for (std::size_t i = 0; i < n; ++i) order_[fill[cell_of_[i]]++] = i;
  }

  const std::array<std::vector<std::size_t>, 3> shifts{unique_shifts(nc[0]), unique_shifts(nc[1]),
                                                       unique_shifts(nc[2])};
  const double rmax2 = rmax_ * rmax_;
  for (std::size_t cz = 0; cz < nc[2]; ++cz) {
    for (std::size_t cy = 0; cy < nc[1]; ++cy) {
      for (std::size_t cx = 0; cx < nc[0]; ++cx) {
        const std::size_t c = (cz * nc[1] + cy) * nc[0] + cx;
        for (std::size_t sz : shifts[2]) {
          if (!reaches(cz, sz, nc[2], periodic[2])) continue;
          for (std::size_t sy : shifts[1]) {
            if (!reaches(cy, sy, nc[1], periodic[1])) continue;
            for (std::size_t sx : shifts[0]) {
              if (!reaches(cx, sx, nc[0], periodic[0])) continue;
              const std::size_t nb =
                  (((cz + sz) % nc[2]) * nc[1] + (cy + sy) % nc[1]) * nc[0] + (cx + sx) % nc[0];
              // Ordered pairs (i in c, j in nb); the symmetric shift set visits (j, i) from nb.
              for (std::size_t a = cell_start_[c]; a < cell_start_[c + 1]; ++a) {
                const std::size_t i = order_[a];
                for (std::size_t b = cell_start_[nb]; b < cell_start_[nb + 1]; ++b) {
                  const std::size_t j = order_[b];
                  if (i == j) continue;
                  double dx = x[j] - x[i];
                  double dy = y[j] - y[i];
                  double dz = z[j] - z[i];
                  if (periodic[0]) dx -= box_len[0] * std::nearbyint(dx / box_len[0]);
                  if (periodic[1]) dy -= box_len[1] * std::nearbyint(dy / box_len[1]);
                  if (periodic[2]) dz -= box_len[2] * std::nearbyint(dz / box_len[2]);
                  const double r2 = dx * dx + dy * dy + dz * dz;
                  if (r2 >= rmax2) continue;
                  auto bin = static_cast<std::size_t>(std::sqrt(r2) / dr_);
                  ++counts_[std::min(bin, bins_ - 1)];
                }
              }
            }
          }
        }
      }
    }
  }

  const double volume = box_len[0] * box_len[1] * box_len[2];
  const auto nd = static_cast<double>(n);
  ideal_pair_density_sum_ += nd * (nd - 1.0) / volume;
  ++samples_;
}

std::vector<double> RadialDistribution::r() const {
  std::vector<double> out(bins_);
  for (std::size_t b = 0; b < bins_; ++b) out[b] = (static_cast<double>(b) + 0.5) * dr_;
  return out;
}

std::vector<double> RadialDistribution::g() const {
  std::vector<double> out(bins_, 0.0);
  if (ideal_pair_density_sum_ <= 0.0) return out;
  for (std::size_t b = 0; b < bins_; ++b) {
    const double lo = static_cast<double>(b) * dr_;
    const double hi = lo + dr_;
    const double shell = 4.0 / 3.0 * std::numbers::pi * (hi * hi * hi - lo * lo * lo);
    out[b] = static_cast<double>(counts_[b]) / (ideal_pair_density_sum_ * shell);
  }
  return out;
}

void RadialDistribution::write_csv(const std::string& path) const {
  const auto rr = r();
  const auto gg = g();
  write_file_atomically(path, [&](std::ostream& os) {
    os << "r,g\n";
    for (std::size_t b = 0; b < bins_; ++b) os << fmt::format("{:.10g},{:.10g}\n", rr[b], gg[b]);
  });
}

double virial_pressure_from_rdf(const std::vector<double>& r, const std::vector<double>& g, double dr,
                                double rho, double kT, double a, double rc) {
  if (r.size() != g.size()) throw std::invalid_argument("virial_pressure_from_rdf: r and g differ in length");
  // F^C from the engine's own force law (physics/dpd_pair.hpp), not a second copy of the formula.
  DpdPairParams conservative;
  conservative.a = a;
  conservative.rc = rc;
  conservative.rd = rc;
  conservative.rcut2 = rc * rc;
  double integral = 0.0;
  for (std::size_t b = 0; b < r.size(); ++b) {
    if (r[b] >= rc) continue;  // F^C vanishes beyond the cutoff
    const double fc = dpd_pair_force(conservative, r[b], 0.0, 0.0, 1.0).fc;
    integral += r[b] * fc * g[b] * r[b] * r[b] * dr;
  }
  // seed 003 line ~303: p = rho kT + (2 pi/3) rho^2 Int r F^C(r) g(r) r^2 dr
  return rho * kT + 2.0 * std::numbers::pi / 3.0 * rho * rho * integral;
}

void RadialDistribution::save(ByteWriter& w) const {
  w.put<std::uint64_t>(bins_);
  w.put<double>(rmax_);
  w.put_vector(counts_);
  w.put<double>(ideal_pair_density_sum_);
  w.put<std::uint64_t>(samples_);
}

void RadialDistribution::load(ByteReader& r, const std::string& context) {
  const auto bins = r.get<std::uint64_t>();
  const double rmax = r.get<double>();
  if (bins != bins_ || rmax != rmax_)
    throw ConfigError(fmt::format("analysis.rdf.bins/rmax: {}/{} differ from the checkpoint's {}/{} ({})", bins_,
                                  rmax_, bins, rmax, context));
  counts_ = r.get_vector<std::uint64_t>();
  ideal_pair_density_sum_ = r.get<double>();
  samples_ = r.get<std::uint64_t>();
  if (counts_.size() != bins_) throw ConfigError(fmt::format("{}: inconsistent RDF state", context));
}

RdfStage::RdfStage(const RdfSpec& spec, AnalysisOutput out, SystemSnapshot& snapshot, const Comm& comm)
    : SnapshotAnalysisStage(std::move(out), snapshot, spec.start, spec.every) {
  if (comm.root()) a_.emplace(static_cast<std::size_t>(spec.bins), spec.rmax);
}

void RdfStage::sample(const StepContext& ctx, const ParticleData& p) {
  a_->sample(p.x.data(), p.y.data(), p.z.data(), p.n_local, {ctx.box.len.x, ctx.box.len.y, ctx.box.len.z},
             ctx.box.periodic);
}

std::string RdfStage::finish(const StepContext&) {
  if (out_.files() && a_ && a_->samples() > 0) a_->write_csv((out_ / "rdf.csv").string());
  return {};
}

}  // namespace mesodpd
