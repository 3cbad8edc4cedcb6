// tear kernels: the geometry of the collision pass (kernels/collision.h): closest points of a
// triangle and of two segments, and the times at which four points moving in straight lines are
// coplanar (where a node meets a face, or two edges meet, during a substep).
//
// Example: a node falling from (0.2, 1, 0.2) to (0.2, -1, 0.2) through the still triangle
// (0,0,0) (1,0,0) (0,0,1): coplanar_times gives t = 0.5, where the node is at (0.2, 0, 0.2),
// inside the triangle (closest_on_triangle gives weights 0.6, 0.2, 0.2 of a, b, c).
#pragma once

#include <cmath>

#include "hd.h"
#include "pd_math.h"

namespace tear::kernels {

/// Barycentric coordinates of the closest point of triangle (a, b, c) to p (Ericson, Real-Time
/// Collision Detection, 5.1.5).
TEAR_HD inline Vec3f closest_on_triangle(Vec3f p, Vec3f a, Vec3f b, Vec3f c) {
  const Vec3f ab = b - a, ac = c - a, ap = p - a;
  const float d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0f && d2 <= 0.0f) return {1, 0, 0};
  const Vec3f bp = p - b;
  const float d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.0f && d4 <= d3) return {0, 1, 0};
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) {
    const float v = d1 / (d1 - d3);
    return {1 - v, v, 0};
  }
  const Vec3f cp = p - c;
  const float d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.0f && d5 <= d6) return {0, 0, 1};
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) {
    const float w = d2 / (d2 - d6);
    return {1 - w, 0, w};
  }
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) {
    const float w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0, 1 - w, w};
  }
  const float denom = 1.0f / (va + vb + vc);
  const float v = vb * denom, w = vc * denom;
  return {1 - v - w, v, w};
}

/// Parameters (s, t) in [0, 1] of the closest points of segments p + s(q − p) and r + t(u − r)
/// (Ericson 5.1.9).
TEAR_HD inline void closest_on_segments(Vec3f p, Vec3f q, Vec3f r, Vec3f u, float& s, float& t) {
  const Vec3f d1 = q - p, d2 = u - r, e = p - r;
  const float a = dot(d1, d1), f = dot(d2, d2), c = dot(d1, e), b = dot(d1, d2), g = dot(d2, e);
  const auto clamp01 = [](float x) { return x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x; };
  if (a <= 1e-30f && f <= 1e-30f) {
    s = t = 0;
    return;
  }
  if (a <= 1e-30f) {
    s = 0, t = clamp01(g / f);
    return;
  }
  if (f <= 1e-30f) {
    t = 0, s = clamp01(-c / a);
    return;
  }
  const float denom = a * f - b * b;
  s = denom > 0.0f ? clamp01((b * g - c * f) / denom) : 0.0f;
  t = (b * s + g) / f;
  if (t < 0.0f) {
    t = 0, s = clamp01(-c / a);
  } else if (t > 1.0f) {
    t = 1, s = clamp01((b - c) / a);
  }
}

/// The times in [0, 1] at which four points moving linearly (x0 → x1) are coplanar, earliest first:
/// the roots of the cubic det(b − a, c − a, p − a), found by bisection between its turning points.
/// Returns how many (at most 3) are in `t`.
TEAR_HD inline int coplanar_times(const Vec3f x0[4], const Vec3f x1[4], double t[3]) {
  // Relative to the first point: B, C, P and their motions.
  Vec3d B, C, P, dB, dC, dP;
  const auto d = [](Vec3f v) { return Vec3d{v.x, v.y, v.z}; };
  B = d(x0[1]) - d(x0[0]), C = d(x0[2]) - d(x0[0]), P = d(x0[3]) - d(x0[0]);
  dB = (d(x1[1]) - d(x1[0])) - B, dC = (d(x1[2]) - d(x1[0])) - C, dP = (d(x1[3]) - d(x1[0])) - P;
  const Vec3d bc = cross(B, C), mid = cross(B, dC) + cross(dB, C), dd = cross(dB, dC);
  const double c0 = dot(bc, P), c1 = dot(bc, dP) + dot(mid, P), c2 = dot(mid, dP) + dot(dd, P), c3 = dot(dd, dP);
  const auto f = [&](double x) { return ((c3 * x + c2) * x + c1) * x + c0; };
  // Turning points of the cubic in (0, 1) split it into monotone pieces.
  double cuts[4] = {0, 0, 0, 1};
  int n = 1;
  const double qa = 3 * c3, qb = 2 * c2, qc = c1;
  if (fabs(qa) > 1e-300) {
    const double disc = qb * qb - 4 * qa * qc;
    if (disc > 0) {
      const double r = sqrt(disc);
      double r1 = (-qb - r) / (2 * qa), r2 = (-qb + r) / (2 * qa);
      if (r1 > r2) {
        const double tmp = r1;
        r1 = r2, r2 = tmp;
      }
      if (r1 > 0 && r1 < 1) cuts[n++] = r1;
      if (r2 > 0 && r2 < 1) cuts[n++] = r2;
    }
  } else if (fabs(qb) > 1e-300) {
    const double r = -qc / qb;
    if (r > 0 && r < 1) cuts[n++] = r;
  }
  cuts[n] = 1;
  int found = 0;
  for (int i = 0; i < n; ++i) {
    double lo = cuts[i], hi = cuts[i + 1];
    double flo = f(lo), fhi = f(hi);
    if (flo == 0) {
      if (found == 0 || t[found - 1] != lo) t[found++] = lo;
      continue;
    }
    if (flo * fhi > 0) continue;
    for (int k = 0; k < 40; ++k) {
      const double m = 0.5 * (lo + hi), fm = f(m);
      if ((fm < 0) == (flo < 0)) {
        lo = m, flo = fm;
      } else {
        hi = m;
      }
    }
    t[found++] = hi;
  }
  return found;
}

TEAR_HD inline Vec3f lerp(Vec3f a, Vec3f b, float t) { return a + t * (b - a); }

/// Distance between point p and triangle (a, b, c).
TEAR_HD inline float point_triangle_distance(Vec3f p, Vec3f a, Vec3f b, Vec3f c) {
  const Vec3f w = closest_on_triangle(p, a, b, c);
  return norm(p - (w.x * a + (w.y * b + w.z * c)));
}

}  // namespace tear::kernels
