// tear kernels: collision of the cloth with itself and with mesh colliders (docs/simulation.md,
// *Collision*), run after the solver's iterations of a substep by cloth/collision_job.h.
//
// The vertices are the cloth's nodes [0, node_count) followed by the mesh colliders' vertices
// (bodies), each with its position at the substep's start (x0) and end (x1). Pairs are node–face
// (a vertex and a triangle) and edge–edge. A pair is in contact when, at the end, the vertex (or
// edge) is within the pair's thickness of the triangle (or other edge) on the side it was on at
// the start, or when it crossed it during the substep (found by the time the four points are
// coplanar: the motion, not only the end positions). Each contact moves its movable vertices
// (free cloth nodes: pinned nodes and bodies do not move) apart along the triangle's (or the
// edges') normal, weighted as a position constraint, with Coulomb friction on their relative
// motion; each vertex averages the moves of its contacts, summed in the order of the pairs (a
// gather: no atomics).
//
// A pair's thickness is `thickness`, except for two parts of the cloth that lie within 2.5 times
// that of each other in the rest shape (neighbours in the fabric): theirs is 0.4 times their
// distance there, so that the fabric's own wrinkles are not taken for contacts it can never
// leave. Two sides of a tear (closer than `rest_gap` there) take no part.
//
// Broad phase: vertices and cloth edges, boxed over the substep's motion, are entered into a
// uniform grid, each in every cell its box meets (sorted by cell); each triangle and edge looks up
// the cells its box covers. Each pair is found once, and kept only if its two sides can come
// within twice the pair's thickness of each other during the substep (their distance at the start
// less how far they move against each other).
//
// Example: a node 1 mm above a face (thickness 5 mm), both moving down together, is moved up by
// 4 mm where the face's nodes are pinned, or up 2 mm with the face down 2 mm where all are free
// (barycentric weights at the face's centre: 1/3 each, so W = 1 + 3·(1/9)).
#pragma once

#include <cmath>
#include <cstdint>

#include "collision_geometry.h"
#include "collision_grid.h"
#include "hd.h"
#include "pd_math.h"
#include "pd_step.h"

namespace tear::kernels {

/// The vertices of the collision pass: cloth nodes, then bodies' vertices.
struct CollisionVertices {
  const float* cloth_x0;  ///< [3 * node_count] the nodes at the substep's start
  const float* cloth_x1;  ///< [3 * node_count] the nodes now (the solver's end, moved by the contacts)
  const float* cloth_rest;
  const std::uint8_t* cloth_pinned;
  const float* body_x0;  ///< [3 * body vertices] at the substep's start
  const float* body_x1;  ///< ... at its end
  index_t node_count, vertex_count;

  TEAR_HD bool is_cloth(index_t v) const { return v < node_count; }
  TEAR_HD Vec3f x0(index_t v) const {
    return v < node_count ? load3<float>(cloth_x0, v) : load3<float>(body_x0, v - node_count);
  }
  TEAR_HD Vec3f x1(index_t v) const {
    return v < node_count ? load3<float>(cloth_x1, v) : load3<float>(body_x1, v - node_count);
  }
  /// Moved by contacts: free cloth nodes only.
  TEAR_HD float w(index_t v) const { return v < node_count && cloth_pinned[v] == 0 ? 1.0f : 0.0f; }
};

/// Triangles: the cloth's faces, then the bodies' (their vertices numbered among the bodies', so
/// `node` adds the cloth's node count).
struct CollisionFaces {
  const index_t* cloth;  ///< [3 * cloth_count]
  const index_t* body;   ///< [3 * (count - cloth_count)]
  index_t cloth_count, count, node_count;
  TEAR_HD index_t node(index_t f, int k) const {
    return f < cloth_count ? cloth[3 * f + k] : node_count + body[3 * (f - cloth_count) + k];
  }
};

/// Edges: the cloth's, then the bodies'.
struct CollisionEdges {
  const index_t* cloth;  ///< [2 * cloth_count]
  const index_t* body;   ///< [2 * (count - cloth_count)]
  index_t cloth_count, count, node_count;
  TEAR_HD index_t node(index_t e, int k) const {
    return e < cloth_count ? cloth[2 * e + k] : node_count + body[2 * (e - cloth_count) + k];
  }
};

/// The box of vertex v over the substep's motion.
TEAR_HD inline Box vertex_box(const CollisionVertices& x, index_t v) {
  Box b = Box::of(x.x0(v));
  b.add(x.x1(v));
  return b;
}
TEAR_HD inline Box face_box(const CollisionVertices& x, const CollisionFaces& f, index_t i) {
  Box b = vertex_box(x, f.node(i, 0));
  b.add(x.x0(f.node(i, 1))), b.add(x.x1(f.node(i, 1)));
  b.add(x.x0(f.node(i, 2))), b.add(x.x1(f.node(i, 2)));
  return b;
}
TEAR_HD inline Box edge_box(const CollisionVertices& x, const CollisionEdges& e, index_t i) {
  Box b = vertex_box(x, e.node(i, 0));
  b.add(x.x0(e.node(i, 1))), b.add(x.x1(e.node(i, 1)));
  return b;
}

/// The entries of the grid: each vertex (or cloth edge), its box grown by `margin`, under the key
/// of each cell it meets, in the cells' order; counted per item (`offset` null), then written at
/// the scanned offsets.
struct EnterItems {
  CollisionVertices x;
  CollisionEdges edges;
  CollisionGrid grid;
  float margin;
  bool of_edges;  ///< entries of cloth edges (else of vertices)
  const index_t* offset;  ///< null: count into `count`
  index_t* count;
  std::uint64_t* keys;
  index_t* items;
  TEAR_HD void operator()(index_t i) const {
    Box b = of_edges ? edge_box(x, edges, i) : vertex_box(x, i);
    b.grow(margin);
    std::int32_t lo[3], hi[3];
    const std::int64_t cells = grid.entry_cells(b, lo, hi);
    if (!offset) {
      count[i] = cells ? static_cast<index_t>(cells) : 1;
      return;
    }
    index_t out = offset[i];
    if (!cells) {
      keys[out] = CollisionGrid::everywhere;
      items[out] = i;
      return;
    }
    for (std::int32_t k = lo[2]; k <= hi[2]; ++k)
      for (std::int32_t j = lo[1]; j <= hi[1]; ++j)
        for (std::int32_t c = lo[0]; c <= hi[0]; ++c) {
          keys[out] = CollisionGrid::key(c, j, k);
          items[out++] = i;
        }
  }
};

/// Two kinds of pairs: a vertex and a face (v = {p, a, b, c}) or two edges (v = {p, q, r, s}),
/// with the distance their contact keeps (metres).
struct CollisionPair {
  index_t v[4];
  std::int32_t edge_edge;
  float thickness;
};

/// The contact of pair `pair` at the vertices' current end positions: whether there is one, and
/// the weights (`bary`, signed: the second side's negative) and unit normal (pointing from the
/// second side to the first) it pushes along, and its violation C (< 0: the first side must move
/// −C further along the normal relative to the second).
struct Contact {
  bool active = false;
  float bary[4];
  Vec3f normal;
  float violation;
};

/// The pass's geometry of one pair.
struct CollisionGeometry {
  CollisionVertices x;
  float thickness;
  /// In-plane slack of a crossing: how far outside the triangle (or past an edge's end) a crossing
  /// still counts, relative to the thickness.
  static constexpr float crossing_slack = 0.1f;

  /// Node–face: p against triangle (a, b, c).
  TEAR_HD Contact node_face(const index_t* v) const {
    Contact k;
    Vec3f s0[4], s1[4];
    for (int i = 0; i < 4; ++i) s0[i] = x.x0(v[i]), s1[i] = x.x1(v[i]);
    // Order for the coplanarity test: a, b, c, p.
    const Vec3f a0 = s0[1], b0 = s0[2], c0 = s0[3], p0 = s0[0];
    const Vec3f a1 = s1[1], b1 = s1[2], c1 = s1[3], p1 = s1[0];
    const Vec3f n0 = cross(b0 - a0, c0 - a0), n1raw = cross(b1 - a1, c1 - a1);
    const float n1len = norm(n1raw);
    if (!(n1len > 0.0f)) return k;
    const Vec3f n1 = (1.0f / n1len) * n1raw;
    const float side0 = dot(p0 - a0, n0);
    const float d1 = dot(p1 - a1, n1);
    // The side at the start; on the plane, the side it is on now.
    const float s = side0 > 0.0f ? 1.0f : side0 < 0.0f ? -1.0f : (d1 >= 0.0f ? 1.0f : -1.0f);
    const float sd1 = s * d1;
    Vec3f w;
    if (sd1 >= 0.0f) {
      if (!(sd1 < thickness)) return k;
      // Close on its own side: the projection must fall inside the triangle.
      w = closest_on_triangle(p1, a1, b1, c1);
      const Vec3f q = w.x * a1 + (w.y * b1 + w.z * c1);
      const Vec3f along = p1 - q;
      const float in_plane = norm(along - dot(along, n1) * n1);
      if (in_plane > crossing_slack * thickness) return k;
    } else {
      // On the other side: a contact only if it went through the triangle during the substep.
      const Vec3f q0[4] = {a0, b0, c0, p0}, q1[4] = {a1, b1, c1, p1};
      if (!first_meeting(q0, q1, false, w)) return k;
    }
    k.active = true;
    k.bary[0] = 1, k.bary[1] = -w.x, k.bary[2] = -w.y, k.bary[3] = -w.z;
    k.normal = s * n1;
    k.violation = dot(p1 - (w.x * a1 + (w.y * b1 + w.z * c1)), k.normal) - thickness;
    return k;
  }

  /// Edge–edge: (p, q) against (r, u).
  TEAR_HD Contact edge_edge(const index_t* v) const {
    Contact k;
    Vec3f s0[4], s1[4];
    for (int i = 0; i < 4; ++i) s0[i] = x.x0(v[i]), s1[i] = x.x1(v[i]);
    const Vec3f e1 = s1[1] - s1[0], e2 = s1[3] - s1[2];
    const Vec3f nraw = cross(e1, e2);
    const float nlen = norm(nraw);
    // Parallel edges: their ends' node–face pairs hold them.
    if (!(nlen > 1e-6f * norm(e1) * norm(e2))) return k;
    const Vec3f n1 = (1.0f / nlen) * nraw;
    float a, b;
    closest_on_segments(s1[0], s1[1], s1[2], s1[3], a, b);
    const Vec3f n0 = cross(s0[1] - s0[0], s0[3] - s0[2]);
    const float g0 = dot(lerp(s0[2], s0[3], b) - lerp(s0[0], s0[1], a), n0);
    const float g1 = dot(lerp(s1[2], s1[3], b) - lerp(s1[0], s1[1], a), n1);
    // σ: the side (r, u) was on relative to (p, q) at the start.
    const float sigma = g0 > 0.0f ? 1.0f : g0 < 0.0f ? -1.0f : (g1 >= 0.0f ? 1.0f : -1.0f);
    const float sg1 = sigma * g1;
    if (sg1 >= 0.0f) {
      if (!(sg1 < thickness)) return k;
      // Close: the closest points inside both edges (at an end, a node–face pair holds it).
      if (a <= 0.0f || a >= 1.0f || b <= 0.0f || b >= 1.0f) return k;
      const Vec3f gap = lerp(s1[2], s1[3], b) - lerp(s1[0], s1[1], a);
      if (norm(gap - dot(gap, n1) * n1) > crossing_slack * thickness) return k;
    } else {
      // Crossed: the edges met during the substep.
      Vec3f ab;
      if (!first_meeting(s0, s1, true, ab)) return k;
      a = ab.x, b = ab.y;
    }
    k.active = true;
    // The first side (p, q) is pushed along −normal... expressed as: normal from (r, u) to (p, q).
    k.normal = (-sigma) * n1;
    k.bary[0] = 1 - a, k.bary[1] = a, k.bary[2] = -(1 - b), k.bary[3] = -b;
    const Vec3f first = lerp(s1[0], s1[1], a), second = lerp(s1[2], s1[3], b);
    k.violation = dot(first - second, k.normal) - thickness;
    return k;
  }

  /// The geometry of the pair's own thickness.
  TEAR_HD CollisionGeometry of(const CollisionPair& pair) const { return {x, pair.thickness}; }

  TEAR_HD Contact contact(const CollisionPair& pair) const {
    const CollisionGeometry g = of(pair);
    return pair.edge_edge ? g.edge_edge(pair.v) : g.node_face(pair.v);
  }

  /// The first time of the substep at which four points moving from `q0` to `q1` meet: they are
  /// coplanar and, there, the node q[3] lies in triangle (q[0], q[1], q[2]) (or, `edges`, the
  /// segments (q[0], q[1]) and (q[2], q[3]) cross), within the crossing slack. The weights there go
  /// to `w`: the triangle's, or the two segments' parameters in w.x and w.y.
  TEAR_HD bool first_meeting(const Vec3f q0[4], const Vec3f q1[4], bool edges, Vec3f& w) const {
    double times[3];
    const int count = coplanar_times(q0, q1, times);
    const float slack = crossing_slack * thickness;
    for (int i = 0; i < count; ++i) {
      const float t = static_cast<float>(times[i]);
      Vec3f q[4];
      for (int j = 0; j < 4; ++j) q[j] = lerp(q0[j], q1[j], t);
      if (edges) {
        float a, b;
        closest_on_segments(q[0], q[1], q[2], q[3], a, b);
        w = {a, b, 0};
        if (norm(lerp(q[2], q[3], b) - lerp(q[0], q[1], a)) <= slack) return true;
      } else {
        w = closest_on_triangle(q[3], q[0], q[1], q[2]);
        if (norm(q[3] - (w.x * q[0] + (w.y * q[1] + w.z * q[2]))) <= slack) return true;
      }
    }
    return false;
  }

  /// Whether the pair meets at some time of the substep (`first_meeting`), whatever the sides.
  TEAR_HD bool meets(const CollisionPair& pair) const {
    Vec3f s0[4], s1[4];
    for (int i = 0; i < 4; ++i) s0[i] = x.x0(pair.v[i]), s1[i] = x.x1(pair.v[i]);
    Vec3f w;
    const CollisionGeometry g = of(pair);
    if (pair.edge_edge) return g.first_meeting(s0, s1, true, w);
    // A node and a face: the face's nodes first.
    const Vec3f q0[4] = {s0[1], s0[2], s0[3], s0[0]}, q1[4] = {s1[1], s1[2], s1[3], s1[0]};
    return g.first_meeting(q0, q1, false, w);
  }
};

/// Each pair's moves of its four vertices (`moves` [4 * pairs]), zero where it has no contact: the
/// constraint normal·(Σ bᵢ xᵢ) ≥ thickness projected with weights wᵢ, plus friction that removes
/// up to `friction` × the normal move of the contact's tangential motion over the substep.
struct resolve_contacts {
  CollisionGeometry geometry;
  const CollisionPair* pairs;
  float friction;
  Vec3f* moves;
  TEAR_HD void operator()(index_t i) const {
    const CollisionPair& pair = pairs[i];
    const Contact k = geometry.contact(pair);
    for (int j = 0; j < 4; ++j) moves[4 * i + j] = Vec3f{0, 0, 0};
    if (!k.active || !(k.violation < 0.0f)) return;
    const CollisionVertices& x = geometry.x;
    float wsum = 0;
    float w[4];
    for (int j = 0; j < 4; ++j) {
      w[j] = x.w(pair.v[j]);
      wsum += w[j] * k.bary[j] * k.bary[j];
    }
    if (!(wsum > 0.0f)) return;
    const float lambda = -k.violation / wsum;
    // The contact points' relative motion over the substep, its part across the normal.
    Vec3f rel{0, 0, 0};
    for (int j = 0; j < 4; ++j) rel = rel + k.bary[j] * (x.x1(pair.v[j]) - x.x0(pair.v[j]));
    const Vec3f tangent = rel - dot(rel, k.normal) * k.normal;
    const float slide = norm(tangent);
    Vec3f stop{0, 0, 0};
    if (friction > 0.0f && slide > 0.0f) {
      const float keep = fminf(1.0f, friction * -k.violation / slide);
      stop = (-keep / wsum) * tangent;
    }
    for (int j = 0; j < 4; ++j)
      if (w[j] > 0.0f) moves[4 * i + j] = (w[j] * k.bary[j]) * (lambda * k.normal + stop);
  }
};

/// Each cloth node's moves from its contacts (`slot_offset`/`slots`: its entries of `moves`, in
/// order), averaged over those that move it, added to its end position; then out of the plane and
/// sphere colliders again, which are never given way to.
struct apply_contact_moves {
  const index_t* slot_offset;  ///< [node_count + 1]
  const index_t* slots;
  const Vec3f* moves;
  const PdCollider* colliders;
  index_t collider_count;
  float* node_x1;
  TEAR_HD void operator()(index_t n) const {
    Vec3f sum{0, 0, 0};
    int count = 0;
    for (index_t i = slot_offset[n]; i < slot_offset[n + 1]; ++i) {
      const Vec3f m = moves[slots[i]];
      if (m.x != 0.0f || m.y != 0.0f || m.z != 0.0f) {
        sum = sum + m;
        ++count;
      }
    }
    if (count == 0) return;
    Vec3f x = load3<float>(node_x1, n) + (1.0f / static_cast<float>(count)) * sum;
    Vec3f unused{0, 0, 0};
    for (index_t i = 0; i < collider_count; ++i) collide(colliders[i], x, unused);
    store3(node_x1, n, x);
  }
};

/// The entries of the node → moves CSR: slot 4i + j is keyed by pair i's vertex j when that is a
/// free cloth node (else it has no key: pinned nodes and bodies, which contacts do not move).
struct ContactSlots {
  const CollisionPair* pairs;
  CollisionVertices x;
  TEAR_HD index_t key(index_t slot) const {
    const index_t v = pairs[slot / 4].v[slot % 4];
    return x.w(v) > 0.0f ? v : -1;
  }
  TEAR_HD index_t value(index_t slot) const { return slot; }
};

/// 1 where pair i meets during the substep (`meets`), for the final check.
struct crossing_of {
  CollisionGeometry geometry;
  const CollisionPair* pairs;
  TEAR_HD index_t operator()(index_t i) const { return geometry.meets(pairs[i]) ? 1 : 0; }
};

/// After the contacts: each free node's velocity gains its contacts' move over the substep, as the
/// solver's velocity update (damping included) would have counted it.
struct add_contact_velocity {
  const float* solved;  ///< the solver's end positions
  const float* node_x1;
  float scale;  ///< (1 − damping)^h / h
  float* node_vel;
  TEAR_HD void operator()(index_t n) const {
    store3(node_vel, n, load3<float>(node_vel, n) + scale * (load3<float>(node_x1, n) - load3<float>(solved, n)));
  }
};

/// Nodes marked `held` go back to where they started the substep.
struct hold_nodes {
  const std::uint8_t* held;
  const float* node_x0;
  float* node_x1;
  TEAR_HD void operator()(index_t n) const {
    if (held[n]) store3(node_x1, n, load3<float>(node_x0, n));
  }
};

/// Marks (`held`) the free cloth nodes of the pairs that still cross: they go back to where they
/// started the substep.
struct hold_crossing {
  CollisionGeometry geometry;
  const CollisionPair* pairs;
  std::uint8_t* held;
  TEAR_HD void operator()(index_t i) const {
    if (!geometry.meets(pairs[i])) return;
    for (int j = 0; j < 4; ++j) {
      const index_t v = pairs[i].v[j];
      if (geometry.x.w(v) > 0.0f) held[v] = 1;  // every writer writes 1: no race on the value
    }
  }
};

/// The candidate pairs: each face looks up the vertices entered near it, each edge the cloth edges
/// entered near it; counted per query (`offset` null), then written at the scanned offsets. Queries
/// are the faces [0, faces.count), then the edges. A pair is kept when the boxes overlap, it
/// shares no vertex, has a vertex that moves, and is cloth against a body or
/// (with `self`) cloth against cloth not within `rest_gap` of each other in the rest shape (the two
/// sides of a tear, neighbours in the fabric).
struct find_pairs {
  CollisionVertices x;
  CollisionFaces faces;
  CollisionEdges edges;
  CollisionGrid grid;
  GridEntries vertex_entries, edge_entries;
  float margin;
  float rest_gap;
  bool self;
  /// Cells a query walks one by one at most; a bigger box scans the entries instead.
  static constexpr std::int64_t max_walk = 125;
  const index_t* offset;  ///< null: count into `count`
  index_t* count;
  CollisionPair* pairs;

  TEAR_HD Box entry_box(index_t item, bool of_edges) const {
    Box b = of_edges ? edge_box(x, edges, item) : vertex_box(x, item);
    b.grow(margin);
    return b;
  }
  TEAR_HD Vec3f rest(index_t v) const { return load3<float>(x.cloth_rest, v); }

  /// The thickness of a cloth pair whose two sides lie `rest_distance` apart in the rest shape.
  TEAR_HD float cloth_thickness(float rest_distance) const { return min_of(margin, 0.4f * rest_distance); }
  /// Whether face f and vertex p make a pair (v = {p, a, b, c}), and its thickness.
  TEAR_HD bool node_face(index_t f, index_t p, index_t v[4], float& thickness) const {
    v[0] = p;
    for (int k = 0; k < 3; ++k) {
      v[k + 1] = faces.node(f, k);
      if (v[k + 1] == p) return false;
    }
    const bool cloth_face = f < faces.cloth_count, cloth_node = x.is_cloth(p);
    if (!cloth_face && !cloth_node) return false;
    thickness = margin;
    if (cloth_face && cloth_node) {
      if (!self) return false;
      const float apart = point_triangle_distance(rest(p), rest(v[1]), rest(v[2]), rest(v[3]));
      if (apart < rest_gap) return false;
      thickness = cloth_thickness(apart);
    }
    return x.w(v[0]) + x.w(v[1]) + x.w(v[2]) + x.w(v[3]) > 0.0f && may_come_near(v, false, thickness);
  }
  /// How far any point of one side of pair v moves over the substep against any point of the
  /// other, at most: the largest motion of one side's vertex against one of the other's (a point
  /// of either side moves as a weighted mean of its vertices). Sides: {v0} and {v1, v2, v3} for a
  /// vertex and a face, {v0, v1} and {v2, v3} for two edges.
  TEAR_HD float relative_motion(const index_t v[4], bool edge_pair) const {
    Vec3f d[4];
    for (int k = 0; k < 4; ++k) d[k] = x.x1(v[k]) - x.x0(v[k]);
    const int first_end = edge_pair ? 2 : 1;
    float most = 0.0f;
    for (int i = 0; i < first_end; ++i)
      for (int k = first_end; k < 4; ++k) most = max_of(most, norm(d[k] - d[i]));
    return most;
  }
  /// Whether the pair can come within twice its thickness of each other over the substep: its
  /// distance at the start less how far its vertices move against each other. Every point of one
  /// side moves against every point of the other by at most that much.
  TEAR_HD bool may_come_near(const index_t v[4], bool edge_pair, float thickness) const {
    float gap;
    if (edge_pair) {
      float s, t;
      const Vec3f a = x.x0(v[0]), b = x.x0(v[1]), c = x.x0(v[2]), d = x.x0(v[3]);
      closest_on_segments(a, b, c, d, s, t);
      gap = norm(lerp(c, d, t) - lerp(a, b, s));
    } else {
      gap = point_triangle_distance(x.x0(v[0]), x.x0(v[1]), x.x0(v[2]), x.x0(v[3]));
    }
    return !(gap - relative_motion(v, edge_pair) > 2.0f * thickness);
  }
  /// Whether edge q and cloth edge e make a pair (v = {q's, e's}), and its thickness.
  TEAR_HD bool edge_edge(index_t q, index_t e, index_t v[4], float& thickness) const {
    const bool cloth_query = q < edges.cloth_count;
    if (cloth_query && (!self || q >= e)) return false;
    v[0] = edges.node(q, 0), v[1] = edges.node(q, 1), v[2] = edges.node(e, 0), v[3] = edges.node(e, 1);
    if (v[0] == v[2] || v[0] == v[3] || v[1] == v[2] || v[1] == v[3]) return false;
    thickness = margin;
    if (cloth_query) {
      float s, t;
      const Vec3f a = rest(v[0]), b = rest(v[1]), c = rest(v[2]), d = rest(v[3]);
      closest_on_segments(a, b, c, d, s, t);
      const float apart = norm(lerp(c, d, t) - lerp(a, b, s));
      if (apart < rest_gap) return false;
      thickness = cloth_thickness(apart);
    }
    return x.w(v[0]) + x.w(v[1]) + x.w(v[2]) + x.w(v[3]) > 0.0f && may_come_near(v, true, thickness);
  }

  /// Query i against entry j: the pair, if it is one. An entry under a cell's key is taken only in
  /// the cell of the lowest corner of the two boxes' overlap, so a pair met in several cells is
  /// taken once.
  TEAR_HD bool take(index_t i, const Box& qb, index_t j, const GridEntries& entries, CollisionPair& pair) const {
    const bool of_edges = i >= faces.count;
    const index_t item = entries.items[j];
    const Box eb = entry_box(item, of_edges);
    if (!qb.overlaps(eb)) return false;
    const std::uint64_t key = entries.keys[j];
    if (key != CollisionGrid::everywhere &&
        key != grid.cell_key({max_of(qb.lo.x, eb.lo.x), max_of(qb.lo.y, eb.lo.y), max_of(qb.lo.z, eb.lo.z)}))
      return false;
    pair.edge_edge = of_edges ? 1 : 0;
    return of_edges ? edge_edge(i - faces.count, item, pair.v, pair.thickness)
                    : node_face(i, item, pair.v, pair.thickness);
  }

  TEAR_HD void operator()(index_t i) const {
    const bool of_edges = i >= faces.count;
    const GridEntries& entries = of_edges ? edge_entries : vertex_entries;
    Box qb = of_edges ? edge_box(x, edges, i - faces.count) : face_box(x, faces, i);
    qb.grow(margin);
    index_t found = 0;
    index_t out = offset ? offset[i] : 0;
    CollisionPair pair;
    const auto visit = [&](index_t j) {
      if (!take(i, qb, j, entries, pair)) return;
      if (offset) pairs[out++] = pair;
      ++found;
    };
    // An entry is in every cell its box meets: one that meets the query's is in the query's cells.
    std::int32_t lo[3], hi[3];
    grid.cells(qb, lo, hi);
    const std::int64_t cells = static_cast<std::int64_t>(hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
    // The entries under `everywhere` come last.
    const index_t everywhere_begin = entries.lower_bound(CollisionGrid::everywhere, entries.count);
    if (cells <= max_walk && cells <= everywhere_begin) {
      for (std::int32_t k = lo[2]; k <= hi[2]; ++k)
        for (std::int32_t jj = lo[1]; jj <= hi[1]; ++jj)
          for (std::int32_t c = lo[0]; c <= hi[0]; ++c) {
            const std::uint64_t key = CollisionGrid::key(c, jj, k);
            for (index_t j = entries.lower_bound(key, everywhere_begin); j < everywhere_begin && entries.keys[j] == key;
                 ++j)
              visit(j);
          }
    } else {
      for (index_t j = 0; j < everywhere_begin; ++j) visit(j);
    }
    for (index_t j = everywhere_begin; j < entries.count; ++j) visit(j);
    if (!offset) {
      count[i] = found;
      return;
    }
    // The run in the order of its vertices, whatever the grid: the contacts' moves are summed in
    // this order, so a resumed run (whose grid may differ) sums them as the uninterrupted one.
    CollisionPair* run = pairs + offset[i];
    for (index_t a = 1; a < found; ++a) {
      const CollisionPair p = run[a];
      index_t b = a;
      for (; b > 0 && before(p, run[b - 1]); --b) run[b] = run[b - 1];
      run[b] = p;
    }
  }
  TEAR_HD static bool before(const CollisionPair& a, const CollisionPair& b) {
    for (int k = 0; k < 4; ++k)
      if (a.v[k] != b.v[k]) return a.v[k] < b.v[k];
    return false;
  }
};

}  // namespace tear::kernels
