// tear: crack growth from tips over smoothed stretch (crack_growth.h).
#include "cloth/crack_growth.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace tear {

namespace {

using Vec3 = std::array<double, 3>;

Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3 scale(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
Vec3 unit(const Vec3& a) {
  const double l = norm(a);
  return l > 0 ? scale(a, 1 / l) : Vec3{0, 0, 0};
}
/// `a` with its component along unit `n` removed.
Vec3 in_plane(const Vec3& a, const Vec3& n) { return sub(a, scale(n, dot(a, n))); }

/// m^T S m for a symmetric tensor stored xx yy zz xy xz yz.
double quad(const double* S, const Vec3& m) {
  return S[0] * m[0] * m[0] + S[1] * m[1] * m[1] + S[2] * m[2] * m[2] +
         2 * (S[3] * m[0] * m[1] + S[4] * m[0] * m[2] + S[5] * m[1] * m[2]);
}
double bilinear(const double* S, const Vec3& a, const Vec3& b) {
  return S[0] * a[0] * b[0] + S[1] * a[1] * b[1] + S[2] * a[2] * b[2] + S[3] * (a[0] * b[1] + a[1] * b[0]) +
         S[4] * (a[0] * b[2] + a[2] * b[0]) + S[5] * (a[1] * b[2] + a[2] * b[1]);
}

/// The distance between segments [p0, p1] and [q0, q1] (sampled closely enough for the test it serves:
/// whether two cracks of one substep come within a radius of each other).
double segment_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
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
Vec3 any_tangent(const Vec3& n) {
  const Vec3 a = std::abs(n[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  return unit(in_plane(a, n));
}

/// The largest eigenvalue of S restricted to the plane of unit normal `n`, and its unit eigenvector.
double principal(const double* S, const Vec3& n, Vec3& r) {
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

/// A hash of a lattice point and a seed to [-1, 1].
double lattice_value(std::int64_t x, std::int64_t y, std::int64_t z, std::uint32_t seed) {
  std::uint64_t h = 0x9E3779B97F4A7C15ull ^ seed;
  for (std::int64_t v : {x, y, z}) {
    h ^= static_cast<std::uint64_t>(v) + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 31;
  }
  return static_cast<double>(h >> 11) / static_cast<double>(1ull << 53) * 2 - 1;
}

/// Value noise of unit feature size at p (trilinear between lattice values, smoothstep weights).
double value_noise(const Vec3& p, std::uint32_t seed) {
  std::int64_t i[3];
  double t[3];
  for (int a = 0; a < 3; ++a) {
    const double f = std::floor(p[a]);
    i[a] = static_cast<std::int64_t>(f);
    const double s = p[a] - f;
    t[a] = s * s * (3 - 2 * s);
  }
  double v = 0;
  for (int c = 0; c < 8; ++c) {
    double w = 1;
    for (int a = 0; a < 3; ++a) w *= (c >> a & 1) ? t[a] : 1 - t[a];
    v += w * lattice_value(i[0] + (c & 1), i[1] + (c >> 1 & 1), i[2] + (c >> 2 & 1), seed);
  }
  return v;
}

constexpr double pi = 3.14159265358979323846;

}  // namespace

std::vector<float> face_strength_field(const std::vector<float>& node_rest, const std::vector<index_t>& face_nodes,
                                       const TearingOptions& options) {
  const std::size_t faces = face_nodes.size() / 3;
  std::vector<float> strength(faces, 1.f);
  if (options.variation <= 0) return strength;
  for (std::size_t f = 0; f < faces; ++f) {
    Vec3 c{0, 0, 0};
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) c[d] += node_rest[3 * face_nodes[3 * f + k] + d] / 3.0;
    strength[f] = static_cast<float>(1 + options.variation * value_noise(scale(c, 1 / options.radius), options.seed));
  }
  return strength;
}

struct CrackField::Tip {
  index_t node;
  Vec3 at, normal, forward;
  Vec3 course;  ///< the point of the crack's fitted line nearest the tip (where its snapped tip should be)
};

CrackField::CrackField(CrackMesh mesh, const TearingOptions& options) : m_(std::move(mesh)), options_(options) {
  const index_t faces = m_.topo.face_count, nodes = m_.topo.node_count;
  face_centroid_.resize(faces);
  face_normal_.resize(faces);
  face_area_.resize(faces);
  node_angle_.assign(nodes, 0);
  for (index_t f = 0; f < faces; ++f) {
    Vec3 X[3];
    for (int k = 0; k < 3; ++k) X[k] = rest(m_.face_nodes[3 * f + k]);
    face_centroid_[f] = scale(add(add(X[0], X[1]), X[2]), 1 / 3.0);
    const Vec3 n = cross(sub(X[1], X[0]), sub(X[2], X[0]));
    face_area_[f] = 0.5 * norm(n);
    total_area_ += face_area_[f];
    face_normal_[f] = unit(n);
    for (int k = 0; k < 3; ++k) {
      const Vec3 a = sub(X[(k + 1) % 3], X[k]), b = sub(X[(k + 2) % 3], X[k]);
      const double c = dot(a, b) / std::max(norm(a) * norm(b), 1e-300);
      node_angle_[m_.face_nodes[3 * f + k]] += std::acos(std::max(-1.0, std::min(1.0, c)));
    }
  }
  // The smoothing disc spans a face at least, so a coarse mesh still averages a neighbourhood.
  double edges = 0;
  for (index_t e = 0; e < m_.topo.edge_count; ++e)
    edges += norm(sub(rest(m_.topo.edge_nodes[2 * e]), rest(m_.topo.edge_nodes[2 * e + 1])));
  radius_ = std::max(options_.radius, m_.topo.edge_count > 0 ? 0.5 * edges / m_.topo.edge_count : 0.0);
  build_grid();
  build_border();
  // The pieces (faces joined through nodes), for keeping a loaded crack's piece to itself.
  std::vector<index_t> parent(nodes);
  for (index_t n = 0; n < nodes; ++n) parent[n] = n;
  const auto find = [&](index_t n) {
    while (parent[n] != n) n = parent[n] = parent[parent[n]];
    return n;
  };
  for (index_t f = 0; f < faces; ++f)
    for (int k = 1; k < 3; ++k) {
      const index_t a = find(m_.face_nodes[3 * f]), b = find(m_.face_nodes[3 * f + k]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  node_piece_.resize(nodes);
  for (index_t n = 0; n < nodes; ++n) node_piece_[n] = find(n);
}

CrackField::Vec3 CrackField::rest(index_t n) const {
  return {m_.node_rest[3 * n], m_.node_rest[3 * n + 1], m_.node_rest[3 * n + 2]};
}

void CrackField::build_grid() {
  cell_ = radius_;
  const index_t faces = m_.topo.face_count;
  std::vector<std::pair<std::int64_t, index_t>> keyed(faces);
  for (index_t f = 0; f < faces; ++f) {
    std::int64_t key = 0;
    for (int a = 0; a < 3; ++a)
      key = key * (std::int64_t(1) << 21) + ((static_cast<std::int64_t>(std::floor(face_centroid_[f][a] / cell_)) +
                                               (std::int64_t(1) << 20)) & ((std::int64_t(1) << 21) - 1));
    keyed[f] = {key, f};
  }
  std::sort(keyed.begin(), keyed.end());
  cell_key_.resize(faces);
  cell_face_.resize(faces);
  for (index_t i = 0; i < faces; ++i) {
    cell_key_[i] = keyed[i].first;
    cell_face_[i] = keyed[i].second;
  }
}

template <class F>
void CrackField::faces_near(const Vec3& p, double r, F&& f) const {
  std::int64_t lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = static_cast<std::int64_t>(std::floor((p[a] - r) / cell_));
    hi[a] = static_cast<std::int64_t>(std::floor((p[a] + r) / cell_));
  }
  const auto wrap = [](std::int64_t v) { return (v + (std::int64_t(1) << 20)) & ((std::int64_t(1) << 21) - 1); };
  for (std::int64_t x = lo[0]; x <= hi[0]; ++x)
    for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
      for (std::int64_t z = lo[2]; z <= hi[2]; ++z) {
        const std::int64_t key = (wrap(x) << 42) + (wrap(y) << 21) + wrap(z);
        auto range = std::equal_range(cell_key_.begin(), cell_key_.end(), key);
        for (auto it = range.first; it != range.second; ++it) {
          const index_t g = cell_face_[it - cell_key_.begin()];
          if (norm(sub(face_centroid_[g], p)) <= r) f(g);
        }
      }
}

void CrackField::build_border() {
  const index_t nodes = m_.topo.node_count, faces = m_.topo.face_count;
  border_next_.assign(nodes, -1);
  border_prev_.assign(nodes, -1);
  border_torn_.assign(nodes, 0);
  for (index_t f = 0; f < faces; ++f)
    for (int k = 0; k < 3; ++k) {
      const index_t e = m_.topo.face_edges[3 * f + k];
      if (m_.topo.edge_faces[2 * e + 1] >= 0) continue;
      const index_t a = m_.face_nodes[3 * f + (k + 1) % 3], b = m_.face_nodes[3 * f + (k + 2) % 3];
      border_next_[a] = b;
      border_prev_[b] = a;
      border_torn_[a] = m_.corner_torn.empty() ? 1 : m_.corner_torn[3 * f + (k + 1) % 3];
      border_edges_.push_back(e);
    }
  std::sort(border_edges_.begin(), border_edges_.end());
  for (index_t n = 0; n < nodes; ++n)
    if (border_next_[n] >= 0 && border_prev_[n] >= 0 && node_angle_[n] > 1.5 * pi) tips_.push_back(n);
  // Seams: inner edges whose two faces give a shared node different UVs.
  edge_seam_.assign(m_.topo.edge_count, 0);
  if (m_.corner_uv.empty() || options_.seam_strength == 1) return;
  const auto uv_of = [&](index_t f, index_t n, double* uv) {
    for (int k = 0; k < 3; ++k)
      if (m_.face_nodes[3 * f + k] == n) {
        uv[0] = m_.corner_uv[6 * f + 2 * k];
        uv[1] = m_.corner_uv[6 * f + 2 * k + 1];
      }
  };
  for (index_t e = 0; e < m_.topo.edge_count; ++e) {
    const index_t f = m_.topo.edge_faces[2 * e], g = m_.topo.edge_faces[2 * e + 1];
    if (g < 0) continue;
    for (int j = 0; j < 2; ++j) {
      const index_t n = m_.topo.edge_nodes[2 * e + j];
      double a[2] = {0, 0}, b[2] = {0, 0};
      uv_of(f, n, a);
      uv_of(g, n, b);
      if (std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) > 1e-6) edge_seam_[e] = 1;
    }
  }
}

std::vector<double> CrackField::face_tensors(const std::vector<float>& node_pos) const {
  const index_t faces = m_.topo.face_count;
  std::vector<double> T(6 * std::size_t(faces), 0.0);
  for (index_t f = 0; f < faces; ++f) {
    Vec3 X[3], x[3];
    for (int k = 0; k < 3; ++k) {
      const index_t n = m_.face_nodes[3 * f + k];
      X[k] = rest(n);
      x[k] = {node_pos[3 * n], node_pos[3 * n + 1], node_pos[3 * n + 2]};
    }
    const Vec3 E1 = sub(X[1], X[0]), E2 = sub(X[2], X[0]), e1 = sub(x[1], x[0]), e2 = sub(x[2], x[0]);
    const double l1 = norm(E1);
    if (!(l1 > 0)) continue;
    const Vec3 u = scale(E1, 1 / l1);
    const double a = dot(E2, u);
    const Vec3 w = sub(E2, scale(u, a));
    const double h = norm(w);
    if (!(h > 1e-12 * l1)) continue;
    const Vec3 v = scale(w, 1 / h);
    const Vec3 f1 = scale(e1, 1 / l1), f2 = scale(sub(e2, scale(e1, a / l1)), 1 / h);
    const double c11 = dot(f1, f1), c12 = dot(f1, f2), c22 = dot(f2, f2);
    double* t = &T[6 * std::size_t(f)];
    const int I[6] = {0, 1, 2, 0, 0, 1}, J[6] = {0, 1, 2, 1, 2, 2};
    for (int s = 0; s < 6; ++s)
      t[s] = c11 * u[I[s]] * u[J[s]] + c22 * v[I[s]] * v[J[s]] + c12 * (u[I[s]] * v[J[s]] + v[I[s]] * u[J[s]]);
  }
  return T;
}

void CrackField::smoothed(const Vec3& p, const std::vector<double>& T, double* S, double* strength) const {
  double r = radius_;
  for (int attempt = 0; attempt < 4; ++attempt, r *= 2) {
    double area = 0, s = 0, sum[6] = {0, 0, 0, 0, 0, 0};
    faces_near(p, r, [&](index_t f) {
      const double A = face_area_[f];
      area += A;
      s += A * (m_.face_strength.empty() ? 1.0 : m_.face_strength[f]);
      for (int k = 0; k < 6; ++k) sum[k] += A * T[6 * std::size_t(f) + k];
    });
    if (area > 0) {
      for (int k = 0; k < 6; ++k) S[k] = sum[k] / area;
      *strength = s / area;
      return;
    }
  }
  for (int k = 0; k < 6; ++k) S[k] = 0;
  *strength = 1;
}

CrackField::Vec3 CrackField::thread_direction(index_t f, double du, double dv) const {
  // The rest-space direction of UV direction (du, dv) in face f: E = J * U, J = E * U^-1.
  const float* uv = &m_.corner_uv[6 * std::size_t(f)];
  const double u1 = uv[2] - uv[0], v1 = uv[3] - uv[1], u2 = uv[4] - uv[0], v2 = uv[5] - uv[1];
  const double det = u1 * v2 - u2 * v1;
  if (!(std::abs(det) > 1e-300)) return {0, 0, 0};
  const Vec3 X0 = rest(m_.face_nodes[3 * f]);
  const Vec3 E1 = sub(rest(m_.face_nodes[3 * f + 1]), X0), E2 = sub(rest(m_.face_nodes[3 * f + 2]), X0);
  // U^-1 (du, dv): the coefficients of E1 and E2.
  const double a = (v2 * du - u2 * dv) / det, b = (-v1 * du + u1 * dv) / det;
  return unit(add(scale(E1, a), scale(E2, b)));
}

bool CrackField::nearest_border(const Vec3& p, const Vec3* d, double reach, index_t from, Vec3& point,
                                index_t& edge) const {
  // The border right at `from` (the flanks of its own slit, half a radius each way) is left out;
  // the rest of its slit lies behind it, which the test "ahead along d" leaves out.
  std::vector<index_t> own;
  if (from >= 0) {
    own.push_back(from);
    for (const auto* step : {&border_next_, &border_prev_}) {
      double walked = 0;
      index_t n = from;
      for (index_t i = 0; i < m_.topo.node_count && walked < 0.5 * options_.radius; ++i) {
        const index_t next = (*step)[n];
        if (next < 0 || next == from) break;
        walked += norm(sub(rest(next), rest(n)));
        n = next;
        own.push_back(n);
      }
    }
    std::sort(own.begin(), own.end());
  }
  const auto is_own = [&](index_t n) { return std::binary_search(own.begin(), own.end(), n); };
  double best = reach;
  bool found = false;
  for (index_t e : border_edges_) {
    const index_t a = m_.topo.edge_nodes[2 * e], b = m_.topo.edge_nodes[2 * e + 1];
    if (is_own(a) && is_own(b)) continue;
    const Vec3 A = rest(a), B = rest(b), AB = sub(B, A);
    const double t = std::max(0.0, std::min(1.0, dot(sub(p, A), AB) / std::max(dot(AB, AB), 1e-300)));
    const Vec3 q = add(A, scale(AB, t));
    const double dist = norm(sub(q, p));
    if (d && dot(sub(q, p), *d) < 0.25 * dist) continue;
    if (dist < best || (dist == best && found && e < edge)) {
      best = dist;
      point = q;
      edge = e;
      found = true;
    }
  }
  return found;
}

double CrackField::piece_cut_off(index_t tip, const Vec3& point, index_t edge) const {
  const index_t a = m_.topo.edge_nodes[2 * edge], b = m_.topo.edge_nodes[2 * edge + 1];
  // The side from `tip` along the border to the edge, closed through `point`; then the other side.
  const auto side = [&](index_t from, index_t until_a, index_t until_b, bool starts_at_point) {
    Vec3 sum{0, 0, 0};
    std::vector<Vec3> poly;
    if (starts_at_point) poly.push_back(point);
    index_t n = from;
    for (index_t i = 0; i <= m_.topo.node_count; ++i) {
      poly.push_back(rest(n));
      if (n == until_a || n == until_b) break;
      n = border_next_[n];
      if (n < 0 || (n == from && i > 0)) return -1.0;  // another loop: nothing is cut off
    }
    if (!starts_at_point) poly.push_back(point);
    for (std::size_t i = 0; i < poly.size(); ++i) sum = add(sum, cross(poly[i], poly[(i + 1) % poly.size()]));
    return 0.5 * norm(sum);
  };
  const double one = side(tip, a, b, false);
  if (one < 0) return std::numeric_limits<double>::infinity();
  // The other side starts after the edge (at whichever of its nodes follows the other on the border).
  const index_t after = border_next_[a] == b ? b : a;
  const double two = side(after, tip, tip, true);
  if (two < 0) return std::numeric_limits<double>::infinity();
  return std::min(one, two);
}

bool CrackField::advance(const Tip& tip, const std::vector<double>& T, std::vector<Vec3>& path, bool& joined,
                         double& ratio) const {
  // The disc lies ahead of the tip, where the crack would run: centred on the tip it would average
  // in the unloaded flanks of its own slit.
  double S[6], strength = 1;
  smoothed(add(tip.at, scale(tip.forward, 0.5 * options_.radius)), T, S, &strength);
  const double limit = options_.stretch * strength;
  // The candidate directions: across the principal direction, or along the warp or the weft, or
  // along a seam from the tip; the one whose opening stretch passes its limit by most.
  Vec3 d{0, 0, 0};
  double best = 0;
  std::vector<Vec3> seam_path;
  const auto consider = [&](Vec3 dir, double stretch_across, double lim) {
    if (dot(dir, tip.forward) < 0) dir = scale(dir, -1);
    const double ratio = std::sqrt(std::max(stretch_across, 0.0)) / lim;
    if (ratio > best) {
      best = ratio;
      d = dir;
      return true;
    }
    return false;
  };
  if (options_.has_weave && !m_.corner_uv.empty()) {
    const index_t f = m_.topo.node_faces[m_.topo.node_face_offset[tip.node]];
    const auto& w = options_.weave.warp;
    const Vec3 warp = unit(in_plane(thread_direction(f, w[0], w[1]), tip.normal));
    const Vec3 weft = unit(in_plane(thread_direction(f, -w[1], w[0]), tip.normal));
    // A crack keeps to the thread it runs along unless the other one opens by a tenth more:
    // woven cloth tears along one thread, not in a staircase of both.
    const double keep_warp = std::abs(dot(warp, tip.forward)) >= std::abs(dot(weft, tip.forward)) ? 1.1 : 1.0;
    consider(warp, keep_warp * keep_warp * quad(S, cross(tip.normal, warp)), limit);
    consider(weft, (2.21 - keep_warp * keep_warp) * quad(S, cross(tip.normal, weft)), limit * options_.weave.weft_strength);
  } else {
    Vec3 r;
    const double lambda = principal(S, tip.normal, r);
    // Across the principal direction, turned halfway to the crack's own course: a crack
    // keeps its course against the noise of a coarse mesh and still turns where the stress does.
    Vec3 across = unit(cross(tip.normal, r));
    if (dot(across, tip.forward) < 0) across = scale(across, -1);
    consider(unit(add(across, tip.forward)), lambda, limit);
  }
  // Along a seam edge that leaves the tip forwards.
  for (index_t i = m_.topo.node_face_offset[tip.node]; i < m_.topo.node_face_offset[tip.node + 1]; ++i) {
    const index_t f = m_.topo.node_faces[i];
    for (int k = 0; k < 3; ++k) {
      const index_t e = m_.topo.face_edges[3 * f + k];
      if (!edge_seam_[e]) continue;
      const index_t a = m_.topo.edge_nodes[2 * e], b = m_.topo.edge_nodes[2 * e + 1];
      if (a != tip.node && b != tip.node) continue;
      const index_t other = a == tip.node ? b : a;
      const Vec3 dir = unit(in_plane(sub(rest(other), tip.at), tip.normal));
      if (dot(dir, tip.forward) < 0.5) continue;
      if (consider(dir, quad(S, cross(tip.normal, dir)), limit * options_.seam_strength))
        seam_path = {tip.at, rest(other)};
    }
  }
  if (std::getenv("TEAR_DEBUG_CRACKS"))
    std::fprintf(stderr, "tip %d at (%.4f %.4f %.4f) fwd (%.3f %.3f %.3f) d (%.3f %.3f %.3f) ratio %.4f\n", tip.node,
                 tip.at[0], tip.at[1], tip.at[2], tip.forward[0], tip.forward[1], tip.forward[2], d[0], d[1], d[2], best);
  ratio = best;
  if (best <= 1) return false;
  // At least past the faces around the tip, so the cut crosses an edge at any resolution.
  double longest = 0;
  for (index_t i = m_.topo.node_face_offset[tip.node]; i < m_.topo.node_face_offset[tip.node + 1]; ++i) {
    const index_t f = m_.topo.node_faces[i];
    for (int k = 0; k < 3; ++k) longest = std::max(longest, norm(sub(rest(m_.face_nodes[3 * f + k]), tip.at)));
  }
  const double step = std::max(options_.step_m(), 1.5 * longest);
  const bool on_seam = !seam_path.empty() && dot(unit(sub(seam_path[1], seam_path[0])), d) > 0.999999;
  const Vec3 q = on_seam ? seam_path[1] : add(tip.course, scale(d, step));
  // Within `radius` of another crack or the border: join it the shortest way, unless that cuts off
  // a piece under `min_piece`.
  Vec3 b;
  index_t edge = -1;
  if (nearest_border(q, &d, std::max(options_.radius, step), tip.node, b, edge) ||
      nearest_border(tip.at, &d, std::max(options_.radius, step), tip.node, b, edge)) {
    if (piece_cut_off(tip.node, b, edge) < options_.min_piece_m2()) {
      ratio = 0;  // held: it cannot run on without cutting off a shred
      return false;
    }
    const Vec3 dir = unit(sub(b, tip.at));
    path = {tip.at, add(b, scale(dir, 0.02 * longest))};  // just across: the far flank of a slit is there too
    joined = true;
    return true;
  }
  path = {tip.at, q};
  joined = false;
  return true;
}

bool CrackField::start(const std::vector<double>& T, const std::vector<double>& stretch,
                       const std::vector<index_t>& loaded, std::vector<Vec3>& path) const {
  const auto is_loaded = [&](index_t node) {
    return std::binary_search(loaded.begin(), loaded.end(), node_piece_[node]);
  };
  const index_t faces = m_.topo.face_count;
  const double start_limit = options_.start_stretch();
  std::vector<std::pair<double, index_t>> candidates;
  for (index_t f = 0; f < faces; ++f) {
    const double s = m_.face_strength.empty() ? 1.0 : m_.face_strength[f];
    if (stretch[f] > start_limit * s && !is_loaded(m_.face_nodes[3 * f])) candidates.push_back({-stretch[f] / s, f});
  }
  // The most stretched face of each grid cell (a disc's size) is a candidate: every stretched
  // region gets a say, not only the sharpest corners of a jagged border.
  std::sort(candidates.begin(), candidates.end());
  {
    std::vector<std::int64_t> seen;
    std::vector<std::pair<double, index_t>> kept;
    for (const auto& c : candidates) {
      const Vec3& p = face_centroid_[c.second];
      std::int64_t key = 0;
      for (int a = 0; a < 3; ++a) key = key * 2097152 + (static_cast<std::int64_t>(std::floor(p[a] / cell_)) & 2097151);
      const auto at = std::lower_bound(seen.begin(), seen.end(), key);
      if (at != seen.end() && *at == key) continue;
      seen.insert(at, key);
      kept.push_back(c);
    }
    candidates.swap(kept);
  }
  // Away from the cracks made so far, and well away from their tips: the cloth ahead of a tip is
  // the tip's to tear, even while it waits for the stress to build up again after a step.
  const auto near_crack = [&](const Vec3& p) {
    for (index_t t : tips_)
      if (norm(sub(rest(t), p)) < 4 * options_.radius) return true;
    for (index_t e : border_edges_) {
      const index_t f = m_.topo.edge_faces[2 * e];
      const index_t k = m_.topo.face_edges[3 * f] == e ? 0 : m_.topo.face_edges[3 * f + 1] == e ? 1 : 2;
      if (!m_.corner_torn.empty() && !m_.corner_torn[3 * f + (k + 1) % 3]) continue;
      const Vec3 A = rest(m_.topo.edge_nodes[2 * e]), B = rest(m_.topo.edge_nodes[2 * e + 1]);
      if (std::min(norm(sub(A, p)), norm(sub(B, p))) < options_.radius) return true;
    }
    return false;
  };
  double best = 1;
  index_t chosen = -1;
  Vec3 across{0, 0, 0};
  for (const auto& c : candidates) {
    const index_t f = c.second;
    const Vec3& p = face_centroid_[f];
    if (near_crack(p)) continue;
    double S[6], strength = 1;
    smoothed(p, T, S, &strength);
    Vec3 r;
    const double ratio = std::sqrt(std::max(principal(S, face_normal_[f], r), 0.0)) / (start_limit * strength);
    if (ratio > best) {
      best = ratio;
      chosen = f;
      across = unit(cross(face_normal_[f], r));
    }
  }
  // A seam that reaches the border opens from there at its own limit.
  index_t seam_node = -1, seam_other = -1;
  for (index_t e = 0; e < m_.topo.edge_count && options_.seam_strength != 1; ++e) {
    if (!edge_seam_[e]) continue;
    for (int j = 0; j < 2; ++j) {
      const index_t n = m_.topo.edge_nodes[2 * e + j], other = m_.topo.edge_nodes[2 * e + 1 - j];
      if (border_next_[n] < 0 || border_next_[other] >= 0 || is_loaded(n)) continue;  // from the border inwards
      const Vec3 p = rest(n);
      if (near_crack(p)) continue;
      const index_t f = m_.topo.edge_faces[2 * e];
      const Vec3 along = unit(in_plane(sub(rest(other), p), face_normal_[f]));
      double S[6], strength = 1;
      smoothed(p, T, S, &strength);
      const double ratio = std::sqrt(std::max(quad(S, cross(face_normal_[f], along)), 0.0)) /
                           (start_limit * strength * options_.seam_strength);
      if (ratio > best) {
        best = ratio;
        seam_node = n;
        seam_other = other;
      }
    }
  }
  if (seam_node >= 0) {
    const Vec3 a = rest(seam_node), b = rest(seam_other);
    path = {sub(a, scale(sub(b, a), 0.1)), b};
    return true;
  }
  if (chosen < 0) return false;
  if (std::getenv("TEAR_DEBUG_CRACKS"))
    std::fprintf(stderr, "start at face %d (%.4f %.4f %.4f) across (%.3f %.3f %.3f) ratio %.4f\n", chosen,
                 face_centroid_[chosen][0], face_centroid_[chosen][1], face_centroid_[chosen][2], across[0], across[1],
                 across[2], best);
  const Vec3 p = face_centroid_[chosen];
  double size = 0;
  for (int k = 0; k < 3; ++k) size = std::max(size, norm(sub(rest(m_.face_nodes[3 * chosen + k]), p)));
  // An interior crack opens only where a crossing has a cut line on both sides: three crossings at
  // least, so the slit is some four faces long at any resolution.
  const double step = std::max(options_.step_m(), 7 * size);
  Vec3 b;
  index_t edge = -1;
  if (nearest_border(p, nullptr, options_.radius, -1, b, edge)) {
    const Vec3 inward = unit(sub(p, b));
    if (std::abs(dot(across, inward)) > 0.3) {
      const Vec3 d = dot(across, inward) > 0 ? across : scale(across, -1);
      path = {sub(b, scale(d, size)), add(b, scale(d, step))};
      return true;
    }
  }
  path = {sub(p, scale(across, step / 2)), add(p, scale(across, step / 2))};
  return true;
}

CrackPlan CrackField::plan(const std::vector<float>& node_pos) const {
  CrackPlan plan;
  const std::vector<double> T = face_tensors(node_pos);
  std::vector<std::vector<Vec3>> paths;
  std::vector<index_t> loaded;  // pieces with a tip free to run that bears most of its limit
  for (index_t n : tips_) {
    if (static_cast<int>(paths.size()) >= options_.max_faces_per_step) break;
    Tip tip{n, rest(n), {0, 0, 0}, {0, 0, 0}, rest(n)};
    Vec3 normal{0, 0, 0};
    for (index_t i = m_.topo.node_face_offset[n]; i < m_.topo.node_face_offset[n + 1]; ++i) {
      const index_t f = m_.topo.node_faces[i];
      normal = add(normal, scale(face_normal_[f], face_area_[f]));
    }
    tip.normal = unit(normal);
    // The crack's course: the line fitted through its slit over four radii back along both flanks,
    // not its last edge. Snapping moves each tip off the line by a fraction of an edge; aiming the
    // next step from the line keeps those offsets from adding up.
    std::vector<Vec3> slit{tip.at};
    Vec3 back{0, 0, 0};
    for (const auto* walk : {&border_prev_, &border_next_}) {
      index_t m = n;
      double walked = 0;
      for (index_t i = 0; i < m_.topo.node_count && walked < 4 * radius_; ++i) {
        const index_t next = (*walk)[m];
        if (next < 0 || next == n) break;
        // Along the slit only: the cloth's own border beyond it is not the crack's course.
        if (!border_torn_[walk == &border_next_ ? m : next]) break;
        const bool near = walked < radius_;
        walked += norm(sub(rest(next), rest(m)));
        m = next;
        slit.push_back(rest(m));
        if (near) back = add(back, unit(sub(rest(m), tip.at)));
      }
    }
    Vec3 centre{0, 0, 0};
    for (const Vec3& p : slit) centre = add(centre, scale(p, 1.0 / slit.size()));
    const Vec3 b1 = any_tangent(tip.normal), b2 = cross(tip.normal, b1);
    double c11 = 0, c12 = 0, c22 = 0;
    for (const Vec3& p : slit) {
      const Vec3 q = sub(p, centre);
      c11 += dot(q, b1) * dot(q, b1), c12 += dot(q, b1) * dot(q, b2), c22 += dot(q, b2) * dot(q, b2);
    }
    const double half = 0.5 * (c11 - c22), lambda = 0.5 * (c11 + c22) + std::sqrt(half * half + c12 * c12);
    Vec3 line = std::abs(lambda - c22) + std::abs(c12) > 1e-300 ? unit(add(scale(b1, lambda - c22), scale(b2, c12)))
                                                                 : unit(in_plane(scale(back, -1), tip.normal));
    if (dot(line, back) > 0) line = scale(line, -1);
    tip.course = add(centre, scale(line, dot(sub(tip.at, centre), line)));
    if (norm(sub(tip.course, tip.at)) > 0.5 * radius_) tip.course = tip.at;  // a kinked slit: no line
    back = scale(line, -1);
    tip.forward = unit(scale(in_plane(back, tip.normal), -1));
    if (norm(tip.forward) == 0) continue;
    std::vector<Vec3> path;
    bool joined = false;
    double ratio = 0;
    const bool moves = advance(tip, T, path, joined, ratio);
    if (ratio > 0.6) loaded.push_back(node_piece_[n]);
    if (!moves) continue;
    // Two cracks of one substep that come near each other could cut off what neither would alone:
    // the later waits for the next substep, when it sees the first as a crack.
    bool clear = true;
    for (const auto& other : paths)
      clear = clear && segment_distance(path.front(), path.back(), other.front(), other.back()) >= options_.radius;
    if (clear) paths.push_back(std::move(path));
  }
  std::sort(loaded.begin(), loaded.end());
  {
    // A new crack only in a piece whose cracks bear little load: a loaded crack runs through its
    // piece and takes the load off it; a second crack there would break it twice, or cut a sliver
    // between the two.
    std::vector<double> stretch(m_.topo.face_count);
    for (index_t f = 0; f < m_.topo.face_count; ++f) {
      Vec3 r;
      stretch[f] = std::sqrt(std::max(principal(&T[6 * std::size_t(f)], face_normal_[f], r), 0.0));
    }
    std::vector<Vec3> path;
    if (paths.empty() && start(T, stretch, loaded, path)) paths.push_back(std::move(path));
  }
  for (const auto& path : paths) {
    // A straight rest-space cut in the plane of its start, projected along that plane's normal.
    const Vec3 d = unit(sub(path.back(), path.front()));
    Vec3 normal{0, 0, 0};
    faces_near(path.front(), options_.radius, [&](index_t f) { normal = add(normal, scale(face_normal_[f], face_area_[f])); });
    normal = unit(in_plane(normal, d));
    if (norm(normal) == 0) normal = any_tangent(d);
    const Vec3 v = cross(normal, d);
    CutLine line;
    line.source = CutLine::Source::node_rest;
    line.axis_u = d;
    line.axis_v = v;
    for (const Vec3& p : path) line.polyline.push_back({dot(p, d), dot(p, v)});
    for (std::size_t i = 1; i < path.size(); ++i) plan.length += norm(sub(path[i], path[i - 1]));
    plan.cuts.push_back(std::move(line));
    ++plan.events;
  }
  return plan;
}

}  // namespace tear
