// A stand-in for a libtear.so built from other headers than the Python module: preloaded
// (LD_PRELOAD), its library_layout_digest takes the place of the real library's, and importing
// `tear` must fail with an ImportError that says so (tests/python/test_module.py, tear/layout.h).
#include <cstdint>

namespace tear {

std::uint64_t library_layout_digest() { return 0; }

}  // namespace tear
