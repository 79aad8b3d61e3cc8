// Implementation of GsdWriter: the GSD 2.0 file layer (header, index, namelist) and the hoomd schema.
//
// File layer, as specified by the GSD documentation (all integers little-endian):
//   header (256 bytes): uint64 magic, index_location, index_allocated_entries, namelist_location,
//     namelist_allocated_entries (in 64-byte units); uint32 schema_version, gsd_version;
//     char application[64], schema[64], reserved[80]
//   index: index_allocated_entries entries of 32 bytes: uint64 frame, N; int64 location;
//     uint32 M; uint16 id (position of the name in the namelist); uint8 type; uint8 flags.
//     Entries are sorted by (frame, id); the first entry with location 0 ends the list.
//   namelist (version 2.0): NUL-terminated names packed back to back; an empty name ends the list.
//   chunk data: anywhere else in the file; entry.location is its byte offset.
// Blocks that outgrow their allocation are rewritten, larger, at the end of the file and the header
// is updated to point at them, as libgsd does.
#include "io/gsd_writer.hpp"
#include "io/output_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <type_traits>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>
#include <span>

#include "io/byte_buffer.hpp"
#include "mesodpd/config_error.hpp"

namespace mesodpd {
namespace {

constexpr std::size_t kHeaderSize = 256;
constexpr std::size_t kEntrySize = 32;
constexpr std::uint64_t kNameBlock = 64;
constexpr std::uint64_t kInitialIndexEntries = 128;
constexpr std::uint64_t kInitialNameBlocks = 16;  // 1 KiB, room for every name we write

// GSD element type codes.
enum GsdType : std::uint8_t {
  kUint8 = 1,
  kUint16 = 2,
  kUint32 = 3,
  kUint64 = 4,
  kInt8 = 5,
  kInt16 = 6,
  kInt32 = 7,
  kInt64 = 8,
  kFloat32 = 9,
  kFloat64 = 10,
};

// The GSD type code of an arithmetic element type.
template <class T>
constexpr GsdType gsd_type_of() {
  if constexpr (std::is_floating_point_v<T>) return sizeof(T) == 4 ? kFloat32 : kFloat64;
  else if constexpr (std::is_signed_v<T>) return sizeof(T) == 1 ? kInt8 : sizeof(T) == 2 ? kInt16 : sizeof(T) == 4 ? kInt32 : kInt64;
  else return sizeof(T) == 1 ? kUint8 : sizeof(T) == 2 ? kUint16 : sizeof(T) == 4 ? kUint32 : kUint64;
}

// Bytes per element of a GSD type code (the file layer's full list, not only the types we write);
// 0 for an unknown code.
std::uint64_t gsd_type_size(std::uint8_t type) {
  // uint8, uint16, uint32, uint64, int8, int16, int32, int64, float, double, character
  constexpr std::array<std::uint8_t, 12> kSizes = {0, 1, 2, 4, 8, 1, 2, 4, 8, 4, 8, 1};
  return type < kSizes.size() ? kSizes[type] : 0;
}

std::array<char, 64> fixed_string(const std::string& s) {
  std::array<char, 64> out{};
  std::memcpy(out.data(), s.data(), std::min(s.size(), out.size() - 1));
  return out;
}

#ifdef MESODPD_VERSION
const std::string kApplication = std::string("mesodpd ") + MESODPD_VERSION;
#else
const std::string kApplication = "mesodpd";
#endif

}  // namespace

struct GsdWriter::Chunk {
  std::string name;
  std::uint8_t type = 0;
  std::uint64_t n = 0;
  std::uint32_t m = 1;
  std::vector<std::byte> data;
  std::uint16_t id = 0;

  template <class T>
  static Chunk make(std::string name, std::uint8_t type, std::uint32_t m, const std::vector<T>& values) {
    Chunk c;
    c.name = std::move(name);
    c.type = type;
    c.m = m;
    c.n = values.size() / m;
    c.data.resize(values.size() * sizeof(T));
    if (!values.empty()) std::memcpy(c.data.data(), values.data(), c.data.size());
    return c;
  }
};

GsdWriter::GsdWriter(std::filesystem::path path, const std::vector<std::string>& fields, bool append,
                     std::optional<std::uint64_t> keep_through_step)
    : path_(std::move(path)), fields_(parse_trajectory_fields(fields, path_)) {
  std::error_code ec;
  const bool existing =
      append && std::filesystem::exists(path_, ec) && std::filesystem::file_size(path_, ec) > 0;
  fd_ = ::open(path_.c_str(), O_RDWR | O_CLOEXEC | (existing ? 0 : O_CREAT | O_TRUNC), 0644);
  if (fd_ < 0) fail(std::string("cannot open for writing: ") + std::strerror(errno));
  try {
    if (existing) {
      open_existing();
      if (keep_through_step) drop_frames_after_step(*keep_through_step);
    } else {
      create_file();
    }
  } catch (...) {
    ::close(fd_);
    fd_ = -1;
    throw;
  }
}

GsdWriter::~GsdWriter() {
  if (fd_ >= 0) ::close(fd_);
}

void GsdWriter::fail(const std::string& message) const {
  throw ConfigError("GSD file '" + path_.string() + "': " + message);
}

void GsdWriter::write_at(const void* data, std::size_t size, std::uint64_t offset, const char* what) {
  if (const int err = injected_output_fault(path_); err != 0)
    fail(std::string("error writing ") + what + ": " + std::strerror(err));
  const auto* p = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t done = ::pwrite(fd_, p, size, static_cast<off_t>(offset));
    if (done < 0) {
      if (errno == EINTR) continue;
      fail(std::string("error writing ") + what + ": " + std::strerror(errno));
    }
    p += done;
    offset += static_cast<std::uint64_t>(done);
    size -= static_cast<std::size_t>(done);
  }
}

void GsdWriter::read_at(void* data, std::size_t size, std::uint64_t offset, const char* what) {
  auto* p = static_cast<char*>(data);
  while (size > 0) {
    const ssize_t done = ::pread(fd_, p, size, static_cast<off_t>(offset));
    if (done < 0) {
      if (errno == EINTR) continue;
      fail(std::string("error reading ") + what + ": " + std::strerror(errno));
    }
    if (done == 0) fail(std::string("file is truncated: the ") + what + " extends past its end");
    p += done;
    offset += static_cast<std::uint64_t>(done);
    size -= static_cast<std::size_t>(done);
  }
}

void GsdWriter::write_header() {
  ByteWriter h;
  h.put(kMagic);
  h.put(index_location_);
  h.put(index_allocated_);
  h.put(namelist_location_);
  h.put(namelist_blocks_);
  h.put(kSchemaVersion);
  h.put(kFileVersion);
  h.put(application_);
  h.put(schema_);
  h.put(std::array<char, 80>{});
  write_at(h.bytes().data(), h.size(), 0, "header");
}

void GsdWriter::create_file() {
  if (::ftruncate(fd_, 0) != 0) fail(std::string("cannot truncate: ") + std::strerror(errno));
  application_ = fixed_string(kApplication);
  schema_ = fixed_string("hoomd");
  index_location_ = kHeaderSize;
  index_allocated_ = kInitialIndexEntries;
  namelist_location_ = index_location_ + index_allocated_ * kEntrySize;
  namelist_blocks_ = kInitialNameBlocks;
  file_size_ = namelist_location_ + namelist_blocks_ * kNameBlock;
  // Zero-filled index and namelist mean "no entries" and "no names".
  const std::vector<char> zeros(file_size_ - kHeaderSize, 0);
  write_at(zeros.data(), zeros.size(), kHeaderSize, "empty index and namelist");
  write_header();
}

void GsdWriter::open_existing() {
  struct stat st {};
  if (::fstat(fd_, &st) != 0) fail(std::string("cannot stat: ") + std::strerror(errno));
  file_size_ = static_cast<std::uint64_t>(st.st_size);
  if (file_size_ < kHeaderSize) fail("cannot append: file is shorter than a GSD header");

  std::vector<std::byte> raw(kHeaderSize);
  read_at(raw.data(), raw.size(), 0, "header");
  ByteReader h(raw, "GSD file '" + path_.string() + "' header");
  if (h.get<std::uint64_t>() != kMagic) fail("cannot append: not a GSD file (bad magic number)");
  index_location_ = h.get<std::uint64_t>();
  index_allocated_ = h.get<std::uint64_t>();
  namelist_location_ = h.get<std::uint64_t>();
  namelist_blocks_ = h.get<std::uint64_t>();
  const auto schema_version = h.get<std::uint32_t>();
  const auto file_version = h.get<std::uint32_t>();
  application_ = h.get<std::array<char, 64>>();
  schema_ = h.get<std::array<char, 64>>();
  schema_.back() = 0;

  // Version 1.x stores names in fixed 64-byte slots; supporting both layouts is not worth it when
  // every file we append to was written by us (2.0) or by a current libgsd (2.x).
  if ((file_version >> 16) != 2) {
    fail("cannot append: GSD file layer version " + std::to_string(file_version >> 16) + "." +
         std::to_string(file_version & 0xFFFF) + " (only 2.x is supported for append)");
  }
  if (std::string(schema_.data()) != "hoomd" || (schema_version >> 16) != 1) {
    fail("cannot append: schema is '" + std::string(schema_.data()) + "' version " +
         std::to_string(schema_version >> 16) + "." + std::to_string(schema_version & 0xFFFF) +
         ", expected 'hoomd' 1.x");
  }
  if (index_allocated_ == 0 || index_location_ + index_allocated_ * kEntrySize > file_size_ ||
      namelist_location_ + namelist_blocks_ * kNameBlock > file_size_) {
    fail("cannot append: file is corrupt (index or namelist outside the file)");
  }

  std::vector<char> names(namelist_blocks_ * kNameBlock);
  read_at(names.data(), names.size(), namelist_location_, "namelist");
  std::size_t pos = 0;
  while (pos < names.size() && names[pos] != 0) {
    const std::size_t len = ::strnlen(names.data() + pos, names.size() - pos);
    if (pos + len == names.size()) fail("cannot append: file is corrupt (unterminated namelist)");
    names_.emplace_back(names.data() + pos, len);
    pos += len + 1;
  }
  names_on_disk_ = names_.size();
  namelist_used_ = pos;

  std::vector<std::byte> index_raw(index_allocated_ * kEntrySize);
  read_at(index_raw.data(), index_raw.size(), index_location_, "index");
  ByteReader r(index_raw, "GSD file '" + path_.string() + "' index");
  for (std::uint64_t k = 0; k < index_allocated_; ++k) {
    IndexEntry e;
    e.frame = r.get<std::uint64_t>();
    e.n = r.get<std::uint64_t>();
    e.location = r.get<std::int64_t>();
    e.m = r.get<std::uint32_t>();
    e.id = r.get<std::uint16_t>();
    e.type = r.get<std::uint8_t>();
    (void)r.get<std::uint8_t>();  // flags, always 0
    if (e.location == 0) break;
    if (e.id >= names_.size() || (!index_.empty() && e.frame < index_.back().frame)) {
      fail("cannot append: file is corrupt (index entry " + std::to_string(k) + " is invalid)");
    }
    index_.push_back(e);
  }
  next_frame_ = index_.empty() ? 0 : index_.back().frame + 1;
}

// Drops the frames from the first one with configuration/step > last_step to the end. A frame
// without a configuration/step chunk has the step of frame 0, or 0 (the hoomd schema's defaults).
void GsdWriter::drop_frames_after_step(std::uint64_t last_step) {
  const auto step_name = std::find(names_.begin(), names_.end(), std::string("configuration/step"));
  const auto step_id = static_cast<std::uint16_t>(step_name - names_.begin());
  const bool has_steps = step_name != names_.end();
  auto read_step = [&](const IndexEntry& e) {
    if (e.type != kUint64 || e.n * e.m == 0) {
      fail("cannot truncate after step " + std::to_string(last_step) + ": configuration/step of frame " +
           std::to_string(e.frame) + " is not a uint64 value");
    }
    std::uint64_t step = 0;
    read_at(&step, sizeof step, static_cast<std::uint64_t>(e.location), "configuration/step chunk");
    return step;  // GSD files are little-endian, like every host this engine builds on
  };

  std::optional<std::uint64_t> frame0_step;
  std::size_t cut = index_.size();  // first index entry to drop
  for (std::size_t begin = 0; begin < index_.size();) {
    std::size_t end = begin;
    std::optional<std::uint64_t> step;
    while (end < index_.size() && index_[end].frame == index_[begin].frame) {
      if (has_steps && index_[end].id == step_id) step = read_step(index_[end]);
      ++end;
    }
    if (index_[begin].frame == 0) frame0_step = step;
    if (step.value_or(frame0_step.value_or(0)) > last_step) {
      cut = begin;
      break;
    }
    begin = end;
  }
  if (cut == index_.size()) return;

  // Zero the dropped entries one frame at a time, last frame first, so that an interruption leaves
  // an index that ends with whole frames followed only by empty entries, as readers require.
  const std::vector<std::byte> zeros(kEntrySize * (index_.size() - cut));
  for (std::size_t end = index_.size(); end > cut;) {
    std::size_t begin = end - 1;
    while (begin > cut && index_[begin - 1].frame == index_[end - 1].frame) --begin;
    write_at(zeros.data(), (end - begin) * kEntrySize, index_location_ + begin * kEntrySize, "index");
    end = begin;
  }
  index_.resize(cut);
  next_frame_ = index_.empty() ? 0 : index_.back().frame + 1;

  // Give back the space after the last byte still referenced. The dropped frames' data is usually
  // all of it; an index or namelist that was moved to the end of the file after them keeps it.
  std::uint64_t used = std::max({std::uint64_t{kHeaderSize}, index_location_ + index_allocated_ * kEntrySize,
                                 namelist_location_ + namelist_blocks_ * kNameBlock});
  for (const auto& e : index_) {
    const std::uint64_t size = gsd_type_size(e.type);
    if (size == 0) return;  // a chunk of unknown extent: keep everything
    used = std::max(used, static_cast<std::uint64_t>(e.location) + e.n * e.m * size);
  }
  if (used < file_size_) {
    if (::ftruncate(fd_, static_cast<off_t>(used)) != 0)
      fail(std::string("cannot truncate: ") + std::strerror(errno));
    file_size_ = used;
  }
}

std::uint16_t GsdWriter::name_id(const std::string& name) {
  const auto it = std::find(names_.begin(), names_.end(), name);
  if (it != names_.end()) return static_cast<std::uint16_t>(it - names_.begin());
  if (names_.size() >= std::numeric_limits<std::uint16_t>::max()) fail("namelist is full");
  names_.push_back(name);
  return static_cast<std::uint16_t>(names_.size() - 1);
}

// Puts names added since the last commit into the file. The header only changes when the namelist
// has to move, and then it is written after the new namelist is complete.
void GsdWriter::commit_names() {
  if (names_on_disk_ == names_.size()) return;
  std::vector<char> added;
  for (std::size_t k = names_on_disk_; k < names_.size(); ++k) {
    added.insert(added.end(), names_[k].begin(), names_[k].end());
    added.push_back(0);
  }
  // One spare NUL keeps an empty name after the last one, the list terminator readers look for.
  const std::uint64_t needed = namelist_used_ + added.size() + 1;
  if (needed <= namelist_blocks_ * kNameBlock) {
    write_at(added.data(), added.size(), namelist_location_ + namelist_used_, "namelist");
  } else {
    std::uint64_t blocks = std::max<std::uint64_t>(2 * namelist_blocks_, 1);
    while (blocks * kNameBlock < needed) blocks *= 2;
    std::vector<char> all;
    for (const auto& n : names_) {
      all.insert(all.end(), n.begin(), n.end());
      all.push_back(0);
    }
    all.resize(blocks * kNameBlock, 0);
    const std::uint64_t location = file_size_;
    write_at(all.data(), all.size(), location, "namelist");
    file_size_ += all.size();
    namelist_location_ = location;
    namelist_blocks_ = blocks;
    write_header();
  }
  namelist_used_ += added.size();
  names_on_disk_ = names_.size();
}

// Writes index entries [first_new, end). Writing them is what makes the frame exist for readers.
void GsdWriter::commit_index(std::size_t first_new) {
  auto serialise = [](ByteWriter& w, const IndexEntry& e) {
    w.put(e.frame);
    w.put(e.n);
    w.put(e.location);
    w.put(e.m);
    w.put(e.id);
    w.put(e.type);
    w.put(std::uint8_t{0});
  };
  if (index_.size() <= index_allocated_) {
    ByteWriter w;
    for (std::size_t k = first_new; k < index_.size(); ++k) serialise(w, index_[k]);
    write_at(w.bytes().data(), w.size(), index_location_ + first_new * kEntrySize, "index");
    return;
  }
  std::uint64_t allocated = 2 * index_allocated_;
  while (allocated < index_.size()) allocated *= 2;
  ByteWriter w;
  for (const auto& e : index_) serialise(w, e);
  w.put_bytes(std::vector<std::byte>((allocated - index_.size()) * kEntrySize));
  const std::uint64_t location = file_size_;
  write_at(w.bytes().data(), w.size(), location, "index");
  file_size_ += w.size();
  index_location_ = location;
  index_allocated_ = allocated;
  write_header();
}

void GsdWriter::write_frame(const FrameView& f) {
  check_frame_arrays(f, fields_, path_);
  if (f.n > std::numeric_limits<std::uint32_t>::max()) fail("more than 2^32-1 particles in a frame");
  const std::vector<std::size_t> order = order_by_id(f, path_);
  const std::size_t n = f.n;

  std::vector<Chunk> chunks;
  chunks.push_back(Chunk::make("configuration/step", kUint64, 1, std::vector<std::uint64_t>{f.step}));
  chunks.push_back(
      Chunk::make("configuration/box", kFloat32, 1,
                  std::vector<float>{static_cast<float>(f.box_len[0]), static_cast<float>(f.box_len[1]),
                                     static_cast<float>(f.box_len[2]), 0.0f, 0.0f, 0.0f}));
  if (next_frame_ == 0) {
    chunks.push_back(Chunk::make("configuration/dimensions", kUint8, 1, std::vector<std::uint8_t>{3}));
  }
  chunks.push_back(
      Chunk::make("particles/N", kUint32, 1, std::vector<std::uint32_t>{static_cast<std::uint32_t>(n)}));

  // Per-particle chunks, rows in id order. An empty frame has none: readers default them to N = 0.
  auto per_particle = [&](auto value_of, std::uint32_t m) {
    using T = decltype(value_of(std::size_t{0}, 0));
    std::vector<T> out;
    out.reserve(n * m);
    for (const std::size_t i : order) {
      for (std::uint32_t c = 0; c < m; ++c) out.push_back(value_of(i, static_cast<int>(c)));
    }
    return out;
  };

  if (fields_.species) {
    std::vector<std::string> types;
    if (f.species_names != nullptr) {
      types = *f.species_names;
    } else {
      // Unnamed species get LAMMPS-style numbers, matching the type column of the text dump.
      std::int32_t max_species = -1;
      for (std::size_t i = 0; i < n; ++i) max_species = std::max(max_species, f.species[i]);
      for (std::int32_t s = 0; s <= max_species; ++s) types.push_back(std::to_string(s + 1));
    }
    if (!types_written_ || types != last_types_) {
      std::size_t width = 1;
      for (const auto& t : types) width = std::max(width, t.size() + 1);
      std::vector<std::int8_t> table(types.size() * width, 0);
      for (std::size_t t = 0; t < types.size(); ++t)
        std::memcpy(&table[t * width], types[t].data(), types[t].size());
      if (!types.empty())
        chunks.push_back(Chunk::make("particles/types", kInt8, static_cast<std::uint32_t>(width), table));
      last_types_ = types;
      types_written_ = true;
    }
    if (n > 0) {
      chunks.push_back(Chunk::make(
          "particles/typeid", kUint32, 1,
          per_particle([&](std::size_t i, int) { return static_cast<std::uint32_t>(f.species[i]); }, 1)));
      if (f.species_mass != nullptr) {
        const auto& mass = *f.species_mass;
        for (std::size_t i = 0; i < n; ++i) {
          if (static_cast<std::size_t>(f.species[i]) >= mass.size()) {
            fail("step " + std::to_string(f.step) + ": no mass given for species index " +
                 std::to_string(f.species[i]));
          }
        }
        chunks.push_back(Chunk::make("particles/mass", kFloat32, 1,
                                     per_particle(
                                         [&](std::size_t i, int) {
                                           return static_cast<float>(
                                               mass[static_cast<std::size_t>(f.species[i])]);
                                         },
                                         1)));
      }
    }
  }
  if (n > 0 && fields_.position) {
    const double* xyz[3] = {f.x, f.y, f.z};
    double centre[3];
    float half[3];  // half of the box length as stored (float32) in configuration/box
    for (int d = 0; d < 3; ++d) {
      centre[d] = f.box_lo[d] + 0.5 * f.box_len[d];
      half[d] = 0.5f * static_cast<float>(f.box_len[d]);
    }
    // HOOMD requires -L/2 <= x < L/2 against the float32 box. A coordinate just below the upper
    // face can round up to +L/2 in float32, so the result is clamped into the half-open range
    // (a change of at most one float32 ulp).
    chunks.push_back(Chunk::make("particles/position", kFloat32, 3,
                                 per_particle(
                                     [&](std::size_t i, int d) {
                                       const float v = static_cast<float>(xyz[d][i] - centre[d]);
                                       return std::clamp(v, -half[d], std::nextafter(half[d], 0.0f));
                                     },
                                     3)));
  }
  if (n > 0 && fields_.velocity) {
    const double* v[3] = {f.vx, f.vy, f.vz};
    chunks.push_back(
        Chunk::make("particles/velocity", kFloat32, 3,
                    per_particle([&](std::size_t i, int d) { return static_cast<float>(v[d][i]); }, 3)));
  }
  if (n > 0 && fields_.image) {
    const std::int32_t* im[3] = {f.ix, f.iy, f.iz};
    chunks.push_back(Chunk::make("particles/image", kInt32, 3,
                                 per_particle([&](std::size_t i, int d) { return im[d][i]; }, 3)));
  }
  if (n > 0 && f.orientation != nullptr)
    chunks.push_back(Chunk::make("particles/orientation", kFloat32, 4,
                                 per_particle([&](std::size_t i, int c) { return static_cast<float>(f.orientation[4 * i + static_cast<std::size_t>(c)]); }, 4)));
  if (n > 0 && f.diameter != nullptr)
    chunks.push_back(Chunk::make("particles/diameter", kFloat32, 1,
                                 per_particle([&](std::size_t i, int) { return static_cast<float>(f.diameter[i]); }, 1)));
  if (n > 0 && next_frame_ == 0 && f.topology != nullptr && !f.topology->empty()) {
    // Rows of the particle chunks are in id order: row of id = its rank among the ids.
    std::vector<std::uint32_t> sorted_ids(n);
    for (std::size_t k = 0; k < n; ++k) sorted_ids[k] = f.id[order[k]];
    auto row = [&](std::uint32_t id) {
      const auto it = std::lower_bound(sorted_ids.begin(), sorted_ids.end(), id);
      if (it == sorted_ids.end() || *it != id)
        fail("step " + std::to_string(f.step) + ": a bond or angle names particle id " + std::to_string(id) +
             ", which is not in the frame");
      return static_cast<std::uint32_t>(it - sorted_ids.begin());
    };
    auto type_table = [&](const std::vector<std::string>* names, int count) {
      std::vector<std::string> t;
      for (int k = 0; k < count; ++k)
        t.push_back(names != nullptr && static_cast<std::size_t>(k) < names->size() ? (*names)[static_cast<std::size_t>(k)]
                                                                                    : std::to_string(k + 1));
      std::size_t width = 1;
      for (const auto& x : t) width = std::max(width, x.size() + 1);
      std::vector<std::int8_t> table(t.size() * width, 0);
      for (std::size_t k = 0; k < t.size(); ++k) std::memcpy(&table[k * width], t[k].data(), t[k].size());
      return std::make_pair(width, table);
    };
    const Topology& topo = *f.topology;
    // One kind of bonded term: its N, type names, type ids and groups of `width` particle rows.
    auto terms = [&](const char* prefix, const auto& list, const std::vector<std::string>* names, std::uint32_t width,
                     const auto& members) {
      if (list.empty()) return;
      int ntypes = 0;
      std::vector<std::uint32_t> typeid_, group;
      for (const auto& t : list) {
        ntypes = std::max(ntypes, t.type + 1);
        typeid_.push_back(static_cast<std::uint32_t>(t.type));
        for (const std::uint32_t id : members(t)) group.push_back(row(id));
      }
      const auto [name_width, table] = type_table(names, ntypes);
      const std::string p = prefix;
      chunks.push_back(Chunk::make(p + "/N", kUint32, 1, std::vector<std::uint32_t>{static_cast<std::uint32_t>(list.size())}));
      chunks.push_back(Chunk::make(p + "/types", kInt8, static_cast<std::uint32_t>(name_width), table));
      chunks.push_back(Chunk::make(p + "/typeid", kUint32, 1, typeid_));
      chunks.push_back(Chunk::make(p + "/group", kUint32, width, group));
    };
    terms("bonds", topo.bonds, f.bond_type_names, 2, [](const Bond& b) { return std::array<std::uint32_t, 2>{b.a, b.b}; });
    terms("angles", topo.angles, f.angle_type_names, 3,
          [](const Angle& a) { return std::array<std::uint32_t, 3>{a.a, a.b, a.c}; });
    terms("dihedrals", topo.dihedrals, f.dihedral_type_names, 4,
          [](const Dihedral& d) { return std::array<std::uint32_t, 4>{d.a, d.b, d.c, d.d}; });
  }
  if (n > 0 && fields_.force) {
    const double* fo[3] = {f.fx, f.fy, f.fz};
    chunks.push_back(
        Chunk::make("log/particles/force", kFloat32, 3,
                    per_particle([&](std::size_t i, int d) { return static_cast<float>(fo[d][i]); }, 3)));
  }
  if (n > 0 && fields_.id) {
    chunks.push_back(Chunk::make("log/particles/id", kUint32, 1,
                                 per_particle([&](std::size_t i, int) { return f.id[i]; }, 1)));
  }
  // Extra fields of the particle field list, in their own element type, as per-particle log chunks.
  for (const std::string& name : fields_.extra) {
    const FrameView::Extra& e = extra_array(f, name);
    if (n == 0) continue;
    visit_extra(e, 0, [&](auto first) {
      using T = decltype(first);
      chunks.push_back(Chunk::make("log/particles/" + name, gsd_type_of<T>(), 1, per_particle([&](std::size_t i, int) {
                                     T v{};
                                     visit_extra(e, i, [&](auto x) { v = static_cast<T>(x); });
                                     return v;
                                   }, 1)));
    });
  }

  // Readers search a frame's entries by name id, so they must be sorted by id within the frame.
  for (auto& c : chunks) c.id = name_id(c.name);
  std::sort(chunks.begin(), chunks.end(), [](const Chunk& a, const Chunk& b) { return a.id < b.id; });

  // Order of writes keeps the file valid at every point: data, then names, then the index entries
  // that reference both.
  std::vector<std::byte> data;
  const std::size_t first_new = index_.size();
  for (const auto& c : chunks) {
    IndexEntry e;
    e.frame = next_frame_;
    e.n = c.n;
    e.m = c.m;
    e.id = c.id;
    e.type = c.type;
    e.location = static_cast<std::int64_t>(file_size_ + data.size());
    data.insert(data.end(), c.data.begin(), c.data.end());
    index_.push_back(e);
  }
  try {
    write_at(data.data(), data.size(), file_size_, "frame data");
    file_size_ += data.size();
    commit_names();
    commit_index(first_new);
  } catch (...) {
    index_.resize(first_new);  // the frame is not in the file; keep memory consistent with it
    throw;
  }
  ++next_frame_;
}

}  // namespace mesodpd
