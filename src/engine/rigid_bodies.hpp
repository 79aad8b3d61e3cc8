// Moving rigid bodies made of frozen particles ([[body]], issue 26): a [[solid]] of a bounded shape
// (sphere, box, or a union or difference of them) whose frozen particles move together as one rigid
// body. Per body the state is a centre of mass, an orientation quaternion, a velocity and an angular
// momentum; its force and torque are the pair forces on its particles (the fluid pushing on them), the
// momentum the bounce-back of fluid particles at its surface gives it, an external force and torque, and
// a short-range repulsion from the other bodies and from the fixed walls. The body is integrated by
// velocity Verlet (half kick, drift, half kick) alongside the fluid's modified velocity-Verlet, the
// rotation by a midpoint quaternion update at constant angular momentum (docs/physics.md, "Rigid
// bodies"). The state is the same on every rank: each rank sums the forces on the particles it owns in
// 2^32 fixed point and the sums are added over the ranks, so the result does not depend on thread or
// rank count.
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "boundary/geometry.hpp"
#include "core/box.hpp"
#include "core/stage.hpp"
#include "core/vec3.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

class ByteReader;
class ByteWriter;

// A unit quaternion w + x i + y j + z k: the rotation from the body frame to the lab frame.
struct Quat {
  double w = 1.0, x = 0.0, y = 0.0, z = 0.0;
};
Quat operator*(const Quat& a, const Quat& b);
// R(q) v, as v + 2 w (u x v) + 2 u x (u x v) with u the vector part.
inline Vec3 rotate(const Quat& q, const Vec3& v) {
  const Vec3 u{q.x, q.y, q.z};
  const Vec3 c = cross(u, v);
  return v + (2.0 * q.w) * c + 2.0 * cross(u, c);
}
// R(q)^T v.
inline Vec3 rotate_back(const Quat& q, const Vec3& v) { return rotate(Quat{q.w, -q.x, -q.y, -q.z}, v); }
// q turned further by the angle |omega| t about the lab-frame axis omega: exp(t omega / 2) q, normalised.
Quat turned(const Quat& q, const Vec3& omega, double t);
// The angular velocity R I^-1 R^T l of a body of orientation q, angular momentum l (lab frame) and inverse
// inertia tensor `inertia_inverse` (body frame, row-major).
Vec3 angular_velocity(const Quat& q, const Vec3& l, const std::array<double, 9>& inertia_inverse);
// The orientation after dt of free rotation at constant angular momentum l: turned at the angular
// velocity of the midpoint orientation (second order in dt; exact for a sphere).
Quat turn_free(const Quat& q, const Vec3& l, const std::array<double, 9>& inertia_inverse, double dt);

enum class BodyMotion { Free, Towed };

// One [[body]] block (engine/install_bodies.cpp has its keys).
struct BodySpec {
  std::string solid;                                // the [[solid]] that moves
  BodyMotion motion = BodyMotion::Free;             // free, or towed at velocity / angular_velocity
  std::array<double, 3> velocity{0, 0, 0};          // start (free) or prescribed (towed)
  std::array<double, 3> angular_velocity{0, 0, 0};  // start (free) or prescribed (towed), lab frame
  std::array<double, 3> force{0, 0, 0};             // external force on a free body
  std::array<double, 3> torque{0, 0, 0};            // external torque on a free body
  double density = 0.0;                             // mass density (0: the fluid's)
  double repulsion = 50.0;                          // contact force per surface point at zero gap
  double repulsion_range = 0.5;                     // gap at which the contact force vanishes
  std::uint64_t output_every = 100;                 // rows of bodies.csv (0: none)
};

// Volume, centre and inertia tensor (about the centre, per unit density; xx, xy, xz, yx, ..., zz) of a
// bounded shape, and the radius of the smallest sphere about the centre that holds it. Spheres exactly,
// other shapes on a grid of about 100 cells along the longest side. Throws ConfigError naming `key` for
// an unbounded shape (plane, cylinder, pillars, image) or an empty one.
struct MassProperties {
  double volume = 0.0;
  Vec3 center;
  std::array<double, 9> inertia{};
  double radius = 0.0;
};
MassProperties mass_properties(const ShapeSpec& shape, const std::string& key);

struct BodyState {
  Vec3 x;     // centre of mass, unwrapped (continuous across periodic faces)
  Quat q;     // orientation: body frame to lab frame (the identity at the start)
  Vec3 v;     // velocity of the centre of mass
  Vec3 l;     // angular momentum about the centre of mass, lab frame
  Vec3 f, t;  // force and torque of the last force evaluation (pair forces, external, contacts)
  // The bounce-backs' momentum and angular momentum of this step over dt (given to a free body at once,
  // so not in the kicks): the force on the body is f + f_bounce.
  Vec3 f_bounce, t_bounce;
};

// A symmetric tensor: xx, yy, zz, xy, xz, yz (the order of PairSums::virial).
using Sym6 = std::array<double, 6>;

class RigidBodies {
 public:
  // `bodies`: the [[body]] blocks, checked (each names a frozen [[solid]] of a bounded shape, none twice).
  // `half_velocity` as Walls's (modified velocity-Verlet keeps the physical velocity in p.h). `box` is the
  // simulation's own (its Lees-Edwards offset changes with time); it must outlive the bodies. Under steady
  // Lees-Edwards shear with lees_edwards.initial_profile a free body starts with the imposed flow at its
  // centre, V = rate (X_g - L_g/2) e_f, and half its vorticity, Omega = (rate/2) e_g x e_f, added to its
  // velocity and angular_velocity (oscillatory shear: its rate at t = 0). Under oscillatory shear each body
  // also feels the homogeneous-shear (SLLOD) force that the fluid's particles feel, summed over its mass:
  // M (d rate/dt) (X_g - L_g/2) along f and the torque (d rate/dt) (M2 e_g) x e_f (M2 = sum m a (x) a).
  RigidBodies(std::vector<BodySpec> bodies, const SimulationSpec& spec, const Box& box, bool half_velocity);

  // The solids moved here (by solid index): ReleasedSolids for the walls.
  std::vector<std::uint8_t> released() const;

  // New run (collective): each body particle's offset from its body's centre, from the particles' initial
  // positions; the particles' start velocities; refusals of bodies that overlap each other or a fixed
  // wall, or that hold no particle.
  void attach(StepContext& ctx);
  // AfterFirstHalf (collective): half kick with the last force, drift and turn, bounce-back of the fluid
  // particles found inside a body (their momentum change goes to the body), then the body particles'
  // positions and velocities.
  void move(StepContext& ctx);
  // AfterSecondHalf (collective): the new force and torque, the second half kick, the particles'
  // velocities. Where the step has pair sums, the bodies' share of the stress goes into their virial
  // (see stresslet()).
  void kick(StepContext& ctx);

  // The stresslet of body k at the last step: the symmetric first moment S = sum sym(a (x) F) of the forces
  // F the body takes at its points a (from its centre): the pair forces on its particles, the bounce-backs'
  // impulses over dt, and the contacts. A rigid body's particles do not carry the stress through it (no
  // forces act between them): the stress of a suspension is the fluid's plus n <S> (Batchelor, J. Fluid
  // Mech. 41, 545 (1970)), so kick() replaces the atomic virial of the forces on the body's particles by
  // the molecular one, W += -S + M (V - u) (x) (V - u) per body (u: the imposed Lees-Edwards flow at
  // its centre, else 0).
  const Sym6& stresslet(std::size_t k) const { return stresslet_[k]; }
  // The mean stresslet of body k over the steps since its previous bodies.csv row (output_every), this one
  // included.
  Sym6 mean_stresslet(std::size_t k) const;

  // Mobile local particles inside some body now, summed over ranks (collective; 0 after every move).
  std::uint64_t inside(const StepContext& ctx) const;
  // Bounce-backs since step 0 (all ranks; kept across a restart), and since the start of this run.
  std::uint64_t bounces() const { return bounces_; }
  std::uint64_t bounces_this_run() const { return bounces_ - bounces_at_start_; }
  // Bounce-backs since the previous call (thermo's rows; the mark is in the checkpoint, so a restart's rows
  // are the uninterrupted run's).
  std::uint64_t take_bounces_since_row() {
    const std::uint64_t n = bounces_ - bounces_at_row_;
    bounces_at_row_ = bounces_;
    return n;
  }

  std::size_t size() const { return specs_.size(); }
  const BodySpec& spec(std::size_t k) const { return specs_[k]; }
  const BodyState& state(std::size_t k) const { return state_[k]; }
  const std::string& name(std::size_t k) const { return names_[k]; }
  double mass(std::size_t k) const { return mass_[k]; }
  // The radius of the smallest sphere about body k's centre that holds its shape.
  double radius(std::size_t k) const { return radius_[k]; }
  // The frozen particles of body k.
  std::size_t particles(std::size_t k) const {
    return static_cast<std::size_t>(std::count(owner_.begin(), owner_.end(), static_cast<std::int32_t>(k)));
  }
  // Angular velocity of body k now (lab frame).
  Vec3 omega(std::size_t k) const { return omega_at(k, state_[k].q); }
  // Inertia tensor of body k in the lab frame now (row-major).
  std::array<double, 9> inertia(std::size_t k) const;

  // Checkpoint part: the states and the particles' offsets (the same on every rank; load on every rank).
  void save(ByteWriter& w) const;
  void load(ByteReader& r, const std::string& context);

 private:
  Vec3 omega_at(std::size_t k, const Quat& q) const;
  double body_sdf(std::size_t k, const Vec3& b) const { return shapes_[k]->sdf(origin_[k] + b); }
  Vec3 body_normal(std::size_t k, const Vec3& b) const { return shapes_[k]->normal(origin_[k] + b); }
  Vec3 wrapped_center(std::size_t k) const;
  // a - b at the nearest image (Lees-Edwards images included); `n` gets the image count of b along the
  // gradient axis: a's velocity relative to b's image is v_a - v_b - n dU e_f.
  Vec3 displacement(const Vec3& a, const Vec3& b, double* n = nullptr) const;
  // Index into ids_ of the body particle `id` (its offset and body), or -1 (ids_ is sorted).
  long find(std::uint32_t id) const;
  // find() of every local particle, kept for the storage order it was made for (ParticleData::generation).
  const std::vector<std::int32_t>& slots(const ParticleData& p);
  // The forces at time t (the oscillatory shear's homogeneous force depends on it).
  void compute_forces(const StepContext& ctx, double t);
  void add_contacts(std::vector<Vec3>& f, std::vector<Vec3>& t, std::vector<Sym6>& s) const;
  void bounce(StepContext& ctx);
  void place(StepContext& ctx, bool positions);
  void index_points();
  void check_box(std::uint64_t step) const;

  std::vector<BodySpec> specs_;
  std::vector<std::string> names_;
  std::vector<int> solid_of_;   // per body: its solid index
  std::vector<int> body_of_;    // per solid: its body, or -1
  std::vector<std::unique_ptr<Shape>> shapes_;  // per body, in the original lab frame (no images)
  std::vector<Vec3> origin_;    // per body: the centre of mass at the start, lab frame
  std::vector<double> mass_, radius_;
  std::vector<std::array<double, 9>> inertia_inverse_;  // body frame
  std::vector<std::array<double, 9>> inertia_body_;
  std::vector<BodyState> state_;
  const Box& box_;
  bool half_velocity_;
  std::vector<std::uint8_t> frozen_;
  std::vector<double> species_mass_;
  Geometry walls_;  // the fixed solids (the moving ones left out)
  // The body particles by id (sorted): their body and offset (body frame).
  std::vector<std::uint32_t> ids_;
  std::vector<std::int32_t> owner_;
  std::vector<Vec3> offset_;
  std::vector<std::vector<Vec3>> points_;  // per body: the offsets within repulsion_range of its surface
  std::vector<std::int32_t> index_of_id_;  // find(): by id up to the largest body particle's, -1 elsewhere
  std::vector<std::int32_t> slot_;         // slots(): per local particle
  std::uint64_t slot_generation_ = 0;
  std::size_t slot_count_ = 0;
  bool ready_ = false;          // offsets known (attach() or load())
  bool forces_known_ = false;   // state_.f, t hold the last force evaluation's
  std::uint64_t bounces_ = 0, bounces_at_row_ = 0, bounces_at_start_ = 0;
  std::vector<Sym6> stresslet_;         // per body, the last step's (pairs, contacts and bounce-backs)
  std::vector<Sym6> bounce_stresslet_;  // per body, this step's bounce-backs' part
  std::vector<Sym6> stresslet_sum_;     // per body, since its previous output row (checkpointed)
  std::vector<std::uint64_t> stresslet_steps_;
};

}  // namespace mesodpd
