// tear: the files a glTF names (buffers, images, shaders), confined to its folder and read for
// tinygltf through these callbacks only, and the checks of what is left to assimp (glTF 1.0,
// Draco-compressed meshes) made before assimp reads it. For read_gltf.cpp.
#pragma once

#include <nlohmann/json.hpp>

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace tear::gltf {

/// tinygltf's messages span lines and end with periods, and quote a buffer's `uri` whole (a
/// data URI of megabytes); ours are one line of at most a few hundred characters.
std::string one_line(std::string text);

/// The files a glTF may read: the path tinygltf asks for, the file it resolves to, and whether
/// to read it (buffers) or not (images, which tear does not decode).
struct ExternalFiles {
  std::string gltf;
  std::map<std::string, std::pair<std::string, bool>> allowed;
};

/// Every external uri of the document checked (data: URIs are tinygltf's to decode): glTF 2.0's
/// arrays of buffers and images, glTF 1.0's objects of named buffers, images and shaders. A uri
/// refused is an input error naming the glTF and the key.
ExternalFiles external_files(const std::string& path, const nlohmann::json& document);

/// tinygltf's file callbacks over `ExternalFiles` (its `user` pointer): only the files checked
/// exist, buffers are read (the file must still be the one checked), nothing is written.
bool external_file_exists(const std::string& asked, void* user);
std::string keep_path(const std::string& path, void*);
bool read_external_file(std::vector<unsigned char>* out, std::string* error, const std::string& asked, void* user);
bool write_nothing(std::string* error, const std::string&, const std::vector<unsigned char>&, void*);

/// What assimp is left to read, checked where its importers trust the file (gltf_files.cpp).
/// `glTF1`: the document must be a glTF 1.0; anything else is bad input with tinygltf's `error`.
void check_left_to_assimp(const std::string& path, const nlohmann::json& document, bool glTF1,
                          const std::string& error);

}  // namespace tear::gltf
