// tear: the one record of a cloth on a backend, which the remesher and the solver both work on in
// place (docs/identity.md).
//
//   model   face_nodes, node_rest, corner UVs and normals, topology
//   state   node_pos, node_vel
//   carried node_pinned, face_origin, corner_origin (with the model and state, every array a cut
//           must carry, each listed once below with its element and rule)
//
// Example: a sheet of 2 faces read from a file: face_origin = [0, 1], corner_origin = the unit
// weights (1,0,0 | 0,1,0 | 0,0,1) of each face's corners; after a cut through face 1, the new
// faces all have face_origin 1 and their corners the weights of where they lie in face 1.
#pragma once

#include <array>
#include <cstdint>

#include "backend/backend.h"
#include "topology/device_topology.h"

namespace tear::backend {

template <class System>
struct DeviceCloth {
  template <class T>
  using vec = vector<System, T>;

  // Model.
  vec<index_t> face_nodes;   ///< [face_count * 3]
  vec<float> node_rest;      ///< [node_count * 3] metres
  vec<float> corner_uv;      ///< [face_count * 3 * 2] or empty
  vec<float> corner_normal;  ///< [face_count * 3 * 3] or empty
  DeviceTopology<System> topo;
  // State.
  vec<float> node_pos;  ///< [node_count * 3] metres
  vec<float> node_vel;  ///< [node_count * 3] m/s
  // Carried attributes besides the model and state.
  vec<std::uint8_t> node_pinned;  ///< [node_count] 0 free, p + 1 held by pin p
  vec<index_t> face_origin;       ///< [face_count] the face of the mesh as read this face lies in
  vec<float> corner_origin;       ///< [face_count * 3 * 3] the corner's weights in its origin face
  // Of the mesh as read, not carried: bit j of face F = F's edge j was on the border.
  vec<std::uint8_t> input_face_border;

  index_t node_count() const { return topo.node_count; }
  index_t face_count() const { return topo.face_count; }

  // The carried attributes, by element and rule. A cut carries every entry; an empty array (a
  // mesh without UVs) is skipped. A new attribute is a new entry here.
  struct NodeValues {
    vec<float>* values;
    int comps;
  };
  struct CornerValues {
    vec<float>* values;
    int comps;
    bool unit;  ///< renormalised after interpolation
  };
  /// Node values interpolated over the node's sources.
  std::array<NodeValues, 3> node_values() { return {{{&node_pos, 3}, {&node_rest, 3}, {&node_vel, 3}}}; }
  /// Node flags kept by a node's copies, 0 on nodes made inside an edge or a face.
  std::array<vec<std::uint8_t>*, 1> node_flags() { return {&node_pinned}; }
  /// Face values each new face takes from its parent.
  std::array<vec<index_t>*, 1> face_values() { return {&face_origin}; }
  /// Corner values interpolated inside the parent face.
  std::array<CornerValues, 3> corner_values() {
    return {{{&corner_uv, 2, false}, {&corner_normal, 3, true}, {&corner_origin, 3, false}}};
  }
};

}  // namespace tear::backend
