// Host/device annotation so physics headers compile unchanged under g++ and nvcc.
// MESODPD_HD_FORCE: the same, always inlined. For a law's evaluator and the arithmetic it calls (the
// power of physics/power.hpp), which the pair loop needs inlined to vectorise; the compiler's own size
// heuristics leave a law with two inlined powers as a call per pair.
#pragma once
#if defined(__CUDACC__)
#define MESODPD_HD __host__ __device__ inline
#define MESODPD_HD_FORCE __host__ __device__ __forceinline__
#else
#define MESODPD_HD inline
#define MESODPD_HD_FORCE [[gnu::always_inline]] inline
#endif
