// `tear demo`: the paper's scene (a sheet torn by six cuts, hanging from its top edge), or a sheet
// torn by pulling or punching, a woven one torn along its grain, or one draped over a turning box
// (`--scene pull|punch|grain|drape`), with no input files, one OBJ per frame (or
// any output `tear run` writes, a USD layer among them).
#include <cctype>
#include <chrono>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>

#include "commands.h"
#include "farm.h"
#include "progress.h"
#include "tear/demo_scene.h"
#include "tear/error.h"
#include "tear/frame_path.h"
#include "tear/output_files.h"
#include "tear/run_cuts.h"

namespace tear::cli {

namespace {

struct DemoCommandOptions {
  std::string output_folder = "demo";
  std::string scene = "paper";
  std::string resolution = "low";
  std::string device = "auto";
  std::string report_path;
  int frames = demo_frames;
  FarmOptions farm;
  int start_frame = 1;
};

/// `-o` names a folder, or, when its file name has an extension tear writes, an output pattern as
/// for `tear run` (`out/demo.####.ply`, `shot.usda`).
std::string output_pattern(const std::string& output) {
  const std::size_t slash = output.find_last_of('/');
  const std::string name = slash == std::string::npos ? output : output.substr(slash + 1);
  const std::size_t dot = name.find_last_of('.');
  std::string extension = dot == std::string::npos ? "" : name.substr(dot + 1);
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const char* known : {"obj", "ply", "gltf", "glb", "usda", "usd"})
    if (extension == known) return output;
  return output + "/demo.####.obj";
}

void run_demo(const DemoCommandOptions& options) {
  const Device device = select_device(options.device);
  // The GPU's context is made while the scene is built.
  const DeviceWarmUp warm_up(device);
  const std::string pattern = output_pattern(options.output_folder);
  FramePattern(pattern).check(1);
  const DemoResolution resolution = parse_demo_resolution(options.resolution);
  const DemoScene scene = parse_demo_scene(options.scene);
  const auto start = std::chrono::steady_clock::now();
  const Mesh sheet = make_demo_mesh(scene, resolution);
  const CutScript script = demo_script(scene);

  RunOptions run;
  run.input_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  run.output_pattern = pattern;
  run.frames = options.frames;
  run.start_frame = options.start_frame;
  run.device = device;
  run.report_path = options.report_path;
  const std::string mesh_name = "(demo sheet, " + std::string(to_string(resolution)) + " resolution)";
  apply_farm_options(options.farm, run);
  // The library checks the whole plan (frames, outputs, checkpoint) once, before anything is written.
  run.check_outputs = true;
  const RunPlan plan = check_run_plan(sheet, mesh_name, script, run);
  run.plan_checked = true;
  remove_stale_temporaries(plan.outputs);
  FrameProgress progress(options.farm.progress, options.frames);
  run.on_frame = [&](const FrameResult& frame) {
    progress.frame(frame.frame, "frames, " + std::to_string(frame.faces_end) + " faces");
  };
  begin_frames();
  const RunSummary summary = run_to_files(sheet, mesh_name, script, run);
  progress.finish();

  std::ostringstream line;
  line << "demo: " << summary.frames << " frames, " << sheet.face_count() << " -> " << summary.faces << " faces, "
       << std::fixed << std::setprecision(2) << summary.wall_ms / 1000.0 << " s on " << device_name(device) << ", "
       << run.output_pattern;
  std::cout << line.str() << std::endl;
  if (!std::cout) throw runtime_error("cannot write to standard output");
}

}  // namespace

void add_demo_command(CLI::App& app) {
  auto options = std::make_shared<DemoCommandOptions>();
  CLI::App* command =
      app.add_subcommand("demo",
                         "Run the paper's scene (a hanging sheet torn by six cuts), or a sheet torn by pulling or "
                         "punching, and write every frame");
  command->footer(
      "Writes DIR/demo.0001.obj ... DIR/demo.0048.obj: two seconds at 24 fps, a cut every 8 frames from frame 4, "
      "the top edge pinned, gravity along -y. --scene pull: a notched sheet whose left and right strips are "
      "pulled apart until it tears in two; --scene punch: a horizontal sheet held at its four edges, torn open by "
      "a rising sphere, its torn flaps kept apart by self-collision; --scene grain: a woven sheet with a UV seam at "
      "x = 0.7 pulled apart along a diagonal, which comes apart along its weaker seam; --scene drape: a sheet "
      "caught at one corner falls onto a slowly turning box, folds on itself and tears where it snags (all four tear "
      "at a stretch of 1.3). An -o whose file name ends in .obj, .ply, .gltf, .glb, .usda "
      "or .usd "
      "is an output pattern as for 'tear run' instead (out/demo.####.ply; shot.usda, one USD layer). Needs no "
      "input file. Exit codes: 0 ok, 1 usage error, 3 runtime failure.");
  command
      ->add_option("-o,--output", options->output_folder,
                   "Output folder (default: demo), or an output pattern such as out/demo.####.ply or shot.usda")
      ->type_name("DIR|PATTERN");
  command
      ->add_option("--scene", options->scene,
                   "Scene: paper (the default), pull (a notched sheet pulled apart), punch (a sphere through a "
                   "held sheet), grain (a woven sheet with a seam, pulled along a diagonal) or drape (a sheet falling onto a "
                   "turning box)")
      ->type_name("paper|pull|punch|grain|drape")
      ->check(CLI::IsMember({"paper", "pull", "punch", "grain", "drape"}));
  command
      ->add_option("--resolution", options->resolution,
                   "Sheet resolution: low (2,822 faces, the default), "
                   "medium (9,022) or high (38,298)")
      ->type_name("low|medium|high")
      ->check(CLI::IsMember({"low", "medium", "high"}));
  command->add_option("--report", options->report_path, "Write a JSON report of the run to FILE (see tear run)")
      ->type_name("FILE");
  // Hidden: runs only the first N frames, for quick checks and tests.
  command->add_option("--frames", options->frames)->check(CLI::Range(1, demo_frames))->group("");
  add_start_frame_option(*command, options->start_frame);
  add_device_option(*command, options->device);
  add_farm_options(*command, options->farm);
  command->callback([options] { run_demo(*options); });
}

}  // namespace tear::cli
