#include <filesystem>
#include <system_error>

#include "tear/error.h"
#include "tear/frame_sink.h"
#include "tear/write_mesh.h"

namespace tear {

void create_folder_of(const std::string& path) {
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  if (folder.empty()) return;
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) throw runtime_error(folder.string() + ": cannot create the output folder: " + error.message());
}

TemporaryFile FrameSink::stage(int, const Mesh&, std::string&) const {
  throw Error(ErrorKind::usage, "this frame sink writes its frames in order only (FrameSink::write)");
}

void FrameFiles::write(int frame, const Mesh& mesh) {
  std::string bytes;
  commit_temporary_file(stage(frame, mesh, bytes));
}

TemporaryFile FrameFiles::stage(int frame, const Mesh& mesh, std::string& bytes) const {
  const std::string path = pattern_.path(frame);
  create_folder_of(path);
  encode_mesh(mesh, path, format_from_path(path), bytes);
  return write_temporary_file(path, bytes);
}

}  // namespace tear
