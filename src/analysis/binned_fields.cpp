// Time-averaged binned fields and the slab profile fit (see binned_fields.hpp).
#include "analysis/binned_fields.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <numeric>
#include <span>
#include <stdexcept>
#include <type_traits>

#include "analysis/svg_plot.hpp"
#include "io/atomic_file.hpp"
#include "io/json_number.hpp"
#include "io/vtk_image.hpp"
#include "parallel/comm.hpp"

namespace mesodpd {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr std::size_t kNoBin = std::numeric_limits<std::size_t>::max();
constexpr double kPi = 3.14159265358979323846;

// One particle's contribution in fixed point; refuses values the 64-bit per-particle term cannot hold
// (|m v^2| above 2 x 10^9, far beyond a stable run's velocities).
std::int64_t fixed(double x) {
  const double scaled = x * BinnedFields::kFixedScale;
  if (!(std::fabs(scaled) < 9.0e18))
    throw std::overflow_error(fmt::format("analysis.fields: a particle's momentum or kinetic term {} is too large "
                                          "to bin (non-finite, or beyond 2e9)", x));
  return std::llround(scaled);
}

// x wrapped into [0, len).
double wrap(double x, double len) {
  double w = x - len * std::floor(x / len);
  if (w >= len) w -= len;
  return w;
}

const char* kAxisNames[] = {"x", "y", "z"};

}  // namespace

// ---------------------------------------------------------------------------------------------
// Slab fit

namespace {

struct SlabModel {
  double period;
  // Value and gradient with respect to (rho_l, rho_v, z0, h, w) at z.
  double eval(const double* p, double z, double* grad) const {
    double d = z - p[2];
    if (period > 0) d -= period * std::round(d / period);
    const double ad = std::fabs(d);
    const double u = (ad - p[3]) / p[4];
    const double t = std::tanh(u), sech2 = 1.0 - t * t;
    const double a = 0.5 * (p[0] + p[1]), b = 0.5 * (p[0] - p[1]);
    if (grad) {
      grad[0] = 0.5 - 0.5 * t;
      grad[1] = 0.5 + 0.5 * t;
      grad[2] = b * sech2 * (d > 0 ? 1.0 : (d < 0 ? -1.0 : 0.0)) / p[4];
      grad[3] = b * sech2 / p[4];
      grad[4] = b * sech2 * u / p[4];
    }
    return a - b * t;
  }
};

// Solves the 5 x 5 system a x = b by Gaussian elimination with partial pivoting; false if singular.
bool solve5(double a[5][5], double b[5], double x[5]) {
  for (int c = 0; c < 5; ++c) {
    int piv = c;
    for (int r = c + 1; r < 5; ++r)
      if (std::fabs(a[r][c]) > std::fabs(a[piv][c])) piv = r;
    if (!(std::fabs(a[piv][c]) > 0.0)) return false;
    if (piv != c) {
      for (int k = 0; k < 5; ++k) std::swap(a[c][k], a[piv][k]);
      std::swap(b[c], b[piv]);
    }
    for (int r = c + 1; r < 5; ++r) {
      const double f = a[r][c] / a[c][c];
      for (int k = c; k < 5; ++k) a[r][k] -= f * a[c][k];
      b[r] -= f * b[c];
    }
  }
  for (int c = 4; c >= 0; --c) {
    double s = b[c];
    for (int k = c + 1; k < 5; ++k) s -= a[c][k] * x[k];
    x[c] = s / a[c][c];
  }
  return true;
}

}  // namespace

SlabFit fit_slab_profile(const std::vector<double>& z, const std::vector<double>& rho, double period) {
  SlabFit out;
  std::vector<double> zs, ys;
  for (std::size_t k = 0; k < z.size() && k < rho.size(); ++k)
    if (std::isfinite(z[k]) && std::isfinite(rho[k])) zs.push_back(z[k]), ys.push_back(rho[k]);
  const std::size_t n = zs.size();
  if (n < 6) return out;
  // Start: liquid and vapour densities from the top and bottom quarters of the values, the centre as the
  // excess-density-weighted mean position (circular for a periodic axis), the half-width from the
  // excess amount, and a width of a couple of bins.
  std::vector<double> sorted = ys;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t q = std::max<std::size_t>(1, n / 4);
  const double rho_v = std::accumulate(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(q), 0.0) / q;
  const double rho_l = std::accumulate(sorted.end() - static_cast<std::ptrdiff_t>(q), sorted.end(), 0.0) / q;
  if (!(rho_l > rho_v)) return out;
  const double zmin = *std::min_element(zs.begin(), zs.end()), zmax = *std::max_element(zs.begin(), zs.end());
  const double dz = (zmax - zmin) / static_cast<double>(n - 1);
  double excess = 0, wsum = 0, c = 0, s = 0, zsum = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double e = std::max(0.0, ys[k] - rho_v);
    excess += e * dz;
    wsum += e;
    if (period > 0) {
      c += e * std::cos(2 * kPi * zs[k] / period);
      s += e * std::sin(2 * kPi * zs[k] / period);
    } else {
      zsum += e * zs[k];
    }
  }
  double p[5];
  p[0] = rho_l;
  p[1] = rho_v;
  p[2] = period > 0 ? period * (std::atan2(-s, -c) + kPi) / (2 * kPi) : zsum / wsum;
  p[3] = std::max(dz, excess / (2 * (rho_l - rho_v)));
  p[4] = std::max(dz, 0.5);
  const SlabModel model{period};
  auto cost_of = [&](const double* params) {
    double sum = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const double r = ys[k] - model.eval(params, zs[k], nullptr);
      sum += r * r;
    }
    return sum;
  };
  double cost = cost_of(p);
  double lambda = 1e-3;
  int it = 0;
  bool converged = false;
  for (; it < 1000 && !converged; ++it) {
    double a[5][5] = {}, g[5] = {}, grad[5];
    for (std::size_t k = 0; k < n; ++k) {
      const double r = ys[k] - model.eval(p, zs[k], grad);
      for (int i = 0; i < 5; ++i) {
        g[i] += grad[i] * r;
        for (int j = 0; j < 5; ++j) a[i][j] += grad[i] * grad[j];
      }
    }
    while (true) {
      double m[5][5], rhs[5], step[5];
      for (int i = 0; i < 5; ++i) {
        for (int j = 0; j < 5; ++j) m[i][j] = a[i][j];
        m[i][i] += lambda * std::max(a[i][i], 1e-12);
        rhs[i] = g[i];
      }
      if (!solve5(m, rhs, step)) return out;
      double trial[5];
      for (int i = 0; i < 5; ++i) trial[i] = p[i] + step[i];
      const bool valid = trial[3] > 0 && trial[4] > 1e-6;
      const double trial_cost = valid ? cost_of(trial) : std::numeric_limits<double>::infinity();
      if (trial_cost <= cost) {
        double change = 0;
        for (int i = 0; i < 5; ++i) change = std::max(change, std::fabs(step[i]) / (std::fabs(p[i]) + 1e-9));
        std::copy(trial, trial + 5, p);
        const double gain = cost - trial_cost;
        cost = trial_cost;
        lambda = std::max(lambda / 3, 1e-12);
        converged = change < 1e-10 || gain <= 1e-15 * std::max(cost, 1e-300);
        break;
      }
      lambda *= 4;
      if (lambda > 1e12) {  // no step lowers the cost: at the minimum to round-off
        converged = true;
        break;
      }
    }
  }
  if (period > 0) p[2] = wrap(p[2], period);
  out.converged = converged;
  out.rho_l = p[0];
  out.rho_v = p[1];
  out.z0 = p[2];
  out.half_width = p[3];
  out.width = p[4];
  out.rms = std::sqrt(cost / static_cast<double>(n));
  out.iterations = it;
  return out;
}

// ---------------------------------------------------------------------------------------------
// Binning

BinnedFields::BinnedFields(const FieldsSpec& spec, std::vector<double> species_mass,
                           std::vector<std::string> species_names, std::array<double, 3> box_len,
                           std::array<bool, 3> periodic)
    : spec_(spec),
      mass_(std::move(species_mass)),
      names_(std::move(species_names)),
      box_len_(box_len),
      periodic_(periodic) {
  n_species_ = mass_.size();
  stride_ = n_species_ + 6 + spec_.means.size();
  n_cells_ = 1;
  for (std::size_t d = 0; d < 3; ++d) {
    if (spec_.bins[d] < 1 || !(spec_.region_hi[d] > spec_.region_lo[d]))
      throw std::invalid_argument("BinnedFields: bins >= 1 and hi > lo on every axis (validate() checks both)");
    n_cells_ *= static_cast<std::size_t>(spec_.bins[d]);
    inv_width_[d] = spec_.bins[d] / (spec_.region_hi[d] - spec_.region_lo[d]);
  }
  if (spec_.fit == FieldsFit::Slab && profile_axis() >= 0) {
    blocked_ = true;
    blocks_ = BlockRows(n_cells_, static_cast<std::size_t>(spec_.blocks));
    row_.assign(n_cells_, 0.0);
  }
  selected_.assign(n_species_, 0);
  for (int s : spec_.selected) selected_.at(static_cast<std::size_t>(s)) = 1;
  sums_.assign(n_cells_ * stride_, 0);
}

std::size_t BinnedFields::bin_of(double x, int axis) const {
  const auto d = static_cast<std::size_t>(axis);
  if (!(x >= spec_.region_lo[d] && x < spec_.region_hi[d])) return kNoBin;
  const auto b = static_cast<std::size_t>((x - spec_.region_lo[d]) * inv_width_[d]);
  return std::min(b, static_cast<std::size_t>(spec_.bins[d] - 1));
}

double BinnedFields::centring_shift(const ParticleData& own, const Comm& comm) const {
  // The centre of mass on a periodic axis is the circular mean of the angles 2 pi x / L (Bai and Breen,
  // J. Graph. Tools 13 (2008) 53): theta = atan2(-<sin>, -<cos>) + pi. The sums are fixed point, so
  // the shift is the same on every rank and for any rank count.
  const auto a = static_cast<std::size_t>(spec_.centre_axis);
  const double len = box_len_[a];
  const std::vector<double>& pos = a == 0 ? own.x : (a == 1 ? own.y : own.z);
  FieldSum cs[2] = {0, 0};
  for (std::size_t i = 0; i < own.n_local; ++i) {
    const auto s = static_cast<std::size_t>(own.species[i]);
    if (!selected_[s]) continue;
    const double theta = 2 * kPi * wrap(pos[i], len) / len;
    cs[0] += fixed(mass_[s] * std::cos(theta));
    cs[1] += fixed(mass_[s] * std::sin(theta));
  }
  comm.sum(std::span<FieldSum>(cs, 2));
  if (cs[0] == 0 && cs[1] == 0) return 0.0;
  const double theta = std::atan2(-static_cast<double>(cs[1]), -static_cast<double>(cs[0])) + kPi;
  return 0.5 * len - len * theta / (2 * kPi);
}

void BinnedFields::sample(const ParticleData& own, const Comm& comm, std::uint64_t step) {
  const double shift = spec_.centre_axis >= 0 ? centring_shift(own, comm) : 0.0;
  scratch_.assign(n_cells_ * stride_, 0);
  // The fields averaged per bin (FieldsSpec::means), found by name among those the particles hold.
  std::vector<const double*> means(spec_.means.size(), nullptr);
  own.for_each_field([&](const FieldInfo& info, const auto& v) {
    if constexpr (std::is_same_v<typename std::decay_t<decltype(v)>::value_type, double>)
      for (std::size_t m = 0; m < means.size(); ++m)
        if (spec_.means[m] == info.name) means[m] = v.data();
  });
  for (std::size_t m = 0; m < means.size(); ++m)
    if (means[m] == nullptr)
      throw ConfigError(fmt::format("analysis.fields.means: this run holds no particle field \"{}\" (\"temp\" needs "
                                    "pair.style = \"edpd\")",
                                    spec_.means[m]),
                        "analysis.fields.means");
  const std::vector<double>* pos[3] = {&own.x, &own.y, &own.z};
  const std::vector<double>* vel[3] = {&own.vx, &own.vy, &own.vz};
  for (std::size_t i = 0; i < own.n_local; ++i) {
    std::size_t cell = 0, stride = 1;
    bool inside = true;
    for (int d = 0; d < 3 && inside; ++d) {
      const auto du = static_cast<std::size_t>(d);
      const double x = wrap((*pos[du])[i] + (d == spec_.centre_axis ? shift : 0.0), box_len_[du]);
      const std::size_t b = bin_of(x, d);
      inside = b != kNoBin;
      cell += b * stride;
      stride *= static_cast<std::size_t>(spec_.bins[du]);
    }
    if (!inside) continue;
    FieldSum* c = &scratch_[cell * stride_];
    const auto s = static_cast<std::size_t>(own.species[i]);
    c[s] += 1;
    if (!selected_[s]) continue;
    for (std::size_t d = 0; d < 3; ++d) {
      const double v = (*vel[d])[i];
      const double p = mass_[s] * v;
      c[n_species_ + d] += fixed(p);
      c[n_species_ + 3 + d] += fixed(p * v);
    }
    for (std::size_t m = 0; m < means.size(); ++m) c[n_species_ + 6 + m] += fixed(means[m][i]);
  }
  comm.sum(std::span<FieldSum>(scratch_));
  for (std::size_t k = 0; k < sums_.size(); ++k) sums_[k] += scratch_[k];
  if (blocked_) {
    for (std::size_t c = 0; c < n_cells_; ++c) {
      FieldSum n = 0;
      for (std::size_t s = 0; s < n_species_; ++s)
        if (selected_[s]) n += scratch_[c * stride_ + s];
      row_[c] = static_cast<double>(n);
    }
    blocks_.add(row_.data());
  }
  if (samples_ == 0) first_step_ = step;
  last_step_ = step;
  ++samples_;
}

// ---------------------------------------------------------------------------------------------
// Results

double BinnedFields::cell_volume() const {
  return 1.0 / (inv_width_[0] * inv_width_[1] * inv_width_[2]);
}

int BinnedFields::profile_axis() const {
  int axis = -1, count = 0;
  for (int d = 0; d < 3; ++d)
    if (spec_.bins[static_cast<std::size_t>(d)] > 1) axis = d, ++count;
  return count == 1 ? axis : -1;
}

std::array<double, 3> BinnedFields::centre(std::size_t cell) const {
  const auto nx = static_cast<std::size_t>(spec_.bins[0]), ny = static_cast<std::size_t>(spec_.bins[1]);
  const std::size_t idx[3] = {cell % nx, (cell / nx) % ny, cell / (nx * ny)};
  std::array<double, 3> c{};
  for (std::size_t d = 0; d < 3; ++d) c[d] = spec_.region_lo[d] + (static_cast<double>(idx[d]) + 0.5) / inv_width_[d];
  return c;
}

std::vector<double> BinnedFields::species_density(int species) const {
  std::vector<double> out(n_cells_, kNaN);
  if (samples_ == 0) return out;
  const long double norm = static_cast<long double>(samples_) * cell_volume();
  for (std::size_t c = 0; c < n_cells_; ++c)
    out[c] = static_cast<double>(total(c, static_cast<std::size_t>(species)) / norm);
  return out;
}

std::vector<double> BinnedFields::density() const {
  std::vector<double> out(n_cells_, kNaN);
  if (samples_ == 0) return out;
  const long double norm = static_cast<long double>(samples_) * cell_volume();
  for (std::size_t c = 0; c < n_cells_; ++c) {
    long double n = 0;
    for (std::size_t s = 0; s < n_species_; ++s)
      if (selected_[s]) n += total(c, s);
    out[c] = static_cast<double>(n / norm);
  }
  return out;
}

std::vector<double> BinnedFields::velocity(int axis) const {
  std::vector<double> out(n_cells_, kNaN);
  for (std::size_t c = 0; c < n_cells_; ++c) {
    long double m = 0;
    for (std::size_t s = 0; s < n_species_; ++s)
      if (selected_[s]) m += total(c, s) * mass_[s];
    if (m > 0) out[c] = static_cast<double>(total(c, n_species_ + static_cast<std::size_t>(axis)) / kFixedScale / m);
  }
  return out;
}

std::vector<double> BinnedFields::mean(std::size_t m) const {
  std::vector<double> out(n_cells_, kNaN);
  for (std::size_t c = 0; c < n_cells_; ++c) {
    long double n = 0;
    for (std::size_t s = 0; s < n_species_; ++s)
      if (selected_[s]) n += total(c, s);
    if (n > 0) out[c] = static_cast<double>(total(c, n_species_ + 6 + m) / kFixedScale / n);
  }
  return out;
}

std::vector<double> BinnedFields::temperature(int axis) const {
  std::vector<double> out(n_cells_, kNaN);
  for (std::size_t c = 0; c < n_cells_; ++c) {
    long double m = 0, n = 0;
    for (std::size_t s = 0; s < n_species_; ++s)
      if (selected_[s]) m += total(c, s) * mass_[s], n += total(c, s);
    if (n < 2) continue;
    long double t = 0;
    for (int d = (axis < 0 ? 0 : axis); d <= (axis < 0 ? 2 : axis); ++d) {
      const long double p = total(c, n_species_ + static_cast<std::size_t>(d)) / kFixedScale;
      const long double k = total(c, n_species_ + 3 + static_cast<std::size_t>(d)) / kFixedScale;
      t += (k - p * p / m) / (n - 1);
    }
    out[c] = static_cast<double>(axis < 0 ? t / 3 : t);
  }
  return out;
}

double BinnedFields::fit_period() const {
  // Minimum image only where the profile spans a whole periodic box length.
  const int axis = profile_axis();
  if (axis < 0) return 0.0;
  const auto a = static_cast<std::size_t>(axis);
  return spec_.region_lo[a] == 0.0 && spec_.region_hi[a] == box_len_[a] && periodic_[a] ? box_len_[a] : 0.0;
}

SlabFit BinnedFields::slab_fit() const {
  const int axis = profile_axis();
  if (axis < 0 || samples_ == 0) return {};
  std::vector<double> z(n_cells_);
  for (std::size_t c = 0; c < n_cells_; ++c) z[c] = centre(c)[static_cast<std::size_t>(axis)];
  SlabFit fit = fit_slab_profile(z, density(), fit_period());
  // Error bars: the spread of the fits to each full block (standard error of their mean).
  std::vector<std::array<double, 4>> per_block;
  if (blocked_) {
    const double norm = static_cast<double>(blocks_.samples_per_block()) * cell_volume();
    std::vector<double> rho(n_cells_);
    for (std::size_t k = 0; k < blocks_.full_blocks(); ++k) {
      for (std::size_t c = 0; c < n_cells_; ++c) rho[c] = blocks_.block(k)[c] / norm;
      const SlabFit b = fit_slab_profile(z, rho, fit_period());
      if (b.converged) per_block.push_back({b.rho_l, b.rho_v, b.half_width, b.width});
    }
  }
  fit.blocks_used = static_cast<int>(per_block.size());
  double* errs[4] = {&fit.rho_l_err, &fit.rho_v_err, &fit.half_width_err, &fit.width_err};
  for (std::size_t q = 0; q < 4; ++q) {
    const double n = static_cast<double>(per_block.size());
    if (per_block.size() < 2) {
      *errs[q] = kNaN;
      continue;
    }
    double mean = 0, ss = 0;
    for (const auto& b : per_block) mean += b[q] / n;
    for (const auto& b : per_block) ss += (b[q] - mean) * (b[q] - mean);
    *errs[q] = std::sqrt(ss / (n - 1) / n);
  }
  return fit;
}

std::string BinnedFields::write(const std::filesystem::path& dir) const {
  const std::string& name = spec_.name;
  const std::vector<double> rho = density();
  std::vector<std::vector<double>> rho_s;
  for (std::size_t s = 0; s < n_species_; ++s) rho_s.push_back(species_density(static_cast<int>(s)));
  const std::vector<double> v[3] = {velocity(0), velocity(1), velocity(2)};
  const std::vector<double> t = temperature(-1);
  const std::vector<double> td[3] = {temperature(0), temperature(1), temperature(2)};
  std::vector<std::vector<double>> means;
  for (std::size_t m = 0; m < spec_.means.size(); ++m) means.push_back(mean(m));

  // VTK image data: one cell per bin.
  VtkImage image;
  image.cells = spec_.bins;
  image.origin = spec_.region_lo;
  for (std::size_t d = 0; d < 3; ++d) image.spacing[d] = 1.0 / inv_width_[d];
  image.arrays.push_back({"density", 1, rho});
  for (std::size_t s = 0; s < n_species_; ++s) image.arrays.push_back({"density_" + names_[s], 1, rho_s[s]});
  std::vector<double> vel(3 * n_cells_);
  for (std::size_t c = 0; c < n_cells_; ++c)
    for (std::size_t d = 0; d < 3; ++d) vel[3 * c + d] = v[d][c];
  image.arrays.push_back({"velocity", 3, std::move(vel)});
  image.arrays.push_back({"temperature", 1, t});
  for (std::size_t d = 0; d < 3; ++d) image.arrays.push_back({fmt::format("temperature_{}", kAxisNames[d]), 1, td[d]});
  for (std::size_t m = 0; m < means.size(); ++m) image.arrays.push_back({"mean_" + spec_.means[m], 1, means[m]});
  image.field_data = {{"samples", static_cast<double>(samples_)},
                      {"first_step", static_cast<double>(first_step_)},
                      {"last_step", static_cast<double>(last_step_)}};
  write_vti(dir / (name + ".vti"), image);

  // CSV: one row per bin, x fastest.
  write_file_atomically(dir / (name + ".csv"), [&](std::ostream& os) {
    os << "ix,iy,iz,x,y,z,density";
    for (const std::string& s : names_) os << ",density_" << s;
    os << ",vx,vy,vz,temperature,temperature_x,temperature_y,temperature_z";
    for (const std::string& m : spec_.means) os << ",mean_" << m;
    os << "\n";
    const auto nx = static_cast<std::size_t>(spec_.bins[0]), ny = static_cast<std::size_t>(spec_.bins[1]);
    for (std::size_t c = 0; c < n_cells_; ++c) {
      const auto x = centre(c);
      os << fmt::format("{},{},{},{:.10g},{:.10g},{:.10g},{:.10g}", c % nx, (c / nx) % ny, c / (nx * ny), x[0], x[1],
                        x[2], rho[c]);
      for (std::size_t s = 0; s < n_species_; ++s) os << fmt::format(",{:.10g}", rho_s[s][c]);
      os << fmt::format(",{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g}", v[0][c], v[1][c], v[2][c], t[c],
                        td[0][c], td[1][c], td[2][c]);
      for (const std::vector<double>& m : means) os << fmt::format(",{:.10g}", m[c]);
      os << "\n";
    }
  });

  // JSON summary: the grid, the sampling and, for a slab, the fit.
  nlohmann::ordered_json j;
  j["name"] = name;
  j["bins"] = spec_.bins;
  j["lo"] = {json_number(spec_.region_lo[0]), json_number(spec_.region_lo[1]), json_number(spec_.region_lo[2])};
  j["hi"] = {json_number(spec_.region_hi[0]), json_number(spec_.region_hi[1]), json_number(spec_.region_hi[2])};
  j["bin_volume"] = json_number(cell_volume());
  j["samples"] = samples_;
  j["first_step"] = first_step_;
  j["last_step"] = last_step_;
  std::vector<std::string> selected;
  for (std::size_t s = 0; s < n_species_; ++s)
    if (selected_[s]) selected.push_back(names_[s]);
  j["species"] = selected;
  j["centre"] = spec_.centre_axis >= 0 ? kAxisNames[spec_.centre_axis] : "none";
  j["means"] = spec_.means;
  std::string summary;
  const int axis = profile_axis();
  SlabFit fit;
  if (spec_.fit == FieldsFit::Slab) {
    fit = slab_fit();
    nlohmann::ordered_json f;
    f["converged"] = fit.converged;
    f["rho_l"] = json_number(fit.rho_l);
    f["rho_l_err"] = json_number(fit.rho_l_err);
    f["rho_v"] = json_number(fit.rho_v);
    f["rho_v_err"] = json_number(fit.rho_v_err);
    f["z0"] = json_number(fit.z0);
    f["half_width"] = json_number(fit.half_width);
    f["half_width_err"] = json_number(fit.half_width_err);
    f["width"] = json_number(fit.width);
    f["width_err"] = json_number(fit.width_err);
    f["blocks_used"] = fit.blocks_used;
    f["thickness_10_90"] = json_number(2 * std::atanh(0.8) * fit.width);
    f["rms"] = json_number(fit.rms);
    f["iterations"] = fit.iterations;
    f["period"] = json_number(fit_period());  // |z - z0| is the minimum image for this period (0: plain)
    j["slab_fit"] = f;
    summary += fmt::format("{}: slab fit{} rho_l = {:.4f} +- {:.4f}, rho_v = {:.4g} +- {:.2g}, interface width w = "
                           "{:.4f} +- {:.4f} (10-90 thickness {:.4f}), half-width {:.4f} at {} = {:.4f} ({} blocks)\n",
                           name, fit.converged ? "" : " (NOT converged)", fit.rho_l, fit.rho_l_err, fit.rho_v,
                           fit.rho_v_err, fit.width, fit.width_err, 2 * std::atanh(0.8) * fit.width, fit.half_width,
                           axis >= 0 ? kAxisNames[axis] : "?", fit.z0, fit.blocks_used);
  }
  write_file_atomically(dir / (name + ".json"), [&](std::ostream& os) { os << j.dump(2) << '\n'; });

  // Pictures: maps of a 2-D grid (density and the two in-plane velocity components), the profile of a
  // 1-D grid; PNG maps with streamlines, and 3-D grids, are drawn by tools/plot_fields.py.
  int plane[2] = {-1, -1}, in_plane = 0;
  for (int d = 0; d < 3; ++d)
    if (spec_.bins[static_cast<std::size_t>(d)] > 1 && in_plane < 2) plane[in_plane++] = d;
  if (in_plane == 2 && plane[0] >= 0 && spec_.bins[static_cast<std::size_t>(3 - plane[0] - plane[1])] == 1) {
    const auto a = static_cast<std::size_t>(plane[0]), b = static_cast<std::size_t>(plane[1]);
    SvgGrid g;
    g.nx = static_cast<std::size_t>(spec_.bins[a]);
    g.ny = static_cast<std::size_t>(spec_.bins[b]);
    g.x0 = spec_.region_lo[a];
    g.x1 = spec_.region_hi[a];
    g.y0 = spec_.region_lo[b];
    g.y1 = spec_.region_hi[b];
    // Cells are stored x fastest, then y, then z; with one bin along the third axis, a is fastest.
    const std::string note = fmt::format("{} samples, steps {} to {}; grey: no particles", samples_, first_step_, last_step_);
    g.values = rho;
    write_svg_map((dir / (name + "_density.svg")).string(), fmt::format("Number density ({})", name), kAxisNames[a],
                  kAxisNames[b], g, "density", {note});
    for (std::size_t d : {a, b}) {
      g.values = v[d];
      write_svg_map((dir / fmt::format("{}_v{}.svg", name, kAxisNames[d])).string(),
                    fmt::format("Velocity v_{} ({})", kAxisNames[d], name), kAxisNames[a], kAxisNames[b], g,
                    fmt::format("v_{}", kAxisNames[d]), {note});
    }
  }
  if (axis >= 0) {
    std::vector<double> z(n_cells_);
    for (std::size_t c = 0; c < n_cells_; ++c) z[c] = centre(c)[static_cast<std::size_t>(axis)];
    std::vector<SvgSeries> series{{z, rho, {}, "density (selected species)", "#1f77b4", true, true}};
    if (selected.size() > 1 || n_species_ > 1)
      for (std::size_t s = 0; s < n_species_; ++s) series.push_back({z, rho_s[s], {}, "density " + names_[s], "", true, false});
    std::vector<std::string> notes{fmt::format("{} samples, steps {} to {}", samples_, first_step_, last_step_)};
    if (spec_.fit == FieldsFit::Slab) {
      std::vector<double> model(n_cells_);
      const double p[5] = {fit.rho_l, fit.rho_v, fit.z0, fit.half_width, fit.width};
      const SlabModel m{fit_period()};
      for (std::size_t c = 0; c < n_cells_; ++c) model[c] = m.eval(p, z[c], nullptr);
      series.push_back({z, model, {}, "tanh fit", "#d62728", true, false});
      notes.push_back(fmt::format("rho_l = {:.4f}, rho_v = {:.4f}, w = {:.4f}, h = {:.4f}", fit.rho_l, fit.rho_v,
                                  fit.width, fit.half_width));
    }
    write_svg_plot((dir / (name + "_profile.svg")).string(), fmt::format("Density profile ({})", name),
                   kAxisNames[axis], "number density", series, notes);
  }
  return summary;
}

// ---------------------------------------------------------------------------------------------
// Checkpoint state

void BinnedFields::save(ByteWriter& w) const {
  w.put<std::uint64_t>(n_species_);
  for (std::size_t d = 0; d < 3; ++d) {
    w.put<std::int32_t>(spec_.bins[d]);
    w.put<double>(spec_.region_lo[d]);
    w.put<double>(spec_.region_hi[d]);
  }
  w.put<std::int32_t>(spec_.centre_axis);
  w.put<std::int32_t>(blocked_ ? spec_.blocks : 0);
  w.put_vector(selected_);
  w.put<std::uint64_t>(samples_);
  w.put<std::uint64_t>(first_step_);
  w.put<std::uint64_t>(last_step_);
  w.put_vector(sums_);
  if (blocked_) blocks_.save(w);
}

void BinnedFields::load(ByteReader& r, const std::string& context) {
  bool same = r.get<std::uint64_t>() == n_species_;
  for (std::size_t d = 0; d < 3; ++d) {
    same = r.get<std::int32_t>() == spec_.bins[d] && same;
    same = r.get<double>() == spec_.region_lo[d] && same;
    same = r.get<double>() == spec_.region_hi[d] && same;
  }
  same = r.get<std::int32_t>() == spec_.centre_axis && same;
  same = r.get<std::int32_t>() == (blocked_ ? spec_.blocks : 0) && same;
  same = r.get_vector<char>() == selected_ && same;
  if (!same)
    throw ConfigError(fmt::format("analysis.fields \"{}\": bins, lo, hi, centre, fit, blocks or the species binned differ from the "
                                  "checkpoint's ({}); keep them, or give the grid another name to start it afresh",
                                  spec_.name, context));
  samples_ = r.get<std::uint64_t>();
  first_step_ = r.get<std::uint64_t>();
  last_step_ = r.get<std::uint64_t>();
  std::vector<FieldSum> sums = r.get_vector<FieldSum>();
  if (sums.size() != sums_.size()) throw ConfigError(fmt::format("{}: inconsistent binned-field state", context));
  sums_ = std::move(sums);
  if (blocked_) blocks_.load(r, context);
}

void BinnedFieldsStage::observe(const StepContext& ctx) {
  const FieldsSpec& f = grid_.spec();
  const std::uint64_t step = ctx.step;
  if (step >= f.start && step % f.every == 0) grid_.sample(ctx.particles, ctx.comm, step);
  // The files so far, for long runs (the averages go on; the end of the run writes them again).
  if (out_.files() && f.write_every > 0 && step % f.write_every == 0 && step > f.start && grid_.samples() > 0)
    ctx.comm.on_root([&] { grid_.write(out_.dir); });
}

std::string BinnedFieldsStage::finish(const StepContext&) {
  if (grid_.samples() == 0) return fmt::format("{}: no samples (run longer than analysis.fields.start)\n", grid_.spec().name);
  return out_.files() ? grid_.write(out_.dir) : std::string();
}

}  // namespace mesodpd
