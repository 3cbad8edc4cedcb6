#include <cstdlib>

#if TEAR_CATCH2_MAJOR >= 3
#include <catch2/catch_session.hpp>
#else
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#endif

int main(int argc, char* argv[]) {
  // Every tear of the suite checks the backend's quick crack check against the host's plan: a
  // substep it skips must be one whose plan cuts nothing (lib/src/cloth/cloth_stepping.h).
  setenv("TEAR_DEBUG_CRACK_CHECK", "1", 0);
  return Catch::Session().run(argc, argv);
}
