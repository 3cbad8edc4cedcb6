// Catch2 v2 (Debian 12) or v3 (later releases): the one CMake found (TEAR_CATCH2_MAJOR).
#pragma once
#if TEAR_CATCH2_MAJOR >= 3
#include <catch2/catch_all.hpp>
using Catch::Approx;
#else
#include <catch2/catch.hpp>
#endif
