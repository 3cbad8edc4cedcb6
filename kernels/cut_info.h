// tear kernels: cut points and cut info (paper §2.1, second half): one averaged, snapped cut
// point per edge, the 6-bit face cut info with its face point, the 2-bit edge cut info.
#pragma once

#include <cstdint>

#include "cut_geometry.h"
#include "hd.h"
#include "intersect_cuts.h"
#include "split_table.h"

namespace tear::kernels {

/// Where an edge's cut point ended up.
enum EdgePoint : std::uint8_t {
  edge_point_none = 0,
  edge_point_inside = 1,     ///< strictly inside the edge: a new node E
  edge_point_low_node = 2,   ///< snapped onto the edge's low node
  edge_point_high_node = 3,  ///< snapped onto the edge's high node
};

/// Local index of edge e in face f (e is one of its edges).
TEAR_HD inline int local_edge_of(const index_t* face_edges, index_t f, index_t e) {
  return face_edges[3 * f] == e ? 0 : face_edges[3 * f + 1] == e ? 1 : 2;
}

/// Per edge: the mean of its crossings from both faces (a gather in face order: deterministic),
/// snapped onto a node when nearer than `snap` times the edge's length.
struct snap_edge_points {
  const index_t* edge_faces;
  const index_t* face_edges;
  const double* half_hit_sum;
  const index_t* half_hit_count;
  double snap;
  float* edge_point_t;       ///< [edge_count] parameter from the low node to the high node
  std::uint8_t* edge_point;  ///< [edge_count] EdgePoint
  TEAR_HD void operator()(index_t e) const {
    double sum = 0;
    index_t count = 0;
    for (int side = 0; side < 2; ++side) {
      const index_t f = edge_faces[2 * e + side];
      if (f < 0) continue;
      const int k = local_edge_of(face_edges, f, e);
      sum += half_hit_sum[3 * f + k];
      count += half_hit_count[3 * f + k];
    }
    std::uint8_t kind = edge_point_none;
    double t = 0;
    if (count) {
      t = sum / count;
      kind = t < snap ? edge_point_low_node : t > 1.0 - snap ? edge_point_high_node : edge_point_inside;
    }
    edge_point[e] = kind;
    edge_point_t[e] = kind == edge_point_inside ? static_cast<float>(t) : (kind == edge_point_high_node ? 1.0f : 0.0f);
  }
};

/// Barycentric coordinates (over the face's local nodes) of local edge k's point at parameter
/// `t_local` from local node k+1 to local node k+2.
TEAR_HD inline void edge_point_bary(int k, double t_local, double* b) {
  b[k] = 0.0;
  b[(k + 1) % 3] = 1.0 - t_local;
  b[(k + 2) % 3] = t_local;
}

/// Crossing of segments a0→a1 and b0→b1 in barycentric (b1, b2) coordinates: an affine image of
/// the face, so the crossing is the same point as on the face itself.
TEAR_HD inline bool cross_bary(const double* a0, const double* a1, const double* b0, const double* b1, double* out) {
  const Vec2 p{a0[1], a0[2]}, r{a1[1] - a0[1], a1[2] - a0[2]}, q{b0[1], b0[2]}, s{b1[1] - b0[1], b1[2] - b0[2]};
  const double d = cross(r, s);
  if (d == 0.0) return false;
  const double u = cross(q - p, s) / d;
  for (int i = 0; i < 3; ++i) out[i] = a0[i] + u * (a1[i] - a0[i]);
  return true;
}

/// Rest positions of the 7 point slots of face f's split (N0..N2, E0..E2 at `t_local`, P at the
/// face point).
TEAR_HD inline void face_point_positions(const index_t* face_nodes, const float* node_rest,
                                         const float* face_point_bary, index_t f, const double* t_local,
                                         double (*point_pos)[3]) {
  for (int slot = 0; slot < face_point_slot_count; ++slot) {
    double b[3] = {0, 0, 0};
    if (slot < 3)
      b[slot] = 1.0;
    else if (slot < 6)
      edge_point_bary(slot - 3, t_local[slot - 3], b);
    else
      for (int i = 0; i < 3; ++i) b[i] = face_point_bary[3 * f + i];
    for (int d = 0; d < 3; ++d) {
      point_pos[slot][d] = 0;
      for (int i = 0; i < 3; ++i) point_pos[slot][d] += b[i] * node_rest[3 * face_nodes[3 * f + i] + d];
    }
  }
}

/// The face point is kept at least this far (in barycentric coordinates) from the face's edges,
/// so the fan of triangles around it has no sliver; the cut bends by less than an element.
inline constexpr double face_point_min_bary = 0.1;

/// Per face: resolves the pairs of crossing places into cut lines once edge points are snapped.
/// Writes the face's split code (split_table.h: the 9-bit cut state and the split variant whose
/// triangles are best shaped on the rest shape), the along-edge lines this face sees
/// (`face_along` bits 2k, 2k+1: the half of local edge k at local node k+1 / k+2), and the face
/// point's barycentric coordinates when the state has one.
struct face_cut_info {
  const index_t* face_nodes;
  const index_t* face_edges;
  const std::uint16_t* face_pairs;
  const std::uint8_t* edge_point;
  const float* edge_point_t;
  std::uint16_t* face_state;
  std::uint8_t* face_along;
  float* face_point_bary;  ///< [face_count * 3]
  const float* node_rest;  ///< [node_count * 3]
  const SplitCase* table;  ///< [split_table_size]

  TEAR_HD void operator()(index_t f) const {
    // Where each crossing place ended up: 0..2 node k, 3..5 edge point k, -1 nowhere.
    int place[6];
    double t_local[3];
    std::uint16_t state = edge_places(f, place, t_local);
    face_along[f] = resolve_lines(face_pairs[f], place, state);

    double bary[3] = {1.0 / 3, 1.0 / 3, 1.0 / 3};
    if (has_face_point(state)) face_point(state, t_local, bary);
    for (int i = 0; i < 3; ++i) face_point_bary[3 * f + i] = static_cast<float>(bary[i]);

    // A per-face choice on the rest shape, so it does not flip as the cloth moves.
    int variant = 0;
    if (table[face_split_code(state, 0)].variant_count > 1) {
      double point_pos[face_point_slot_count][3];
      face_point_positions(face_nodes, node_rest, face_point_bary, f, t_local, point_pos);
      variant = best_split_variant(table, state, point_pos);
    }
    face_state[f] = face_split_code(state, variant);
  }

  /// Face f's crossing places after snapping (`place`: 0..2 node k, 3..5 edge point k, -1
  /// nowhere) and its edge points' parameters along its local edges (`t_local`); returns the
  /// state's edge-point bits.
  TEAR_HD std::uint16_t edge_places(index_t f, int (&place)[6], double (&t_local)[3]) const {
    std::uint16_t state = 0;
    for (int k = 0; k < 3; ++k) {
      const index_t e = face_edges[3 * f + k];
      const bool forward = face_nodes[3 * f + (k + 1) % 3] < face_nodes[3 * f + (k + 2) % 3];
      const std::uint8_t kind = edge_point[e];
      t_local[k] = forward ? edge_point_t[e] : 1.0 - edge_point_t[e];
      if (kind == edge_point_inside) {
        place[k] = 3 + k;
        state |= std::uint16_t(1u << k);
      } else if (kind == edge_point_none) {
        place[k] = -1;
      } else {
        const bool at_low = kind == edge_point_low_node;
        place[k] = (at_low == forward) ? (k + 1) % 3 : (k + 2) % 3;
      }
      place[3 + k] = k;
    }
    return state;
  }

  /// The pairs of crossing places a cut joins inside the face (`pairs`, location_pair_bit), as
  /// lines between where they ended up: the EN and EE line bits added to `state`; returns the
  /// along-edge bits (`face_along`).
  TEAR_HD static std::uint8_t resolve_lines(std::uint16_t pairs, const int (&place)[6], std::uint16_t& state) {
    std::uint8_t along = 0;
    for (int a = 0; a < 6; ++a)
      for (int b = a + 1; b < 6; ++b) {
        if (!(pairs & (1u << location_pair_bit(a, b)))) continue;
        int pa = place[a], pb = place[b];
        if (pa < 0 || pb < 0 || pa == pb) continue;
        if (pa > pb) {
          const int tmp = pa;
          pa = pb;
          pb = tmp;
        }
        if (pa >= 3) {  // edge point to edge point: EE line cutting off the third corner
          state |= std::uint16_t(1u << (6 + (3 - (pa - 3) - (pb - 3))));
        } else if (pb >= 3) {  // node pa to edge point pb-3
          const int k = pb - 3;
          if (pa == k)
            state |= std::uint16_t(1u << (3 + k));  // EN line to the opposite node
          else
            along |= std::uint8_t(1u << (2 * k + (pa == (k + 1) % 3 ? 0 : 1)));  // along half of edge k
        } else {  // node to node: along the whole edge between them
          const int k = 3 - pa - pb;
          along |= std::uint8_t(3u << (2 * k));
        }
      }
    return along;
  }

  /// The face point of a state that has one, in barycentric coordinates: the average of the
  /// crossings of the face's lines (paper §2.1), kept at least face_point_min_bary inside.
  TEAR_HD static void face_point(std::uint16_t state, const double (&t_local)[3], double (&bary)[3]) {
    double sum[3] = {0, 0, 0}, corner[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, e_b[3][3];
    for (int k = 0; k < 3; ++k) edge_point_bary(k, t_local[k], e_b[k]);
    int found = 0;
    double x[3];
    for (int k = 0; k < 3; ++k) {
      if (!(state & (1u << (3 + k)))) continue;
      if ((state & (1u << (6 + k))) && cross_bary(e_b[k], corner[k], e_b[(k + 1) % 3], e_b[(k + 2) % 3], x)) {
        for (int i = 0; i < 3; ++i) sum[i] += x[i];
        ++found;
      }
      for (int j = k + 1; j < 3; ++j)
        if ((state & (1u << (3 + j))) && cross_bary(e_b[k], corner[k], e_b[j], corner[j], x)) {
          for (int i = 0; i < 3; ++i) sum[i] += x[i];
          ++found;
        }
    }
    if (found)
      for (int i = 0; i < 3; ++i) bary[i] = sum[i] / found;
    // Keep the point well inside the face.
    double total = 0;
    for (int i = 0; i < 3; ++i) {
      bary[i] = bary[i] < face_point_min_bary ? face_point_min_bary : bary[i];
      total += bary[i];
    }
    for (int i = 0; i < 3; ++i) bary[i] /= total;
  }
};

/// Per edge: the 2-bit edge cut info (bit 0: the half at the low node is a cut line, bit 1: the
/// half at the high node; both for a cut along the whole edge), gathered from its faces.
/// A boundary edge is a border already: always 0.
struct edge_cut_info {
  const index_t* face_nodes;
  const index_t* edge_faces;
  const index_t* edge_nodes;
  const index_t* face_edges;
  const std::uint8_t* face_along;
  std::uint8_t* edge_cut;
  TEAR_HD void operator()(index_t e) const {
    std::uint8_t bits = 0;
    if (edge_faces[2 * e + 1] >= 0) {
      for (int side = 0; side < 2; ++side) {
        const index_t f = edge_faces[2 * e + side];
        const int k = local_edge_of(face_edges, f, e);
        const std::uint8_t half = (face_along[f] >> (2 * k)) & 3u;
        const bool forward = face_nodes[3 * f + (k + 1) % 3] == edge_nodes[2 * e];
        bits |= forward ? half : std::uint8_t(((half & 1u) << 1) | (half >> 1));
      }
    }
    edge_cut[e] = bits;
  }
};

/// Per edge: drops a cut point that no cut line uses: no line of either face ends at it and no
/// cut runs along the edge to it. Such a point would only split faces: a cut crossing one edge and
/// ending in the next face, or a cut crossing a border edge whose line in the face then runs
/// along the border (a tear retraced where snapping had moved it off the drawn line).
struct drop_unused_edge_points {
  const index_t* edge_faces;
  const index_t* face_edges;
  const std::uint16_t* face_state;
  const std::uint8_t* edge_cut;
  std::uint8_t* edge_point;
  TEAR_HD void operator()(index_t e) const {
    if (edge_point[e] != edge_point_inside || edge_cut[e] != 0) return;
    for (int side = 0; side < 2; ++side) {
      const index_t f = edge_faces[2 * e + side];
      if (f < 0) continue;
      const int k = local_edge_of(face_edges, f, e);
      const unsigned lines =
          face_cut_edge_node_line(k) | face_cut_edge_edge_line((k + 1) % 3) | face_cut_edge_edge_line((k + 2) % 3);
      if (face_split_state(face_state[f]) & lines) return;
    }
    edge_point[e] = edge_point_none;
  }
};

/// Per face: runs `face_cut_info` again on a face that lost an edge point to
/// `drop_unused_edge_points`. None of its lines used that point, so the edges' cut info stands.
struct refresh_face_cut_info {
  face_cut_info info;
  TEAR_HD void operator()(index_t f) const {
    const unsigned state = face_split_state(info.face_state[f]);
    for (int k = 0; k < 3; ++k)
      if ((state & face_cut_edge_point(k)) && info.edge_point[info.face_edges[3 * f + k]] != edge_point_inside) {
        info(f);
        return;
      }
  }
};

/// Per face: when the face's split (with its best variant) still has an angle sharper than
/// `max_cosine` allows, asks to move the edge point nearest a node onto that node, if it lies
/// within `limit` of its edge from it. Points a cut placed near a node make the thinnest triangles
/// (the cut through a node crossing the opposite edge near its end, a corner cut off with one
/// side far shorter than the other); on the node they leave the face unsplit or split at a node.
struct request_quality_snaps {
  const index_t* face_nodes;
  const index_t* face_edges;
  const std::uint16_t* face_state;
  const float* edge_point_t;
  const float* face_point_bary;
  const float* node_rest;
  const SplitCase* table;
  double max_cosine;
  double limit;
  std::int8_t* face_snap_edge;  ///< [face_count] local edge whose point should snap, or -1
  TEAR_HD void operator()(index_t f) const {
    face_snap_edge[f] = -1;
    const unsigned code = face_state[f], state = face_split_state(code);
    if (!(state & 7u)) return;
    double t_local[3];
    for (int k = 0; k < 3; ++k) {
      const index_t e = face_edges[3 * f + k];
      const bool forward = face_nodes[3 * f + (k + 1) % 3] < face_nodes[3 * f + (k + 2) % 3];
      t_local[k] = forward ? edge_point_t[e] : 1.0 - edge_point_t[e];
    }
    double point_pos[face_point_slot_count][3];
    face_point_positions(face_nodes, node_rest, face_point_bary, f, t_local, point_pos);
    if (split_worst_cosine(split_case(table, code), point_pos) <= max_cosine) return;
    int best = -1;
    double best_d = limit;
    for (int k = 0; k < 3; ++k) {
      if (!(state & face_cut_edge_point(k))) continue;
      const double d = t_local[k] < 0.5 ? t_local[k] : 1.0 - t_local[k];
      if (d < best_d) {
        best_d = d;
        best = k;
      }
    }
    face_snap_edge[f] = static_cast<std::int8_t>(best);
  }
};

/// Per edge: snaps its point onto the nearer node when a face on either side asked for it.
struct apply_quality_snaps {
  const index_t* edge_faces;
  const index_t* face_edges;
  const std::int8_t* face_snap_edge;
  std::uint8_t* edge_point;
  float* edge_point_t;
  TEAR_HD void operator()(index_t e) const {
    if (edge_point[e] != edge_point_inside) return;
    for (int side = 0; side < 2; ++side) {
      const index_t f = edge_faces[2 * e + side];
      if (f < 0 || face_snap_edge[f] != local_edge_of(face_edges, f, e)) continue;
      const bool low = edge_point_t[e] < 0.5f;
      edge_point[e] = low ? edge_point_low_node : edge_point_high_node;
      edge_point_t[e] = low ? 0.0f : 1.0f;
      return;
    }
  }
};

/// Per face: runs `face_cut_info` again on a face one of whose edge points `apply_quality_snaps`
/// may have moved: one that asked for a snap itself, or whose neighbour across an edge asked for
/// that edge. A face's cut info depends only on its own edges' points (and its crossings), so every
/// other face keeps what it has, and the result is the same as resolving every face again.
struct refresh_snapped_faces {
  face_cut_info info;
  const index_t* edge_faces;
  const std::int8_t* face_snap_edge;
  TEAR_HD void operator()(index_t f) const {
    bool moved = face_snap_edge[f] >= 0;
    for (int k = 0; k < 3 && !moved; ++k) {
      const index_t e = info.face_edges[3 * f + k];
      for (int side = 0; side < 2 && !moved; ++side) {
        const index_t g = edge_faces[2 * e + side];
        moved = g >= 0 && g != f && face_snap_edge[g] == local_edge_of(info.face_edges, g, e);
      }
    }
    if (moved) info(f);
  }
};

}  // namespace tear::kernels
