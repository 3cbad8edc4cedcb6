#include "tear/layout.h"

namespace tear {

std::uint64_t library_layout_digest() { return layout_digest_here(); }

}  // namespace tear
