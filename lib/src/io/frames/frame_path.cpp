#include "tear/frame_path.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <string>
#include <utility>

#include "tear/error.h"
#include "tear/usd_layer.h"
#include "tear/write_mesh.h"

namespace tear {

namespace {

Error pattern_error(const std::string& pattern, const std::string& what) {
  return Error(ErrorKind::usage, "output pattern '" + pattern + "': " + what);
}

std::string padded(int frame, std::size_t width) {
  std::string digits = std::to_string(frame);
  if (digits.size() < width) digits.insert(0, width - digits.size(), '0');
  return digits;
}

/// Expands every placeholder of `pattern` with `frame`; sets `*found` when there was one. The one
/// parser of the syntax, so that checking and expanding cannot disagree.
std::string expand(const std::string& pattern, int frame, bool* found) {
  static const char open[] = "{frame";
  const std::size_t open_size = std::strlen(open);
  std::string out;
  *found = false;
  for (std::size_t i = 0; i < pattern.size();) {
    if (pattern[i] == '#') {
      std::size_t end = i;
      while (end < pattern.size() && pattern[end] == '#') ++end;
      out += padded(frame, end - i);
      *found = true;
      i = end;
      continue;
    }
    if (pattern.compare(i, open_size, open) == 0) {
      const std::size_t close = pattern.find('}', i);
      const std::string placeholder = pattern.substr(i, close == std::string::npos ? std::string::npos : close - i + 1);
      const std::string spec = close == std::string::npos ? "" : pattern.substr(i + open_size, close - i - open_size);
      std::size_t width = 0;
      bool valid = close != std::string::npos;
      if (valid && !spec.empty()) {
        // ":0N", one digit N from 1 to 9: the only format spec that makes sense for a file name.
        valid = spec.size() == 3 && spec[0] == ':' && spec[1] == '0' && spec[2] >= '1' && spec[2] <= '9';
        if (valid) width = static_cast<std::size_t>(spec[2] - '0');
      }
      if (!valid)
        throw pattern_error(pattern,
                            "bad placeholder '" + placeholder + "' (expected {frame} or {frame:0N}, N from 1 to 9)");
      out += padded(frame, width);
      *found = true;
      i = close + 1;
      continue;
    }
    out += pattern[i++];
  }
  return out;
}

}  // namespace

FramePattern::FramePattern(std::string pattern) : pattern_(std::move(pattern)) {
  if (pattern_.empty()) throw pattern_error(pattern_, "empty (expected a path such as out/cloth.####.obj)");
  expand(pattern_, 1, &has_frame_number_);
}

std::string FramePattern::path(int frame) const {
  bool found = false;
  return expand(pattern_, frame, &found);
}

void check_first_frame(int first_frame, int frame_count) {
  const int largest = std::numeric_limits<int>::max() - (std::max(frame_count, 1) - 1);
  if (first_frame < 0 || first_frame > largest)
    throw Error(ErrorKind::usage, "--start-frame: expected an integer from 0 to " + std::to_string(largest) +
                                      " for a run of " + std::to_string(frame_count) + " frames, got " +
                                      std::to_string(first_frame));
}

void FramePattern::check(int frame_count, int first_frame) const {
  check_first_frame(first_frame, frame_count);
  // One USD layer holds every frame; any other file holds one.
  if (!has_frame_number_ && frame_count > 1 && !is_usd_path(pattern_))
    throw pattern_error(pattern_, "no frame number, and the run has " + std::to_string(frame_count) +
                                      " frames (put #### or {frame:04} where the number goes, or write one USD "
                                      "layer: .usda)");
  // Placeholders may sit in the extension too ("x.{frame}"), so every frame's path is checked.
  for (int i = 0; i < frame_count; ++i) {
    const std::string frame_path = path(first_frame + i);
    const std::size_t slash = frame_path.find_last_of('/');
    const std::string name = slash == std::string::npos ? frame_path : frame_path.substr(slash + 1);
    if (name.empty() || name == "." || name == "..")
      throw pattern_error(pattern_, "no file name (expected a path such as out/cloth.####.obj)");
    if (!is_usd_path(frame_path)) {
      try {
        format_from_path(frame_path);
      } catch (const Error&) {
        // The pattern is what the user typed: name it rather than one of its expansions.
        const std::size_t dot = name.find_last_of('.');
        throw pattern_error(pattern_, "unknown output format" +
                                          (dot == std::string::npos ? std::string(" (no extension)")
                                                                    : " '" + name.substr(dot) + "'") +
                                          "; supported: .obj, .ply, .gltf, .glb, .usda, .usd");
      }
    }
    if (!has_frame_number_) break;
  }
}

std::string expand_frame_path(const std::string& pattern, int frame) { return FramePattern(pattern).path(frame); }

}  // namespace tear
