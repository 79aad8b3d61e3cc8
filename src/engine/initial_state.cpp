// Initial particle placement and velocities.
#include "engine/initial_state.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/philox.hpp"
#include "io/lammps_data_reader.hpp"

namespace mesodpd {

namespace {

// Four independent words per (seed, stream, id, sub-draw), from the same generator as the pair noise.
Philox4x32 particle_bits(std::uint64_t seed, RngStream stream, std::uint32_t id, std::uint32_t draw) {
  Philox4x32 ctr{{id, draw, 0u, static_cast<std::uint32_t>(stream) << 24}};
  return philox4x32_10(ctr, static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32));
}

// Returns whether the file had a Velocities section.
bool load_data_file(const SimulationSpec& spec, Box& box, ParticleData& p) {
  const LammpsData data = read_lammps_data(spec.data_file);
  const int ns = static_cast<int>(spec.species.size());
  if (data.n_types > ns)
    throw ConfigError(fmt::format("{}: the data file has {} atom types but the config defines {} species",
                                  spec.data_file, data.n_types, ns));
  for (int d = 0; d < 3; ++d) {
    const double len = data.hi[static_cast<std::size_t>(d)] - data.lo[static_cast<std::size_t>(d)];
    if (std::abs(len - spec.box[static_cast<std::size_t>(d)]) > 1e-9 * len)
      throw ConfigError(fmt::format("system.box: length {} along {} differs from the data file {} ({})",
                                    spec.box[static_cast<std::size_t>(d)], "xyz"[d], spec.data_file, len));
  }
  for (std::size_t t = 0; t < data.masses.size() && t < spec.species.size(); ++t)
    if (std::abs(data.masses[t] - spec.species[t].mass) > 1e-12 * spec.species[t].mass)
      throw ConfigError(fmt::format("species[{}].mass: {} differs from the mass {} of atom type {} in {}", t,
                                    spec.species[t].mass, data.masses[t], t + 1, spec.data_file));
  box.len = {spec.box[0], spec.box[1], spec.box[2]};
  const std::size_t n = data.atoms.size();
  p.resize(n);
  p.n_local = n;
  p.n_ghost = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& a = data.atoms[i];
    p.id[i] = a.id;
    p.species[i] = a.type - 1;
    p.x[i] = a.x - data.lo[0];
    p.y[i] = a.y - data.lo[1];
    p.z[i] = a.z - data.lo[2];
    p.ix[i] = a.ix;
    p.iy[i] = a.iy;
    p.iz[i] = a.iz;
    wrap_coordinate(p.x[i], p.ix[i], box.len.x);
    wrap_coordinate(p.y[i], p.iy[i], box.len.y);
    wrap_coordinate(p.z[i], p.iz[i], box.len.z);
    if (data.has_velocities) {
      p.vx[i] = data.velocities[i][0];
      p.vy[i] = data.velocities[i][1];
      p.vz[i] = data.velocities[i][2];
    }
  }
  return data.has_velocities;
}

void zero_velocities(ParticleData& p) {
  std::fill(p.vx.begin(), p.vx.end(), 0.0);
  std::fill(p.vy.begin(), p.vy.end(), 0.0);
  std::fill(p.vz.begin(), p.vz.end(), 0.0);
}

}  // namespace

void make_initial_state(const SimulationSpec& spec, Box& box, ParticleData& p) {
  if (!spec.data_file.empty()) {
    const bool has_velocities = load_data_file(spec, box, p);
    if (spec.velocities == VelocityInit::File && !has_velocities)
      throw ConfigError(fmt::format("init.velocities: \"file\" (the default with init.lammps_data) but {} has no "
                                    "Velocities section; set init.velocities = \"maxwell\" or \"zero\"",
                                    spec.data_file));
    if (spec.velocities == VelocityInit::Maxwell) assign_maxwell_velocities(spec, p);
    if (spec.velocities == VelocityInit::Zero) zero_velocities(p);
    return;
  }
  box.len = {spec.box[0], spec.box[1], spec.box[2]};
  std::uint64_t total = 0, lattice_total = 0;
  for (const auto& s : spec.species) {
    total += s.count;
    if (s.placement == Placement::Lattice) lattice_total += s.count;
  }
  if (total > std::numeric_limits<std::uint32_t>::max())
    throw ConfigError(fmt::format("species: {} particles exceed the 32-bit id range", total));
  p.resize(total);
  p.n_local = total;
  p.n_ghost = 0;

  // Lattice species share one simple-cubic-like grid with at least lattice_total sites, spaced to fill
  // the box; sites are filled in order, species after species.
  std::array<std::uint64_t, 3> grid{1, 1, 1};
  if (lattice_total > 0) {
    const double spacing = std::cbrt(box.volume() / static_cast<double>(lattice_total));
    const double len[3] = {box.len.x, box.len.y, box.len.z};
    for (int d = 0; d < 3; ++d) grid[static_cast<std::size_t>(d)] = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::ceil(len[d] / spacing - 1e-9)));
    while (grid[0] * grid[1] * grid[2] < lattice_total) ++grid[0];
  }
  std::uint64_t i = 0, site = 0;
  for (std::size_t s = 0; s < spec.species.size(); ++s) {
    for (std::uint64_t c = 0; c < spec.species[s].count; ++c, ++i) {
      p.id[i] = static_cast<std::uint32_t>(i + 1);  // LAMMPS-style ids start at 1
      p.species[i] = static_cast<std::int32_t>(s);
      if (spec.species[s].placement == Placement::Lattice) {
        const std::uint64_t gx = site % grid[0], gy = (site / grid[0]) % grid[1], gz = site / (grid[0] * grid[1]);
        ++site;
        p.x[i] = (static_cast<double>(gx) + 0.5) * box.len.x / static_cast<double>(grid[0]);
        p.y[i] = (static_cast<double>(gy) + 0.5) * box.len.y / static_cast<double>(grid[1]);
        p.z[i] = (static_cast<double>(gz) + 0.5) * box.len.z / static_cast<double>(grid[2]);
      } else {
        const Philox4x32 b = particle_bits(spec.seed, RngStream::InitPosition, p.id[i], 0);
        p.x[i] = (static_cast<double>(b.v[0]) / 4294967296.0) * box.len.x;
        p.y[i] = (static_cast<double>(b.v[1]) / 4294967296.0) * box.len.y;
        p.z[i] = (static_cast<double>(b.v[2]) / 4294967296.0) * box.len.z;
      }
    }
  }
  if (spec.velocities == VelocityInit::Zero)
    zero_velocities(p);
  else
    assign_maxwell_velocities(spec, p);
}

void assign_maxwell_velocities(const SimulationSpec& spec, ParticleData& p) {
  const std::size_t n = p.n_local;
  if (n == 0) return;
  double mom[3] = {0, 0, 0}, mass_total = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double m = spec.species[static_cast<std::size_t>(p.species[i])].mass;
    const double sd = std::sqrt(spec.kT / m);
    const Philox4x32 a = particle_bits(spec.seed, RngStream::InitVelocity, p.id[i], 0);
    const Philox4x32 b = particle_bits(spec.seed, RngStream::InitVelocity, p.id[i], 1);
    p.vx[i] = sd * gaussian_unit(a.v[0], a.v[1]);
    p.vy[i] = sd * gaussian_unit(a.v[2], a.v[3]);
    p.vz[i] = sd * gaussian_unit(b.v[0], b.v[1]);
    mom[0] += m * p.vx[i];
    mom[1] += m * p.vy[i];
    mom[2] += m * p.vz[i];
    mass_total += m;
  }
  double ke2 = 0;
  for (std::size_t i = 0; i < n; ++i) {
    p.vx[i] -= mom[0] / mass_total;
    p.vy[i] -= mom[1] / mass_total;
    p.vz[i] -= mom[2] / mass_total;
    const double m = spec.species[static_cast<std::size_t>(p.species[i])].mass;
    ke2 += m * (p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i]);
  }
  if (n < 2 || ke2 <= 0) return;
  const double scale = std::sqrt(spec.kT * (3.0 * static_cast<double>(n) - 3.0) / ke2);
  for (std::size_t i = 0; i < n; ++i) {
    p.vx[i] *= scale;
    p.vy[i] *= scale;
    p.vz[i] *= scale;
  }
}

}  // namespace mesodpd
