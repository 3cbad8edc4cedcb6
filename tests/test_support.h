// Shared helpers of the test suite.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <string>

#include "tear/device.h"

namespace tear::test {

/// The backend under test: TEAR_TEST_DEVICE=cuda runs the suite on the GPU; the default is cpu.
inline Device test_device() {
  const char* env = std::getenv("TEAR_TEST_DEVICE");
  return select_device(env && *env ? env : "cpu");
}

/// Seed of a property test: TEAR_TEST_SEED when set, else `fallback`. Print it on failure.
inline std::uint64_t test_seed(std::uint64_t fallback) {
  const char* env = std::getenv("TEAR_TEST_SEED");
  return env && *env ? std::strtoull(env, nullptr, 10) : fallback;
}

inline std::string source_path(const std::string& relative) { return std::string(TEAR_SOURCE_DIR) + "/" + relative; }

/// Sets an environment variable for a scope, then restores it (or unsets it).
class ScopedEnvironment {
 public:
  ScopedEnvironment(const char* name, const char* value) : name_(name) {
    const char* old = std::getenv(name);
    had_ = old != nullptr;
    if (had_) old_ = old;
    setenv(name, value, 1);
  }
  ~ScopedEnvironment() {
    if (had_)
      setenv(name_.c_str(), old_.c_str(), 1);
    else
      unsetenv(name_.c_str());
  }
  ScopedEnvironment(const ScopedEnvironment&) = delete;
  ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;

 private:
  std::string name_, old_;
  bool had_ = false;
};


}  // namespace tear::test
