#include "tear/mesh_info.h"

#include "topology/disjoint_sets.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include <nlohmann/json.hpp>

namespace tear {

namespace {


constexpr double kPi = 3.14159265358979323846;

using Vec3 = std::array<double, 3>;

Vec3 node_position(const Mesh& mesh, index_t n) {
  return {mesh.node_pos[3 * n], mesh.node_pos[3 * n + 1], mesh.node_pos[3 * n + 2]};
}
Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }

/// The criterion of validate_mesh's face_degenerate kernel, so "non-degenerate" means the same
/// thing in the report and in min_angle_deg.
bool face_degenerate(const Mesh& mesh, index_t f) {
  const index_t a = mesh.face_nodes[3 * f], b = mesh.face_nodes[3 * f + 1], c = mesh.face_nodes[3 * f + 2];
  if (a == b || b == c || c == a) return true;
  const Vec3 pa = node_position(mesh, a), u = sub(node_position(mesh, b), pa), v = sub(node_position(mesh, c), pa);
  const Vec3 w = sub(v, u), n = cross(u, v);
  const double longest = std::max({dot(u, u), dot(v, v), dot(w, w)});
  return dot(n, n) <= degenerate_area_ratio * degenerate_area_ratio * longest * longest;
}

std::int64_t count_boundary_loops(const Topology& topology) {
  DisjointSets sets(topology.node_count);
  std::vector<std::uint8_t> on_boundary(static_cast<std::size_t>(topology.node_count), 0);
  for (index_t e = 0; e < topology.edge_count; ++e) {
    if (!topology.edge_boundary[e]) continue;
    const index_t a = topology.edge_nodes[2 * e], b = topology.edge_nodes[2 * e + 1];
    on_boundary[a] = on_boundary[b] = 1;
    sets.unite(a, b);
  }
  std::int64_t loops = 0;
  for (index_t n = 0; n < topology.node_count; ++n) loops += on_boundary[n] && sets.find(n) == n;
  return loops;
}

std::int64_t count_components(const Topology& topology) {
  DisjointSets sets(topology.face_count);
  for (index_t n = 0; n < topology.node_count; ++n) {
    const index_t begin = topology.node_face_offset[n], end = topology.node_face_offset[n + 1];
    for (index_t i = begin + 1; i < end; ++i) sets.unite(topology.node_faces[begin], topology.node_faces[i]);
  }
  std::int64_t components = 0;
  for (index_t f = 0; f < topology.face_count; ++f) components += sets.find(f) == f;
  return components;
}

}  // namespace

MeshInfo compute_mesh_info(const Mesh& mesh, const Topology& topology, const MeshReport& report) {
  MeshInfo info;
  info.nodes = mesh.node_count();
  info.faces = mesh.face_count();
  info.edges = topology.edge_count;
  info.boundary_edges = std::count(topology.edge_boundary.begin(), topology.edge_boundary.end(), std::uint8_t(1));
  info.boundary_loops = count_boundary_loops(topology);
  info.components = count_components(topology);
  info.pieces = info.components;
  if (mesh.has_pieces()) {
    std::vector<index_t> ids(mesh.face_piece);
    std::sort(ids.begin(), ids.end());
    info.pieces = std::unique(ids.begin(), ids.end()) - ids.begin();
  }
  info.euler_characteristic = info.nodes - info.edges + info.faces;
  info.non_manifold_edges = report.non_manifold_edges;
  info.non_manifold_nodes = report.non_manifold_nodes;
  info.degenerate_faces = report.degenerate_faces;
  info.inconsistent_edges = report.inconsistent_edges;
  info.duplicate_faces = report.duplicate_faces;
  info.thin_faces = report.thin_faces;
  info.imprecise_faces = report.imprecise_faces;
  info.has_uv = mesh.has_uv();
  info.has_normals = mesh.has_normals();

  const double nan = std::numeric_limits<double>::quiet_NaN();
  double min_angle = nan;
  for (index_t f = 0; f < mesh.face_count(); ++f) {
    const Vec3 p[3] = {node_position(mesh, mesh.face_nodes[3 * f]), node_position(mesh, mesh.face_nodes[3 * f + 1]),
                       node_position(mesh, mesh.face_nodes[3 * f + 2])};
    info.area += 0.5 * norm(cross(sub(p[1], p[0]), sub(p[2], p[0])));
    if (face_degenerate(mesh, f)) continue;
    double face_min = 180.0;
    for (int k = 0; k < 3; ++k) {
      const Vec3 u = sub(p[(k + 1) % 3], p[k]), v = sub(p[(k + 2) % 3], p[k]);
      // atan2 of |u x v| and u.v stays accurate for angles near 0 and 180 degrees, where acos does not.
      const double angle = std::atan2(norm(cross(u, v)), dot(u, v)) * (180.0 / kPi);
      face_min = std::min(face_min, angle);
      if (std::isnan(min_angle) || angle < min_angle) min_angle = angle;
    }
    if (face_min < sliver_angle_deg) ++info.sliver_faces;
  }
  info.min_angle_deg = min_angle;

  if (mesh.node_count() == 0) {
    info.bbox_min = info.bbox_max = {nan, nan, nan};
  } else {
    info.bbox_min = info.bbox_max = node_position(mesh, 0);
    for (index_t n = 1; n < mesh.node_count(); ++n) {
      const Vec3 p = node_position(mesh, n);
      for (int d = 0; d < 3; ++d) {
        info.bbox_min[d] = std::min(info.bbox_min[d], p[d]);
        info.bbox_max[d] = std::max(info.bbox_max[d], p[d]);
      }
    }
  }
  return info;
}

std::string to_json(const MeshInfo& info) {
  auto number_or_null = [](double x) { return std::isnan(x) ? nlohmann::json(nullptr) : nlohmann::json(x); };
  auto point_or_null = [](const std::array<double, 3>& p) {
    return std::isnan(p[0]) ? nlohmann::json(nullptr) : nlohmann::json::array({p[0], p[1], p[2]});
  };
  nlohmann::json j = nlohmann::json::object();
  j["nodes"] = info.nodes;
  j["faces"] = info.faces;
  j["edges"] = info.edges;
  j["boundary_edges"] = info.boundary_edges;
  j["boundary_loops"] = info.boundary_loops;
  j["components"] = info.components;
  j["pieces"] = info.pieces;
  j["euler_characteristic"] = info.euler_characteristic;
  j["non_manifold_edges"] = info.non_manifold_edges;
  j["non_manifold_nodes"] = info.non_manifold_nodes;
  j["degenerate_faces"] = info.degenerate_faces;
  j["inconsistent_edges"] = info.inconsistent_edges;
  j["duplicate_faces"] = info.duplicate_faces;
  j["sliver_faces"] = info.sliver_faces;
  j["thin_faces"] = info.thin_faces;
  j["imprecise_faces"] = info.imprecise_faces;
  j["area"] = number_or_null(info.area);
  j["has_uv"] = info.has_uv;
  j["has_normals"] = info.has_normals;
  j["min_angle_deg"] = number_or_null(info.min_angle_deg);
  j["bbox_min"] = point_or_null(info.bbox_min);
  j["bbox_max"] = point_or_null(info.bbox_max);
  return j.dump();
}

}  // namespace tear
