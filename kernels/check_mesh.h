// tear kernels: per-element checks of validate_mesh; each returns 1 for a bad element, so a
// plain integer reduction counts them.
#pragma once

#include <cmath>
#include <cstdint>

#include "hd.h"

namespace tear::kernels {

using index_t = std::int32_t;

struct face_index_out_of_range {
  const index_t* face_nodes;
  index_t node_count;
  TEAR_HD int operator()(index_t f) const {
    for (int k = 0; k < 3; ++k) {
      const index_t n = face_nodes[3 * f + k];
      if (n < 0 || n >= node_count) return 1;
    }
    return 0;
  }
};

struct node_non_finite {
  const float* node_pos;
  TEAR_HD int operator()(index_t n) const {
    for (int d = 0; d < 3; ++d)
      if (!is_finite(node_pos[3 * n + d])) return 1;
    return 0;
  }
};

/// Repeated node, or twice the area at most `ratio` times the squared longest edge.
struct face_degenerate {
  const float* node_pos;
  const index_t* face_nodes;
  double ratio;
  TEAR_HD int operator()(index_t f) const {
    const index_t a = face_nodes[3 * f], b = face_nodes[3 * f + 1], c = face_nodes[3 * f + 2];
    if (a == b || b == c || c == a) return 1;
    double u[3], v[3], w[3];
    for (int d = 0; d < 3; ++d) {
      u[d] = double(node_pos[3 * b + d]) - node_pos[3 * a + d];
      v[d] = double(node_pos[3 * c + d]) - node_pos[3 * a + d];
      w[d] = v[d] - u[d];
    }
    const double cx = u[1] * v[2] - u[2] * v[1], cy = u[2] * v[0] - u[0] * v[2], cz = u[0] * v[1] - u[1] * v[0];
    const double area2_sq = cx * cx + cy * cy + cz * cz;
    double longest = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    const double lv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2], lw = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    longest = lv > longest ? lv : longest;
    longest = lw > longest ? lw : longest;
    return area2_sq <= ratio * ratio * longest * longest ? 1 : 0;
  }
};

/// A face that `face_degenerate` at `thin_ratio` passes but whose height is at most `steps`
/// single-precision steps at its largest coordinate M (a step there is at most M 2^-23): twice
/// its area at most steps M 2^-23 times its longest edge. Example: nodes (0.25, 0, 0), (0.5,
/// 0.75, 0), (1, 0.25, 3333330): M = 3333330, where a step is at most 0.397; the height, 0.79, is
/// 2 steps (and 2.4e-7 of the longest edge, over the thin ratio 1e-7): imprecise.
struct face_imprecise {
  const float* node_pos;
  const index_t* face_nodes;
  double thin_ratio;
  double steps;
  TEAR_HD int operator()(index_t f) const {
    if (face_degenerate{node_pos, face_nodes, thin_ratio}(f)) return 0;  // thin or degenerate already
    const index_t n[3] = {face_nodes[3 * f], face_nodes[3 * f + 1], face_nodes[3 * f + 2]};
    double largest = 0;
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) {
        const double x = node_pos[3 * n[k] + d];
        largest = (x < 0 ? -x : x) > largest ? (x < 0 ? -x : x) : largest;
      }
    double u[3], v[3], w[3];
    for (int d = 0; d < 3; ++d) {
      u[d] = double(node_pos[3 * n[1] + d]) - node_pos[3 * n[0] + d];
      v[d] = double(node_pos[3 * n[2] + d]) - node_pos[3 * n[0] + d];
      w[d] = v[d] - u[d];
    }
    const double cx = u[1] * v[2] - u[2] * v[1], cy = u[2] * v[0] - u[0] * v[2], cz = u[0] * v[1] - u[1] * v[0];
    const double area2_sq = cx * cx + cy * cy + cz * cz;
    double longest = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    const double lv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2], lw = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    longest = lv > longest ? lv : longest;
    longest = lw > longest ? lw : longest;
    const double height = steps * largest * (1.0 / 8388608.0);  // steps * M * 2^-23
    return area2_sq <= height * height * longest ? 1 : 0;
  }
};

/// A face on the same three nodes as another face, in either order. Two such faces oppositely
/// oriented pass every other check (each of their edges has two consistently oriented faces) but
/// close a surface of no volume: a cut through it separates the two faces along the cut and
/// leaves them joined at its ends, which makes bow-tie nodes. Faces repeating a node are only
/// degenerate. Scans the faces of the face's node of fewest faces.
struct face_duplicate {
  const index_t* face_nodes;
  const index_t* node_face_offset;
  const index_t* node_faces;
  TEAR_HD int operator()(index_t f) const {
    const index_t a = face_nodes[3 * f], b = face_nodes[3 * f + 1], c = face_nodes[3 * f + 2];
    if (a == b || b == c || c == a) return 0;
    index_t n = a;
    if (node_face_offset[b + 1] - node_face_offset[b] < node_face_offset[n + 1] - node_face_offset[n]) n = b;
    if (node_face_offset[c + 1] - node_face_offset[c] < node_face_offset[n + 1] - node_face_offset[n]) n = c;
    for (index_t i = node_face_offset[n]; i < node_face_offset[n + 1]; ++i) {
      const index_t g = node_faces[i];
      if (g == f) continue;
      const index_t* m = face_nodes + 3 * g;
      const bool has_a = m[0] == a || m[1] == a || m[2] == a, has_b = m[0] == b || m[1] == b || m[2] == b,
                 has_c = m[0] == c || m[1] == c || m[2] == c;
      if (has_a && has_b && has_c) return 1;
    }
    return 0;
  }
};

struct edge_non_manifold {
  const index_t* edge_face_count;
  TEAR_HD int operator()(index_t e) const { return edge_face_count[e] > 2 ? 1 : 0; }
};

/// Local index of edge e in face f, or -1.
TEAR_HD inline int local_edge(const index_t* face_edges, index_t f, index_t e) {
  for (int k = 0; k < 3; ++k)
    if (face_edges[3 * f + k] == e) return k;
  return -1;
}

/// A two-face edge whose faces run through it in the same direction.
struct edge_inconsistent {
  const index_t* face_nodes;
  const index_t* face_edges;
  const index_t* edge_faces;
  const index_t* edge_face_count;
  TEAR_HD int operator()(index_t e) const {
    if (edge_face_count[e] != 2) return 0;
    const index_t f0 = edge_faces[2 * e], f1 = edge_faces[2 * e + 1];
    if (f0 == f1) return 0;  // both sides in one face repeating a node: degenerate, not misoriented
    const int k0 = local_edge(face_edges, f0, e), k1 = local_edge(face_edges, f1, e);
    if (k0 < 0 || k1 < 0) return 0;
    const index_t a0 = face_nodes[3 * f0 + (k0 + 1) % 3], a1 = face_nodes[3 * f1 + (k1 + 1) % 3];
    return a0 == a1 ? 1 : 0;  // both start the edge at the same node: same direction
  }
};

/// Number of faces reached from the node's first face by crossing the node's manifold
/// (two-face) edges, walking both ways round. Fewer than the node's faces: more than one fan.
struct node_non_manifold {
  const index_t* face_nodes;
  const index_t* face_edges;
  const index_t* edge_faces;
  const index_t* edge_face_count;
  const index_t* node_face_offset;
  const index_t* node_faces;
  TEAR_HD int operator()(index_t n) const {
    // Distinct faces (a face repeating the node is listed once per corner, adjacent in the list).
    const index_t begin = node_face_offset[n], end = node_face_offset[n + 1];
    index_t valence = 0;
    for (index_t i = begin; i < end; ++i) valence += (i == begin || node_faces[i] != node_faces[i - 1]) ? 1 : 0;
    if (valence <= 1) return 0;
    const index_t start = node_faces[begin];
    index_t reached = 1;
    // The two edges of `start` at n; walk out through each.
    int k_n = 0;
    while (k_n < 3 && face_nodes[3 * start + k_n] != n) ++k_n;
    if (k_n == 3) return 1;
    bool closed = false;
    for (int side = 0; side < 2 && !closed; ++side) {
      index_t f = start;
      index_t e = face_edges[3 * start + (k_n + 1 + side) % 3];
      for (index_t step = 0; step < valence; ++step) {
        if (edge_face_count[e] != 2) break;
        const index_t g = edge_faces[2 * e] == f ? edge_faces[2 * e + 1] : edge_faces[2 * e];
        if (g == start) {
          closed = true;
          break;
        }
        ++reached;
        // the other edge of g at n
        int j = 0;
        while (j < 3 && face_nodes[3 * g + j] != n) ++j;
        if (j == 3) return 1;
        const index_t e1 = face_edges[3 * g + (j + 1) % 3], e2 = face_edges[3 * g + (j + 2) % 3];
        e = e1 == e ? e2 : e1;
        f = g;
      }
    }
    return reached < valence ? 1 : 0;
  }
};

}  // namespace tear::kernels
