// `tear diff A B`: two meshes, or two frame sequences, compared the way a golden-file test needs:
// silent and 0 when equal, one line per differing frame and exit code 5 otherwise.
#include <algorithm>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "tear/diff_meshes.h"
#include "tear/error.h"
#include "tear/find_frames.h"
#include "tear/frame_path.h"
#include "tear/read_mesh.h"

namespace tear::cli {

namespace {

/// `tear diff`'s exit code when the inputs differ: neither bad input nor a failure.
constexpr int differ_exit_code = 5;

struct DiffCommandOptions {
  std::string a, b;
  DiffOptions diff;
  ReadOptions read;  // the limits only: both files are read with the default options
  bool json = false;
};

/// One pair of files to compare: a frame of two sequences (`frame` >= 0) or two files (-1).
struct FramePair {
  int frame = -1;
  std::string a, b;
  bool has_a = true, has_b = true;
};

/// The frames of both sequences, their union in ascending order; a pattern matching no file is bad
/// input (a wrong path must not pass as "every frame missing").
std::vector<FramePair> frame_pairs(const FramePattern& a, const FramePattern& b) {
  const std::vector<int> frames_a = find_frames(a), frames_b = find_frames(b);
  if (frames_a.empty()) throw input_error(a.pattern(), "no file matches the frame pattern");
  if (frames_b.empty()) throw input_error(b.pattern(), "no file matches the frame pattern");
  std::vector<int> frames;
  std::set_union(frames_a.begin(), frames_a.end(), frames_b.begin(), frames_b.end(), std::back_inserter(frames));
  std::vector<FramePair> pairs;
  for (int frame : frames) {
    FramePair pair;
    pair.frame = frame;
    pair.a = a.path(frame);
    pair.b = b.path(frame);
    pair.has_a = std::binary_search(frames_a.begin(), frames_a.end(), frame);
    pair.has_b = std::binary_search(frames_b.begin(), frames_b.end(), frame);
    pairs.push_back(pair);
  }
  return pairs;
}

void run_diff(const DiffCommandOptions& options) {
  const FramePattern pattern_a(options.a), pattern_b(options.b);
  if (pattern_a.has_frame_number() != pattern_b.has_frame_number())
    throw Error(ErrorKind::usage, "'" + options.a + "' and '" + options.b +
                                      "': give two mesh files or two frame patterns (such as out/f.####.ply)");
  const std::vector<FramePair> pairs = pattern_a.has_frame_number()
                                           ? frame_pairs(pattern_a, pattern_b)
                                           : std::vector<FramePair>{{-1, options.a, options.b}};

  std::int64_t compared = 0;
  MeshDiff largest;  // the maxima over every frame compared
  nlohmann::json differences = nlohmann::json::array();
  std::vector<std::string> lines;
  for (const FramePair& pair : pairs) {
    std::string what;
    if (!pair.has_a || !pair.has_b) {
      what = "missing in " + std::string(pair.has_a ? "b (" + pair.b : "a (" + pair.a) + ")";
    } else {
      // As written, node for node: a torn OBJ frame is not welded, an unused node still counts.
      ReadOptions as_written = options.read;
      as_written.as_written = true;
      const Mesh a = read_mesh(pair.a, as_written), b = read_mesh(pair.b, as_written);
      const MeshDiff diff = diff_meshes(a, b, options.diff);
      ++compared;
      largest.max_position = std::max(largest.max_position, diff.max_position);
      largest.max_velocity = std::max(largest.max_velocity, diff.max_velocity);
      largest.max_uv = std::max(largest.max_uv, diff.max_uv);
      largest.max_normal = std::max(largest.max_normal, diff.max_normal);
      if (diff.equal()) continue;
      what = diff.first.describe();
    }
    const std::string where = pair.frame >= 0 ? "frame " + std::to_string(pair.frame) : pair.a + " vs " + pair.b;
    lines.push_back(where + ": " + what);
    nlohmann::json entry = {{"a", pair.a}, {"b", pair.b}, {"difference", what}};
    entry["frame"] = pair.frame >= 0 ? nlohmann::json(pair.frame) : nlohmann::json(nullptr);
    differences.push_back(entry);
  }

  if (options.json) {
    const nlohmann::json summary = {
        {"frames_compared", compared},
        {"frames_differing", differences.size()},
        {"max_position_difference", largest.max_position},
        {"max_velocity_difference", largest.max_velocity},
        {"max_uv_difference", largest.max_uv},
        {"max_normal_difference", largest.max_normal},
        {"tolerance", options.diff.tolerance},
        {"uv_tolerance", options.diff.uv_tolerance},
        {"differences", differences},
    };
    std::cout << summary.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) << '\n';
  } else {
    for (const std::string& line : lines) std::cout << line << '\n';
  }
  std::cout.flush();
  if (!std::cout) throw runtime_error("cannot write to standard output");
  if (!lines.empty()) throw ExitCode{differ_exit_code};
}

}  // namespace

void add_diff_command(CLI::App& app) {
  auto options = std::make_shared<DiffCommandOptions>();
  CLI::App* command =
      app.add_subcommand("diff", "Compare two meshes, or two frame sequences, within tolerances (golden-file tests)");
  command->footer(
      "A and B are mesh files, or frame patterns (out/f.####.ply) compared frame by frame. Node i of A is node i "
      "of B. Faces must match exactly (as sets, rotation allowed, orientation not); positions and velocities within "
      "--tolerance, corner UVs and normals within --uv-tolerance. Exit codes: 0 equal, 1 usage error, 2 bad input, "
      "3 runtime failure, 5 different (one line per differing frame on standard output).");
  command->add_option("A", options->a, "Mesh file, or frame pattern such as out/f.####.ply")->required()->type_name("");
  command->add_option("B", options->b, "Mesh file, or frame pattern such as golden/f.####.ply (the same kind as A)")
      ->required()
      ->type_name("");
  command
      ->add_option("--tolerance", options->diff.tolerance,
                   "Largest difference per coordinate of positions (mesh units) and velocities that still compares "
                   "equal")
      ->type_name("T")
      ->check(finite_non_negative())
      ->capture_default_str();
  command
      ->add_option("--uv-tolerance", options->diff.uv_tolerance,
                   "Largest difference per component of corner UVs and normals that still compares equal")
      ->type_name("U")
      ->check(finite_non_negative())
      ->capture_default_str();
  add_input_limits(*command, options->read);
  command->add_flag("--json", options->json,
                    "Print one JSON summary object instead of the lines (keys: see docs/cli.md)");
  command->callback([options] { run_diff(*options); });
}

}  // namespace tear::cli
