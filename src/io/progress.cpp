// Progress reporting to stderr.
#include "io/progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>
#include <string>

namespace mesodpd {

ProgressReporter::ProgressReporter(std::uint64_t first_step, std::uint64_t last_step)
    : first_(first_step), last_(last_step), tty_(isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()), last_draw_(start_) {}

void ProgressReporter::update(std::uint64_t step) {
  const auto now = std::chrono::steady_clock::now();
  if (tty_) {
    if (now - last_draw_ > std::chrono::milliseconds(200) || step == last_) {
      last_draw_ = now;
      draw(step, false);
    }
  } else {
    const std::uint64_t span = last_ > first_ ? last_ - first_ : 1;
    const int decile = static_cast<int>(10 * (step - first_) / span);
    if (decile != last_decile_) {
      last_decile_ = decile;
      draw(step, false);
    }
  }
}

void ProgressReporter::draw(std::uint64_t step, bool final) {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const std::uint64_t done = step - first_, span = last_ > first_ ? last_ - first_ : 1;
  const double frac = static_cast<double>(done) / static_cast<double>(span);
  const double rate = elapsed > 0 ? static_cast<double>(done) / elapsed : 0.0;
  const double eta = rate > 0 ? static_cast<double>(last_ - step) / rate : 0.0;
  if (tty_) {
    const int width = 30, filled = static_cast<int>(frac * width);
    fmt::print(stderr, "\r[{}{}] {:5.1f}%  step {}/{}  {:.0f} steps/s  ETA {:.0f} s   ", std::string(static_cast<std::size_t>(filled), '#'),
               std::string(static_cast<std::size_t>(width - filled), '.'), 100 * frac, step, last_, rate, eta);
    if (final) fmt::print(stderr, "\n");
  } else {
    fmt::print(stderr, "step {}/{} ({:.0f}%), {:.0f} steps/s, elapsed {:.0f} s, ETA {:.0f} s\n", step, last_, 100 * frac,
               rate, elapsed, eta);
  }
  std::fflush(stderr);
}

void ProgressReporter::finish() {
  if (finished_) return;
  finished_ = true;
  if (tty_) draw(last_, true);
}

}  // namespace mesodpd
