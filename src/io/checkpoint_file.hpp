// The checkpoint container: a versioned, checksummed envelope around an opaque payload, so a
// restart detects a foreign, truncated, corrupted or newer-format file before trusting any byte.
//
// Layout (little-endian):
//   16 bytes  magic "MESODPD-CKPT" followed by four NUL bytes
//   uint32    container format version (kCheckpointFormatVersion)
//   uint64    payload size in bytes
//   payload
//   uint64    checkpoint_checksum(payload)
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace mesodpd {

inline constexpr std::uint32_t kCheckpointFormatVersion = 1;
inline constexpr std::array<char, 16> kCheckpointMagic = {'M', 'E', 'S', 'O', 'D', 'P', 'D', '-',
                                                          'C', 'K', 'P', 'T', 0,   0,   0,   0};

// 64-bit FNV-1a over the bytes. Not cryptographic: it guards against truncation and bit rot, not
// against deliberate tampering, which a local restart file does not need.
std::uint64_t checkpoint_checksum(std::span<const std::byte> bytes);

// Wraps the payload in the container and replaces `path` atomically (see io/atomic_file.hpp), so an
// interrupted write never destroys the previous checkpoint. Throws ConfigError naming the file.
void write_checkpoint_file(const std::filesystem::path& path, std::span<const std::byte> payload);

// Returns the payload after checking magic, version, size and checksum. Throws ConfigError naming
// the file for: missing file, bad magic, unsupported version, truncation, trailing bytes, checksum
// mismatch.
std::vector<std::byte> read_checkpoint_file(const std::filesystem::path& path);

}  // namespace mesodpd
