// Building the topology on either backend: sort + unique of node pairs for edges, a stable sort
// of corners by node for the node→faces CSR, gathers for boundary flags.
#include <thrust/binary_search.h>
#include <thrust/copy.h>
#include <thrust/for_each.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/scan.h>
#include <thrust/sort.h>

#include "backend.h"
#include "build_topology.h"
#include "device_topology.h"

namespace tear::backend {

template <class System>
void build_device_topology(DeviceTopology<System>& topo, const vector<System, index_t>& face_nodes, index_t node_count,
                           TopologyScratch<System>& scratch, TemporaryAllocator<System>& alloc) {
  using namespace kernels;
  const auto policy = Traits<System>::policy(alloc);
  const index_t face_count = static_cast<index_t>(face_nodes.size() / 3);
  const index_t half_count = 3 * face_count;
  thrust::counting_iterator<index_t> zero(0);
  topo.node_count = node_count;
  topo.face_count = face_count;

  // Edges: sort the half-edges' (low, high) node keys; equal keys are one edge.
  auto& half_key = scratch.half_key;
  auto& half_id = scratch.half_id;
  auto& head = scratch.head;
  auto& edge_of_sorted = scratch.edge_of_sorted;
  half_key.resize(half_count);
  half_id.resize(half_count);
  head.resize(half_count);
  edge_of_sorted.resize(half_count);
  thrust::for_each(policy, zero, zero + half_count, make_half_edge_keys{raw<index_t>(face_nodes), raw<std::uint64_t>(half_key), raw<index_t>(half_id)});
  thrust::stable_sort_by_key(policy, half_key.begin(), half_key.end(), half_id.begin());
  thrust::for_each(policy, zero, zero + half_count, flag_edge_heads{raw<std::uint64_t>(half_key), raw<index_t>(head)});
  thrust::inclusive_scan(policy, head.begin(), head.end(), edge_of_sorted.begin());
  const index_t edge_count = half_count ? static_cast<index_t>(edge_of_sorted[half_count - 1]) : 0;
  topo.edge_count = edge_count;

  topo.face_edges.resize(half_count);
  topo.edge_nodes.resize(2 * static_cast<std::size_t>(edge_count));
  auto& edge_first_half = scratch.edge_first_half;
  edge_first_half.resize(edge_count);
  thrust::for_each(policy, zero, zero + half_count,
                   write_face_edges{raw<std::uint64_t>(half_key), raw<index_t>(half_id), raw<index_t>(head), raw<index_t>(edge_of_sorted),
                                    raw<index_t>(topo.face_edges), raw<index_t>(topo.edge_nodes), raw<index_t>(edge_first_half)});
  topo.edge_faces.resize(2 * static_cast<std::size_t>(edge_count));
  topo.edge_face_count.resize(edge_count);
  topo.edge_boundary.resize(edge_count);
  thrust::for_each(policy, zero, zero + edge_count,
                   write_edge_faces{raw<index_t>(edge_first_half), raw<index_t>(half_id), half_count, edge_count, raw<index_t>(topo.edge_faces),
                                    raw<index_t>(topo.edge_face_count), raw<std::uint8_t>(topo.edge_boundary)});

  // Node→faces: corners stably sorted by node keep each node's faces ascending; the offsets are
  // where each node's run begins.
  auto& corner_node = scratch.corner_node;
  corner_node.resize(half_count);
  topo.node_faces.resize(half_count);
  thrust::for_each(policy, zero, zero + half_count, make_corner_keys{raw<index_t>(face_nodes), raw<index_t>(corner_node), raw<index_t>(topo.node_faces)});
  thrust::stable_sort_by_key(policy, corner_node.begin(), corner_node.end(), topo.node_faces.begin());
  topo.node_face_offset.resize(static_cast<std::size_t>(node_count) + 1);
  thrust::lower_bound(policy, corner_node.begin(), corner_node.end(), zero, zero + node_count + 1, topo.node_face_offset.begin());

  topo.node_boundary.resize(node_count);
  thrust::for_each(policy, zero, zero + node_count,
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
