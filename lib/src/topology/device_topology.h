// tear: the topology arrays as they live on a backend, and their copy to the host.
#pragma once

#include <utility>

#include <thrust/copy.h>
#include <thrust/fill.h>
#include <thrust/for_each.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/scan.h>

#include "backend/backend.h"
#include "build_topology.h"
#include "tear/topology.h"
#include "backend/temporary_allocator.h"

namespace tear::backend {

/// `Topology` in `System`'s memory; same arrays, same meaning.
template <class System>
struct DeviceTopology {
  index_t node_count = 0, face_count = 0, edge_count = 0;
  vector<System, index_t> edge_nodes, edge_faces, edge_face_count, face_edges, node_face_offset, node_faces;
  vector<System, std::uint8_t> edge_boundary, node_boundary;
  vector<System, index_t> node_edge_offset;  ///< [node_count + 2] first edge whose lower node is n (edges run by it); the last less the one before: the half-edges left uncounted (`count_node_edges`)

  void swap(DeviceTopology& o) {
    std::swap(node_count, o.node_count);
    std::swap(face_count, o.face_count);
    std::swap(edge_count, o.edge_count);
    edge_nodes.swap(o.edge_nodes);
    edge_faces.swap(o.edge_faces);
    edge_face_count.swap(o.edge_face_count);
    face_edges.swap(o.face_edges);
    node_face_offset.swap(o.node_face_offset);
    node_faces.swap(o.node_faces);
    edge_boundary.swap(o.edge_boundary);
    node_boundary.swap(o.node_boundary);
    node_edge_offset.swap(o.node_edge_offset);
  }
};

template <class System>
Topology download(const DeviceTopology<System>& d) {
  Topology t;
  t.node_count = d.node_count;
  t.face_count = d.face_count;
  t.edge_count = d.edge_count;
  t.edge_nodes = to_host<index_t>(d.edge_nodes);
  t.edge_faces = to_host<index_t>(d.edge_faces);
  t.edge_face_count = to_host<index_t>(d.edge_face_count);
  t.face_edges = to_host<index_t>(d.face_edges);
  t.node_face_offset = to_host<index_t>(d.node_face_offset);
  t.node_faces = to_host<index_t>(d.node_faces);
  t.edge_boundary = to_host<std::uint8_t>(d.edge_boundary);
  t.node_boundary = to_host<std::uint8_t>(d.node_boundary);
  return t;
}

/// The CSR of `item_count` items by key over `key_count` keys, by counting (kernels/build_topology.h):
/// `offset` [key_count + 1], `values` the items' values run by run, each run ascending; `tally`
/// [key_count + 1] is scratch. `value_count` is the number of items with a key when the caller
/// knows it; negative, it is read back from the device.
template <class System, class Policy, class Items>
void build_csr_by_counting(const Policy& policy, Items items, index_t item_count, index_t key_count,
                           index_t value_count, vector<System, index_t>& tally, vector<System, index_t>& offset,
                           vector<System, index_t>& values) {
  const std::size_t ends = static_cast<std::size_t>(key_count) + 1;
  resize_for_overwrite(tally, ends);
  thrust::fill(policy, tally.begin(), tally.end(), 0);
  for_each_index<System>(item_count, kernels::count_keys<Items>{items, raw<index_t>(tally)});
  resize_for_overwrite(offset, ends);
  exclusive_sum<System>(policy, raw<index_t>(tally), raw<index_t>(offset), static_cast<index_t>(ends));
  // The cursors; tally[key_count] stays 0 (a count of keys' ends may follow: `count_node_edges`).
  thrust::copy(policy, offset.begin(), offset.end() - 1, tally.begin());
  resize_for_overwrite(values, value_count >= 0 ? value_count : static_cast<index_t>(offset[key_count]));
  for_each_index<System>(item_count,
                   kernels::fill_by_key<Items>{items, raw<index_t>(tally), raw<index_t>(values)});
  for_each_index<System>(key_count, kernels::sort_runs{raw<index_t>(offset), raw<index_t>(values)});
}

/// Working arrays of `build_device_topology`, kept between builds so they only grow.
template <class System>
struct TopologyScratch {
  vector<System, index_t> node_tally;  // [node_count + 2] corner counts, then cursors, then edge counts
  // A node's half-edges sorted as keys, when some node has more edges than one pass gathers
  // (`sort_node_half_edges`): their counts, their slices' offsets, the keys.
  vector<System, index_t> half_edge_key_count, half_edge_key_offset;
  vector<System, std::uint64_t> half_edge_keys;
  // A patch's marks: the old faces a cut split or renumbered, and the nodes of those faces.
  vector<System, std::uint8_t> face_touched, node_touched;
};

/// Builds the topology of `face_nodes` (already on the backend) into `topo`, using `scratch` and
/// `alloc` for working memory.
template <class System>
void build_device_topology(DeviceTopology<System>& topo, const vector<System, index_t>& face_nodes, index_t node_count,
                           TopologyScratch<System>& scratch, TemporaryAllocator<System>& alloc);

/// The topology of the mesh a cut made, from `old` (the topology of `old_face_nodes`), into `topo`:
/// the arrays `build_device_topology` would build, but only the nodes of the faces the cut split or
/// gave other nodes are counted and written as a build does; every other node's faces, edges and
/// flags are the old ones copied, with faces renumbered. `face_offset` [old face count + 1] is the
/// first new face of each old face (the cut's scan of its new faces); `face_nodes` the new faces,
/// over `node_count` nodes, the old ones first.
template <class System>
void patch_device_topology(DeviceTopology<System>& topo, const DeviceTopology<System>& old,
                           const vector<System, index_t>& old_face_nodes, const vector<System, index_t>& face_offset,
                           const vector<System, index_t>& face_nodes, index_t node_count,
                           TopologyScratch<System>& scratch, TemporaryAllocator<System>& alloc);

template <class System>
Topology build_topology_on(const Mesh& mesh);

}  // namespace tear::backend

namespace tear::backend {

/// The same with working memory of its own (allocated for this one build).
template <class System>
void build_device_topology(DeviceTopology<System>& topo, const vector<System, index_t>& face_nodes, index_t node_count) {
  TopologyScratch<System> scratch;
  TemporaryAllocator<System> alloc;
  build_device_topology(topo, face_nodes, node_count, scratch, alloc);
}

}  // namespace tear::backend
