// A read-only view of one snapshot, shared by the trajectory writers, plus the helpers they all
// need: parsing the field selection and ordering particles by global id.
//
// The view holds plain pointers so any storage (engine arrays, gathered MPI buffers, test vectors)
// can be written without copying. Writers never modify what the pointers address.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace mesodpd {

struct FrameView {
  std::uint64_t step = 0;
  double time = 0;
  std::array<double, 3> box_lo{}, box_len{};
  std::array<bool, 3> periodic{true, true, true};  // per axis; false: bounded (LAMMPS "ff")
  std::size_t n = 0;
  const std::uint32_t* id = nullptr;                      // global ids; required whenever n > 0
  const std::int32_t* species = nullptr;                  // species index 0..
  const double *x = nullptr, *y = nullptr, *z = nullptr;  // wrapped positions, inside the box
  const double *vx = nullptr, *vy = nullptr, *vz = nullptr;
  const double *fx = nullptr, *fy = nullptr, *fz = nullptr;
  const std::int32_t *ix = nullptr, *iy = nullptr, *iz = nullptr;  // periodic image counters
  const std::vector<std::string>* species_names = nullptr;
  const std::vector<double>* species_mass = nullptr;
};

// Which per-particle quantities a writer emits. Parsed from names in
// {"id", "species", "position", "velocity", "force", "image"}; output column order is fixed
// (the order of the members here), whatever order the names were given in.
struct FieldSet {
  bool id = false, species = false, position = false, velocity = false, force = false, image = false;
};

// Throws ConfigError naming `file` for an unknown, repeated or empty selection.
FieldSet parse_trajectory_fields(const std::vector<std::string>& names, const std::filesystem::path& file);

// Throws ConfigError naming `file` if an array needed by `fields` (or the id array, always needed
// to order the output) is missing from a frame with particles, or the box is not positive.
void check_frame_arrays(const FrameView& frame, const FieldSet& fields, const std::filesystem::path& file);

// Storage indices ordered by global id, so output does not depend on how particles happen to be
// stored (cell sorting, thread or rank layout). Throws ConfigError naming `file` on duplicate ids.
std::vector<std::size_t> order_by_id(const FrameView& frame, const std::filesystem::path& file);

}  // namespace mesodpd
