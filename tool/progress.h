// tear CLI: a progress bar on standard error, drawn only when standard error is a terminal, so
// pipelines and farm logs stay clean.
#pragma once

#include <string>

namespace tear::cli {

class ProgressBar {
 public:
  /// `total` steps; draws nothing unless standard error is a terminal (or `force` is set).
  explicit ProgressBar(int total, bool force = false);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  /// `done` of `total` steps finished; `detail` follows the bar on the same line.
  void update(int done, const std::string& detail);
  /// Clears the bar's line (also done by the destructor).
  void finish();
  bool enabled() const { return enabled_; }

 private:
  int total_;
  bool enabled_;
  bool drawn_ = false;
};

}  // namespace tear::cli
