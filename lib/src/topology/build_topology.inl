// Building the topology on either backend by counting and scanning (kernels/build_topology.h):
// no sort, one read-back (the edge count).
#include <thrust/copy.h>
#include <thrust/fill.h>
#include <thrust/for_each.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/scan.h>

#include "backend/backend.h"
#include "build_topology.h"
#include "topology/device_topology.h"

namespace tear::backend {

template <class System>
void build_device_topology(DeviceTopology<System>& topo, const vector<System, index_t>& face_nodes, index_t node_count,
                           TopologyScratch<System>& scratch, TemporaryAllocator<System>& alloc) {
  using namespace kernels;
  const auto policy = Traits<System>::policy(alloc);
  const index_t face_count = static_cast<index_t>(face_nodes.size() / 3);
  const index_t half_count = 3 * face_count;
  topo.node_count = node_count;
  topo.face_count = face_count;
  const std::size_t nodes_and_end = static_cast<std::size_t>(node_count) + 1;

  // Node→faces: the corners counting-sorted by node (faces ascending in each node's run).
  auto& node_tally = scratch.node_tally;
  build_csr_by_counting<System>(policy, FaceCorners{raw<index_t>(face_nodes)}, half_count, node_count, half_count,
                                node_tally, topo.node_face_offset, topo.node_faces);

  // Edges: counted at their lower node, numbered by a scan of the counts, written in (low, high)
  // order with their faces.
  for_each_index<System>(node_count + 1,
                   count_node_edges{raw<index_t>(face_nodes), raw<index_t>(topo.node_face_offset),
                                    raw<index_t>(topo.node_faces), raw<index_t>(node_tally), node_count});
  auto& node_edge_offset = scratch.node_edge_offset;
  resize_for_overwrite(node_edge_offset, nodes_and_end);
  thrust::exclusive_scan(policy, node_tally.begin(), node_tally.end(), node_edge_offset.begin());
  const index_t edge_count = node_edge_offset[node_count];
  topo.edge_count = edge_count;
  resize_for_overwrite(topo.edge_nodes, 2 * static_cast<std::size_t>(edge_count));
  resize_for_overwrite(topo.edge_faces, 2 * static_cast<std::size_t>(edge_count));
  resize_for_overwrite(topo.edge_face_count, edge_count);
  resize_for_overwrite(topo.edge_boundary, edge_count);
  for_each_index<System>(node_count,
                   write_node_edges{raw<index_t>(face_nodes), raw<index_t>(topo.node_face_offset),
                                    raw<index_t>(topo.node_faces), raw<index_t>(node_edge_offset),
                                    raw<index_t>(topo.edge_nodes), raw<index_t>(topo.edge_faces),
                                    raw<index_t>(topo.edge_face_count), raw<std::uint8_t>(topo.edge_boundary)});
  resize_for_overwrite(topo.face_edges, half_count);
  for_each_index<System>(half_count,
                   write_face_edges{raw<index_t>(face_nodes), raw<index_t>(node_edge_offset),
                                    raw<index_t>(topo.edge_nodes), raw<index_t>(topo.face_edges)});

  resize_for_overwrite(topo.node_boundary, node_count);
  for_each_index<System>(node_count,
                   flag_boundary_nodes{raw<index_t>(face_nodes), raw<index_t>(topo.face_edges), raw<index_t>(topo.node_face_offset),
                                       raw<index_t>(topo.node_faces), raw<std::uint8_t>(topo.edge_boundary), raw<std::uint8_t>(topo.node_boundary)});
}

template <class System>
Topology build_topology_on(const Mesh& mesh) {
  vector<System, index_t> face_nodes(mesh.face_nodes.begin(), mesh.face_nodes.end());
  DeviceTopology<System> topo;
  TopologyScratch<System> scratch;
  TemporaryAllocator<System> alloc;
  build_device_topology(topo, face_nodes, mesh.node_count(), scratch, alloc);
  return download(topo);
}

#define TEAR_INSTANTIATE(S)                                                                                          \
  template void build_device_topology<S>(DeviceTopology<S>&, const vector<S, index_t>&, index_t, TopologyScratch<S>&, \
                                         TemporaryAllocator<S>&);                                                   \
  template Topology build_topology_on<S>(const Mesh&);
TEAR_FOR_EACH_SYSTEM(TEAR_INSTANTIATE)
#undef TEAR_INSTANTIATE

}  // namespace tear::backend
