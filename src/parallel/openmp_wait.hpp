// How idle OpenMP threads wait at barriers: a short spin, then sleep, so that a run on cores shared
// with other jobs slows in proportion to the cores it lost instead of spinning against them.
#pragma once
#include <string>

namespace mesodpd {

// The spin (in libgomp's rounds of a pause instruction) a waiting thread spends before it sleeps.
// libgomp's default is 300,000 rounds (milliseconds), and it uses this same 1,000 (tens of
// microseconds) when it sees more threads than cores; see docs/performance.md "Busy machines".
inline constexpr const char* kOpenmpSpinCount = "1000";

// libgomp reads OMP_WAIT_POLICY and GOMP_SPINCOUNT once, when it is loaded, before main(). Where
// neither is set, this sets GOMP_SPINCOUNT = kOpenmpSpinCount and re-executes the program (same
// arguments, same process id), so that the runtime starts with it. Call it first in main(), before
// MPI or OpenMP start. Returns only if nothing was to be done or the re-execution failed (then the
// environment is left as it was and libgomp keeps its default).
void bound_openmp_spin_wait(char** argv);

// The wait policy this process runs with, for the run banner: "GOMP_SPINCOUNT=1000",
// "OMP_WAIT_POLICY=passive", or "libgomp default".
std::string openmp_wait_description();

}  // namespace mesodpd
