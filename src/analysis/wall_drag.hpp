// What a run with walls measures and writes (seed 004 Eqs 10-11): the drag on each solid body, sampled at
// EndOfStep into drag.csv and block-averaged into drag_summary.csv and the run summary, and the adaptive
// near-wall force's log, adaptive.csv. The walls themselves (boundary/walls.hpp) only act on particles.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "analysis/block_rows.hpp"
#include "core/stage.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

class ByteReader;
class ByteWriter;
class Comm;
class Walls;

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

// EndOfStep (collective): a drag sample every walls.drag_every steps after walls.drag_start, appended to
// drag.csv on the root when there is an output directory.
class WallDrag final : public Stage {
 public:
  // Creates drag.csv with its header (root; kept on a restart).
  WallDrag(const SimulationSpec& spec, const Walls& walls, std::filesystem::path out_dir, bool restarted,
           const Comm& comm);
  void run(StepContext& ctx) override;

  // Block-averaged drag per body (the same on every rank).
  std::vector<DragResult> results() const;
  // Writes drag_summary.csv (root, with an output directory) and returns the summary lines.
  std::string finish(const Comm& comm) const;
  // Checkpoint part (the first of the "walls" section): the sample sums and blocks.
  void save(ByteWriter& w) const;
  void load(ByteReader& r, const std::string& context);

 private:
  const SimulationSpec& spec_;
  const Walls& walls_;
  std::filesystem::path out_dir_;
  std::vector<std::uint8_t> frozen_;  // by species
  // Per body 3 forces, then 3 fluid velocity components, summed over all samples and in blocks
  // (between walls.drag_blocks and twice as many full blocks at any time; blocks that do not depend on
  // the run length, so that a restart continues them exactly).
  std::uint64_t samples_ = 0;
  std::vector<double> total_;
  BlockRows blocks_;
};

// EndOfStep, after the controller (root, with an output directory): the step, U_k and rho_k / rho_bulk
// of every bin at each update of the adaptive near-wall force, appended to adaptive.csv.
class AdaptiveLog final : public Stage {
 public:
  AdaptiveLog(const SimulationSpec& spec, const Walls& walls, std::filesystem::path out_dir, bool restarted,
              const Comm& comm);
  void run(StepContext& ctx) override;

 private:
  const Walls& walls_;
  std::filesystem::path out_dir_;
};

}  // namespace mesodpd
