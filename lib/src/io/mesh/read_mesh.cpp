#include "tear/read_mesh.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "io/mesh/file_mesh.h"
#include "tear/error.h"
#include "tear/input_file.h"

namespace tear {
namespace {

enum class Reader { obj, ply, gltf, assimp };

std::string lower_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

/// The content decides where it is unambiguous (a PLY or GLB under any name never reaches
/// assimp's importers for them), the extension otherwise.
Reader reader_for(const std::string& path, const std::string& head) {
  if (head.compare(0, 4, "ply\n") == 0 || head.compare(0, 4, "ply\r") == 0) return Reader::ply;
  if (head.compare(0, 4, "glTF") == 0) return Reader::gltf;
  const std::string extension = lower_extension(path);
  if (extension == ".obj") return Reader::obj;
  if (extension == ".ply") return Reader::ply;
  if (extension == ".gltf" || extension == ".glb") return Reader::gltf;
  return Reader::assimp;
}

/// `ReadOptions::as_written`: the file's first vertices, up to the first whose id is not its own
/// index, are the nodes; each later vertex is a copy of the node its id names. A file whose ids do
/// not have that form (not written by tear) is welded by id.
void keep_as_written(FileMesh& file) {
  Mesh& mesh = file.mesh;
  const index_t count = mesh.node_count();
  if (file.vertex_id.size() != static_cast<std::size_t>(count)) return;
  index_t nodes = 0;
  while (nodes < count && file.vertex_id[nodes] == nodes) ++nodes;
  for (index_t v = nodes; v < count; ++v) {
    if (file.vertex_id[v] < 0 || file.vertex_id[v] >= nodes) {
      weld_nodes_by_id(mesh, file.vertex_id);
      return;
    }
  }
  for (index_t& n : mesh.face_nodes) n = file.vertex_id[n];
  for (index_t& n : mesh.torn_edge_nodes) n = file.vertex_id[n];
  const std::size_t n = static_cast<std::size_t>(nodes);
  mesh.node_pos.resize(3 * n);
  if (!mesh.node_vel.empty()) mesh.node_vel.resize(3 * n);
  if (!mesh.node_origin_face.empty()) mesh.node_origin_face.resize(n);
  if (!mesh.node_origin_bary.empty()) mesh.node_origin_bary.resize(2 * n);
}

}  // namespace

void check_face_budget(const std::string& path, std::uint64_t faces, std::uint64_t max_faces) {
  if (faces > max_faces)
    throw input_error(path, "has " + std::to_string(faces) + " triangles or more, over the limit of " +
                                std::to_string(max_faces) + " (--max-faces)");
}

Mesh read_mesh(const std::string& path, const ReadOptions& options) {
  WeldReport report;
  return read_mesh(path, options, report);
}

Mesh read_mesh(const std::string& path, const ReadOptions& options, WeldReport& report) {
  report = WeldReport{};
  if (!std::isfinite(options.weld_tolerance) || options.weld_tolerance < 0.0) {
    throw Error(ErrorKind::usage,
                "weld tolerance must be a finite number >= 0, got " + std::to_string(options.weld_tolerance));
  }
  // A regular file of a known size within --max-input-bytes, read at once: never a FIFO, a
  // device or a folder, which would block, run forever or fail with no file named.
  std::string bytes = read_input_file(path, "the mesh");
  if (bytes.empty()) throw input_error(path, "is empty");
  FileMesh file;
  switch (reader_for(path, bytes.substr(0, 4))) {
    case Reader::obj:
      file = read_obj_file(path, std::move(bytes), options.mesh_name);
      break;
    case Reader::ply:
      file = read_ply_file(path, bytes, options.mesh_name);
      break;
    case Reader::gltf:
      if (std::optional<FileMesh> gltf = read_gltf_file(path, bytes, options.mesh_name, options.max_faces)) {
        file = std::move(*gltf);
      } else {
        std::string().swap(bytes);
        file = read_assimp_file(path, options.mesh_name);
      }
      break;
    case Reader::assimp:
      std::string().swap(bytes);
      file = read_assimp_file(path, options.mesh_name);
      break;
  }
  check_face_budget(path, file.mesh.face_count(), options.max_faces);

  Mesh& mesh = file.mesh;
  if (mesh.face_count() == 0) throw input_error(path, "holds no triangles");
  if (options.as_written) {
    keep_as_written(file);
  } else if (!options.weld) {
    drop_unused_nodes(mesh);
  } else if (!file.vertex_id.empty()) {
    weld_nodes_by_id(mesh, file.vertex_id, &report);
  } else {
    weld_nodes(mesh, options.weld_tolerance, &report);
  }
  if (mesh.face_count() == 0)
    throw input_error(path, "holds no triangles (all are degenerate" +
                                (report.any() ? "; " + report.describe() : std::string()) + ")");
  return mesh;
}

}  // namespace tear
