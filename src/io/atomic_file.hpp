// Crash-safe replacement of a whole file (checkpoints, final outputs): a reader sees either the
// complete old file or the complete new one, never a half-written mixture.
#pragma once
#include <cstddef>
#include <filesystem>
#include <functional>
#include <ostream>
#include <span>

namespace mesodpd {

// Writes `path` by calling `writer` on a stream to a temporary file in the same directory
// (path + ".tmp.<pid>"), flushing and fsync-ing it, then renaming it over `path`. The rename is
// atomic on POSIX file systems because source and target share a directory. If the writer throws
// or any step fails, the temporary is removed, `path` keeps its previous content (or stays absent),
// and a ConfigError naming `path` is thrown.
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& writer);

// Same, for content already held in memory.
void write_file_atomically(const std::filesystem::path& path, std::span<const std::byte> bytes);

}  // namespace mesodpd
