// [[body]]: a [[solid]] that moves as a rigid body (engine/rigid_bodies.hpp). The installer takes the
// solid away from the fixed walls (ReleasedSolids, before the walls are installed), attaches the solid's
// frozen particles to the body in a new run, and adds two stages: the body's half kick, drift and the
// fluid's bounce-back right after the particles move (AfterFirstHalf), and its new force and second half
// kick after the forces (AfterSecondHalf). bodies.csv has each body's position, orientation, velocities,
// force and torque; a thermo column counts the bounce-backs, the end-of-run summary the fluid particles
// found inside a body (target 0).
#include <algorithm>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "boundary/walls.hpp"
#include "engine/installer.hpp"
#include "engine/pair_laws.hpp"
#include "engine/lees_edwards_spec.hpp"
#include "engine/rigid_bodies.hpp"
#include "engine/simulation.hpp"
#include "io/byte_buffer.hpp"
#include "io/frame.hpp"
#include "io/gsd_writer.hpp"
#include "io/output_file.hpp"
#include "mesodpd/config_error.hpp"
#include "mesodpd/key_table.hpp"
#include "mesodpd/model_section.hpp"
#include "parallel/comm.hpp"

namespace mesodpd {

namespace {

const keys::KeyTable<BodySpec>& body_keys() {
  using T = BodySpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("body");
    t.string("solid", &T::solid,
             "The `[[solid]]` (by `name`) that moves as this rigid body: a sphere, a box, or a union or difference of "
             "them, made of a frozen species. Its frozen particles (the fluid frozen inside it, `walls.depth` deep) "
             "move with it; the fixed walls no longer reflect at its surface, the body bounces the fluid back itself "
             "(relative to the surface's own velocity V + Omega x r), and it turns and moves under the pair forces "
             "on its particles. At most one body per solid.")
        .required("(a [[solid]] name)");
    t.choice("motion", &T::motion, {{"free", BodyMotion::Free}, {"towed", BodyMotion::Towed}},
             "`free`: the body moves under the forces and torques (pair forces on its particles, the fluid's "
             "bounce-back, `force`, `torque`, contacts), starting at `velocity` and `angular_velocity`; `towed`: "
             "it moves at `velocity` and turns at `angular_velocity` whatever the forces, which bodies.csv then "
             "reports (the drag and the torque of a towed or rotated sphere).")
        .default_text("\"free\"");
    t.vec3("velocity", &T::velocity, keys::kFinite,
           "Velocity of the centre of mass: at the start (free) or always (towed).");
    t.vec3("angular_velocity", &T::angular_velocity, keys::kFinite,
           "Angular velocity about the centre of mass (lab frame): at the start (free) or always (towed).");
    t.vec3("force", &T::force, keys::kFinite, "A constant external force on a free body (sedimentation).");
    t.vec3("torque", &T::torque, keys::kFinite, "A constant external torque on a free body (lab frame).");
    t.number("density", &T::density, keys::kNonNegative,
             "Mass density of the body: its mass is density x volume and its inertia tensor that of a uniform "
             "solid (exact for a sphere, on a grid of ~100 cells along the longest side otherwise). 0 (the default) "
             "means the fluid's mass density (the mobile species' masses over the box volume): a neutrally buoyant "
             "body.");
    t.number("repulsion", &T::repulsion, keys::kNonNegative,
             "Contact repulsion: each of the body's particles within `repulsion_range` of its surface that comes "
             "within `repulsion_range` of another body's surface or of a fixed wall is pushed out along that "
             "surface's normal by repulsion x (1 - gap / repulsion_range), and the other body takes the opposite "
             "force. 0: bodies pass through each other.")
        .default_text("50");
    t.number("repulsion_range", &T::repulsion_range, {0.0, 10.0, false, true},
             "Gap at which the contact repulsion starts; also the depth of the body's surface shell whose "
             "particles feel it.")
        .default_text("0.5");
    t.integer("output_every", &T::output_every, {0, 1000000000},
              "Steps between this body's rows of bodies.csv (0: none).")
        .default_text("100");
    return t;
  }();
  return table;
}

void check_bodies(const std::vector<BodySpec>& list, const SimulationSpec& spec) {
  if (list.empty()) return;
  const LeesEdwardsSpec* le = spec.model<LeesEdwardsSpec>("lees_edwards");
  if (spec.walls.adaptive)
    keys::fail("walls.adaptive", "true", "the adaptive wall force does not work with [[body]] rigid bodies yet");
  if (spec.bond_subcycles > 1)
    keys::fail("bonds.subcycles", std::to_string(spec.bond_subcycles), "[[body]] rigid bodies need bonds.subcycles = 1");
  // Single-particle DPD's rotational friction would see the body's particles as not spinning (their
  // spins do not follow the body's rotation), and the law's torques on them would not reach the body.
  if (pair_law(spec.pair_style).style == SpdpdLaw::kStyle)
    keys::fail("pair.style", std::string(SpdpdLaw::kStyle),
               "[[body]] rigid bodies do not work with single-particle DPD yet (the body's particles would not spin "
               "with it, and the law's torques on them would not reach it); use pair.style = \"dpd\", or sp-DPD "
               "colloids without [[body]] (examples/colloids/brownian.toml)");
  std::vector<std::string> used;
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string key = fmt::format("body[{}]", k);
    const BodySpec& b = list[k];
    const auto it = std::find_if(spec.solids.begin(), spec.solids.end(), [&](const SolidSpec& s) { return s.name == b.solid; });
    if (it == spec.solids.end()) keys::fail(key + ".solid", b.solid, "no [[solid]] has this name");
    if (std::find(used.begin(), used.end(), b.solid) != used.end())
      keys::fail(key + ".solid", b.solid, "another [[body]] already moves this solid");
    used.push_back(b.solid);
    mass_properties(it->shape, fmt::format("{}.solid ('{}')", key, b.solid));  // refuses unbounded shapes
    const bool towed = b.motion == BodyMotion::Towed;
    if (towed && le && b.velocity[static_cast<std::size_t>(le->gradient)] != 0.0)
      keys::fail(key + ".velocity", "",
                 "a towed body may not move along the Lees-Edwards gradient axis: it would cross the sheared faces, "
                 "where the image frame moves, and keep the velocity of the frame it left");
    if (towed && (b.force != std::array<double, 3>{0, 0, 0} || b.torque != std::array<double, 3>{0, 0, 0}))
      keys::fail(key + (b.force != std::array<double, 3>{0, 0, 0} ? ".force" : ".torque"), "",
                 "a towed body moves as prescribed: an external force or torque would do nothing");
  }
}

// bodies.csv: every body's state at the steps its output_every divides; bodies.gsd: all bodies at those
// steps, one particle per body (typed by its solid's name) with its centre, velocity, image, orientation
// and the diameter of its bounding sphere, so OVITO draws them (root writes both; the state is the same
// on every rank).
class BodyOutputStage final : public Stage {
 public:
  BodyOutputStage(const RigidBodies& bodies, const std::filesystem::path& dir, bool append, std::uint64_t start_step,
                  const Box& box)
      : bodies_(bodies), box_(box) {
    for (std::size_t k = 0; k < bodies_.size(); ++k) names_.push_back(bodies_.name(k));
    Comm::world().on_root([&] {
      gsd_.emplace(dir / "bodies.gsd", std::vector<std::string>{"id", "species", "position", "velocity", "image"}, append,
                   append ? std::optional<std::uint64_t>(start_step) : std::nullopt);
      const auto csv = dir / "bodies.csv";
      if (append && std::filesystem::exists(csv)) trim_csv_after_step(csv, start_step);
      const bool resume = append && std::filesystem::exists(csv) && std::filesystem::file_size(csv) > 0;
      file_.open(csv, resume ? OutputFile::Mode::Append : OutputFile::Mode::Truncate);
      if (!resume)
        file_ << "step,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz,fx,fy,fz,tx,ty,tz,sxx,syy,szz,sxy,sxz,syz\n";
      file_.flush();
    });
  }
  void run(StepContext& ctx) override {
    if (!ctx.comm.root()) return;
    bool any = false;
    for (std::size_t k = 0; k < bodies_.size(); ++k) {
      const std::uint64_t e = bodies_.spec(k).output_every;
      if (e == 0 || ctx.step % e != 0) continue;
      const BodyState& s = bodies_.state(k);
      const Vec3 w = bodies_.omega(k);
      const Sym6 st = bodies_.mean_stresslet(k);
      file_ << fmt::format("{},{},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},"
                           "{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},"
                           "{:.10g},{:.10g},{:.10g}\n",
                           ctx.step, k, s.x.x, s.x.y, s.x.z, s.q.w, s.q.x, s.q.y, s.q.z, s.v.x, s.v.y, s.v.z, w.x, w.y,
                           w.z, s.f.x + s.f_bounce.x, s.f.y + s.f_bounce.y, s.f.z + s.f_bounce.z, s.t.x + s.t_bounce.x,
                           s.t.y + s.t_bounce.y, s.t.z + s.t_bounce.z, st[0], st[1], st[2], st[3], st[4], st[5]);
      any = true;
    }
    if (!any) return;
    file_.flush();
    const std::size_t n = bodies_.size();
    std::vector<std::uint32_t> id(n);
    std::vector<std::int32_t> type(n), image(3 * n);
    std::vector<double> r(3 * n), v(3 * n), q(4 * n), diameter(n);
    for (std::size_t k = 0; k < n; ++k) {
      const BodyState& s = bodies_.state(k);
      id[k] = static_cast<std::uint32_t>(k);
      type[k] = static_cast<std::int32_t>(k);
      const double c[3] = {s.x.x, s.x.y, s.x.z}, u[3] = {s.v.x, s.v.y, s.v.z};
      for (int a = 0; a < 3; ++a) {
        double x = c[a];
        std::int32_t img = 0;
        if (box_.periodic[static_cast<std::size_t>(a)]) wrap_coordinate(x, img, box_.length(a));
        r[static_cast<std::size_t>(a) * n + k] = x;
        image[static_cast<std::size_t>(a) * n + k] = img;
        v[static_cast<std::size_t>(a) * n + k] = u[a];
      }
      const double w[4] = {s.q.w, s.q.x, s.q.y, s.q.z};
      for (std::size_t c4 = 0; c4 < 4; ++c4) q[4 * k + c4] = w[c4];
      diameter[k] = 2.0 * bodies_.radius(k);
    }
    FrameView f;
    f.step = ctx.step;
    f.box_len = {box_.len.x, box_.len.y, box_.len.z};
    f.periodic = box_.periodic;
    f.n = n;
    f.id = id.data();
    f.species = type.data();
    f.species_names = &names_;
    f.x = r.data();
    f.y = r.data() + n;
    f.z = r.data() + 2 * n;
    f.vx = v.data();
    f.vy = v.data() + n;
    f.vz = v.data() + 2 * n;
    f.ix = image.data();
    f.iy = image.data() + n;
    f.iz = image.data() + 2 * n;
    f.orientation = q.data();
    f.diameter = diameter.data();
    gsd_->write_frame(f);
  }

 private:
  const RigidBodies& bodies_;
  Box box_;
  std::vector<std::string> names_;
  OutputFile file_;
  std::optional<GsdWriter> gsd_;
};

}  // namespace

ModelSection body_section() {
  return model_list_section(body_keys(), check_bodies, "solid = \"ball\"");
}

void install_bodies(Installation& in) {
  const auto* list = in.spec.model<std::vector<BodySpec>>("body");
  if (!list || list->empty()) return;
  Simulation& sim = in.sim;
  RigidBodies& bodies = in.components.add(
      std::make_shared<RigidBodies>(*list, in.spec, sim.box(), in.spec.integrator == IntegratorKind::GrootWarren));
  in.components.add(std::make_shared<ReleasedSolids>(ReleasedSolids{bodies.released()}));
  if (!in.restarted) {
    StepContext ctx = in.context();
    bodies.attach(ctx);
  }
  in.stages.add(StagePoint::AfterFirstHalf, make_stage([&bodies](StepContext& ctx) { bodies.move(ctx); }));
  in.stages.add(StagePoint::AfterSecondHalf, make_stage([&bodies](StepContext& ctx) { bodies.kick(ctx); }));
  in.sections.push_back({"bodies", [&bodies](ByteWriter& w) { bodies.save(w); },
                         [&bodies](ByteReader& r, const std::string& context) { bodies.load(r, context); }});
  // Bounce-backs since the previous thermo row (as the walls' reflections; the mark is in the checkpoint,
  // so a restart's rows are the same as the uninterrupted run's).
  in.thermo_columns.push_back(
      {"body_bounces", [&bodies](const StepContext&) { return static_cast<double>(bodies.take_bounces_since_row()); }});
  in.summaries.push_back([&bodies](const StepContext& ctx) {
    const std::uint64_t n[1] = {bodies.bounces_this_run()};
    const std::uint64_t inside = bodies.inside(ctx);
    std::string text = fmt::format("bodies: {} bounce-backs at the bodies' surfaces this run; {} fluid particles inside a "
                                   "body at the end (target 0)\n",
                                   n[0], inside);
    for (std::size_t k = 0; k < bodies.size(); ++k) {
      const BodyState& s = bodies.state(k);
      const Vec3 w = bodies.omega(k);
      text += fmt::format("  body[{}] '{}': {} particles, mass {:.5g}, centre ({:.5g}, {:.5g}, {:.5g}), velocity ({:.4g}, {:.4g}, {:.4g}), "
                          "angular velocity ({:.4g}, {:.4g}, {:.4g}), force ({:.4g}, {:.4g}, {:.4g})\n",
                          k, bodies.name(k), bodies.particles(k), bodies.mass(k), s.x.x, s.x.y, s.x.z, s.v.x, s.v.y, s.v.z, w.x, w.y, w.z,
                          s.f.x + s.f_bounce.x, s.f.y + s.f_bounce.y, s.f.z + s.f_bounce.z);
    }
    return ctx.comm.root() ? text : std::string();
  });
  if (!in.options.out_dir.empty() &&
      std::any_of(list->begin(), list->end(), [](const BodySpec& b) { return b.output_every > 0; }))
    in.stages.add(StagePoint::EndOfStep,
                  std::make_unique<BodyOutputStage>(bodies, in.options.out_dir, in.restarted, in.context().step, sim.box()));
}

}  // namespace mesodpd
