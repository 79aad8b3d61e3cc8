// Initial particle placement and velocities.
#include "engine/initial_state.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <array>
#include <limits>
#include <stdexcept>
#include <optional>
#include <vector>

#include "boundary/geometry.hpp"
#include "engine/blow_up_error.hpp"
#include "engine/installer.hpp"
#include "core/philox.hpp"
#include "io/lammps_data_reader.hpp"
#include "engine/pair_laws.hpp"
#include "engine/transported_scalars.hpp"
#include "mesodpd/config_error.hpp"

namespace mesodpd {

namespace {

// The particles every model places (Model::place), model after model in the list's order.
std::vector<PlacedParticle> model_particles(const SimulationSpec& spec) {
  std::vector<PlacedParticle> all;
  for (const Model& m : models())
    if (m.place)
      for (const PlacedParticle& q : m.place(spec)) all.push_back(q);
  return all;
}

// Four independent words per (seed, stream, id, sub-draw), from the same generator as the pair noise.
Philox4x32 particle_bits(std::uint64_t seed, RngStream stream, std::uint32_t id, std::uint32_t draw) {
  Philox4x32 ctr{{id, draw, 0u, static_cast<std::uint32_t>(stream) << 24}};
  return philox4x32_10(ctr, static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32));
}

// Returns whether the file had a Velocities section. With `topology`, also its bonds, angles and dihedrals.
bool load_data_file(const SimulationSpec& spec, Box& box, ParticleData& p, Topology* topology) {
  const LammpsData data = read_lammps_data(spec.data_file, tdpd_solutes(spec));
  const int ns = static_cast<int>(spec.species.size());
  // Atom styles edpd and tdpd carry the transported scalars of their pair style, and only of it.
  const std::string_view law = pair_law(spec.pair_style).style;
  if ((data.style == "edpd" || data.style == "tdpd") && law != data.style)
    throw ConfigError(fmt::format("init.lammps_data: the data file '{}' has atom style {} (its Atoms section), which "
                                  "needs pair.style = \"{}\" (this run's is \"{}\")",
                                  spec.data_file, data.style, data.style, law),
                      "init.lammps_data");
  // Every bond and angle type of the file needs its parameters in the config ([[bond_type]] k is type k).
  if (!data.bonds.empty() && data.n_bond_types > static_cast<int>(spec.bond_types.size()))
    throw ConfigError(fmt::format("bond_type: the data file {} has {} bond types but the config defines {} "
                                  "[[bond_type]] blocks (type k takes the k-th block's parameters)",
                                  spec.data_file, data.n_bond_types, spec.bond_types.size()));
  if (!data.angles.empty() && data.n_angle_types > static_cast<int>(spec.angle_types.size()))
    throw ConfigError(fmt::format("angle_type: the data file {} has {} angle types but the config defines {} "
                                  "[[angle_type]] blocks (type k takes the k-th block's parameters)",
                                  spec.data_file, data.n_angle_types, spec.angle_types.size()));
  if (!data.dihedrals.empty() && data.n_dihedral_types > static_cast<int>(spec.dihedral_types.size()))
    throw ConfigError(fmt::format("dihedral_type: the data file {} has {} dihedral types but the config defines {} "
                                  "[[dihedral_type]] blocks (type k takes the k-th block's parameters)",
                                  spec.data_file, data.n_dihedral_types, spec.dihedral_types.size()));
  if (topology != nullptr) {
    topology->bonds.clear();
    topology->angles.clear();
    topology->dihedrals.clear();
    for (const LammpsBonded& d : data.dihedrals)
      topology->dihedrals.push_back({d.atoms[0], d.atoms[1], d.atoms[2], d.atoms[3], d.type - 1});
    for (const LammpsBonded& b : data.bonds) topology->bonds.push_back({b.atoms[0], b.atoms[1], b.type - 1});
    for (const LammpsBonded& a : data.angles)
      topology->angles.push_back({a.atoms[0], a.atoms[1], a.atoms[2], a.type - 1});
  }
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
  if (data.atoms.empty())
    throw ConfigError(fmt::format("init.lammps_data: the data file '{}' has no atoms: the system would be empty",
                                  spec.data_file),
                      "init.lammps_data");
  box.len = {spec.box[0], spec.box[1], spec.box[2]};
  box.periodic = spec.periodic;
  const std::size_t n = data.atoms.size();
  p.resize(n);
  p.n_local = n;
  p.n_ghost = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& a = data.atoms[i];
    // Coordinates lie within the box bounds (lo <= x <= hi; unwrapped positions carry image flags):
    // a coordinate beyond them is refused, never wrapped in silence, since it is most often a file
    // written for another box or with other units.
    const double r_file[3] = {a.x, a.y, a.z};
    for (int d = 0; d < 3; ++d) {
      const auto k = static_cast<std::size_t>(d);
      if (!(r_file[d] >= data.lo[k] && r_file[d] <= data.hi[k]))
        throw ConfigError(fmt::format("init.lammps_data: LAMMPS data file '{}', line {}: atom {} has {} = {}, outside the "
                                      "box [{}, {}] of the file; give coordinates inside the box (unwrapped "
                                      "positions go in with image flags: ix iy iz after x y z)",
                                      spec.data_file, a.line, a.id, "xyz"[d], r_file[d], data.lo[k], data.hi[k]),
                          "init.lammps_data");
    }
    p.id[i] = a.id;
    p.species[i] = a.type - 1;
    p.x[i] = a.x - data.lo[0];
    p.y[i] = a.y - data.lo[1];
    p.z[i] = a.z - data.lo[2];
    p.ix[i] = a.ix;
    p.iy[i] = a.iy;
    p.iz[i] = a.iz;
    p.mol[i] = a.mol;
    double* r[3] = {&p.x[i], &p.y[i], &p.z[i]};
    std::int32_t* image[3] = {&p.ix[i], &p.iy[i], &p.iz[i]};
    for (int d = 0; d < 3; ++d) {
      if (box.periodic[static_cast<std::size_t>(d)]) {
        wrap_coordinate(*r[d], *image[d], box.length(d));
      } else if (!(*r[d] >= 0.0 && *r[d] < box.length(d))) {
        throw ConfigError(fmt::format("{}: atom {} lies outside the box along {}, which is bounded (system.periodic)",
                                      spec.data_file, a.id, "xyz"[d]));
      }
    }
    // The scalars of atom styles edpd and tdpd (checked here, where every rank holds every atom, so that
    // all refuse together): the heat capacity is the species' (C_v per particle, species[k].cv), and a
    // wall held at a temperature or a concentration starts at it.
    const SpeciesSpec& sp = spec.species[static_cast<std::size_t>(a.type - 1)];
    const auto refuse = [&](const std::string& key, const std::string& what) {
      throw ConfigError(fmt::format("species[{}].{}: {} (atom {} in '{}', line {})", a.type - 1, key, what, a.id,
                                    spec.data_file, a.line),
                        fmt::format("species[{}].{}", a.type - 1, key));
    };
    if (data.style == "edpd") {
      const double cv = sp.own.at("cv"), held = sp.own.at("temperature");
      if (std::abs(a.cv - cv) > 1e-12 * cv) refuse("cv", fmt::format("{} differs from the file's edpd_cv {}", cv, a.cv));
      if (sp.frozen && held > 0 && a.temp != held)
        refuse("temperature", fmt::format("the wall is held at {}, but the file starts it at {}", held, a.temp));
    }
    for (int k = 0; k < data.concentrations; ++k) {
      const std::string key = fmt::format("conc{}", k + 1);
      const double held = sp.own.at(key), c = a.conc[static_cast<std::size_t>(k)];
      if (sp.frozen && sp.own.at("solute_wall") > 0.5 && c != held)
        refuse(key, fmt::format("the solute wall is held at {}, but the file starts it at {}", held, c));
    }
    if (data.has_velocities) {
      p.vx[i] = data.velocities[i][0];
      p.vy[i] = data.velocities[i][1];
      p.vz[i] = data.velocities[i][2];
    }
  }
  // The file's temperatures or concentrations: the fields enabled here keep them (engine/install_edpd.cpp,
  // install_tdpd.cpp start the others from the species' keys).
  if (data.style == "edpd") {
    p.enable("temp");
    for (std::size_t i = 0; i < n; ++i) p.temp[i] = data.atoms[i].temp;
  }
  for (int k = 0; k < data.concentrations; ++k) {
    const std::string field = fmt::format("conc{}", k + 1);
    p.enable(field);
    std::vector<double>& c = *p.doubles(field);
    for (std::size_t i = 0; i < n; ++i) c[i] = data.atoms[i].conc[static_cast<std::size_t>(k)];
  }
  return data.has_velocities;
}

// One particle of a generated system, as the builder visits them in id order.
struct NewParticle {
  std::uint32_t id = 0;
  std::int32_t species = 0;
  std::int32_t mol = 0;
  std::int32_t body = 0;  // [[solid]] index + 1 of a frozen wall particle
  std::array<double, 3> r{};
  std::array<std::int32_t, 3> image{};
};

// Unwrapped bead positions of molecule number `mol` (1-based, all kinds together) of kind k: a random
// walk with steps of bond_length in uniformly random directions, each bead placed from the bead it is
// bonded to, the first uniformly in the box. A pure function of (seed, mol). On a bounded axis a step
// that would leave the box is drawn again, and so is a bead (or the midpoint of its bond) closer than
// kSolidClearance to a [[solid]] (up to 1000 times, then the molecule cannot be placed).
constexpr double kSolidClearance = 0.5;

bool clear_of_solids(const Geometry* geometry, const std::array<double, 3>& r) {
  return geometry == nullptr || geometry->sdf(Vec3{r[0], r[1], r[2]}) > kSolidClearance;
}

void random_walk(const SimulationSpec& spec, const Box& box, std::size_t k, std::uint64_t mol,
                 std::vector<std::array<double, 3>>& walk, const Geometry* geometry) {
  const MoleculeSpec& m = spec.molecules[k];
  walk.assign(m.beads.size(), {0, 0, 0});
  const auto key = static_cast<std::uint32_t>(mol);
  std::uint32_t draw = 0;
  for (int attempt = 0;; ++attempt) {
    if (attempt == 1000)
      throw ConfigError(fmt::format("molecule[{}]: molecule {} cannot be placed: no place found at least {} away from "
                                    "the [[solid]] walls",
                                    k, mol, kSolidClearance));
    const Philox4x32 first = particle_bits(spec.seed, RngStream::InitMolecule, key, draw++);
    for (int d = 0; d < 3; ++d)
      walk[0][static_cast<std::size_t>(d)] = (static_cast<double>(first.v[d]) / 4294967296.0) * box.length(d);
    if (clear_of_solids(geometry, walk[0])) break;
  }
  for (const auto& bond : m.bonds) {
    const auto from = static_cast<std::size_t>(bond[0]), to = static_cast<std::size_t>(bond[1]);
    for (int attempt = 0;; ++attempt) {
      if (attempt == 1000)
        throw ConfigError(fmt::format("molecule[{}]: molecule {} cannot be placed: its random walk keeps leaving the "
                                      "box across a bounded axis (system.periodic) or running into a [[solid]]; use a "
                                      "larger box or a shorter molecule[{}].bond_length", k, mol, k));
      const Philox4x32 b = particle_bits(spec.seed, RngStream::InitMolecule, key, draw++);
      const double cz = 2.0 * u01_open(b.v[0]) - 1.0;
      const double phi = 6.283185307179586 * u01_open(b.v[1]);
      const double sz = std::sqrt(std::max(0.0, 1.0 - cz * cz));
      const double dir[3] = {sz * std::cos(phi), sz * std::sin(phi), cz};
      bool inside = true;
      for (int d = 0; d < 3; ++d) {
        const auto du = static_cast<std::size_t>(d);
        walk[to][du] = walk[from][du] + m.bond_length * dir[d];
        if (!box.periodic[du] && !(walk[to][du] >= 0.0 && walk[to][du] < box.length(d))) inside = false;
      }
      if (inside && geometry != nullptr) {
        std::array<double, 3> mid{};
        for (std::size_t d = 0; d < 3; ++d) mid[d] = 0.5 * (walk[from][d] + walk[to][d]);
        inside = clear_of_solids(geometry, walk[to]) && clear_of_solids(geometry, mid);
      }
      if (inside) break;
    }
  }
}

// The bonds and angles of the generated molecules, by global id (molecule beads are ids 1 .. M).
Topology molecule_topology(const SimulationSpec& spec) {
  Topology t;
  std::uint32_t first = 1;
  for (const MoleculeSpec& m : spec.molecules) {
    for (std::uint64_t c = 0; c < m.count; ++c) {
      for (const auto& b : m.bonds)
        t.bonds.push_back({first + static_cast<std::uint32_t>(b[0]), first + static_cast<std::uint32_t>(b[1]),
                           m.bond_type_index});
      for (const auto& a : m.angles)
        t.angles.push_back({first + static_cast<std::uint32_t>(a[0]), first + static_cast<std::uint32_t>(a[1]),
                            first + static_cast<std::uint32_t>(a[2]), m.angle_type_index});
      first += static_cast<std::uint32_t>(m.beads.size());
    }
  }
  return t;
}

void zero_velocities(ParticleData& p) {
  std::fill(p.vx.begin(), p.vx.end(), 0.0);
  std::fill(p.vy.begin(), p.vy.end(), 0.0);
  std::fill(p.vz.begin(), p.vz.end(), 0.0);
}


// Unit-variance Maxwell-Boltzmann draw for particle `id` (a pure function of seed and id); returns
// the particle's mass.
double raw_maxwell(const SimulationSpec& spec, std::uint32_t id, std::int32_t species, double v[3]) {
  const double m = spec.species[static_cast<std::size_t>(species)].mass;
  const double sd = std::sqrt(spec.kT / m);
  const Philox4x32 a = particle_bits(spec.seed, RngStream::InitVelocity, id, 0);
  const Philox4x32 b = particle_bits(spec.seed, RngStream::InitVelocity, id, 1);
  v[0] = sd * gaussian_unit(a.v[0], a.v[1]);
  v[1] = sd * gaussian_unit(a.v[2], a.v[3]);
  v[2] = sd * gaussian_unit(b.v[0], b.v[1]);
  return m;
}

// Centre-of-mass velocity u and the factor that makes the kinetic temperature (3N - 3 degrees of
// freedom) exactly kT: v = (raw - u) * scale.
struct MaxwellShift {
  double u[3] = {0, 0, 0};
  double scale = 1.0;
};

// for_all(f) calls f(id, species) for every particle of the system, always in the same order.
template <class ForAll>
MaxwellShift maxwell_shift(const SimulationSpec& spec, std::uint64_t n, ForAll&& for_all) {
  MaxwellShift out;
  if (n == 0) return out;
  double mom[3] = {0, 0, 0}, mass_total = 0;
  for_all([&](std::uint32_t id, std::int32_t s) {
    double v[3];
    const double m = raw_maxwell(spec, id, s, v);
    for (int d = 0; d < 3; ++d) mom[d] += m * v[d];
    mass_total += m;
  });
  for (int d = 0; d < 3; ++d) out.u[d] = mom[d] / mass_total;
  double ke2 = 0;
  for_all([&](std::uint32_t id, std::int32_t s) {
    double v[3];
    const double m = raw_maxwell(spec, id, s, v);
    for (int d = 0; d < 3; ++d) v[d] -= out.u[d];
    ke2 += m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  });
  if (n >= 2 && ke2 > 0) out.scale = std::sqrt(spec.kT * (3.0 * static_cast<double>(n) - 3.0) / ke2);
  return out;
}

void apply_maxwell(const SimulationSpec& spec, const MaxwellShift& shift, ParticleData& p) {
  for (std::size_t k = 0; k < p.n_local; ++k) {
    if (p.body[k] > 0) {
      // A frozen wall particle moves with its solid.
      const auto& w = spec.solids[static_cast<std::size_t>(p.body[k] - 1)].velocity;
      p.vx[k] = w[0];
      p.vy[k] = w[1];
      p.vz[k] = w[2];
      continue;
    }
    double v[3];
    raw_maxwell(spec, p.id[k], p.species[k], v);
    p.vx[k] = (v[0] - shift.u[0]) * shift.scale;
    p.vy[k] = (v[1] - shift.u[1]) * shift.scale;
    p.vz[k] = (v[2] - shift.u[2]) * shift.scale;
  }
}

}  // namespace

std::uint64_t make_initial_state(const SimulationSpec& spec, Box& box, ParticleData& p, const KeepPredicate& keep,
                                 Topology* topology, const std::vector<double>* placed) {
  if (!spec.data_file.empty()) {
    for (const Model& m : models())
      if (m.place && !m.place(spec).empty())
        throw ConfigError(fmt::format("init.lammps_data: the {} model places its own particles, which a data file "
                                      "cannot be combined with; leave one out",
                                      m.name),
                          "init.lammps_data");
    const bool has_velocities = load_data_file(spec, box, p, topology);
    if (spec.velocities == VelocityInit::File && !has_velocities)
      throw ConfigError(fmt::format("init.velocities: \"file\" (the default with init.lammps_data) but {} has no "
                                    "Velocities section; set init.velocities = \"maxwell\" or \"zero\"",
                                    spec.data_file));
    if (spec.velocities == VelocityInit::Maxwell) assign_maxwell_velocities(spec, p);
    if (spec.velocities == VelocityInit::Zero) zero_velocities(p);
    if (topology != nullptr) check_initial_bonds(spec, box, p, *topology);
    return p.n_local;
  }
  box.len = {spec.box[0], spec.box[1], spec.box[2]};
  box.periodic = spec.periodic;
  std::uint64_t total = 0, lattice_total = 0;
  for (const auto& s : spec.species) {
    total += s.count;
    if (s.placement == Placement::Lattice) lattice_total += s.count;
  }
  // Particles the models place (membrane vertices), after the molecules.
  const std::vector<PlacedParticle> by_models = model_particles(spec);
  if (placed && (placed->size() != 3 * total || !spec.molecules.empty() || !by_models.empty()))
    throw std::logic_error("make_initial_state: equilibrated positions do not match the species counts");

  // Lattice species share one simple-cubic-like grid with at least lattice_total sites, spaced to fill
  // the box; sites are filled in order, species after species.
  std::array<std::uint64_t, 3> grid{1, 1, 1};
  if (lattice_total > 0) {
    const double spacing = std::cbrt(box.volume() / static_cast<double>(lattice_total));
    const double len[3] = {box.len.x, box.len.y, box.len.z};
    for (int d = 0; d < 3; ++d) grid[static_cast<std::size_t>(d)] = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::ceil(len[d] / spacing - 1e-9)));
    while (grid[0] * grid[1] * grid[2] < lattice_total) ++grid[0];
  }
  // Molecules first (ids 1 .. M, molecule after molecule), then the free particles of each species.
  // Solids: the fluid inside them is frozen near their surface and left out deeper in; molecules are
  // placed clear of them (random_walk).
  std::optional<Geometry> geometry;
  if (!spec.solids.empty()) geometry.emplace(spec.solids, box);
  // [[species]] region: a species' free particles outside its region are not created (their draws
  // are skipped, so the others keep their positions); inside a solid they still make the wall.
  std::vector<std::unique_ptr<Shape>> regions(spec.species.size());
  for (std::size_t s = 0; s < spec.species.size(); ++s)
    if (spec.species[s].region) regions[s] = make_shape(*spec.species[s].region, box, fmt::format("species[{}].region", s));
  // Visits every particle in id order; positions are functions of the draw number (the id when there
  // are no solids), of the lattice site, or of the molecule's random walk.
  auto for_each_particle = [&](auto&& f) {
    NewParticle q;
    std::uint64_t i = 0, site = 0;
    std::uint32_t next_id = 1;  // LAMMPS-style ids start at 1
    std::uint64_t mol = 0;
    std::vector<std::array<double, 3>> walk;
    for (std::size_t k = 0; k < spec.molecules.size(); ++k) {
      const MoleculeSpec& m = spec.molecules[k];
      for (std::uint64_t c = 0; c < m.count; ++c) {
        ++mol;
        random_walk(spec, box, k, mol, walk, geometry ? &*geometry : nullptr);
        for (std::size_t b = 0; b < m.beads.size(); ++b, ++i) {
          q.id = next_id++;
          q.species = m.beads[b];
          q.mol = static_cast<std::int32_t>(mol);
          q.r = walk[b];
          q.image = {0, 0, 0};
          for (int d = 0; d < 3; ++d)
            if (box.periodic[static_cast<std::size_t>(d)])
              wrap_coordinate(q.r[static_cast<std::size_t>(d)], q.image[static_cast<std::size_t>(d)], box.length(d));
          f(q);
        }
      }
    }
    for (const PlacedParticle& m : by_models) {
      q.id = next_id++;
      ++i;
      q.species = m.species;
      q.mol = m.mol;
      q.r = m.r;
      q.image = {0, 0, 0};
      for (int d = 0; d < 3; ++d)
        if (box.periodic[static_cast<std::size_t>(d)])
          wrap_coordinate(q.r[static_cast<std::size_t>(d)], q.image[static_cast<std::size_t>(d)], box.length(d));
      f(q);
    }
    q.mol = 0;
    q.image = {0, 0, 0};
    for (std::size_t s = 0; s < spec.species.size(); ++s) {
      for (std::uint64_t c = 0; c < spec.species[s].count; ++c, ++i) {
        const auto id = static_cast<std::uint32_t>(i + 1);  // the draw number
        double x, y, z;
        if (placed) {
          // Equilibrated before freezing: the pre-run's particle i + 1 (it had no solids to cut it).
          x = (*placed)[3 * i];
          y = (*placed)[3 * i + 1];
          z = (*placed)[3 * i + 2];
        } else if (spec.species[s].placement == Placement::Lattice) {
          const std::uint64_t gx = site % grid[0], gy = (site / grid[0]) % grid[1], gz = site / (grid[0] * grid[1]);
          ++site;
          x = (static_cast<double>(gx) + 0.5) * box.len.x / static_cast<double>(grid[0]);
          y = (static_cast<double>(gy) + 0.5) * box.len.y / static_cast<double>(grid[1]);
          z = (static_cast<double>(gz) + 0.5) * box.len.z / static_cast<double>(grid[2]);
        } else {
          const Philox4x32 b = particle_bits(spec.seed, RngStream::InitPosition, id, 0);
          x = (static_cast<double>(b.v[0]) / 4294967296.0) * box.len.x;
          y = (static_cast<double>(b.v[1]) / 4294967296.0) * box.len.y;
          z = (static_cast<double>(b.v[2]) / 4294967296.0) * box.len.z;
        }
        q.species = static_cast<std::int32_t>(s);
        q.body = 0;
        if (geometry && !spec.species[s].frozen) {
          int b = -1;
          const double d = geometry->sdf(Vec3{x, y, z}, b);
          if (d < 0) {
            if (d < -spec.walls.depth) continue;  // deep inside: no fluid ever comes near it
            q.species = spec.solids[static_cast<std::size_t>(b)].species_index;
            q.body = b + 1;
          }
        }
        if (q.body == 0 && regions[s] && !(regions[s]->sdf(Vec3{x, y, z}) < 0)) continue;
        q.id = next_id++;
        q.r = {x, y, z};
        f(q);
      }
    }
  };
  std::size_t kept = 0;
  std::uint64_t system_total = 0, mobile_total = 0;
  for_each_particle([&](const NewParticle& q) {
    ++system_total;
    mobile_total += q.body == 0 ? 1 : 0;
    kept += !keep || keep(q.r[0], q.r[1], q.r[2]) ? 1 : 0;
  });
  if (system_total > std::numeric_limits<std::uint32_t>::max())
    throw ConfigError(fmt::format("species: {} particles exceed the 32-bit id range", system_total));
  p.resize(kept);
  p.n_local = kept;
  p.n_ghost = 0;
  std::size_t i = 0;
  for_each_particle([&](const NewParticle& q) {
    if (keep && !keep(q.r[0], q.r[1], q.r[2])) return;
    p.id[i] = q.id;
    p.species[i] = q.species;
    p.body[i] = q.body;
    p.x[i] = q.r[0];
    p.y[i] = q.r[1];
    p.z[i] = q.r[2];
    p.ix[i] = q.image[0];
    p.iy[i] = q.image[1];
    p.iz[i] = q.image[2];
    p.mol[i] = q.mol;
    ++i;
  });
  if (topology != nullptr) *topology = molecule_topology(spec);
  if (spec.velocities == VelocityInit::Zero) {
    zero_velocities(p);
    return system_total;
  }
  // Maxwell-Boltzmann: the centre-of-mass velocity and the rescaling come from sums over the whole
  // system in id order, so a rank that keeps only its own particles gets the same bits as one rank.
  // Frozen particles take their solid's velocity instead and are left out of the sums.
  const MaxwellShift shift = maxwell_shift(spec, mobile_total, [&](auto&& f) {
    for_each_particle([&](const NewParticle& q) {
      if (q.body == 0) f(q.id, q.species);
    });
  });
  apply_maxwell(spec, shift, p);
  return system_total;
}

std::uint64_t check_initial_state(const SimulationSpec& spec) {
  const bool any_region = std::any_of(spec.species.begin(), spec.species.end(), [](const SpeciesSpec& s) { return s.region.has_value(); });
  if (spec.data_file.empty() && spec.solids.empty() && !any_region) {
    std::uint64_t n = 0;
    for (const auto& s : spec.species) n += s.count;
    for (const auto& m : spec.molecules) n += m.count * m.beads.size();
    return n + model_particles(spec).size();
  }
  Box box;
  ParticleData p;
  Topology topology;  // read, so that its bonds are checked as a run checks them
  return make_initial_state(spec, box, p, {}, spec.data_file.empty() ? nullptr : &topology);
}

void check_initial_bonds(const SimulationSpec& spec, const Box& box, const ParticleData& p, const Topology& topology) {
  if (topology.bonds.empty()) return;
  std::uint32_t max_id = 0;
  for (std::size_t i = 0; i < p.n_local; ++i) max_id = std::max(max_id, p.id[i]);
  constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> at(static_cast<std::size_t>(max_id) + 1, kNone);
  for (std::size_t i = 0; i < p.n_local; ++i) at[p.id[i]] = i;
  for (std::size_t k = 0; k < topology.bonds.size(); ++k) {
    const Bond& b = topology.bonds[k];
    if (b.type < 0 || static_cast<std::size_t>(b.type) >= spec.bond_types.size()) continue;  // refused elsewhere
    const BondTypeSpec& type = spec.bond_types[static_cast<std::size_t>(b.type)];
    if (type.style == BondStyleSpec::Harmonic) continue;
    if (b.a > max_id || b.b > max_id || at[b.a] == kNone || at[b.b] == kNone) continue;
    const std::size_t i = at[b.a], j = at[b.b];
    const double dx = minimum_image(p.x[i] - p.x[j], box.image_len(0), box.half_image_len(0));
    const double dy = minimum_image(p.y[i] - p.y[j], box.image_len(1), box.half_image_len(1));
    const double dz = minimum_image(p.z[i] - p.z[j], box.image_len(2), box.half_image_len(2));
    const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (r < type.rmax) continue;
    const std::string source = spec.data_file.empty() ? std::string("the initial state") : spec.data_file;
    throw BlowUpError(0, std::min(b.a, b.b),
                      fmt::format("{}: bond {} (particle ids {} and {}, type {}) is {} long at the start, at or past "
                                  "its maximum length bond_type[{}].rmax = {} ({}), where the force is infinite; "
                                  "shorten the bond in the data file or raise bond_type[{}].rmax",
                                  source, k + 1, b.a, b.b, b.type + 1, r, b.type, type.rmax,
                                  type.style == BondStyleSpec::Fene ? "FENE" : "worm-like chain", b.type));
  }
}

void assign_maxwell_velocities(const SimulationSpec& spec, ParticleData& p) {
  const MaxwellShift shift = maxwell_shift(spec, p.n_local, [&](auto&& f) {
    for (std::size_t i = 0; i < p.n_local; ++i) f(p.id[i], p.species[i]);
  });
  apply_maxwell(spec, shift, p);
}

std::uint32_t first_placed_id(const SimulationSpec& spec, const std::string& name) {
  std::uint64_t id = 1;
  for (const MoleculeSpec& m : spec.molecules) id += m.count * m.beads.size();
  for (const Model& m : models()) {
    if (m.name == name) return static_cast<std::uint32_t>(id);
    if (m.place) id += m.place(spec).size();
  }
  throw std::logic_error("first_placed_id: no model named " + name);
}

}  // namespace mesodpd
