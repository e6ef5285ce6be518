#pragma once
// VARSPH_HD marks a function callable on the host and on a CUDA device (docs/gpu.md): the physics terms
// and kernels are written once and run in the OpenMP loops (src/physics/pair_loop.hpp) and in the device
// loops (src/exec/). Plain inline C++ when the translation unit is not compiled by nvcc.
#if defined(__CUDACC__)
#define VARSPH_HD __host__ __device__
#else
#define VARSPH_HD
#endif
