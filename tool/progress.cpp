#include "progress.h"

#include <unistd.h>

#include <cstdio>

namespace tear::cli {

ProgressBar::ProgressBar(int total, bool force) : total_(total > 0 ? total : 1), enabled_(force || isatty(STDERR_FILENO)) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::update(int done, const std::string& detail) {
  if (!enabled_) return;
  constexpr int width = 30;
  const int filled = static_cast<int>(static_cast<long long>(width) * done / total_);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.append(static_cast<std::size_t>(width - filled), '.');
  // \r returns to the line's start, \033[K clears what a longer previous line left.
  std::fprintf(stderr, "\r[%s] %d/%d %s\033[K", bar.c_str(), done, total_, detail.c_str());
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressBar::finish() {
  if (!drawn_) return;
  std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
  drawn_ = false;
}

}  // namespace tear::cli
