// tear kernels: cracks where the cloth is stretched too far (the `tearing` of a simulation).
//
// A face's stretch is the largest principal stretch of its map from the rest triangle to the
// current one: the largest singular value of its 3x2 deformation gradient F, whose right singular
// vector r is the rest-space direction stretched most. A face over the limit tears when it is the
// most stretched of the faces sharing a node with it (by stretch, then the lower face index), so
// the faces torn at once share no node. The crack runs through the face across r in the rest
// shape, and is written as `intersect_cuts` writes a cut's crossings (per-face half-edge hits and
// the pairs of places a line joins), so the rest of §2.1 and §2.2–2.4 treat it as a scripted cut.
//
// Example: one face, nodes 0 1 2 at rest (0,0,0) (1,0,0) (0,1,0), now at (0,0,0) (1.5,0,0) (0,1,0):
// stretch 1.5 along r = (1,0,0). No node's line across r enters the face, so the crack runs through
// the centroid along x = 1/3: half_hit_sum = [2/3, 0, 1/3] (edge 0 from node 1 to node 2 at 2/3,
// edge 2 from node 0 to node 1 at 1/3), half_hit_count = [1, 0, 1], face_pairs = the bit of the
// places (edge 0, edge 2), crack_length = 2/3 m (from (1/3, 0) to (1/3, 2/3)).
#pragma once

#include <cmath>
#include <cstdint>

#include "cut_info.h"
#include "hd.h"
#include "intersect_cuts.h"

namespace tear::kernels {

/// The largest principal stretch of face f (0 for a face of no rest area); with `r` given, also
/// the rest-space unit direction it stretches most along.
TEAR_HD inline double face_principal_stretch(const index_t* face_nodes, const float* node_rest, const float* node_pos,
                                             index_t f, double* r = nullptr) {
  double X[3][3], x[3][3];
  for (int k = 0; k < 3; ++k) {
    const index_t n = face_nodes[3 * f + k];
    for (int d = 0; d < 3; ++d) {
      X[k][d] = node_rest[3 * n + d];
      x[k][d] = node_pos[3 * n + d];
    }
  }
  // The rest triangle in an orthonormal frame (u, v) of its plane: edges (l1, 0) and (a, h).
  double E1[3], E2[3], e1[3], e2[3];
  for (int d = 0; d < 3; ++d) {
    E1[d] = X[1][d] - X[0][d];
    E2[d] = X[2][d] - X[0][d];
    e1[d] = x[1][d] - x[0][d];
    e2[d] = x[2][d] - x[0][d];
  }
  const double l1 = sqrt(E1[0] * E1[0] + E1[1] * E1[1] + E1[2] * E1[2]);
  if (!(l1 > 0)) return 0;
  double u[3], w[3];
  for (int d = 0; d < 3; ++d) u[d] = E1[d] / l1;
  const double a = E2[0] * u[0] + E2[1] * u[1] + E2[2] * u[2];
  for (int d = 0; d < 3; ++d) w[d] = E2[d] - a * u[d];
  const double h = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  if (!(h > 1e-12 * l1)) return 0;
  // F = [e1 e2] Dm^-1 with Dm = [[l1, a], [0, h]]: its columns f1, f2.
  double f1[3], f2[3];
  for (int d = 0; d < 3; ++d) {
    f1[d] = e1[d] / l1;
    f2[d] = (e2[d] - (a / l1) * e1[d]) / h;
  }
  const double c11 = f1[0] * f1[0] + f1[1] * f1[1] + f1[2] * f1[2];
  const double c12 = f1[0] * f2[0] + f1[1] * f2[1] + f1[2] * f2[2];
  const double c22 = f2[0] * f2[0] + f2[1] * f2[1] + f2[2] * f2[2];
  // The larger eigenvalue of the right Cauchy-Green tensor F^T F and its eigenvector.
  const double half_diff = 0.5 * (c11 - c22);
  const double lambda = 0.5 * (c11 + c22) + sqrt(half_diff * half_diff + c12 * c12);
  if (r) {
    double p0 = lambda - c22, p1 = c12, q0 = c12, q1 = lambda - c11;
    double n0 = p0 * p0 + p1 * p1, n1 = q0 * q0 + q1 * q1;
    double r0 = 1, r1 = 0;
    if (n0 >= n1 && n0 > 0) {
      r0 = p0 / sqrt(n0);
      r1 = p1 / sqrt(n0);
    } else if (n1 > 0) {
      r0 = q0 / sqrt(n1);
      r1 = q1 / sqrt(n1);
    }
    for (int d = 0; d < 3; ++d) r[d] = r0 * u[d] + r1 * w[d] / h;
  }
  return lambda > 0 ? sqrt(lambda) : 0;
}

/// Per face: its stretch.
struct write_face_stretch {
  const index_t* face_nodes;
  const float* node_rest;
  const float* node_pos;
  double* face_stretch;
  TEAR_HD void operator()(index_t f) const {
    face_stretch[f] = face_principal_stretch(face_nodes, node_rest, node_pos, f);
  }
};

/// Per face: its crossings cleared (half-edge hits and pairs), before the cracks are written.
struct clear_crossings {
  double* half_hit_sum;
  index_t* half_hit_count;
  std::uint16_t* face_pairs;
  TEAR_HD void operator()(index_t f) const {
    for (int k = 0; k < 3; ++k) {
      half_hit_sum[3 * f + k] = 0;
      half_hit_count[3 * f + k] = 0;
    }
    face_pairs[f] = 0;
  }
};

/// Face f ranks before face g: more stretched, or as stretched and of a lower index.
TEAR_HD inline bool tears_before(const double* face_stretch, index_t f, index_t g) {
  return face_stretch[f] > face_stretch[g] || (face_stretch[f] == face_stretch[g] && f < g);
}

/// Per face: 1 when it is over `limit` and ranks before every face sharing a node with it (an
/// independent set: no two chosen faces share a node).
struct choose_tearing_faces {
  const index_t* face_nodes;
  const index_t* node_face_offset;
  const index_t* node_faces;
  const double* face_stretch;
  double limit;
  std::uint8_t* chosen;
  TEAR_HD void operator()(index_t f) const {
    std::uint8_t pick = face_stretch[f] > limit ? 1 : 0;
    for (int k = 0; k < 3 && pick; ++k) {
      const index_t n = face_nodes[3 * f + k];
      for (index_t i = node_face_offset[n]; i < node_face_offset[n + 1] && pick; ++i) {
        const index_t g = node_faces[i];
        if (g != f && !tears_before(face_stretch, f, g)) pick = 0;
      }
    }
    chosen[f] = pick;
  }
};

/// Orders chosen faces by rank (most stretched first, ties by index), for the cap on a substep.
struct by_tear_rank {
  const double* face_stretch;
  TEAR_HD bool operator()(index_t f, index_t g) const { return tears_before(face_stretch, f, g); }
};

struct is_chosen {
  const std::uint8_t* chosen;
  TEAR_HD bool operator()(index_t f) const { return chosen[f] != 0; }
};

/// Per chosen face (one thread each, `chosen` [count]): the crack through it, written as cut
/// crossings into `half_hit_sum` / `half_hit_count` [face_count * 3] and `face_pairs`
/// [face_count], all zero beforehand.
///
/// The crack runs across r, the rest direction stretched most. From a node of the face on the
/// border (a crack tip or the cloth's edge) when the line from it across r enters the face (of
/// several, the one crossing its opposite edge nearest the middle, then the lowest local node):
/// node to opposite edge. Otherwise through the face's centroid: edge to edge. At each crossed
/// edge that is not on the border the crack goes on into the face across it, to that face's
/// opposite node, so the edge's cut point has a line on both sides and opens. The faces written
/// are the chosen face and the faces across its edges: those of two chosen faces never meet, as
/// chosen faces share no node. `crack_length` [count]: the rest length of the crack's segments.
struct write_cracks {
  const index_t* chosen;
  const index_t* face_nodes;
  const index_t* face_edges;
  const index_t* edge_faces;
  const std::uint8_t* node_boundary;  ///< [node_count] 1 for a node on a border edge (the topology's)
  const float* node_rest;
  const float* node_pos;
  double* half_hit_sum;
  index_t* half_hit_count;
  std::uint16_t* face_pairs;
  double* crack_length;

  TEAR_HD void rest_point(index_t n, double* p) const {
    for (int d = 0; d < 3; ++d) p[d] = node_rest[3 * n + d];
  }
  TEAR_HD static double distance(const double* p, const double* q) {
    double s = 0;
    for (int d = 0; d < 3; ++d) s += (p[d] - q[d]) * (p[d] - q[d]);
    return sqrt(s);
  }

  TEAR_HD void operator()(index_t i) const {
    const index_t f = chosen[i];
    crack_length[i] = 0;
    double r[3];
    if (!(face_principal_stretch(face_nodes, node_rest, node_pos, f, r) > 0)) return;
    index_t node[3];
    double X[3][3];
    for (int k = 0; k < 3; ++k) {
      node[k] = face_nodes[3 * f + k];
      rest_point(node[k], X[k]);
    }
    // The line is {p : (p - anchor) · r = 0}; s[k] the signed distance of node k from it.
    int tip = -1;
    double tip_t = 0, best = 2;
    for (int k = 0; k < 3; ++k) {
      if (!node_boundary[node[k]]) continue;
      const int a = (k + 1) % 3, b = (k + 2) % 3;
      double sa = 0, sb = 0;
      for (int d = 0; d < 3; ++d) {
        sa += (X[a][d] - X[k][d]) * r[d];
        sb += (X[b][d] - X[k][d]) * r[d];
      }
      if (!((sa < 0 && sb > 0) || (sa > 0 && sb < 0))) continue;
      const double t = sa / (sa - sb);
      const double off = t < 0.5 ? 0.5 - t : t - 0.5;
      if (off < best) {
        best = off;
        tip = k;
        tip_t = t;
      }
    }
    int loc[2];      // the crack's two places in the face: 0..2 inside edge k, 3..5 on node k-3
    double t_at[3];  // where along local edge k (from local node k+1), for places inside edges
    int found = 0;
    if (tip >= 0) {
      loc[0] = 3 + tip;
      loc[1] = tip;
      t_at[tip] = tip_t;
      found = 2;
    } else {
      double c[3], s[3];
      for (int d = 0; d < 3; ++d) c[d] = (X[0][d] + X[1][d] + X[2][d]) / 3.0;
      for (int k = 0; k < 3; ++k) {
        s[k] = 0;
        for (int d = 0; d < 3; ++d) s[k] += (X[k][d] - c[d]) * r[d];
      }
      for (int k = 0; k < 3 && found < 3; ++k) {
        const double sa = s[(k + 1) % 3], sb = s[(k + 2) % 3];
        if (s[k] == 0.0) {
          if (found < 2) loc[found] = 3 + k;
          ++found;
        } else if ((sa < 0 && sb > 0) || (sa > 0 && sb < 0)) {
          t_at[k] = sa / (sa - sb);
          if (found < 2) loc[found] = k;
          ++found;
        }
      }
      if (found != 2) return;  // the line misses the face's inside (no stretch direction)
    }
    // The places' rest points, for the crack's length.
    double P[2][3];
    for (int j = 0; j < 2; ++j) {
      const int l = loc[j];
      if (l >= 3) {
        for (int d = 0; d < 3; ++d) P[j][d] = X[l - 3][d];
      } else {
        const double t = t_at[l];
        for (int d = 0; d < 3; ++d) P[j][d] = (1 - t) * X[(l + 1) % 3][d] + t * X[(l + 2) % 3][d];
      }
    }
    double length = distance(P[0], P[1]);
    face_pairs[f] = std::uint16_t(face_pairs[f] | (1u << location_pair_bit(loc[0], loc[1])));
    for (int j = 0; j < 2; ++j) {
      const int k = loc[j];
      if (k >= 3) continue;
      const index_t e = face_edges[3 * f + k];
      const bool forward = node[(k + 1) % 3] < node[(k + 2) % 3];
      const double t_canonical = forward ? t_at[k] : 1.0 - t_at[k];
      half_hit_sum[3 * f + k] = t_canonical;
      half_hit_count[3 * f + k] = 1;
      // On into the face across the edge, to its opposite node.
      const index_t g = edge_faces[2 * e] == f ? edge_faces[2 * e + 1] : edge_faces[2 * e];
      if (g < 0) continue;
      const int kg = local_edge_of(face_edges, g, e);
      half_hit_sum[3 * g + kg] = t_canonical;
      half_hit_count[3 * g + kg] = 1;
      face_pairs[g] = std::uint16_t(face_pairs[g] | (1u << location_pair_bit(kg, 3 + kg)));
      double O[3];
      rest_point(face_nodes[3 * g + kg], O);
      length += distance(P[j], O);
    }
    crack_length[i] = length;
  }
};

}  // namespace tear::kernels
