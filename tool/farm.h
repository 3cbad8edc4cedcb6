// tear CLI: what a farm needs of `run` and `demo`: checkpoints, resuming, stopping on SIGTERM or
// SIGINT after a whole frame, and progress lines a farm manager can parse (docs/cli.md, "On a farm").
#pragma once

#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "progress.h"
#include "tear/run_cuts.h"

namespace tear::cli {

struct FarmOptions {
  std::string checkpoint_path;
  int checkpoint_every = 1;
  bool resume = false;
  std::string progress = "auto";
  int writer_threads = 0;
};

/// Adds `--checkpoint PATH`, `--checkpoint-every N`, `--resume`, `--progress auto|bar|lines|none`
/// and `--writer-threads N`.
void add_farm_options(CLI::App& command, FarmOptions& options);

/// Installs the SIGTERM/SIGINT handlers: the first thing `main` does, so that a stop at any
/// moment ends in exit 4. Until `begin_frames`, a stop ends the process at once (nothing has been
/// written); after it, the run stops after the frame being written (`RunOptions::stop`).
void install_stop_handlers();

/// Marks the start of the frames: from now on a stop lets the frame being written finish.
void begin_frames();

/// Copies the checkpoint options and the writer threads into `run`, with the flag the stop
/// handlers set (`RunOptions::stop`). The combination
/// (`--resume` needs `--checkpoint`) is checked with the run's plan (`check_run_plan`).
void apply_farm_options(const FarmOptions& options, RunOptions& run);

/// Progress of a run's frames on standard error: `bar` draws a bar, `lines` prints one line per
/// frame, `frame 12/48 (25%)`, `none` nothing; `auto` is the bar on a terminal, nothing otherwise.
class FrameProgress {
 public:
  FrameProgress(const std::string& mode, int total);
  void frame(int done, const std::string& detail);
  void finish();

 private:
  bool lines_;
  int total_;
  std::unique_ptr<ProgressBar> bar_;
};

}  // namespace tear::cli
