// The sanitizer options of every program of a TEAR_SANITIZE build (tear, the tests, the fuzz
// replay), compiled in so that a sanitized program behaves the same run by ctest, by a test
// through the shell or by hand: every report stops it with a signal, leaks are reported, and the
// suppressions of third-party idioms apply (ubsan.supp beside this file; clang builds leave them
// out at compile time instead). ASAN_OPTIONS and UBSAN_OPTIONS in the environment still override.
extern "C" const char* __asan_default_options() {
  return "abort_on_error=1:detect_leaks=1:check_initialization_order=1:strict_init_order=1";
}

extern "C" const char* __ubsan_default_options() {
  return "halt_on_error=1:abort_on_error=1:print_stacktrace=1:suppressions=" TEAR_UBSAN_SUPPRESSIONS;
}
