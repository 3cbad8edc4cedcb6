// tear: the paper's scene (a square sheet torn by six crossing cuts), hanging from its top edge,
// as `tear demo` runs it with no input files.
#pragma once

#include <string>

#include "tear/cut_script.h"
#include "tear/mesh.h"

namespace tear {

/// The paper's three sheet resolutions (Table 1).
enum class DemoResolution { low, medium, high };

/// "low", "medium" or "high".
const char* to_string(DemoResolution resolution);

/// Parses "low", "medium" or "high"; anything else is a usage `Error`.
DemoResolution parse_demo_resolution(const std::string& text);

/// Faces of the sheet at `resolution`: 2,822, 9,022 or 38,298.
index_t demo_face_count(DemoResolution resolution);

/// Frames of the demo, at `demo_fps`: two seconds.
inline constexpr int demo_frames = 48;
inline constexpr double demo_fps = 24;
/// The six cuts come at frames 4, 12, ..., 44, one every third of a second, so each opens under
/// gravity before the next.
inline constexpr int demo_first_cut_frame = 4;
inline constexpr int demo_cut_interval = 8;

/// The irregular 1 m sheet of `make_sheet` at `resolution` (seed 1), in the xy plane.
Mesh make_demo_sheet(DemoResolution resolution);

/// The script of the demo, named "(demo scene)" in messages: `demo_frames` frames, the six
/// rest-xy cuts of examples/paper_scene.json (repeated here so that the demo needs no file), and a
/// `simulation` block with the default solver settings, gravity along -y and the top edge (rest
/// y = 1) pinned.
CutScript demo_script();

}  // namespace tear
