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
