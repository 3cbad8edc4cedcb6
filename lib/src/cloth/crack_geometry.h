// tear: the small geometry crack growth is made of (crack_growth.h), shared by its two files:
// vectors of the rest shape, symmetric tensors stored xx yy zz xy xz yz, and the grid lookup of
// the faces near a point. Only for crack_field.cpp and crack_growth.cpp.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "cloth/crack_growth.h"

namespace tear {
namespace crack {

using Vec3 = std::array<double, 3>;

inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 scale(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline Vec3 unit(const Vec3& a) {
  const double l = norm(a);
  return l > 0 ? scale(a, 1 / l) : Vec3{0, 0, 0};
}
/// `a` with its component along unit `n` removed.
inline Vec3 in_plane(const Vec3& a, const Vec3& n) { return sub(a, scale(n, dot(a, n))); }

/// m^T S m for a symmetric tensor stored xx yy zz xy xz yz.
inline double quad(const double* S, const Vec3& m) {
  return S[0] * m[0] * m[0] + S[1] * m[1] * m[1] + S[2] * m[2] * m[2] +
         2 * (S[3] * m[0] * m[1] + S[4] * m[0] * m[2] + S[5] * m[1] * m[2]);
}
inline double bilinear(const double* S, const Vec3& a, const Vec3& b) {
  return S[0] * a[0] * b[0] + S[1] * a[1] * b[1] + S[2] * a[2] * b[2] + S[3] * (a[0] * b[1] + a[1] * b[0]) +
         S[4] * (a[0] * b[2] + a[2] * b[0]) + S[5] * (a[1] * b[2] + a[2] * b[1]);
}

/// The distance between segments [p0, p1] and [q0, q1] (sampled closely enough for the test it serves:
/// whether two cracks of one substep come within a radius of each other).
inline double segment_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  const auto point_segment = [](const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = sub(b, a);
    const double t = std::max(0.0, std::min(1.0, dot(sub(p, a), ab) / std::max(dot(ab, ab), 1e-300)));
    return norm(sub(p, add(a, scale(ab, t))));
  };
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= 16; ++i) {
    const double t = i / 16.0;
    best = std::min(best, point_segment(add(p0, scale(sub(p1, p0), t)), q0, q1));
    best = std::min(best, point_segment(add(q0, scale(sub(q1, q0), t)), p0, p1));
  }
  return best;
}

/// A unit vector orthogonal to unit `n`.
inline Vec3 any_tangent(const Vec3& n) {
  const Vec3 a = std::abs(n[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  return unit(in_plane(a, n));
}

/// The largest eigenvalue of S restricted to the plane of unit normal `n`, and its unit eigenvector.
inline double principal(const double* S, const Vec3& n, Vec3& r) {
  const Vec3 b1 = any_tangent(n), b2 = cross(n, b1);
  const double s11 = quad(S, b1), s22 = quad(S, b2), s12 = bilinear(S, b1, b2);
  const double half = 0.5 * (s11 - s22), lambda = 0.5 * (s11 + s22) + std::sqrt(half * half + s12 * s12);
  double r0 = lambda - s22, r1 = s12;
  if (std::abs(r0) + std::abs(r1) < 1e-300) {
    r0 = s12;
    r1 = lambda - s11;
  }
  if (std::abs(r0) + std::abs(r1) < 1e-300) r0 = 1, r1 = 0;
  r = unit(add(scale(b1, r0), scale(b2, r1)));
  return lambda;
}

constexpr double pi = 3.14159265358979323846;

/// A point in a plane's own coordinates (a cut's tests project onto the plane of its start).
using Flat = std::array<double, 2>;
/// Twice the signed area of triangle o, a, b: positive where it turns left.
inline double turn(const Flat& o, const Flat& a, const Flat& b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}
/// Whether segments [p0, p1] and [a, b] cross properly: each one's ends strictly on both sides of
/// the other's line.
inline bool segments_cross(const Flat& p0, const Flat& p1, const Flat& a, const Flat& b) {
  const double s0 = turn(p0, p1, a), s1 = turn(p0, p1, b), s2 = turn(a, b, p0), s3 = turn(a, b, p1);
  return ((s0 > 0 && s1 < 0) || (s0 < 0 && s1 > 0)) && ((s2 > 0 && s3 < 0) || (s2 < 0 && s3 > 0));
}

}  // namespace crack

struct CrackField::Tip {
  index_t node = -1;
  Vec3 at, normal, forward;
  Vec3 course;  ///< the point of the crack's fitted line nearest the tip (where its snapped tip should be)
};

template <class F>
void CrackField::faces_near(const Vec3& p, double r, F&& f) const {
  std::int64_t lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = static_cast<std::int64_t>(std::floor((p[a] - r) / cell_));
    hi[a] = static_cast<std::int64_t>(std::floor((p[a] + r) / cell_));
  }
  const auto wrap = [](std::int64_t v) { return (v + (std::int64_t(1) << 20)) & ((std::int64_t(1) << 21) - 1); };
  // The cells of one (x, y) column are consecutive keys (z is the key's low bits) unless z wraps
  // within the range: one search per column then, and the faces visited in the same order.
  const bool column = wrap(lo[2]) <= wrap(hi[2]) && hi[2] - lo[2] < (std::int64_t(1) << 21);
  for (std::int64_t x = lo[0]; x <= hi[0]; ++x)
    for (std::int64_t y = lo[1]; y <= hi[1]; ++y) {
      const std::int64_t base = (wrap(x) << 42) + (wrap(y) << 21);
      const auto visit = [&](std::vector<std::int64_t>::const_iterator it, std::int64_t last) {
        for (; it != cell_key_.end() && *it <= last; ++it) {
          const index_t g = cell_face_[it - cell_key_.begin()];
          if (crack::norm(crack::sub(face_centroid_[g], p)) <= r) f(g);
        }
      };
      if (column) {
        visit(std::lower_bound(cell_key_.begin(), cell_key_.end(), base + wrap(lo[2])), base + wrap(hi[2]));
      } else {
        for (std::int64_t z = lo[2]; z <= hi[2]; ++z)
          visit(std::lower_bound(cell_key_.begin(), cell_key_.end(), base + wrap(z)), base + wrap(z));
      }
    }
}

}  // namespace tear
