#include "tear/script_warnings.h"

#include <cstdio>

#include "tear/cloth.h"
#include "tear/mesh_info.h"
#include "tear/topology.h"
#include "tear/validate_mesh.h"

namespace tear {

namespace {

std::string shown(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", x);
  return text;
}

}  // namespace

std::vector<std::string> script_warnings(const CutScript& script, const Mesh& mesh, const std::string& mesh_path,
                                         Device device) {
  std::vector<std::string> warnings;
  CutOptions options;
  options.snap = script.snap;
  // Each cut tried costs a cut of the whole mesh: the first `max_tried_cuts` are tried, so the
  // check's time grows with the script's length only by reading it.
  std::size_t tried = 0, untried = 0;
  for (const Cut& cut : script.cuts) {
    if (cut.kind != CutKind::polyline) continue;
    if (tried == max_tried_cuts) {
      ++untried;
      continue;
    }
    ++tried;
    Cloth cloth(mesh, device);
    const CutStats stats = cloth.cut({to_cut_line(cut)}, options);
    if (stats.nodes_after != stats.nodes_before || stats.faces_after != stats.faces_before) continue;
    warnings.push_back(script.path + ": " + cut.key_path + ": changes nothing on the rest shape of " + mesh_path +
                       " (it misses the cloth, or is a slit too short to cross an edge outside the snap distance of " +
                       "its nodes, " + shown(script.snap) + " of an edge)");
  }

  if (untried > 0)
    warnings.push_back(script.path + ": only the first " + std::to_string(max_tried_cuts) +
                       " polyline cuts were tried on the rest shape of " + mesh_path + " (" + std::to_string(untried) +
                       " more not tried)");

  const Topology topology = build_topology(mesh, device);
  const MeshInfo info = compute_mesh_info(mesh, topology, validate_mesh(mesh, topology, device));
  if (info.sliver_faces > 0)
    warnings.push_back(mesh_path + ": " + std::to_string(info.sliver_faces) +
                       (info.sliver_faces == 1 ? " sliver face" : " sliver faces") + " (an angle under " +
                       shown(sliver_angle_deg) + " deg, the smallest " + shown(info.min_angle_deg) +
                       " deg): cuts near them make thinner slivers still");
  return warnings;
}

}  // namespace tear
