// Solid walls at run time: reflection of fluid particles in a thin layer at the solid surfaces (seed 000
// Sect. 3.2.1) as an AfterFirstHalf stage, and the drag on each solid body (seed 004 Eqs 10-11) sampled
// at EndOfStep. The frozen wall particles themselves are made by make_initial_state and are ordinary
// particles of frozen species (never integrated: inverse mass 0) with a body index.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "boundary/geometry.hpp"
#include "core/stage.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

class Comm;

// The time-averaged drag on one body. Forces are those the fluid exerts on the body: pair forces on its
// frozen particles plus the momentum the reflections at its surface take from the fluid, per unit time.
struct DragResult {
  std::string name;
  std::array<double, 3> force{0, 0, 0}, error{0, 0, 0};  // mean and block standard error
  std::array<double, 3> fluid_velocity{0, 0, 0};          // mean fluid velocity over the same samples
  std::uint64_t samples = 0;
  double drag = 0, drag_error = 0;  // F . u / |u| (u: mean fluid velocity)
  double cd = -1, cd_error = -1;    // C_D = 2 F_D / (rho |u|^2 A), when walls.reference_area is set
  double re = -1;                   // Re = rho |u| d / mu, when walls.reference_length and viscosity are set
};

class Walls {
 public:
  // `half_velocity`: the integrator keeps the physical velocity in p.h{x,y,z} between its two halves
  // (modified velocity-Verlet) and p.v is the predicted one; false for Euler (p.v only).
  Walls(const SimulationSpec& spec, const Box& box, bool half_velocity, std::uint64_t first_step,
        std::uint64_t final_step);

  // AfterFirstHalf: every mobile particle found inside a solid (a penetration) is mirrored out through
  // the surface, and its velocity gets the walls.reflection rule if it points into the solid.
  void mirror_positions(StepContext& ctx);
  // AfterSecondHalf: every mobile particle within walls.layer of a surface whose velocity relative to
  // the wall points into the solid gets the walls.reflection rule (specular, bounce-back, or Maxwellian
  // at kT and the wall velocity; seed 000 Sect. 3.2.1). Acting on the end-of-step velocity, the one the
  // next position update uses, it turns particles back before they reach the surface.
  void reflect_velocities(StepContext& ctx);
  // EndOfStep: a drag sample when due (collective), appended to drag.csv on the root if `out` is set.
  void sample_drag(StepContext& ctx);

  // Reflections and penetrations since the previous call, summed over ranks (collective).
  std::array<std::uint64_t, 2> take_counts(const Comm& comm);
  // Penetrations since the start of this run, summed over ranks (collective).
  std::uint64_t total_penetrations(const Comm& comm) const;
  // Block-averaged drag per body (the same on every rank).
  std::vector<DragResult> drag() const;
  // Writes drag_summary.csv (root) and returns summary lines.
  std::string finish(const Comm& comm, const std::filesystem::path& out_dir) const;

  const Geometry& geometry() const { return geometry_; }
  void set_output(const std::filesystem::path& out_dir, bool restarted, const Comm& comm);

 private:
  Vec3 reflected(const Vec3& u, const Vec3& nrm, double m, std::uint64_t step, std::uint32_t id) const;
  // Calls act(i, r, d, body, mass, count) for every mobile local particle with signed distance d < below
  // (in parallel); act returns the particle's velocity change, whose momentum goes to the body.
  template <class Act>
  void for_near_wall(StepContext& ctx, double below, Act&& act);

  const SimulationSpec& spec_;
  Geometry geometry_;
  bool half_velocity_;
  std::vector<std::uint8_t> frozen_;  // by species
  double fill_density_ = 0;           // mass density of the fluid the walls were cut from
  std::uint64_t reflections_ = 0, penetrations_ = 0, penetrations_total_ = 0;  // this rank
  std::uint64_t counted_ = 0;  // of the current for_near_wall
  std::vector<std::int64_t> impulse_;  // this rank, this step: 3 per body, momentum/dt in 2^32 units
  // Drag samples in blocks: per block, per body 3 force sums, then 3 fluid velocity sums; counts.
  std::uint64_t samples_expected_ = 0, samples_ = 0, block_size_ = 1;
  std::vector<std::array<double, 6>> block_sums_;  // [block * bodies + body]
  std::vector<std::uint64_t> block_counts_;
  std::filesystem::path out_dir_;
};

}  // namespace mesodpd
