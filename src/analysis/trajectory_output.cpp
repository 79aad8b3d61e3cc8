// Trajectory frames (trajectory_output.hpp).
#include "analysis/trajectory_output.hpp"

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "io/frame.hpp"
#include "io/output_file.hpp"
#include "parallel/comm.hpp"

namespace mesodpd {

namespace {

// A restarted run continues from the checkpoint's step K, but the run that wrote the checkpoint may
// have gone further: frames after K are dropped so that appending does not duplicate steps.
void trim_lammps_dump(const std::filesystem::path& path, std::uint64_t last_step) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::optional<std::uintmax_t> cut;
  while (true) {
    const std::streamoff pos = in.tellg();
    if (!std::getline(in, line)) break;
    if (line != "ITEM: TIMESTEP") continue;
    std::optional<std::uint64_t> step;
    if (std::getline(in, line)) step = leading_step(line);
    if (!step || *step > last_step) {
      cut = static_cast<std::uintmax_t>(pos);
      break;
    }
  }
  in.close();
  if (cut) std::filesystem::resize_file(path, *cut);
}

}  // namespace

TrajectoryOutput::TrajectoryOutput(const SimulationSpec& spec, AnalysisOutput out, SystemSnapshot& snapshot,
                                   const StepContext& start)
    : spec_(spec), snapshot_(snapshot) {
  const bool restarted = out.restarted;
  start.comm.on_root([&] {
    std::filesystem::create_directories(out.dir);
    const bool gsd = spec_.dump.format == DumpFormat::Gsd;
    const std::string name = !spec_.dump.file.empty() ? spec_.dump.file : (gsd ? "trajectory.gsd" : "trajectory.lammpstrj");
    if (gsd) {
      // Frames after the checkpoint's step are dropped from the index, as trim_lammps_dump does for text.
      gsd_.emplace(out / name, spec_.dump.fields, restarted,
                   restarted ? std::optional<std::uint64_t>(start.step) : std::nullopt);
    } else {
      if (restarted && std::filesystem::exists(out / name)) trim_lammps_dump(out / name, start.step);
      lammps_.emplace(out / name, spec_.dump.fields, restarted);
    }
  });
}

void TrajectoryOutput::observe(const StepContext& ctx) {
  if (!due(ctx.step)) return;
  // The frame is written by the root; a failed write stops every rank.
  const ParticleData& all = snapshot_.of(ctx);  // collective
  ctx.comm.on_root([&] { write_frame(ctx.step, ctx, all); });
}

void TrajectoryOutput::write_frame(std::uint64_t step, const StepContext& ctx, const ParticleData& p) {
  const SimulationSpec& s = spec_;
  std::vector<std::string> names;
  for (const auto& sp : s.species) names.push_back(sp.name);
  FrameView f;
  f.step = step;
  f.time = static_cast<double>(step) * s.dt;
  f.box_lo = {0, 0, 0};
  f.box_len = {ctx.box.len.x, ctx.box.len.y, ctx.box.len.z};
  f.periodic = ctx.box.periodic;
  set_frame_arrays(f, p);
  f.species_names = &names;
  f.species_mass = &ctx.species_mass;
  std::vector<std::string> bond_names, angle_names, dihedral_names;
  for (const auto& b : s.bond_types) bond_names.push_back(b.name);
  for (const auto& a : s.angle_types) angle_names.push_back(a.name);
  for (const auto& d : s.dihedral_types) dihedral_names.push_back(d.name);
  f.topology = ctx.topology;
  f.bond_type_names = &bond_names;
  f.angle_type_names = &angle_names;
  f.dihedral_type_names = &dihedral_names;
  if (lammps_) lammps_->write_frame(f);
  if (gsd_) gsd_->write_frame(f);
}

}  // namespace mesodpd
