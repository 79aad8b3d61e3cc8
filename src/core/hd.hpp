// Host/device annotation so physics headers compile unchanged under g++ and nvcc.
#pragma once
#if defined(__CUDACC__)
#define MESODPD_HD __host__ __device__ inline
#else
#define MESODPD_HD inline
#endif
