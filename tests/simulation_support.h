// Shared helpers of the simulation tests: options read the way a script gives them, and the
// horizontal sheet they hang, pull and push.
#pragma once

#include <string>

#include "catch.h"
#include "tear/cut_script.h"
#include "tear/make_sheet.h"
#include "tear/mesh.h"
#include "tear/simulation_options.h"

namespace tear::test {

/// The options of a script whose `simulation` block is `block` (JSON text), as the script's parser
/// reads them (the only way in: the block is parsed with the script).
inline SimulationOptions parse_simulation(const std::string& block, const std::string& path = "s.json") {
  const CutScript script = parse_cut_script(R"({"version": 1, "frames": 1, "simulation": )" + block + "}", path);
  REQUIRE(script.simulation.has_value());
  return *script.simulation;
}

/// A sheet of about `faces` faces (`make_sheet`, regular unless `irregular`) turned into the xz plane
/// ([0,1] × {0} × [0,1]), so that gravity -y hangs it down when one edge is pinned.
inline Mesh horizontal_sheet(index_t faces, bool irregular = false) {
  SheetOptions o;
  o.face_count = faces;
  o.irregular = irregular;
  Mesh mesh = make_sheet(o);
  for (index_t n = 0; n < mesh.node_count(); ++n) {
    const float y = mesh.node_pos[3 * n + 1];
    mesh.node_pos[3 * n + 1] = 0;
    mesh.node_pos[3 * n + 2] = y;
  }
  return mesh;
}

}  // namespace tear::test
