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

void FrameFiles::write(int frame, const Mesh& mesh) {
  const std::string path = pattern_.path(frame);
  create_folder_of(path);
  write_mesh(mesh, path);
}

}  // namespace tear
