// tear kernels: the new faces (paper §2.3, write step): parent face and per-corner attributes,
// interpolated inside the parent face only, so UVs never blend across a seam; a corner at an old
// node keeps that node's corner values exactly.
#pragma once

#include <cmath>

#include "carry_attributes.h"
#include "cut_info.h"
#include "split_table.h"

namespace tear::kernels {

/// Barycentric coordinates over face f's corners of a point code of f's split.
TEAR_HD inline void point_code_bary(std::uint8_t code, const index_t* face_nodes, const index_t* face_edges,
                                    const float* edge_point_t, const float* face_point_bary, index_t f, double* b) {
  const int local = point_local(code);
  switch (point_kind(code)) {
    case PointKind::node:
      b[0] = b[1] = b[2] = 0.0;
      b[local] = 1.0;
      break;
    case PointKind::edge: {
      const index_t e = face_edges[3 * f + local];
      const bool forward = face_nodes[3 * f + (local + 1) % 3] < face_nodes[3 * f + (local + 2) % 3];
      edge_point_bary(local, forward ? edge_point_t[e] : 1.0 - edge_point_t[e], b);
      break;
    }
    default:
      for (int i = 0; i < 3; ++i) b[i] = face_point_bary[3 * f + i];
  }
}

/// Each face writes its new triangles' parents and carries its face values and corner attributes
/// into them.
struct write_new_faces {
  const index_t* face_nodes;
  const index_t* face_edges;
  const std::uint16_t* face_state;
  const SplitCase* table;
  const float* edge_point_t;
  const float* face_point_bary;
  const index_t* face_tri_offset;
  CornerAttributes corners;
  FaceAttributes face_values;
  index_t* new_face_parent;
  TEAR_HD void operator()(index_t f) const {
    const SplitCase& c = split_case(table, face_state[f]);
    for (int t = 0; t < c.tri_count; ++t) {
      const index_t nf = face_tri_offset[f] + t;
      new_face_parent[nf] = f;
      // The attribute loops run to the capacity with the count as a condition: the index of the
      // by-value arrays is then known at compile time, and they stay in registers.
      TEAR_UNROLL
      for (int a = 0; a < FaceAttributes::capacity; ++a)
        if (a < face_values.count) face_values.at[a].new_value[nf] = face_values.at[a].old_value[f];
      if (c.tri_count == 1 && c.tri[0][0] == point_code(PointKind::node, 0) &&
          c.tri[0][1] == point_code(PointKind::node, 1) && c.tri[0][2] == point_code(PointKind::node, 2)) {
        TEAR_UNROLL
        for (int a = 0; a < CornerAttributes::capacity; ++a)
          if (a < corners.count) copy_face_corners(corners.at[a], f, nf);
        continue;
      }
      for (int k = 0; k < 3; ++k) {
        const std::uint8_t code = c.tri[t][k];
        if (point_kind(code) == PointKind::node) {
          TEAR_UNROLL
          for (int a = 0; a < CornerAttributes::capacity; ++a)
            if (a < corners.count) copy_corner(corners.at[a], f, point_local(code), 3 * nf + k);
          continue;
        }
        double b[3];
        point_code_bary(code, face_nodes, face_edges, edge_point_t, face_point_bary, f, b);
        TEAR_UNROLL
        for (int a = 0; a < CornerAttributes::capacity; ++a)
          if (a < corners.count) interpolate_corner(corners.at[a], f, 3 * nf + k, b);
      }
    }
  }
};

}  // namespace tear::kernels
