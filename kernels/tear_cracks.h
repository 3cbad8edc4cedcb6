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
  const double n0 = E1[1] * E2[2] - E1[2] * E2[1], n1 = E1[2] * E2[0] - E1[0] * E2[2],
               n2 = E1[0] * E2[1] - E1[1] * E2[0];
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

/// Per element i: f(i) into out[i] (the check's largest values are reduced from these).
template <class F>
struct store_value {
  F f;
  double* out;
  TEAR_HD void operator()(index_t i) const { out[i] = f(i); }
};

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

/// Face f's share of a disc's sums: its area times its stretch tensor and its strength, its area.
TEAR_HD inline DiscSums face_disc_term(const index_t* face_nodes, const float* node_rest, const float* node_pos,
                                       const float* face_strength, index_t f) {
  DiscSums out;
  double t[6];
  const double A = face_stretch_tensor(face_nodes, node_rest, node_pos, f, t);
  for (int s = 0; s < 6; ++s) out.v[s] = A * t[s];
  out.v[6] = A * (face_strength ? face_strength[f] : 1.0);
  out.v[7] = A;
  return out;
}

/// Per entry i of the discs' face lists (face `faces[i]`): its DiscSums term, to be summed per
/// disc (a reduction by key over the entries, which lie disc by disc).
struct disc_term {
  const index_t* faces;
  const index_t* face_nodes;
  const float* node_rest;
  const float* node_pos;
  const float* face_strength;  // null: 1
  TEAR_HD DiscSums operator()(index_t i) const {
    return face_disc_term(face_nodes, node_rest, node_pos, face_strength, faces[i]);
  }
};

/// Per face: its own stretch over the start limit (`start` times its strength) where a crack may
/// start there (`may_start`), else 0: a looser bound of every start than `start_ratio_of`, for
/// backends where the discs cost more than the plan they would spare (the CPU).
struct start_stretch_ratio_of {
  const index_t* face_nodes;
  const float* node_rest;
  const float* node_pos;
  const float* face_strength;  // null: 1
  const std::uint8_t* may_start;
  double start;
  TEAR_HD double operator()(index_t f) const {
    if (!may_start[f]) return 0;
    return face_principal_stretch(face_nodes, node_rest, node_pos, f) /
           (start * (face_strength ? face_strength[f] : 1.0));
  }
};

/// Crack growth's grid of faces by rest centroid (lib/src/cloth/crack_field.cpp, build_grid): cells
/// of side `cell`, keys sorted, each with its face.
struct FaceGrid {
  const std::int64_t* keys;
  const index_t* faces;
  index_t count;
  double cell;

  /// A cell coordinate as the key holds it: 21 bits, offset by 2^20 (wrapping beyond that).
  static TEAR_HD std::int64_t wrap(std::int64_t v) {
    return (v + (std::int64_t(1) << 20)) & ((std::int64_t(1) << 21) - 1);
  }
  /// The key of cell (x, y, z): x, y and z wrapped, z in the low bits.
  static TEAR_HD std::int64_t key(std::int64_t x, std::int64_t y, std::int64_t z) {
    return (wrap(x) << 42) + (wrap(y) << 21) + wrap(z);
  }
};

/// Face f's rest centroid, as crack growth computes it.
TEAR_HD inline void rest_centroid(const index_t* face_nodes, const float* node_rest, index_t f, double c[3]) {
  for (int d = 0; d < 3; ++d) {
    const double a = node_rest[3 * face_nodes[3 * f] + d], b = node_rest[3 * face_nodes[3 * f + 1] + d],
                 e = node_rest[3 * face_nodes[3 * f + 2] + d];
    c[d] = ((a + b) + e) * (1 / 3.0);
  }
}

/// The largest eigenvalue of the symmetric tensor S (xx yy zz xy xz yz) in the plane of unit
/// normal n: crack growth's `principal` (crack_geometry.h), the same arithmetic.
TEAR_HD inline double principal_in_plane(const double* S, const double n[3]) {
  double a[3] = {0, 1, 0};
  if (fabs(n[0]) < 0.9) a[0] = 1, a[1] = 0;
  const double an = a[0] * n[0] + a[1] * n[1] + a[2] * n[2];
  double b1[3] = {a[0] - n[0] * an, a[1] - n[1] * an, a[2] - n[2] * an};
  const double l = sqrt(b1[0] * b1[0] + b1[1] * b1[1] + b1[2] * b1[2]);
  for (int d = 0; d < 3; ++d) b1[d] = l > 0 ? b1[d] * (1 / l) : 0;
  const double b2[3] = {n[1] * b1[2] - n[2] * b1[1], n[2] * b1[0] - n[0] * b1[2], n[0] * b1[1] - n[1] * b1[0]};
  const auto quad = [&](const double* m) {
    return S[0] * m[0] * m[0] + S[1] * m[1] * m[1] + S[2] * m[2] * m[2] +
           2 * (S[3] * m[0] * m[1] + S[4] * m[0] * m[2] + S[5] * m[1] * m[2]);
  };
  const double s11 = quad(b1), s22 = quad(b2);
  const double s12 = S[0] * b1[0] * b2[0] + S[1] * b1[1] * b2[1] + S[2] * b1[2] * b2[2] +
                     S[3] * (b1[0] * b2[1] + b1[1] * b2[0]) + S[4] * (b1[0] * b2[2] + b1[2] * b2[0]) +
                     S[5] * (b1[1] * b2[2] + b1[2] * b2[1]);
  const double half = 0.5 * (s11 - s22);
  return 0.5 * (s11 + s22) + sqrt(half * half + s12 * s12);
}

/// Every face's DiscSums term (`face_disc_term`) into `out`, once per check: the start candidates'
/// discs below read them instead of computing each face's tensor again for every disc it lies in.
struct store_disc_terms {
  const index_t* face_nodes;
  const float* node_rest;
  const float* node_pos;
  const float* face_strength;  // null: 1
  DiscSums* out;
  TEAR_HD void operator()(index_t f) const { out[f] = face_disc_term(face_nodes, node_rest, node_pos, face_strength, f); }
};

/// Every face's rest centroid (`rest_centroid`) into `out` (3 per face), once per view of the mesh.
struct store_rest_centroids {
  const index_t* face_nodes;
  const float* node_rest;
  double* out;
  TEAR_HD void operator()(index_t f) const { rest_centroid(face_nodes, node_rest, f, out + 3 * f); }
};

/// The disc a start candidate's stretch is smoothed over: the plane of face f (its unit normal `n`)
/// and the grid's cells over [c - r, c + r] around its rest centroid c, as key ranges. The cells of
/// one (x, y) column are consecutive keys (z is the key's low bits) unless z wraps within the range:
/// one range per column then, else one per cell; ranges in x, y, z order, at most 27.
struct StartDisc {
  double n[3];
  const double* c;
  std::int64_t lo[3], hi[3];
  bool column;

  /// False where face f has no area (no plane).
  TEAR_HD bool make(const index_t* face_nodes, const float* node_rest, const double* centroids, const FaceGrid& grid,
                    double radius, index_t f) {
    double E1[3], E2[3];
    for (int d = 0; d < 3; ++d) {
      E1[d] = static_cast<double>(node_rest[3 * face_nodes[3 * f + 1] + d]) - node_rest[3 * face_nodes[3 * f] + d];
      E2[d] = static_cast<double>(node_rest[3 * face_nodes[3 * f + 2] + d]) - node_rest[3 * face_nodes[3 * f] + d];
    }
    n[0] = E1[1] * E2[2] - E1[2] * E2[1];
    n[1] = E1[2] * E2[0] - E1[0] * E2[2];
    n[2] = E1[0] * E2[1] - E1[1] * E2[0];
    const double ln = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(ln > 0)) return false;
    for (int d = 0; d < 3; ++d) n[d] = n[d] * (1 / ln);
    c = centroids + 3 * f;
    for (int a = 0; a < 3; ++a) {
      lo[a] = static_cast<std::int64_t>(floor((c[a] - radius) / grid.cell));
      hi[a] = static_cast<std::int64_t>(floor((c[a] + radius) / grid.cell));
    }
    column = FaceGrid::wrap(lo[2]) <= FaceGrid::wrap(hi[2]) && hi[2] - lo[2] < (std::int64_t(1) << 21);
    return true;
  }
  TEAR_HD int ranges() const {
    return static_cast<int>((hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (column ? 1 : hi[2] - lo[2] + 1));
  }
  /// Range r: the index of its first entry in the grid and the last key in it.
  TEAR_HD index_t range(const FaceGrid& grid, int r, std::int64_t& last_key) const {
    const std::int64_t nz = column ? 1 : hi[2] - lo[2] + 1, ny = hi[1] - lo[1] + 1;
    const std::int64_t x = lo[0] + r / (ny * nz), y = lo[1] + (r / nz) % ny, z = lo[2] + r % nz;
    const std::int64_t key = FaceGrid::key(x, y, z);
    last_key = column ? FaceGrid::key(x, y, hi[2]) : key;
    index_t first = 0, last = grid.count;  // lower bound of key
    while (first < last) {
      const index_t mid = first + (last - first) / 2;
      if (grid.keys[mid] < key)
        first = mid + 1;
      else
        last = mid;
    }
    return first;
  }
  /// Entry i's face's term added to `sum` where its centroid lies within `radius`.
  TEAR_HD void add(const FaceGrid& grid, const DiscSums* terms, const double* centroids, double radius, index_t i,
                   DiscSums& sum) const {
    const index_t g = grid.faces[i];
    const double* q = centroids + 3 * g;
    const double dx = q[0] - c[0], dy = q[1] - c[1], dz = q[2] - c[2];
    if (!(sqrt(dx * dx + dy * dy + dz * dz) <= radius)) return;
    const DiscSums& term = terms[g];
    for (int k = 0; k < 8; ++k) sum.v[k] += term.v[k];
  }
  /// The smoothed stretch of the disc's sums over the start limit `start`, 0 for an empty disc.
  TEAR_HD double ratio(DiscSums sum, double start) const {
    const double area = sum.v[7];
    if (!(area > 0)) return 0;
    for (int k = 0; k < 6; ++k) sum.v[k] = sum.v[k] / area;
    const double lambda = principal_in_plane(sum.v, n);
    return sqrt(lambda > 0 ? lambda : 0.0) / (start * (sum.v[6] / area));
  }
};

/// Per face: where a new crack could start there, its smoothed stretch over the start limit (the
/// test `CrackField::start` makes of a candidate: the stretch smoothed over the disc of `radius`
/// around the face's rest centroid, in the face's plane, over `start` times the disc's mean
/// strength); 0 where it cannot (near a crack or a tip, `may_start`, or its own stretch under the
/// limit, which every candidate passes first). The faces' largest bounds every start of a substep.
/// The faces' terms and rest centroids come stored (store_disc_terms, store_rest_centroids).
struct start_ratio_of {
  start_stretch_ratio_of own;  // the face's own stretch over the limit, 0 where it may not start
  FaceGrid grid;
  double radius;
  const DiscSums* terms;    // [faces]
  const double* centroids;  // [3 faces]
  TEAR_HD double operator()(index_t f) const {
    StartDisc disc;
    if (!(own(f) > 0.999) || !disc.make(own.face_nodes, own.node_rest, centroids, grid, radius, f)) return 0;
    DiscSums sum{{0, 0, 0, 0, 0, 0, 0, 0}};
    for (int r = 0; r < disc.ranges(); ++r) {
      std::int64_t last_key = 0;
      for (index_t i = disc.range(grid, r, last_key); i < grid.count && grid.keys[i] <= last_key; ++i)
        disc.add(grid, terms, centroids, radius, i, sum);
    }
    return disc.ratio(sum, own.start);
  }
};

/// `start_ratio_of` into `out` [faces], a warp a face: element i is lane i % 32 of face i / 32 (a
/// launch of 32 elements a face, one per thread, so that a warp holds one face's 32 lanes). The
/// lanes search the disc's ranges at once and share its entries (lane j takes every 32nd from the
/// j-th), then their sums are added in a fixed tree: the same value every run, though summed in
/// another order than `start_ratio_of` (the value only gates the host's plan, with a margin). A
/// face's disc walked by one thread is a chain of some 900 dependent loads, about half a
/// millisecond on an H200 whatever the number of faces. Off the GPU, lane 0 computes
/// `start_ratio_of`.
struct start_ratio_by_warp {
  start_ratio_of one;
  double* out;
  TEAR_HD void operator()(index_t i) const {
    const index_t f = i / 32;
    const int lane = static_cast<int>(i % 32);
#if defined(__CUDA_ARCH__)
    StartDisc disc;
    const bool candidate =
        one.own(f) > 0.999 && disc.make(one.own.face_nodes, one.own.node_rest, one.centroids, one.grid, one.radius, f);
    if (!candidate) {  // the same for the whole warp
      if (lane == 0) out[f] = 0;
      return;
    }
    std::int64_t last_key = 0;
    const int ranges = disc.ranges();
    if (ranges > 32) {  // a grid finer than the disc: one lane walks it
      if (lane == 0) out[f] = one(f);
      return;
    }
    const index_t first = lane < ranges ? disc.range(one.grid, lane, last_key) : 0;
    DiscSums sum{{0, 0, 0, 0, 0, 0, 0, 0}};
    for (int r = 0; r < ranges; ++r) {
      const index_t begin = __shfl_sync(0xffffffffu, first, r);
      const std::int64_t end_key = __shfl_sync(0xffffffffu, last_key, r);
      for (index_t e = begin + lane; e < one.grid.count && one.grid.keys[e] <= end_key; e += 32)
        disc.add(one.grid, one.terms, one.centroids, one.radius, e, sum);
    }
    for (int offset = 16; offset > 0; offset /= 2)
      for (int k = 0; k < 8; ++k) sum.v[k] += __shfl_down_sync(0xffffffffu, sum.v[k], offset);
    if (lane == 0) out[f] = disc.ratio(sum, one.own.start);
#else
    if (lane == 0) out[f] = one(f);
#endif
  }
};

}  // namespace tear::kernels
