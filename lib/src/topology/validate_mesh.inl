// validate_mesh on either backend: per-element flags reduced by an integer sum.
#include <thrust/iterator/counting_iterator.h>
#include <thrust/transform_reduce.h>

#include "backend/backend.h"
#include "check_mesh.h"
#include "tear/validate_mesh.h"
#include "topology/device_topology.h"
#include "topology/entry_points.h"

namespace tear::backend {

namespace {
template <class System, class Check>
std::int64_t count_bad(index_t count, Check check) {
  thrust::counting_iterator<index_t> zero(0);
  return thrust::transform_reduce(Traits<System>::policy(), zero, zero + count, check, std::int64_t(0),
                                  thrust::plus<std::int64_t>());
}

/// The index and coordinate checks of a mesh already on the backend.
template <class System>
void check_indices_into(MeshReport& report, const vector<System, index_t>& face_nodes,
                        const vector<System, float>& node_pos, index_t face_count, index_t node_count) {
  report.indices_out_of_range =
      count_bad<System>(face_count, kernels::face_index_out_of_range{raw<index_t>(face_nodes), node_count});
  report.non_finite_nodes = count_bad<System>(node_count, kernels::node_non_finite{raw<float>(node_pos)});
}

/// The checks that need the topology, on arrays already on the backend.
template <class System>
void check_topology_into(MeshReport& report, const vector<System, index_t>& face_nodes,
                         const vector<System, float>& node_pos, index_t face_count, index_t node_count,
                         index_t edge_count, const vector<System, index_t>& face_edges,
                         const vector<System, index_t>& edge_faces, const vector<System, index_t>& edge_face_count,
                         const vector<System, index_t>& node_face_offset, const vector<System, index_t>& node_faces) {
  if (!report.non_finite_nodes) {
    report.degenerate_faces = count_bad<System>(
        face_count, kernels::face_degenerate{raw<float>(node_pos), raw<index_t>(face_nodes), degenerate_area_ratio});
    // Degenerate at the thin ratio, less those degenerate at the degenerate ratio.
    report.thin_faces =
        count_bad<System>(face_count,
                          kernels::face_degenerate{raw<float>(node_pos), raw<index_t>(face_nodes), thin_area_ratio}) -
        report.degenerate_faces;
    report.imprecise_faces = count_bad<System>(
        face_count, kernels::face_imprecise{raw<float>(node_pos), raw<index_t>(face_nodes), thin_area_ratio, imprecise_steps});
  }
  report.non_manifold_edges = count_bad<System>(edge_count, kernels::edge_non_manifold{raw<index_t>(edge_face_count)});
  report.inconsistent_edges = count_bad<System>(
      edge_count, kernels::edge_inconsistent{raw<index_t>(face_nodes), raw<index_t>(face_edges),
                                             raw<index_t>(edge_faces), raw<index_t>(edge_face_count)});
  report.duplicate_faces = count_bad<System>(
      face_count,
      kernels::face_duplicate{raw<index_t>(face_nodes), raw<index_t>(node_face_offset), raw<index_t>(node_faces)});
  report.non_manifold_nodes = count_bad<System>(
      node_count, kernels::node_non_manifold{raw<index_t>(face_nodes), raw<index_t>(face_edges),
                                             raw<index_t>(edge_faces), raw<index_t>(edge_face_count),
                                             raw<index_t>(node_face_offset), raw<index_t>(node_faces)});
}
}  // namespace

template <class System>
MeshReport check_indices_on(const Mesh& mesh) {
  vector<System, index_t> face_nodes(mesh.face_nodes.begin(), mesh.face_nodes.end());
  vector<System, float> node_pos(mesh.node_pos.begin(), mesh.node_pos.end());
  MeshReport report;
  check_indices_into<System>(report, face_nodes, node_pos, mesh.face_count(), mesh.node_count());
  return report;
}

template <class System>
MeshReport validate_mesh_on(const Mesh& mesh, const Topology& t) {
  vector<System, index_t> face_nodes(mesh.face_nodes.begin(), mesh.face_nodes.end());
  vector<System, float> node_pos(mesh.node_pos.begin(), mesh.node_pos.end());
  MeshReport report;
  check_indices_into<System>(report, face_nodes, node_pos, mesh.face_count(), mesh.node_count());
  if (report.indices_out_of_range) return report;
  const vector<System, index_t> face_edges(t.face_edges.begin(), t.face_edges.end()),
      edge_faces(t.edge_faces.begin(), t.edge_faces.end()),
      edge_face_count(t.edge_face_count.begin(), t.edge_face_count.end()),
      node_face_offset(t.node_face_offset.begin(), t.node_face_offset.end()),
      node_faces(t.node_faces.begin(), t.node_faces.end());
  check_topology_into<System>(report, face_nodes, node_pos, mesh.face_count(), t.node_count, t.edge_count, face_edges,
                              edge_faces, edge_face_count, node_face_offset, node_faces);
  return report;
}

template <class System>
MeshReport validate_mesh_on(const Mesh& mesh) {
  // The mesh goes to the backend once; its topology is built there and never leaves it.
  const vector<System, index_t> face_nodes(mesh.face_nodes.begin(), mesh.face_nodes.end());
  const vector<System, float> node_pos(mesh.node_pos.begin(), mesh.node_pos.end());
  MeshReport report;
  check_indices_into<System>(report, face_nodes, node_pos, mesh.face_count(), mesh.node_count());
  if (report.indices_out_of_range) return report;
  DeviceTopology<System> t;
  build_device_topology(t, face_nodes, mesh.node_count());
  check_topology_into<System>(report, face_nodes, node_pos, mesh.face_count(), t.node_count, t.edge_count, t.face_edges,
                              t.edge_faces, t.edge_face_count, t.node_face_offset, t.node_faces);
  return report;
}

#define TEAR_INSTANTIATE(S)                                              \
  template MeshReport check_indices_on<S>(const Mesh&);                  \
  template MeshReport validate_mesh_on<S>(const Mesh&, const Topology&); \
  template MeshReport validate_mesh_on<S>(const Mesh&);
TEAR_FOR_EACH_SYSTEM(TEAR_INSTANTIATE)
#undef TEAR_INSTANTIATE

}  // namespace tear::backend
