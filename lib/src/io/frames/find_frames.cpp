#include "tear/find_frames.h"

#include <algorithm>
#include <cctype>
#include <climits>
#include <filesystem>
#include <string>
#include <system_error>

#include "tear/error.h"

namespace tear {

namespace {

namespace fs = std::filesystem;

/// The frame number a file name may carry: the first run of digits standing where the pattern's
/// first placeholder stands, or -1. `prefix` is the pattern's literal text before that placeholder.
int number_after(const std::string& name, const std::string& prefix) {
  if (name.compare(0, prefix.size(), prefix) != 0) return -1;
  std::size_t end = prefix.size();
  while (end < name.size() && std::isdigit(static_cast<unsigned char>(name[end]))) ++end;
  if (end == prefix.size() || end - prefix.size() > 9) return -1;  // 9 digits fit an int
  return std::stoi(name.substr(prefix.size(), end - prefix.size()));
}

}  // namespace

std::vector<int> find_frames(const FramePattern& pattern) {
  const std::string& text = pattern.pattern();
  if (!pattern.has_frame_number())
    throw Error(ErrorKind::usage, "pattern '" + text + "': no frame number (put #### or {frame:04} where it goes)");
  const std::size_t slash = text.find_last_of('/');
  const std::string folder = slash == std::string::npos ? "" : text.substr(0, slash + 1);
  const std::string file = slash == std::string::npos ? text : text.substr(slash + 1);
  if (folder.find('#') != std::string::npos || folder.find("{frame") != std::string::npos)
    throw Error(ErrorKind::usage, "pattern '" + text + "': the frame number must be in the file name, not a folder");
  const std::string prefix = file.substr(0, std::min(file.find('#'), file.find("{frame")));

  std::vector<int> frames;
  std::error_code error;
  fs::directory_iterator it(folder.empty() ? fs::path(".") : fs::path(folder), error), end;
  if (error) throw input_error(text, "cannot list the folder (" + error.message() + ")");
  for (; it != end; it.increment(error)) {
    if (error) throw input_error(text, "cannot list the folder (" + error.message() + ")");
    const std::string name = it->path().filename().string();
    const int frame = number_after(name, prefix);
    // The pattern itself decides: padding, repeated placeholders and the rest of the name must agree.
    if (frame >= 0 && pattern.path(frame) == folder + name && !it->is_directory(error)) frames.push_back(frame);
  }
  std::sort(frames.begin(), frames.end());
  return frames;
}

}  // namespace tear
