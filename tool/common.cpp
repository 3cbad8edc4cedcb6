// Options and input handling shared by the subcommands.
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <new>
#include <utility>
#include <limits>
#include <string>
#include <vector>

#include "commands.h"
#include "tear/device.h"
#include "tear/error.h"
#include "tear/input_file.h"
#include "tear/usd_layer.h"
#include "tear/validate_mesh.h"

namespace tear::cli {

namespace {

/// Accepts a finite number >= 0; CLI11's own NonNegativeNumber lets "nan" and "inf" through.
std::string check_finite_non_negative(const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(value) || value < 0.0)
    return "expected a finite number >= 0, got '" + text + "'";
  return {};
}

/// Accepts an integer from 0 to INT_MAX.
std::string check_non_negative_int(const std::string& text) {
  char* end = nullptr;
  errno = 0;
  const long value = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || end != text.c_str() + text.size() || errno != 0 || value < 0 || value > INT_MAX)
    return "expected an integer >= 0, got '" + text + "'";
  return {};
}

std::string plural(std::int64_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

}  // namespace

CLI::Validator finite_non_negative() { return CLI::Validator(check_finite_non_negative, ""); }

CLI::Option* add_device_option(CLI::App& command, std::string& spec) {
  // The CPU backend's threads: with every command that runs on a device (docs/cli.md, *Threads*).
  command
      .add_option_function<int>(
          "--threads", [](const int& threads) { tear::set_cpu_threads(threads); },
          "Most CPU threads the CPU backend and the frame writers use (default: OMP_NUM_THREADS, else "
          "SLURM_CPUS_PER_TASK, else every hardware thread)")
      ->type_name("N")
      ->check(CLI::Range(1, 4096));
  return command
      .add_option("--device", spec,
                  "Backend that runs the kernels: 'auto' (a CUDA GPU when one is usable, else the CPU), 'cpu', "
                  "'cuda' (fails when no GPU is usable) or 'cuda:N' (GPU number N)")
      ->type_name("auto|cpu|cuda|cuda:N")
      ->capture_default_str();
}

CLI::Option* add_start_frame_option(CLI::App& command, int& start_frame) {
  return command
      .add_option("--start-frame", start_frame,
                  "Number of the first frame in file names, USD time codes, the report and -v lines (the "
                  "script's frame 1 is written as this frame); an integer >= 0")
      ->type_name("N")
      ->check(CLI::Validator(check_non_negative_int, ""))
      ->capture_default_str();
}

void add_input_limits(CLI::App& command, ReadOptions& options) {
  command
      .add_option_function<std::uint64_t>(
          "--max-input-bytes", [](std::uint64_t bytes) { set_max_input_bytes(bytes); },
          "Largest input file read (mesh, glTF buffer, script, checkpoint), in bytes; a larger file is bad "
          "input (default " + std::to_string(default_max_input_bytes) + ", 4 GiB)")
      ->type_name("BYTES")
      ->check(CLI::Range(std::uint64_t(1), std::numeric_limits<std::uint64_t>::max()));
  command
      .add_option("--max-faces", options.max_faces,
                  "Most triangles a mesh may have once read, polygons triangulated and glTF instances placed; "
                  "more is bad input")
      ->type_name("N")
      ->check(CLI::Range(std::uint64_t(1), std::numeric_limits<std::uint64_t>::max()))
      ->capture_default_str();
}

void add_read_options(CLI::App& command, ReadOptions& options) {
  add_input_limits(command, options);
  command
      .add_option("--mesh-name", options.mesh_name,
                  "Read only the meshes of this name (the mesh's or its scene node's name); by default every mesh "
                  "of the file is merged")
      ->type_name("NAME");
  command
      .add_option("--weld-tolerance", options.weld_tolerance,
                  "Weld nodes whose positions differ by at most this distance per coordinate (mesh units); 0 welds "
                  "identical positions only, which joins the copies importers make at UV seams and hard edges")
      ->type_name("T")
      ->check(finite_non_negative())
      ->capture_default_str();
  command.add_flag_callback(
      "--no-weld", [&options] { options.weld = false; },
      "Weld nothing: every vertex of the file that a face uses is a node of its own, so a frame written as "
      "OBJ reads back with its tears open (docs/io.md). By default vertices are welded by id in tear's own "
      "PLY and glTF files, by position in others");
}

void add_strict_option(CLI::App& command, bool& strict) {
  command.add_flag("--strict", strict,
                   "Fail (exit 3) where the data is damaged instead of warning: reading that joined corners of one "
                   "face (coordinates float32 cannot keep apart), and with 'tear run' a frame with degenerate or "
                   "inverted faces");
}

Mesh read_checked_mesh(const std::string& path, const ReadOptions& options, Device device, bool strict) {
  return checked_mesh(read_mesh_quietly(path, options), path, device, strict);
}

MeshRead read_mesh_quietly(const std::string& path, const ReadOptions& options) {
  MeshRead read;
  try {
    read.mesh = read_mesh(path, options, read.welded);
  } catch (...) {
    read.failure = std::current_exception();
  }
  return read;
}

Mesh checked_mesh(MeshRead read, const std::string& path, Device device, bool strict) {
  if (read.failure) std::rethrow_exception(read.failure);
  Mesh mesh = std::move(read.mesh);
  const WeldReport& welded = read.welded;
  const MeshReport report = check_indices(mesh, device);
  if (!report.readable())
    throw input_error(path, report.describe() + " (the mesh has " + plural(mesh.node_count(), "node", "nodes") +
                                " and " + plural(mesh.face_count(), "face", "faces") + ")");
  if (welded.any()) {
    if (strict) throw runtime_error(path + ": " + welded.describe() + " (--strict)");
    std::cerr << "tear: warning: " << path << ": " << welded.describe() << '\n';
  }
  return mesh;
}

}  // namespace tear::cli

namespace tear::cli {

std::string one_line(std::string message) {
  for (char& c : message)
    if (c == '\n' || c == '\r') c = ' ';
  while (!message.empty() && message.back() == ' ') message.pop_back();
  // A line of a log stays short whatever an input put in it (a file's text quoted by a library).
  constexpr std::size_t longest = 400;
  if (message.size() > longest) message = message.substr(0, longest - 3) + "...";
  return message;
}

Failure current_failure() {
  try {
    throw;
  } catch (const tear::Error& e) {
    return {e.exit_code(), one_line(e.what())};
  } catch (const std::bad_alloc&) {
    return {3, "out of memory"};
  } catch (const std::exception& e) {
    return {3, one_line(std::string("internal error: ") + e.what())};
  } catch (...) {
    return {3, "internal error: unknown exception"};
  }
}

}  // namespace tear::cli
