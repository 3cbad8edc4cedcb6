// tear: whether a crack's cut crosses what it may not: a border (another crack, or the cloth's
// edge, where a cut would close a loop) or cloth a pin holds whole (crack_growth.h).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "cloth/crack_geometry.h"
#include "cloth/crack_growth.h"

namespace tear {

using namespace crack;

bool CrackField::crosses_border(index_t tip, const Vec3& at, const Vec3& normal, const Vec3& q) const {
  // In the plane of the tip: a proper crossing, each segment's ends strictly on both sides of the
  // other's line. Only edges within a hundredth of the cut's length of it in space are tested (a
  // curved cloth's far borders would project anywhere onto the plane).
  const Vec3 b1 = any_tangent(normal), b2 = cross(normal, b1);
  const auto flat = [&](const Vec3& p) { return std::array<double, 2>{dot(sub(p, at), b1), dot(sub(p, at), b2)}; };
  const auto side = [](const std::array<double, 2>& o, const std::array<double, 2>& a, const std::array<double, 2>& b) {
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
  };
  const double reach = norm(sub(q, at));
  const std::array<double, 2> p0{0, 0}, p1 = flat(q);
  for (const index_t e : border_edges_) {
    const index_t a = m_.topo.edge_nodes[2 * e], b = m_.topo.edge_nodes[2 * e + 1];
    if (a == tip || b == tip) continue;
    if (segment_distance(at, q, rest(a), rest(b)) > 0.01 * reach) continue;
    const std::array<double, 2> A = flat(rest(a)), B = flat(rest(b));
    const double s0 = side(p0, p1, A), s1 = side(p0, p1, B), s2 = side(A, B, p0), s3 = side(A, B, p1);
    if (((s0 > 0 && s1 < 0) || (s0 < 0 && s1 > 0)) && ((s2 > 0 && s3 < 0) || (s2 < 0 && s3 > 0))) return true;
  }
  return false;
}

bool CrackField::crosses_held(const Vec3& a, const Vec3& b, const Vec3& normal) const {
  if (held_faces_.empty()) return false;
  // In the plane of the cut: the segment meets the inside of a held face shrunk by a thousandth
  // about its centroid, so a cut along the clamp's edge or from a corner of it does not count.
  // Only faces within an edge of the segment in space (a curved cloth's far faces would project
  // anywhere onto the plane).
  using Flat = std::array<double, 2>;
  const Vec3 b1 = any_tangent(normal), b2 = cross(normal, b1);
  const auto flat = [&](const Vec3& p) { return Flat{dot(sub(p, a), b1), dot(sub(p, a), b2)}; };
  const auto side = [](const Flat& o, const Flat& p, const Flat& q) {
    return (p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0]);
  };
  const Flat p0{0, 0}, p1 = flat(b);
  const Vec3 ab = sub(b, a);
  const double length = norm(ab);
  if (!(length > 0)) return false;
  const Vec3 mid = scale(add(a, b), 0.5);
  for (const index_t f : held_faces_) {
    const Vec3& c = face_centroid_[f];
    if (norm(sub(c, mid)) > 0.5 * length + longest_edge_) continue;
    const double t = std::max(0.0, std::min(1.0, dot(sub(c, a), ab) / std::max(dot(ab, ab), 1e-300)));
    if (norm(sub(c, add(a, scale(ab, t)))) > longest_edge_) continue;
    Flat T[3];
    for (int k = 0; k < 3; ++k) T[k] = flat(add(c, scale(sub(rest(m_.face_nodes[3 * f + k]), c), 0.999)));
    const double turn = side(T[0], T[1], T[2]);
    if (turn == 0) continue;
    const auto inside = [&](const Flat& p) {
      for (int k = 0; k < 3; ++k)
        if (side(T[k], T[(k + 1) % 3], p) * turn <= 0) return false;
      return true;
    };
    if (inside(p0) || inside(p1)) return true;
    for (int k = 0; k < 3; ++k) {
      const Flat &A = T[k], &B = T[(k + 1) % 3];
      const double s0 = side(p0, p1, A), s1 = side(p0, p1, B), s2 = side(A, B, p0), s3 = side(A, B, p1);
      if (((s0 > 0 && s1 < 0) || (s0 < 0 && s1 > 0)) && ((s2 > 0 && s3 < 0) || (s2 < 0 && s3 > 0))) return true;
    }
    // Along an edge between two held faces (within the shrink's gap of it): it would part them.
    for (int k = 0; k < 3; ++k) {
      const index_t e = m_.topo.face_edges[3 * f + k];
      const index_t other = m_.topo.edge_faces[2 * e] == f ? m_.topo.edge_faces[2 * e + 1] : m_.topo.edge_faces[2 * e];
      if (other < 0 || !face_held_[other]) continue;
      const Flat A = flat(rest(m_.topo.edge_nodes[2 * e])), B = flat(rest(m_.topo.edge_nodes[2 * e + 1]));
      const double edge = std::hypot(B[0] - A[0], B[1] - A[1]), gap = 2e-3 * edge * length;
      if (std::abs(side(p0, p1, A)) > gap || std::abs(side(p0, p1, B)) > gap) continue;
      const double ta = (A[0] * p1[0] + A[1] * p1[1]) / (length * length),
                   tb = (B[0] * p1[0] + B[1] * p1[1]) / (length * length);
      if (std::min(1.0, std::max(ta, tb)) - std::max(0.0, std::min(ta, tb)) > 1e-6) return true;
    }
  }
  return false;
}

}  // namespace tear
