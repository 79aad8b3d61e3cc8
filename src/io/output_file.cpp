// Implementation of OutputFile: unbuffered POSIX writes of whole rows, checked byte for byte.
#include "io/output_file.hpp"

#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <mutex>
#include <utility>

namespace mesodpd {

namespace {

std::mutex& hook_mutex() {
  static std::mutex m;
  return m;
}
OutputFaultHook& hook() {
  static OutputFaultHook h;
  return h;
}

}  // namespace

void set_output_fault_hook(OutputFaultHook h) {
  const std::lock_guard<std::mutex> lock(hook_mutex());
  hook() = std::move(h);
}

int injected_output_fault(const std::filesystem::path& path) {
  const std::lock_guard<std::mutex> lock(hook_mutex());
  return hook() ? hook()(path) : 0;
}

OutputFile::~OutputFile() {
  if (fd_ < 0) return;
  if (failed_.empty() && !pending_.empty()) {
    try {
      write_all(pending_);
    } catch (...) {  // best effort only: close() is where errors are reported
    }
  }
  ::close(fd_);
}

OutputFile::OutputFile(OutputFile&& other) noexcept
    : path_(std::move(other.path_)),
      fd_(std::exchange(other.fd_, -1)),
      pending_(std::move(other.pending_)),
      failed_(std::move(other.failed_)) {}

OutputFile& OutputFile::operator=(OutputFile&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    path_ = std::move(other.path_);
    fd_ = std::exchange(other.fd_, -1);
    pending_ = std::move(other.pending_);
    failed_ = std::move(other.failed_);
  }
  return *this;
}

void OutputFile::open(std::filesystem::path path, Mode mode) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  path_ = std::move(path);
  pending_.clear();
  failed_.clear();
  const int flags = O_WRONLY | O_CREAT | O_CLOEXEC | (mode == Mode::Append ? O_APPEND : O_TRUNC);
  fd_ = ::open(path_.c_str(), flags, 0644);
  if (fd_ < 0) throw OutputError(path_, std::string("cannot open: ") + std::strerror(errno));
}

void OutputFile::write_all(std::string_view bytes) {
  if (!failed_.empty()) throw OutputError(path_, failed_ + " (an earlier write failed)");
  if (fd_ < 0) throw OutputError(path_, "the file is not open");
  auto fail = [&](int err, std::size_t lost) {
    failed_ = std::string(std::strerror(err)) + " (" + std::to_string(lost) + " bytes not written)";
    throw OutputError(path_, failed_);
  };
  if (const int err = injected_output_fault(path_); err != 0) fail(err, bytes.size());
  const char* p = bytes.data();
  std::size_t left = bytes.size();
  while (left > 0) {
    const ssize_t done = ::write(fd_, p, left);
    if (done < 0) {
      if (errno == EINTR) continue;
      fail(errno, left);
    }
    if (done == 0) fail(EIO, left);
    p += done;
    left -= static_cast<std::size_t>(done);
  }
}

void OutputFile::write(std::string_view text) {
  pending_ += text;
  flush();
}

void OutputFile::flush() {
  if (pending_.empty() && failed_.empty()) return;
  std::string bytes;
  bytes.swap(pending_);  // what failed is not written again later, after a gap
  write_all(bytes);
}

void OutputFile::close() {
  if (fd_ < 0) return;
  flush();
  const int rc = ::close(fd_);
  const int err = errno;
  fd_ = -1;
  if (rc != 0 && err != EINTR) throw OutputError(path_, std::string("close failed: ") + std::strerror(err));
}

void trim_csv_after_step(const std::filesystem::path& path, std::uint64_t last_step) {
  std::ifstream in(path, std::ios::binary);
  std::string line, kept;
  bool trimmed = false;
  for (bool header = true; std::getline(in, line); header = false) {
    const bool complete = !in.eof();  // a last line without '\n' was cut short by a crash
    const auto step = leading_step(line);
    if (!complete || (!header && (!step || *step > last_step))) {
      trimmed = true;
      break;
    }
    kept += line;
    kept += '\n';
  }
  in.close();
  if (trimmed) write_file_atomically(path, [&](std::ostream& os) { os << kept; });
}

std::optional<std::uint64_t> leading_step(const std::string& text) {
  std::uint64_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc{} || end == text.data()) return std::nullopt;
  return v;
}

}  // namespace mesodpd
