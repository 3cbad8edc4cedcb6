// tear: the device side of `tear bench`.
#pragma once

#include <cstddef>

#include "backend/systems.h"

namespace tear::backend {

/// Seconds of the fastest of `repeats` copies of a `bytes`-long buffer on `System`, each waited for.
template <class System>
double fastest_copy_seconds(std::size_t bytes, int repeats);

}  // namespace tear::backend
