// tear: the topology arrays as they live on a backend, and their copy to the host.
#pragma once

#include <thrust/copy.h>

#include "backend.h"
#include "tear/topology.h"
#include "temporary_allocator.h"

namespace tear::backend {

/// `Topology` in `System`'s memory; same arrays, same meaning.
template <class System>
struct DeviceTopology {
  index_t node_count = 0, face_count = 0, edge_count = 0;
  vector<System, index_t> edge_nodes, edge_faces, edge_face_count, face_edges, node_face_offset, node_faces;
  vector<System, std::uint8_t> edge_boundary, node_boundary;
};

template <class T, class Vector>
std::vector<T> to_host(const Vector& v) {
  std::vector<T> out(v.size());
  thrust::copy(v.begin(), v.end(), out.begin());
  return out;
}

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

/// Working arrays of `build_device_topology`, kept between builds so they only grow.
template <class System>
struct TopologyScratch {
  vector<System, index_t> node_tally;        // [node_count + 1] corner counts, then cursors, then edge counts
  vector<System, index_t> node_edge_offset;  // [node_count + 1] first edge whose lower node is n
};

/// Builds the topology of `face_nodes` (already on the backend) into `topo`, using `scratch` and
/// `alloc` for working memory.
template <class System>
void build_device_topology(DeviceTopology<System>& topo, const vector<System, index_t>& face_nodes, index_t node_count,
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
