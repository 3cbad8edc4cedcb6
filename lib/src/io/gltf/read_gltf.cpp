// glTF and GLB through tinygltf (Debian's libtinygltf), which hands over the document as it is:
// every primitive's own vertex arrays in order, the application attributes (`_ID`, `_VELOCITY`)
// that assimp drops, and nothing merged or reordered. tinygltf checks the JSON and the buffers'
// declared lengths; the GLB container and every accessor's range are checked here, before any
// value is read, and an index out of range is an error (assimp drops such faces).
#include <tiny_gltf.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "io/gltf/gltf_accessors.h"
#include "io/gltf/gltf_files.h"
#include "io/mesh/file_mesh.h"
#include "tear/error.h"
#include "tear/input_file.h"

namespace tear {
namespace {

std::uint32_t read_u32(const std::string& bytes, std::size_t at) {
  std::uint32_t value = 0;
  for (int k = 3; k >= 0; --k) value = (value << 8) | static_cast<unsigned char>(bytes[at + k]);
  return value;
}

/// The GLB container: a 12-byte header, a JSON chunk, then optionally a BIN chunk, each length
/// within the file (tinygltf 2.7 allows a BIN chunk to end 8 bytes past the data it was given).
void check_glb(const std::string& path, const std::string& bytes) {
  auto fail = [&](const std::string& what) { return input_error(path, "GLB " + what); };
  if (bytes.size() < 20) throw fail("file is too short (" + std::to_string(bytes.size()) + " bytes)");
  const std::uint32_t version = read_u32(bytes, 4), length = read_u32(bytes, 8);
  if (version != 2) throw fail("version " + std::to_string(version) + " is not 2");
  if (length > bytes.size()) {
    throw fail("header says " + std::to_string(length) + " bytes, the file has " + std::to_string(bytes.size()) +
               " (truncated)");
  }
  const std::uint64_t json_length = read_u32(bytes, 12);
  if (read_u32(bytes, 16) != 0x4E4F534Au) throw fail("first chunk is not JSON");
  if (json_length == 0 || 20 + json_length > length) {
    throw fail("JSON chunk of " + std::to_string(json_length) + " bytes does not fit in the file's " +
               std::to_string(length) + " bytes");
  }
  const std::uint64_t bin_at = 20 + json_length;
  if (bin_at == length) return;
  if (bin_at + 8 > length) throw fail("chunk header after the JSON chunk is truncated");
  const std::uint64_t bin_length = read_u32(bytes, bin_at);
  if (bin_at + 8 + bin_length > length) {
    throw fail("chunk of " + std::to_string(bin_length) + " bytes after the JSON chunk does not fit in the file's " +
               std::to_string(length) + " bytes");
  }
}

// tinygltf converts `extras` recursively: the JSON's nesting is bounded before it is parsed
// (json_nesting_depth, tear/input_file.h); glTF documents nest a few levels.
constexpr std::size_t max_json_depth = 256;

/// Images are of no use to cloth: they are not decoded.
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

using gltf::AccessorReader;
using gltf::check_left_to_assimp;
using gltf::ExternalFiles;
using gltf::one_line;

/// A node's own transform: its matrix (column-major) or translation * rotation * scale.
Transform local_transform(const tinygltf::Node& node) {
  Transform t;
  if (node.matrix.size() == 16) {
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) t.m[r][c] = node.matrix[4 * c + r];
    }
    return t;
  }
  double q[4] = {0, 0, 0, 1};
  if (node.rotation.size() == 4) {
    const double length = std::sqrt(node.rotation[0] * node.rotation[0] + node.rotation[1] * node.rotation[1] +
                                    node.rotation[2] * node.rotation[2] + node.rotation[3] * node.rotation[3]);
    if (length > 0.0) {
      for (int k = 0; k < 4; ++k) q[k] = node.rotation[k] / length;
    }
  }
  const double x = q[0], y = q[1], z = q[2], w = q[3];
  const double rotation[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                                 {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                                 {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
  const double scale[3] = {node.scale.size() == 3 ? node.scale[0] : 1.0, node.scale.size() == 3 ? node.scale[1] : 1.0,
                           node.scale.size() == 3 ? node.scale[2] : 1.0};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) t.m[r][c] = rotation[r][c] * scale[c];
    t.m[r][3] = node.translation.size() == 3 ? node.translation[r] : 0.0;
  }
  return t;
}

struct Placement {
  int mesh;
  int node;  ///< -1 for a mesh read without a scene
  Transform transform;
};

/// Appends the placements below `root` in depth-first order (a node's mesh, then its children in
/// order), with an explicit stack: a file can nest nodes a million deep.
void collect_placements(const std::string& path, const tinygltf::Model& model, int root,
                        std::vector<std::uint8_t>& visited, std::vector<Placement>& placements) {
  std::vector<std::pair<int, Transform>> stack = {{root, Transform()}};
  while (!stack.empty()) {
    const auto [node_index, parent] = stack.back();
    stack.pop_back();
    if (node_index < 0 || static_cast<std::size_t>(node_index) >= model.nodes.size()) {
      throw input_error(path, "the scene uses node " + std::to_string(node_index) + ", which does not exist");
    }
    // glTF nodes form trees: a node reached twice is an error.
    if (visited[node_index]) {
      throw input_error(path, "node " + std::to_string(node_index) +
                                  " is reached twice in the scene (it has two parents, or the hierarchy has a cycle)");
    }
    visited[node_index] = 1;
    const tinygltf::Node& node = model.nodes[node_index];
    const Transform transform = parent * local_transform(node);
    if (node.mesh >= 0) {
      if (static_cast<std::size_t>(node.mesh) >= model.meshes.size()) {
        throw input_error(path, "node " + std::to_string(node_index) + " uses mesh " + std::to_string(node.mesh) +
                                    ", which does not exist");
      }
      placements.push_back({node.mesh, node_index, transform});
    }
    for (auto child = node.children.rbegin(); child != node.children.rend(); ++child)
      stack.emplace_back(*child, transform);
  }
}

bool is_triangles(const tinygltf::Primitive& primitive) {
  const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
  return mode == TINYGLTF_MODE_TRIANGLES || mode == TINYGLTF_MODE_TRIANGLE_STRIP || mode == TINYGLTF_MODE_TRIANGLE_FAN;
}

bool has_triangles(const tinygltf::Mesh& mesh) {
  for (const tinygltf::Primitive& primitive : mesh.primitives) {
    if (is_triangles(primitive) && primitive.attributes.count("POSITION")) return true;
  }
  return false;
}

/// The glTF document of `bytes`, through tinygltf; nothing for a document that assimp is left to
/// read (glTF 1.0, Draco-compressed meshes), once `check_left_to_assimp` has passed it.
std::optional<tinygltf::Model> load_model(const std::string& path, const std::string& bytes) {
  const bool binary = bytes.compare(0, 4, "glTF") == 0;
  // glTF 1.0 (another schema, which tinygltf does not read) is left to assimp. A binary one's
  // header is as 2.0's, its JSON at 20 with its length at 12.
  if (binary && bytes.size() >= 8 && read_u32(bytes, 4) == 1) {
    if (bytes.size() < 20 || read_u32(bytes, 12) > bytes.size() - 20)
      throw input_error(path, "cannot read as glTF: the binary glTF 1.0's content is longer than the file");
    if (json_nesting_depth(bytes.data() + 20, read_u32(bytes, 12)) > max_json_depth)
      throw input_error(path, "glTF JSON nests deeper than " + std::to_string(max_json_depth) + " levels");
    const char* json = bytes.data() + 20;
    check_left_to_assimp(path, nlohmann::json::parse(json, json + read_u32(bytes, 12), nullptr, false), false, "");
    return std::nullopt;
  }
  if (binary) check_glb(path, bytes);
  if (bytes.size() > std::numeric_limits<unsigned int>::max())
    throw input_error(path, "too large for glTF (4 GiB or more)");

  const std::size_t json_begin = binary ? 20 : 0;
  const std::size_t json_size = binary ? read_u32(bytes, 12) : bytes.size();
  if (json_nesting_depth(bytes.data() + json_begin, json_size) > max_json_depth) {
    throw input_error(path, "glTF JSON nests deeper than " + std::to_string(max_json_depth) + " levels");
  }

  // Parsed here once (tinygltf parses its own copy): the uris are checked before tinygltf reads a
  // file, and what is left to assimp is checked from it too.
  const char* json = bytes.data() + json_begin;
  const nlohmann::json document = nlohmann::json::parse(json, json + json_size, nullptr, false);
  ExternalFiles files = gltf::external_files(path, document);
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(skip_image, nullptr);
  loader.SetFsCallbacks({gltf::external_file_exists, gltf::keep_path, gltf::read_external_file, gltf::write_nothing, &files});
  tinygltf::Model model;
  std::string error, warning;
  const std::string base_dir = std::filesystem::path(path).parent_path().string();
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const unsigned int size = static_cast<unsigned int>(binary ? read_u32(bytes, 8) : bytes.size());
  const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &error, &warning, data, size, base_dir)
                         : loader.LoadASCIIFromString(&model, &error, &warning, bytes.data(), size, base_dir);
  if (!ok && error.find("\"asset\"") != std::string::npos) {
    check_left_to_assimp(path, document, true, error);
    return std::nullopt;
  }
  // Draco-compressed meshes are decoded by assimp (tinygltf is built without Draco here).
  if (bytes.find("KHR_draco_mesh_compression") != std::string::npos) {
    check_left_to_assimp(path, document, false, error);
    return std::nullopt;
  }
  if (!ok) throw input_error(path, "cannot read as glTF: " + one_line(error.empty() ? "malformed" : error));
  if (model.asset.version.compare(0, 1, "2") != 0) {
    check_left_to_assimp(path, document, false, error);
    return std::nullopt;
  }

  for (const char* extension : {"EXT_meshopt_compression", "KHR_meshopt_compression"}) {
    if (std::find(model.extensionsUsed.begin(), model.extensionsUsed.end(), extension) != model.extensionsUsed.end()) {
      throw input_error(path, std::string("uses ") + extension + ", which tear does not read");
    }
  }
  return model;
}

/// The scene's nodes, each placing its mesh with the product of the transforms above it: those
/// with triangles, and of them those `mesh_name` names (a mesh's or its node's name) when it is given.
std::vector<Placement> scene_placements(const std::string& path, const tinygltf::Model& model,
                                        const std::string& mesh_name) {
  std::vector<Placement> placements;
  std::vector<std::uint8_t> visited(model.nodes.size(), 0);
  const int scene = model.defaultScene >= 0 ? model.defaultScene : (model.scenes.empty() ? -1 : 0);
  if (scene >= static_cast<int>(model.scenes.size())) {
    throw input_error(path, "the default scene " + std::to_string(scene) + " does not exist");
  }
  if (scene >= 0) {
    for (int root : model.scenes[scene].nodes) collect_placements(path, model, root, visited, placements);
  } else {
    // No scene: every mesh once, where it is.
    for (std::size_t mesh = 0; mesh < model.meshes.size(); ++mesh) {
      placements.push_back({static_cast<int>(mesh), -1, Transform()});
    }
  }
  placements.erase(std::remove_if(placements.begin(), placements.end(),
                                  [&](const Placement& p) { return !has_triangles(model.meshes[p.mesh]); }),
                   placements.end());
  auto node_name = [&](const Placement& p) { return p.node >= 0 ? model.nodes[p.node].name : std::string(); };
  if (!mesh_name.empty()) {
    std::vector<std::string> names;
    for (const Placement& p : placements) {
      append_name(names, model.meshes[p.mesh].name);
      append_name(names, node_name(p));
    }
    placements.erase(std::remove_if(placements.begin(), placements.end(),
                                    [&](const Placement& p) {
                                      return mesh_name != model.meshes[p.mesh].name && mesh_name != node_name(p);
                                    }),
                     placements.end());
    if (placements.empty()) throw no_mesh_named(path, mesh_name, names);
  }
  return placements;
}

/// Which arrays the mesh has: those any placed primitive has. Ids weld nodes only when every
/// primitive has them and no mesh that has them is placed twice (its two copies would carry the
/// same ids).
struct Channels {
  bool uv = false, normals = false, velocities = false, ids = false;
};

Channels channels_of(const tinygltf::Model& model, const std::vector<Placement>& placements) {
  Channels with;
  with.ids = !placements.empty();
  std::map<int, int> placement_count;
  for (const Placement& p : placements) ++placement_count[p.mesh];
  for (const Placement& p : placements) {
    for (const tinygltf::Primitive& primitive : model.meshes[p.mesh].primitives) {
      if (!is_triangles(primitive) || !primitive.attributes.count("POSITION")) continue;
      with.uv = with.uv || primitive.attributes.count("TEXCOORD_0");
      with.normals = with.normals || primitive.attributes.count("NORMAL");
      with.velocities = with.velocities || primitive.attributes.count("_VELOCITY");
      with.ids = with.ids && primitive.attributes.count("_ID") && placement_count[p.mesh] == 1;
    }
  }
  return with;
}

/// A primitive's vertex arrays, each checked to have one value per vertex (or none).
struct PrimitiveVertices {
  std::vector<float> position, normal, uv, velocity;
  std::vector<index_t> id;
};

/// The values of a primitive's attribute, or none when it has not that attribute.
template <typename T>
std::vector<T> attribute_values(const AccessorReader& reader, const tinygltf::Primitive& primitive,
                                const char* semantic, int components, const std::string& name) {
  const auto found = primitive.attributes.find(semantic);
  if (found == primitive.attributes.end()) return std::vector<T>();
  return reader.read<T>(found->second, components, name + " " + semantic);
}

PrimitiveVertices primitive_vertices(const std::string& path, const AccessorReader& reader,
                                     const tinygltf::Primitive& primitive, const std::string& name, bool with_ids,
                                     std::size_t nodes_before) {
  PrimitiveVertices vertices;
  vertices.position = attribute_values<float>(reader, primitive, "POSITION", 3, name);
  const std::size_t vertex_count = vertices.position.size() / 3;
  if (nodes_before + vertex_count > max_index_count) {
    throw input_error(path, "too large: more than 2^31 vertices");
  }
  auto per_vertex = [&](auto values, const char* semantic, std::size_t width) {
    if (!values.empty() && values.size() != width * vertex_count) {
      throw input_error(path, name + " has " + std::to_string(values.size() / width) + " " + semantic + " values for " +
                                  std::to_string(vertex_count) + " vertices");
    }
    return values;
  };
  vertices.normal = per_vertex(attribute_values<float>(reader, primitive, "NORMAL", 3, name), "NORMAL", 3);
  vertices.uv = per_vertex(attribute_values<float>(reader, primitive, "TEXCOORD_0", 2, name), "TEXCOORD_0", 2);
  // glTF puts the UV origin at the top left; tear's (OBJ's) is at the bottom left.
  for (std::size_t i = 1; i < vertices.uv.size(); i += 2) vertices.uv[i] = 1.0f - vertices.uv[i];
  vertices.velocity = per_vertex(attribute_values<float>(reader, primitive, "_VELOCITY", 3, name), "_VELOCITY", 3);
  if (with_ids) {
    for (double value : per_vertex(attribute_values<double>(reader, primitive, "_ID", 1, name), "_ID", 1)) {
      if (!(value >= 0.0 && value <= static_cast<double>(max_index_count) && value == std::floor(value))) {
        throw input_error(path, name + " has an _ID that is not a node index: " + std::to_string(value));
      }
      vertices.id.push_back(static_cast<index_t>(value));
    }
  }
  return vertices;
}

/// A primitive's indices (glTF's are unsigned bytes, shorts or ints), each checked to name one of
/// its `vertex_count` vertices; without an index accessor, its vertices in order.
std::vector<std::uint32_t> primitive_indices(const std::string& path, const tinygltf::Model& model,
                                             const AccessorReader& reader, const tinygltf::Primitive& primitive,
                                             const std::string& name, std::size_t vertex_count) {
  std::vector<std::uint32_t> indices;
  if (primitive.indices < 0) {
    indices.resize(vertex_count);
    for (std::size_t i = 0; i < vertex_count; ++i) indices[i] = static_cast<std::uint32_t>(i);
    return indices;
  }
  if (primitive.indices >= static_cast<int>(model.accessors.size())) {
    throw input_error(path, name + " uses accessor " + std::to_string(primitive.indices) + ", which does not exist");
  }
  if (model.accessors[primitive.indices].normalized) throw input_error(path, name + " has normalized indices");
  const int type = model.accessors[primitive.indices].componentType;
  if (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
    throw input_error(path, name + " has indices of component type " + std::to_string(type));
  }
  indices = reader.read<std::uint32_t>(primitive.indices, 1, name + " indices");
  for (std::size_t i = 0; i < indices.size(); ++i) {
    if (indices[i] >= vertex_count) {
      throw input_error(path, name + ": index " + std::to_string(indices[i]) + " (number " + std::to_string(i) +
                                  ") is out of range (the primitive has " + std::to_string(vertex_count) +
                                  " vertices)");
    }
  }
  return indices;
}

/// The primitive's triangles as vertex numbers, from its triangle list, strip or fan.
std::vector<index_t> primitive_triangles(const tinygltf::Primitive& primitive,
                                         const std::vector<std::uint32_t>& indices) {
  std::vector<index_t> triangles;
  const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
  triangles.reserve(mode == TINYGLTF_MODE_TRIANGLES ? indices.size() / 3 * 3 : 3 * indices.size());
  auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    triangles.insert(triangles.end(), {static_cast<index_t>(a), static_cast<index_t>(b), static_cast<index_t>(c)});
  };
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    for (std::size_t i = 0; i + 2 < indices.size(); i += 3) add(indices[i], indices[i + 1], indices[i + 2]);
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    // Triangle i is (p_i, p_i+1+i%2, p_i+2-i%2): every other one turned to keep its orientation.
    for (std::size_t i = 0; i + 2 < indices.size(); ++i) {
      add(indices[i], indices[i + 1 + i % 2], indices[i + 2 - i % 2]);
    }
  } else {
    for (std::size_t i = 0; i + 2 < indices.size(); ++i) add(indices[i + 1], indices[i + 2], indices[0]);
  }
  return triangles;
}

/// Primitive `k` of the placement's mesh appended to `out`, placed.
void append_primitive(const std::string& path, const tinygltf::Model& model, const AccessorReader& reader,
                      const Placement& p, std::size_t k, const Channels& with, std::uint64_t max_faces,
                      FileMesh& out) {
  const tinygltf::Mesh& mesh = model.meshes[p.mesh];
  const tinygltf::Primitive& primitive = mesh.primitives[k];
  const std::string name = "mesh " + std::to_string(p.mesh) +
                           (mesh.name.empty() ? std::string() : " ('" + mesh.name + "')") + " primitive " +
                           std::to_string(k);
  const PrimitiveVertices vertices =
      primitive_vertices(path, reader, primitive, name, with.ids, out.mesh.node_pos.size() / 3);
  const std::size_t vertex_count = vertices.position.size() / 3;
  const std::vector<std::uint32_t> indices = primitive_indices(path, model, reader, primitive, name, vertex_count);
  const std::vector<index_t> triangles = primitive_triangles(primitive, indices);
  if (out.mesh.face_nodes.size() + triangles.size() > max_index_count) {
    throw input_error(path, "too large: more than 2^31 face corners");
  }
  // Checked as each placed primitive is added: a few nodes placing a mesh many times over would
  // otherwise multiply its faces without bound before any later check.
  check_face_budget(path, (out.mesh.face_nodes.size() + triangles.size()) / 3, max_faces);

  PlacedTriangles placed;
  placed.vertex_count = static_cast<index_t>(vertex_count);
  placed.vertex_pos = vertices.position.data();
  placed.vertex_normal = vertices.normal.empty() ? nullptr : vertices.normal.data();
  placed.vertex_uv = vertices.uv.empty() ? nullptr : vertices.uv.data();
  placed.vertex_vel = vertices.velocity.empty() ? nullptr : vertices.velocity.data();
  placed.vertex_id = vertices.id.empty() ? nullptr : vertices.id.data();
  placed.triangles = &triangles;
  placed.transform = p.transform;
  append_placed(placed, with.uv, with.normals, with.velocities, with.ids, out);
}

}  // namespace

std::optional<FileMesh> read_gltf_file(const std::string& path, const std::string& bytes,
                                       const std::string& mesh_name, std::uint64_t max_faces) {
  const std::optional<tinygltf::Model> model = load_model(path, bytes);
  if (!model) return std::nullopt;
  const std::vector<Placement> placements = scene_placements(path, *model, mesh_name);
  const Channels with = channels_of(*model, placements);
  const AccessorReader reader(path, *model, bytes.size());
  FileMesh out;
  for (const Placement& p : placements) {
    const tinygltf::Mesh& mesh = model->meshes[p.mesh];
    for (std::size_t k = 0; k < mesh.primitives.size(); ++k) {
      const tinygltf::Primitive& primitive = mesh.primitives[k];
      if (!is_triangles(primitive) || !primitive.attributes.count("POSITION")) continue;
      append_primitive(path, *model, reader, p, k, with, max_faces, out);
    }
  }
  return out;
}

}  // namespace tear
