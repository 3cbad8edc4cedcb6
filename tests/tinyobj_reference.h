// tear tests: the OBJ reader tear had before its own parser, through tinyobjloader's callback
// API, as the reference `read_obj_file` must match bit for bit, errors included.
#pragma once

#include <string>

#include "io/mesh/file_mesh.h"

namespace tear {

/// What `read_obj_file(path, text, mesh_name)` returned when tinyobjloader read OBJ files: the
/// same mesh, or an input `Error` with the same message.
FileMesh read_obj_with_tinyobjloader(const std::string& path, std::string text, const std::string& mesh_name);

}  // namespace tear
