// tear tests: the encoders tear had before a frame was encoded in parallel, as the reference the
// parallel ones must match byte for byte.
#pragma once

#include <string>

#include "tear/mesh.h"
#include "tear/write_mesh.h"

namespace tear {

/// The bytes `encode_mesh` gave for `mesh` in `format` when it ran on one thread, one value after
/// another. `mesh` must be one `encode_mesh` accepts (its arrays match).
std::string encode_mesh_reference(const Mesh& mesh, MeshFormat format);

}  // namespace tear
