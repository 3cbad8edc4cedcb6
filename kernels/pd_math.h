// tear kernels: the small vector math and constraint geometry of projective dynamics.
#pragma once

#include <cmath>

#include "hd.h"

namespace tear::kernels {

template <class T>
struct Vec3T {
  T x, y, z;
};
using Vec3f = Vec3T<float>;
using Vec3d = Vec3T<double>;

template <class T>
TEAR_HD inline Vec3T<T> operator+(Vec3T<T> a, Vec3T<T> b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class T>
TEAR_HD inline Vec3T<T> operator-(Vec3T<T> a, Vec3T<T> b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class T>
TEAR_HD inline Vec3T<T> operator*(T s, Vec3T<T> a) {
  return {s * a.x, s * a.y, s * a.z};
}
template <class T>
TEAR_HD inline T dot(Vec3T<T> a, Vec3T<T> b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
TEAR_HD inline Vec3T<T> cross(Vec3T<T> a, Vec3T<T> b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T>
TEAR_HD inline T norm(Vec3T<T> a) {
  return sqrt(dot(a, a));
}

template <class T, class P>
TEAR_HD inline Vec3T<T> load3(const P* p, int i) {
  return {static_cast<T>(p[3 * i]), static_cast<T>(p[3 * i + 1]), static_cast<T>(p[3 * i + 2])};
}
TEAR_HD inline void store3(float* p, int i, Vec3f v) {
  p[3 * i] = v.x;
  p[3 * i + 1] = v.y;
  p[3 * i + 2] = v.z;
}

/// Area of triangle (a, b, c), m².
TEAR_HD inline double triangle_area(Vec3d a, Vec3d b, Vec3d c) { return 0.5 * norm(cross(b - a, c - a)); }

/// The bending operator of the hinge of edge (x0, x1) between faces (x0, x1, x2) and (x1, x0, x3):
/// coefficients k[4] with Σ kᵢ = 0 and Σ kᵢ xᵢ = 0 when the hinge is unfolded flat (the rest
/// hinge's intrinsic shape), scaled so that |Σ kᵢ xᵢ| ≈ θ (radians) when it folds by θ from flat.
/// This is the cotangent form of Bergou et al. 2006 / Wardetzky et al. 2007, divided by the edge
/// length: k₂ = 1/h₂, k₃ = 1/h₃ (hᵢ: height of the opposite node over the edge). Returns false
/// for a degenerate hinge (a face with no area compared with the edge's length squared).
TEAR_HD inline bool hinge_coefficients(Vec3d x0, Vec3d x1, Vec3d x2, Vec3d x3, double* k) {
  const Vec3d e = x1 - x0;
  const double len2 = dot(e, e);
  const double twice_area0 = norm(cross(e, x2 - x0)), twice_area1 = norm(cross(e, x3 - x0));
  const double min_twice_area = 1e-8 * len2;
  if (!(len2 > 0) || !(twice_area0 > min_twice_area) || !(twice_area1 > min_twice_area)) return false;
  const double len = sqrt(len2);
  // Cotangents of the angles at x0 (a) and x1 (b) in faces 0 and 1.
  const double cot_a0 = dot(e, x2 - x0) / twice_area0, cot_b0 = dot(x0 - x1, x2 - x1) / twice_area0;
  const double cot_a1 = dot(e, x3 - x0) / twice_area1, cot_b1 = dot(x0 - x1, x3 - x1) / twice_area1;
  k[0] = -(cot_b0 + cot_b1) / len;
  k[1] = -(cot_a0 + cot_a1) / len;
  k[2] = (cot_a0 + cot_b0) / len;
  k[3] = (cot_a1 + cot_b1) / len;
  return true;
}

/// The local step of a constraint that keeps the length of d = Σ kᵢ xᵢ at `rest` (an edge spring:
/// d = x₀ − x₁; a hinge: d ≈ its fold, `rest` its rest fold): the nearest such vector, d rescaled.
/// A zero d has no direction; it is left as it is (no force), which only happens for a collapsed
/// edge or an exactly flat hinge whose projection is d itself.
TEAR_HD inline Vec3f project_length(Vec3f d, float rest) {
  const float len = norm(d);
  if (!(len > 0.0f)) return d;
  return (rest / len) * d;
}

}  // namespace tear::kernels
