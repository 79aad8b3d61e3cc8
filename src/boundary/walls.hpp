// Solid walls at run time: reflection of fluid particles in a thin layer at the solid surfaces (seed 000
// Sect. 3.2.1) and the adaptive near-wall force, as stages; the momentum both take from the fluid per
// body, which the drag analysis (analysis/wall_drag.hpp, seed 004 Eqs 10-11) adds to the pair forces.
// The frozen wall particles themselves are made by make_initial_state and are ordinary particles of
// frozen species (never integrated: inverse mass 0) with a body index.
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "boundary/geometry.hpp"
#include "core/stage.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

class ByteReader;
class ByteWriter;
class Comm;

// The fixed-point unit of the walls' per-body sums (wall_forces() and the drag built on it): 2^32 per
// unit of force, summed in integers so that the totals do not depend on the order of the particles.
inline constexpr double kWallFixedScale = 4294967296.0;
inline std::int64_t wall_fixed(double v) { return static_cast<std::int64_t>(std::llround(v * kWallFixedScale)); }

// The [[solid]] blocks that a model moves itself (rigid bodies, engine/rigid_bodies.hpp), by solid
// index: such a model adds this to the Components before the walls are installed, and the walls then
// leave those solids out of their reflections and adaptive force (their frozen particles stay, and the
// drag still reports the pair forces on them).
struct ReleasedSolids {
  std::vector<std::uint8_t> released;
};

class Walls {
 public:
  // `half_velocity`: the integrator keeps the physical velocity in p.h{x,y,z} between its two halves
  // (modified velocity-Verlet) and p.v is the predicted one; false for Euler (p.v only). `released`:
  // ReleasedSolids::released (empty: none).
  Walls(const SimulationSpec& spec, const Box& box, bool half_velocity, const std::vector<std::uint8_t>& released = {});

  // AfterFirstHalf: every mobile particle found inside a solid (a penetration) is mirrored out through
  // the surface, and its velocity gets the walls.reflection rule if it points into the solid.
  void mirror_positions(StepContext& ctx);
  // AfterSecondHalf: every mobile particle within walls.layer of a surface, or whose next position
  // update would end inside a solid, and whose velocity relative to the wall points into the solid gets
  // the walls.reflection rule (specular, bounce-back, or Maxwellian at kT and the wall velocity; seed 000
  // Sect. 3.2.1). The next move is known here (this step's velocity and force), so a fast particle
  // outside the layer (|v| dt can exceed walls.layer) is turned back too; one that the force kick alone
  // would still carry in gets the normal velocity that stops its move on the surface (a "push"). The
  // simulation also applies this to the initial state. No particle then crosses a surface, and
  // mirror_positions finds nothing.
  void reflect_velocities(StepContext& ctx);
  // The force on each body from the walls' own rules at this step, 3 per body in kWallFixedScale units, on
  // this rank: the momentum per unit time the reflections took from the fluid plus the opposite of the
  // adaptive force of the last force evaluation. The drag adds the pair forces on the frozen particles.
  std::vector<std::int64_t> wall_forces() const;
  // Mass density of the fluid the walls were cut from (the reference density of C_D and Re).
  double fill_density() const { return fill_density_; }

  // Adaptive near-wall force (walls.adaptive; seed 002 "Boundary Conditions", third category). The
  // distance from the nearest surface between walls.layer and walls.adaptive_range is cut into
  // walls.adaptive_bins bins of width h, each with a potential U_k (0 beyond the range); a mobile
  // particle at distance d feels minus the slope of the piecewise-linear U through the bin centres,
  // along the surface normal, and the solid feels the opposite force (it enters the drag). The
  // reflecting layer itself is left alone: its density is set by the reflections (a particle that
  // enters it moving in is turned back), which no force can change.
  // Forces stage: adds f_k n to every local mobile particle in range; a function of the positions only.
  void add_adaptive_force(StepContext& ctx);
  // EndOfStep (collective): counts the mobile particles per bin and in the bulk (beyond the range) at
  // every step up to walls.adaptive_stop; every walls.adaptive_every steps the controller sets
  //   U_k += gain kT ln(rho_k / rho_bulk)
  // from the counts over those steps (integer sums over ranks, so every rank computes the same U).
  void adapt(StepContext& ctx);
  // The step of the controller's last update (0: none yet in this process); analysis/wall_drag.hpp
  // writes U_k and rho_k / rho_bulk to adaptive.csv at each one.
  std::uint64_t last_adaptive_update() const { return last_update_; }
  bool adaptive() const { return spec_.walls.adaptive; }
  const std::vector<double>& adaptive_potential() const { return potential_; }
  // The adaptive force along the outward normal at signed distance d from `body` (0 outside the bins).
  double adaptive_force_at(double d, int body) const;
  // rho_k / rho_bulk at the last update, bins of solid 0 first (empty before the first update).
  const std::vector<double>& adaptive_density() const { return ratio_; }

  // Checkpoint part: the adaptive force's state (the same on every rank; the drag averages precede it in
  // the checkpoint's "walls" section).
  void save(ByteWriter& w) const;
  void load(ByteReader& r, const std::string& context);

  // Reflections and penetrations since the previous call, summed over ranks (collective).
  std::array<std::uint64_t, 2> take_counts(const Comm& comm);
  // Penetrations and pushes since the start of this run, summed over ranks (collective).
  std::array<std::uint64_t, 2> totals(const Comm& comm) const;
  // Reflections and pushes of the last reflect_velocities() call, summed over ranks (collective).
  std::uint64_t last_changes(const Comm& comm) const;

  const Geometry& geometry() const { return geometry_; }
  // Whole cells far from every surface are skipped when the step says where its cells are
  // (StepContext::cells); off, every particle is looked at (tests compare the two: same bits).
  void set_cell_skip(bool on) { cell_skip_ = on; }
  // Mobile particles whose distance bound the last mirror_positions or reflect_velocities looked at
  // (this rank).
  std::uint64_t examined() const { return examined_; }

 private:
  // The adaptive bin of a point at signed distance d from solid `body`: body * bins + (0 .. bins-1)
  // from the layer to the range, bodies * bins (the bulk) beyond it, -1 in the layer or inside a solid.
  int adaptive_bin(double d, int body) const;
  void update_segment_forces();
  Vec3 reflected(const Vec3& u, const Vec3& nrm, double m, std::uint64_t step, std::uint32_t id) const;
  // Calls act(i, r, d, body, mass, counts) for every mobile local particle with signed distance d < below
  // (in parallel), except those that far(i, mass, bound) declares out of reach given a lower bound of
  // their distance (the far-field grid below), and except every particle of a cell whose cell_bounds()
  // entry is at least skip_at (where ctx.cells is set); act returns the particle's velocity change, whose
  // momentum goes to the body.
  template <class Far, class Act>
  void for_near_wall(StepContext& ctx, double below, double skip_at, Far&& far, Act&& act);
  // Lower bounds of the signed distance over each owned cell of ctx.cells, widened by ctx.cell_slack
  // (computed when the grid or the slack changes; a geometry evaluation per cell).
  const std::vector<float>& cell_bounds(const StepContext& ctx);
  // The length of the longest next move, dt v + (kick / m) f, of any mobile local particle.
  double longest_move(const StepContext& ctx, double kick) const;
  // A lower bound of the signed distance at r: the distance at the centre of r's cell of a fixed grid
  // minus Geometry::lipschitz() times the cell's half diagonal (the signed distance changes by at most
  // that per unit length: 1 for the exact shapes, sqrt(3) for the interpolated images). Lets the
  // per-step passes skip the particles far from every surface without evaluating the geometry; the
  // particles that remain see exactly the same computation, so results do not change.
  double distance_bound(const Vec3& r) const;

  const SimulationSpec& spec_;
  Geometry geometry_;
  std::array<int, 3> bound_cells_{1, 1, 1};
  std::array<double, 3> bound_inverse_width_{0, 0, 0};
  std::vector<float> bound_;  // distance_bound per grid cell (rounded down to float)
  // Cell skipping: cell_bounds() and what they were computed for (global dims, owned lo and dims; the
  // box lengths and the slack).
  bool cell_skip_ = true;
  std::vector<float> cell_bound_;
  std::array<int, 9> cell_bound_grid_{};
  std::array<double, 4> cell_bound_lengths_{-1, -1, -1, -1};
  // After reflect_velocities: an upper bound of every mobile particle's next move, for the step and
  // storage generation it belongs to (mirror_positions of the next step skips the cells beyond it).
  double next_move_ = 0;
  std::uint64_t next_move_step_ = 0, next_move_generation_ = 0;
  std::uint64_t examined_ = 0;
  bool half_velocity_;
  std::vector<std::uint8_t> frozen_;  // by species
  double fill_density_ = 0;           // mass density of the fluid the walls were cut from
  std::uint64_t reflections_ = 0, penetrations_ = 0, penetrations_total_ = 0;  // this rank
  std::uint64_t pushes_ = 0;  // this rank: normal pushes that stopped a force kick at a surface
  std::array<std::uint64_t, 2> counted_{0, 0};  // of the current for_near_wall
  std::vector<std::int64_t> impulse_;  // this rank, this step: 3 per body, momentum/dt in 2^32 units
  std::vector<std::int64_t> adaptive_impulse_;  // this rank: minus the adaptive force, 3 per body, 2^32 units
  std::uint64_t last_update_ = 0;
  // Adaptive force, per solid and bin: the potential and the force of each segment; the fluid volume of
  // the bin and the particle counts since the last update (over all ranks; the bulk beyond the range
  // last), the last density ratios.
  double bin_width_ = 0;
  std::vector<double> potential_, segment_force_, bin_volume_, ratio_;
  std::vector<std::uint64_t> bin_counts_;
  std::uint64_t bin_samples_ = 0;
};

}  // namespace mesodpd
