// Implementation of write_file_atomically: temporary file, fsync, rename.
#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <exception>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

#include "io/output_file.hpp"
#include "mesodpd/config_error.hpp"

namespace mesodpd {
namespace {

std::string quoted(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

// std::ofstream::flush only reaches the kernel; fsync is what makes the bytes durable before the
// rename publishes them. Without it a power loss could leave a renamed but empty file.
void fsync_file(const std::filesystem::path& p) {
  const int fd = ::open(p.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw std::system_error(errno, std::generic_category(), "open for fsync");
  const int rc = ::fsync(fd);
  const int saved = errno;
  ::close(fd);
  if (rc != 0) throw std::system_error(saved, std::generic_category(), "fsync");
}

// Makes the rename itself durable. Best effort: the new file is already in place when this runs,
// so failing here must not report the write as failed (some file systems refuse directory fsync).
void fsync_directory(const std::filesystem::path& dir) noexcept {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  (void)::fsync(fd);
  ::close(fd);
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& writer) {
  std::filesystem::path tmp = path;
  tmp += ".tmp." + std::to_string(::getpid());
  try {
    {
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      if (!out) {
        throw std::system_error(errno, std::generic_category(), "cannot create " + quoted(tmp));
      }
      writer(out);
      if (const int err = injected_output_fault(path); err != 0)
        throw std::system_error(err, std::generic_category(), "write");
      out.flush();
      if (!out) throw std::runtime_error("write error on " + quoted(tmp));
      out.close();
      if (out.fail()) throw std::runtime_error("close failed on " + quoted(tmp));
    }
    fsync_file(tmp);
    std::filesystem::rename(tmp, path);
  } catch (const std::exception& e) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw ConfigError("cannot write file " + quoted(path) +
                      " (previous content left unchanged): " + e.what());
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw ConfigError("cannot write file " + quoted(path) +
                      " (previous content left unchanged): unknown error");
  }
  fsync_directory(path.parent_path());
}

void write_file_atomically(const std::filesystem::path& path, std::span<const std::byte> bytes) {
  write_file_atomically(path, [bytes](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  });
}

}  // namespace mesodpd
