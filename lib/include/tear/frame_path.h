// tear: output file names of a frame sequence, from a pattern such as `out/cloth.####.obj`.
#pragma once

#include <string>

namespace tear {

/// An output pattern: a path in which the frame number goes where a placeholder stands.
///
/// Placeholders (anywhere in the path, folders included; each one gets the same number):
/// - a run of `#`: the frame number zero-padded to the run's length (`####` → `0007`); a number
///   with more digits than `#`s is written whole (`##` → `123`);
/// - `{frame}`: the frame number without padding;
/// - `{frame:0N}` (N from 1 to 9): zero-padded to N digits, as in Python's format.
///
/// Any other `{frame...}` (`{frame:4}`, `{frame:x}`, an unclosed `{frame`) is a usage error, so a
/// typo never becomes part of a file name. Other braces are literal.
/// Refuses (a usage `Error` naming `--start-frame`) a first frame number below 0, or one whose run
/// of `frame_count` frames would number past the largest int.
void check_first_frame(int first_frame, int frame_count);

class FramePattern {
 public:
  /// Parses `pattern`. Throws a usage `Error` naming the pattern when it is empty or holds a
  /// malformed `{frame...}` placeholder.
  explicit FramePattern(std::string pattern);

  /// True when the pattern has at least one placeholder, so that every frame gets its own file.
  bool has_frame_number() const { return has_frame_number_; }

  /// The path of frame `frame` (>= 0).
  std::string path(int frame) const;

  /// Checks the pattern for a run of `frame_count` frames numbered from `first_frame` before
  /// anything is written: a pattern without placeholder is allowed for a single frame only (it is
  /// then the file name itself) unless it names a USD layer (`is_usd_path`: one layer holds every
  /// frame), and every frame's extension must name a format tear writes (`format_from_path`'s, or
  /// .usda/.usd). Throws a usage `Error` naming the pattern otherwise.
  void check(int frame_count, int first_frame = 1) const;

  const std::string& pattern() const { return pattern_; }

 private:
  std::string pattern_;
  bool has_frame_number_ = false;
};

/// `FramePattern(pattern).path(frame)`.
std::string expand_frame_path(const std::string& pattern, int frame);

}  // namespace tear
