#include "tear/validate_mesh.h"

#include <string>

#include "topology/entry_points.h"

namespace tear {

std::string MeshReport::describe() const {
  std::string out;
  auto add = [&](std::int64_t n, const char* one, const char* many) {
    if (!n) return;
    if (!out.empty()) out += ", ";
    out += std::to_string(n) + " " + (n == 1 ? one : many);
  };
  add(indices_out_of_range, "face with a node index out of range", "faces with a node index out of range");
  add(non_finite_nodes, "node with a non-finite coordinate", "nodes with a non-finite coordinate");
  add(degenerate_faces, "degenerate face", "degenerate faces");
  add(non_manifold_edges, "non-manifold edge (more than two faces)", "non-manifold edges (more than two faces)");
  add(non_manifold_nodes, "non-manifold (bow-tie) node", "non-manifold (bow-tie) nodes");
  add(inconsistent_edges, "edge with inconsistently oriented faces", "edges with inconsistently oriented faces");
  add(duplicate_faces, "face on the same three nodes as another face", "faces on the same three nodes as another face");
  add(thin_faces, "face too thin to cut (height under 1e-7 of its longest edge)",
      "faces too thin to cut (height under 1e-7 of their longest edge)");
  add(imprecise_faces,
      "face too thin for single precision at its coordinates (height under 8 float32 steps at its largest "
      "coordinate: the mesh spans scales float32 cannot hold together)",
      "faces too thin for single precision at their coordinates (height under 8 float32 steps at their largest "
      "coordinate: the mesh spans scales float32 cannot hold together)");
  return out.empty() ? "no problems" : out;
}

MeshReport check_indices(const Mesh& mesh, Device device) {
  return backend::dispatch(device, [&](auto system) { return backend::check_indices_on<decltype(system)>(mesh); });
}

MeshReport validate_mesh(const Mesh& mesh, const Topology& topology, Device device) {
  return backend::dispatch(device,
                           [&](auto system) { return backend::validate_mesh_on<decltype(system)>(mesh, topology); });
}

MeshReport validate_mesh(const Mesh& mesh, Device device) {
  return backend::dispatch(device, [&](auto system) { return backend::validate_mesh_on<decltype(system)>(mesh); });
}

}  // namespace tear
