// [[membrane]]: closed elastic membranes (red cells, vesicles) whose vertices are particles of the run
// (membrane/membrane_forces.hpp has the forces). Each block is one cell at `center`, or many cells of the
// same mesh and parameters (a `cells_file`, or a lattice at a `haematocrit`): each cell's mesh is generated
// or read and placed (Model::place gives its vertices ids after the molecules, cell after cell), and a
// Forces stage adds the membrane forces to its vertices every step. The stage gathers the vertices of every cell in id
// order (under MPI every rank receives all of them), evaluates each cell whole, in mesh order, and adds
// the forces to the vertices it owns: the result does not depend on thread or rank count.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <sstream>
#include <memory>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <omp.h>

#include "core/adjacent_bins.hpp"
#include "engine/blow_up_error.hpp"
#include "engine/initial_state.hpp"
#include "engine/installer.hpp"
#include "engine/simulation.hpp"
#include "io/gsd_writer.hpp"
#include "io/output_file.hpp"
#include "parallel/comm.hpp"
#include "membrane/bounce.hpp"
#include "membrane/membrane_forces.hpp"
#include "membrane/mesh.hpp"
#include "mesodpd/config_error.hpp"
#include "mesodpd/key_table.hpp"
#include "mesodpd/model_section.hpp"

namespace mesodpd {

enum class MeshKind { RedCell, Sphere, File };

struct MembraneSpec {
  std::string species;
  MeshKind mesh = MeshKind::RedCell;
  std::string file;
  std::uint64_t vertices = 500;
  double diameter = 0;
  std::optional<std::array<double, 3>> center;
  std::string cells_file;
  std::optional<double> haematocrit;
  int axis = 2;
  double shear_modulus = 0, persistence = 0;
  double x0 = 1.0 / 2.2, m = 2.0;
  bool stress_free = true;
  membrane::Bending bending = membrane::Bending::None;
  double kb = 0, theta0_deg = 0, kappa = 0;
  double ka = 0, kd = 0, kv = 0, area0 = 0, volume0 = 0;
  double gamma_t = 0, gamma_c = 0, viscosity = 0;
  double tweezers_force = 0, tweezers_fraction = 0.02;
  int tweezers_axis = 0;
  std::uint64_t tweezers_ramp = 0;
  std::uint64_t output_every = 0;
  bool bounce = true;
  std::string inner_species;
  double repulsion = 0, repulsion_range = 0.5;
};

namespace {

using membrane::norm;

const keys::KeyTable<MembraneSpec>& membrane_keys() {
  using T = MembraneSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("membrane");
    t.string("species", &T::species, "The species of the cell's vertices: a mobile species with no `density` or `count` of its own (its particles are the vertices). Its pair parameters with the fluid set how the membrane and the solvent interact.")
        .required("(a [[species]] name)");
    t.choice("mesh", &T::mesh, {{"red_cell", MeshKind::RedCell}, {"sphere", MeshKind::Sphere}, {"file", MeshKind::File}}, "`red_cell`: the Evans-Fung biconcave shape (Evans & Fung 1972) of `diameter`, its axis along `axis`; `sphere`: a geodesic sphere of `diameter`; `file`: the closed triangle mesh of an OFF file (`file`), used as it is, moved to `center`. The generated meshes have 10 n^2 + 2 vertices, n chosen to come nearest `vertices` (500 -> 492, 1000 -> 1002, 3000 -> 2892). The mesh is also the stress-free reference shape (`stress_free`).")
        .default_text("\"red_cell\"");
    t.string("file", &T::file, "The OFF file of `mesh = \"file\"` (triangles only, closed, consistently oriented; inward-facing files are turned round). A relative path is relative to the config file's directory.");
    t.integer("vertices", &T::vertices, {4, 200000}, "Vertex count wanted for a generated mesh.").default_text("500");
    t.number("diameter", &T::diameter, keys::kNonNegative, "Diameter of a generated mesh (7.82 um for a human red cell).");
    t.vec3("center", &T::center, keys::kFinite, "Where the cell's centroid starts (the mesh's centre of its vertices). Give this, `cells_file` or `haematocrit`.")
        .default_text("(one of center, cells_file, haematocrit)");
    t.string("cells_file", &T::cells_file, "Many cells of this block's mesh and parameters, one per line of a text file: `x y z` (the centroid) or `x y z ax ay az` (and the direction onto which the mesh's z axis, the red cell's symmetry axis, is turned); `#` starts a comment. Each cell is a molecule of its own with its own row in cells.csv. A relative path is relative to the config file's directory. Cells whose meshes overlap (a vertex of one inside another, at the nearest periodic image) are refused naming both lines.");
    t.number("haematocrit", &T::haematocrit, {0.0, 0.6, false, true}, "Fill the box with cells of this block at this volume fraction (the cells' enclosed volume over the box volume, walls included), all turned to `axis`, on the sites of a lattice whose spacing is the cell's extent plus one cutoff along each axis, spread evenly over the sites; refused naming the key when the lattice has too few sites. The count is the nearest integer to fraction x box volume / cell volume (at least 1). The lattice ignores [[solid]] walls: in a channel or tube give a `cells_file`.");
    t.choice("axis", &T::axis, {{"x", 0}, {"y", 1}, {"z", 2}}, "The red cell's symmetry axis.").default_text("\"z\"");
    t.number("shear_modulus", &T::shear_modulus, keys::kNonNegative, "The linear shear modulus mu0 of the WLC-POW network; sets `persistence` through the analytic modulus at the mesh's mean edge length (Fedosov et al., Biophys. J. 98, 2215 (2010); docs/physics.md). Give this or `persistence`.");
    t.number("persistence", &T::persistence, keys::kNonNegative, "The WLC persistence length p (energy scale `system.kT`). Give this or `shear_modulus`; neither: no in-plane elasticity.");
    t.number("x0", &T::x0, {0.0, 1.0, false, false}, "l0 / l_max: each edge breaks at l0 / x0 (the run stops, naming the cell and the vertex ids).").default_text("1/2.2");
    t.number("m", &T::m, {0.0, 10.0, false, true}, "Exponent of the power-law repulsion k_p / l^m.").default_text("2");
    t.boolean("stress_free", &T::stress_free, "Per-edge rest lengths and per-triangle rest areas from the initial mesh (true), or the mean edge length and the mean triangle area for all (false).");
    t.choice("bending", &T::bending, {{"none", membrane::Bending::None}, {"kantor-nelson", membrane::Bending::KantorNelson}, {"juelicher", membrane::Bending::Juelicher}}, "`kantor-nelson`: U = kb [1 - cos(theta - theta0)] per edge; `juelicher`: U = 2 kappa sum_i M_i^2 / A_i (8 pi kappa for a sphere).")
        .default_text("\"none\"");
    t.number("kb", &T::kb, keys::kNonNegative, "Kantor-Nelson bending constant (2 kappa / sqrt(3) for a rigidity kappa).");
    t.number("theta0", &T::theta0_deg, {-180.0, 180.0, true, true}, "Kantor-Nelson spontaneous angle between neighbouring triangles' normals.").unit("degrees");
    t.number("kappa", &T::kappa, keys::kNonNegative, "Juelicher bending rigidity.");
    t.number("ka", &T::ka, keys::kNonNegative, "Global area constraint k_a (A - A0)^2 / (2 A0).");
    t.number("kd", &T::kd, keys::kNonNegative, "Local area constraint: k_d (A_t - A0_t)^2 / (2 A0_t) per triangle.");
    t.number("kv", &T::kv, keys::kNonNegative, "Volume constraint k_v (V - V0)^2 / (2 V0).");
    t.number("area0", &T::area0, keys::kNonNegative, "Target area A0.").default_text("the initial mesh's");
    t.number("volume0", &T::volume0, keys::kNonNegative, "Target volume V0 (below the mesh's to deflate a vesicle).").default_text("the initial mesh's");
    t.number("gamma_t", &T::gamma_t, keys::kNonNegative, "Membrane viscosity: the edge friction gamma_T on the relative velocity of an edge's ends, with its random force (fluctuation-dissipation at `system.kT`; docs/physics.md). Give gamma_t and gamma_c, or `viscosity`.");
    t.number("gamma_c", &T::gamma_c, keys::kNonNegative, "Membrane viscosity: the edge friction gamma_C along the edge. The random force needs 3 gamma_c >= gamma_t.");
    t.number("viscosity", &T::viscosity, keys::kNonNegative, "The membrane shear viscosity eta_m = sqrt(3) (gamma_T + gamma_C / 4) (Fedosov et al. 2010), with gamma_C = gamma_T / 3 as they chose: gamma_T = 12 eta_m / (13 sqrt(3)).");
    t.number("repulsion", &T::repulsion, keys::kNonNegative, "Cells that touch: the amplitude a of a soft repulsion a (1 - r / r_r) between vertices of two different cells closer than `repulsion_range` r_r (within a cell the membrane forces act; without it nothing but the fluid between them keeps two cells apart, and a squeezed cell can pass through another). Between blocks the amplitude is sqrt(a_1 a_2) and the range the larger one; 0 (the default) in either block: no repulsion between them. In the pressure tensor and in membrane_energy (energy a r_r / 2 (1 - r / r_r)^2 per pair).");
    t.number("repulsion_range", &T::repulsion_range, keys::kPositive, "The range r_r of `repulsion` (typically the mean edge length of the mesh).").default_text("0.5");
    t.number("tweezers_force", &T::tweezers_force, keys::kNonNegative, "Optical-tweezers stretching (Mills et al. 2004): a total force +F along `tweezers_axis` spread over the `tweezers_fraction` of the vertices farthest along it in the initial mesh, -F over the same fraction at the other end.");
    t.number("tweezers_fraction", &T::tweezers_fraction, {0.0, 0.5, false, true}, "The gripped fraction of the vertices at each end.").default_text("0.02");
    t.choice("tweezers_axis", &T::tweezers_axis, {{"x", 0}, {"y", 1}, {"z", 2}}, "The stretching direction.").default_text("\"x\"");
    t.integer("tweezers_ramp", &T::tweezers_ramp, {0, 1000000000}, "The tweezers force grows linearly from 0 at step 0 to `tweezers_force` at this step (a sudden pull of the few gripped vertices would tear their edges).").default_text("0 (at once)");
    t.boolean("bounce", &T::bounce, "Bounce the other mobile particles (solvent, molecules) back from the cell's moving triangles, so the fluids inside and outside stay apart: a particle whose step would take it through a triangle is sent back from the point of contact with its velocity relative to the triangle reversed, and the momentum it gains is taken from the triangle's vertices (docs/physics.md). Needs the Groot-Warren integrator.").default_text("true");
    t.string("inner_species", &T::inner_species, "In a new run, the free mobile particles that start inside the cell (not molecule beads) take this species: an inner fluid that may differ from the outer one (its pair parameters set its viscosity). A [[species]] with no particles of its own.").default_text("(none: the inner fluid keeps its species)");
    t.integer("output_every", &T::output_every, {0, 1000000000}, "Write cells.csv (step, cell, centroid, axial and transverse diameters along/across `tweezers_axis`, area, volume, asphericity, and `wrong_side`: the particles inside the cell now that were outside it at the start of the run, or the other way round, whose target is zero) every this many steps, and cells.gsd (every cell's vertices, the edges as bonds, so OVITO or VMD draw the meshes; tools/render_cells.py draws a picture) at the same steps; 0: never.").default_text("0");
    return t;
  }();
  return table;
}

// The index of the [[species]] named by membrane[k].<role>, a fluid with no particles of its own, or one
// error naming the key.
int named_species(const std::string& name, const SimulationSpec& spec, const std::string& key, const char* own) {
  for (std::size_t s = 0; s < spec.species.size(); ++s)
    if (spec.species[s].name == name) {
      if (spec.species[s].frozen) keys::fail(key, "\"" + name + "\"", "a frozen species is not integrated");
      if (spec.species[s].count > 0)
        keys::fail(key, "\"" + name + "\"", std::string("the species has particles of its own (density or count); ") + own);
      return static_cast<int>(s);
    }
  keys::fail(key, "\"" + name + "\"", "no [[species]] of that name");
  return -1;
}

int species_of(const MembraneSpec& c, const SimulationSpec& spec, const std::string& key) {
  return named_species(c.species, spec, key + ".species", "give the vertices a species of their own");
}

int inner_species_of(const MembraneSpec& c, const SimulationSpec& spec, const std::string& key) {
  if (c.inner_species == c.species)
    keys::fail(key + ".inner_species", "\"" + c.inner_species + "\"", "that is the species of the cell's vertices");
  return named_species(c.inner_species, spec, key + ".inner_species",
                       "the inner fluid's particles are those found inside the cell");
}

// A path of the config, relative to the config file's directory.
std::string config_path(const SimulationSpec& spec, const std::string& file) {
  std::filesystem::path base = std::filesystem::path(spec.source).parent_path();
  if (base.empty()) base = std::filesystem::current_path();
  return std::filesystem::absolute(base / std::filesystem::path(file)).lexically_normal().string();
}

// Where one cell of a block starts: its centroid, and optionally the direction its mesh's z axis is
// turned to (cells_file); `line` names the cells_file line (0: not from a file).
struct Placement {
  Vec3 center;
  std::optional<Vec3> axis;
  std::size_t line = 0;
};

// The mesh turned so that its z axis points along the unit vector a (the rotation about z x a).
void turn_z_to(membrane::Mesh& m, Vec3 a) {
  const Vec3 z{0, 0, 1};
  const Vec3 k = cross(z, a);
  const double s = norm(k), c = a.z;
  if (s < 1e-12) {
    if (c < 0)
      for (Vec3& p : m.vertices) p = {p.x, -p.y, -p.z};  // half a turn about x
    return;
  }
  const Vec3 u = (1.0 / s) * k;
  for (Vec3& p : m.vertices)  // Rodrigues
    p = c * p + s * cross(u, p) + ((1.0 - c) * dot(u, p)) * u;
}

// The cell's mesh, placed: generated or read, the red cell turned to its axis (or to the placement's),
// moved to the placement's centre.
membrane::Mesh cell_mesh(const MembraneSpec& c, const SimulationSpec& spec, const std::string& key, const Placement& at) {
  membrane::Mesh m;
  try {
    if (c.mesh == MeshKind::File) {
      m = membrane::read_off(config_path(spec, c.file));
    } else {
      const int n = membrane::frequency_for(c.vertices);
      m = c.mesh == MeshKind::Sphere ? membrane::geodesic_sphere(n, c.diameter / 2) : membrane::red_cell(n, c.diameter);
      if (c.axis != 2 && !at.axis)
        for (Vec3& p : m.vertices) p = c.axis == 0 ? Vec3{p.z, p.x, p.y} : Vec3{p.y, p.z, p.x};
    }
  } catch (const membrane::MeshError& e) {
    throw ConfigError(fmt::format("{}: {}", key, e.what()), key + (c.mesh == MeshKind::File ? ".file" : ".mesh"));
  }
  Vec3 mean;
  for (const Vec3& p : m.vertices) mean += p;
  mean = (1.0 / static_cast<double>(m.vertices.size())) * mean;
  for (Vec3& p : m.vertices) p = p - mean;
  if (at.axis) turn_z_to(m, *at.axis);
  for (Vec3& p : m.vertices) p = p + at.center;
  return m;
}

// The bounding box of a set of points: lowest and highest coordinate along each axis.
std::pair<Vec3, Vec3> bounds(const std::vector<Vec3>& x) {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const Vec3& p : x) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  return {lo, hi};
}

// The cells_file's lines: "x y z" or "x y z ax ay az", '#' comments; one error naming file and line.
std::vector<Placement> read_cells_file(const std::string& path, const std::string& key) {
  std::ifstream in(path);
  if (!in) keys::fail(key + ".cells_file", "\"" + path + "\"", "cannot read the file");
  std::vector<Placement> out;
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream words(line);
    std::vector<double> v;
    std::string w;
    while (words >> w) {
      char* end = nullptr;
      const double x = std::strtod(w.c_str(), &end);
      if (end == w.c_str() || *end != '\0' || !std::isfinite(x))
        throw ConfigError(fmt::format("{}:{}: \"{}\" is not a finite number ({}.cells_file)", path, n, w, key), key + ".cells_file");
      v.push_back(x);
    }
    if (v.empty()) continue;
    if (v.size() != 3 && v.size() != 6)
      throw ConfigError(fmt::format("{}:{}: {} numbers; a cell is \"x y z\" or \"x y z ax ay az\" ({}.cells_file)", path, n,
                                    v.size(), key),
                        key + ".cells_file");
    Placement p{{v[0], v[1], v[2]}, std::nullopt, n};
    if (v.size() == 6) {
      const Vec3 a{v[3], v[4], v[5]};
      if (!(norm(a) > 0))
        throw ConfigError(fmt::format("{}:{}: the axis ({}, {}, {}) is the zero vector ({}.cells_file)", path, n, a.x, a.y, a.z, key),
                          key + ".cells_file");
      p.axis = (1.0 / norm(a)) * a;
    }
    out.push_back(p);
  }
  if (out.empty()) keys::fail(key + ".cells_file", "\"" + path + "\"", "the file lists no cell");
  return out;
}

// The lattice of a haematocrit: sites spaced by the cell's extent plus one cutoff, the cells spread
// evenly over them (site floor(k S / n) for cell k of n, S sites, in x-fastest order).
std::vector<Placement> lattice_cells(const MembraneSpec& c, const SimulationSpec& spec, const std::string& key) {
  const membrane::Mesh m = cell_mesh(c, spec, key, Placement{});
  const double volume = membrane::mesh_volume(m, m.vertices);
  const double box_volume = spec.box[0] * spec.box[1] * spec.box[2];
  const std::size_t n = std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(*c.haematocrit * box_volume / volume)));
  const auto [lo, hi] = bounds(m.vertices);
  const Vec3 e = hi - lo;
  const double site[3] = {e.x + 1.0, e.y + 1.0, e.z + 1.0};
  std::size_t sites[3];
  for (int d = 0; d < 3; ++d) sites[d] = static_cast<std::size_t>(std::floor(spec.box[static_cast<std::size_t>(d)] / site[d]));
  const std::size_t total = sites[0] * sites[1] * sites[2];
  if (total < n)
    keys::fail(key + ".haematocrit", fmt::format("{}", *c.haematocrit),
               fmt::format("{} cells of volume {:.4g} are needed, but a lattice of sites {:.4g} x {:.4g} x {:.4g} (the cell's extent "
                           "plus one cutoff) holds {} x {} x {} = {} in this box (at most {:.3g})",
                           n, volume, site[0], site[1], site[2], sites[0], sites[1], sites[2], total,
                           static_cast<double>(total) * volume / box_volume));
  std::vector<Placement> out;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t s = k * total / n;
    const std::size_t i = s % sites[0], j = (s / sites[0]) % sites[1], l = s / (sites[0] * sites[1]);
    out.push_back({{(static_cast<double>(i) + 0.5) * spec.box[0] / static_cast<double>(sites[0]),
                    (static_cast<double>(j) + 0.5) * spec.box[1] / static_cast<double>(sites[1]),
                    (static_cast<double>(l) + 0.5) * spec.box[2] / static_cast<double>(sites[2])},
                   std::nullopt, 0});
  }
  return out;
}

// Every cell of block c: one at `center`, the lines of `cells_file`, or the lattice of `haematocrit`.
std::vector<Placement> placements(const MembraneSpec& c, const SimulationSpec& spec, const std::string& key) {
  const bool has_center = c.center.has_value();
  const int given = (has_center ? 1 : 0) + (c.cells_file.empty() ? 0 : 1) + (c.haematocrit ? 1 : 0);
  if (given == 0) keys::fail(key + ".center", "(missing)", "give the cell's centre, a cells_file or a haematocrit");
  if (given > 1)
    keys::fail(key + (c.haematocrit ? ".haematocrit" : ".cells_file"),
               c.haematocrit ? fmt::format("{}", *c.haematocrit) : "\"" + c.cells_file + "\"",
               "give one of center, cells_file and haematocrit");
  if (has_center) return {Placement{{(*c.center)[0], (*c.center)[1], (*c.center)[2]}, std::nullopt, 0}};
  if (!c.cells_file.empty()) return read_cells_file(config_path(spec, c.cells_file), key);
  return lattice_cells(c, spec, key);
}

// Every cell of every block, in order (the order of their vertex ids and of cells.csv's `cell`).
struct PlacedCell {
  std::size_t block;
  Placement at;
};
std::vector<PlacedCell> all_cells(const std::vector<MembraneSpec>& list, const SimulationSpec& spec) {
  std::vector<PlacedCell> out;
  for (std::size_t k = 0; k < list.size(); ++k)
    for (const Placement& p : placements(list[k], spec, fmt::format("membrane[{}]", k))) out.push_back({k, p});
  return out;
}

membrane::Parameters cell_parameters(const MembraneSpec& c, const SimulationSpec& spec, double mean_length) {
  membrane::Parameters p;
  p.kT = spec.kT;
  // The random force's variates: those of the pair noise (run.noise).
  p.noise = spec.noise == NoiseDistribution::Gaussian ? NoiseKind::Gaussian : NoiseKind::Uniform;
  p.x0 = c.x0;
  p.m = c.m;
  p.stress_free = c.stress_free;
  p.persistence = c.persistence > 0 ? c.persistence
                  : c.shear_modulus > 0 ? membrane::persistence_for(c.shear_modulus, mean_length, c.x0, spec.kT, c.m)
                                        : 0.0;
  p.bending = c.bending;
  p.kb = c.kb;
  p.theta0 = c.theta0_deg * std::numbers::pi / 180.0;
  p.kappa = c.kappa;
  p.ka = c.ka;
  p.kd = c.kd;
  p.kv = c.kv;
  p.area0 = c.area0;
  p.volume0 = c.volume0;
  if (c.viscosity > 0) {
    p.gamma_t = c.viscosity / membrane::membrane_viscosity(1.0, 1.0 / 3.0);  // eta_m is linear in gamma_T
    p.gamma_c = p.gamma_t / 3.0;
  } else {
    p.gamma_t = c.gamma_t;
    p.gamma_c = c.gamma_c;
  }
  return p;
}

// "membrane[k]" and, for a cell of a cells_file or a haematocrit, which one.
std::string cell_name(const PlacedCell& pc, std::size_t index_in_block, const MembraneSpec& c) {
  if (pc.at.line > 0) return fmt::format("membrane[{}] (line {} of {})", pc.block, pc.at.line, c.cells_file);
  if (c.haematocrit) return fmt::format("membrane[{}] (lattice cell {})", pc.block, index_in_block);
  return fmt::format("membrane[{}]", pc.block);
}

// No cell larger than the box less a cutoff (it would meet its own images), and no two cells overlapping:
// for every pair whose bounding boxes meet at the nearest periodic image, no vertex of one inside the
// other. One error naming the cells.
void check_overlaps(const std::vector<MembraneSpec>& list, const SimulationSpec& spec) {
  const std::vector<PlacedCell> cells = all_cells(list, spec);
  struct Built {
    membrane::Mesh mesh;
    Vec3 centre, lo, hi;  // lo, hi: the bounding box relative to the centre
    std::string name;
  };
  std::vector<Built> built;
  std::vector<std::size_t> in_block(list.size(), 0);
  for (const PlacedCell& pc : cells) {
    const MembraneSpec& c = list[pc.block];
    const std::string key = fmt::format("membrane[{}]", pc.block);
    Built b{cell_mesh(c, spec, key, pc.at), pc.at.center, {}, {}, cell_name(pc, in_block[pc.block]++, c)};
    const auto [lo, hi] = bounds(b.mesh.vertices);
    const Vec3 e = hi - lo;
    for (int d = 0; d < 3; ++d) {
      const double span = d == 0 ? e.x : d == 1 ? e.y : e.z;
      if (span + 1.0 > spec.box[static_cast<std::size_t>(d)]) {
        const std::string where = pc.at.line > 0 ? ".cells_file" : c.mesh == MeshKind::File ? ".file" : ".diameter";
        throw ConfigError(fmt::format("{}{}: {}: the cell spans {} along {}, more than the box ({}) less one cutoff", key, where,
                                      b.name, span, "xyz"[d], spec.box[static_cast<std::size_t>(d)]),
                          key + where);
      }
    }
    b.lo = lo - b.centre;
    b.hi = hi - b.centre;
    built.push_back(std::move(b));
  }
  auto nearest = [&](double diff, int d) {
    const double l = spec.box[static_cast<std::size_t>(d)];
    return spec.periodic[static_cast<std::size_t>(d)] ? diff - l * std::round(diff / l) : diff;
  };
  for (std::size_t a = 0; a < built.size(); ++a)
    for (std::size_t b = a + 1; b < built.size(); ++b) {
      const Vec3 raw = built[b].centre - built[a].centre;
      const Vec3 d{nearest(raw.x, 0), nearest(raw.y, 1), nearest(raw.z, 2)};
      const Vec3 blo = built[b].lo + d, bhi = built[b].hi + d;
      if (blo.x > built[a].hi.x || bhi.x < built[a].lo.x || blo.y > built[a].hi.y || bhi.y < built[a].lo.y ||
          blo.z > built[a].hi.z || bhi.z < built[a].lo.z)
        continue;
      const Vec3 shift = d - raw;  // brings b next to a
      std::vector<Vec3> xb = built[b].mesh.vertices;
      for (Vec3& p : xb) p = p + shift;
      bool inside = false;
      for (const Vec3& q : xb) inside = inside || membrane::winding_number(built[a].mesh, built[a].mesh.vertices, q) > 0.5;
      for (const Vec3& q : built[a].mesh.vertices) inside = inside || membrane::winding_number(built[b].mesh, xb, q) > 0.5;
      if (inside) {
        const std::string key = fmt::format("membrane[{}]", cells[b].block);
        const std::string where = cells[b].at.line > 0 ? ".cells_file" : list[cells[b].block].haematocrit ? ".haematocrit" : ".center";
        throw ConfigError(fmt::format("{}{}: {} and {} overlap (a vertex of one lies inside the other)", key, where, built[a].name,
                                      built[b].name),
                          key + where);
      }
    }
}

void check_membranes(const std::vector<MembraneSpec>& list, const SimulationSpec& spec) {
  // The vertex gather unwraps with whole box lengths and the bounce-back takes plain periodic images: a
  // cell across the sheared faces of Lees-Edwards would see its vertices an offset apart and moving dU
  // apart. Refused rather than run wrong.
  if (!list.empty() && spec.models.count("lees_edwards"))
    keys::fail("lees_edwards", "", "[[membrane]] cells do not work with Lees-Edwards shear yet (their vertices are unwrapped "
               "and the solvent bounced back with plain periodic images, not the sheared ones); shear a suspension of "
               "cells between moving walls ([[solid]] planes with a velocity) instead");
  for (std::size_t k = 0; k < list.size(); ++k) {
    const MembraneSpec& c = list[k];
    const std::string key = fmt::format("membrane[{}]", k);
    species_of(c, spec, key);
    if (!c.inner_species.empty()) inner_species_of(c, spec, key);
    if (c.bounce && spec.integrator != IntegratorKind::GrootWarren)
      keys::fail(key + ".bounce", "true", "the bounce-back needs the Groot-Warren integrator (its half-step velocity is the one that moved the particles); set bounce = false or integrator.type = \"groot-warren\"");
    if (c.mesh == MeshKind::File && c.file.empty()) keys::fail(key + ".file", "(missing)", "mesh = \"file\" needs the OFF file");
    if (c.mesh != MeshKind::File && !(c.diameter > 0)) keys::fail(key + ".diameter", "(missing)", "a generated mesh needs its diameter");
    if (c.shear_modulus > 0 && c.persistence > 0)
      keys::fail(key + ".persistence", fmt::format("{}", c.persistence), "give shear_modulus or persistence, not both");
    if (c.viscosity > 0 && (c.gamma_t > 0 || c.gamma_c > 0))
      keys::fail(key + ".viscosity", fmt::format("{}", c.viscosity), "give viscosity or gamma_t and gamma_c, not both");
    if (3 * c.gamma_c < c.gamma_t)
      keys::fail(key + ".gamma_c", fmt::format("{}", c.gamma_c),
                 fmt::format("the random force needs 3 gamma_c >= gamma_t ({}): its amplitude is sqrt(3 gamma_c - gamma_t)", c.gamma_t));
  }
  check_overlaps(list, spec);
}

// Every cell's vertices, in id order, unwrapped, and where asked their velocities: (id, x, y, z[, vx, vy,
// vz]) gathered from the ranks that own them.
class VertexGather {
 public:
  // `velocities`: none, the predicted velocities v (what the forces see) or the half-step ones h.
  enum class Velocities { None, Predicted, HalfStep };
  VertexGather(std::uint32_t first, std::uint32_t count, Velocities velocities = Velocities::None)
      : first_(first), count_(count), velocities_(velocities != Velocities::None), half_(velocities == Velocities::HalfStep),
        x_(count), v_(velocities_ ? count : 0) {}
  const std::vector<Vec3>& gather(const StepContext& ctx) {
    const ParticleData& p = ctx.particles;
    const double lx = ctx.box.len.x, ly = ctx.box.len.y, lz = ctx.box.len.z;
    const std::size_t width = velocities_ ? 7 : 4;
    std::vector<double> mine;  // id, x, y, z[, vx, vy, vz] of the owned vertices
    std::size_t found = 0;
    const auto unwrapped = [&](std::size_t i) {
      return Vec3{p.x[i] + p.ix[i] * lx, p.y[i] + p.iy[i] * ly, p.z[i] + p.iz[i] * lz};
    };
    if (!ctx.comm.distributed()) {
      // Every vertex is here: each thread writes the vertices it finds into their own places.
      const auto n = static_cast<std::ptrdiff_t>(p.n_local);
#pragma omp parallel for schedule(static) reduction(+ : found)
      for (std::ptrdiff_t k = 0; k < n; ++k) {
        const auto i = static_cast<std::size_t>(k);
        const std::uint32_t id = p.id[i];
        if (id < first_ || id >= first_ + count_) continue;
        x_[id - first_] = unwrapped(i);
        if (velocities_) v_[id - first_] = vel(p, i);
        ++found;
      }
    } else {
      for (std::size_t i = 0; i < p.n_local; ++i) {
        const std::uint32_t id = p.id[i];
        if (id < first_ || id >= first_ + count_) continue;
        const Vec3 r = unwrapped(i);
        mine.insert(mine.end(), {static_cast<double>(id), r.x, r.y, r.z});
        if (velocities_) mine.insert(mine.end(), {vel(p, i).x, vel(p, i).y, vel(p, i).z});
        ++found;
      }
      std::vector<std::byte> bytes(mine.size() * sizeof(double));
      std::memcpy(bytes.data(), mine.data(), bytes.size());
      std::vector<std::byte> all = ctx.comm.gather(bytes);
      ctx.comm.broadcast(all);
      std::vector<double> values(all.size() / sizeof(double));
      std::memcpy(values.data(), all.data(), values.size() * sizeof(double));
      found = values.size() / width;
      for (std::size_t k = 0; k + width <= values.size(); k += width) {
        const std::uint32_t at = static_cast<std::uint32_t>(values[k]) - first_;
        x_[at] = {values[k + 1], values[k + 2], values[k + 3]};
        if (velocities_) v_[at] = {values[k + 4], values[k + 5], values[k + 6]};
      }
    }
    if (found != count_)
      throw std::logic_error(fmt::format("membrane: {} of {} vertices found", found, count_));
    return x_;
  }
  std::uint32_t first() const { return first_; }
  const std::vector<Vec3>& velocities() const { return v_; }

 private:
  Vec3 vel(const ParticleData& p, std::size_t i) const {
    return half_ ? Vec3{p.hx[i], p.hy[i], p.hz[i]} : Vec3{p.vx[i], p.vy[i], p.vz[i]};
  }
  std::uint32_t first_, count_;
  bool velocities_, half_;
  std::vector<Vec3> x_, v_;
};

struct Cell {
  membrane::CellModel model;
  std::uint32_t first = 0;             // id of vertex 0
  std::vector<Vec3> external;          // tweezers force per vertex (at full strength)
  std::uint64_t ramp = 0;              // steps over which it grows from 0
  std::size_t species = 0;             // of its vertices
  std::size_t block = 0;               // its [[membrane]] block
  double repulsion = 0, repulsion_range = 0;  // its block's repulsion from other cells
};

class MembraneForcesStage final : public Stage {
 public:
  MembraneForcesStage(std::vector<Cell> cells, std::uint32_t first, std::uint32_t count, std::uint64_t seed)
      : cells_(std::move(cells)),
        gather_(first, count,
                std::any_of(cells_.begin(), cells_.end(), [](const Cell& c) { return c.model.viscous(); })
                    ? VertexGather::Velocities::Predicted
                    : VertexGather::Velocities::None),
        seed_(seed) {
    for (std::size_t c = 0; c < cells_.size(); ++c) {
      cell_of_.insert(cell_of_.end(), cells_[c].model.vertex_count(), static_cast<std::uint32_t>(c));
      if (cells_[c].repulsion > 0) range_ = std::max(range_, cells_[c].repulsion_range);
    }
  }
  void run(StepContext& ctx) override {
    const std::vector<Vec3>& all = gather_.gather(ctx);
    forces_.assign(all.size(), Vec3{});
    // Each cell is evaluated whole by one thread, into its own slice of forces_: the same numbers on any
    // thread count. A broken edge is reported after the loop (the first cell in order), not thrown from it.
    const auto n_cells = static_cast<std::ptrdiff_t>(cells_.size());
    energies_.assign(cells_.size(), 0.0);
    broken_.assign(cells_.size(), kIntact);
    virials_.assign(cells_.size(), CellVirial{});
#pragma omp parallel
    {
      std::vector<Vec3> x, v, f;
#pragma omp for schedule(dynamic)
      for (std::ptrdiff_t c = 0; c < n_cells; ++c) {
        const Cell& cell = cells_[static_cast<std::size_t>(c)];
        const std::size_t nv = cell.model.vertex_count(), off = cell.first - gather_.first();
        x.assign(all.begin() + static_cast<std::ptrdiff_t>(off), all.begin() + static_cast<std::ptrdiff_t>(off + nv));
        f.assign(nv, Vec3{});
        std::size_t broken = 0;
        const auto e = cell.model.forces(x, f, &broken);
        if (!e) {
          broken_[static_cast<std::size_t>(c)] = broken;
          continue;
        }
        energies_[static_cast<std::size_t>(c)] = e->total();
        CellVirial& w = virials_[static_cast<std::size_t>(c)];
        w.total = membrane::virial(x, f);
        w.elastic_trace = w.total[0] + w.total[1] + w.total[2];
        if (cell.model.viscous()) {
          const std::vector<Vec3>& vel = gather_.velocities();
          v.assign(vel.begin() + static_cast<std::ptrdiff_t>(off), vel.begin() + static_cast<std::ptrdiff_t>(off + nv));
          cell.model.viscous_forces(x, v, ctx.dt, seed_, ctx.step, cell.first, f);
          w.total = membrane::virial(x, f);
        }
        const double share = cell.ramp > ctx.step ? static_cast<double>(ctx.step) / static_cast<double>(cell.ramp) : 1.0;
        for (std::size_t i = 0; i < nv; ++i) forces_[off + i] = f[i] + share * cell.external[i];
      }
    }
    energy_ = 0;
    for (std::size_t c = 0; c < cells_.size(); ++c) {
      if (broken_[c] != kIntact) {
        const Cell& cell = cells_[c];
        const membrane::Hinge& h = cell.model.hinges()[broken_[c]];
        const std::size_t off = cell.first - gather_.first();
        const double l = norm(all[off + h.c] - all[off + h.b]);
        throw BlowUpError(ctx.step, cell.first + h.b,
                          fmt::format("step {}: cell {} (membrane[{}]): the edge between vertices {} and {} (particle ids {} and {}) is "
                                      "{:.6g} long, at or past its maximum {:.6g} (l0 / x0), where the WLC force is infinite; "
                                      "lower the time step or the forces on the cell, or raise membrane[{}].x0's room",
                                      ctx.step, c, cell.block, h.b, h.c, cell.first + h.b, cell.first + h.c, l,
                                      cell.model.max_length(broken_[c]), cell.block));
      }
      energy_ += energies_[c];
    }
    std::array<double, 6> contact{};
    if (range_ > 0) {
      contact = repel(all, ctx.box);
      energy_ += contact_energy_;
    }
    // The membranes' internal forces act between particles: their virial belongs to the stress (summed in
    // cell order, the same on every rank, which all evaluate every cell). The tweezers are external.
    if (ctx.pair_sums) {
      for (const CellVirial& w : virials_) {
        for (std::size_t k = 0; k < 6; ++k) ctx.pair_sums->virial[k] += w.total[k];
        ctx.pair_sums->virial_conservative += w.elastic_trace;
      }
      for (std::size_t k = 0; k < 6; ++k) ctx.pair_sums->virial[k] += contact[k];
      ctx.pair_sums->virial_conservative += contact[0] + contact[1] + contact[2];
    }
    ParticleData& p = ctx.particles;
    const std::uint32_t first = gather_.first(), end = first + static_cast<std::uint32_t>(all.size());
    for (std::size_t i = 0; i < p.n_local; ++i) {
      const std::uint32_t id = p.id[i];
      if (id < first || id >= end) continue;
      const Vec3& g = forces_[id - first];
      p.fx[i] += g.x;
      p.fy[i] += g.y;
      p.fz[i] += g.z;
    }
  }
  const std::vector<Cell>& cells() const { return cells_; }
  double energy() const { return energy_; }

 private:
  std::vector<Cell> cells_;
  VertexGather gather_;
  std::uint64_t seed_;
  static constexpr std::size_t kIntact = ~std::size_t{0};
  struct CellVirial {
    std::array<double, 6> total{};  // elastic and viscous (membrane::virial)
    double elastic_trace = 0;       // of the conservative (elastic) forces only
  };
  std::vector<CellVirial> virials_;  // per cell

  // The repulsion between vertices of different cells ([[membrane]] repulsion): adds each vertex's force to
  // forces_, sets contact_energy_ and returns the virial (PairSums' order). Every vertex sums over its own
  // neighbours (bins of at least the largest range, minimum image), on all threads; the totals are added
  // in vertex order, so the bits do not depend on the thread count.
  std::array<double, 6> repel(const std::vector<Vec3>& all, const Box& box) {
    const std::size_t n = all.size();
    int dims[3];
    for (int d = 0; d < 3; ++d) dims[d] = std::max(1, static_cast<int>(std::floor(box.length(d) / range_)));
    const auto bin_of = [&](const Vec3& r, int out[3]) {
      const double x[3] = {r.x, r.y, r.z};
      for (int d = 0; d < 3; ++d) {
        const double l = box.length(d);
        const double w = x[d] - l * std::floor(x[d] / l);
        out[d] = std::clamp(static_cast<int>(w / l * dims[d]), 0, dims[d] - 1);
      }
    };
    const std::size_t bins = static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]) * static_cast<std::size_t>(dims[2]);
    // A counting sort of the vertices by bin (the buffers are kept from step to step).
    std::vector<std::uint32_t>& start = rep_start_;
    start.assign(bins + 1, 0);
    rep_cell_.resize(n);
    rep_order_.resize(n);
    const auto flat = [&](int x, int y, int z) { return static_cast<std::size_t>((x * dims[1] + y) * dims[2] + z); };
    for (std::size_t i = 0; i < n; ++i) {
      bin_of(all[i], rep_cell_[i].data());
      ++start[flat(rep_cell_[i][0], rep_cell_[i][1], rep_cell_[i][2]) + 1];
    }
    for (std::size_t b = 0; b < bins; ++b) start[b + 1] += start[b];
    rep_fill_.assign(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
      rep_order_[rep_fill_[flat(rep_cell_[i][0], rep_cell_[i][1], rep_cell_[i][2])]++] = static_cast<std::uint32_t>(i);
    const std::vector<std::uint32_t>& order = rep_order_;
    std::vector<Vec3>& f = rep_force_;
    std::vector<double>& e = rep_energy_;
    std::vector<std::array<double, 6>>& w = rep_virial_;
    f.assign(n, Vec3{});
    e.assign(n, 0.0);
    w.assign(n, std::array<double, 6>{});
    const auto ptr = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t ii = 0; ii < ptr; ++ii) {
      const auto i = static_cast<std::size_t>(ii);
      const Cell& ci = cells_[cell_of_[i]];
      if (ci.repulsion == 0) continue;
      const std::array<int, 3>& b = rep_cell_[i];
      int near[3][3], m[3];
      for (int d = 0; d < 3; ++d) m[d] = adjacent_bins(b[d], dims[d], box.periodic[static_cast<std::size_t>(d)], near[d]);
      for (int a0 = 0; a0 < m[0]; ++a0)
        for (int a1 = 0; a1 < m[1]; ++a1)
          for (int a2 = 0; a2 < m[2]; ++a2) {
            const std::size_t bb = flat(near[0][a0], near[1][a1], near[2][a2]);
            for (std::uint32_t q = start[bb]; q < start[bb + 1]; ++q) {
              const std::uint32_t j = order[q];
              if (cell_of_[j] == cell_of_[i]) continue;
              const Cell& cj = cells_[cell_of_[j]];
              if (cj.repulsion == 0) continue;
              const double rr = std::max(ci.repulsion_range, cj.repulsion_range);
              double dx[3] = {all[i].x - all[j].x, all[i].y - all[j].y, all[i].z - all[j].z};
              for (int d = 0; d < 3; ++d)
                if (box.periodic[static_cast<std::size_t>(d)]) dx[d] -= box.length(d) * std::round(dx[d] / box.length(d));
              const double r2 = dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2];
              if (r2 >= rr * rr || r2 == 0.0) continue;
              const double r = std::sqrt(r2), a = std::sqrt(ci.repulsion * cj.repulsion), om = 1.0 - r / rr;
              const double fr = a * om / r;  // the force on i is fr d
              f[i] += Vec3{fr * dx[0], fr * dx[1], fr * dx[2]};
              e[i] += 0.25 * a * rr * om * om;  // half of the pair's a r_r / 2 (1 - r/r_r)^2
              // Half of the pair's virial d (x) F (the other half comes with j): ab = d_b F_a.
              std::array<double, 6>& wi = w[i];
              wi[0] += 0.5 * dx[0] * fr * dx[0];
              wi[1] += 0.5 * dx[1] * fr * dx[1];
              wi[2] += 0.5 * dx[2] * fr * dx[2];
              wi[3] += 0.5 * dx[1] * fr * dx[0];
              wi[4] += 0.5 * dx[2] * fr * dx[0];
              wi[5] += 0.5 * dx[2] * fr * dx[1];
            }
          }
    }
    std::array<double, 6> total{};
    contact_energy_ = 0;
    for (std::size_t i = 0; i < n; ++i) {
      forces_[i] += f[i];
      contact_energy_ += e[i];
      for (std::size_t k = 0; k < 6; ++k) total[k] += w[i][k];
    }
    return total;
  }
  // repel()'s buffers, kept from step to step: per vertex its bin coordinates, force, energy and virial
  // halves; the bins' starts, the vertices in bin order, the counting sort's fill pointers.
  std::vector<std::array<int, 3>> rep_cell_;
  std::vector<Vec3> rep_force_;
  std::vector<double> rep_energy_;
  std::vector<std::array<double, 6>> rep_virial_;
  std::vector<std::uint32_t> rep_start_, rep_order_, rep_fill_;
  std::vector<std::uint32_t> cell_of_;  // per gathered vertex: its cell
  double range_ = 0;                    // the largest repulsion range (0: no repulsion)
  double contact_energy_ = 0;
  std::vector<Vec3> forces_;
  std::vector<double> energies_;     // per cell, summed in cell order
  std::vector<std::size_t> broken_;  // per cell: the hinge of a broken edge, or kIntact
  double energy_ = 0;
};

// The particles a membrane keeps apart: every local particle that is mobile and not a membrane vertex.
struct Movers {
  std::vector<char> frozen;  // by species
  std::uint32_t first = 0, count = 0;
  bool operator()(const ParticleData& p, std::size_t i) const {
    return !frozen[static_cast<std::size_t>(p.species[i])] && (p.id[i] < first || p.id[i] >= first + count);
  }
};

// The nearest image of a difference along axis d however many periods it spans: the gathered vertices are
// unwrapped (position plus image times the box), so a cell that has travelled k box lengths lies about
// k L from the wrapped particles near it, beyond what one minimum_image() step brings back.
double nearest_image(const Box& box, int d, double diff) {
  const double g = minimum_image(diff, box.image_len(d), box.half_image_len(d));
  if (std::abs(g) <= box.half_image_len(d)) return g;
  return diff - box.length(d) * std::round(diff / box.length(d));
}

// The shift by whole periods that brings the wrapped position r next to the unwrapped point near (the
// nearest image of near - r taken off near - r).
Vec3 image_shift(const Box& box, Vec3 r, Vec3 near) {
  const auto along = [&](int d, double diff) { return diff - nearest_image(box, d, diff); };
  return {along(0, near.x - r.x), along(1, near.y - r.y), along(2, near.z - r.z)};
}

// Which local movers lie inside each cell (winding number > 1/2), as sorted global ids over all ranks.
std::vector<std::vector<std::uint32_t>> inside_ids(const StepContext& ctx, const std::vector<Cell>& cells,
                                                   const std::vector<Vec3>& all, std::uint32_t first_all, const Movers& movers) {
  const ParticleData& p = ctx.particles;
  std::vector<std::vector<std::uint32_t>> ids(cells.size());
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const Cell& cell = cells[c];
    const std::size_t off = cell.first - first_all, nv = cell.model.vertex_count();
    const std::vector<Vec3> x(all.begin() + static_cast<std::ptrdiff_t>(off), all.begin() + static_cast<std::ptrdiff_t>(off + nv));
    Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const Vec3& v : x) {
      lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
      hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
    }
    const Vec3 mid = 0.5 * (lo + hi);
    std::vector<std::uint32_t> mine;
    for (std::size_t i = 0; i < p.n_local; ++i) {
      if (!movers(p, i)) continue;
      Vec3 r{p.x[i], p.y[i], p.z[i]};
      r += image_shift(ctx.box, r, mid);
      if (r.x < lo.x || r.y < lo.y || r.z < lo.z || r.x > hi.x || r.y > hi.y || r.z > hi.z) continue;
      if (membrane::winding_number(cell.model.mesh(), x, r) > 0.5) mine.push_back(p.id[i]);
    }
    if (ctx.comm.distributed()) {
      std::vector<std::byte> bytes(mine.size() * sizeof(std::uint32_t));
      std::memcpy(bytes.data(), mine.data(), bytes.size());
      std::vector<std::byte> every = ctx.comm.gather(bytes);
      ctx.comm.broadcast(every);
      mine.resize(every.size() / sizeof(std::uint32_t));
      std::memcpy(mine.data(), every.data(), every.size());
    }
    std::sort(mine.begin(), mine.end());
    ids[c] = std::move(mine);
  }
  return ids;
}

// The solvent's bounce-back on the moving triangles (AfterFirstHalf: positions moved, forces not yet
// computed). With the Groot-Warren integrator every particle moved this step from x - dt h to x, h its
// half-step velocity, and every vertex likewise: the straight paths membrane::first_contact needs. A
// mover whose path meets a triangle (the earliest contact over all candidates) is sent back from the
// point of contact with its velocity relative to the triangle (the vertices' h interpolated there)
// reversed, for the rest of the step; its momentum change is taken from the triangle's three vertices in
// the proportions of the contact's weights. The candidates come from a grid of unit bins holding every
// triangle's swept box, widened by the longest move of any particle. The contacts of all ranks are
// applied to the vertices in order of particle id, so the result is the same on any thread or rank count.
class MembraneBounceStage final : public Stage {
 public:
  MembraneBounceStage(const std::vector<Cell>& cells, std::vector<char> bounce, Movers movers, std::uint32_t first,
                      std::uint32_t count)
      : cells_(cells), bounce_(std::move(bounce)), movers_(std::move(movers)),
        gather_(first, count, VertexGather::Velocities::HalfStep), momentum_(count) {
    for (std::uint32_t c = 0; c < cells_.size(); ++c) {
      const std::uint32_t off = cells_[c].first - gather_.first();
      for (const auto& tri : cells_[c].model.mesh().triangles) {
        cell_of_.push_back(c);
        corners_.push_back({off + tri[0], off + tri[1], off + tri[2]});
      }
    }
    swept_.resize(corners_.size());
  }

  void run(StepContext& ctx) override {
    const std::vector<Vec3>& x1 = gather_.gather(ctx);
    const std::vector<Vec3>& h = gather_.velocities();
    const double dt = ctx.dt;
    ParticleData& p = ctx.particles;
    const Box& box = ctx.box;
    std::size_t moving = 0;
    const auto n_local = static_cast<std::ptrdiff_t>(p.n_local);
#pragma omp parallel for schedule(static) reduction(+ : moving)
    for (std::ptrdiff_t i = 0; i < n_local; ++i)
      if (movers_(p, static_cast<std::size_t>(i))) ++moving;
    std::vector<double> hits;  // per contact: particle id, three vertex indices, three weights, dp
    // A rank with no solvent (a membrane alone) has nothing to test; it still takes part in the gather.
    if (moving > 0) {
      bin_triangles(box, x1, h, dt);
      // Threads take particles in blocks and keep their contacts apart; give_to_vertices orders all
      // contacts by particle id, so the vertices' kicks do not depend on the thread count.
      std::uint64_t unresolved = 0;
#pragma omp parallel reduction(+ : unresolved)
      {
        std::vector<double> mine;
#pragma omp for schedule(static) nowait
        for (std::ptrdiff_t i = 0; i < n_local; ++i)
          unresolved += bounce_particle(ctx, static_cast<std::size_t>(i), x1, h, mine);
#pragma omp critical(membrane_bounce_hits)
        hits.insert(hits.end(), mine.begin(), mine.end());
      }
      unresolved_ += unresolved;
    }
    bounces_ += hits.size() / kWidth;
    give_to_vertices(ctx, hits);
  }

  std::uint64_t bounces() const { return bounces_; }        // on this rank, since the start of this run
  std::uint64_t unresolved() const { return unresolved_; }  // paths with kRounds contacts in a step (not tested further)

 private:
  // Particle i's path of this step against the binned triangles: its contacts appended to `hits`, the
  // particle moved to the end of its bounced path. Returns 1 when the path still had contacts after
  // kRounds of them (not tested further), else 0.
  int bounce_particle(StepContext& ctx, std::size_t i, const std::vector<Vec3>& x1, const std::vector<Vec3>& h,
                      std::vector<double>& hits) const {
    ParticleData& p = ctx.particles;
    const Box& box = ctx.box;
    const double dt = ctx.dt;
    if (!movers_(p, i)) return 0;
    const Vec3 r{p.x[i], p.y[i], p.z[i]};
    {  // most particles are far from every membrane: their step lies in one bin that lists nothing
      const std::size_t bin = locate(box, r).bin;
      if (bin_start_[bin] == bin_start_[bin + 1] && locate(box, r - dt * Vec3{p.hx[i], p.hy[i], p.hz[i]}).bin == bin) return 0;
    }
    // The path of this step, then after each contact the rest of the step from the contact point with
    // the reflected velocity, until a path meets nothing (at most kRounds contacts).
    Vec3 hcur{p.hx[i], p.hy[i], p.hz[i]};
    Vec3 end = r, start = r - dt * hcur;
    double t0 = 0;
    std::uint32_t last_g = ~0u;  // the triangle met last (index in corners_)
    std::array<std::uint32_t, 3> last_corners{};
    Vec3 last_shift;
    double last_side = 1.0;
    int rounds = 0;
    const double m = ctx.species_mass[static_cast<std::size_t>(p.species[i])];
    for (; rounds < kRounds; ++rounds) {
      double best = 2.0;
      std::uint32_t best_g = ~0u;
      membrane::Hit hit;
      std::array<std::uint32_t, 3> corners{};
      Vec3 shift;
      // The path's box, as centre and half extents, for a quick test against each candidate's swept box
      // at the nearest image: it rejects only what the exact test below would reject (the boxes are
      // far smaller than half the box), without reading the triangle's corners. A triangle whose box
      // meets the path's is listed in a bin that both boxes cover: the candidates are the triangles
      // listed in the bins the path's box covers (usually one).
      const Vec3 pc = 0.5 * (start + end);
      const Vec3 ph{0.5 * std::abs(end.x - start.x), 0.5 * std::abs(end.y - start.y), 0.5 * std::abs(end.z - start.z)};
      bool spans = false;  // the path's bins are the whole of a periodic axis (a box of a few bins)
      const AxisRun runs[3] = {axis_run(box, 0, pc.x - ph.x, pc.x + ph.x, spans), axis_run(box, 1, pc.y - ph.y, pc.y + ph.y, spans),
                               axis_run(box, 2, pc.z - ph.z, pc.z + ph.z, spans)};
      const float inf = std::numeric_limits<float>::infinity();
      const float fh[3] = {spans ? inf : static_cast<float>(ph.x), spans ? inf : static_cast<float>(ph.y), spans ? inf : static_cast<float>(ph.z)};
      for_bins(runs, [&](std::size_t bin, const std::array<long, 3>& image) {
        // First in single precision against the slots' boxes in the wrapped frame (the bin's image taken
        // off), contiguous in memory; branch-free over blocks of slots, the few survivors then in slot
        // order.
        const float fc[3] = {static_cast<float>(pc.x - static_cast<double>(image[0]) * box.len.x),
                             static_cast<float>(pc.y - static_cast<double>(image[1]) * box.len.y),
                             static_cast<float>(pc.z - static_cast<double>(image[2]) * box.len.z)};
        const std::size_t k_end = bin_start_[bin + 1];
        for (std::size_t base = bin_start_[bin]; base < k_end; base += kBlock) {
          std::array<std::uint32_t, kBlock> pass;
          std::size_t np = 0;
          const std::size_t block_end = std::min(k_end, base + kBlock);
          for (std::size_t k = base; k < block_end; ++k) {
            const SlotBox& sb = slot_boxes_[k];
            const bool in = (std::abs(fc[0] - sb.c[0]) <= fh[0] + sb.h[0]) & (std::abs(fc[1] - sb.c[1]) <= fh[1] + sb.h[1]) &
                            (std::abs(fc[2] - sb.c[2]) <= fh[2] + sb.h[2]);
            pass[np] = static_cast<std::uint32_t>(k - base);
            np += in ? 1 : 0;
          }
          for (std::size_t q = 0; q < np; ++q) {
            const std::uint32_t g = slot_boxes_[base + pass[q]].triangle;
            if (g == last_g) continue;  // the reflected path leaves the triangle just met
            // The survivors' swept boxes again, in double precision at the nearest image.
            const Box3& tb = swept_[g];
            if (!near_box(box, pc, ph, tb)) continue;
            const std::array<std::uint32_t, 3>& v = corners_[g];
            const Vec3 s = image_shift(box, end, x1[v[0]]);
            const Vec3 ps = start + s, pe = end + s;
            if (std::max(ps.x, pe.x) < tb.lo.x || std::min(ps.x, pe.x) > tb.hi.x || std::max(ps.y, pe.y) < tb.lo.y ||
                std::min(ps.y, pe.y) > tb.hi.y || std::max(ps.z, pe.z) < tb.lo.z || std::min(ps.z, pe.z) > tb.hi.z)
              continue;
            const auto at = [&](std::uint32_t k) { return x1[k] - ((1.0 - t0) * dt) * h[k]; };
            const auto a = membrane::first_contact(ps, pe, at(v[0]), x1[v[0]], at(v[1]), x1[v[1]], at(v[2]), x1[v[2]]);
            // The earliest contact; between equal times the first triangle in (cell, triangle) order,
            // whichever bin listed it first.
            if (a && (a->t < best || (a->t == best && g < best_g))) {
              best = a->t;
              best_g = g;
              hit = *a;
              corners = v;
              shift = s;
            }
          }
        }
      });
      if (best > 1.0) break;
      const Vec3 contact = start + best * (end - start);
      const Vec3 u = hit.w[0] * h[corners[0]] + hit.w[1] * h[corners[1]] + hit.w[2] * h[corners[2]];
      // An elastic collision with the contact point, whose mass is M = 1 / sum_k w_k^2 / m_k: the
      // velocity relative to it reversed in the frame of their centre of mass, which conserves momentum
      // and energy (the full bounce-back 2 u - h of an immovable wall would heat the membrane).
      const double mv = ctx.species_mass[cells_[cell_of_[best_g]].species];
      const double big_m = mv / (hit.w[0] * hit.w[0] + hit.w[1] * hit.w[1] + hit.w[2] * hit.w[2]);
      const double mu = m * big_m / (m + big_m);
      const Vec3 hn = hcur - (2.0 * mu / m) * (hcur - u);
      const Vec3 dp = m * (hn - hcur);
      // The side the particle came from, by its approach to the triangle at the time of contact.
      {
        const auto at = [&](std::uint32_t k) { return x1[k] - ((1.0 - (t0 + best * (1.0 - t0))) * dt) * h[k]; };
        const Vec3 n = cross(at(corners[1]) - at(corners[0]), at(corners[2]) - at(corners[0]));
        last_side = dot(hcur - u, n) > 0 ? -1.0 : 1.0;
      }
      hits.insert(hits.end(), {static_cast<double>(p.id[i]), static_cast<double>(corners[0]), static_cast<double>(corners[1]),
                               static_cast<double>(corners[2]), hit.w[0], hit.w[1], hit.w[2], dp.x, dp.y, dp.z});
      t0 += best * (1.0 - t0);
      start = contact;
      end = contact + ((1.0 - t0) * dt) * hn;
      hcur = hn;
      last_g = best_g;
      last_corners = corners;
      last_shift = shift;
    }
    if (rounds == 0) return 0;
    place(p, i, end, hcur, last_corners, last_side, last_shift, x1, box);
    return rounds == kRounds ? 1 : 0;
  }

  static constexpr std::size_t kWidth = 10;
  static constexpr std::size_t kBlock = 64;
  static constexpr int kRounds = 4;
  static constexpr double kBinWidth = 1.0;  // at least
  // A triangle listed in a bin (its index in corners_) with its box of this step, moved by whole box
  // lengths to the image next to the bin (the wrapped frame), as centre and half extents in single
  // precision, the half extents padded for the rounding; +inf where its listing spans a whole periodic
  // axis (a box of a few bins), where only near_box's nearest image can tell.
  struct SlotBox {
    float c[3], h[3];
    std::uint32_t triangle;
  };
  // A point's bin, and its image (whole box lengths from the wrapped position) on the periodic axes.
  struct Located {
    std::size_t bin = 0;
    std::array<long, 3> image{0, 0, 0};
  };
  struct Box3 {
    Vec3 lo, hi;
  };

  // Whether the box of centre pc and half extents ph meets the box tb at tb's nearest image.
  static bool near_box(const Box& box, Vec3 pc, Vec3 ph, const Box3& tb) {
    const auto apart = [&](int d, double p, double half, double lo, double hi) {
      const double gap = nearest_image(box, d, p - 0.5 * (lo + hi));
      return std::abs(gap) > half + 0.5 * (hi - lo);
    };
    return !(apart(0, pc.x, ph.x, tb.lo.x, tb.hi.x) || apart(1, pc.y, ph.y, tb.lo.y, tb.hi.y) ||
             apart(2, pc.z, ph.z, tb.lo.z, tb.hi.z));
  }

  // Along axis d: the bin of coordinate v, and the image of v (0 on a bounded axis, whose end bins take
  // what lies beyond).
  std::size_t bin_index(const Box& box, int d, double v, long& image) const {
    const auto n = static_cast<long>(bins_[static_cast<std::size_t>(d)]);
    const long k = floor_of(v * inv_width_[static_cast<std::size_t>(d)]);
    if (!box.periodic[static_cast<std::size_t>(d)]) {
      image = 0;
      return static_cast<std::size_t>(std::clamp(k, 0L, n - 1));
    }
    return static_cast<std::size_t>(wrap(k, n, image));
  }
  // std::floor without the library call (|v| far below 2^63).
  static long floor_of(double v) {
    const auto k = static_cast<long>(v);
    return static_cast<double>(k) > v ? k - 1 : k;
  }
  // Bin k of an axis of n wrapped into [0, n), and the whole periods taken off it: a division only off
  // the first period.
  static long wrap(long k, long n, long& image) {
    image = 0;
    if (k >= 0 && k < n) return k;
    image = (k >= 0 ? k : k - n + 1) / n;
    return k - image * n;
  }
  Located locate(const Box& box, Vec3 r) const {
    Located at;
    const std::size_t i = bin_index(box, 0, r.x, at.image[0]), j = bin_index(box, 1, r.y, at.image[1]),
                      k = bin_index(box, 2, r.z, at.image[2]);
    at.bin = (k * bins_[1] + j) * bins_[0] + i;
    return at;
  }

  // The bins along one axis that an interval covers: `count` of them from bin `first` (wrapped as
  // bin_index wraps a coordinate) at image `image` (whole box lengths), counting on with a wrap.
  struct AxisRun {
    long first = 0, count = 0, image = 0;
  };
  // Along axis d, for [lo, hi]; `exact` set where it spans a whole periodic axis. The bins are distinct,
  // as the range is shorter than the axis or is the whole axis.
  [[gnu::always_inline]] AxisRun axis_run(const Box& box, int d, double lo, double hi, bool& exact) const {
    const auto u = static_cast<std::size_t>(d);
    long from = floor_of(lo * inv_width_[u]), to = floor_of(hi * inv_width_[u]);
    const auto n = static_cast<long>(bins_[u]);
    if (to - from + 1 >= n) {
      from = 0;
      to = n - 1;
      exact = exact || box.periodic[u];
    }
    if (!box.periodic[u]) {  // a bounded axis: its end bins take what lies beyond
      from = std::clamp(from, 0L, n - 1);
      to = std::clamp(to, 0L, n - 1);
    }
    AxisRun run{0, to - from + 1, 0};
    run.first = wrap(from, n, run.image);
    return run;
  }

  // Visits the bins of three axis runs, x fastest, with their images (whole box lengths along each axis).
  template <class Visit>
  void for_bins(const AxisRun (&r)[3], Visit&& visit) const {
    const auto nx = static_cast<long>(bins_[0]), ny = static_cast<long>(bins_[1]), nz = static_cast<long>(bins_[2]);
    long k = r[2].first, ik = r[2].image;
    for (long a = 0; a < r[2].count; ++a) {
      long j = r[1].first, ij = r[1].image;
      for (long b = 0; b < r[1].count; ++b) {
        const auto row = static_cast<std::size_t>((k * ny + j) * nx);
        long i = r[0].first, ii = r[0].image;
        for (long c = 0; c < r[0].count; ++c) {
          visit(row + static_cast<std::size_t>(i), std::array<long, 3>{ii, ij, ik});
          if (++i == nx) i = 0, ++ii;
        }
        if (++j == ny) j = 0, ++ij;
      }
      if (++k == nz) k = 0, ++ik;
    }
  }

  // Lists each triangle in the bins (at least kBinWidth wide) that its box over this step's move (its
  // corners at the start and the end of the step) covers, at their images: a counting sort in two
  // passes over the same blocks of triangles per thread, the first finding the boxes and counting per bin
  // and thread, the second writing each thread's triangles after those of the threads before it. So each
  // bin lists its triangles in (cell, triangle) order, whatever the thread count (the contact chosen
  // does not depend on the order: bounce_particle).
  void bin_triangles(const Box& box, const std::vector<Vec3>& x1, const std::vector<Vec3>& h, double dt) {
    for (int d = 0; d < 3; ++d) {
      const auto u = static_cast<std::size_t>(d);
      bins_[u] = std::max<std::size_t>(1, static_cast<std::size_t>(box.length(d) / kBinWidth));
      inv_width_[u] = static_cast<double>(bins_[u]) / box.length(d);
    }
    const std::size_t n_bins = bins_[0] * bins_[1] * bins_[2];
    const std::size_t n_tri = corners_.size();
    bin_start_.resize(n_bins + 1);
    // The pad covers the single-precision rounding of both sides' coordinates in bounce_particle's first
    // test (within a few box lengths of the origin), so that test passes whatever near_box passes: a slot
    // that is not `exact` lists the only image at which a path whose box covers its bin can meet its box,
    // as the bins it covers span less than the axis.
    const double pad = 1e-5 * (1.0 + std::max({box.len.x, box.len.y, box.len.z}));
    const double len[3] = {box.len.x, box.len.y, box.len.z};
#pragma omp parallel
    {
      // The team as it is (it may be smaller than asked for): the blocks and counts follow it.
      const auto threads = static_cast<std::size_t>(omp_get_num_threads());
      const auto me = static_cast<std::size_t>(omp_get_thread_num());
#pragma omp single
      counts_.assign(threads * n_bins, 0);
      const std::size_t g0 = n_tri * me / threads, g1 = n_tri * (me + 1) / threads;
      std::size_t* count = counts_.data() + me * n_bins;
      // Visits the bins of triangle g with their images.
      const auto each_bin = [&](std::size_t g, auto&& visit) {
        const Box3& tb = swept_[g];
        bool exact = false;
        const AxisRun r[3] = {axis_run(box, 0, tb.lo.x, tb.hi.x, exact), axis_run(box, 1, tb.lo.y, tb.hi.y, exact),
                              axis_run(box, 2, tb.lo.z, tb.hi.z, exact)};
        for_bins(r, [&](std::size_t bin, const std::array<long, 3>& image) { visit(bin, image, exact); });
      };
      for (std::size_t g = g0; g < g1; ++g) {
        if (!bounce_[cell_of_[g]]) continue;
        Box3 b{{1e300, 1e300, 1e300}, {-1e300, -1e300, -1e300}};
        for (std::uint32_t k : corners_[g])
          for (const Vec3& q : {x1[k], x1[k] - dt * h[k]}) {
            b.lo = {std::min(b.lo.x, q.x), std::min(b.lo.y, q.y), std::min(b.lo.z, q.z)};
            b.hi = {std::max(b.hi.x, q.x), std::max(b.hi.y, q.y), std::max(b.hi.z, q.z)};
          }
        swept_[g] = {b.lo - Vec3{1e-9, 1e-9, 1e-9}, b.hi + Vec3{1e-9, 1e-9, 1e-9}};
        each_bin(g, [&](std::size_t bin, const std::array<long, 3>&, bool) { ++count[bin]; });
      }
#pragma omp barrier
#pragma omp single
      {
        // Each bin's slots: thread 0's, then thread 1's, ...; counts_ becomes each thread's next place.
        std::size_t next = 0;
        for (std::size_t bin = 0; bin < n_bins; ++bin) {
          bin_start_[bin] = next;
          for (std::size_t th = 0; th < threads; ++th) {
            const std::size_t here = counts_[th * n_bins + bin];
            counts_[th * n_bins + bin] = next;
            next += here;
          }
        }
        bin_start_[n_bins] = next;
        slot_boxes_.resize(next);
      }
      for (std::size_t g = g0; g < g1; ++g) {
        if (!bounce_[cell_of_[g]]) continue;
        const Box3& tb = swept_[g];
        const double lo[3] = {tb.lo.x, tb.lo.y, tb.lo.z}, hi[3] = {tb.hi.x, tb.hi.y, tb.hi.z};
        each_bin(g, [&](std::size_t bin, const std::array<long, 3>& image, bool exact) {
          SlotBox& sb = slot_boxes_[count[bin]++];
          for (std::size_t d = 0; d < 3; ++d) {
            sb.c[d] = static_cast<float>(0.5 * (lo[d] + hi[d]) - static_cast<double>(image[d]) * len[d]);
            sb.h[d] = exact ? std::numeric_limits<float>::infinity() : static_cast<float>(0.5 * (hi[d] - lo[d]) + pad);
          }
          sb.triangle = static_cast<std::uint32_t>(g);
        });
      }
    }
  }

  // Puts particle i at the end of its bounced path (in the frame of the last triangle met: shift) with
  // the half-step velocity hn, at least 1e-7 from that triangle's plane at the end of the step on the
  // side it came from (side: +1 where the triangle's normal points); the predicted velocity keeps its
  // offset from the half-step one.
  static void place(ParticleData& p, std::size_t i, Vec3 end, Vec3 hn, const std::array<std::uint32_t, 3>& v, double side,
                    Vec3 shift, const std::vector<Vec3>& x1, const Box& box) {
    Vec3 r = end + shift;
    const Vec3 n1 = cross(x1[v[1]] - x1[v[0]], x1[v[2]] - x1[v[0]]);
    const Vec3 nh = (1.0 / norm(n1)) * n1;
    const double dist = side * dot(r - x1[v[0]], nh);
    if (dist < 1e-7) r += (side * (1e-7 - dist)) * nh;
    r = r - shift;
    double* xyz[3] = {&p.x[i], &p.y[i], &p.z[i]};
    std::int32_t* img[3] = {&p.ix[i], &p.iy[i], &p.iz[i]};
    const double q[3] = {r.x, r.y, r.z};
    for (int d = 0; d < 3; ++d) {
      *xyz[d] = q[d];
      if (box.periodic[static_cast<std::size_t>(d)]) wrap_coordinate(*xyz[d], *img[d], box.length(d));
    }
    const Vec3 dh = hn - Vec3{p.hx[i], p.hy[i], p.hz[i]};
    p.hx[i] = hn.x;
    p.hy[i] = hn.y;
    p.hz[i] = hn.z;
    p.vx[i] += dh.x;
    p.vy[i] += dh.y;
    p.vz[i] += dh.z;
  }

  // Every rank's contacts, in order of particle id: their momentum taken from the vertices this rank owns.
  void give_to_vertices(StepContext& ctx, std::vector<double>& hits) {
    if (ctx.comm.distributed()) {
      std::vector<std::byte> bytes(hits.size() * sizeof(double));
      std::memcpy(bytes.data(), hits.data(), bytes.size());
      std::vector<std::byte> all = ctx.comm.gather(bytes);
      ctx.comm.broadcast(all);
      hits.resize(all.size() / sizeof(double));
      std::memcpy(hits.data(), all.data(), all.size());
    }
    if (hits.empty()) return;
    std::vector<std::size_t> order(hits.size() / kWidth);
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    // A particle's contacts stay in the order they happened (stable).
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return hits[a * kWidth] < hits[b * kWidth]; });
    std::fill(momentum_.begin(), momentum_.end(), Vec3{});
    for (std::size_t k : order) {
      const double* e = &hits[k * kWidth];
      const Vec3 dp{e[7], e[8], e[9]};
      for (int c = 0; c < 3; ++c) momentum_[static_cast<std::size_t>(e[1 + c])] += (-e[4 + c]) * dp;
    }
    ParticleData& p = ctx.particles;
    const std::uint32_t first = gather_.first(), end = first + static_cast<std::uint32_t>(momentum_.size());
    const auto n_local = static_cast<std::ptrdiff_t>(p.n_local);
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t k = 0; k < n_local; ++k) {
      const auto i = static_cast<std::size_t>(k);
      if (p.id[i] < first || p.id[i] >= end) continue;
      const Vec3 g = (1.0 / ctx.species_mass[static_cast<std::size_t>(p.species[i])]) * momentum_[p.id[i] - first];
      p.hx[i] += g.x;
      p.hy[i] += g.y;
      p.hz[i] += g.z;
      p.vx[i] += g.x;
      p.vy[i] += g.y;
      p.vz[i] += g.z;
    }
  }

  const std::vector<Cell>& cells_;
  std::vector<char> bounce_;
  Movers movers_;
  VertexGather gather_;
  std::vector<Vec3> momentum_;
  std::array<std::size_t, 3> bins_{1, 1, 1};
  std::array<double, 3> inv_width_{1, 1, 1};  // bins per unit length along each axis
  // Every triangle of every cell, in (cell, triangle) order: its cell, and its corners among the gathered
  // vertices.
  std::vector<std::uint32_t> cell_of_;
  std::vector<std::array<std::uint32_t, 3>> corners_;
  std::vector<std::size_t> counts_;     // bin_triangles' count per thread and bin (thread-major)
  std::vector<std::size_t> bin_start_;  // bin b's triangles: slot_boxes_[bin_start_[b] .. bin_start_[b + 1])
  std::vector<SlotBox> slot_boxes_;     // the triangles by bin, with their boxes of this step
  std::vector<Box3> swept_;              // each triangle's box over this step's move
  std::uint64_t bounces_ = 0, unresolved_ = 0;
};

// cells.csv: the shape of every cell every `every` steps; cells.gsd: the vertices of every cell at the
// same steps (the union over the blocks), with the edges as bonds, so OVITO or VMD draw the meshes (root
// writes both).
class CellOutputStage final : public Stage {
 public:
  CellOutputStage(const MembraneForcesStage& forces, std::shared_ptr<const std::vector<std::vector<std::uint32_t>>> inside, Movers movers,
                  std::vector<std::uint64_t> every, std::vector<int> axes, const std::filesystem::path& dir, bool append,
                  std::uint64_t start_step, std::vector<std::string> species_names, std::uint32_t first, std::uint32_t count)
      : forces_(forces), inside_(std::move(inside)), movers_(std::move(movers)), every_(std::move(every)), axes_(std::move(axes)),
        gather_(first, count), species_names_(std::move(species_names)) {
    Comm::world().on_root([&] {
      // A restart drops the rows after its step (left by the run that went on past its checkpoint) and
      // appends; a header is written when there is no earlier file to continue.
      const auto csv = dir / "cells.csv";
      if (append && std::filesystem::exists(csv)) trim_csv_after_step(csv, start_step);
      const bool resume = append && std::filesystem::exists(csv) && std::filesystem::file_size(csv) > 0;
      file_.open(csv, resume ? OutputFile::Mode::Append : OutputFile::Mode::Truncate);
      if (!resume) file_ << "step,cell,cx,cy,cz,axial,transverse,area,volume,asphericity,wrong_side\n";
      file_.flush();
      gsd_.emplace(dir / "cells.gsd", std::vector<std::string>{"id", "species", "position", "image"}, append,
                   append ? std::optional<std::uint64_t>(start_step) : std::nullopt);
    });
    for (const Cell& cell : forces_.cells()) {
      for (const membrane::Hinge& h : cell.model.hinges()) edges_.bonds.push_back({cell.first + h.b, cell.first + h.c, 0});
      species_.insert(species_.end(), cell.model.vertex_count(), static_cast<std::int32_t>(cell.species));
    }
    for (std::uint32_t k = 0; k < count; ++k) ids_.push_back(first + k);
  }
  void run(StepContext& ctx) override {
    bool any = false;
    for (std::uint64_t e : every_) any = any || (e > 0 && ctx.step % e == 0);
    if (!any) return;
    const std::vector<Vec3>& all = gather_.gather(ctx);
    const std::vector<std::vector<std::uint32_t>> now = inside_ids(ctx, forces_.cells(), all, gather_.first(), movers_);
    if (!ctx.comm.root()) return;
    for (std::size_t c = 0; c < forces_.cells().size(); ++c) {
      if (every_[c] == 0 || ctx.step % every_[c] != 0) continue;
      const Cell& cell = forces_.cells()[c];
      const std::size_t off = cell.first - gather_.first(), nv = cell.model.vertex_count();
      const std::vector<Vec3> x(all.begin() + static_cast<std::ptrdiff_t>(off), all.begin() + static_cast<std::ptrdiff_t>(off + nv));
      const membrane::Shape s = membrane::measure(cell.model.mesh(), x, axes_[c]);
      file_ << fmt::format("{},{},{:.8g},{:.8g},{:.8g},{:.8g},{:.8g},{:.8g},{:.8g},{:.6g},{}\n", ctx.step, c, s.centroid.x,
                           s.centroid.y, s.centroid.z, s.axial, s.transverse, s.area, s.volume, s.asphericity,
                           wrong_side((*inside_)[c], now[c]));
    }
    file_.flush();
    write_vertices(ctx, all);
  }

 private:

 public:
  // The particles in one sorted list and not the other.
  static std::size_t wrong_side(const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b) {
    std::vector<std::uint32_t> diff;
    std::set_symmetric_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(diff));
    return diff.size();
  }


 private:
  // One cells.gsd frame: the unwrapped vertices split into wrapped positions and image counters.
  void write_vertices(const StepContext& ctx, const std::vector<Vec3>& all) {
    const std::size_t n = all.size();
    x_.resize(n), y_.resize(n), z_.resize(n), ix_.resize(n), iy_.resize(n), iz_.resize(n);
    const auto wrap = [](double u, double len, double& w, std::int32_t& image) {
      const double k = std::floor(u / len);
      w = u - k * len;
      if (w >= len) w = 0;  // rounding of a value just below a period
      image = static_cast<std::int32_t>(k);
    };
    for (std::size_t i = 0; i < n; ++i) {
      wrap(all[i].x, ctx.box.len.x, x_[i], ix_[i]);
      wrap(all[i].y, ctx.box.len.y, y_[i], iy_[i]);
      wrap(all[i].z, ctx.box.len.z, z_[i], iz_[i]);
    }
    FrameView f;
    f.step = ctx.step;
    f.box_lo = {0, 0, 0};
    f.box_len = {ctx.box.len.x, ctx.box.len.y, ctx.box.len.z};
    f.periodic = {ctx.box.periodic[0], ctx.box.periodic[1], ctx.box.periodic[2]};
    f.n = n;
    f.id = ids_.data();
    f.species = species_.data();
    f.x = x_.data(), f.y = y_.data(), f.z = z_.data();
    f.ix = ix_.data(), f.iy = iy_.data(), f.iz = iz_.data();
    f.species_names = &species_names_;
    f.species_mass = &ctx.species_mass;
    f.topology = &edges_;
    f.bond_type_names = &kEdgeType;
    gsd_->write_frame(f);
  }

  inline static const std::vector<std::string> kEdgeType{"edge"};
  const MembraneForcesStage& forces_;
  std::shared_ptr<const std::vector<std::vector<std::uint32_t>>> inside_;
  Movers movers_;
  std::vector<std::uint64_t> every_;
  std::vector<int> axes_;
  VertexGather gather_;
  OutputFile file_;
  std::optional<GsdWriter> gsd_;
  std::vector<std::string> species_names_;
  Topology edges_;                  // every cell's edges, by vertex id
  std::vector<std::uint32_t> ids_;  // first .. first + count - 1
  std::vector<std::int32_t> species_;
  std::vector<double> x_, y_, z_;
  std::vector<std::int32_t> ix_, iy_, iz_;
};

std::vector<PlacedParticle> place_membranes(const SimulationSpec& spec) {
  const auto* list = spec.model<std::vector<MembraneSpec>>("membrane");
  std::vector<PlacedParticle> out;
  if (!list) return out;
  std::int32_t mol = 0;
  for (const MoleculeSpec& m : spec.molecules) mol += static_cast<std::int32_t>(m.count);
  for (const PlacedCell& pc : all_cells(*list, spec)) {
    const MembraneSpec& c = (*list)[pc.block];
    const std::string key = fmt::format("membrane[{}]", pc.block);
    const int species = species_of(c, spec, key);
    ++mol;
    for (const Vec3& p : cell_mesh(c, spec, key, pc.at).vertices) out.push_back({species, {p.x, p.y, p.z}, mol});
  }
  return out;
}

}  // namespace

ModelSection membrane_section() {
  return model_list_section(membrane_keys(), check_membranes, "species = \"M\"\ndiameter = 7.82\ncenter = [10, 10, 10]");
}

std::vector<PlacedParticle> membrane_particles(const SimulationSpec& spec) { return place_membranes(spec); }

void install_membrane(Installation& in) {
  const auto* list = in.spec.model<std::vector<MembraneSpec>>("membrane");
  if (!list || list->empty()) return;
  const std::uint32_t first = first_placed_id(in.spec, "membrane");
  std::vector<Cell> cells;
  std::uint32_t next = first;
  std::vector<std::uint64_t> every;
  std::vector<int> axes;
  std::vector<char> bounce;
  std::vector<std::size_t> block_of;  // per cell
  std::vector<double> mean_length(list->size(), -1.0);  // per block: every cell of a block has the same mesh
  for (const PlacedCell& pc : all_cells(*list, in.spec)) {
    const MembraneSpec& c = (*list)[pc.block];
    const std::string key = fmt::format("membrane[{}]", pc.block);
    membrane::Mesh mesh = cell_mesh(c, in.spec, key, pc.at);
    if (mean_length[pc.block] < 0) mean_length[pc.block] = membrane::CellModel(mesh, membrane::Parameters{}, nullptr, key).mean_length();
    membrane::CellModel model(mesh, cell_parameters(c, in.spec, mean_length[pc.block]), nullptr, key);
    const std::size_t nv = model.vertex_count();
    std::vector<Vec3> external = membrane::tweezers(mesh, c.tweezers_force, c.tweezers_fraction, c.tweezers_axis);
    cells.push_back({std::move(model), next, std::move(external), c.tweezers_ramp,
                     static_cast<std::size_t>(species_of(c, in.spec, key)), pc.block, c.repulsion, c.repulsion_range});
    next += static_cast<std::uint32_t>(nv);
    every.push_back(c.output_every);
    axes.push_back(c.tweezers_axis);
    bounce.push_back(c.bounce ? 1 : 0);
    block_of.push_back(pc.block);
  }
  const std::uint32_t count = next - first;
  auto& stage = in.stages.add(StagePoint::Forces, std::make_unique<MembraneForcesStage>(std::move(cells), first, count, in.spec.seed));
  Movers movers{{}, first, count};
  for (const SpeciesSpec& sp : in.spec.species) movers.frozen.push_back(sp.frozen ? 1 : 0);
  // The inner fluids of a new run, then who is inside each cell at the start (the reference of the
  // wrong-side count).
  StepContext ctx = in.context();
  VertexGather gather(first, count);
  const std::vector<Vec3>& vertices = gather.gather(ctx);
  std::vector<std::vector<std::uint32_t>> start;
  if (!in.restarted) {
    start = inside_ids(ctx, stage.cells(), vertices, first, movers);
    ParticleData& p = ctx.particles;
    for (std::size_t k = 0; k < block_of.size(); ++k) {
      const MembraneSpec& c = (*list)[block_of[k]];
      if (c.inner_species.empty()) continue;
      const int inner = inner_species_of(c, in.spec, fmt::format("membrane[{}]", block_of[k]));
      for (std::size_t i = 0; i < p.n_local; ++i)
        if (p.mol[i] == 0 && movers(p, i) && std::binary_search(start[k].begin(), start[k].end(), p.id[i])) p.species[i] = inner;
    }
  }
  // Relabelling moves no particle: in a new run the start is the reference.
  auto inside = std::make_shared<const std::vector<std::vector<std::uint32_t>>>(
      in.restarted ? inside_ids(ctx, stage.cells(), vertices, first, movers) : std::move(start));
  MembraneBounceStage* bouncer = nullptr;
  if (std::any_of(bounce.begin(), bounce.end(), [](char b) { return b != 0; }))
    bouncer = &in.stages.add(StagePoint::AfterFirstHalf, std::make_unique<MembraneBounceStage>(stage.cells(), bounce, movers, first, count));
  // The cells' elastic energy (bonds, bending, area and volume terms) at the last force evaluation, in
  // thermo.csv: with kinetic_energy (and potential_energy for the pair forces) the energy a run without
  // friction conserves (tests/membrane: membrane_energy_conserved).
  in.thermo_columns.push_back({"membrane_energy", [&stage](const StepContext&) { return stage.energy(); }});
  in.summaries.push_back([&stage, bouncer, inside, movers, first, count](const StepContext& c) {
    std::uint64_t n[2] = {bouncer ? bouncer->bounces() : 0, bouncer ? bouncer->unresolved() : 0};
    c.comm.sum(std::span<std::uint64_t>(n, 2));
    VertexGather g(first, count);
    const std::vector<std::vector<std::uint32_t>> now = inside_ids(c, stage.cells(), g.gather(c), first, movers);
    std::size_t wrong = 0;
    for (std::size_t k = 0; k < now.size(); ++k) wrong += CellOutputStage::wrong_side((*inside)[k], now[k]);
    std::size_t in_cells = 0;
    for (const auto& ids : now) in_cells += ids.size();
    return c.comm.root() ? fmt::format("membranes: {} bounce-backs on the cells' triangles this run ({} paths with 4 "
                                       "contacts in one step, the most tested); {} particles inside cells, {} of them or "
                                       "others on the wrong side of a membrane (target 0)\n",
                                       n[0], n[1], in_cells, wrong)
                         : std::string();
  });
  if (!in.options.out_dir.empty() && std::any_of(every.begin(), every.end(), [](std::uint64_t e) { return e > 0; })) {
    std::vector<std::string> names;
    for (const SpeciesSpec& sp : in.spec.species) names.push_back(sp.name);
    in.stages.add(StagePoint::EndOfStep, std::make_unique<CellOutputStage>(stage, inside, movers, std::move(every), std::move(axes),
                                                                           in.options.out_dir, in.restarted, ctx.step,
                                                                           std::move(names), first, count));
  }
}

}  // namespace mesodpd
