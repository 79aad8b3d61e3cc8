// [[membrane]]: closed elastic membranes (red cells, vesicles) whose vertices are particles of the run
// (membrane/membrane_forces.hpp has the forces). Each block is one cell: its mesh is generated or read,
// placed at `center` (Model::place gives its vertices ids after the molecules), and a Forces stage adds
// the membrane forces to its vertices every step. The stage gathers the vertices of every cell in id
// order (under MPI every rank receives all of them), evaluates each cell whole, in mesh order, and adds
// the forces to the vertices it owns: the result does not depend on thread or rank count.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/blow_up_error.hpp"
#include "engine/initial_state.hpp"
#include "engine/installer.hpp"
#include "engine/simulation.hpp"
#include "io/output_file.hpp"
#include "parallel/comm.hpp"
#include "membrane/membrane_forces.hpp"
#include "membrane/mesh.hpp"
#include "mesodpd/config_error.hpp"
#include "mesodpd/key_table.hpp"
#include "mesodpd/model_section.hpp"

namespace mesodpd {

enum class MeshKind { RedCell, Sphere, File };
enum class BendingKind { None, KantorNelson, Juelicher };

struct MembraneSpec {
  std::string species;
  MeshKind mesh = MeshKind::RedCell;
  std::string file;
  std::uint64_t vertices = 500;
  double diameter = 0;
  std::array<double, 3> center{0, 0, 0};
  int axis = 2;
  double shear_modulus = 0, persistence = 0;
  double x0 = 1.0 / 2.2, m = 2.0;
  bool stress_free = true;
  BendingKind bending = BendingKind::None;
  double kb = 0, theta0_deg = 0, kappa = 0;
  double ka = 0, kd = 0, kv = 0, area0 = 0, volume0 = 0;
  double gamma_t = 0, gamma_c = 0, viscosity = 0;
  double tweezers_force = 0, tweezers_fraction = 0.02;
  int tweezers_axis = 0;
  std::uint64_t tweezers_ramp = 0;
  std::uint64_t output_every = 0;
};

namespace {

const keys::KeyTable<MembraneSpec>& membrane_keys() {
  using T = MembraneSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("membrane");
    t.string("species", &T::species, "The species of the cell's vertices: a mobile species with no `density` or `count` of its own (its particles are the vertices). Its pair parameters with the fluid set how the membrane and the solvent interact.")
        .required("(a [[species]] name)");
    t.choice("mesh", &T::mesh, {{"red_cell", MeshKind::RedCell}, {"sphere", MeshKind::Sphere}, {"file", MeshKind::File}}, "`red_cell`: the Evans-Fung biconcave shape (Evans & Fung 1972) of `diameter`, its axis along `axis`; `sphere`: a geodesic sphere of `diameter`; `file`: the closed triangle mesh of an OFF file (`file`), used as it is, moved to `center`. The generated meshes have 10 n^2 + 2 vertices, n chosen to come nearest `vertices` (500 -> 492, 1000 -> 1002, 3000 -> 2892). The mesh is also the stress-free reference shape (`stress_free`).")
        .default_text("\"red_cell\"");
    t.string("file", &T::file, "The OFF file of `mesh = \"file\"` (triangles only, closed, consistently oriented; inward-facing files are turned round).");
    t.integer("vertices", &T::vertices, {4, 200000}, "Vertex count wanted for a generated mesh.").default_text("500");
    t.number("diameter", &T::diameter, keys::kNonNegative, "Diameter of a generated mesh (7.82 um for a human red cell).");
    t.vec3("center", &T::center, keys::kFinite, "Where the cell's centroid starts (the mesh's centre of its vertices).")
        .required("(a position, e.g. [16, 16, 16])");
    t.choice("axis", &T::axis, {{"x", 0}, {"y", 1}, {"z", 2}}, "The red cell's symmetry axis.").default_text("\"z\"");
    t.number("shear_modulus", &T::shear_modulus, keys::kNonNegative, "The linear shear modulus mu0 of the WLC-POW network; sets `persistence` through the analytic modulus at the mesh's mean edge length (Fedosov et al., Biophys. J. 98, 2215 (2010); docs/physics.md). Give this or `persistence`.");
    t.number("persistence", &T::persistence, keys::kNonNegative, "The WLC persistence length p (energy scale `system.kT`). Give this or `shear_modulus`; neither: no in-plane elasticity.");
    t.number("x0", &T::x0, {0.0, 1.0, false, false}, "l0 / l_max: each edge breaks at l0 / x0 (the run stops, naming the cell and the vertex ids).").default_text("1/2.2");
    t.number("m", &T::m, {0.0, 10.0, false, true}, "Exponent of the power-law repulsion k_p / l^m.").default_text("2");
    t.boolean("stress_free", &T::stress_free, "Per-edge rest lengths and per-triangle rest areas from the initial mesh (true), or the mean edge length and the mean triangle area for all (false).");
    t.choice("bending", &T::bending, {{"none", BendingKind::None}, {"kantor-nelson", BendingKind::KantorNelson}, {"juelicher", BendingKind::Juelicher}}, "`kantor-nelson`: U = kb [1 - cos(theta - theta0)] per edge; `juelicher`: U = 2 kappa sum_i M_i^2 / A_i (8 pi kappa for a sphere).")
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
    t.number("tweezers_force", &T::tweezers_force, keys::kNonNegative, "Optical-tweezers stretching (Mills et al. 2004): a total force +F along `tweezers_axis` spread over the `tweezers_fraction` of the vertices farthest along it in the initial mesh, -F over the same fraction at the other end.");
    t.number("tweezers_fraction", &T::tweezers_fraction, {0.0, 0.5, false, true}, "The gripped fraction of the vertices at each end.").default_text("0.02");
    t.choice("tweezers_axis", &T::tweezers_axis, {{"x", 0}, {"y", 1}, {"z", 2}}, "The stretching direction.").default_text("\"x\"");
    t.integer("tweezers_ramp", &T::tweezers_ramp, {0, 1000000000}, "The tweezers force grows linearly from 0 at step 0 to `tweezers_force` at this step (a sudden pull of the few gripped vertices would tear their edges).").default_text("0 (at once)");
    t.integer("output_every", &T::output_every, {0, 1000000000}, "Write cells.csv (step, cell, centroid, axial and transverse diameters along/across `tweezers_axis`, area, volume, asphericity, membrane energy) every this many steps; 0: never.").default_text("0");
    return t;
  }();
  return table;
}

int species_of(const MembraneSpec& c, const SimulationSpec& spec, const std::string& key) {
  for (std::size_t s = 0; s < spec.species.size(); ++s)
    if (spec.species[s].name == c.species) {
      const SpeciesSpec& sp = spec.species[s];
      if (sp.frozen) keys::fail(key + ".species", "\"" + c.species + "\"", "a frozen species is not integrated");
      if (sp.count > 0) keys::fail(key + ".species", "\"" + c.species + "\"", "the species has particles of its own (density or count); give the vertices a species of their own");
      return static_cast<int>(s);
    }
  keys::fail(key + ".species", "\"" + c.species + "\"", "no [[species]] of that name");
  return -1;
}

// The cell's mesh, placed: generated or read, the red cell turned to its axis, moved to `center`.
membrane::Mesh cell_mesh(const MembraneSpec& c, const std::string& key) {
  membrane::Mesh m;
  try {
    if (c.mesh == MeshKind::File) {
      m = membrane::read_off(c.file);
    } else {
      const int n = membrane::frequency_for(c.vertices);
      m = c.mesh == MeshKind::Sphere ? membrane::geodesic_sphere(n, c.diameter / 2) : membrane::red_cell(n, c.diameter);
      if (c.axis != 2)
        for (Vec3& p : m.vertices) p = c.axis == 0 ? Vec3{p.z, p.x, p.y} : Vec3{p.y, p.z, p.x};
    }
  } catch (const membrane::MeshError& e) {
    throw ConfigError(fmt::format("{}: {}", key, e.what()), key + (c.mesh == MeshKind::File ? ".file" : ".mesh"));
  }
  Vec3 mean;
  for (const Vec3& p : m.vertices) mean += p;
  mean = (1.0 / static_cast<double>(m.vertices.size())) * mean;
  for (Vec3& p : m.vertices) p = p - mean + Vec3{c.center[0], c.center[1], c.center[2]};
  return m;
}

membrane::Parameters cell_parameters(const MembraneSpec& c, double kT, double mean_length) {
  membrane::Parameters p;
  p.kT = kT;
  p.x0 = c.x0;
  p.m = c.m;
  p.stress_free = c.stress_free;
  p.persistence = c.persistence > 0 ? c.persistence
                  : c.shear_modulus > 0 ? membrane::persistence_for(c.shear_modulus, mean_length, c.x0, kT, c.m)
                                        : 0.0;
  p.bending = c.bending == BendingKind::KantorNelson ? membrane::Bending::KantorNelson
              : c.bending == BendingKind::Juelicher  ? membrane::Bending::Juelicher
                                                     : membrane::Bending::None;
  p.kb = c.kb;
  p.theta0 = c.theta0_deg * std::numbers::pi / 180.0;
  p.kappa = c.kappa;
  p.ka = c.ka;
  p.kd = c.kd;
  p.kv = c.kv;
  p.area0 = c.area0;
  p.volume0 = c.volume0;
  if (c.viscosity > 0) {
    p.gamma_t = 12.0 * c.viscosity / (13.0 * std::sqrt(3.0));
    p.gamma_c = p.gamma_t / 3.0;
  } else {
    p.gamma_t = c.gamma_t;
    p.gamma_c = c.gamma_c;
  }
  return p;
}

void check_membranes(const std::vector<MembraneSpec>& list, const SimulationSpec& spec) {
  for (std::size_t k = 0; k < list.size(); ++k) {
    const MembraneSpec& c = list[k];
    const std::string key = fmt::format("membrane[{}]", k);
    species_of(c, spec, key);
    if (c.mesh == MeshKind::File && c.file.empty()) keys::fail(key + ".file", "(missing)", "mesh = \"file\" needs the OFF file");
    if (c.mesh != MeshKind::File && !(c.diameter > 0)) keys::fail(key + ".diameter", "(missing)", "a generated mesh needs its diameter");
    if (c.shear_modulus > 0 && c.persistence > 0)
      keys::fail(key + ".persistence", fmt::format("{}", c.persistence), "give shear_modulus or persistence, not both");
    if (c.viscosity > 0 && (c.gamma_t > 0 || c.gamma_c > 0))
      keys::fail(key + ".viscosity", fmt::format("{}", c.viscosity), "give viscosity or gamma_t and gamma_c, not both");
    if (3 * c.gamma_c < c.gamma_t)
      keys::fail(key + ".gamma_c", fmt::format("{}", c.gamma_c),
                 fmt::format("the random force needs 3 gamma_c >= gamma_t ({}): its amplitude is sqrt(3 gamma_c - gamma_t)", c.gamma_t));
    const membrane::Mesh m = cell_mesh(c, key);
    // A cell larger than the box would overlap its own images.
    for (int d = 0; d < 3; ++d) {
      double lo = 1e300, hi = -1e300;
      for (const Vec3& p : m.vertices) {
        const double v = d == 0 ? p.x : d == 1 ? p.y : p.z;
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
      if (hi - lo + 1.0 > spec.box[static_cast<std::size_t>(d)])
        keys::fail(key + ".diameter", fmt::format("{}", c.diameter),
                   fmt::format("the cell spans {} along {}, more than the box ({}) less one cutoff", hi - lo, "xyz"[d],
                               spec.box[static_cast<std::size_t>(d)]));
    }
  }
}

// Every cell's vertices, in id order, unwrapped, and where asked their velocities: (id, x, y, z[, vx, vy,
// vz]) gathered from the ranks that own them.
class VertexGather {
 public:
  VertexGather(std::uint32_t first, std::uint32_t count, bool velocities = false)
      : first_(first), count_(count), velocities_(velocities), x_(count), v_(velocities ? count : 0) {}
  const std::vector<Vec3>& gather(const StepContext& ctx) {
    const ParticleData& p = ctx.particles;
    const double lx = ctx.box.len.x, ly = ctx.box.len.y, lz = ctx.box.len.z;
    const std::size_t width = velocities_ ? 7 : 4;
    std::vector<double> mine;  // id, x, y, z[, vx, vy, vz] of the owned vertices
    std::size_t found = 0;
    for (std::size_t i = 0; i < p.n_local; ++i) {
      const std::uint32_t id = p.id[i];
      if (id < first_ || id >= first_ + count_) continue;
      const Vec3 r{p.x[i] + p.ix[i] * lx, p.y[i] + p.iy[i] * ly, p.z[i] + p.iz[i] * lz};
      if (ctx.comm.distributed()) {
        mine.insert(mine.end(), {static_cast<double>(id), r.x, r.y, r.z});
        if (velocities_) mine.insert(mine.end(), {p.vx[i], p.vy[i], p.vz[i]});
      } else {
        x_[id - first_] = r;
        if (velocities_) v_[id - first_] = {p.vx[i], p.vy[i], p.vz[i]};
      }
      ++found;
    }
    if (ctx.comm.distributed()) {
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
  std::uint32_t first_, count_;
  bool velocities_;
  std::vector<Vec3> x_, v_;
};

struct Cell {
  membrane::CellModel model;
  std::uint32_t first = 0;             // id of vertex 0
  std::vector<Vec3> external;          // tweezers force per vertex (at full strength)
  std::uint64_t ramp = 0;              // steps over which it grows from 0
};

class MembraneForcesStage final : public Stage {
 public:
  MembraneForcesStage(std::vector<Cell> cells, std::uint32_t first, std::uint32_t count, std::uint64_t seed)
      : cells_(std::move(cells)),
        gather_(first, count, std::any_of(cells_.begin(), cells_.end(), [](const Cell& c) { return c.model.viscous(); })),
        seed_(seed) {}
  void run(StepContext& ctx) override {
    const std::vector<Vec3>& all = gather_.gather(ctx);
    forces_.assign(all.size(), Vec3{});
    std::vector<Vec3> x, v, f;
    energy_ = 0;
    for (std::size_t c = 0; c < cells_.size(); ++c) {
      const Cell& cell = cells_[c];
      const std::size_t nv = cell.model.vertex_count(), off = cell.first - gather_.first();
      x.assign(all.begin() + static_cast<std::ptrdiff_t>(off), all.begin() + static_cast<std::ptrdiff_t>(off + nv));
      f.assign(nv, Vec3{});
      std::size_t broken = 0;
      const auto e = cell.model.forces(x, f, &broken);
      if (!e) {
        const membrane::Hinge& h = cell.model.hinges()[broken];
        const double l = std::sqrt(dot(x[h.c] - x[h.b], x[h.c] - x[h.b]));
        throw BlowUpError(ctx.step, cell.first + h.b,
                          fmt::format("step {}: membrane[{}]: the edge between vertices {} and {} (particle ids {} and {}) is "
                                      "{:.6g} long, at or past its maximum {:.6g} (l0 / x0), where the WLC force is infinite; "
                                      "lower the time step or the forces on the cell, or raise membrane[{}].x0's room",
                                      ctx.step, c, h.b, h.c, cell.first + h.b, cell.first + h.c, l, cell.model.max_length(broken), c));
      }
      energy_ += e->total();
      if (cell.model.viscous()) {
        const std::vector<Vec3>& vel = gather_.velocities();
        v.assign(vel.begin() + static_cast<std::ptrdiff_t>(off), vel.begin() + static_cast<std::ptrdiff_t>(off + nv));
        cell.model.viscous_forces(x, v, ctx.dt, seed_, ctx.step, cell.first, f);
      }
      const double share = cell.ramp > ctx.step ? static_cast<double>(ctx.step) / static_cast<double>(cell.ramp) : 1.0;
      for (std::size_t i = 0; i < nv; ++i) forces_[off + i] = f[i] + share * cell.external[i];
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
  std::vector<Vec3> forces_;
  double energy_ = 0;
};

// cells.csv: the shape of every cell every `every` steps (root writes).
class CellOutputStage final : public Stage {
 public:
  CellOutputStage(const MembraneForcesStage& forces, std::vector<std::uint64_t> every, std::vector<int> axes,
                  std::filesystem::path path, bool append, std::uint32_t first, std::uint32_t count)
      : forces_(forces), every_(std::move(every)), axes_(std::move(axes)), gather_(first, count) {
    Comm::world().on_root([&] {
      file_.open(path, append ? OutputFile::Mode::Append : OutputFile::Mode::Truncate);
      if (!append) file_ << "step,cell,cx,cy,cz,axial,transverse,area,volume,asphericity\n";
      file_.flush();
    });
  }
  void run(StepContext& ctx) override {
    bool any = false;
    for (std::uint64_t e : every_) any = any || (e > 0 && ctx.step % e == 0);
    if (!any) return;
    const std::vector<Vec3>& all = gather_.gather(ctx);
    if (!ctx.comm.root()) return;
    for (std::size_t c = 0; c < forces_.cells().size(); ++c) {
      if (every_[c] == 0 || ctx.step % every_[c] != 0) continue;
      const Cell& cell = forces_.cells()[c];
      const std::size_t off = cell.first - gather_.first(), nv = cell.model.vertex_count();
      const std::vector<Vec3> x(all.begin() + static_cast<std::ptrdiff_t>(off), all.begin() + static_cast<std::ptrdiff_t>(off + nv));
      const membrane::Shape s = membrane::measure(cell.model.mesh(), x, axes_[c]);
      file_ << fmt::format("{},{},{:.8g},{:.8g},{:.8g},{:.8g},{:.8g},{:.8g},{:.8g},{:.6g}\n", ctx.step, c, s.centroid.x,
                           s.centroid.y, s.centroid.z, s.axial, s.transverse, s.area, s.volume, s.asphericity);
    }
    file_.flush();
  }

 private:
  const MembraneForcesStage& forces_;
  std::vector<std::uint64_t> every_;
  std::vector<int> axes_;
  VertexGather gather_;
  OutputFile file_;
};

std::vector<PlacedParticle> place_membranes(const SimulationSpec& spec) {
  const auto* list = spec.model<std::vector<MembraneSpec>>("membrane");
  std::vector<PlacedParticle> out;
  if (!list) return out;
  std::int32_t mol = 0;
  for (const MoleculeSpec& m : spec.molecules) mol += static_cast<std::int32_t>(m.count);
  for (std::size_t k = 0; k < list->size(); ++k) {
    const MembraneSpec& c = (*list)[k];
    const std::string key = fmt::format("membrane[{}]", k);
    const int species = species_of(c, spec, key);
    ++mol;
    for (const Vec3& p : cell_mesh(c, key).vertices) out.push_back({species, {p.x, p.y, p.z}, mol});
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
  for (std::size_t k = 0; k < list->size(); ++k) {
    const MembraneSpec& c = (*list)[k];
    const std::string key = fmt::format("membrane[{}]", k);
    membrane::Mesh mesh = cell_mesh(c, key);
    const membrane::CellModel probe(mesh, membrane::Parameters{}, nullptr, key);
    membrane::CellModel model(mesh, cell_parameters(c, in.spec.kT, probe.mean_length()), nullptr, key);
    const std::size_t nv = model.vertex_count();
    std::vector<Vec3> external = membrane::tweezers(mesh, c.tweezers_force, c.tweezers_fraction, c.tweezers_axis);
    cells.push_back({std::move(model), next, std::move(external), c.tweezers_ramp});
    next += static_cast<std::uint32_t>(nv);
    every.push_back(c.output_every);
    axes.push_back(c.tweezers_axis);
  }
  const std::uint32_t count = next - first;
  auto& stage = in.stages.add(StagePoint::Forces, std::make_unique<MembraneForcesStage>(std::move(cells), first, count, in.spec.seed));
  if (!in.options.out_dir.empty() && std::any_of(every.begin(), every.end(), [](std::uint64_t e) { return e > 0; }))
    in.stages.add(StagePoint::EndOfStep, std::make_unique<CellOutputStage>(stage, std::move(every), std::move(axes),
                                                                           in.options.out_dir / "cells.csv",
                                                                           in.restarted, first, count));
}

}  // namespace mesodpd
