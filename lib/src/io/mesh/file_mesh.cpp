#include "io/mesh/file_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "tear/error.h"

namespace tear {

Error no_mesh_named(const std::string& path, const std::string& mesh_name, const std::vector<std::string>& names) {
  std::string listed;
  for (const std::string& name : names) listed += (listed.empty() ? "'" : ", '") + name + "'";
  return input_error(path, "no mesh named '" + mesh_name +
                               "'; meshes in the file: " + (listed.empty() ? std::string("none with a name") : listed));
}

void append_name(std::vector<std::string>& names, const std::string& name) {
  if (!name.empty() && std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
}

Transform Transform::operator*(const Transform& o) const {
  Transform t;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      t.m[r][c] = m[r][0] * o.m[0][c] + m[r][1] * o.m[1][c] + m[r][2] * o.m[2][c] + m[r][3] * o.m[3][c];
    }
  }
  return t;
}

bool Transform::is_identity() const {
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      if (m[r][c] != (r == c ? 1.0 : 0.0)) return false;
    }
  }
  return true;
}

double Transform::linear_determinant() const {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

namespace {

/// Corners of one primitive from which `append_placed` gathers their values on several threads.
constexpr std::int64_t parallel_corners = std::int64_t(1) << 16;

/// Appends `count` zeros to `values` and returns where they begin.
template <class T>
T* grow(std::vector<T>& values, std::size_t count) {
  const std::size_t at = values.size();
  values.resize(at + count);
  return values.data() + at;
}

/// The inverse transpose of the linear part of `t`, through which normals go: the cofactor matrix
/// over the determinant `det` (the cofactors alone where it is 0).
void normal_matrix_of(const Transform& t, double det, double normal_matrix[3][3]) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      const int r1 = (r + 1) % 3, r2 = (r + 2) % 3, c1 = (c + 1) % 3, c2 = (c + 2) % 3;
      const double cofactor = t.m[r1][c1] * t.m[r2][c2] - t.m[r1][c2] * t.m[r2][c1];
      normal_matrix[r][c] = det != 0.0 ? cofactor / det : cofactor;
    }
  }
}

/// Room for a placement of `vertex_count` vertices and `corners` corners, so that a large primitive
/// is not copied as its arrays grow (and still geometric growth, so that many small ones are not
/// copied once each).
void make_room(std::size_t vertex_count, std::size_t corners, bool with_uv, bool with_normals, bool with_velocities,
               bool with_ids, FileMesh& out) {
  auto room_for = [](auto& values, std::size_t more) {
    if (values.capacity() < values.size() + more) values.reserve(std::max(values.size() + more, 2 * values.size()));
  };
  Mesh& mesh = out.mesh;
  room_for(mesh.node_pos, 3 * vertex_count);
  if (with_velocities) room_for(mesh.node_vel, 3 * vertex_count);
  if (with_ids) room_for(out.vertex_id, vertex_count);
  room_for(mesh.face_nodes, corners);
  if (with_uv) room_for(mesh.corner_uv, 2 * corners);
  if (with_normals) room_for(mesh.corner_normal, 3 * corners);
}

/// The placement's vertices as nodes: copied whole where the transform is the identity, else one
/// by one; velocities (zeros where the primitive has none) and ids (-1 where it has none).
void append_nodes(const PlacedTriangles& placed, bool identity, bool with_velocities, bool with_ids, FileMesh& out) {
  const Transform& t = placed.transform;
  Mesh& mesh = out.mesh;
  const std::size_t vertex_count = static_cast<std::size_t>(placed.vertex_count);
  if (identity) {
    mesh.node_pos.insert(mesh.node_pos.end(), placed.vertex_pos, placed.vertex_pos + 3 * vertex_count);
  } else {
    float* pos = grow(mesh.node_pos, 3 * vertex_count);
    for (std::size_t v = 0; v < vertex_count; ++v) {
      const float* p = placed.vertex_pos + 3 * v;
      for (int r = 0; r < 3; ++r)
        pos[3 * v + r] = static_cast<float>(t.m[r][0] * p[0] + t.m[r][1] * p[1] + t.m[r][2] * p[2] + t.m[r][3]);
    }
  }
  if (with_velocities) {
    if (placed.vertex_vel && identity) {
      mesh.node_vel.insert(mesh.node_vel.end(), placed.vertex_vel, placed.vertex_vel + 3 * vertex_count);
    } else {
      float* vel = grow(mesh.node_vel, 3 * vertex_count);  // zeros where the primitive has none
      for (std::size_t v = 0; placed.vertex_vel && v < vertex_count; ++v) {
        const float* w = placed.vertex_vel + 3 * v;
        for (int r = 0; r < 3; ++r)
          vel[3 * v + r] = static_cast<float>(t.m[r][0] * w[0] + t.m[r][1] * w[1] + t.m[r][2] * w[2]);
      }
    }
  }
  if (with_ids) {
    if (placed.vertex_id)
      out.vertex_id.insert(out.vertex_id.end(), placed.vertex_id, placed.vertex_id + vertex_count);
    else
      out.vertex_id.insert(out.vertex_id.end(), vertex_count, none);
  }
}

}  // namespace

void append_placed(const PlacedTriangles& placed, bool with_uv, bool with_normals, bool with_velocities, bool with_ids,
                   FileMesh& out) {
  const bool identity = placed.transform.is_identity();
  const double det = placed.transform.linear_determinant();
  // A mirroring transform turns counter-clockwise faces clockwise; swapping two corners restores it.
  const bool mirrored = det < 0.0;
  double normal_matrix[3][3];
  normal_matrix_of(placed.transform, det, normal_matrix);

  Mesh& mesh = out.mesh;
  const index_t base = mesh.node_count();
  const std::vector<index_t>& triangles = *placed.triangles;
  const std::size_t corners = triangles.size() / 3 * 3;
  make_room(static_cast<std::size_t>(placed.vertex_count), corners, with_uv, with_normals, with_velocities, with_ids,
            out);
  append_nodes(placed, identity, with_velocities, with_ids, out);

  // Faces, and their corners' values gathered from their vertices: each corner written in place,
  // on OpenMP threads for a large primitive (every corner is its own, so the result is the same).
  index_t* face_nodes = grow(mesh.face_nodes, corners);
  float* corner_uv = with_uv ? grow(mesh.corner_uv, 2 * corners) : nullptr;  // zeros where none
  float* corner_normal = with_normals ? grow(mesh.corner_normal, 3 * corners) : nullptr;
  const float* vertex_uv = placed.vertex_uv;
  const float* vertex_normal = placed.vertex_normal;
  const std::int64_t corner_total = static_cast<std::int64_t>(corners);
#pragma omp parallel for schedule(static) if (corner_total >= parallel_corners)
  for (std::int64_t ci = 0; ci < corner_total; ++ci) {
    const std::size_t c = static_cast<std::size_t>(ci);
    const std::size_t k = c % 3;
    const index_t v = triangles[c - k + (mirrored && k > 0 ? 3 - k : k)];
    face_nodes[c] = base + v;
    const std::size_t vi = static_cast<std::size_t>(v);
    if (corner_uv && vertex_uv) {
      corner_uv[2 * c] = vertex_uv[2 * vi];
      corner_uv[2 * c + 1] = vertex_uv[2 * vi + 1];
    }
    if (!corner_normal || !vertex_normal) continue;
    const float* n = vertex_normal + 3 * vi;
    if (identity) {
      for (int r = 0; r < 3; ++r) corner_normal[3 * c + r] = n[r];
      continue;
    }
    double m[3];
    for (int r = 0; r < 3; ++r)
      m[r] = normal_matrix[r][0] * n[0] + normal_matrix[r][1] * n[1] + normal_matrix[r][2] * n[2];
    const double length = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    const double scale = length > 0.0 ? 1.0 / length : 0.0;
    for (int r = 0; r < 3; ++r) corner_normal[3 * c + r] = static_cast<float>(m[r] * scale);
  }
}

}  // namespace tear
