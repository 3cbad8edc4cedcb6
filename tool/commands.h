// tear CLI: the subcommands and the options they share.
//
// Each subcommand lives in its own file (`info_command.cpp`, ...) and registers itself with one
// `add_*_command(app)` call in main.cpp. A command reports failure by throwing `tear::Error`
// (or any exception); main.cpp alone turns exceptions into exit codes and messages.
#pragma once

#include <exception>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "tear/device.h"
#include "tear/frame_path.h"
#include "tear/mesh.h"
#include "tear/read_mesh.h"

namespace tear::cli {

/// `tear info MESH`: counts, boundary loops, components and defects of a mesh.
void add_info_command(CLI::App& app);

/// `tear bench`: remesh timings on generated sheets, GPU and CPU side by side.
void add_bench_command(CLI::App& app);

/// `tear run MESH SCRIPT -o PATTERN`: a cut script applied frame by frame, one mesh file per frame.
void add_run_command(CLI::App& app);

/// `tear demo [-o DIR]`: the paper's scene, generated, torn and simulated, one OBJ per frame.
void add_demo_command(CLI::App& app);

/// `tear validate SCRIPT [MESH]`: the script's checks, and with MESH those of `tear run` against it.
void add_validate_command(CLI::App& app);

/// `tear diff A B`: two meshes, or two frame sequences, compared the way a golden-file test needs.
void add_diff_command(CLI::App& app);

/// Thrown by a command that finished its work and must exit with `code` without a message (`tear
/// diff` found a difference: 5). main.cpp returns the code.
struct ExitCode {
  int code;
};

/// A CLI11 check: a finite number >= 0 (CLI11's own NonNegativeNumber lets "nan" and "inf" through).
CLI::Validator finite_non_negative();

/// Adds `--device auto|cpu|cuda|cuda:N` (default auto) to `command`, stored in `spec`.
/// Pass the result to `tear::select_device` before reading any input, so that a wrong device is a
/// usage error whatever the input.
CLI::Option* add_device_option(CLI::App& command, std::string& spec);

/// Adds `--start-frame N` (an integer >= 0; default: what `start_frame` holds) to `command`.
CLI::Option* add_start_frame_option(CLI::App& command, int& start_frame);

/// Adds `--mesh-name NAME`, `--weld-tolerance T` (finite, >= 0) and `--no-weld` to `command`, stored
/// in `options`.
void add_read_options(CLI::App& command, ReadOptions& options);

/// Adds `--max-input-bytes BYTES` (process-wide: `set_max_input_bytes`) and `--max-faces N`
/// (`options.max_faces`); part of `add_read_options`.
void add_input_limits(CLI::App& command, ReadOptions& options);

/// Adds `--strict` to `command`, stored in `strict`: warnings about the data (what reading did to
/// it, and with `tear run` frames of degenerate or inverted faces) become failures, exit 3.
void add_strict_option(CLI::App& command, bool& strict);

/// Reads the mesh at `path` and checks its indices and coordinates on `device`: a face index out of
/// range or a non-finite coordinate throws an input `Error` naming the file and the counts, so that
/// what is returned can go to `build_topology`. What welding did to data the file kept apart
/// (`WeldReport`) is a warning on standard error, or with `strict` a runtime `Error` (exit 3).
Mesh read_checked_mesh(const std::string& path, const ReadOptions& options, Device device, bool strict = false);

/// A mesh file read (`read_mesh`) without a word said: the mesh and what welding did, or what
/// reading threw. `tear batch` reads the next shot's mesh so while a shot runs.
struct MeshRead {
  Mesh mesh;
  WeldReport welded;
  std::exception_ptr failure;
};
MeshRead read_mesh_quietly(const std::string& path, const ReadOptions& options);

/// `read_checked_mesh` of a mesh read before: throws what reading threw, then checks and warns as
/// `read_checked_mesh` does.
Mesh checked_mesh(MeshRead read, const std::string& path, Device device, bool strict = false);

}  // namespace tear::cli

namespace tear::cli {

/// Messages from libraries (assimp, CLI11) may span lines; a pipeline log wants one line per error.
std::string one_line(std::string message);

/// An exit code and the message that goes with it (without the leading "tear: ").
struct Failure {
  int code = 0;
  std::string message;
};

/// The exit code and message of the exception being handled (call inside a `catch`): a
/// `tear::Error`'s own, 3 "out of memory" for `std::bad_alloc`, 3 "internal error: ..." for
/// anything else. `tear` and each shot of `tear batch` report failures through it.
Failure current_failure();

/// `tear batch SHOTS.json`: the shots of a list run one after the other, each as `tear run` would.
void add_batch_command(CLI::App& app);

}  // namespace tear::cli
