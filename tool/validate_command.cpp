// `tear validate SCRIPT [MESH]`: the checks of `tear run`, without running anything.
#include <iostream>
#include <memory>
#include <string>

#include "commands.h"
#include "tear/cut_script.h"
#include "tear/error.h"
#include "tear/run_cuts.h"
#include "tear/script_warnings.h"

namespace tear::cli {

namespace {

struct ValidateOptions {
  std::string script_path;
  std::string mesh_path;
  bool has_mesh = false;  // an empty MESH argument is still a mesh to read (and an error)
  std::string device = "auto";
  ReadOptions read;
  bool strict = false;
};

std::string plural(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

void run_validate(const ValidateOptions& options) {
  const Device device = select_device(options.device);
  // The GPU's context is made while the input is read.
  const DeviceWarmUp warm_up(device);
  const CutScript script = read_cut_script(options.script_path);
  if (options.has_mesh) {
    const Mesh mesh = read_checked_mesh(options.mesh_path, options.read, device, options.strict);
    check_run_inputs(script, mesh, options.mesh_path, device);
    // Allowed, but probably not meant: said on standard error, and the script is still ok.
    for (const std::string& warning : script_warnings(script, mesh, options.mesh_path, device))
      std::cerr << "tear: warning: " << warning << '\n';
  }
  std::cout << options.script_path << ": ok (" << plural(script.cuts.size(), "cut", "cuts") << " over "
            << plural(static_cast<std::size_t>(script.frames), "frame", "frames") << ")" << std::endl;
  if (!std::cout) throw runtime_error("cannot write to standard output");
}

}  // namespace

void add_validate_command(CLI::App& app) {
  auto options = std::make_shared<ValidateOptions>();
  CLI::App* command =
      app.add_subcommand("validate", "Check a cut script, and optionally that it can be applied to a mesh");
  command->footer(
      "Without MESH: the script's syntax and schema. With MESH: also that every cut can be applied to it (a \"uv\" "
      "cut needs UVs, a rest-* plane must not see the cloth edge-on) and that the mesh can be cut (an oriented "
      "manifold without degenerate faces). Prints 'SCRIPT: ok (N cuts over F frames)'. Exit codes: 0 ok, 1 usage "
      "error, 2 bad input, 3 runtime failure.");
  command->add_option("SCRIPT", options->script_path, "Cut script (JSON, see docs/cut-script.md)")
      ->required()
      ->type_name("");
  CLI::Option* mesh = command->add_option("MESH", options->mesh_path, "Mesh the script is meant for (optional)");
  mesh->type_name("");
  add_device_option(*command, options->device);
  add_read_options(*command, options->read);
  add_strict_option(*command, options->strict);
  command->callback([options, mesh] {
    options->has_mesh = mesh->count() > 0;
    run_validate(*options);
  });
}

}  // namespace tear::cli
