// The checks of a run, made once before anything is written, and the files it will write.
#include <charconv>
#include <cmath>
#include <string>
#include <vector>

#include "tear/error.h"
#include "tear/frame_path.h"
#include "tear/output_files.h"
#include "tear/run_cuts.h"
#include "tear/usd_layer.h"

namespace tear {

namespace {

/// The frames the run computes: `RunOptions::frames`, or all of the script's.
int checked_frame_count(const CutScript& script, const RunOptions& options) {
  const int frame_count = options.frames == 0 ? script.frames : options.frames;
  if (frame_count > script.frames)
    throw Error(ErrorKind::usage, script.path + ": --frames " + std::to_string(frame_count) +
                                      " is more than the script's " + std::to_string(script.frames) + " frames");
  if (frame_count < 1)
    throw Error(ErrorKind::usage, script.path + ": cannot run " + std::to_string(frame_count) +
                                      " frames (expected 1.." + std::to_string(script.frames) +
                                      ", the frames of the script)");
  return frame_count;
}

void check_meters_per_unit(double meters_per_unit) {
  if (!(meters_per_unit > 0) || !std::isfinite(meters_per_unit)) {
    char text[32];
    const std::to_chars_result end = std::to_chars(text, text + sizeof text, meters_per_unit);
    throw Error(ErrorKind::usage, "--meters-per-unit: expected a finite number > 0, got " + std::string(text, end.ptr));
  }
}

void check_checkpoint_options(const FramePattern& pattern, const RunOptions& options) {
  if (options.resume && options.checkpoint_path.empty())
    throw Error(ErrorKind::usage, "--resume needs --checkpoint PATH (the checkpoint to go on from)");
  // A layer holding every frame is assembled at the end from this process's frames alone.
  if (!options.checkpoint_path.empty() && is_usd_path(pattern.pattern()) && !pattern.has_frame_number())
    throw Error(ErrorKind::usage, options.output_pattern +
                                      ": a single USD layer cannot be checkpointed and resumed; write one layer per "
                                      "frame (a pattern with a frame number, e.g. shot.####.usda) or PLY frames");
}

/// The files a run writes: its frames numbered from `options.start_frame` (a USD layer for the
/// whole run with the temporaries it streams its samples to), then the report and the checkpoint.
std::vector<std::string> output_paths(const FramePattern& pattern, int frame_count, const RunOptions& options) {
  std::vector<std::string> paths;
  const int files = pattern.has_frame_number() ? frame_count : 1;
  for (int i = 0; i < files; ++i) paths.push_back(pattern.path(options.start_frame + i));
  if (!pattern.has_frame_number() && is_usd_path(pattern.pattern())) {
    const std::vector<std::string> samples = usd_layer_sample_paths(pattern.path(options.start_frame));
    paths.insert(paths.end(), samples.begin(), samples.end());
  }
  if (!options.report_path.empty()) paths.push_back(options.report_path);
  if (!options.checkpoint_path.empty()) paths.push_back(options.checkpoint_path);
  return paths;
}

}  // namespace

RunPlan check_run_plan(const Mesh& mesh, const std::string& mesh_path, const CutScript& script,
                       const RunOptions& options) {
  const FramePattern pattern(options.output_pattern);
  RunPlan plan;
  plan.frame_count = checked_frame_count(script, options);
  pattern.check(plan.frame_count, options.start_frame);
  check_meters_per_unit(options.meters_per_unit);
  check_run_inputs(script, mesh, mesh_path, options.device);
  if (options.check_outputs)
    check_output_files(options.input_files, &pattern, plan.frame_count,
                       {{"the report", options.report_path}, {"the checkpoint", options.checkpoint_path}},
                       options.start_frame);
  check_checkpoint_options(pattern, options);
  plan.outputs = output_paths(pattern, plan.frame_count, options);
  return plan;
}

}  // namespace tear
