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

/// The local step of a face's membrane (a strain constraint, Bouaziz et al. 2014, §5.1): the 3×2
/// matrix [r0 r1] with orthonormal columns nearest to F = [f0 f1], the face's deformation gradient,
/// which is R = F (FᵀF)^(−1/2), its polar factor: the face moved rigidly, at its rest size and
/// shape, the same way whatever the directions of its edges. A face collapsed to a segment keeps the
/// segment's direction as one column and leaves the other as it is; one collapsed to a point is left
/// as it is (no force), like `project_length`'s zero vector.
TEAR_HD inline void project_rotation(Vec3f f0, Vec3f f1, Vec3f& r0, Vec3f& r1) {
  const float a = dot(f0, f0), b = dot(f0, f1), c = dot(f1, f1);
  const float det = a * c - b * b;
  const float trace = a + c;
  if (!(trace > 0.0f)) {
    r0 = f0;
    r1 = f1;
    return;
  }
  if (det > 1e-12f * trace * trace) {
    // (FᵀF)^(1/2) = (C + √det I) / √(tr C + 2√det); its inverse by the 2×2 adjugate.
    const float root = sqrtf(det);
    const float scale = sqrtf(trace + 2.0f * root);
    const float s00 = (a + root) / scale, s01 = b / scale, s11 = (c + root) / scale;
    const float inv_det = 1.0f / (s00 * s11 - s01 * s01);
    // F S⁻¹ with S⁻¹ = [s11 −s01; −s01 s00] / det S.
    r0 = (s11 * inv_det) * f0 - (s01 * inv_det) * f1;
    r1 = (s00 * inv_det) * f1 - (s01 * inv_det) * f0;
    return;
  }
  // Rank one: F ≈ u σ vᵀ with u along the longer column; R's column j is u vⱼ.
  const Vec3f u_raw = a >= c ? f0 : f1;
  const float u_len = sqrtf(a >= c ? a : c);
  const Vec3f u = (1.0f / u_len) * u_raw;
  const float v0 = dot(u, f0), v1 = dot(u, f1);
  const float v_len = sqrtf(v0 * v0 + v1 * v1);
  r0 = (v0 / v_len) * u;
  r1 = (v1 / v_len) * u;
}

}  // namespace tear::kernels
