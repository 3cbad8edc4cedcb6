// tear: whether a crack's cut crosses what it may not: a border (another crack, or the cloth's
// edge, where a cut would close a loop) or cloth a pin holds whole (crack_growth.h).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "cloth/crack_geometry.h"
#include "cloth/crack_growth.h"

namespace tear {

using namespace crack;

bool CrackField::crosses_border(index_t tip, const Vec3& at, const Vec3& normal, const Vec3& q) const {
  // In the plane of the tip: a proper crossing. Only edges within a hundredth of the cut's length
  // of it in space are tested (a curved cloth's far borders would project anywhere onto the plane).
  const Vec3 b1 = any_tangent(normal), b2 = cross(normal, b1);
  const auto flat = [&](const Vec3& p) { return Flat{dot(sub(p, at), b1), dot(sub(p, at), b2)}; };
  const double reach = norm(sub(q, at));
  const Flat p0{0, 0}, p1 = flat(q);
  for (const index_t e : border_edges_) {
    const index_t a = m_.topo.edge_nodes[2 * e], b = m_.topo.edge_nodes[2 * e + 1];
    if (a == tip || b == tip) continue;
    if (segment_distance(at, q, rest(a), rest(b)) > 0.01 * reach) continue;
    if (segments_cross(p0, p1, flat(rest(a)), flat(rest(b)))) return true;
  }
  return false;
}

bool CrackField::crosses_held(const Vec3& a, const Vec3& b, const Vec3& normal) const {
  if (!any_held_) return false;
  // In the plane of the cut: the segment meets the inside of a held face shrunk by a thousandth
  // about its centroid, so a cut along the clamp's edge or from a corner of it does not count.
  // Only faces within an edge of the segment in space (a curved cloth's far faces would project
  // anywhere onto the plane), found through the grid.
  const Vec3 b1 = any_tangent(normal), b2 = cross(normal, b1);
  const auto flat = [&](const Vec3& p) { return Flat{dot(sub(p, a), b1), dot(sub(p, a), b2)}; };
  const Flat p0{0, 0}, p1 = flat(b);
  const Vec3 ab = sub(b, a);
  const double length = norm(ab);
  if (!(length > 0)) return false;
  bool hit = false;
  faces_near(scale(add(a, b), 0.5), 0.5 * length + longest_edge_, [&](index_t f) {
    if (hit || !face_held(f)) return;
    const Vec3& c = face_centroid_[f];
    const double t = std::max(0.0, std::min(1.0, dot(sub(c, a), ab) / (length * length)));
    if (norm(sub(c, add(a, scale(ab, t)))) > longest_edge_) return;
    Flat T[3];
    for (int k = 0; k < 3; ++k) T[k] = flat(add(c, scale(sub(rest(m_.face_nodes[3 * f + k]), c), 0.999)));
    const double orientation = turn(T[0], T[1], T[2]);
    if (orientation == 0) return;
    const auto inside = [&](const Flat& p) {
      for (int k = 0; k < 3; ++k)
        if (turn(T[k], T[(k + 1) % 3], p) * orientation <= 0) return false;
      return true;
    };
    hit = inside(p0) || inside(p1);
    for (int k = 0; k < 3 && !hit; ++k) hit = segments_cross(p0, p1, T[k], T[(k + 1) % 3]);
    // Along an edge between two held faces (within the shrink's gap of it): it would part them.
    for (int k = 0; k < 3 && !hit; ++k) {
      const index_t e = m_.topo.face_edges[3 * f + k];
      const index_t other = m_.topo.edge_faces[2 * e] == f ? m_.topo.edge_faces[2 * e + 1] : m_.topo.edge_faces[2 * e];
      if (other < 0 || !face_held(other)) continue;
      const Flat A = flat(rest(m_.topo.edge_nodes[2 * e])), B = flat(rest(m_.topo.edge_nodes[2 * e + 1]));
      const double gap = 2e-3 * std::hypot(B[0] - A[0], B[1] - A[1]) * length;
      if (std::abs(turn(p0, p1, A)) > gap || std::abs(turn(p0, p1, B)) > gap) continue;
      const double ta = (A[0] * p1[0] + A[1] * p1[1]) / (length * length),
                   tb = (B[0] * p1[0] + B[1] * p1[1]) / (length * length);
      hit = std::min(1.0, std::max(ta, tb)) - std::max(0.0, std::min(ta, tb)) > 1e-6;
    }
  });
  return hit;
}

}  // namespace tear
