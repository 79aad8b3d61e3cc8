// Binary trajectories in HOOMD-blue's GSD format (file layer version 2.0, "hoomd" schema 1.4),
// written by our own code so the engine needs no libgsd; readable by the gsd Python package, OVITO,
// VMD and HOOMD-blue.
//
// Chunks written per frame (only for the selected fields):
//   configuration/step        uint64 [1]
//   configuration/box         float32 [6]  Lx Ly Lz xy xz yz (tilts are always 0)
//   configuration/dimensions  uint8 [1] = 3, first frame of the file only
//   particles/N               uint32 [1]
//   particles/types           int8 [ntypes x width], NUL-padded names; "species" field, written on the
//                             first frame of each writer and whenever the names change
//   particles/typeid          uint32 [N]        "species"
//   particles/mass            float32 [N]       "species", when the frame carries species masses
//   particles/position        float32 [N x 3]   "position", relative to the box centre (HOOMD's box
//                                               spans [-L/2, L/2)), i.e. x - (lo + L/2), kept
//                                               strictly below +L/2 after rounding to float32
//   particles/velocity        float32 [N x 3]   "velocity"
//   particles/image           int32 [N x 3]     "image"
//   particles/orientation     float32 [N x 4]   FrameView::orientation, when set (rigid bodies)
//   particles/diameter        float32 [N]       FrameView::diameter, when set
//   log/particles/force       float32 [N x 3]   "force" (the hoomd schema has no force chunk)
//   log/particles/id          uint32 [N]        "id" (the hoomd schema has no id chunk)
//   log/particles/<name>      its type [N]      an extra field of the particle field list
//                                               (FrameView::extra), when selected by name
//   bonds/N, bonds/types, bonds/typeid, bonds/group (uint32 [N x 2], particle rows)   the frame's
//   angles/N, angles/types, angles/typeid, angles/group (uint32 [N x 3])              topology, in
//   dihedrals/N, dihedrals/types, dihedrals/typeid, dihedrals/group (uint32 [N x 4])
//                                               the first frame of a file only (the schema's readers
//                                               take absent chunks from frame 0), so OVITO and VMD
//                                               draw the chains
// Particles are written in increasing global id, so row k of every per-particle chunk is the k-th
// smallest id; for ids 0..N-1 the row index equals the id. The frame's `time` has no place in the
// schema and is not written.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/frame.hpp"

namespace mesodpd {

class GsdWriter {
 public:
  // `fields` ⊆ trajectory_field_names() (io/frame.hpp). Without `append` the file
  // is created or truncated. With `append` frames are added after those of an existing GSD 2.x
  // "hoomd" schema file (a missing or empty file is created); other files are rejected.
  // With `append` and `keep_through_step` = K (a restart from a checkpoint at step K), the existing
  // frames from the first one whose configuration/step exceeds K onwards are dropped first: their
  // index entries are zeroed, so readers no longer see them, and the file is cut after the last
  // byte still in use (their chunk data, unless the index or namelist was moved after it). Frames
  // are assumed to be in increasing step order, as every writer of a trajectory produces them.
  GsdWriter(std::filesystem::path path, const std::vector<std::string>& fields, bool append = false,
            std::optional<std::uint64_t> keep_through_step = std::nullopt);
  ~GsdWriter();
  GsdWriter(const GsdWriter&) = delete;
  GsdWriter& operator=(const GsdWriter&) = delete;

  // Writes one frame. The frame becomes visible to readers only once its index entries are
  // written, which happens last, so an interrupted write leaves the earlier frames readable.
  void write_frame(const FrameView& frame);

  [[nodiscard]] const std::filesystem::path& path() const { return path_; }
  // Frames in the file, including those present before an append.
  [[nodiscard]] std::uint64_t frame_count() const { return next_frame_; }

  // Format constants, public for tests.
  static constexpr std::uint64_t kMagic = 0x65DF65DF65DF65DFULL;
  static constexpr std::uint32_t kFileVersion = 2u << 16;           // 2.0
  static constexpr std::uint32_t kSchemaVersion = (1u << 16) | 4u;  // hoomd 1.4

 private:
  struct IndexEntry {
    std::uint64_t frame = 0, n = 0;
    std::int64_t location = 0;
    std::uint32_t m = 0;
    std::uint16_t id = 0;
    std::uint8_t type = 0;
  };
  struct Chunk;

  void create_file();
  void open_existing();
  void drop_frames_after_step(std::uint64_t last_step);
  void write_header();
  void write_at(const void* data, std::size_t size, std::uint64_t offset, const char* what);
  void read_at(void* data, std::size_t size, std::uint64_t offset, const char* what);
  std::uint16_t name_id(const std::string& name);
  void commit_names();
  void commit_index(std::size_t first_new);
  [[noreturn]] void fail(const std::string& message) const;

  std::filesystem::path path_;
  FieldSet fields_;
  int fd_ = -1;
  std::uint64_t file_size_ = 0;

  // Header fields kept in memory; the header is rewritten whenever a block moves.
  std::uint64_t index_location_ = 0, index_allocated_ = 0;
  std::uint64_t namelist_location_ = 0, namelist_blocks_ = 0;  // namelist size in 64-byte blocks
  std::array<char, 64> application_{}, schema_{};

  std::vector<std::string> names_;   // id -> name
  std::size_t names_on_disk_ = 0;    // names_[0, names_on_disk_) are already in the file
  std::uint64_t namelist_used_ = 0;  // bytes of NUL-terminated names in the file's namelist
  std::vector<IndexEntry> index_;    // every entry in the file, in file order
  std::uint64_t next_frame_ = 0;
  std::vector<std::string> last_types_;  // particles/types last written by this writer
  bool types_written_ = false;
};

}  // namespace mesodpd
