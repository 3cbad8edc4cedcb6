#include "tear/diff_meshes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

namespace tear {

namespace {

/// |a - b|, with NaN equal to NaN and NaN against a number infinitely far.
double distance(double a, double b) {
  if (std::isnan(a) || std::isnan(b))
    return std::isnan(a) && std::isnan(b) ? 0.0 : std::numeric_limits<double>::infinity();
  if (a == b) return 0.0;  // also inf == inf
  return std::fabs(a - b);
}

std::string number(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", x);
  return buffer;
}

/// A face rotated to start at its smallest node, orientation kept; `rotation` is the corner of the
/// original face that became corner 0.
struct CanonicalFace {
  std::array<index_t, 3> nodes;
  int rotation;
  index_t face;
};

std::vector<CanonicalFace> canonical_faces(const Mesh& mesh) {
  std::vector<CanonicalFace> faces(static_cast<std::size_t>(mesh.face_count()));
  for (index_t f = 0; f < mesh.face_count(); ++f) {
    const index_t* n = &mesh.face_nodes[3 * static_cast<std::size_t>(f)];
    int r = 0;
    if (n[1] < n[r]) r = 1;
    if (n[2] < n[r]) r = 2;
    faces[f] = {{n[r], n[(r + 1) % 3], n[(r + 2) % 3]}, r, f};
  }
  std::sort(faces.begin(), faces.end(), [](const CanonicalFace& x, const CanonicalFace& y) {
    return std::tie(x.nodes, x.face) < std::tie(y.nodes, y.face);
  });
  return faces;
}

/// Keeps the first difference in the order (kind, element, corner, component).
void keep_first(Difference& first, const Difference& d) {
  if (first.kind == DiffKind::None || std::make_tuple(d.kind, d.element, d.corner, d.component) <
                                          std::make_tuple(first.kind, first.element, first.corner, first.component))
    first = d;
}

/// Compares per-element values of `width` components; records the largest difference and any
/// beyond `tolerance`.
void compare_values(const std::vector<float>& a, const std::vector<float>& b, std::size_t ia, std::size_t ib, int width,
                    double tolerance, Difference d, double& max, Difference& first) {
  for (int k = 0; k < width; ++k) {
    const double va = a[ia * width + k], vb = b[ib * width + k];
    const double by = distance(va, vb);
    max = std::max(max, by);
    if (by > tolerance) {
      d.component = k;
      d.value_a = va;
      d.value_b = vb;
      d.by = by;
      keep_first(first, d);
    }
  }
}

}  // namespace

const char* to_string(DiffKind kind) {
  switch (kind) {
    case DiffKind::None:
      return "none";
    case DiffKind::NodeCount:
      return "node count";
    case DiffKind::FaceCount:
      return "face count";
    case DiffKind::Face:
      return "face";
    case DiffKind::Position:
      return "position";
    case DiffKind::Velocity:
      return "velocity";
    case DiffKind::Uv:
      return "uv";
    case DiffKind::Normal:
      return "normal";
  }
  return "unknown";
}

std::string Difference::describe() const {
  static const char* const xyz[] = {"x", "y", "z"};
  static const char* const uv[] = {"u", "v"};
  const std::string values = number(value_a) + " vs " + number(value_b) + " (by " + number(by) + ")";
  switch (kind) {
    case DiffKind::None:
      return "equal";
    case DiffKind::NodeCount:
    case DiffKind::FaceCount:
      return std::string(to_string(kind)) + " " + number(value_a) + " vs " + number(value_b);
    case DiffKind::Face:
      return "face " + std::to_string(element) + " of " + (in_b ? "b" : "a") + " has no match in " + (in_b ? "a" : "b");
    case DiffKind::Position:
    case DiffKind::Velocity:
      return "node " + std::to_string(element) + " " + xyz[component] + " " + to_string(kind) + " " + values;
    case DiffKind::Uv:
    case DiffKind::Normal:
      if (element == none)
        return std::string(kind == DiffKind::Uv ? "uvs" : "normals") + " in " + (value_a != 0 ? "a" : "b") + " only";
      return "face " + std::to_string(element) + " corner " + std::to_string(corner) + " " +
             (kind == DiffKind::Uv ? uv[component] : xyz[component]) + " " + to_string(kind) + " " + values;
  }
  return "unknown difference";
}

namespace {

/// Faces of `a` and `b` on the same nodes, as pairs of canonical faces.
using MatchedFaces = std::vector<std::pair<const CanonicalFace*, const CanonicalFace*>>;

/// The node and face counts of `a` and `b`.
void compare_counts(const Mesh& a, const Mesh& b, Difference& first) {
  if (a.node_count() != b.node_count()) {
    Difference d;
    d.kind = DiffKind::NodeCount;
    d.value_a = a.node_count();
    d.value_b = b.node_count();
    d.by = std::fabs(d.value_a - d.value_b);
    keep_first(first, d);
  }
  if (a.face_count() != b.face_count()) {
    Difference d;
    d.kind = DiffKind::FaceCount;
    d.value_a = a.face_count();
    d.value_b = b.face_count();
    d.by = std::fabs(d.value_a - d.value_b);
    keep_first(first, d);
  }
}

/// Faces as sets: a merge of the two sorted canonical lists `fa` and `fb`. Matched pairs give the
/// corner map; the lowest face of either mesh that has no match is a difference.
MatchedFaces match_faces(const std::vector<CanonicalFace>& fa, const std::vector<CanonicalFace>& fb,
                         Difference& first) {
  MatchedFaces matched;
  index_t unmatched_a = none, unmatched_b = none;  // lowest unmatched face index of each
  auto note = [](index_t& lowest, index_t face) { lowest = lowest == none ? face : std::min(lowest, face); };
  for (std::size_t i = 0, j = 0; i < fa.size() || j < fb.size();) {
    if (j == fb.size() || (i < fa.size() && fa[i].nodes < fb[j].nodes)) {
      note(unmatched_a, fa[i++].face);
    } else if (i == fa.size() || fb[j].nodes < fa[i].nodes) {
      note(unmatched_b, fb[j++].face);
    } else {
      matched.emplace_back(&fa[i++], &fb[j++]);
    }
  }
  if (unmatched_a != none || unmatched_b != none) {
    Difference d;
    d.kind = DiffKind::Face;
    d.in_b = unmatched_a == none;
    d.element = d.in_b ? unmatched_b : unmatched_a;
    keep_first(first, d);
  }
  return matched;
}

/// Node values over the nodes both meshes have: positions, and velocities when both have them.
void compare_nodes(const Mesh& a, const Mesh& b, const DiffOptions& options, MeshDiff& result) {
  const std::size_t common_nodes = static_cast<std::size_t>(std::min(a.node_count(), b.node_count()));
  const bool velocities = a.has_velocities() && b.has_velocities();
  for (std::size_t n = 0; n < common_nodes; ++n) {
    Difference d;
    d.element = static_cast<index_t>(n);
    d.kind = DiffKind::Position;
    compare_values(a.node_pos, b.node_pos, n, n, 3, options.tolerance, d, result.max_position, result.first);
    if (velocities) {
      d.kind = DiffKind::Velocity;
      compare_values(a.node_vel, b.node_vel, n, n, 3, options.tolerance, d, result.max_velocity, result.first);
    }
  }
}

/// Corner values through the face matching: canonical corner k is corner (rotation + k) % 3.
void compare_corners(DiffKind kind, const std::vector<float>& va, const std::vector<float>& vb, int width,
                     const MatchedFaces& matched, double tolerance, double& max, Difference& first) {
  if (va.empty() != vb.empty()) {
    Difference d;
    d.kind = kind;
    d.value_a = va.empty() ? 0 : 1;
    d.value_b = vb.empty() ? 0 : 1;
    d.by = 1;
    keep_first(first, d);
    return;
  }
  if (va.empty()) return;
  for (const auto& pair : matched) {
    for (int k = 0; k < 3; ++k) {
      const int corner_a = (pair.first->rotation + k) % 3, corner_b = (pair.second->rotation + k) % 3;
      Difference d;
      d.kind = kind;
      d.element = pair.first->face;
      d.corner = corner_a;
      compare_values(va, vb, 3 * static_cast<std::size_t>(pair.first->face) + corner_a,
                     3 * static_cast<std::size_t>(pair.second->face) + corner_b, width, tolerance, d, max, first);
    }
  }
}

}  // namespace

MeshDiff diff_meshes(const Mesh& a, const Mesh& b, const DiffOptions& options) {
  MeshDiff result;
  compare_counts(a, b, result.first);
  const std::vector<CanonicalFace> fa = canonical_faces(a), fb = canonical_faces(b);
  const MatchedFaces matched = match_faces(fa, fb, result.first);
  compare_nodes(a, b, options, result);
  compare_corners(DiffKind::Uv, a.corner_uv, b.corner_uv, 2, matched, options.uv_tolerance, result.max_uv,
                  result.first);
  compare_corners(DiffKind::Normal, a.corner_normal, b.corner_normal, 3, matched, options.uv_tolerance,
                  result.max_normal, result.first);
  return result;
}

}  // namespace tear
