// Implementation of the checkpoint container (see checkpoint_file.hpp for the layout).
#include "io/checkpoint_file.hpp"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <system_error>

#include "io/atomic_file.hpp"
#include "io/byte_buffer.hpp"
#include "mesodpd/config_error.hpp"

namespace mesodpd {
namespace {

constexpr std::size_t kHeaderBytes = sizeof(kCheckpointMagic) + sizeof(std::uint32_t) + sizeof(std::uint64_t);
constexpr std::size_t kTrailerBytes = sizeof(std::uint64_t);

std::string describe(const std::filesystem::path& path) { return "checkpoint file '" + path.string() + "'"; }

std::vector<std::byte> slurp(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw ConfigError(describe(path) + " does not exist");
  if (std::filesystem::is_directory(path, ec)) throw ConfigError(describe(path) + " is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(describe(path) + " cannot be opened for reading");
  std::vector<char> raw((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw ConfigError(describe(path) + ": read error");
  std::vector<std::byte> bytes(raw.size());
  if (!raw.empty()) std::memcpy(bytes.data(), raw.data(), raw.size());
  return bytes;
}

}  // namespace

std::uint64_t checkpoint_checksum(std::span<const std::byte> bytes) {
  // FNV-1a, 64-bit parameters (offset basis and prime from the FNV specification).
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  for (const std::byte b : bytes) {
    hash ^= static_cast<std::uint64_t>(b);
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

void write_checkpoint_file(const std::filesystem::path& path, std::span<const std::byte> payload) {
  ByteWriter header;
  header.put(kCheckpointMagic);
  header.put(kCheckpointFormatVersion);
  header.put<std::uint64_t>(payload.size());
  const std::uint64_t checksum = checkpoint_checksum(payload);
  // Stream the three parts instead of concatenating them: a checkpoint can be large and a second
  // full copy in memory buys nothing.
  write_file_atomically(path, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(header.bytes().data()),
              static_cast<std::streamsize>(header.size()));
    out.write(reinterpret_cast<const char*>(payload.data()), static_cast<std::streamsize>(payload.size()));
    out.write(reinterpret_cast<const char*>(&checksum), sizeof(checksum));
  });
}

std::vector<std::byte> read_checkpoint_file(const std::filesystem::path& path) {
  const std::vector<std::byte> bytes = slurp(path);
  const std::string what = describe(path);

  // Magic first, on whatever prefix exists: a short file that is not ours should say "not a
  // checkpoint" rather than "truncated".
  if (bytes.empty()) throw ConfigError(what + " is empty (truncated)");
  const std::size_t magic_avail = std::min(bytes.size(), kCheckpointMagic.size());
  if (std::memcmp(bytes.data(), kCheckpointMagic.data(), magic_avail) != 0) {
    throw ConfigError(what + " is not a mesodpd checkpoint (bad magic number)");
  }
  if (bytes.size() < kHeaderBytes + kTrailerBytes) {
    throw ConfigError(what + " is truncated: " + std::to_string(bytes.size()) + " bytes, shorter than the " +
                      std::to_string(kHeaderBytes + kTrailerBytes) + "-byte container header and trailer");
  }

  ByteReader reader(bytes, what);
  (void)reader.get_bytes(kCheckpointMagic.size());
  const auto version = reader.get<std::uint32_t>();
  if (version != kCheckpointFormatVersion) {
    throw ConfigError(what + " has checkpoint format version " + std::to_string(version) +
                      ", but this build reads only version " + std::to_string(kCheckpointFormatVersion));
  }
  const auto payload_size = reader.get<std::uint64_t>();
  const std::size_t available = bytes.size() - kHeaderBytes - kTrailerBytes;
  if (payload_size > available) {
    throw ConfigError(what + " is truncated: header announces a payload of " + std::to_string(payload_size) +
                      " bytes, but the file holds " + std::to_string(bytes.size()) +
                      " bytes in total (expected " + std::to_string(kHeaderBytes + kTrailerBytes) + " + " +
                      std::to_string(payload_size) + ")");
  }
  if (payload_size < available) {
    throw ConfigError(what + " has " + std::to_string(available - payload_size) +
                      " unexpected bytes after the payload (file damaged or concatenated)");
  }
  const auto payload = reader.get_bytes(static_cast<std::size_t>(payload_size));
  const auto stored = reader.get<std::uint64_t>();
  const auto computed = checkpoint_checksum(payload);
  if (stored != computed) {
    throw ConfigError(what + " is corrupted: checksum mismatch (stored " + std::to_string(stored) +
                      ", computed " + std::to_string(computed) + ")");
  }
  return {payload.begin(), payload.end()};
}

}  // namespace mesodpd
