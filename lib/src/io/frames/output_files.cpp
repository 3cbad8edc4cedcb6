#include "tear/output_files.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <set>
#include <string>
#include <system_error>
#include <vector>

#include "tear/error.h"
#include "tear/input_file.h"

namespace tear {

namespace {

namespace fs = std::filesystem;

/// The file `path` names (symlinks followed), when it exists.
struct FileId {
  dev_t device = 0;
  ino_t inode = 0;
  bool exists = false;
  bool folder = false;
};

FileId file_id(const std::string& path) {
  struct stat s {};
  if (path.empty() || ::stat(path.c_str(), &s) != 0) return {};
  return {s.st_dev, s.st_ino, true, S_ISDIR(s.st_mode)};
}

/// The file `path` will name once the writer has made its missing folders: the same as `file_id`,
/// except through a `..` after a folder that does not exist yet (`new/../cloth.obj` is
/// `cloth.obj` once `new` is made), which the file system resolves only then.
FileId file_id_once_written(const std::string& path) {
  const FileId id = file_id(path);
  if (id.exists || path.find("..") == std::string::npos) return id;
  std::error_code error;
  const fs::path resolved = fs::weakly_canonical(fs::path(path), error);
  return error ? FileId{} : file_id(resolved.string());
}

std::string folder_of(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

std::string file_name_of(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

/// `path` made absolute against `cwd` and normalised lexically (no file system access).
std::string normal_path(const fs::path& cwd, const std::string& path) {
  const fs::path p(path);
  return (p.is_absolute() ? p : cwd / p).lexically_normal().string();
}

/// The checks of one output file against the inputs.
class OutputChecker {
 public:
  explicit OutputChecker(const std::vector<NamedPath>& inputs) {
    for (const NamedPath& input : inputs) {
      const FileId id = file_id(input.path);
      if (id.exists) inputs_.push_back({input, id});
    }
  }

  void check(const std::string& what, const std::string& path) {
    const FileId id = file_id_once_written(path);
    if (id.exists) {
      for (const auto& [input, input_id] : inputs_)
        if (id.device == input_id.device && id.inode == input_id.inode)
          throw input_error(path, what + " is the input " + input.what + " " + input.path +
                                      "; refusing to overwrite it (choose another path)");
      if (id.folder) throw input_error(path, "cannot write " + what + ": it is a folder");
    }
    // Only a regular file is replaced: a rename over a device node or a FIFO would replace it,
    // and a symbolic link would be replaced by a file (or, written through, write elsewhere).
    struct stat s {};
    if (::lstat(path.c_str(), &s) == 0 && !S_ISREG(s.st_mode))
      throw input_error(path, "cannot write " + what + ": it is " + file_kind(s.st_mode) +
                                  "; only a regular file is replaced (choose another path)");
    check_folder(folder_of(path));
  }

 private:
  /// The folder exists and can be written, or its nearest existing ancestor can (it will be made).
  void check_folder(const std::string& folder) {
    if (!checked_folders_.insert(folder).second) return;
    std::string existing = folder;
    for (;;) {
      struct stat s {};
      if (::stat(existing.c_str(), &s) == 0) {
        const bool missing = existing != folder;
        const char* action = missing ? "cannot create the output folder" : "cannot write in the output folder";
        if (!S_ISDIR(s.st_mode)) throw runtime_error(folder + ": " + action + ": " + std::strerror(ENOTDIR));
        if (::access(existing.c_str(), W_OK | X_OK) != 0)
          throw runtime_error(folder + ": " + action + ": " + std::strerror(errno));
        return;
      }
      if (errno != ENOENT) {
        const int error = errno;
        throw runtime_error(folder + ": cannot create the output folder: " + std::strerror(error));
      }
      const std::string parent = folder_of(existing);
      if (parent == existing) return;  // nothing exists up to the root: the writer will say why
      existing = parent;
    }
  }

  std::vector<std::pair<NamedPath, FileId>> inputs_;
  std::set<std::string> checked_folders_;
};

}  // namespace

void check_output_files(const std::vector<NamedPath>& inputs, const FramePattern* pattern, int frame_count,
                        const std::vector<NamedPath>& outputs, int first_number) {
  OutputChecker checker(inputs);
  const int frames = pattern == nullptr ? 0 : pattern->has_frame_number() ? frame_count : std::min(frame_count, 1);
  if (frames > 0) check_first_frame(first_number, frames);
  for (int i = 0; i < frames; ++i)
    checker.check("frame " + std::to_string(first_number + i), pattern->path(first_number + i));

  std::error_code error;
  const fs::path cwd = fs::current_path(error);
  std::vector<const NamedPath*> named;
  for (const NamedPath& output : outputs)
    if (!output.path.empty()) named.push_back(&output);
  for (std::size_t i = 0; i < named.size(); ++i) {
    const NamedPath& output = *named[i];
    checker.check(output.what, output.path);
    const std::string normal = normal_path(cwd, output.path);
    for (std::size_t j = 0; j < i; ++j)
      if (normal_path(cwd, named[j]->path) == normal)
        throw Error(ErrorKind::usage, output.path + ": " + output.what + " is also " + named[j]->what);
    // The frames: compared by file name first, so that a long run costs a string comparison a frame.
    const std::string name = file_name_of(output.path);
    for (int i = 0; i < frames; ++i) {
      const int frame = first_number + i;
      const std::string frame_path = pattern->path(frame);
      if (file_name_of(frame_path) == name && normal_path(cwd, frame_path) == normal)
        throw Error(ErrorKind::usage, output.path + ": " + output.what + " is also frame " + std::to_string(frame));
    }
  }
}

}  // namespace tear
