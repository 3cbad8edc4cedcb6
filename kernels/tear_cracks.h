// tear kernels: how far the cloth is stretched (the first question of `tearing`).
//
// A face's stretch is the largest principal stretch of its map from the rest triangle to the
// current one: the largest singular value of its 3x2 deformation gradient F, whose right singular
// vector r is the rest-space direction stretched most. Where no face passes the tearing limits,
// nothing tears; where one does, crack growth (lib/src/cloth/crack_growth.h) decides where cracks
// run from the stretch smoothed around their tips.
//
// Example: one face, nodes 0 1 2 at rest (0,0,0) (1,0,0) (0,1,0), now at (0,0,0) (1.5,0,0) (0,1,0):
// stretch 1.5 along r = (1,0,0).
#pragma once

#include <cmath>
#include <cstdint>

#include "hd.h"

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

/// Per face: its stretch over `limit` (the faces' largest, reduced on the backend, is the tear check's
/// first and usually only question: nothing passes it, nothing tears).
struct face_stretch_of {
  const index_t* face_nodes;
  const float* node_rest;
  const float* node_pos;
  TEAR_HD double operator()(index_t f) const { return face_principal_stretch(face_nodes, node_rest, node_pos, f); }
};

}  // namespace tear::kernels

namespace tear::kernels {

/// Face f's stretch tensor in rest space: F^T F of its map from the rest triangle to the current
/// one, pushed to the rest triangle's plane in 3D, as xx yy zz xy xz yz (crack growth smooths it
/// over discs, lib/src/cloth/crack_field.cpp). Returns the face's rest area; a face of no rest area
/// gets a zero tensor. Example: the unit right triangle in z = 0 stretched 1.5 along x: t = (2.25,
/// 1, 0, 0, 0, 0), area 0.5.
TEAR_HD inline double face_stretch_tensor(const index_t* face_nodes, const float* node_rest, const float* node_pos,
                                          index_t f, double t[6]) {
  double X[3][3], x[3][3];
  for (int k = 0; k < 3; ++k) {
    const index_t n = face_nodes[3 * f + k];
    for (int d = 0; d < 3; ++d) {
      X[k][d] = node_rest[3 * n + d];
      x[k][d] = node_pos[3 * n + d];
    }
  }
  for (int s = 0; s < 6; ++s) t[s] = 0;
  double E1[3], E2[3], e1[3], e2[3];
  for (int d = 0; d < 3; ++d) {
    E1[d] = X[1][d] - X[0][d];
    E2[d] = X[2][d] - X[0][d];
    e1[d] = x[1][d] - x[0][d];
    e2[d] = x[2][d] - x[0][d];
  }
  const double n0 = E1[1] * E2[2] - E1[2] * E2[1], n1 = E1[2] * E2[0] - E1[0] * E2[2], n2 = E1[0] * E2[1] - E1[1] * E2[0];
  const double area = 0.5 * sqrt(n0 * n0 + n1 * n1 + n2 * n2);
  const double l1 = sqrt(E1[0] * E1[0] + E1[1] * E1[1] + E1[2] * E1[2]);
  if (!(l1 > 0)) return area;
  double u[3], w[3], v[3], f1[3], f2[3];
  for (int d = 0; d < 3; ++d) u[d] = E1[d] * (1 / l1);
  const double a = E2[0] * u[0] + E2[1] * u[1] + E2[2] * u[2];
  for (int d = 0; d < 3; ++d) w[d] = E2[d] - u[d] * a;
  const double h = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  if (!(h > 1e-12 * l1)) return area;
  for (int d = 0; d < 3; ++d) {
    v[d] = w[d] * (1 / h);
    f1[d] = e1[d] * (1 / l1);
    f2[d] = (e2[d] - e1[d] * (a / l1)) * (1 / h);
  }
  const double c11 = f1[0] * f1[0] + f1[1] * f1[1] + f1[2] * f1[2];
  const double c12 = f1[0] * f2[0] + f1[1] * f2[1] + f1[2] * f2[2];
  const double c22 = f2[0] * f2[0] + f2[1] * f2[1] + f2[2] * f2[2];
  const int I[6] = {0, 1, 2, 0, 0, 1}, J[6] = {0, 1, 2, 1, 2, 2};
  for (int s = 0; s < 6; ++s)
    t[s] = c11 * u[I[s]] * u[J[s]] + c22 * v[I[s]] * v[J[s]] + c12 * (u[I[s]] * v[J[s]] + v[I[s]] * u[J[s]]);
  return area;
}

/// Eight sums of a disc of crack growth: the area-weighted stretch tensor (6), strength, and area.
struct DiscSums {
  double v[8];
};
struct add_disc_sums {
  TEAR_HD DiscSums operator()(const DiscSums& a, const DiscSums& b) const {
    DiscSums c;
    for (int s = 0; s < 8; ++s) c.v[s] = a.v[s] + b.v[s];
    return c;
  }
};

/// Per entry i of the discs' face lists (face `faces[i]`): its DiscSums term, to be summed per
/// disc (a reduction by key over the entries, which lie disc by disc).
struct disc_term {
  const index_t* faces;
  const index_t* face_nodes;
  const float* node_rest;
  const float* node_pos;
  const float* face_strength;  // null: 1
  TEAR_HD DiscSums operator()(index_t i) const {
    const index_t f = faces[i];
    DiscSums out;
    double t[6];
    const double A = face_stretch_tensor(face_nodes, node_rest, node_pos, f, t);
    for (int s = 0; s < 6; ++s) out.v[s] = A * t[s];
    out.v[6] = A * (face_strength ? face_strength[f] : 1.0);
    out.v[7] = A;
    return out;
  }
};

/// Per face: its stretch over its strength where a crack may start there (`may_start`), else 0.
/// The faces' largest is what a start needs to pass (`tearing.start`).
struct start_stretch_of {
  const index_t* face_nodes;
  const float* node_rest;
  const float* node_pos;
  const float* face_strength;  // null: 1
  const std::uint8_t* may_start;
  TEAR_HD double operator()(index_t f) const {
    if (!may_start[f]) return 0;
    return face_principal_stretch(face_nodes, node_rest, node_pos, f) / (face_strength ? face_strength[f] : 1.0);
  }
};

}  // namespace tear::kernels
