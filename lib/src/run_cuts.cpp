#include "tear/run_cuts.h"

#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "tear/error.h"
#include "tear/frame_path.h"
#include "tear/validate_mesh.h"
#include "tear/write_mesh.h"

namespace tear {

namespace {

void check_frame_count(const CutScript& script, int frame_count) {
  if (frame_count < 1 || frame_count > script.frames)
    throw Error(ErrorKind::usage, script.path + ": cannot run " + std::to_string(frame_count) +
                                      " frames (expected 1.." + std::to_string(script.frames) +
                                      ", the frames of the script)");
}

void create_folder_of(const std::string& path) {
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  if (folder.empty()) return;
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) throw runtime_error(folder.string() + ": cannot create the output folder: " + error.message());
}

}  // namespace

void check_cuttable(const Mesh& mesh, const std::string& mesh_path, Device device) {
  const MeshReport report = validate_mesh(mesh, device);
  if (!report.ok()) throw input_error(mesh_path, "cannot be cut: " + report.describe());
}

void check_run_inputs(const CutScript& script, const Mesh& mesh, const std::string& mesh_path, Device device) {
  check_script_against_mesh(script, mesh, mesh_path);
  check_cuttable(mesh, mesh_path, device);
}

void run_cuts(Cloth& cloth, const CutScript& script, int frame_count, const FrameCallback& on_frame) {
  check_frame_count(script, frame_count);
  const CutOptions cut_options{script.snap};
  for (int frame = 1; frame <= frame_count; ++frame) {
    const std::vector<const Cut*> cuts = script.cuts_of_frame(frame);
    FrameResult result;
    result.frame = frame;
    result.cut_count = static_cast<int>(cuts.size());
    if (cuts.empty()) {
      result.stats.nodes_before = result.stats.nodes_after = cloth.node_count();
      result.stats.faces_before = result.stats.faces_after = cloth.face_count();
    } else {
      std::vector<CutLine> lines;
      lines.reserve(cuts.size());
      for (const Cut* cut : cuts) lines.push_back(to_cut_line(*cut));
      result.stats = cloth.cut(lines, cut_options);
    }
    if (on_frame) on_frame(result, cloth);
  }
}

void run_to_files(const Mesh& mesh, const std::string& mesh_path, const CutScript& script, const RunOptions& options) {
  // Everything that can be refused is refused before the first folder or file is created.
  const FramePattern pattern(options.output_pattern);
  const int frame_count = options.frames == 0 ? script.frames : options.frames;
  check_frame_count(script, frame_count);
  pattern.check(frame_count);
  check_run_inputs(script, mesh, mesh_path, options.device);

  Cloth cloth(mesh, options.device);
  run_cuts(cloth, script, frame_count, [&](const FrameResult& frame, const Cloth& cut_cloth) {
    FrameResult written = frame;
    written.path = pattern.path(frame.frame);
    create_folder_of(written.path);
    write_mesh(cut_cloth.mesh(), written.path);
    if (options.on_frame) options.on_frame(written, cut_cloth);
  });
}

}  // namespace tear
