// Implementation of OutputLock: flock on DIR/mesodpd.lock, plus a list of the folders this process
// holds (flock alone would not tell two simulations of one process apart on every file system).
#include "io/output_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <utility>

#include "mesodpd/config_error.hpp"

namespace mesodpd {

namespace {

std::mutex& held_mutex() {
  static std::mutex m;
  return m;
}
std::set<std::string>& held_here() {
  static std::set<std::string> s;
  return s;
}

std::string host_name() {
  char buf[256] = {};
  if (::gethostname(buf, sizeof buf - 1) != 0) return "unknown host";
  return buf;
}

// The holder as its lock file describes it ("pid 123 on host h"), or a plain phrase if unreadable.
std::string holder_of(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  return line.empty() ? std::string("another run") : line;
}

// A temporary of io/atomic_file: NAME.tmp.DIGITS.
bool atomic_temporary(const std::string& name) {
  const auto at = name.rfind(".tmp.");
  if (at == std::string::npos || at == 0 || at + 5 == name.size()) return false;
  for (std::size_t k = at + 5; k < name.size(); ++k)
    if (name[k] < '0' || name[k] > '9') return false;
  return true;
}

}  // namespace

OutputLock::OutputLock(const std::filesystem::path& dir) : dir_(dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) throw ConfigError("cannot create the output folder '" + dir_.string() + "': " + ec.message());
  const std::filesystem::path file = dir_ / kOutputLockName;
  const std::filesystem::path canonical = std::filesystem::weakly_canonical(dir_, ec);
  key_ = ec ? std::filesystem::absolute(dir_) : canonical;
  auto refuse = [&](const std::string& who) {
    throw ConfigError("output folder '" + dir_.string() + "' is in use by " + who + " (lock file '" + file.string() +
                      "'); wait for that run to end, or give this run another output folder");
  };
  {
    const std::lock_guard<std::mutex> guard(held_mutex());
    if (held_here().count(key_.string()) != 0) refuse("another simulation of this process, which must end (or be closed) first");
    held_here().insert(key_.string());
  }
  try {
    // The lock file may be removed by a holder that ends between our open and our flock: the lock is
    // then on a file nobody else will see, so the file must still be the one at the path afterwards.
    for (int attempt = 0;; ++attempt) {
      const int fd = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
      if (fd < 0)
        throw ConfigError("cannot create the lock file '" + file.string() + "' of the output folder: " +
                          std::strerror(errno));
      if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
        const int err = errno;
        ::close(fd);
        if (err == EWOULDBLOCK) refuse(holder_of(file));
        throw ConfigError("cannot lock '" + file.string() + "': " + std::strerror(err));
      }
      struct stat mine {}, there {};
      if (::fstat(fd, &mine) == 0 && ::stat(file.c_str(), &there) == 0 && mine.st_ino == there.st_ino &&
          mine.st_dev == there.st_dev) {
        fd_ = fd;
        break;
      }
      ::close(fd);
      if (attempt > 100) throw ConfigError("cannot lock '" + file.string() + "': it keeps being replaced");
    }
    std::ostringstream who;
    who << "pid " << ::getpid() << " on host " << host_name() << '\n';
    const std::string text = who.str();
    if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, text.data(), text.size(), 0) != static_cast<ssize_t>(text.size()))
      throw ConfigError("cannot write the lock file '" + file.string() + "': " + std::strerror(errno));
  } catch (...) {
    release();
    throw;
  }
  // Temporaries of atomic writes by runs that were killed in the middle of one.
  for (const auto& entry : std::filesystem::directory_iterator(dir_, ec)) {
    if (!atomic_temporary(entry.path().filename().string())) continue;
    std::error_code ignored;
    if (entry.is_regular_file(ignored)) std::filesystem::remove(entry.path(), ignored);
  }
}

OutputLock::~OutputLock() { release(); }

OutputLock::OutputLock(OutputLock&& other) noexcept
    : dir_(std::move(other.dir_)), key_(std::move(other.key_)), fd_(std::exchange(other.fd_, -1)) {
  other.key_.clear();
}

OutputLock& OutputLock::operator=(OutputLock&& other) noexcept {
  if (this != &other) {
    release();
    dir_ = std::move(other.dir_);
    key_ = std::move(other.key_);
    fd_ = std::exchange(other.fd_, -1);
    other.key_.clear();
  }
  return *this;
}

void OutputLock::release() noexcept {
  if (fd_ >= 0) {
    // Removed while still locked: a run that opened it meanwhile finds its lock on a removed file and
    // opens the path again (see the constructor).
    std::error_code ignored;
    std::filesystem::remove(dir_ / kOutputLockName, ignored);
    ::close(fd_);
    fd_ = -1;
  }
  if (!key_.empty()) {
    const std::lock_guard<std::mutex> guard(held_mutex());
    held_here().erase(key_.string());
    key_.clear();
  }
}

}  // namespace mesodpd
