// The OpenMP wait policy the program chooses for itself (see openmp_wait.hpp).
#include "parallel/openmp_wait.hpp"

#include <unistd.h>

#include <cstdlib>

namespace mesodpd {

void bound_openmp_spin_wait(char** argv) {
#if defined(__linux__)
  // A choice made by the user, either way, stands.
  if (std::getenv("OMP_WAIT_POLICY") != nullptr || std::getenv("GOMP_SPINCOUNT") != nullptr) return;
  if (setenv("GOMP_SPINCOUNT", kOpenmpSpinCount, 1) != 0) return;
  execv("/proc/self/exe", argv);
  unsetenv("GOMP_SPINCOUNT");  // still here: the runtime keeps its default, and the banner says so
#else
  (void)argv;
#endif
}

std::string openmp_wait_description() {
  if (const char* policy = std::getenv("OMP_WAIT_POLICY")) {
    std::string text = std::string("OMP_WAIT_POLICY=") + policy;
    if (const char* spin = std::getenv("GOMP_SPINCOUNT")) text += std::string(", GOMP_SPINCOUNT=") + spin;
    return text;
  }
  if (const char* spin = std::getenv("GOMP_SPINCOUNT")) return std::string("GOMP_SPINCOUNT=") + spin;
  return "libgomp default";
}

}  // namespace mesodpd
