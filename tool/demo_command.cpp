// `tear demo`: the paper's scene (a sheet torn by six cuts, hanging from its top edge) with no input
// files, one OBJ per frame.
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
  std::string resolution = "low";
  std::string device = "auto";
  std::string report_path;
  int frames = demo_frames;
  FarmOptions farm;
};

void run_demo(const DemoCommandOptions& options) {
  const Device device = select_device(options.device);
  const DemoResolution resolution = parse_demo_resolution(options.resolution);
  const Mesh sheet = make_demo_sheet(resolution);
  const CutScript script = demo_script();

  RunOptions run;
  run.output_pattern = options.output_folder + "/demo.####.obj";
  run.frames = options.frames;
  run.device = device;
  run.report_path = options.report_path;
  const std::string mesh_name = "(demo sheet, " + std::string(to_string(resolution)) + " resolution)";
  const FramePattern pattern(run.output_pattern);
  pattern.check(options.frames);
  check_output_files({}, &pattern, options.frames,
                     {{"the report", options.report_path}, {"the checkpoint", options.farm.checkpoint_path}});
  std::vector<std::string> outputs = output_paths(pattern, options.frames, options.report_path);
  if (!options.farm.checkpoint_path.empty()) outputs.push_back(options.farm.checkpoint_path);
  remove_stale_temporaries(outputs);
  apply_farm_options(options.farm, run);
  FrameProgress progress(options.farm.progress, options.frames);
  run.on_frame = [&](const FrameResult& frame, const Cloth&) {
    progress.frame(frame.frame, "frames, " + std::to_string(frame.stats.faces_after) + " faces");
  };
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
      app.add_subcommand("demo", "Run the paper's scene (a hanging sheet torn by six cuts) and write every frame");
  command->footer(
      "Writes DIR/demo.0001.obj ... DIR/demo.0048.obj: two seconds at 24 fps, a cut every 8 frames from frame 4, "
      "the top edge pinned, gravity along -y. Needs no input file. Exit codes: 0 ok, 1 usage error, 3 runtime "
      "failure.");
  command->add_option("-o,--output", options->output_folder, "Output folder (default: demo)")->type_name("DIR");
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
  add_device_option(*command, options->device);
  add_farm_options(*command, options->farm);
  command->callback([options] { run_demo(*options); });
}

}  // namespace tear::cli
