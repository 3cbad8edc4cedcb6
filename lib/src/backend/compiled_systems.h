// tear: which backend systems this translation unit compiles: TEAR_CUDA_SYSTEM (1 in a CUDA build's
// .cu files, where nvcc compiles device code) and TEAR_FOR_EACH_SYSTEM.
#pragma once

#include <thrust/detail/config.h>

#include "backend/systems.h"

#if TEAR_WITH_CUDA && defined(__CUDACC__)
#include <thrust/system/cuda/execution_policy.h>
#include <thrust/system/cuda/vector.h>
#include <cub/block/block_load.cuh>
#include <cub/block/block_scan.cuh>
#include <cub/block/block_store.cuh>
#define TEAR_CUDA_SYSTEM 1
#else
#define TEAR_CUDA_SYSTEM 0
#endif

/// Instantiates `MACRO(System)` for every system this translation unit can run: the OpenMP
/// system always, the CUDA system in a CUDA build.
#if TEAR_CUDA_SYSTEM
#define TEAR_FOR_EACH_SYSTEM(MACRO) \
  MACRO(::tear::backend::Omp)       \
  MACRO(::tear::backend::Cuda)
#else
#define TEAR_FOR_EACH_SYSTEM(MACRO) MACRO(::tear::backend::Omp)
#endif
