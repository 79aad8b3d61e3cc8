// One run per output folder: a run holds an exclusive lock on a file in its output folder for as long
// as it lives, so a second run into the same folder (another process, or a second simulation in the
// same process) is refused instead of tearing the first one's files.
#pragma once
#include <filesystem>

namespace mesodpd {

// Name of the lock file inside the output folder.
inline constexpr const char* kOutputLockName = "mesodpd.lock";

class OutputLock {
 public:
  OutputLock() = default;
  // Creates `dir` if needed and takes the lock, writing this process's pid and host into the lock
  // file. The lock is flock(2)'s, on an open file description: the kernel drops it when the holder
  // exits for whatever reason, so the file of a killed run is stale and simply taken over. Throws
  // ConfigError naming the folder (and the holder's pid and host, as its lock file tells them) when
  // another live run holds it. Then removes the temporaries left by killed runs' atomic writes
  // (NAME.tmp.PID, io/atomic_file), which no live run can own while this lock is held.
  explicit OutputLock(const std::filesystem::path& dir);
  // Releases the lock and removes the lock file.
  ~OutputLock();
  OutputLock(OutputLock&& other) noexcept;
  OutputLock& operator=(OutputLock&& other) noexcept;
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  bool held() const { return fd_ >= 0; }
  const std::filesystem::path& dir() const { return dir_; }

 private:
  void release() noexcept;

  std::filesystem::path dir_, key_;  // key_: the folder as this process registered it
  int fd_ = -1;
};

}  // namespace mesodpd
