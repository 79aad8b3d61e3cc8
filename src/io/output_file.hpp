// Checked output files: every byte the program writes to its output folder goes through here (text
// files written row by row) or through io/atomic_file (whole files), and a failed write is an error
// naming the file, never a silently shorter file.
#pragma once
#include <concepts>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "mesodpd/config_error.hpp"

namespace mesodpd {

// A file of the output could not be opened, written or closed (full disk, quota, I/O error). A
// ConfigError, so the program exits with code 2 like any other input/output problem; the message names
// the file and the system's reason.
class OutputError : public ConfigError {
 public:
  OutputError(const std::filesystem::path& path, const std::string& what)
      : ConfigError("cannot write output file '" + path.string() + "': " + what), path_(path) {}
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// A text file written by appending: text collects in memory and goes to the file at flush() (or
// close()), which checks that every byte arrived and throws OutputError otherwise. Once a write has
// failed the file stays failed: later flushes throw again rather than write after a gap.
class OutputFile {
 public:
  enum class Mode { Truncate, Append };

  OutputFile() = default;
  // Opens (creating if needed); throws OutputError when the file cannot be opened.
  OutputFile(std::filesystem::path path, Mode mode) { open(std::move(path), mode); }
  // Closes the file. Text not yet flushed is written on a best-effort basis: call close() to learn
  // whether it arrived.
  ~OutputFile();
  OutputFile(OutputFile&& other) noexcept;
  OutputFile& operator=(OutputFile&& other) noexcept;
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  void open(std::filesystem::path path, Mode mode);
  bool is_open() const { return fd_ >= 0; }
  const std::filesystem::path& path() const { return path_; }

  // Text for the next flush. Only text and integers: numbers with a fraction are formatted by the
  // caller, which decides their precision.
  OutputFile& operator<<(std::string_view text) {
    pending_ += text;
    return *this;
  }
  OutputFile& operator<<(const char* text) { return *this << std::string_view(text); }
  OutputFile& operator<<(const std::string& text) { return *this << std::string_view(text); }
  OutputFile& operator<<(char c) {
    pending_ += c;
    return *this;
  }
  template <std::integral T>
    requires(!std::same_as<T, char> && !std::same_as<T, bool>)
  OutputFile& operator<<(T value) {
    pending_ += std::to_string(value);
    return *this;
  }

  // Writes `text` and everything pending now.
  void write(std::string_view text);
  // Writes what is pending; throws OutputError (naming the file) if any of it could not be written.
  void flush();
  // flush(), then closes the file; a failure to close is reported like a failed write.
  void close();

 private:
  void write_all(std::string_view bytes);

  std::filesystem::path path_;
  int fd_ = -1;
  std::string pending_;
  std::string failed_;  // the first error, once a write failed
};

// For tests: a function asked before each write of an output file (OutputFile and
// write_file_atomically) that returns an errno value to fail that write with, or 0 to let it through.
// An empty function (the default) injects nothing.
using OutputFaultHook = std::function<int(const std::filesystem::path&)>;
void set_output_fault_hook(OutputFaultHook hook);
// The injected errno for a write to `path` (0 when none); used by the writers of this module.
int injected_output_fault(const std::filesystem::path& path);

// The leading unsigned integer of `text` (the step of a thermo row or of a dump frame), or nothing: a
// restarted run drops the rows and frames of its files that lie after the checkpoint's step.
std::optional<std::uint64_t> leading_step(const std::string& text);

// A restarted run continues from the checkpoint's step K, but the files in the output directory may
// go further: the run that wrote the checkpoint went on (and perhaps blew up) before the restart. This
// drops the rows of a CSV file (a header line, then rows that start with their step, in increasing step
// order) from the first one after K, or the first damaged one, by rewriting the file atomically, so that
// appending does not repeat steps.
void trim_csv_after_step(const std::filesystem::path& path, std::uint64_t last_step);

}  // namespace mesodpd
