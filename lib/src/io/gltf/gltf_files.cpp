// tear: the files a glTF names, checked and read for tinygltf, and what is left to assimp checked
// first (read_gltf.cpp).
#include "io/gltf/gltf_files.h"

#include <limits.h>
#include <stdlib.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "tear/error.h"
#include "tear/input_file.h"

namespace tear::gltf {
namespace {

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

}  // namespace

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

}  // namespace tear::gltf
