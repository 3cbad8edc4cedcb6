#include <cctype>
#include <string>

#include "tear/error.h"
#include "tear/write_mesh.h"

namespace tear {

MeshFormat format_from_path(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  std::string extension;
  if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) extension = path.substr(dot + 1);
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension == "obj") return MeshFormat::obj;
  if (extension == "ply") return MeshFormat::ply;
  if (extension == "gltf") return MeshFormat::gltf;
  if (extension == "glb") return MeshFormat::glb;
  throw Error(ErrorKind::usage, path + ": unknown mesh format" +
                                    (extension.empty() ? std::string(" (no extension)") : " '." + extension + "'") +
                                    "; supported: .obj, .ply, .gltf, .glb");
}

}  // namespace tear
