// tear: the one header that owns the differences between the two backends (host side; the device
// side's markers are kernels/hd.h).
//
// Kernels are written once, as TEAR_HD functors over raw pointers, and launched through Thrust
// algorithms with the execution policy of a backend system: Thrust's CUDA system on the GPU,
// its OpenMP system on the CPU. Stage code is templated on the system tag and never tests
// __CUDACC__ itself.
//
// It is split by concern: compiled_systems.h (TEAR_CUDA_SYSTEM, TEAR_FOR_EACH_SYSTEM),
// allocators.h (counting and pool allocators), vector.h (the vector, `resize_for_overwrite`,
// `raw`), traits.h (`Traits<System>`), launch.h (`for_each_index`, `exclusive_sum`) and
// transfer.h (`to_host`, `assign_from_host`, `ReadBack`, `Upload`).
#pragma once

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <new>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <thrust/copy.h>
#include <thrust/detail/config.h>
#include <thrust/fill.h>
#include <thrust/for_each.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/scan.h>
#include <thrust/system/omp/execution_policy.h>
#include <thrust/system/omp/vector.h>

#include "backend/allocators.h"
#include "backend/compiled_systems.h"
#include "backend/device_memory.h"
#include "backend/launch.h"
#include "backend/systems.h"
#include "backend/traits.h"
#include "backend/transfer.h"
#include "backend/vector.h"
#include "hd.h"
#include "tear/error.h"
