// tear: the scenes `tear demo` runs with no input files: the paper's (a square sheet torn by six
// crossing cuts, hanging from its top edge), a notched sheet pulled apart until it tears in two, and
// a sheet held at its four edges that a rising sphere punches through.
#pragma once

#include <string>

#include "tear/cut_script.h"
#include "tear/simulation_options.h"
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

/// The scenes of `tear demo`: the paper's (the default), a notched sheet pulled apart by keyed pins
/// until it tears in two, a horizontal sheet held at its edges torn open by a rising sphere, a
/// woven square with a UV seam pulled along a diagonal (it comes apart along its weaker
/// seam), and a sheet caught at a corner falling onto a slowly turning box (it folds on itself and
/// tears where it snags).
enum class DemoScene { paper, pull, punch, grain, drape };

/// "paper", "pull", "punch", "grain" or "drape".
const char* to_string(DemoScene scene);

/// Parses "paper", "pull", "punch", "grain" or "drape"; anything else is a usage `Error`.
DemoScene parse_demo_scene(const std::string& text);

/// The stretch limit (`simulation.tearing.stretch`) of the pull and punch scenes.
inline constexpr double demo_tear_stretch = 1.3;
/// The pull scene: each pinned strip moves this far along x (outwards) by the last frame, metres.
inline constexpr double demo_pull_distance = 0.3;
/// The punch scene: the sphere's radius, its centre at the start (under the sheet's middle) and
/// how far it rises by the last frame, metres.
inline constexpr double demo_punch_radius = 0.15;
inline constexpr double demo_punch_start_y = -0.2;
inline constexpr double demo_punch_rise = 0.8;

/// The grain scene: the seam's place (the faces whose centroid lies right of it have their UVs
/// moved by half a tile), the weave's weft strength and the seam's strength.
inline constexpr double demo_grain_seam_x = 0.7;
inline constexpr double demo_grain_weft_strength = 0.85;
inline constexpr double demo_grain_seam_strength = 0.85;

/// The drape scene: the sheet's height above the box's centre at the start, the box's half side
/// and its turn over the frames (degrees about y), the collision thickness (punch's too).
inline constexpr double demo_drape_height = 0.55;
inline constexpr double demo_drape_box_half = 0.22;
inline constexpr double demo_drape_turn = 60;
inline constexpr double demo_collision_thickness = 0.004;

/// A closed box of half side `half` about `centre`, its faces counter-clockwise seen from outside,
/// each side split into `n` × `n` squares: the drape scene's body.
ColliderMesh make_box_collider(std::array<double, 3> centre, double half, int n);

/// The sheet of `scene` at `resolution`: `make_demo_sheet`'s for the paper and pull scenes (grain:
/// with its UV seam at `demo_grain_seam_x`); for
/// punch the same sheet turned horizontal, [0, 1] x {0} x [0, 1] with its normal along +y
/// (a node at (x, y, 0) moves to (x, 0, 1 - y)).
Mesh make_demo_mesh(DemoScene scene, DemoResolution resolution);

/// The script of `scene`, `demo_frames` frames at `demo_fps`: `demo_script()` for paper.
/// pull (named "(demo scene: pull)"): a notch cut in frame 1 along x = 0.5 from the bottom border
/// to y = 0.25 (rest-xy), the strips x <= 0.04 and x >= 0.96 pinned and moved apart by
/// `demo_pull_distance` each, linearly over the frames, no gravity, tearing at `demo_tear_stretch`.
/// punch (named "(demo scene: punch)"): no cuts, the four edges of the horizontal sheet pinned,
/// gravity along -y, a sphere of `demo_punch_radius` under the sheet's middle rising by
/// `demo_punch_rise` linearly over the frames, tearing at `demo_tear_stretch`.
/// grain (named "(demo scene: grain)"): no cuts, no gravity, the strips x <= 0.04 and x >= 0.96
/// pinned and moved apart along the diagonal (-1, -1) and (1, 1) by `demo_pull_distance` each,
/// tearing at `demo_tear_stretch` with a weave (warp along v, weft along u, weft strength
/// `demo_grain_weft_strength`) and seams at `demo_grain_seam_strength`.
/// punch also has self-collision (`demo_collision_thickness`), so its torn flaps stay apart.
/// drape (named "(demo scene: drape)"): the punch's horizontal sheet `demo_drape_height` above a
/// box (`make_box_collider`, centre (0.5, 0, 0.5)) turning by `demo_drape_turn` degrees about y over
/// the frames, the sheet's corner x, z <= 0.04 pinned where it is, gravity along -y, a floor at
/// y = -0.3, self-collision with friction 0.3, tearing at `demo_tear_stretch`.
CutScript demo_script(DemoScene scene);

}  // namespace tear
