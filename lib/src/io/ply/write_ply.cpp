// PLY frames: binary little endian, with node ids, velocities, origins and torn edges.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "io/mesh/corner_numbering.h"
#include "io/mesh/encode_mesh.h"
#include "io/mesh/parallel_pieces.h"
#include "tear/error.h"

namespace tear::encode {
void put_ply_bytes(const Mesh& mesh, const PieceTeam& team, std::string& out) {
  const SplitNodes split = split_nodes(mesh, team);
  out = "ply\nformat binary_little_endian 1.0\ncomment tear\n";
  out += "element vertex " + std::to_string(split.vertex_node.size()) + "\n";
  out += "property float x\nproperty float y\nproperty float z\n";
  if (mesh.has_normals()) out += "property float nx\nproperty float ny\nproperty float nz\n";
  if (mesh.has_uv()) out += "property float s\nproperty float t\n";
  // Identity (docs/io.md): the node each vertex is, its velocity (m/s) and its origin.
  out += "property int id\nproperty float vx\nproperty float vy\nproperty float vz\n";
  out += "property int origin_face\nproperty float origin_u\nproperty float origin_v\n";
  // The connected piece of the vertex's node and of each face (docs/identity.md, *Pieces*).
  const bool pieces = mesh.has_pieces();
  if (pieces) out += "property int piece\n";
  out += "element face " + std::to_string(mesh.face_count()) + "\n";
  out += "property list uchar int vertex_indices\n";
  if (pieces) out += "property int piece\n";
  const std::size_t torn_edge_count = mesh.torn_edge_nodes.size() / 2;
  if (torn_edge_count > 0) {
    out += "element edge " + std::to_string(torn_edge_count) + "\nproperty int vertex1\nproperty int vertex2\n";
  }
  out += "end_header\n";
  // Fixed-size records: each piece writes its vertices and faces at their offsets.
  const std::size_t vertex_size = 4 * (3 + (mesh.has_normals() ? 3 : 0) + (mesh.has_uv() ? 2 : 0) + 7 + (pieces ? 1 : 0));
  const std::size_t face_size = 1 + 3 * 4 + (pieces ? 4 : 0);
  const std::size_t vertex_count = split.vertex_node.size(), face_count = static_cast<std::size_t>(mesh.face_count());
  const std::size_t header_size = out.size();
  out.resize(header_size + vertex_count * vertex_size + face_count * face_size + 4 * mesh.torn_edge_nodes.size());
  char* const vertices = out.data() + header_size;
  char* const faces = vertices + vertex_count * vertex_size;
  team.for_each_range(vertex_count, [&](std::size_t, std::size_t begin, std::size_t end) {
    char* at = vertices + begin * vertex_size;
    for (std::size_t v = begin; v < end; ++v) {
      const index_t node = split.vertex_node[v];
      const index_t corner = split.vertex_corner[v];
      for (int k = 0; k < 3; ++k) put_f32(at, mesh.node_pos[3 * node + k]);
      for (int k = 0; mesh.has_normals() && k < 3; ++k) put_f32(at, corner_value(mesh.corner_normal, 3, corner, k));
      for (int k = 0; mesh.has_uv() && k < 2; ++k) put_f32(at, corner_value(mesh.corner_uv, 2, corner, k));
      put_u32(at, static_cast<std::uint32_t>(node));
      for (int k = 0; k < 3; ++k) put_f32(at, mesh.has_velocities() ? mesh.node_vel[3 * node + k] : 0.0f);
      put_u32(at, static_cast<std::uint32_t>(mesh.has_origins() ? mesh.node_origin_face[node] : none));
      for (int k = 0; k < 2; ++k) put_f32(at, mesh.has_origins() ? mesh.node_origin_bary[2 * node + k] : 0.0f);
      if (pieces) put_u32(at, static_cast<std::uint32_t>(corner >= 0 ? mesh.face_piece[corner / 3] : none));
    }
  });
  team.for_each_range(face_count, [&](std::size_t, std::size_t begin, std::size_t end) {
    char* at = faces + begin * face_size;
    for (std::size_t face = begin; face < end; ++face) {
      *at++ = 3;
      for (std::size_t c = 3 * face; c < 3 * face + 3; ++c)
        put_u32(at, static_cast<std::uint32_t>(split.corner_vertex[c]));
      if (pieces) put_u32(at, static_cast<std::uint32_t>(mesh.face_piece[face]));
    }
  });
  // Vertex i is node i, so the torn edges' node pairs are vertex pairs.
  char* at = faces + face_count * face_size;
  for (index_t node : mesh.torn_edge_nodes) put_u32(at, static_cast<std::uint32_t>(node));
}

}  // namespace tear::encode
