// The configurations of the eDPD, tDPD and sources tests: a periodic box of the standard fluid, and a
// channel (a 6 x 6 x 12 box, periodic in x and y) between two plane walls of frozen particles (bottom
// z < 1, top z > 11) of species "bottom" and "top" with the fluid (species 0, "fluid") between them;
// and the straight-line check of a slab profile across the channel.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <omp.h>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/particle_data.hpp"
#include "engine/simulation.hpp"
#include "mesodpd/config.hpp"
#include "mesodpd/config_error.hpp"

namespace mesodpd::test {

// A periodic l^3 box of one species "A" at density 3 (a = 25, gamma = 4.5, kT = 1); `pair` adds the [pair]
// lines (the style and its keys), `species` the species' lines, `extra` tables at the end.
inline std::string periodic_fluid_config(const std::string& pair, const std::string& species, const std::string& extra,
                                         double l, double dt = 0.01, int seed = 31) {
  return fmt::format(R"(
[system]
box = [{3}, {3}, {3}]
kT = 1.0
seed = {5}

[[species]]
name = "A"
density = 3.0
{1}

[pair]
a = 25.0
gamma = 4.5
{0}

[integrator]
dt = {4}

[run]
steps = 100

[output]
thermo_every = 10
progress = false
{2}
)",
                     pair, species, extra, l, dt, seed);
}

// `fluid`, `bottom`, `top`: extra lines of the three [[species]] blocks; `pair`: the [pair] table's
// lines after a = 25, gamma = 4.5 (the style and its keys).
inline std::string plate_channel_config(const std::string& fluid, const std::string& bottom, const std::string& top,
                                        const std::string& pair) {
  return fmt::format(R"(
[system]
box = [6.0, 6.0, 12.0]
periodic = [true, true, false]
kT = 1.0
seed = 99

[[species]]
name = "fluid"
density = 3.0
{0}

[[species]]
name = "bottom"
frozen = true
{1}

[[species]]
name = "top"
frozen = true
{2}

[pair]
a = 25.0
gamma = 4.5
{3}

[[solid]]
name = "b"
species = "bottom"
shape = "plane"
point = [0, 0, 1]
normal = [0, 0, 1]

[[solid]]
name = "t"
species = "top"
shape = "plane"
point = [0, 0, 11]
normal = [0, 0, -1]

[walls]
reflection = "bounce_back"

[integrator]
dt = 0.01

[run]
steps = 100000

[output]
thermo_every = 100
progress = false
)",
                     fluid, bottom, top, pair);
}

// Mean of `value` over the fluid (species 0) in `bins` slabs of z in [1, 11].
inline std::vector<double> fluid_slabs(const ParticleData& p, const std::vector<double>& value, int bins) {
  std::vector<double> sum(static_cast<std::size_t>(bins), 0.0), count(static_cast<std::size_t>(bins), 0.0);
  for (std::size_t i = 0; i < p.n_local; ++i) {
    if (p.species[i] != 0) continue;
    const int b = static_cast<int>((p.z[i] - 1.0) / 10.0 * bins);
    if (b < 0 || b >= bins) continue;
    sum[static_cast<std::size_t>(b)] += value[i];
    count[static_cast<std::size_t>(b)] += 1;
  }
  for (int b = 0; b < bins; ++b) sum[static_cast<std::size_t>(b)] /= std::max(1.0, count[static_cast<std::size_t>(b)]);
  return sum;
}

// A straight line through the inner slabs (all but the first and last) of a profile over z in [1, 11]:
// its slope and the largest deviation of an inner slab from it. Prints the profile under `label`.
struct ProfileLine {
  double slope = 0, worst = 0;
};
inline ProfileLine inner_line(const std::vector<double>& mean, const char* label) {
  const int bins = static_cast<int>(mean.size());
  const double width = 10.0 / bins;
  auto z_of = [&](int b) { return 1.0 + (b + 0.5) * width; };
  double sx = 0, sy = 0, sxx = 0, sxy = 0, m = 0;
  for (int b = 1; b < bins - 1; ++b) {
    const double z = z_of(b), y = mean[static_cast<std::size_t>(b)];
    sx += z, sy += y, sxx += z * z, sxy += z * y, m += 1;
  }
  ProfileLine line;
  line.slope = (m * sxy - sx * sy) / (m * sxx - sx * sx);
  const double icpt = (sy - line.slope * sx) / m;
  for (int b = 1; b < bins - 1; ++b)
    line.worst = std::max(line.worst, std::abs(mean[static_cast<std::size_t>(b)] - (icpt + line.slope * z_of(b))));
  std::printf("%s: profile", label);
  for (double v : mean) std::printf(" %.4f", v);
  std::printf("\n  slope %.5f, largest deviation of an inner slab from the line %.4f\n", line.slope, line.worst);
  return line;
}

// The values of the particle fields `fields` ("temp", "conc1", ...) by id, one field after the other.
inline std::vector<double> fields_by_id(const ParticleData& p, const std::vector<std::string>& fields) {
  std::vector<double> out(fields.size() * p.n_local);
  for (std::size_t f = 0; f < fields.size(); ++f) {
    const std::vector<double>& v = *p.doubles(fields[f]);
    for (std::size_t i = 0; i < p.n_local; ++i) out[f * p.n_local + p.id[i] - 1] = v[i];
  }
  return out;
}

// `steps` steps of the config `text` on `threads` threads, from the start or continued from the
// checkpoint `restart`; writes a checkpoint to `save` at the end when given. Returns fields_by_id.
inline std::vector<double> run_fields(const std::string& text, int threads, int steps,
                                      const std::vector<std::string>& fields, const std::filesystem::path& restart = {},
                                      const std::filesystem::path& save = {}) {
  omp_set_num_threads(threads);
  RunOptions o;
  o.restart = restart;
  Simulation sim(parse_config(text, "r.toml"), o);
  for (int k = 0; k < steps; ++k) sim.step();
  if (!save.empty()) sim.write_checkpoint(save);
  omp_set_num_threads(1);
  return fields_by_id(sim.particles(), fields);
}

// The message of the ConfigError that building a simulation from `text` raises ("no error" without one;
// "other: ..." for another exception).
inline std::string config_error_of(const std::string& text) {
  try {
    Simulation sim(parse_config(text, "bad.toml"), RunOptions{});
  } catch (const ConfigError& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("other: ") + e.what();
  }
  return "no error";
}

}  // namespace mesodpd::test
