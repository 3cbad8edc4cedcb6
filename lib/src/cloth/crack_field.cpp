// tear: what crack growth knows of the rest mesh (crack_growth.h): faces' areas, normals and
// stretch tensors, the grid of faces by disc-sized cell, the smoothed tensor, the border walked
// both ways with its torn edges and seams, the nearest border point and the piece a cut would leave.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <utility>
#include <vector>
#if defined(__GLIBCXX__) && defined(_OPENMP)
#include <parallel/algorithm>
#endif

#include "cloth/crack_geometry.h"
#include "cloth/crack_growth.h"
#include "tear/error.h"
#include "tear_cracks.h"

namespace tear {

using namespace crack;

namespace {

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

}  // namespace

float StrengthMap::at(double u, double v) const {
  if (width <= 0 || height <= 0 || !std::isfinite(u) || !std::isfinite(v)) return 1.f;
  // Texel (i, j) has its centre at u = (i + 0.5) / width, v = 1 - (j + 0.5) / height.
  const double x = (u - std::floor(u)) * width - 0.5, y = (1 - (v - std::floor(v))) * height - 0.5;
  const double x0 = std::floor(x), y0 = std::floor(y);
  const double fx = x - x0, fy = y - y0;
  const auto texel = [&](double i, double j) {
    const long long ii = (static_cast<long long>(i) % width + width) % width;
    const long long jj = (static_cast<long long>(j) % height + height) % height;
    return static_cast<double>(value[static_cast<std::size_t>(jj * width + ii)]);
  };
  const double top = texel(x0, y0) * (1 - fx) + texel(x0 + 1, y0) * fx;
  const double bottom = texel(x0, y0 + 1) * (1 - fx) + texel(x0 + 1, y0 + 1) * fx;
  return static_cast<float>(top * (1 - fy) + bottom * fy);
}

std::vector<float> face_strength_field(const std::vector<float>& node_rest, const std::vector<index_t>& face_nodes,
                                       const std::vector<float>& corner_uv, const TearingOptions& options,
                                       const std::string& script) {
  const std::size_t faces = face_nodes.size() / 3;
  std::vector<float> strength(faces, 1.f);
  const StrengthMap* map = options.strength_map.get();
  if (map && corner_uv.size() != 6 * faces)
    throw input_error(script, "simulation.tearing.strength_map: the map is laid out in UV space, and the mesh has no UVs");
  for (std::size_t f = 0; f < faces; ++f) {
    double factor = 1;
    if (options.variation > 0) {
      Vec3 c{0, 0, 0};
      for (int k = 0; k < 3; ++k)
        for (int d = 0; d < 3; ++d) c[d] += node_rest[3 * face_nodes[3 * f + k] + d] / 3.0;
      factor = 1 + options.variation * value_noise(scale(c, 1 / options.radius), options.seed);
    }
    if (map) {
      // At the face's UV centroid: a face spans a few texels at most on a cloth meshed for tearing.
      const float* uv = &corner_uv[6 * f];
      factor *= map->at((uv[0] + uv[2] + uv[4]) / 3.0, (uv[1] + uv[3] + uv[5]) / 3.0);
    }
    strength[f] = static_cast<float>(factor);
  }
  if (map) {
    // A limit at or under 1 tears the cloth at rest (the parser checks the other factors alone).
    const double k = std::min({1.0, options.seam_strength, options.has_weave ? options.weave.weft_strength : 1.0});
    const double weakest = faces ? *std::min_element(strength.begin(), strength.end()) : 1.0;
    if (!(options.stretch * weakest * k > 1)) {
      char line[200];
      std::snprintf(line, sizeof line, "the weakest face's strength, %.4g, times stretch (%.4g)%s is %.4g: at or under 1, "
                    "the cloth would tear at rest (a map value v needs v * stretch over 1)", weakest, options.stretch,
                    k < 1 ? " and the seam or weft factor" : "", options.stretch * weakest * k);
      throw input_error(script, "simulation.tearing.strength_map: " + map->file + ": " + line);
    }
  }
  return strength;
}

CrackField::CrackField(CrackMesh mesh, const TearingOptions& options) : m_(std::move(mesh)), options_(options) {
  build();
}

CrackField::CrackField(CrackMesh mesh, const TearingOptions& options, CrackField* recycled)
    : m_(std::move(mesh)), options_(options) {
  if (recycled) reuse(*recycled);
  build();
}

void CrackField::reuse(CrackField& old) {
  // Every array the build fills, cleared: it starts as a new view's would, in memory already
  // touched.
  const auto take = [](auto& into, auto& from) {
    into = std::move(from);
    into.clear();
  };
  take(face_centroid_, old.face_centroid_);
  take(face_normal_, old.face_normal_);
  take(face_area_, old.face_area_);
  take(border_next_, old.border_next_);
  take(border_prev_, old.border_prev_);
  take(border_torn_, old.border_torn_);
  take(border_edges_, old.border_edges_);
  take(edge_seam_, old.edge_seam_);
  take(tips_, old.tips_);
  take(may_start_, old.may_start_);
  take(node_piece_, old.node_piece_);
  take(cell_key_, old.cell_key_);
  take(cell_face_, old.cell_face_);
  scratch_ = std::move(old.scratch_);  // each build assigns what it uses
}

void CrackField::build() {
  // TEAR_DEBUG_CRACK_TIMES=1: the construction's parts on standard error.
  static const bool timed = std::getenv("TEAR_DEBUG_CRACK_TIMES") != nullptr;
  using Clock = std::chrono::steady_clock;
  Clock::time_point mark = Clock::now();
  double part_ms[5] = {0, 0, 0, 0, 0};
  const auto lap = [&](int part) {
    if (!timed) return;
    const Clock::time_point now = Clock::now();
    part_ms[part] = std::chrono::duration<double, std::milli>(now - mark).count();
    mark = now;
  };
  const index_t faces = m_.topo.face_count;
  face_centroid_.resize(faces);
  face_normal_.resize(faces);
  face_area_.resize(faces);
  // Each face on its own (threads of the host), then the total in face order.
#pragma omp parallel for schedule(static)
  for (index_t f = 0; f < faces; ++f) {
    Vec3 X[3];
    for (int k = 0; k < 3; ++k) X[k] = rest(m_.face_nodes[3 * f + k]);
    face_centroid_[f] = scale(add(add(X[0], X[1]), X[2]), 1 / 3.0);
    const Vec3 n = cross(sub(X[1], X[0]), sub(X[2], X[0]));
    face_area_[f] = 0.5 * norm(n);
    face_normal_[f] = unit(n);
  }
  for (index_t f = 0; f < faces; ++f) total_area_ += face_area_[f];
  // The smoothing disc spans a face at least, so a coarse mesh still averages a neighbourhood.
  // Each edge's length on the host's threads, summed in edge order: the same sum on any number.
  std::vector<double>& length = scratch_.length;
  length.assign(m_.topo.edge_count, 0.0);
#pragma omp parallel for schedule(static)
  for (index_t e = 0; e < m_.topo.edge_count; ++e)
    length[e] = norm(sub(rest(m_.topo.edge_nodes[2 * e]), rest(m_.topo.edge_nodes[2 * e + 1])));
  double edges = 0;
  longest_edge_ = 0;
  for (const double l : length) {
    edges += l;
    longest_edge_ = std::max(longest_edge_, l);
  }
  radius_ = std::max(options_.radius, m_.topo.edge_count > 0 ? 0.5 * edges / m_.topo.edge_count : 0.0);
  // Whether a pin holds any face whole (face_held), where a crack does not run.
  any_held_ = false;
  for (index_t f = 0; f < faces && !m_.node_held.empty() && !any_held_; ++f) any_held_ = face_held(f);
  lap(0);
  build_grid();
  lap(1);
  build_border();
  lap(2);
  build_pieces();
  lap(3);
  mark_may_start();
  lap(4);
  if (timed)
    std::fprintf(stderr, "view: %d faces: faces %.3f ms, grid %.3f, border %.3f, pieces %.3f, may start %.3f\n",
                 static_cast<int>(faces), part_ms[0], part_ms[1], part_ms[2], part_ms[3], part_ms[4]);
}

void CrackField::build_pieces() {
  // The pieces (faces joined through nodes), for keeping a loaded crack's piece to itself: a
  // union of the faces' nodes on the host's threads, each union hooking the larger root under the
  // smaller by compare-and-swap (a root is hooked only while it is one), so whatever the order each
  // piece's root is its lowest node, as one thread would find it.
  const index_t nodes = m_.topo.node_count, faces = m_.topo.face_count;
  std::vector<std::atomic<index_t>> parent(static_cast<std::size_t>(nodes));
#pragma omp parallel for schedule(static)
  for (index_t n = 0; n < nodes; ++n) parent[n].store(n, std::memory_order_relaxed);
  const auto find = [&](index_t n) {
    for (;;) {
      index_t p = parent[n].load(std::memory_order_relaxed);
      if (p == n) return n;
      const index_t q = parent[p].load(std::memory_order_relaxed);
      if (q != p) parent[n].compare_exchange_weak(p, q, std::memory_order_relaxed);  // halve the path
      n = q;
    }
  };
#pragma omp parallel for schedule(static)
  for (index_t f = 0; f < faces; ++f)
    for (int k = 1; k < 3; ++k) {
      index_t a = m_.face_nodes[3 * f], b = m_.face_nodes[3 * f + k];
      for (;;) {
        a = find(a);
        b = find(b);
        if (a == b) break;
        if (a > b) std::swap(a, b);
        index_t root = b;
        if (parent[b].compare_exchange_strong(root, a, std::memory_order_relaxed)) break;
      }
    }
  node_piece_.resize(nodes);
#pragma omp parallel for schedule(static)
  for (index_t n = 0; n < nodes; ++n) node_piece_[n] = find(n);
}

CrackField::Vec3 CrackField::rest(index_t n) const {
  return {m_.node_rest[3 * n], m_.node_rest[3 * n + 1], m_.node_rest[3 * n + 2]};
}

void CrackField::build_grid() {
  cell_ = radius_;
  const index_t faces = m_.topo.face_count;
  // Each face's cell, then the faces by cell key and face: a counting sort over the box of cells
  // the faces span where it is small (a cloth's rest shape, a few cells deep), a sort of the
  // (key, face) pairs where not. The two give the same order: within 2^20 cells of the origin a
  // key orders cells as their x, y, z do (the box's order, z fastest).
  constexpr std::int64_t half = std::int64_t(1) << 20;
  std::vector<std::int64_t>& at = scratch_.at;
  at.assign(3 * std::size_t(faces), 0);
#pragma omp parallel for schedule(static)
  for (index_t f = 0; f < faces; ++f)
    for (int a = 0; a < 3; ++a)
      at[3 * std::size_t(f) + a] = static_cast<std::int64_t>(std::floor(face_centroid_[f][a] / cell_));
  const auto key_of = [&](index_t f) {
    const std::int64_t* c = &at[3 * std::size_t(f)];
    return kernels::FaceGrid::key(c[0], c[1], c[2]);
  };
  std::int64_t lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::numeric_limits<std::int64_t>::max();
    hi[a] = std::numeric_limits<std::int64_t>::min();
  }
  for (std::size_t i = 0; i < at.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], at[i]);
    hi[i % 3] = std::max(hi[i % 3], at[i]);
  }
  cell_key_.resize(faces);
  cell_face_.resize(faces);
  bool small = true;
  double cells = 1;
  for (int a = 0; a < 3; ++a) {
    small = small && lo[a] >= -half && hi[a] < half;
    cells *= static_cast<double>(hi[a] - lo[a] + 1);
  }
  if (faces > 0 && small && cells <= 4.0 * faces + 4096) {
    const std::int64_t ny = hi[1] - lo[1] + 1, nz = hi[2] - lo[2] + 1;
    const auto cell_of = [&](index_t f) {
      const std::int64_t* c = &at[3 * std::size_t(f)];
      return ((c[0] - lo[0]) * ny + (c[1] - lo[1])) * nz + (c[2] - lo[2]);
    };
    std::vector<index_t>& first = scratch_.first;
    first.assign(static_cast<std::size_t>(cells) + 1, 0);
    for (index_t f = 0; f < faces; ++f) ++first[cell_of(f) + 1];
    for (std::size_t c = 1; c < first.size(); ++c) first[c] += first[c - 1];
    for (index_t f = 0; f < faces; ++f) {
      const index_t i = first[cell_of(f)]++;
      cell_key_[i] = key_of(f);
      cell_face_[i] = f;
    }
    return;
  }
  std::vector<std::pair<std::int64_t, index_t>> keyed(faces);
#pragma omp parallel for schedule(static)
  for (index_t f = 0; f < faces; ++f) keyed[f] = {key_of(f), f};
  // The pairs are distinct (one per face): any sort orders them the same way.
#if defined(__GLIBCXX__) && defined(_OPENMP)
  __gnu_parallel::sort(keyed.begin(), keyed.end());
#else
  std::sort(keyed.begin(), keyed.end());
#endif
  for (index_t i = 0; i < faces; ++i) {
    cell_key_[i] = keyed[i].first;
    cell_face_[i] = keyed[i].second;
  }
}

bool CrackField::ends_slit(index_t n) const {
  // Between two torn border edges, a tip is where a slit's two flanks meet: its neighbours along
  // them are the two copies of one cut point, in one place in the rest shape. A corner of a torn
  // border that bends back on itself (a crack's path where its cut snapped to the faces, or where it
  // met the border) is no tip: run on from there, it would cut along the border it already has.
  const index_t prev = border_prev_[n], next = border_next_[n];
  if (!border_torn_[prev] || !border_torn_[n]) return true;  // the cloth's own border: a notch
  return norm(sub(rest(prev), rest(next))) <= 1e-6 * norm(sub(rest(prev), rest(n)));
}

void CrackField::build_border() {
  const index_t nodes = m_.topo.node_count, faces = m_.topo.face_count;
  border_next_.assign(nodes, -1);
  border_prev_.assign(nodes, -1);
  border_torn_.assign(nodes, 0);
  // The corners whose opposite edge is on the border, found on the host's threads; then walked in
  // face order, as one thread would.
  std::vector<std::uint8_t>& on_border = scratch_.on_border;
  on_border.assign(3 * std::size_t(faces), 0);
#pragma omp parallel for schedule(static)
  for (index_t c = 0; c < 3 * faces; ++c) on_border[c] = m_.topo.edge_faces[2 * m_.topo.face_edges[c] + 1] < 0;
  for (index_t f = 0; f < faces; ++f)
    for (int k = 0; k < 3; ++k) {
      if (!on_border[3 * std::size_t(f) + k]) continue;
      const index_t e = m_.topo.face_edges[3 * f + k];
      const index_t a = m_.face_nodes[3 * f + (k + 1) % 3], b = m_.face_nodes[3 * f + (k + 2) % 3];
      border_next_[a] = b;
      border_prev_[b] = a;
      border_torn_[a] = m_.corner_torn.empty() ? 1 : m_.corner_torn[3 * f + (k + 1) % 3];
      border_edges_.push_back(e);
    }
  std::sort(border_edges_.begin(), border_edges_.end());
  // The rest angle sums of the border nodes (a tip's passes 1.5π); the nodes inside need none.
  // Each border node sums its corners over its faces in ascending order (the node's faces are
  // listed so), as a walk over all faces in order would: the same sums.
  std::vector<double>& node_angle = scratch_.node_angle;
  node_angle.assign(nodes, 0.0);
#pragma omp parallel for schedule(dynamic, 256)
  for (index_t n = 0; n < nodes; ++n) {
    if (border_next_[n] < 0) continue;
    const Vec3 X = rest(n);
    for (index_t i = m_.topo.node_face_offset[n]; i < m_.topo.node_face_offset[n + 1]; ++i) {
      const index_t f = m_.topo.node_faces[i];
      if (i > m_.topo.node_face_offset[n] && m_.topo.node_faces[i - 1] == f) continue;  // one face, two corners
      for (int k = 0; k < 3; ++k) {
        if (m_.face_nodes[3 * f + k] != n) continue;
        const Vec3 a = sub(rest(m_.face_nodes[3 * f + (k + 1) % 3]), X);
        const Vec3 b = sub(rest(m_.face_nodes[3 * f + (k + 2) % 3]), X);
        const double c = dot(a, b) / std::max(norm(a) * norm(b), 1e-300);
        node_angle[n] += std::acos(std::max(-1.0, std::min(1.0, c)));
      }
    }
  }
  for (index_t n = 0; n < nodes; ++n)
    if (border_next_[n] >= 0 && border_prev_[n] >= 0 && node_angle[n] > 1.5 * pi && ends_slit(n)) tips_.push_back(n);
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

std::vector<index_t> CrackField::disc(const Vec3& p) const {
  std::vector<index_t> faces;
  double r = radius_;
  for (int attempt = 0; attempt < 4; ++attempt, r *= 2) {
    double area = 0;
    faces.clear();
    faces_near(p, r, [&](index_t f) {
      area += face_area_[f];
      faces.push_back(f);
    });
    if (area > 0) return faces;
  }
  faces.clear();
  return faces;
}

void CrackField::smoothed(const Vec3& p, const FaceTensors& T, double* S, double* strength) const {
  double area = 0, s = 0, sum[6] = {0, 0, 0, 0, 0, 0};
  for (const index_t f : disc(p)) {
    const double A = face_area_[f];
    area += A;
    s += A * (m_.face_strength.empty() ? 1.0 : m_.face_strength[f]);
    const double* t = T(f);
    for (int k = 0; k < 6; ++k) sum[k] += A * t[k];
  }
  if (area > 0) {
    for (int k = 0; k < 6; ++k) S[k] = sum[k] / area;
    *strength = s / area;
    return;
  }
  for (int k = 0; k < 6; ++k) S[k] = 0;
  *strength = 1;
}

CrackField::FaceTensors::FaceTensors(const CrackMesh& mesh, const std::vector<float>& node_pos)
    : m_(mesh),
      pos_(node_pos),
      values_(new double[6 * std::size_t(mesh.topo.face_count)]),
      ready_(static_cast<std::size_t>(mesh.topo.face_count), 0) {}

void CrackField::FaceTensors::compute(index_t f) const {
  kernels::face_stretch_tensor(m_.face_nodes.data(), m_.node_rest.data(), pos_.data(), f, &values_[6 * std::size_t(f)]);
  ready_[f] = 1;
}

void CrackField::FaceTensors::compute_all() const {
  const index_t faces = m_.topo.face_count;
#pragma omp parallel for schedule(static)
  for (index_t f = 0; f < faces; ++f)
    if (!ready_[f]) compute(f);
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

bool CrackField::on_one_border(index_t a, index_t b) const {
  index_t n = a;
  for (index_t i = 0; i < m_.topo.node_count; ++i) {
    n = border_next_[n];
    if (n < 0 || n == a) return false;
    if (n == b) return true;
  }
  return false;
}

double CrackField::piece_cut_off(index_t tip, const Vec3& point, index_t edge) const {
  const index_t a = m_.topo.edge_nodes[2 * edge], b = m_.topo.edge_nodes[2 * edge + 1];
  // The side from `tip` along the border to the edge, closed through `point`; then the other side.
  // The polygon's vector area, summed edge by edge as its corners are walked (first corner last).
  const auto side = [&](index_t from, index_t until_a, index_t until_b, bool starts_at_point) {
    Vec3 sum{0, 0, 0}, first = starts_at_point ? point : rest(from), last = first;
    const auto corner = [&](const Vec3& p) {
      sum = add(sum, cross(last, p));
      last = p;
    };
    index_t n = from;
    for (index_t i = 0; i <= m_.topo.node_count; ++i) {
      if (starts_at_point || i > 0) corner(rest(n));
      if (n == until_a || n == until_b) break;
      n = border_next_[n];
      if (n < 0 || (n == from && i > 0)) return -1.0;  // another loop: nothing is cut off
    }
    if (!starts_at_point) corner(point);
    corner(first);
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

}  // namespace tear
