// Text trajectories in the LAMMPS "dump custom" layout, readable by OVITO, VMD and LAMMPS's own
// tools, written at full double precision so a dump can also serve as exact reference data.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "io/frame.hpp"
#include "io/output_file.hpp"

namespace mesodpd {

// Each frame is:
//   ITEM: TIMESTEP / step
//   ITEM: NUMBER OF ATOMS / n
//   ITEM: BOX BOUNDS pp pp pp / lo hi (three lines)
//   ITEM: ATOMS <columns> / one line per particle, sorted by id
// Columns, in this order for the selected fields: id type x y z vx vy vz fx fy fz ix iy iz, where
// type = species index + 1 (LAMMPS types start at 1), then one column per selected extra field of
// the particle field list, named after it (FrameView::extra). Reals are printed as the shortest decimal
// that reads back to the same double.
class LammpsDumpWriter {
 public:
  // `fields` ⊆ trajectory_field_names() (io/frame.hpp). With `append` new frames
  // go after those already in the file (restarts); otherwise the file is truncated.
  LammpsDumpWriter(std::filesystem::path path, const std::vector<std::string>& fields, bool append = false);

  // Writes one frame and flushes it, so a crashed run keeps every completed frame. Throws OutputError
  // naming the file when the frame could not be written whole.
  void write_frame(const FrameView& frame);

  [[nodiscard]] const std::filesystem::path& path() const { return path_; }
  [[nodiscard]] std::uint64_t frames_written() const { return frames_written_; }

 private:
  std::filesystem::path path_;
  FieldSet fields_;
  OutputFile out_;
  std::uint64_t frames_written_ = 0;
};

}  // namespace mesodpd
