// Invariant checks of the remesher, shared by its tests.
#pragma once

#include <cmath>
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
      sum += std::sqrt(double(a[0] - b[0]) * (a[0] - b[0]) + double(a[1] - b[1]) * (a[1] - b[1]) + double(a[2] - b[2]) * (a[2] - b[2]));
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
