// tear: mesh connectivity, built on the device (either backend) from face_nodes.
#pragma once

#include <cstdint>
#include <vector>

#include "tear/device.h"
#include "tear/mesh.h"

namespace tear {

/// Connectivity of a triangle mesh, as flat index arrays.
///
/// Edges are the unique unordered node pairs of the faces, ordered by (low node, high node).
struct Topology {
  index_t node_count = 0;
  index_t face_count = 0;
  index_t edge_count = 0;
  std::vector<index_t> edge_nodes;        ///< [edge_count * 2] low node, high node
  std::vector<index_t> edge_faces;        ///< [edge_count * 2] faces in ascending order; second is -1 on the boundary
  std::vector<index_t> edge_face_count;   ///< [edge_count] faces on the edge (more than 2: non-manifold)
  std::vector<index_t> face_edges;        ///< [face_count * 3] local edge k is opposite local node k
  std::vector<index_t> node_face_offset;  ///< [node_count + 1] CSR offsets into node_faces
  std::vector<index_t> node_faces;        ///< [face_count * 3] faces around each node, ascending
  std::vector<std::uint8_t> edge_boundary;  ///< [edge_count] 1 if the edge has exactly one face
  std::vector<std::uint8_t> node_boundary;  ///< [node_count] 1 if the node is on a boundary edge
};

/// Builds the topology of `mesh` on `device`: edges by sort + unique of node pairs, edge→faces,
/// face→edges, node→faces (CSR) and boundary flags. Requires every index in range
/// (see `validate_mesh`).
Topology build_topology(const Mesh& mesh, Device device);

}  // namespace tear
