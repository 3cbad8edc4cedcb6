// validate_mesh on either backend: per-element flags reduced by an integer sum.
#include <thrust/iterator/counting_iterator.h>
#include <thrust/transform_reduce.h>

#include "backend/backend.h"
#include "check_mesh.h"
#include "backend/entry_points.h"
#include "tear/validate_mesh.h"

namespace tear::backend {

namespace {
template <class System, class Check>
std::int64_t count_bad(index_t count, Check check) {
  thrust::counting_iterator<index_t> zero(0);
  return thrust::transform_reduce(Traits<System>::policy(), zero, zero + count, check, std::int64_t(0), thrust::plus<std::int64_t>());
}
}  // namespace

template <class System>
MeshReport check_indices_on(const Mesh& mesh) {
  vector<System, index_t> face_nodes(mesh.face_nodes.begin(), mesh.face_nodes.end());
  vector<System, float> node_pos(mesh.node_pos.begin(), mesh.node_pos.end());
  MeshReport report;
  report.indices_out_of_range = count_bad<System>(mesh.face_count(), kernels::face_index_out_of_range{raw<index_t>(face_nodes), mesh.node_count()});
  report.non_finite_nodes = count_bad<System>(mesh.node_count(), kernels::node_non_finite{raw<float>(node_pos)});
  return report;
}

template <class System>
MeshReport validate_mesh_on(const Mesh& mesh, const Topology& t) {
  MeshReport report = check_indices_on<System>(mesh);
  if (report.indices_out_of_range) return report;
  vector<System, index_t> face_nodes(mesh.face_nodes.begin(), mesh.face_nodes.end());
  vector<System, float> node_pos(mesh.node_pos.begin(), mesh.node_pos.end());
  vector<System, index_t> face_edges(t.face_edges.begin(), t.face_edges.end()), edge_faces(t.edge_faces.begin(), t.edge_faces.end()),
      edge_face_count(t.edge_face_count.begin(), t.edge_face_count.end()), node_face_offset(t.node_face_offset.begin(), t.node_face_offset.end()),
      node_faces(t.node_faces.begin(), t.node_faces.end());
  if (!report.non_finite_nodes) {
    report.degenerate_faces = count_bad<System>(mesh.face_count(), kernels::face_degenerate{raw<float>(node_pos), raw<index_t>(face_nodes), degenerate_area_ratio});
    // Degenerate at the thin ratio, less those degenerate at the degenerate ratio.
    report.thin_faces = count_bad<System>(mesh.face_count(), kernels::face_degenerate{raw<float>(node_pos), raw<index_t>(face_nodes), thin_area_ratio}) -
                        report.degenerate_faces;
  }
  report.non_manifold_edges = count_bad<System>(t.edge_count, kernels::edge_non_manifold{raw<index_t>(edge_face_count)});
  report.inconsistent_edges = count_bad<System>(
      t.edge_count, kernels::edge_inconsistent{raw<index_t>(face_nodes), raw<index_t>(face_edges), raw<index_t>(edge_faces), raw<index_t>(edge_face_count)});
  report.duplicate_faces = count_bad<System>(
      mesh.face_count(), kernels::face_duplicate{raw<index_t>(face_nodes), raw<index_t>(node_face_offset), raw<index_t>(node_faces)});
  report.non_manifold_nodes = count_bad<System>(
      t.node_count, kernels::node_non_manifold{raw<index_t>(face_nodes), raw<index_t>(face_edges), raw<index_t>(edge_faces), raw<index_t>(edge_face_count),
                                               raw<index_t>(node_face_offset), raw<index_t>(node_faces)});
  return report;
}

#define TEAR_INSTANTIATE(S)                                \
  template MeshReport check_indices_on<S>(const Mesh&); \
  template MeshReport validate_mesh_on<S>(const Mesh&, const Topology&);
TEAR_FOR_EACH_SYSTEM(TEAR_INSTANTIATE)
#undef TEAR_INSTANTIATE

}  // namespace tear::backend
