// glTF and GLB through tinygltf (Debian's libtinygltf), which hands over the document as it is:
// every primitive's own vertex arrays in order, the application attributes (`_ID`, `_VELOCITY`)
// that assimp drops, and nothing merged or reordered. tinygltf checks the JSON and the buffers'
// declared lengths; the GLB container and every accessor's range are checked here, before any
// value is read, and an index out of range is an error (assimp drops such faces).
#include <limits.h>
#include <stdlib.h>
#include <sys/stat.h>
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

/// tinygltf's messages span lines and end with periods, and quote a buffer's `uri` whole (a
/// data URI of megabytes); ours are one line of at most a few hundred characters.
std::string one_line(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  std::replace(text.begin(), text.end(), '\r', ' ');
  while (!text.empty() && (text.back() == ' ' || text.back() == '.')) text.pop_back();
  constexpr std::size_t longest = 160;
  if (text.size() > longest) text = text.substr(0, longest) + "...";
  return text;
}

// External files (`uri` of buffers and images). A glTF names its own files, so a uri is confined
// to the folder of the glTF and below: after percent-decoding, no URL scheme (`file:`), no
// absolute path, no `..`; the path resolved (symbolic links followed) must stay inside the folder
// and be a regular file within --max-input-bytes. Each is checked before tinygltf reads anything,
// and tinygltf reads through callbacks that open only the files checked (never the current
// folder, its fallback). Messages name the glTF and the buffer or image, never the target.

/// tinygltf's decoding of a uri (dlib's urldecode): %XX and '+' for a space.
std::string decode_uri(const std::string& uri) {
  auto hex = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return 0;
  };
  std::string out;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '+') {
      out += ' ';
    } else if (uri[i] == '%' && uri.size() > i + 2) {
      out += static_cast<char>((hex(uri[i + 1]) << 4) | hex(uri[i + 2]));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

/// tinygltf's JoinPath.
std::string join_path(const std::string& folder, const std::string& name) {
  if (folder.empty()) return name;
  return folder.back() == '/' ? folder + name : folder + "/" + name;
}

std::string real_path(const std::string& path) {
  char resolved[PATH_MAX];
  if (::realpath(path.c_str(), resolved) == nullptr) return {};
  return resolved;
}

/// The files a glTF may read: the path tinygltf asks for, the file it resolves to, and whether
/// to read it (buffers) or not (images, which tear does not decode).
struct ExternalFiles {
  std::string gltf;
  std::map<std::string, std::pair<std::string, bool>> allowed;
};

/// Checks the uri of the buffer, image or shader `name` ("buffer 0"; glTF 1.0 names them: "buffer
/// b") and adds it to `files`; a buffer's file must have `byte_length` bytes where that is known.
void allow_uri(const std::string& base_dir, const std::string& kind, const std::string& name, const std::string& uri,
               std::optional<std::uint64_t> byte_length, ExternalFiles& files) {
  const std::string& path = files.gltf;
  const std::string decoded = decode_uri(uri);
  auto refuse = [&](const std::string& why) { return input_error(path, name + ": " + why); };
  const std::string rule = "a uri must be a relative path to a file in the folder of the glTF or below";
  std::string target;
  switch (confine_file(base_dir, decoded, target)) {
    case Confined::not_relative:
      throw refuse("the uri is not a relative path (" + rule + ")");
    case Confined::goes_up:
      throw refuse("the uri goes up with '..' (" + rule + ")");
    case Confined::not_a_file_inside:
      throw refuse("the uri does not name a regular file in the folder of the glTF or below (" + rule + ")");
    case Confined::ok:
      break;
  }
  const std::string asked = join_path(base_dir, decoded);
  struct stat s {};
  if (::stat(target.c_str(), &s) != 0 || !S_ISREG(s.st_mode))
    throw refuse("the uri does not name a regular file in the folder of the glTF or below (" + rule + ")");
  if (static_cast<std::uint64_t>(s.st_size) > max_input_bytes())
    throw refuse("its file is over the limit of " + std::to_string(max_input_bytes()) + " bytes (--max-input-bytes)");
  if (kind == "buffer" && byte_length && static_cast<std::uint64_t>(s.st_size) != *byte_length)
    throw refuse("its file does not have the buffer's byteLength of " + std::to_string(*byte_length) + " bytes");
  auto& entry = files.allowed[asked];
  entry.first = target;
  entry.second = entry.second || kind == "buffer";
}

/// Every external uri of the document in `json` checked (data: URIs are tinygltf's to decode):
/// glTF 2.0's arrays of buffers and images, and glTF 1.0's objects of named buffers, images and
/// shaders, whose files assimp would otherwise be the first to look for (it reads glTF 1.0).
ExternalFiles external_files(const std::string& path, const nlohmann::json& document) {
  ExternalFiles files;
  files.gltf = path;
  if (!document.is_object()) return files;  // tinygltf says what is wrong
  const std::string base_dir = std::filesystem::path(path).parent_path().string();
  const auto check = [&](const std::string& kind, const std::string& name, const nlohmann::json& item, bool glTF2) {
    if (!item.is_object()) return;
    const auto uri = item.find("uri");
    if (uri == item.end() || !uri->is_string()) return;
    const std::string& text = uri->get_ref<const std::string&>();
    if (text.empty() || text.compare(0, 5, "data:") == 0) return;
    // A glTF 2.0 buffer's file has its byteLength (a missing one reads as 0); glTF 1.0's are
    // assimp's to check.
    std::optional<std::uint64_t> byte_length;
    if (glTF2) {
      const auto length = item.find("byteLength");
      byte_length = length != item.end() && length->is_number_unsigned() ? length->get<std::uint64_t>() : 0;
    }
    allow_uri(base_dir, kind, kind + " " + name, text, byte_length, files);
  };
  const std::pair<const char*, std::string> lists[] = {{"buffers", "buffer"}, {"images", "image"}, {"shaders", "shader"}};
  for (const auto& [list_name, kind] : lists) {
    const auto list = document.find(list_name);
    if (list == document.end()) continue;
    if (list->is_array() && kind != "shader") {
      for (std::size_t i = 0; i < list->size(); ++i) check(kind, std::to_string(i), (*list)[i], true);
    } else if (list->is_object()) {
      for (const auto& item : list->items()) check(kind, one_line(item.key()), item.value(), false);
    }
  }
  return files;
}

bool external_file_exists(const std::string& asked, void* user) {
  return static_cast<const ExternalFiles*>(user)->allowed.count(asked) != 0;
}

std::string keep_path(const std::string& path, void*) { return path; }

bool read_external_file(std::vector<unsigned char>* out, std::string* error, const std::string& asked, void* user) {
  const ExternalFiles& files = *static_cast<const ExternalFiles*>(user);
  const auto found = files.allowed.find(asked);
  if (found == files.allowed.end() || !found->second.second) {
    *error = "not read";
    return false;
  }
  if (real_path(asked) != found->second.first) throw input_error(files.gltf, "a file it names changed while it was read");
  const std::string bytes = read_input_file(found->second.first, "a file of " + files.gltf);
  out->assign(bytes.begin(), bytes.end());
  return true;
}

bool write_nothing(std::string* error, const std::string&, const std::vector<unsigned char>&, void*) {
  *error = "not written";
  return false;
}

using gltf::AccessorReader;

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

/// What assimp is left to read (glTF 1.0, Draco-compressed meshes), checked where its importers
/// trust the file: a line strip, triangle strip or fan of fewer vertices than one segment or
/// triangle needs made them allocate for 2^32 faces (counted as count - 1 or count - 2, unsigned):
/// tens of GB. `glTF1`: the document must be a glTF 1.0 (tinygltf refused its "asset"); anything
/// else is bad input with tinygltf's `error`.
void check_left_to_assimp(const std::string& path, const nlohmann::json& document, bool glTF1,
                          const std::string& error) {
  const auto member = [](const nlohmann::json& object, const char* name) -> const nlohmann::json* {
    if (!object.is_object()) return nullptr;
    const auto it = object.find(name);
    return it == object.end() ? nullptr : &*it;
  };
  if (glTF1) {
    const nlohmann::json* asset = member(document, "asset");
    const nlohmann::json* version = asset ? member(*asset, "version") : nullptr;
    if (!version || !version->is_string() || version->get_ref<const std::string&>().compare(0, 1, "1") != 0)
      throw input_error(path, "cannot read as glTF: " + one_line(error.empty() ? "malformed" : error));
  }
  if (!document.is_object()) throw input_error(path, "cannot read as glTF: its JSON is malformed");
  // glTF 1.0 names its meshes and accessors (objects), 2.0 numbers them (arrays).
  const auto find = [](const nlohmann::json* list, const nlohmann::json* key) -> const nlohmann::json* {
    if (!list || !key) return nullptr;
    if (list->is_array() && key->is_number_unsigned() && key->get<std::uint64_t>() < list->size())
      return &(*list)[key->get<std::size_t>()];
    if (list->is_object() && key->is_string()) {
      const auto it = list->find(key->get_ref<const std::string&>());
      if (it != list->end()) return &*it;
    }
    return nullptr;
  };
  const nlohmann::json* meshes = member(document, "meshes");
  const nlohmann::json* accessors = member(document, "accessors");
  if (!meshes || !(meshes->is_array() || meshes->is_object())) return;
  std::size_t index = 0;
  for (const auto& item : meshes->items()) {
    const std::string mesh = meshes->is_array() ? std::to_string(index++) : one_line(item.key());
    const nlohmann::json* primitives = member(item.value(), "primitives");
    if (!primitives || !primitives->is_array()) continue;
    for (std::size_t p = 0; p < primitives->size(); ++p) {
      const nlohmann::json& primitive = (*primitives)[p];
      const nlohmann::json* mode = member(primitive, "mode");
      const std::int64_t kind = mode && mode->is_number_integer() ? mode->get<std::int64_t>() : 4;
      if (kind != 3 && kind != 5 && kind != 6) continue;  // LINE_STRIP, TRIANGLE_STRIP, TRIANGLE_FAN
      const nlohmann::json* attributes = member(primitive, "attributes");
      const nlohmann::json* key = member(primitive, "indices");
      if (!key && attributes) key = member(*attributes, "POSITION");
      const nlohmann::json* accessor = find(accessors, key);
      const nlohmann::json* count = accessor ? member(*accessor, "count") : nullptr;
      const std::uint64_t vertices = count && count->is_number_unsigned() ? count->get<std::uint64_t>() : 0;
      const std::uint64_t needed = kind == 3 ? 2 : 3;
      if (vertices < needed)
        throw input_error(path, "mesh " + mesh + ", primitive " + std::to_string(p) + ": a " +
                                    (kind == 3 ? "line strip" : kind == 5 ? "triangle strip" : "triangle fan") + " of " +
                                    std::to_string(vertices) + " vertices (it needs " + std::to_string(needed) + ")");
    }
  }
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
  ExternalFiles files = external_files(path, document);
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(skip_image, nullptr);
  loader.SetFsCallbacks({external_file_exists, keep_path, read_external_file, write_nothing, &files});
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
