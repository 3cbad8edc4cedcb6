#include "farm.h"

#include <csignal>
#include <cstdio>

#include <unistd.h>

#include "tear/error.h"

namespace tear::cli {

namespace {

volatile std::sig_atomic_t stop_requested = 0;
volatile std::sig_atomic_t frames_running = 0;

/// Before the frames run (reading, checking: nothing written yet) a stop ends the process at once,
/// with exit 4 and its one line, whatever the command is doing; while they run, it asks the run to
/// stop after the frame being written.
extern "C" void request_stop(int) {
  if (!frames_running) {
    static const char message[] = "tear: stopped before the first frame was written (SIGTERM or SIGINT)\n";
    const ssize_t ignored = ::write(STDERR_FILENO, message, sizeof message - 1);
    (void)ignored;
    ::_exit(4);
  }
  stop_requested = 1;
}

}  // namespace

void install_stop_handlers() {
  struct sigaction action {};
  action.sa_handler = request_stop;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // a write in progress goes on; the run stops after its frame
  sigaction(SIGTERM, &action, nullptr);
  sigaction(SIGINT, &action, nullptr);
}

void begin_frames() { frames_running = 1; }

void add_farm_options(CLI::App& command, FarmOptions& options) {
  command
      .add_option("--checkpoint", options.checkpoint_path,
                  "Write the state needed to go on bit-exactly to PATH (atomically) after every frame written, "
                  "or every --checkpoint-every frames, and when stopped")
      ->type_name("PATH");
  command
      .add_option("--checkpoint-every", options.checkpoint_every,
                  "Write the checkpoint after every N-th frame (and after the last, and when stopped)")
      ->type_name("N")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  command.add_flag("--resume", options.resume,
                   "Go on after the frame of the --checkpoint when it exists and was made from the same inputs "
                   "(exit 2 when not); start from the first frame when it does not exist");
  command
      .add_option("--progress", options.progress,
                  "Progress on standard error: 'bar', 'lines' (one line per frame: 'frame 12/48 (25%) Progress: 25%'), 'none', "
                  "or 'auto' (the bar on a terminal, nothing otherwise)")
      ->type_name("auto|bar|lines|none")
      ->check(CLI::IsMember({"auto", "bar", "lines", "none"}))
      ->capture_default_str();
  command
      .add_option("--writer-threads", options.writer_threads,
                  "Threads that encode and write the frames beside the run (files still appear in frame order); "
                  "0: min(4, hardware threads)")
      ->type_name("N")
      ->check(CLI::Range(0, 256))
      ->capture_default_str();
}

void apply_farm_options(const FarmOptions& options, RunOptions& run) {
  run.checkpoint_path = options.checkpoint_path;
  run.checkpoint_every = options.checkpoint_every;
  run.resume = options.resume;
  run.writer_threads = options.writer_threads;
  run.stop = &stop_requested;
}

FrameProgress::FrameProgress(const std::string& mode, int total)
    : lines_(mode == "lines"), total_(total > 0 ? total : 1) {
  if (mode == "bar" || mode == "auto") bar_ = std::make_unique<ProgressBar>(total, mode == "bar");
}

void FrameProgress::frame(int done, const std::string& detail) {
  if (bar_) bar_->update(done, detail);
  if (lines_) {
    // `Progress: P%`: the token farm managers' progress handlers look for (docs/cli.md, *Progress*).
    const int percent = static_cast<int>(100LL * done / total_);
    std::fprintf(stderr, "frame %d/%d (%d%%) Progress: %d%%\n", done, total_, percent, percent);
    std::fflush(stderr);
  }
}

void FrameProgress::finish() {
  if (bar_) bar_->finish();
}

}  // namespace tear::cli
