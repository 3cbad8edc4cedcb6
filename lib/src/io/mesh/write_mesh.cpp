#include "tear/write_mesh.h"

#include <omp.h>

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

#include "io/mesh/encode_mesh.h"
#include "io/mesh/parallel_pieces.h"
#include "tear/error.h"

namespace tear {
namespace {

/// Rejects meshes whose arrays do not match, so a writer never reads out of range.
void check_mesh(const Mesh& mesh, const std::string& path, const PieceTeam& team) {
  auto fail = [&](const std::string& what) { return runtime_error(path + ": cannot write: " + what); };
  const std::size_t corner_count = mesh.face_nodes.size();
  const std::size_t node_count = static_cast<std::size_t>(mesh.node_count());
  if (mesh.node_pos.size() % 3 != 0) throw fail("node_pos size is not a multiple of 3");
  if (corner_count % 3 != 0) throw fail("face_nodes size is not a multiple of 3");
  if (mesh.has_uv() && mesh.corner_uv.size() != 2 * corner_count) throw fail("corner_uv has the wrong size");
  if (mesh.has_normals() && mesh.corner_normal.size() != 3 * corner_count) {
    throw fail("corner_normal has the wrong size");
  }
  if (mesh.has_velocities() && mesh.node_vel.size() != 3 * node_count) throw fail("node_vel has the wrong size");
  if (mesh.has_origins() && mesh.node_origin_face.size() != node_count) {
    throw fail("node_origin_face has the wrong size");
  }
  if (mesh.node_origin_bary.size() != 2 * mesh.node_origin_face.size())
    throw fail("node_origin_bary has the wrong size");
  // The first corner (in order) that uses a node out of range: each piece finds its first.
  const std::size_t piece_count = team.pieces(corner_count);
  std::vector<std::size_t> bad_corner(piece_count, corner_count);
  team.for_each_range(corner_count, piece_count, [&](std::size_t k, std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c) {
      const index_t node = mesh.face_nodes[c];
      if (node < 0 || node >= mesh.node_count()) {
        bad_corner[k] = c;
        return;
      }
    }
  });
  for (std::size_t c : bad_corner) {
    if (c == corner_count) continue;
    throw fail("face " + std::to_string(c / 3) + " uses node " + std::to_string(mesh.face_nodes[c]) + " of " +
               std::to_string(mesh.node_count()));
  }
  if (mesh.torn_edge_nodes.size() % 2 != 0) throw fail("torn_edge_nodes does not hold pairs");
  for (index_t node : mesh.torn_edge_nodes) {
    if (node < 0 || node >= mesh.node_count()) {
      throw fail("a torn edge uses node " + std::to_string(node) + " of " + std::to_string(mesh.node_count()));
    }
  }
}

}  // namespace

using namespace encode;

void write_mesh(const Mesh& mesh, const std::string& path) { write_mesh(mesh, path, format_from_path(path)); }

void encode_mesh(const Mesh& mesh, const std::string& path, MeshFormat format, std::string& bytes,
                 const EncodeOptions& options) {
  PieceTeam team;
  team.threads = options.threads > 0 ? options.threads : omp_get_max_threads();
  if (mesh.face_count() < options.parallel_from && mesh.node_count() < options.parallel_from) team.threads = 1;
  check_mesh(mesh, path, team);
  switch (format) {
    case MeshFormat::obj:
      return put_obj_text(mesh, team, bytes);
    case MeshFormat::ply:
      return put_ply_bytes(mesh, team, bytes);
    case MeshFormat::gltf:
      return put_gltf_text(mesh, team, bytes);
    case MeshFormat::glb:
      return put_glb_bytes(mesh, team, bytes);
  }
  throw Error(ErrorKind::usage, path + ": unknown mesh format");
}

void write_mesh(const Mesh& mesh, const std::string& path, MeshFormat format) {
  std::string bytes;
  encode_mesh(mesh, path, format, bytes);
  write_file_atomically(path, bytes);
}

}  // namespace tear
