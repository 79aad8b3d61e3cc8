// A read-only view of one snapshot, shared by the trajectory writers, plus the helpers they all
// need: parsing the field selection and ordering particles by global id.
//
// The view holds plain pointers so any storage (engine arrays, gathered MPI buffers, test vectors)
// can be written without copying. Writers never modify what the pointers address.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "core/particle_data.hpp"
#include "core/topology.hpp"

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
  // Rigid bodies' orientations, 4 per particle (unit quaternion w, x, y, z), and diameters: the GSD
  // writer adds particles/orientation and particles/diameter when set (whatever the field selection).
  const double* orientation = nullptr;
  const double* diameter = nullptr;
  const std::vector<std::string>* species_names = nullptr;
  const std::vector<double>* species_mass = nullptr;
  // Further per-particle arrays: the fields of the particle field list flagged kFrame that are not
  // among the columns above (core/particle_data.hpp), by field name. Written when selected by name.
  struct Extra {
    std::string name;
    char kind = 'f';             // FieldInfo::kind: 'f', 'i' or 'u'
    std::size_t elem_bytes = 8;  // 1, 2, 4 or 8
    const void* data = nullptr;
  };
  std::vector<Extra> extra;
  // Bonds, angles and dihedrals by global id (GSD bonds/, angles/ and dihedrals/ chunks), with their type
  // names; may be null.
  const Topology* topology = nullptr;
  const std::vector<std::string>* bond_type_names = nullptr;
  const std::vector<std::string>* angle_type_names = nullptr;
  const std::vector<std::string>* dihedral_type_names = nullptr;
};

// Points the frame's arrays at the first p.n_local particles of `p` (every field flagged kFrame) and
// sets n; step, time, box and species tables are left to the caller.
void set_frame_arrays(FrameView& frame, const ParticleData& p);

// Calls f(value) with element i of an extra array, as its own arithmetic type.
template <class F>
void visit_extra(const FrameView::Extra& e, std::size_t i, F&& f) {
  auto read = [&](auto zero) {
    decltype(zero) v;
    std::memcpy(&v, static_cast<const std::byte*>(e.data) + i * sizeof v, sizeof v);
    f(v);
  };
  switch (e.kind == 'f' ? 100 + static_cast<int>(e.elem_bytes) : (e.kind == 'i' ? 0 : 10) + static_cast<int>(e.elem_bytes)) {
    case 104: return read(float{});
    case 108: return read(double{});
    case 1: return read(std::int8_t{});
    case 2: return read(std::int16_t{});
    case 4: return read(std::int32_t{});
    case 8: return read(std::int64_t{});
    case 11: return read(std::uint8_t{});
    case 12: return read(std::uint16_t{});
    case 14: return read(std::uint32_t{});
    case 18: return read(std::uint64_t{});
    default: return;
  }
}

// Which per-particle quantities a writer emits. Parsed from names in
// {"id", "species", "position", "velocity", "force", "image"} and the names of the extra fields
// (trajectory_field_names()); output column order is fixed (the order of the members here, extras
// in the order of the particle field list), whatever order the names were given in.
struct FieldSet {
  bool id = false, species = false, position = false, velocity = false, force = false, image = false;
  std::vector<std::string> extra;
};

// Every name a trajectory's field selection may use: the six above, then the fields of the particle
// field list flagged kFrame that are not part of them.
const std::vector<std::string>& trajectory_field_names();

// Throws ConfigError naming `file` for an unknown, repeated or empty selection.
FieldSet parse_trajectory_fields(const std::vector<std::string>& names, const std::filesystem::path& file);

// The extra array called `name` of a frame (ConfigError if it has none).
const FrameView::Extra& extra_array(const FrameView& frame, const std::string& name);

// Throws ConfigError naming `file` if an array needed by `fields` (or the id array, always needed
// to order the output) is missing from a frame with particles, or the box is not positive.
void check_frame_arrays(const FrameView& frame, const FieldSet& fields, const std::filesystem::path& file);

// Storage indices ordered by global id, so output does not depend on how particles happen to be
// stored (cell sorting, thread or rank layout). Throws ConfigError naming `file` on duplicate ids.
std::vector<std::size_t> order_by_id(const FrameView& frame, const std::filesystem::path& file);

}  // namespace mesodpd
