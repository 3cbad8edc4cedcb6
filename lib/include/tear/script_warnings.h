// tear: what is allowed but probably not meant in a script and the mesh it cuts: cuts that change
// nothing, sliver faces. `tear validate SCRIPT MESH` prints them as warnings.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "tear/cut_script.h"
#include "tear/device.h"
#include "tear/mesh.h"

namespace tear {

/// One-line warnings (without the "tear: warning: " of the CLI), each naming its file and, for a
/// cut, its key path:
///
/// - every `uv` or `rest-*` cut that, applied alone (with the script's `snap`) to the rest shape of
///   `mesh`, changes nothing: "shot.json: cuts[2]: changes nothing on the rest shape of cloth.obj
///   (...)". Such a cut misses the cloth, or is a slit too short to cross an edge away from the
///   snap zones of its nodes. Blades and planes cut the pose of their frame, which a simulation
///   moves, so they are not tried;
///   Only the first `max_tried_cuts` such cuts are tried; when the script has more, one warning
///   says how many were not ("shot.json: only the first 256 polyline cuts were tried ...");
/// - sliver faces of `mesh` (`sliver_angle_deg`): "cloth.obj: 3 sliver faces (...)".
///
/// `mesh` must pass `check_cuttable` and `check_script_against_mesh`. Cost: one cut of the whole
/// mesh per tried cut, so at most `max_tried_cuts` cuts of it.
inline constexpr std::size_t max_tried_cuts = 256;

std::vector<std::string> script_warnings(const CutScript& script, const Mesh& mesh, const std::string& mesh_path,
                                         Device device);

}  // namespace tear
