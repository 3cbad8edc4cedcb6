// tear: exporting a mesh as OBJ, PLY, glTF or GLB, atomically and byte-reproducibly.
#pragma once

#include <string>

#include "tear/mesh.h"

namespace tear {

enum class MeshFormat { obj, ply, gltf, glb };

/// The format named by the file's extension (.obj, .ply, .gltf, .glb; case-insensitive);
/// throws a usage `Error` for any other.
MeshFormat format_from_path(const std::string& path);

/// Writes `mesh` to `path` in `format`: to a temporary file beside it, then renamed, so a reader
/// never sees a half-written file. Floats are printed with 9 significant digits (they read back
/// to the same float), so the same mesh always gives the same bytes.
///
/// - OBJ: `v`, `vt`, `vn` and `f v/vt/vn` with per-corner indices (UVs and normals deduplicated
///   by value, in order of first use).
/// - PLY (binary little endian): positions and faces over the welded nodes; per-corner UVs as the
///   face property `texcoord` (6 floats), normals per node (area-weighted mean of the corners).
/// - glTF/GLB: one mesh, one primitive with POSITION, NORMAL and TEXCOORD_0; nodes are split where
///   their corners disagree on UV or normal (glTF has no per-corner indices). A `.gltf` embeds its
///   buffer as a data URI, so the frame is one file.
///
/// Throws a runtime `Error` naming the file when it cannot be written.
void write_mesh(const Mesh& mesh, const std::string& path);
void write_mesh(const Mesh& mesh, const std::string& path, MeshFormat format);

/// Writes `text` to `path` atomically (temporary file beside it, then rename). Throws a runtime
/// `Error` naming the file on failure.
void write_file_atomically(const std::string& path, const std::string& text);

}  // namespace tear
