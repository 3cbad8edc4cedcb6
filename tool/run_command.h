// tear CLI: the options of `tear run` and the run itself, shared by `tear run` and `tear batch`.
#pragma once

#include <future>
#include <string>

#include "commands.h"

#include "farm.h"
#include "tear/read_mesh.h"

namespace tear::cli {

/// What `tear run` takes on its command line (and `tear batch` from each shot of its list).
struct RunCommandOptions {
  std::string mesh_path;
  std::string script_path;
  std::string output_pattern;
  std::string device = "auto";
  std::string report_path;
  ReadOptions read;
  int frames = 0;
  int start_frame = 1;
  std::string up_axis = "Y";
  double meters_per_unit = 1;
  bool usd_metadata_given = false;  // --up-axis or --meters-per-unit given
  bool verbose = false;
  bool strict = false;  // --strict: data warnings fail (exit 3)
  FarmOptions farm;
  /// The mesh, already read (`tear batch` reads a shot's mesh ahead): taken instead of reading
  /// `mesh_path` (with `read`) when set.
  std::future<MeshRead>* mesh_read = nullptr;
};

/// One whole `tear run`: throws what the run throws (main.cpp, or `tear batch`, turns it into the
/// exit code and the message).
void run_run(const RunCommandOptions& options);

}  // namespace tear::cli
