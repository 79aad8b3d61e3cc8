// Run progress: a redrawn bar with rate and ETA on a terminal, a plain log line every 10% otherwise.
#pragma once
#include <chrono>
#include <cstdint>

namespace mesodpd {

class ProgressReporter {
 public:
  ProgressReporter(std::uint64_t first_step, std::uint64_t last_step);
  void update(std::uint64_t step);
  void finish();

 private:
  void draw(std::uint64_t step, bool final);

  std::uint64_t first_, last_;
  bool tty_;
  std::chrono::steady_clock::time_point start_, last_draw_;
  int last_decile_ = -1;
  bool finished_ = false;
};

}  // namespace mesodpd
