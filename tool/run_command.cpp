// `tear run MESH SCRIPT -o PATTERN`: a script's cuts applied frame by frame, one mesh file per frame.
#include <cerrno>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "farm.h"
#include "progress.h"
#include "run_command.h"
#include "tear/cut_script.h"
#include "tear/error.h"
#include "tear/frame_path.h"
#include "tear/output_files.h"
#include "tear/run_cuts.h"
#include "tear/usd_layer.h"

namespace tear::cli {

namespace {


/// CLI11's PositiveNumber message quotes the largest double; say what is expected instead.
std::string check_positive_int(const std::string& text) {
  char* end = nullptr;
  errno = 0;
  const long value = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || end != text.c_str() + text.size() || errno != 0 || value < 1 || value > INT_MAX)
    return "expected an integer >= 1, got '" + text + "'";
  return {};
}

/// Accepts a finite number > 0.
std::string check_finite_positive(const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(value) || !(value > 0.0))
    return "expected a finite number > 0, got '" + text + "'";
  return {};
}

/// `frame N/LAST: ...`: the frame's number and the last frame's, as the files are numbered.
void print_frame(const FrameResult& frame, int last_frame) {
  const CutStats& s = frame.stats;
  // Cuts that split nothing (they missed the cloth, or retraced a tear) are said to have done so.
  const bool changed = s.nodes_after != s.nodes_before || s.faces_after != s.faces_before;
  std::cout << "frame " << frame.output_frame << '/' << last_frame << ": " << frame.cut_count
            << (frame.cut_count == 1 ? " cut" : " cuts")
            << (frame.cut_count > 0 && !changed ? " (changed nothing), " : ", ") << s.nodes_before << " -> "
            << s.nodes_after << " nodes, " << s.faces_before << " -> " << s.faces_after << " faces, ";
  // Tears happen while the frame is stepped, after its cuts: the mesh they leave is the frame's.
  if (frame.tearing)
    std::cout << frame.tear_events << (frame.tear_events == 1 ? " tear event" : " tear events") << " ("
              << frame.torn_length << " m torn) -> " << frame.nodes_end << " nodes, " << frame.faces_end << " faces, ";
  std::cout << frame.path << std::endl;
  if (!std::cout) throw runtime_error("cannot write to standard output");
}

}  // namespace

void run_run(const RunCommandOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const Device device = select_device(options.device);
  // The GPU's context is made while the input is read.
  const DeviceWarmUp warm_up(device);
  // The pattern's syntax and the format of its extension are usage errors, found before any input is read.
  FramePattern(options.output_pattern).check(1);
  // Stage metadata exists in USD only: a flag that another format would silently drop is refused.
  if (options.usd_metadata_given && !is_usd_path(options.output_pattern))
    throw Error(ErrorKind::usage, "--up-axis and --meters-per-unit apply to USD output only (.usda, .usd), not to '" +
                                      options.output_pattern + "'");
  const UpAxis up_axis = parse_up_axis(options.up_axis);
  const Mesh mesh = options.mesh_read ? checked_mesh(options.mesh_read->get(), options.mesh_path, device, options.strict)
                                      : read_checked_mesh(options.mesh_path, options.read, device, options.strict);
  const CutScript script = read_cut_script(options.script_path);

  RunOptions run;
  run.output_pattern = options.output_pattern;
  run.frames = options.frames;
  run.device = device;
  run.report_path = options.report_path;
  run.start_frame = options.start_frame;
  run.up_axis = up_axis;
  run.meters_per_unit = options.meters_per_unit;
  run.strict = options.strict;
  // What changes results besides the mesh, the script and the device, for the checkpoint's digest.
  run.result_options = "mesh-name=" + options.read.mesh_name +
                       ";weld-tolerance=" + std::to_string(options.read.weld_tolerance) +
                       ";weld=" + (options.read.weld ? "1" : "0");
  apply_farm_options(options.farm, run);
  // The library checks the whole plan (frames, inputs, outputs: none may be an input, every folder
  // must be writable; checkpoint) once, before anything is written.
  run.check_outputs = true;
  run.input_files = {{"mesh", options.mesh_path}, {"script", options.script_path}};
  const RunPlan plan = check_run_plan(mesh, options.mesh_path, script, run);
  run.plan_checked = true;
  run.input_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  remove_stale_temporaries(plan.outputs);
  const int frame_count = plan.frame_count;
  FrameProgress progress(options.farm.progress, frame_count);
  run.on_frame = [&](const FrameResult& frame) {
    if (options.verbose) {
      progress.finish();
      print_frame(frame, options.start_frame + frame_count - 1);
    }
    progress.frame(frame.frame, "frames, " + std::to_string(frame.faces_end) + " faces");
  };
  // A frame of damaged faces (`tear::FaceQuality`), said once it is on disk.
  run.on_warning = [&](const std::string& warning) {
    progress.finish();
    std::cerr << "tear: warning: " << warning << std::endl;
  };
  begin_frames();
  run_to_files(mesh, options.mesh_path, script, run);
  progress.finish();
}

void add_run_command(CLI::App& app) {
  auto options = std::make_shared<RunCommandOptions>();
  CLI::App* command = app.add_subcommand("run", "Apply a cut script to a mesh and write the mesh of every frame");
  command->footer(
      "Output pattern: a run of '#' is the frame number zero-padded to that many digits (out/cloth.####.obj writes "
      "out/cloth.0001.obj, ...); {frame} and {frame:04} work too. Without a placeholder the pattern is the file "
      "name of a single-frame run, or, for .usda/.usd, one USD layer holding every frame as a time sample. The "
      "extension picks the format: .obj, .ply, .gltf, .glb, or .usda/.usd (USDA text). Folders are created. "
      "Everything is checked before the first file is written: the mesh must be cuttable (see 'tear info'). "
      "Exit codes: 0 ok, 1 usage error, 2 bad input, 3 runtime failure, 4 stopped by SIGTERM/SIGINT (resumable).");
  command->add_option("MESH", options->mesh_path, "Mesh file: OBJ, glTF, GLB, PLY or any format assimp reads")
      ->required()
      ->type_name("");
  command->add_option("SCRIPT", options->script_path, "Cut script (JSON, see docs/cut-script.md)")
      ->required()
      ->type_name("");
  command->add_option("-o,--output", options->output_pattern, "Output file pattern, e.g. out/cloth.####.obj")
      ->required()
      ->type_name("PATTERN");
  command->add_option("--frames", options->frames, "Run only the first N frames of the script (default: all of them)")
      ->type_name("N")
      ->check(CLI::Validator(check_positive_int, ""));
  command->add_flag("-v,--verbose", options->verbose, "Print one line per frame written: cuts, counts, file");
  command
      ->add_option("--report", options->report_path,
                   "Write a JSON report (per-frame counts and timings, totals) to FILE at the end")
      ->type_name("FILE");
  add_start_frame_option(*command, options->start_frame);
  CLI::Option* up_axis = command
                             ->add_option("--up-axis", options->up_axis,
                                          "USD output: the stage's upAxis, Y or Z (the points are "
                                          "written as they are; this says how to read them)")
                             ->type_name("Y|Z")
                             ->check(CLI::IsMember({"Y", "Z", "y", "z"}))
                             ->capture_default_str();
  CLI::Option* meters_per_unit =
      command
          ->add_option("--meters-per-unit", options->meters_per_unit,
                       "USD output: the stage's metersPerUnit, the length of one unit of the mesh in metres")
          ->type_name("M")
          ->check(CLI::Validator(check_finite_positive, ""))
          ->capture_default_str();
  add_device_option(*command, options->device);
  add_read_options(*command, options->read);
  add_strict_option(*command, options->strict);
  add_farm_options(*command, options->farm);
  command->callback([options, up_axis, meters_per_unit] {
    options->usd_metadata_given = up_axis->count() > 0 || meters_per_unit->count() > 0;
    run_run(*options);
  });
}

}  // namespace tear::cli
