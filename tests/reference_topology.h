// A plain serial reference of build_topology and validate_mesh (std::map and loops, no Thrust),
// written from the documented conventions so the device code can be checked against it.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "tear/mesh.h"
#include "tear/topology.h"
#include "tear/validate_mesh.h"

namespace tear::test {

/// Topology of `mesh` by the conventions of `tear::Topology`. Requires every index in range.
inline Topology reference_topology(const Mesh& mesh) {
  Topology t;
  t.node_count = mesh.node_count();
  t.face_count = mesh.face_count();
  const std::size_t face_count = static_cast<std::size_t>(t.face_count);

  // Undirected node pair (low, high) -> the faces of its half-edges, in face order. Local edge k
  // joins local nodes k+1 and k+2; a face repeating a node may put the same pair on two of its edges.
  std::map<std::pair<index_t, index_t>, std::vector<index_t>> pair_faces;
  auto pair_of = [&](std::size_t f, int k) {
    const index_t a = mesh.face_nodes[3 * f + (k + 1) % 3], b = mesh.face_nodes[3 * f + (k + 2) % 3];
    return std::make_pair(std::min(a, b), std::max(a, b));
  };
  for (std::size_t f = 0; f < face_count; ++f)
    for (int k = 0; k < 3; ++k) pair_faces[pair_of(f, k)].push_back(static_cast<index_t>(f));

  std::map<std::pair<index_t, index_t>, index_t> edge_of_pair;
  for (const auto& [pair, faces] : pair_faces) {
    edge_of_pair[pair] = t.edge_count++;
    t.edge_nodes.push_back(pair.first);
    t.edge_nodes.push_back(pair.second);
    t.edge_faces.push_back(faces[0]);
    t.edge_faces.push_back(faces.size() >= 2 ? faces[1] : none);
    t.edge_face_count.push_back(static_cast<index_t>(faces.size()));
    t.edge_boundary.push_back(faces.size() == 1 ? 1 : 0);
  }

  for (std::size_t f = 0; f < face_count; ++f)
    for (int k = 0; k < 3; ++k) t.face_edges.push_back(edge_of_pair.at(pair_of(f, k)));

  // One entry per corner, so a face repeating a node is listed twice at that node.
  std::vector<std::vector<index_t>> faces_of_node(static_cast<std::size_t>(t.node_count));
  for (std::size_t c = 0; c < 3 * face_count; ++c)
    faces_of_node[static_cast<std::size_t>(mesh.face_nodes[c])].push_back(static_cast<index_t>(c / 3));
  t.node_face_offset.push_back(0);
  for (auto& faces : faces_of_node) {
    std::sort(faces.begin(), faces.end());
    t.node_faces.insert(t.node_faces.end(), faces.begin(), faces.end());
    t.node_face_offset.push_back(static_cast<index_t>(t.node_faces.size()));
  }

  t.node_boundary.assign(static_cast<std::size_t>(t.node_count), 0);
  for (index_t e = 0; e < t.edge_count; ++e)
    if (t.edge_boundary[e]) {
      t.node_boundary[t.edge_nodes[2 * e]] = 1;
      t.node_boundary[t.edge_nodes[2 * e + 1]] = 1;
    }
  return t;
}

/// Counts of `check_indices`: faces with an index outside [0, node_count), nodes with a NaN or
/// infinite coordinate.
inline MeshReport reference_check_indices(const Mesh& mesh) {
  MeshReport report;
  for (index_t f = 0; f < mesh.face_count(); ++f) {
    bool bad = false;
    for (int k = 0; k < 3; ++k) {
      const index_t n = mesh.face_nodes[3 * f + k];
      bad = bad || n < 0 || n >= mesh.node_count();
    }
    report.indices_out_of_range += bad ? 1 : 0;
  }
  for (index_t n = 0; n < mesh.node_count(); ++n) {
    bool bad = false;
    for (int d = 0; d < 3; ++d) bad = bad || !std::isfinite(mesh.node_pos[3 * n + d]);
    report.non_finite_nodes += bad ? 1 : 0;
  }
  return report;
}

/// The `degenerate_area_ratio` rule: a repeated node, or (twice the area)^2 at most
/// ratio^2 * (longest edge^2)^2, in double precision.
inline bool reference_face_degenerate(const Mesh& mesh, index_t f, double ratio = degenerate_area_ratio) {
  const index_t n[3] = {mesh.face_nodes[3 * f], mesh.face_nodes[3 * f + 1], mesh.face_nodes[3 * f + 2]};
  if (n[0] == n[1] || n[1] == n[2] || n[2] == n[0]) return true;
  double p[3][3];
  for (int k = 0; k < 3; ++k)
    for (int d = 0; d < 3; ++d) p[k][d] = mesh.node_pos[3 * n[k] + d];
  double edge[3][3];
  for (int k = 0; k < 3; ++k)
    for (int d = 0; d < 3; ++d) edge[k][d] = p[(k + 2) % 3][d] - p[(k + 1) % 3][d];
  const double* u = edge[2];  // node 0 -> node 1
  double v[3];                // node 0 -> node 2
  for (int d = 0; d < 3; ++d) v[d] = -edge[1][d];
  const double cross[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  const double area2_sq = cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2];
  double longest_sq = 0;
  for (const auto& e : edge) longest_sq = std::max(longest_sq, e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
  return area2_sq <= ratio * ratio * longest_sq * longest_sq;
}

/// Whether face `f`'s height is at most `imprecise_steps` single-precision steps at its largest
/// coordinate M (a step at most M 2^-23), by its height h = twice its area over its longest edge.
inline bool reference_face_imprecise(const Mesh& mesh, index_t f) {
  double p[3][3], largest = 0;
  for (int k = 0; k < 3; ++k)
    for (int d = 0; d < 3; ++d) {
      p[k][d] = mesh.node_pos[3 * mesh.face_nodes[3 * f + k] + d];
      largest = std::max(largest, std::abs(p[k][d]));
    }
  double u[3], v[3], longest_sq = 0;
  for (int d = 0; d < 3; ++d) {
    u[d] = p[1][d] - p[0][d];
    v[d] = p[2][d] - p[0][d];
  }
  for (int k = 0; k < 3; ++k) {
    double sq = 0;
    for (int d = 0; d < 3; ++d) sq += (p[(k + 1) % 3][d] - p[k][d]) * (p[(k + 1) % 3][d] - p[k][d]);
    longest_sq = std::max(longest_sq, sq);
  }
  const double cross[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
  const double twice_area = std::sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]);
  return twice_area <= imprecise_steps * largest * std::ldexp(1.0, -23) * std::sqrt(longest_sq);
}

/// All counts of `validate_mesh`, from `reference_topology`. As the device code does, nothing past
/// the index checks when an index is out of range, and no degenerate faces judged on non-finite
/// coordinates.
inline MeshReport reference_validate_mesh(const Mesh& mesh) {
  MeshReport report = reference_check_indices(mesh);
  if (report.indices_out_of_range) return report;
  const Topology t = reference_topology(mesh);

  if (!report.non_finite_nodes)
    for (index_t f = 0; f < mesh.face_count(); ++f) {
      report.degenerate_faces += reference_face_degenerate(mesh, f) ? 1 : 0;
      report.thin_faces += !reference_face_degenerate(mesh, f) && reference_face_degenerate(mesh, f, thin_area_ratio);
      report.imprecise_faces += !reference_face_degenerate(mesh, f, thin_area_ratio) && reference_face_imprecise(mesh, f);
    }

  // Directed half-edges of each edge: half-edge 3 f + k runs from local node k+1 to local node k+2.
  std::vector<std::vector<index_t>> edge_halves(static_cast<std::size_t>(t.edge_count));
  for (index_t h = 0; h < 3 * t.face_count; ++h) edge_halves[t.face_edges[h]].push_back(h);
  auto half_start = [&](index_t h) { return mesh.face_nodes[3 * (h / 3) + (h % 3 + 1) % 3]; };
  for (index_t e = 0; e < t.edge_count; ++e) {
    const auto& halves = edge_halves[e];
    if (halves.size() > 2) ++report.non_manifold_edges;
    if (halves.size() == 2 && half_start(halves[0]) == half_start(halves[1])) ++report.inconsistent_edges;
  }

  // Faces of three distinct nodes whose node set another face has too.
  std::map<std::array<index_t, 3>, int> faces_of_nodes;
  auto sorted_nodes = [&](index_t f) {
    std::array<index_t, 3> n{mesh.face_nodes[3 * f], mesh.face_nodes[3 * f + 1], mesh.face_nodes[3 * f + 2]};
    std::sort(n.begin(), n.end());
    return n;
  };
  for (index_t f = 0; f < mesh.face_count(); ++f) ++faces_of_nodes[sorted_nodes(f)];
  for (index_t f = 0; f < mesh.face_count(); ++f) {
    const auto n = sorted_nodes(f);
    if (n[0] != n[1] && n[1] != n[2] && faces_of_nodes[n] > 1) ++report.duplicate_faces;
  }

  // A node's distinct faces, joined when they are the two faces of an edge at the node; more
  // than one group is more than one fan.
  std::vector<std::vector<index_t>> two_face_edges_of_node(static_cast<std::size_t>(t.node_count));
  for (index_t e = 0; e < t.edge_count; ++e) {
    if (t.edge_face_count[e] != 2 || t.edge_faces[2 * e] == t.edge_faces[2 * e + 1]) continue;
    two_face_edges_of_node[t.edge_nodes[2 * e]].push_back(e);
    if (t.edge_nodes[2 * e + 1] != t.edge_nodes[2 * e]) two_face_edges_of_node[t.edge_nodes[2 * e + 1]].push_back(e);
  }
  std::vector<index_t> group(static_cast<std::size_t>(t.face_count));
  std::iota(group.begin(), group.end(), 0);
  for (index_t n = 0; n < t.node_count; ++n) {
    const std::set<index_t> faces(t.node_faces.begin() + t.node_face_offset[n],
                                  t.node_faces.begin() + t.node_face_offset[n + 1]);
    for (index_t f : faces) group[f] = f;
    auto root = [&](index_t f) {
      while (group[f] != f) f = group[f];
      return f;
    };
    for (index_t e : two_face_edges_of_node[n]) group[root(t.edge_faces[2 * e])] = root(t.edge_faces[2 * e + 1]);
    std::set<index_t> roots;
    for (index_t f : faces) roots.insert(root(f));
    if (roots.size() > 1) ++report.non_manifold_nodes;
  }
  return report;
}

/// True when some face lists one node twice (a degenerate face whose fan and orientation are not
/// well defined).
inline bool has_repeated_node_face(const Mesh& mesh) {
  for (index_t f = 0; f < mesh.face_count(); ++f) {
    const index_t* n = &mesh.face_nodes[3 * static_cast<std::size_t>(f)];
    if (n[0] == n[1] || n[1] == n[2] || n[2] == n[0]) return true;
  }
  return false;
}

/// "" when the two topologies are equal, else the first array that differs, where, and how.
inline std::string topology_difference(const Topology& actual, const Topology& expected) {
  std::ostringstream out;
  auto count = [&](const char* name, index_t a, index_t b) {
    if (out.tellp() == 0 && a != b) out << name << ": " << a << " instead of " << b;
  };
  auto array = [&](const char* name, const auto& a, const auto& b) {
    if (out.tellp() != 0) return;
    if (a.size() != b.size()) {
      out << name << ": size " << a.size() << " instead of " << b.size();
      return;
    }
    for (std::size_t i = 0; i < a.size(); ++i)
      if (a[i] != b[i]) {
        out << name << "[" << i << "]: " << +a[i] << " instead of " << +b[i];
        return;
      }
  };
  count("node_count", actual.node_count, expected.node_count);
  count("face_count", actual.face_count, expected.face_count);
  count("edge_count", actual.edge_count, expected.edge_count);
  array("edge_nodes", actual.edge_nodes, expected.edge_nodes);
  array("edge_faces", actual.edge_faces, expected.edge_faces);
  array("edge_face_count", actual.edge_face_count, expected.edge_face_count);
  array("face_edges", actual.face_edges, expected.face_edges);
  array("node_face_offset", actual.node_face_offset, expected.node_face_offset);
  array("node_faces", actual.node_faces, expected.node_faces);
  array("edge_boundary", actual.edge_boundary, expected.edge_boundary);
  array("node_boundary", actual.node_boundary, expected.node_boundary);
  return out.str();
}

/// Every count of a report, named, for comparisons that print both sides.
inline std::string report_counts(const MeshReport& r) {
  std::ostringstream out;
  out << "indices_out_of_range " << r.indices_out_of_range << ", non_finite_nodes " << r.non_finite_nodes
      << ", degenerate_faces " << r.degenerate_faces << ", non_manifold_edges " << r.non_manifold_edges
      << ", non_manifold_nodes " << r.non_manifold_nodes << ", inconsistent_edges " << r.inconsistent_edges
      << ", duplicate_faces " << r.duplicate_faces << ", thin_faces " << r.thin_faces << ", imprecise_faces "
      << r.imprecise_faces;
  return out.str();
}

}  // namespace tear::test
