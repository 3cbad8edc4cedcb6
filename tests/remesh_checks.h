// Invariant checks of the remesher, shared by its tests.
#pragma once

#include <algorithm>
#include <array>
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "catch.h"
#include "tear/cloth.h"
#include "tear/mesh_info.h"
#include "tear/topology.h"
#include "tear/validate_mesh.h"

namespace tear::test {

inline double face_area(const Mesh& m, index_t f) {
  const float* a = &m.node_pos[3 * m.face_nodes[3 * f]];
  const float* b = &m.node_pos[3 * m.face_nodes[3 * f + 1]];
  const float* c = &m.node_pos[3 * m.face_nodes[3 * f + 2]];
  double u[3], v[3];
  for (int d = 0; d < 3; ++d) {
    u[d] = double(b[d]) - a[d];
    v[d] = double(c[d]) - a[d];
  }
  const double x = u[1] * v[2] - u[2] * v[1], y = u[2] * v[0] - u[0] * v[2], z = u[0] * v[1] - u[1] * v[0];
  return 0.5 * std::sqrt(x * x + y * y + z * z);
}

/// The piece (faces joined through shared nodes) of every node, as the piece's lowest node.
inline std::vector<index_t> node_piece_roots(const Mesh& m) {
  std::vector<index_t> parent(static_cast<std::size_t>(m.node_count()));
  for (index_t i = 0; i < m.node_count(); ++i) parent[i] = i;
  const auto find = [&](index_t n) {
    while (parent[n] != n) n = parent[n] = parent[parent[n]];
    return n;
  };
  for (index_t f = 0; f < m.face_count(); ++f)
    for (int k = 1; k < 3; ++k) {
      const index_t a = find(m.face_nodes[3 * f]), b = find(m.face_nodes[3 * f + k]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  for (index_t n = 0; n < m.node_count(); ++n) parent[n] = find(n);
  return parent;
}

/// Areas of the mesh's pieces (faces joined through shared nodes), largest first.
inline std::vector<double> component_areas(const Mesh& m) {
  const std::vector<index_t> root = node_piece_roots(m);
  const auto find = [&](index_t n) { return root[n]; };
  std::map<index_t, double> area;
  for (index_t f = 0; f < m.face_count(); ++f) area[find(m.face_nodes[3 * f])] += face_area(m, f);
  std::vector<double> out;
  for (const auto& [root, a] : area) out.push_back(a);
  std::sort(out.begin(), out.end(), std::greater<double>());
  return out;
}

inline double total_area(const Mesh& m) {
  double sum = 0;
  for (index_t f = 0; f < m.face_count(); ++f) sum += face_area(m, f);
  return sum;
}

inline double boundary_length(const Mesh& m, const Topology& t) {
  double sum = 0;
  for (index_t e = 0; e < t.edge_count; ++e)
    if (t.edge_boundary[e]) {
      const float* a = &m.node_pos[3 * t.edge_nodes[2 * e]];
      const float* b = &m.node_pos[3 * t.edge_nodes[2 * e + 1]];
      sum += std::sqrt(double(a[0] - b[0]) * (a[0] - b[0]) + double(a[1] - b[1]) * (a[1] - b[1]) +
                       double(a[2] - b[2]) * (a[2] - b[2]));
    }
  return sum;
}

/// Everything that must hold after any cut: a valid oriented manifold, the same area, corner
/// arrays of the right size. Returns the mesh's statistics for further checks.
inline MeshInfo check_valid_after_cut(const Cloth& cloth, double area_before, Device device) {
  const Mesh m = cloth.mesh();
  const Topology t = cloth.topology();
  const MeshReport report = validate_mesh(m, t, device);
  INFO("after cut: " << report.describe());
  CHECK(report.ok());
  CHECK(std::abs(total_area(m) - area_before) <= 1e-5 * area_before);
  if (!m.corner_uv.empty()) CHECK(m.corner_uv.size() == 6 * std::size_t(m.face_count()));
  if (!m.corner_normal.empty()) CHECK(m.corner_normal.size() == 9 * std::size_t(m.face_count()));
  return compute_mesh_info(m, t, report);
}

}  // namespace tear::test

namespace tear::test {

/// A cut on the rest shape's xy plane.
inline CutLine cut_rest_xy(std::vector<std::array<double, 2>> points) {
  CutLine line;
  line.source = CutLine::Source::node_rest;
  line.polyline = std::move(points);
  return line;
}

/// A cut in UV space.
inline CutLine cut_uv(std::vector<std::array<double, 2>> points) {
  CutLine line;
  line.source = CutLine::Source::corner_uv;
  line.polyline = std::move(points);
  return line;
}

/// Smallest interior angle of the mesh, degrees (NaN-free: degenerate faces count as 0).
inline double min_angle_deg(const Mesh& m) {
  double worst = 180.0;
  for (index_t f = 0; f < m.face_count(); ++f) {
    double p[3][3];
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) p[k][d] = m.node_pos[3 * std::size_t(m.face_nodes[3 * f + k]) + d];
    for (int k = 0; k < 3; ++k) {
      double u[3], v[3], uu = 0, vv = 0, uv = 0;
      for (int d = 0; d < 3; ++d) {
        u[d] = p[(k + 1) % 3][d] - p[k][d];
        v[d] = p[(k + 2) % 3][d] - p[k][d];
        uu += u[d] * u[d];
        vv += v[d] * v[d];
        uv += u[d] * v[d];
      }
      const double c = uu > 0 && vv > 0 ? uv / std::sqrt(uu * vv) : 1.0;
      const double angle = std::acos(c < -1 ? -1 : c > 1 ? 1 : c) * 180.0 / 3.14159265358979323846;
      if (angle < worst) worst = angle;
    }
  }
  return worst;
}

/// Every corner's UV equals (x, y) / size of its node: true of `make_sheet` and kept by any cut
/// that interpolates inside faces, since that map is affine on the flat sheet.
inline void check_uv_is_xy(const Mesh& m, double size = 1.0) {
  REQUIRE(m.corner_uv.size() == 6 * std::size_t(m.face_count()));
  std::size_t bad = 0;
  double worst = 0;
  for (std::size_t c = 0; c < m.face_nodes.size(); ++c) {
    const std::size_t n = std::size_t(m.face_nodes[c]);
    for (int d = 0; d < 2; ++d) {
      const double err = std::abs(double(m.corner_uv[2 * c + d]) - m.node_pos[3 * n + d] / size);
      worst = std::max(worst, err);
      if (err > 1e-5) ++bad;
    }
  }
  INFO("worst UV error " << worst);
  CHECK(bad == 0);
}

/// How many entries of two arrays differ (all of the longer one's extra entries count).
template <class T>
std::size_t count_differences(const std::vector<T>& a, const std::vector<T>& b) {
  std::size_t diff = a.size() > b.size() ? a.size() - b.size() : b.size() - a.size();
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) diff += a[i] == b[i] ? 0 : 1;
  return diff;
}

/// The two meshes are the same arrays, bit for bit (counts of differing entries on failure).
inline void check_same_mesh(const Mesh& a, const Mesh& b) {
  CHECK(a.node_count() == b.node_count());
  CHECK(a.face_count() == b.face_count());
  CHECK(count_differences(a.node_pos, b.node_pos) == 0);
  CHECK(count_differences(a.face_nodes, b.face_nodes) == 0);
  CHECK(count_differences(a.corner_uv, b.corner_uv) == 0);
  CHECK(count_differences(a.corner_normal, b.corner_normal) == 0);
}

/// Drops the faces whose centroid lies in the disc, then the nodes no face uses.
inline Mesh cut_disc_hole(const Mesh& mesh, double cx, double cy, double radius) {
  Mesh out;
  std::vector<index_t> new_node(std::size_t(mesh.node_count()), -1);
  for (index_t f = 0; f < mesh.face_count(); ++f) {
    double x = 0, y = 0;
    for (int k = 0; k < 3; ++k) {
      x += mesh.node_pos[3 * std::size_t(mesh.face_nodes[3 * f + k])] / 3.0;
      y += mesh.node_pos[3 * std::size_t(mesh.face_nodes[3 * f + k]) + 1] / 3.0;
    }
    if ((x - cx) * (x - cx) + (y - cy) * (y - cy) < radius * radius) continue;
    for (int k = 0; k < 3; ++k) {
      const index_t n = mesh.face_nodes[3 * f + k];
      if (new_node[n] < 0) {
        new_node[n] = out.node_count();
        out.node_pos.insert(out.node_pos.end(), mesh.node_pos.begin() + 3 * n, mesh.node_pos.begin() + 3 * n + 3);
      }
      out.face_nodes.push_back(new_node[n]);
    }
    if (mesh.has_uv())
      out.corner_uv.insert(out.corner_uv.end(), mesh.corner_uv.begin() + 6 * f, mesh.corner_uv.begin() + 6 * f + 6);
    if (mesh.has_normals())
      out.corner_normal.insert(out.corner_normal.end(), mesh.corner_normal.begin() + 9 * f,
                               mesh.corner_normal.begin() + 9 * f + 9);
  }
  return out;
}

}  // namespace tear::test
