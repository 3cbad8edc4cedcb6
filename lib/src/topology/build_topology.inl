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

namespace {

/// The edge arrays sized for `edge_count` edges.
template <class System>
void size_edges(DeviceTopology<System>& topo, index_t edge_count) {
  topo.edge_count = edge_count;
  resize_for_overwrite(topo.edge_nodes, 2 * static_cast<std::size_t>(edge_count));
  resize_for_overwrite(topo.edge_faces, 2 * static_cast<std::size_t>(edge_count));
  resize_for_overwrite(topo.edge_face_count, edge_count);
  resize_for_overwrite(topo.edge_boundary, edge_count);
}

/// The per-node passes a build runs and a patch runs for its touched nodes, over `topo`'s arrays
/// (their pointers taken when called: once the arrays are sized).
template <class System>
kernels::count_node_edges edge_counter(DeviceTopology<System>& topo, const vector<System, index_t>& face_nodes,
                                       vector<System, index_t>& counts) {
  return {raw<index_t>(face_nodes), raw<index_t>(topo.node_face_offset), raw<index_t>(topo.node_faces),
          raw<index_t>(counts), topo.node_count};
}
template <class System>
kernels::write_node_edges edge_writer(DeviceTopology<System>& topo, const vector<System, index_t>& face_nodes) {
  return {raw<index_t>(face_nodes),      raw<index_t>(topo.node_face_offset), raw<index_t>(topo.node_faces),
          raw<index_t>(topo.node_edge_offset), raw<index_t>(topo.edge_nodes),       raw<index_t>(topo.edge_faces),
          raw<index_t>(topo.edge_face_count),  raw<std::uint8_t>(topo.edge_boundary)};
}
template <class System>
kernels::flag_boundary_nodes boundary_flagger(DeviceTopology<System>& topo, const vector<System, index_t>& face_nodes) {
  return {raw<index_t>(face_nodes),        raw<index_t>(topo.face_edges),         raw<index_t>(topo.node_face_offset),
          raw<index_t>(topo.node_faces),   raw<std::uint8_t>(topo.edge_boundary), raw<std::uint8_t>(topo.node_boundary)};
}

/// The edge counts of `counts` [node_count + 2] (`count_node_edges`) scanned into
/// `topo.node_edge_offset`, and the edge arrays sized for the edge count: one read-back of two
/// values. When some node's edges were left uncounted (too many for one pass), every node of many
/// faces has its half-edges sorted and its edges counted from them (`sort_node_half_edges`, into
/// the scratch's keys), and the counts are scanned again. Returns the writer of the edges.
template <class System, class Policy>
kernels::write_node_edges scan_edge_counts(DeviceTopology<System>& topo, const vector<System, index_t>& face_nodes,
                                           vector<System, index_t>& counts, TopologyScratch<System>& scratch,
                                           const Policy& policy) {
  const index_t node_count = topo.node_count;
  auto& offset = topo.node_edge_offset;
  resize_for_overwrite(offset, static_cast<std::size_t>(node_count) + 2);
  exclusive_sum<System>(policy, raw<index_t>(counts), raw<index_t>(offset), node_count + 2);
  index_t ends[2];
  thrust::copy(offset.begin() + node_count, offset.begin() + node_count + 2, ends);
  const bool sorted = ends[1] != ends[0];
  auto& key_offset = scratch.half_edge_key_offset;
  auto& keys = scratch.half_edge_keys;
  if (sorted) {
    const std::size_t nodes_and_end = static_cast<std::size_t>(node_count) + 1;
    resize_for_overwrite(key_offset, nodes_and_end);
    resize_for_overwrite(scratch.half_edge_key_count, nodes_and_end);
    for_each_index<System>(node_count + 1,
                           kernels::count_half_edge_keys{raw<index_t>(face_nodes), raw<index_t>(topo.node_face_offset),
                                                         raw<index_t>(topo.node_faces), node_count,
                                                         raw<index_t>(scratch.half_edge_key_count)});
    exclusive_sum<System>(policy, raw<index_t>(scratch.half_edge_key_count), raw<index_t>(key_offset),
                          node_count + 1);
    const index_t key_count = key_offset[node_count];
    resize_for_overwrite(keys, static_cast<std::size_t>(key_count));
    for_each_index<System>(node_count + 1, kernels::sort_node_half_edges{
                                               raw<index_t>(face_nodes), raw<index_t>(topo.node_face_offset),
                                               raw<index_t>(topo.node_faces), raw<index_t>(key_offset),
                                               raw<std::uint64_t>(keys), node_count, raw<index_t>(counts)});
    exclusive_sum<System>(policy, raw<index_t>(counts), raw<index_t>(offset), node_count + 2);
    ends[0] = offset[node_count];
  }
  size_edges(topo, ends[0]);
  kernels::write_node_edges writer = edge_writer(topo, face_nodes);
  if (sorted) {
    writer.key_offset = raw<index_t>(key_offset);
    writer.keys = raw<std::uint64_t>(keys);
  }
  return writer;
}


/// face_edges of every half-edge, once the edges are written.
template <class System>
void write_all_face_edges(DeviceTopology<System>& topo, const vector<System, index_t>& face_nodes) {
  const index_t half_count = 3 * topo.face_count;
  resize_for_overwrite(topo.face_edges, half_count);
  for_each_index<System>(half_count, kernels::write_face_edges{raw<index_t>(face_nodes), raw<index_t>(topo.node_edge_offset),
                                                               raw<index_t>(topo.edge_nodes), raw<index_t>(topo.face_edges)});
}

}  // namespace

template <class System>
void build_device_topology(DeviceTopology<System>& topo, const vector<System, index_t>& face_nodes, index_t node_count,
                           TopologyScratch<System>& scratch, TemporaryAllocator<System>& alloc) {
  using namespace kernels;
  const auto policy = Traits<System>::policy(alloc);
  const index_t face_count = static_cast<index_t>(face_nodes.size() / 3);
  const index_t half_count = 3 * face_count;
  topo.node_count = node_count;
  topo.face_count = face_count;

  // Node→faces: the corners counting-sorted by node (faces ascending in each node's run).
  auto& node_tally = scratch.node_tally;
  build_csr_by_counting<System>(policy, FaceCorners{raw<index_t>(face_nodes)}, half_count, node_count, half_count,
                                node_tally, topo.node_face_offset, topo.node_faces);

  // Edges: counted at their lower node, numbered by a scan of the counts, written in (low, high)
  // order with their faces.
  // node_tally[node_count] is 0 after the counting sort; the count adds to it (`count_node_edges`).
  resize_for_overwrite(node_tally, static_cast<std::size_t>(node_count) + 2);
  for_each_index<System>(node_count + 2, edge_counter(topo, face_nodes, node_tally));
  for_each_index<System>(node_count, scan_edge_counts(topo, face_nodes, node_tally, scratch, policy));
  write_all_face_edges(topo, face_nodes);

  resize_for_overwrite(topo.node_boundary, node_count);
  for_each_index<System>(node_count, boundary_flagger(topo, face_nodes));
}

template <class System>
void patch_device_topology(DeviceTopology<System>& topo, const DeviceTopology<System>& old,
                           const vector<System, index_t>& old_face_nodes, const vector<System, index_t>& face_offset,
                           const vector<System, index_t>& face_nodes, index_t node_count,
                           TopologyScratch<System>& scratch, TemporaryAllocator<System>& alloc) {
  using namespace kernels;
  const auto policy = Traits<System>::policy(alloc);
  const index_t face_count = static_cast<index_t>(face_nodes.size() / 3);
  const index_t half_count = 3 * face_count;
  const index_t old_faces = old.face_count;
  topo.node_count = node_count;
  topo.face_count = face_count;
  const std::size_t nodes_and_end = static_cast<std::size_t>(node_count) + 1;

  // The faces the cut split or gave other nodes, and their nodes.
  resize_for_overwrite(scratch.face_touched, old_faces);
  resize_for_overwrite(scratch.node_touched, node_count);
  for_each_index<System>(node_count, clear_node_marks{old.node_count, raw<std::uint8_t>(scratch.node_touched)});
  for_each_index<System>(old_faces, mark_cut_faces{raw<index_t>(old_face_nodes), raw<index_t>(face_nodes),
                                                   raw<index_t>(face_offset), raw<std::uint8_t>(scratch.face_touched),
                                                   raw<std::uint8_t>(scratch.node_touched)});
  const OldTopology was{old.node_count,
                        raw<index_t>(old.node_face_offset),
                        raw<index_t>(old.node_faces),
                        raw<index_t>(old.node_edge_offset),
                        raw<index_t>(old.edge_nodes),
                        raw<index_t>(old.edge_faces),
                        raw<index_t>(old.edge_face_count),
                        raw<std::uint8_t>(old.edge_boundary),
                        raw<std::uint8_t>(old.node_boundary),
                        raw<index_t>(face_offset),
                        raw<std::uint8_t>(scratch.face_touched),
                        raw<std::uint8_t>(scratch.node_touched)};

  // Node→faces: counted, scanned, kept runs copied, the touched faces' corners added.
  auto& tally = scratch.node_tally;
  resize_for_overwrite(tally, nodes_and_end + 1);  // the edge counts' two ends (`count_node_edges`)
  for_each_index<System>(node_count + 1, count_patched_corners{was, node_count, raw<index_t>(tally)});
  for_each_index<System>(old_faces, add_touched_corners{raw<index_t>(face_nodes), raw<index_t>(face_offset),
                                                        raw<std::uint8_t>(scratch.face_touched), raw<index_t>(tally)});
  resize_for_overwrite(topo.node_face_offset, nodes_and_end);
  exclusive_sum<System>(policy, raw<index_t>(tally), raw<index_t>(topo.node_face_offset), node_count + 1);
  resize_for_overwrite(topo.node_faces, half_count);
  for_each_index<System>(node_count, fill_patched_runs{was, raw<index_t>(topo.node_face_offset),
                                                       raw<index_t>(topo.node_faces), raw<index_t>(tally)});
  for_each_index<System>(old_faces, fill_touched_corners{raw<index_t>(face_nodes), raw<index_t>(face_offset),
                                                         raw<std::uint8_t>(scratch.face_touched), raw<index_t>(tally),
                                                         raw<index_t>(topo.node_faces)});

  // Edges: kept nodes' counts and edges copied, touched nodes' runs sorted and their edges counted
  // and written.
  // tally[node_count] is the 0 count_patched_corners wrote after the corner counts.
  for_each_index<System>(node_count + 2, count_patched_edges{was, edge_counter(topo, face_nodes, tally),
                                                             sort_runs{raw<index_t>(topo.node_face_offset),
                                                                       raw<index_t>(topo.node_faces)}});
  for_each_index<System>(node_count, write_patched_edges{was, scan_edge_counts(topo, face_nodes, tally, scratch, policy)});
  write_all_face_edges(topo, face_nodes);
  resize_for_overwrite(topo.node_boundary, node_count);
  for_each_index<System>(node_count, flag_patched_boundary{was, boundary_flagger(topo, face_nodes)});
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
  template void patch_device_topology<S>(DeviceTopology<S>&, const DeviceTopology<S>&, const vector<S, index_t>&,   \
                                         const vector<S, index_t>&, const vector<S, index_t>&, index_t,             \
                                         TopologyScratch<S>&, TemporaryAllocator<S>&);                              \
  template Topology build_topology_on<S>(const Mesh&);
TEAR_FOR_EACH_SYSTEM(TEAR_INSTANTIATE)
#undef TEAR_INSTANTIATE

}  // namespace tear::backend
