// tear kernels: carrying attributes through a cut (paper §2.2–2.3, write steps), one rule each:
// - interpolate (node values): a gather over the new node's provenance (write_new_nodes.h), in a
//   fixed order; a copy of one old node is bit-exact;
// - copy (node flags): a copy of one old node takes its flag, a node made inside an edge or a face
//   gets 0 (a pin stays with both copies of a pinned node, a new node is free);
//   (both in one pass over the new nodes: carry_node_attributes)
// - parent (face values): each new face takes its parent face's value;
// - corner values are interpolated inside the parent face;
//   (both written by `write_new_faces`, with the parents)
// Example: old vel [a, b], new node 2 = 0.75·node 0 + 0.25·node 1 → new vel [a, b, 0.75a + 0.25b];
// old pinned [1, 0] → new pinned [1, 0, 0].
#pragma once

#include <cstdint>

#include "hd.h"

namespace tear::kernels {

/// One node attribute of `comps` floats per node (1..4), interpolated over the new node's sources.
struct NodeValueArrays {
  const float* old_value;  ///< [old_node_count * comps]
  float* new_value;        ///< [new_node_count * comps]
  int comps;
};

/// One node flag: the copies of an old node keep its flag; interpolated nodes get 0.
struct NodeFlagArrays {
  const std::uint8_t* old_flag;  ///< [old_node_count]
  std::uint8_t* new_flag;        ///< [new_node_count]
};

/// The node attributes a cut carries, as a small value one kernel takes.
struct NodeAttributes {
  static constexpr int value_capacity = 4, flag_capacity = 2;
  NodeValueArrays values[value_capacity];
  int value_count = 0;
  NodeFlagArrays flags[flag_capacity];
  int flag_count = 0;
};

/// Every node attribute of new node i from its sources (write_new_nodes.h), in one pass: values
/// interpolated in a fixed order (a copy of one old node is bit-exact), flags copied from the
/// node's one source or 0.
struct carry_node_attributes {
  const index_t* node_source;       ///< [new_node_count * 3], -1 unused
  const float* node_source_weight;  ///< [new_node_count * 3]
  NodeAttributes at;
  TEAR_HD void operator()(index_t i) const {
    index_t n[3];
    float w[3];
    for (int s = 0; s < 3; ++s) {
      n[s] = node_source[3 * i + s];
      w[s] = node_source_weight[3 * i + s];
    }
    const bool copy = n[0] >= 0 && w[0] == 1.f;  // a copy: bit-exact
    TEAR_UNROLL
    for (int a = 0; a < NodeAttributes::value_capacity; ++a) {
      if (a >= at.value_count) break;
      const NodeValueArrays& x = at.values[a];
      float v[4] = {0, 0, 0, 0};
      if (copy) {
        for (int d = 0; d < x.comps; ++d) v[d] = x.old_value[x.comps * n[0] + d];
      } else {
        for (int s = 0; s < 3; ++s) {
          if (n[s] < 0) continue;
          for (int d = 0; d < x.comps; ++d) v[d] += w[s] * x.old_value[x.comps * n[s] + d];
        }
      }
      for (int d = 0; d < x.comps; ++d) x.new_value[x.comps * i + d] = v[d];
    }
    const bool flag_copy = n[1] < 0 && w[0] == 1.f;
    TEAR_UNROLL
    for (int a = 0; a < NodeAttributes::flag_capacity; ++a)
      if (a < at.flag_count) at.flags[a].new_flag[i] = flag_copy ? at.flags[a].old_flag[n[0]] : std::uint8_t(0);
  }
};

/// One face value (an index per face): each new face takes its parent's.
/// One face value (an index or a float), copied bit for bit from the parent as a 32-bit word.
struct FaceValueArrays {
  const std::uint32_t* old_value;  ///< [old_face_count]
  std::uint32_t* new_value;        ///< [new_face_count]
};

/// The face values a cut carries; `write_new_faces` writes them with the parents.
struct FaceAttributes {
  static constexpr int capacity = 3;
  FaceValueArrays at[capacity];
  int count = 0;
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

/// Copies `Count` floats, all loaded before any is stored: a store may alias a later load, so
/// value by value each load would wait for the store before it.
template <int Count>
TEAR_HD inline void copy_floats(const float* from, float* to) {
  float v[Count];
  TEAR_UNROLL
  for (int i = 0; i < Count; ++i) v[i] = from[i];
  TEAR_UNROLL
  for (int i = 0; i < Count; ++i) to[i] = v[i];
}

/// A new corner at an old node of its parent face (corner `local` of it) keeps that corner's
/// values exactly, unit values included: a face no cut touches keeps its corners bit for bit, and
/// the corners around an old node stay as equal as they were.
TEAR_HD inline void copy_corner(const CornerValues& a, index_t old_face, int local, index_t new_corner) {
  const float* old = a.old_value + a.comps * (3 * old_face + local);
  float* out = a.new_value + a.comps * new_corner;
  switch (a.comps) {
    case 1: copy_floats<1>(old, out); break;
    case 2: copy_floats<2>(old, out); break;
    case 3: copy_floats<3>(old, out); break;
    default: copy_floats<4>(old, out); break;
  }
}

/// The three corners of a face the cut left whole (one new face, its corners the old ones in
/// order), copied as one block.
TEAR_HD inline void copy_face_corners(const CornerValues& a, index_t old_face, index_t new_face) {
  const float* old = a.old_value + 3 * a.comps * old_face;
  float* out = a.new_value + 3 * a.comps * new_face;
  switch (a.comps) {
    case 1: copy_floats<3>(old, out); break;
    case 2: copy_floats<6>(old, out); break;
    case 3: copy_floats<9>(old, out); break;
    default: copy_floats<12>(old, out); break;
  }
}

}  // namespace tear::kernels
