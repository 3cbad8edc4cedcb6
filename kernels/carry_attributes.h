// tear kernels: carrying attributes through a cut (paper §2.2–2.3, write steps), one rule each:
// - interpolate (node values): a gather over the new node's provenance (write_new_nodes.h), in a
//   fixed order; a copy of one old node is bit-exact;
// - copy (node flags): a copy of one old node takes its flag, a node made inside an edge or a face
//   gets 0 (a pin stays with both copies of a pinned node, a new node is free);
// - parent (face values): each new face takes its parent face's value;
// - corner values are interpolated inside the parent face by `write_new_faces`.
// Example: old vel [a, b], new node 2 = 0.75·node 0 + 0.25·node 1 → new vel [a, b, 0.75a + 0.25b];
// old pinned [1, 0] → new pinned [1, 0, 0].
#pragma once

#include <cstdint>

#include "hd.h"

namespace tear::kernels {

/// Node values with `comps` floats per node, interpolated over the new node's sources.
struct interpolate_node_values {
  const index_t* node_source;       ///< [new_node_count * 3], -1 unused
  const float* node_source_weight;  ///< [new_node_count * 3]
  const float* old_value;           ///< [old_node_count * comps]
  float* new_value;                 ///< [new_node_count * comps]
  int comps;
  TEAR_HD void operator()(index_t i) const {
    float v[4] = {0, 0, 0, 0};
    for (int s = 0; s < 3; ++s) {
      const index_t n = node_source[3 * i + s];
      if (n < 0) continue;
      const float w = node_source_weight[3 * i + s];
      if (s == 0 && w == 1.f) {  // a copy: bit-exact
        for (int d = 0; d < comps; ++d) v[d] = old_value[comps * n + d];
        break;
      }
      for (int d = 0; d < comps; ++d) v[d] += w * old_value[comps * n + d];
    }
    for (int d = 0; d < comps; ++d) new_value[comps * i + d] = v[d];
  }
};

/// Node flags: the copies of an old node keep its flag; interpolated nodes get 0.
struct copy_node_flags {
  const index_t* node_source;
  const float* node_source_weight;
  const std::uint8_t* old_flag;
  std::uint8_t* new_flag;
  TEAR_HD void operator()(index_t i) const {
    const bool copy = node_source[3 * i + 1] < 0 && node_source_weight[3 * i] == 1.f;
    new_flag[i] = copy ? old_flag[node_source[3 * i]] : std::uint8_t(0);
  }
};

/// Face values: each new face takes its parent's.
struct copy_parent_values {
  const index_t* new_face_parent;  ///< [new_face_count]
  const index_t* old_value;        ///< [old_face_count]
  index_t* new_value;              ///< [new_face_count]
  TEAR_HD void operator()(index_t f) const { new_value[f] = old_value[new_face_parent[f]]; }
};

/// One corner attribute: `comps` floats per corner (corner c = 3 * face + k), interpolated with the
/// barycentric weights of the new corner in its parent face; `unit` values (normals) are
/// renormalised.
struct CornerValues {
  const float* old_value;  ///< [old_face_count * 3 * comps]
  float* new_value;        ///< [new_face_count * 3 * comps]
  int comps;               ///< 1..4
  bool unit;
};

/// The corner attributes a cut carries, as a small value the face writer takes.
struct CornerAttributes {
  static constexpr int capacity = 4;
  CornerValues at[capacity];
  int count = 0;
};

/// Writes the new corner's values from its parent face's corners, barycentric weights `b` (double,
/// so a weight of exactly 0 keeps a zero value exactly zero). `Comps` fixed at compile time, so the
/// loops unroll.
template <int Comps>
TEAR_HD inline void interpolate_corner(const CornerValues& a, index_t old_face, index_t new_corner, const double* b) {
  double v[Comps], len2 = 0;
  const float* old = a.old_value + 3 * Comps * old_face;
  TEAR_UNROLL
  for (int d = 0; d < Comps; ++d) {
    v[d] = 0;
    for (int i = 0; i < 3; ++i) v[d] += b[i] * old[i * Comps + d];
    len2 += v[d] * v[d];
  }
  const double scale = !a.unit ? 1.0 : len2 > 0 ? 1.0 / sqrt(len2) : 0.0;
  float* out = a.new_value + Comps * new_corner;
  TEAR_UNROLL
  for (int d = 0; d < Comps; ++d) out[d] = static_cast<float>(v[d] * scale);
}

TEAR_HD inline void interpolate_corner(const CornerValues& a, index_t old_face, index_t new_corner, const double* b) {
  switch (a.comps) {
    case 1: interpolate_corner<1>(a, old_face, new_corner, b); break;
    case 2: interpolate_corner<2>(a, old_face, new_corner, b); break;
    case 3: interpolate_corner<3>(a, old_face, new_corner, b); break;
    default: interpolate_corner<4>(a, old_face, new_corner, b); break;
  }
}

}  // namespace tear::kernels
