// tear: checkpoints of a run, so a farm can stop a shot and resume it with the same bytes
// (docs/cli.md, "Stopping and resuming").
#pragma once

#include <cstdint>
#include <string>

#include "tear/cloth.h"
#include "tear/cut_script.h"
#include "tear/mesh.h"

namespace tear {

/// What a checkpoint was made from: a digest (64-bit FNV-1a) of the mesh file's bytes and of the
/// script file's bytes, and the options that change results, spelled out (`RunOptions::result_options`).
struct RunInputs {
  std::uint64_t mesh_digest = 0;
  std::uint64_t script_digest = 0;
  std::string options;
};

/// A run stopped after `frame` (1-based in the script): the inputs and the cloth's state then
/// (`Cloth::save_state`).
struct Checkpoint {
  int frame = 0;
  RunInputs inputs;
  std::string cloth_state;
};

/// FNV-1a (64 bits) of `bytes`.
std::uint64_t digest_bytes(const std::string& bytes);
/// `digest_bytes` of a file's contents; an input `Error` naming it when it cannot be read.
std::uint64_t digest_file(const std::string& path);

/// Writes `checkpoint` to `path` atomically (a temporary file renamed), with a trailing checksum.
/// A runtime `Error` naming the path when it cannot be written.
void write_checkpoint(const std::string& path, const Checkpoint& checkpoint);

/// Reads a checkpoint `write_checkpoint` wrote. A file that is not one, truncated, of another
/// version or whose checksum does not match is an input `Error` naming it (never a crash).
Checkpoint read_checkpoint(const std::string& path);

/// Checks a checkpoint as the input it is, once its checksum matched and its cloth was loaded
/// (`Cloth::load_state`): a checksum guards against damage, not against a file made by hand.
/// `frame` must be within the script's frames; the cloth must hold at least the nodes of `mesh`
/// (a cut only appends nodes), finite positions, rest positions and velocities within bounds
/// (rest positions inside the box of the mesh's, which cuts only interpolate; positions within
/// 1e9 m plus that box; speeds at most 1e6 m/s), faces on nodes in range, none repeating a node,
/// oriented consistently, manifold and not duplicated, and pins of the script's pins only.
/// Throws an input `Error` naming `path` (exit 2) otherwise.
void check_checkpoint_cloth(const std::string& path, int frame, const Cloth& cloth, const Mesh& mesh,
                            const CutScript& script);

/// Why `inputs` (of a checkpoint) does not fit `now` (of this run), e.g. "the script changed";
/// empty when it fits.
std::string inputs_mismatch(const RunInputs& inputs, const RunInputs& now);

}  // namespace tear
