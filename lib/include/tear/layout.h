// tear: whether a program and the libtear.so it loaded were built from the same headers.
//
// The types of the API are passed by value and allocated on both sides of the library's boundary
// (a CutScript returned by parse_cut_script, a Cloth made with std::make_unique), so a program
// built against one version of these headers that loads a libtear.so built from another (an older
// build found first through LD_LIBRARY_PATH, say) corrupts memory instead of failing: the Python
// module did so in tear.Script(dict). libtear.so's name carries no version, so the loader cannot
// tell; a program compares `layout_digest_here()` with `library_layout_digest()` instead (the
// Python module does so on import). A libtear.so older than this check lacks the function, and
// the loader refuses it by name.
#pragma once

#include <cstddef>
#include <cstdint>

#include "tear/cloth.h"
#include "tear/cut_script.h"
#include "tear/frame_path.h"
#include "tear/mesh.h"
#include "tear/read_mesh.h"
#include "tear/run_cuts.h"
#include "tear/simulation_options.h"
#include "tear/usd_layer.h"
#include "tear/validate_mesh.h"

namespace tear {

/// A digest (FNV-1a) of the sizes and alignments of the API's types as this translation unit sees
/// them. Not a full check: a change that keeps every size (two fields swapped) goes unseen.
inline std::uint64_t layout_digest_here() {
  std::uint64_t h = 14695981039346656037ull;
  const auto mix = [&h](std::size_t v) {
    for (int i = 0; i < 8; ++i) {
      h ^= (static_cast<std::uint64_t>(v) >> (8 * i)) & 0xFF;
      h *= 1099511628211ull;
    }
  };
#define TEAR_LAYOUT_MIX(T) (mix(sizeof(T)), mix(alignof(T)))
  TEAR_LAYOUT_MIX(Mesh);
  TEAR_LAYOUT_MIX(ReadOptions);
  TEAR_LAYOUT_MIX(Cut);
  TEAR_LAYOUT_MIX(CutScript);
  TEAR_LAYOUT_MIX(Key);
  TEAR_LAYOUT_MIX(Pin);
  TEAR_LAYOUT_MIX(Collider);
  TEAR_LAYOUT_MIX(ChebyshevOptions);
  TEAR_LAYOUT_MIX(Weave);
  TEAR_LAYOUT_MIX(TearingOptions);
  TEAR_LAYOUT_MIX(SimulationOptions);
  TEAR_LAYOUT_MIX(FrameResult);
  TEAR_LAYOUT_MIX(RunOptions);
  TEAR_LAYOUT_MIX(RunPlan);
  TEAR_LAYOUT_MIX(RunSummary);
  TEAR_LAYOUT_MIX(CutLine);
  TEAR_LAYOUT_MIX(CutOptions);
  TEAR_LAYOUT_MIX(CutStats);
  TEAR_LAYOUT_MIX(Cloth);
  TEAR_LAYOUT_MIX(UsdLayerOptions);
  TEAR_LAYOUT_MIX(MeshReport);
  TEAR_LAYOUT_MIX(FramePattern);
#undef TEAR_LAYOUT_MIX
  return h;
}

/// `layout_digest_here()` as libtear.so was compiled.
std::uint64_t library_layout_digest();

}  // namespace tear
