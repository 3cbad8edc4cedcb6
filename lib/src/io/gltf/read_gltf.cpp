// glTF and GLB through tinygltf (Debian's libtinygltf), which hands over the document as it is:
// every primitive's own vertex arrays in order, the application attributes (`_ID`, `_VELOCITY`)
// that assimp drops, and nothing merged or reordered. tinygltf checks the JSON and the buffers'
// declared lengths; the GLB container and every accessor's range are checked here, before any
// value is read, and an index out of range is an error (assimp drops such faces).
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "io/mesh/file_mesh.h"
#include "tear/error.h"

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

/// How deep arrays and objects nest in the JSON text (strings skipped). tinygltf converts
/// `extras` recursively, so a file of a few hundred kilobytes of `[[[[...` would overflow the
/// stack; glTF documents nest a few levels.
std::size_t json_depth(const char* text, std::size_t size) {
  std::size_t depth = 0, deepest = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < size; ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return deepest;
}

constexpr std::size_t max_json_depth = 256;

/// Images are of no use to cloth: they are not decoded.
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

/// tinygltf's messages span lines and end with periods; ours are one line.
std::string one_line(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  std::replace(text.begin(), text.end(), '\r', ' ');
  while (!text.empty() && (text.back() == ' ' || text.back() == '.')) text.pop_back();
  return text;
}

/// Reads accessors with every range checked against the buffers first.
class AccessorReader {
 public:
  AccessorReader(const std::string& path, const tinygltf::Model& model, std::size_t file_size)
      : path_(path), model_(model), file_size_(file_size) {}

  /// `count * components` values of accessor `index` as `T`, normalized integers mapped to [0, 1]
  /// or [-1, 1] as glTF defines them (computed in double, then converted: a float component read as
  /// float is the float in the file). `what` names it in messages.
  template <class T>
  std::vector<T> read(int index, int components, const std::string& what) const {
    if (index < 0 || static_cast<std::size_t>(index) >= model_.accessors.size()) {
      throw fail(what + " uses accessor " + std::to_string(index) + ", which does not exist");
    }
    const tinygltf::Accessor& accessor = model_.accessors[index];
    const std::string name = what + " (accessor " + std::to_string(index) + ")";
    const int type_components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(accessor.type));
    if (type_components != components) {
      throw fail(name + " has " + std::to_string(type_components) + " components, expected " +
                 std::to_string(components));
    }
    const int component_size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(accessor.componentType));
    if (component_size <= 0 || accessor.componentType == TINYGLTF_COMPONENT_TYPE_INT ||
        accessor.componentType == TINYGLTF_COMPONENT_TYPE_DOUBLE) {
      throw fail(name + " has the unknown component type " + std::to_string(accessor.componentType));
    }
    const std::uint64_t count = accessor.count;
    if (count > max_index_count) throw fail(name + " has too many elements (" + std::to_string(count) + ")");
    const std::uint64_t element_size = static_cast<std::uint64_t>(component_size) * components;

    std::vector<T> values;
    if (accessor.bufferView < 0) {
      // No data: zeros (to be replaced by sparse values). Bounded by the file's size so that a
      // tiny file cannot ask for gigabytes.
      if (count > file_size_) throw fail(name + " has " + std::to_string(count) + " elements and no data");
      values.assign(count * components, T(0));
    } else {
      std::uint64_t stride = 0;
      const unsigned char* data =
          view_data(accessor.bufferView, accessor.byteOffset, count, element_size, &stride, name);
      values.resize(count * components);
      if (std::is_same<T, float>::value && accessor.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) {
        // Floats as they are in the file: whole when tightly packed, else element by element.
        if (stride == element_size) {
          if (count > 0) std::memcpy(values.data(), data, count * element_size);
        } else {
          for (std::uint64_t i = 0; i < count; ++i) std::memcpy(&values[i * components], data + i * stride, element_size);
        }
      } else {
        for (std::uint64_t i = 0; i < count; ++i) {
          for (int k = 0; k < components; ++k) {
            values[i * components + k] = static_cast<T>(component(data + i * stride + k * component_size, accessor));
          }
        }
      }
    }

    if (accessor.sparse.isSparse) {
      const auto& sparse = accessor.sparse;
      if (sparse.count < 0 || static_cast<std::uint64_t>(sparse.count) > count) {
        throw fail(name + " has " + std::to_string(sparse.count) + " sparse values for " + std::to_string(count) +
                   " elements");
      }
      const std::uint64_t sparse_count = static_cast<std::uint64_t>(sparse.count);
      const int index_size =
          tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(sparse.indices.componentType));
      if (sparse.indices.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
          sparse.indices.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
          sparse.indices.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
        throw fail(name + " has sparse indices of component type " + std::to_string(sparse.indices.componentType));
      }
      if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0)
        throw fail(name + " has a negative sparse offset");
      std::uint64_t index_stride = 0, value_stride = 0;
      const unsigned char* indices =
          view_data(sparse.indices.bufferView, static_cast<std::size_t>(sparse.indices.byteOffset), sparse_count,
                    index_size, &index_stride, name + " sparse indices");
      const unsigned char* data =
          view_data(sparse.values.bufferView, static_cast<std::size_t>(sparse.values.byteOffset), sparse_count,
                    element_size, &value_stride, name + " sparse values");
      // Sparse data is tightly packed whatever the views' strides say.
      index_stride = index_size;
      value_stride = element_size;
      for (std::uint64_t s = 0; s < sparse_count; ++s) {
        std::uint32_t target = 0;
        if (index_size == 1) target = indices[s];
        if (index_size == 2) {
          std::uint16_t v;
          std::memcpy(&v, indices + 2 * s, 2);
          target = v;
        }
        if (index_size == 4) std::memcpy(&target, indices + 4 * s, 4);
        if (target >= count) {
          throw fail(name + " has the sparse index " + std::to_string(target) + " of " + std::to_string(count) +
                     " elements");
        }
        for (int k = 0; k < components; ++k) {
          values[static_cast<std::size_t>(target) * components + k] =
              static_cast<T>(component(data + s * value_stride + k * component_size, accessor));
        }
      }
      (void)index_stride;
    }
    return values;
  }

  Error fail(const std::string& what) const { return input_error(path_, what); }

 private:
  /// The bytes of `count` elements of `element_size` at `offset` in buffer view `view_index`, all
  /// of them inside the view and the view inside its buffer.
  const unsigned char* view_data(int view_index, std::size_t offset, std::uint64_t count, std::uint64_t element_size,
                                 std::uint64_t* stride, const std::string& name) const {
    if (view_index < 0 || static_cast<std::size_t>(view_index) >= model_.bufferViews.size()) {
      throw fail(name + " uses buffer view " + std::to_string(view_index) + ", which does not exist");
    }
    const tinygltf::BufferView& view = model_.bufferViews[view_index];
    if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model_.buffers.size()) {
      throw fail("buffer view " + std::to_string(view_index) + " uses buffer " + std::to_string(view.buffer) +
                 ", which does not exist");
    }
    const std::vector<unsigned char>& buffer = model_.buffers[view.buffer].data;
    const std::uint64_t view_offset = view.byteOffset, view_length = view.byteLength;
    if (view_offset > buffer.size() || view_length > buffer.size() - view_offset) {
      throw fail("buffer view " + std::to_string(view_index) + " (bytes " + std::to_string(view_offset) + " + " +
                 std::to_string(view_length) + ") reaches past the end of its buffer of " +
                 std::to_string(buffer.size()) + " bytes");
    }
    *stride = view.byteStride ? view.byteStride : element_size;
    if (*stride < element_size) {
      throw fail(name + ": buffer view " + std::to_string(view_index) + " has a stride of " + std::to_string(*stride) +
                 " bytes, less than an element's " + std::to_string(element_size));
    }
    if (count > 0) {
      // offset + stride * (count - 1) + element_size <= view_length, without overflow.
      const std::uint64_t last = count - 1;
      const bool fits = offset <= view_length && element_size <= view_length - offset &&
                        (last == 0 || *stride <= (view_length - offset - element_size) / last);
      if (!fits) {
        throw fail(name + ": " + std::to_string(count) + " elements at offset " + std::to_string(offset) +
                   " reach past the end of buffer view " + std::to_string(view_index) + " (" +
                   std::to_string(view_length) + " bytes)");
      }
    }
    return buffer.data() + view_offset + offset;
  }

  static double component(const unsigned char* at, const tinygltf::Accessor& accessor) {
    const bool normalized = accessor.normalized;
    switch (accessor.componentType) {
      case TINYGLTF_COMPONENT_TYPE_BYTE: {
        const double v = static_cast<std::int8_t>(*at);
        return normalized ? std::max(v / 127.0, -1.0) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return normalized ? *at / 255.0 : *at;
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        std::int16_t v;
        std::memcpy(&v, at, 2);
        return normalized ? std::max(v / 32767.0, -1.0) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t v;
        std::memcpy(&v, at, 2);
        return normalized ? v / 65535.0 : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        std::uint32_t v;
        std::memcpy(&v, at, 4);
        return normalized ? v / 4294967295.0 : v;
      }
      case TINYGLTF_COMPONENT_TYPE_FLOAT: {
        float v;
        std::memcpy(&v, at, 4);
        return v;
      }
    }
    return 0.0;
  }

  const std::string& path_;
  const tinygltf::Model& model_;
  std::size_t file_size_;
};

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

}  // namespace

std::optional<FileMesh> read_gltf_file(const std::string& path, const std::string& bytes,
                                       const std::string& mesh_name) {
  const bool binary = bytes.compare(0, 4, "glTF") == 0;
  // glTF 1.0 (another schema, which tinygltf does not read) is left to assimp.
  if (binary && bytes.size() >= 8 && read_u32(bytes, 4) == 1) return std::nullopt;
  if (binary) check_glb(path, bytes);
  if (bytes.size() > std::numeric_limits<unsigned int>::max())
    throw input_error(path, "too large for glTF (4 GiB or more)");

  const std::size_t json_begin = binary ? 20 : 0;
  const std::size_t json_size = binary ? read_u32(bytes, 12) : bytes.size();
  if (json_depth(bytes.data() + json_begin, json_size) > max_json_depth) {
    throw input_error(path, "glTF JSON nests deeper than " + std::to_string(max_json_depth) + " levels");
  }

  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(skip_image, nullptr);
  tinygltf::Model model;
  std::string error, warning;
  const std::string base_dir = std::filesystem::path(path).parent_path().string();
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const unsigned int size = static_cast<unsigned int>(binary ? read_u32(bytes, 8) : bytes.size());
  const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &error, &warning, data, size, base_dir)
                         : loader.LoadASCIIFromString(&model, &error, &warning, bytes.data(), size, base_dir);
  if (!ok && error.find("\"asset\"") != std::string::npos) return std::nullopt;
  // Draco-compressed meshes are decoded by assimp (tinygltf is built without Draco here).
  if (bytes.find("KHR_draco_mesh_compression") != std::string::npos) return std::nullopt;
  if (!ok) throw input_error(path, "cannot read as glTF: " + one_line(error.empty() ? "malformed" : error));
  if (model.asset.version.compare(0, 1, "2") != 0) return std::nullopt;

  for (const char* extension : {"EXT_meshopt_compression", "KHR_meshopt_compression"}) {
    if (std::find(model.extensionsUsed.begin(), model.extensionsUsed.end(), extension) != model.extensionsUsed.end()) {
      throw input_error(path, std::string("uses ") + extension + ", which tear does not read");
    }
  }

  // The scene's nodes, each placing its mesh with the product of the transforms above it.
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

  // Ids weld nodes only when every primitive has them and no mesh that has them is placed twice
  // (its two copies would carry the same ids).
  bool with_uv = false, with_normals = false, with_velocities = false, with_ids = !placements.empty();
  std::map<int, int> placement_count;
  for (const Placement& p : placements) ++placement_count[p.mesh];
  for (const Placement& p : placements) {
    for (const tinygltf::Primitive& primitive : model.meshes[p.mesh].primitives) {
      if (!is_triangles(primitive) || !primitive.attributes.count("POSITION")) continue;
      with_uv = with_uv || primitive.attributes.count("TEXCOORD_0");
      with_normals = with_normals || primitive.attributes.count("NORMAL");
      with_velocities = with_velocities || primitive.attributes.count("_VELOCITY");
      with_ids = with_ids && primitive.attributes.count("_ID") && placement_count[p.mesh] == 1;
    }
  }

  const AccessorReader reader(path, model, bytes.size());
  FileMesh out;
  for (const Placement& p : placements) {
    const tinygltf::Mesh& mesh = model.meshes[p.mesh];
    for (std::size_t k = 0; k < mesh.primitives.size(); ++k) {
      const tinygltf::Primitive& primitive = mesh.primitives[k];
      if (!is_triangles(primitive) || !primitive.attributes.count("POSITION")) continue;
      const std::string name = "mesh " + std::to_string(p.mesh) +
                               (mesh.name.empty() ? std::string() : " ('" + mesh.name + "')") + " primitive " +
                               std::to_string(k);
      auto attribute = [&](const char* semantic, int components, auto zero) {
        using T = decltype(zero);
        const auto found = primitive.attributes.find(semantic);
        if (found == primitive.attributes.end()) return std::vector<T>();
        return reader.read<T>(found->second, components, name + " " + semantic);
      };
      const std::vector<float> position = attribute("POSITION", 3, 0.0f);
      const std::size_t vertex_count = position.size() / 3;
      if (out.mesh.node_pos.size() / 3 + vertex_count > max_index_count) {
        throw input_error(path, "too large: more than 2^31 vertices");
      }
      auto per_vertex = [&](auto values, const char* semantic, std::size_t width) {
        if (!values.empty() && values.size() != width * vertex_count) {
          throw input_error(path, name + " has " + std::to_string(values.size() / width) + " " + semantic +
                                      " values for " + std::to_string(vertex_count) + " vertices");
        }
        return values;
      };
      const std::vector<float> normal = per_vertex(attribute("NORMAL", 3, 0.0f), "NORMAL", 3);
      std::vector<float> uv = per_vertex(attribute("TEXCOORD_0", 2, 0.0f), "TEXCOORD_0", 2);
      // glTF puts the UV origin at the top left; tear's (OBJ's) is at the bottom left.
      for (std::size_t i = 1; i < uv.size(); i += 2) uv[i] = 1.0f - uv[i];
      const std::vector<float> velocity = per_vertex(attribute("_VELOCITY", 3, 0.0f), "_VELOCITY", 3);
      std::vector<index_t> id;
      if (with_ids) {
        for (double value : per_vertex(attribute("_ID", 1, 0.0), "_ID", 1)) {
          if (!(value >= 0.0 && value <= static_cast<double>(max_index_count) && value == std::floor(value))) {
            throw input_error(path, name + " has an _ID that is not a node index: " + std::to_string(value));
          }
          id.push_back(static_cast<index_t>(value));
        }
      }

      std::vector<std::uint32_t> indices;  // glTF's indices are unsigned bytes, shorts or ints
      if (primitive.indices >= 0) {
        if (primitive.indices >= static_cast<int>(model.accessors.size())) {
          throw input_error(path,
                            name + " uses accessor " + std::to_string(primitive.indices) + ", which does not exist");
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
            throw input_error(path, name + ": index " + std::to_string(indices[i]) +
                                        " (number " + std::to_string(i) + ") is out of range (the primitive has " +
                                        std::to_string(vertex_count) + " vertices)");
          }
        }
      } else {
        indices.resize(vertex_count);
        for (std::size_t i = 0; i < vertex_count; ++i) indices[i] = static_cast<std::uint32_t>(i);
      }

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
      if (out.mesh.face_nodes.size() + triangles.size() > max_index_count) {
        throw input_error(path, "too large: more than 2^31 face corners");
      }

      PlacedTriangles placed;
      placed.vertex_count = static_cast<index_t>(vertex_count);
      placed.vertex_pos = position.data();
      placed.vertex_normal = normal.empty() ? nullptr : normal.data();
      placed.vertex_uv = uv.empty() ? nullptr : uv.data();
      placed.vertex_vel = velocity.empty() ? nullptr : velocity.data();
      placed.vertex_id = id.empty() ? nullptr : id.data();
      placed.triangles = &triangles;
      placed.transform = p.transform;
      append_placed(placed, with_uv, with_normals, with_velocities, with_ids, out);
    }
  }
  return out;
}

}  // namespace tear
