// tear: what each format's reader hands to read_mesh before welding, and helpers they share.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tear/error.h"
#include "tear/mesh.h"
#include "tear/read_mesh.h"

namespace tear {

/// A mesh as its file stores it: one node per vertex of the file, in the file's order, faces
/// triangulated, UVs and normals per corner, identity arrays (`node_vel`, origins, torn edges)
/// per vertex when the file has them. `read_mesh` welds it.
struct FileMesh {
  Mesh mesh;
  /// [node_count] the node id each vertex carries (PLY `id`, glTF `_ID`), or empty when the
  /// file has none: then nodes weld by position.
  std::vector<index_t> vertex_id;
};

/// Bytes of OBJ text below which `read_obj_file` reads a file in one piece; larger files are read
/// in pieces of about this size or more, one per thread and a few over.
inline constexpr std::size_t obj_piece_bytes = std::size_t(1) << 20;

/// The readers. `bytes` is the whole file. Each throws an input `Error` naming `path`.
/// `piece_bytes` lets tests cut small files into many pieces; the result does not depend on it.
FileMesh read_obj_file(const std::string& path, std::string bytes, const std::string& mesh_name,
                       std::size_t piece_bytes = obj_piece_bytes);
FileMesh read_ply_file(const std::string& path, const std::string& bytes, const std::string& mesh_name);
/// glTF 2.0 and GLB 2; nothing for a glTF 1.0 document (another schema, which assimp reads).
/// `max_faces`: the placed triangles at which reading stops with an input error (instancing can
/// multiply a small file's faces without bound).
std::optional<FileMesh> read_gltf_file(const std::string& path, const std::string& bytes, const std::string& mesh_name,
                                       std::uint64_t max_faces);
/// Throws an input error naming `path` when `faces` is over `max_faces` (`--max-faces`).
void check_face_budget(const std::string& path, std::uint64_t faces, std::uint64_t max_faces);
FileMesh read_assimp_file(const std::string& path, const std::string& mesh_name);

/// The error for a `--mesh-name` that names nothing, listing the names the file has.
Error no_mesh_named(const std::string& path, const std::string& mesh_name, const std::vector<std::string>& names);

/// Appends `name` to `names` unless it is empty or already there.
void append_name(std::vector<std::string>& names, const std::string& name);

/// A row-major 4x4 affine transform in double precision: where a scene node places a mesh.
struct Transform {
  double m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};

  Transform operator*(const Transform& o) const;
  bool is_identity() const;
  double linear_determinant() const;
};

/// One placed primitive: per-vertex arrays of the file (positions required, the others may be
/// null) and its triangles as vertex numbers.
struct PlacedTriangles {
  index_t vertex_count = 0;
  const float* vertex_pos = nullptr;                ///< [vertex_count * 3]
  const float* vertex_normal = nullptr;             ///< [vertex_count * 3] or null
  const float* vertex_uv = nullptr;                 ///< [vertex_count * 2] or null, tear's convention (v up)
  const float* vertex_vel = nullptr;                ///< [vertex_count * 3] or null, m/s
  const index_t* vertex_id = nullptr;               ///< [vertex_count] or null
  const std::vector<index_t>* triangles = nullptr;  ///< [triangle_count * 3] vertex numbers, in range
  Transform transform;
};

/// Appends one placement's vertices as nodes and its triangles as faces of `out`, transformed:
/// positions by the transform, normals by its inverse transpose (renormalised), velocities by its
/// linear part; a mirroring transform swaps two corners of each face. `with_uv`, `with_normals`,
/// `with_velocities`, `with_ids` say whether `out` has those arrays at all (a primitive without
/// them gets zeros, and id -1).
void append_placed(const PlacedTriangles& placed, bool with_uv, bool with_normals, bool with_velocities, bool with_ids,
                   FileMesh& out);

/// Largest count of nodes or corners a mesh can hold (`index_t` indices).
inline constexpr std::uint64_t max_index_count = 0x7FFFFFFF;

}  // namespace tear
