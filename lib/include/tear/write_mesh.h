// tear: exporting a mesh as OBJ, PLY, glTF or GLB, atomically and byte-reproducibly.
#pragma once

#include <string>

#include "tear/mesh.h"
#include "tear/output_files.h"

namespace tear {

enum class MeshFormat { obj, ply, gltf, glb };

/// The format named by the file's extension (.obj, .ply, .gltf, .glb; case-insensitive);
/// throws a usage `Error` naming the path and the supported extensions for any other.
MeshFormat format_from_path(const std::string& path);

/// Writes `mesh` to `path` in `format` (the first overload takes it from the extension): to a
/// temporary file beside it (`.<name>.tmp.<pid>.<16 hex digits>`, locked while written), then renamed, so a reader never sees a
/// half-written file. The same mesh always gives the same bytes.
///
/// - OBJ: a `# tear` header line, `v` for every node (node `i` is `v` number `i + 1`), `vt` and
///   `vn` deduplicated by exact value in order of first use, and `f v/vt/vn` per face (`f v//vn`,
///   `f v/vt` or `f v` when UVs or normals are missing). No .mtl file. Floats are printed with
///   `%.9g` (they read back to the same float), except magnitudes below 1e-4, printed in fixed
///   notation with 15 decimals when that reads back to the same float: fast OBJ parsers
///   (assimp's among them) round numbers with an exponent inexactly, fixed notation they read
///   exactly (below about 1e-7 15 decimals are too few and `%.9g` is kept).
/// - PLY and glTF/GLB have no per-corner indices, so nodes whose corners disagree on UV or normal
///   are split (docs/io.md): vertex `i` is node `i` for every `i < node_count`, with the UV and
///   normal of the node's first corner; each other distinct (UV, normal) of a node gets a vertex
///   after all the nodes, in the order of the corners that first use it. Attributes are compared
///   as numbers (-0 == +0), so equal ones never split a node. A node no face uses gets UV (0, 0)
///   and normal (0, 0, 0).
/// - PLY: binary little endian, vertex properties `x y z`, then `nx ny nz` and `s t` when the mesh
///   has them, then identity: `id` (int, the node), `vx vy vz` (float, m/s; 0 when the mesh has no
///   velocities), `origin_face` (int, -1 when unknown), `origin_u origin_v` (float, 0 when
///   unknown); faces are `vertex_indices` lists; an `edge` element (`vertex1 vertex2`, int) lists
///   `torn_edge_nodes` when there are any. Reading it back welds by `id`: node i is node i again.
/// - glTF/GLB: one scene, one node, one mesh, one primitive (triangles) with POSITION (with
///   min/max), NORMAL and TEXCOORD_0 (those the mesh has), `_ID` (SCALAR FLOAT, the node; left out
///   for meshes of more than 2^24 nodes, which a float cannot number exactly), `_VELOCITY` (VEC3
///   FLOAT, m/s, 0 without velocities) and UNSIGNED_INT indices. glTF puts the UV origin at the top
///   left, so `v` is written as `1 - v` (readers flip it back). A `.gltf` embeds its buffer as a
///   base64 data URI, so a frame is one file; a `.glb` is the binary container.
///
/// Throws a runtime `Error` ("<path>: cannot write: <reason>") when the file cannot be written,
/// leaving no temporary file behind.
void write_mesh(const Mesh& mesh, const std::string& path);
void write_mesh(const Mesh& mesh, const std::string& path, MeshFormat format);

/// How `encode_mesh` spreads one frame over threads. The bytes do not depend on either field.
struct EncodeOptions {
  /// Threads of the OpenMP team that encodes the frame; 0: `omp_get_max_threads()` on the calling
  /// thread (OMP_NUM_THREADS, else the hardware threads; a `FrameWriter` thread's own share,
  /// tear/frame_writer.h).
  int threads = 0;
  /// A frame of fewer faces and fewer nodes than this is encoded on the calling thread alone:
  /// starting a team for each of its loops would cost about what the threads save (a team of 2
  /// gains from about 1,000 faces, and larger teams start slower). 0 runs every frame in pieces,
  /// as tests do to reach the parallel path with small meshes.
  index_t parallel_from = 4096;
};

/// The bytes `write_mesh` writes for `mesh` in `format`, in `bytes`: its contents are replaced and
/// its memory kept, so a writer that encodes frame after frame into the same buffer allocates
/// little. A mesh whose arrays do not match is a runtime `Error` "<path>: cannot write: <what>"
/// (`path` only names it; nothing is written).
void encode_mesh(const Mesh& mesh, const std::string& path, MeshFormat format, std::string& bytes,
                 const EncodeOptions& options = {});

/// Writes `text` (any bytes) to `path` atomically: to its temporary file in the same directory
/// (`create_temporary_file`, locked until the rename), then `rename`d over `path`. On failure the temporary file is removed and a runtime `Error`
/// "<path>: cannot write: <reason>" is thrown.
void write_file_atomically(const std::string& path, const std::string& text);

/// A file written whole under its temporary name beside `path` and not yet renamed to it: the
/// two halves of `write_file_atomically` apart, so that files written side by side on several
/// threads can be renamed in an order of the caller's (tear/frame_writer.h).
struct TemporaryFile {
  std::string path;        ///< where the file goes
  std::string temporary;   ///< `.<name>.tmp.<pid>.<16 hex digits>` in the folder of `path`
  TemporaryFileLock lock;  ///< the file kept open, and so locked, until this is destroyed
};

/// The first half of `write_file_atomically`: writes `bytes` to the temporary file of `path`,
/// flushed to disk and kept open (locked) in the returned value. On failure the temporary file is removed and a runtime `Error`
/// "<path>: cannot write: <reason>" is thrown. Files of different paths may be written at once.
TemporaryFile write_temporary_file(const std::string& path, const std::string& bytes);

/// The second half: renames `file.temporary` over `file.path`. On failure the temporary file is
/// removed and a runtime `Error` "<path>: cannot write: <reason>" is thrown.
void commit_temporary_file(const TemporaryFile& file);

/// Removes `file.temporary` (a file that will not be renamed); never throws.
void remove_temporary_file(const TemporaryFile& file);

}  // namespace tear
