// Frames written beside the run (tear/frame_writer.h): the bytes of frames written one after the
// other, files renamed in frame order, bounded frames in flight, a failing frame's error with the
// frames before it on disk and nothing after it, checkpoints and stops after the frame is on disk.
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "catch.h"
#include "cli_support.h"
#include "tear/checkpoint.h"
#include "tear/cut_script.h"
#include "tear/error.h"
#include "tear/frame_path.h"
#include "tear/frame_sink.h"
#include "tear/frame_writer.h"
#include "tear/run_cuts.h"
#include "tear/usd_layer.h"
#include "tear/write_mesh.h"
#include "test_support.h"

namespace fs = std::filesystem;
using tear::test::read_bytes;
using tear::test::regular_sheet;
using tear::test::TempDir;
using tear::test::test_device;

namespace {

/// Eight frames of a hanging sheet, cut twice: the cloth moves, so every frame's normals are
/// computed again, and the mesh changes at frames 2 and 5.
const char* const falling_script = R"({ "version": 1, "frames": 8,
  "cuts": [ { "frame": 2, "space": "rest-xy", "polyline": [[-0.1, 0.53], [0.56, 0.53]] },
            { "frame": 5, "space": "rest-xy", "polyline": [[1.1, 0.33], [0.44, 0.33]] } ],
  "simulation": { "substeps": 1, "iterations": 10,
                  "pins": [ { "box": { "min": [-1, 0.999, -1], "max": [2, 1.001, 1] } } ] } })";

tear::RunOptions run_options(const fs::path& pattern, int writer_threads = 0) {
  tear::RunOptions options;
  options.output_pattern = pattern.string();
  options.device = test_device();
  options.writer_threads = writer_threads;
  return options;
}

/// Every file under `folder` (relative paths, sorted), temporary files included.
std::vector<std::string> files_under(const fs::path& folder) {
  std::vector<std::string> names;
  for (const fs::directory_entry& entry : fs::recursive_directory_iterator(folder))
    if (!entry.is_directory()) names.push_back(fs::relative(entry.path(), folder).string());
  std::sort(names.begin(), names.end());
  return names;
}

/// Frame files as a `FrameFiles` writes them, staged slowly so that frames finish out of order
/// (a frame takes longer the earlier it is), with the stages running at once counted.
class SlowFrameFiles final : public tear::FrameSink {
 public:
  SlowFrameFiles(const fs::path& pattern, int frame_count)
      : files_(tear::FramePattern(pattern.string())), frame_count_(frame_count) {}
  void write(int frame, const tear::Mesh& mesh) override { files_.write(frame, mesh); }
  std::string path_of(int frame) const override { return files_.path_of(frame); }
  bool stages_files() const override { return true; }
  tear::TemporaryFile stage(int frame, const tear::Mesh& mesh, std::string& bytes) const override {
    const int now = ++staging_;
    for (int most = most_staging_; now > most && !most_staging_.compare_exchange_weak(most, now);) {
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(3 * (frame_count_ - frame)));
    tear::TemporaryFile file = files_.stage(frame, mesh, bytes);
    --staging_;
    return file;
  }
  int most_staging() const { return most_staging_; }

 private:
  tear::FrameFiles files_;
  int frame_count_;
  mutable std::atomic<int> staging_{0}, most_staging_{0};
};

/// Frame files whose stages note the OpenMP threads their thread's teams get.
class TeamFrameFiles final : public tear::FrameSink {
 public:
  explicit TeamFrameFiles(const fs::path& pattern) : files_(tear::FramePattern(pattern.string())) {}
  void write(int frame, const tear::Mesh& mesh) override { files_.write(frame, mesh); }
  std::string path_of(int frame) const override { return files_.path_of(frame); }
  bool stages_files() const override { return true; }
  tear::TemporaryFile stage(int frame, const tear::Mesh& mesh, std::string& bytes) const override {
    const int threads = omp_get_max_threads();
    for (int most = most_threads_; threads > most && !most_threads_.compare_exchange_weak(most, threads);) {
    }
    for (int least = least_threads_; threads < least && !least_threads_.compare_exchange_weak(least, threads);) {
    }
    return files_.stage(frame, mesh, bytes);
  }
  int most_threads() const { return most_threads_; }
  int least_threads() const { return least_threads_; }

 private:
  tear::FrameFiles files_;
  mutable std::atomic<int> most_threads_{0}, least_threads_{1 << 30};
};

/// Frame files that note each frame's OpenMP team; frame 1's stage waits (10 s at most) until
/// frame 2's has begun, so frame 2 is taken while frame 1 is written.
class GatedTeamFrameFiles final : public tear::FrameSink {
 public:
  explicit GatedTeamFrameFiles(const fs::path& pattern) : files_(tear::FramePattern(pattern.string())) {}
  void write(int frame, const tear::Mesh& mesh) override { files_.write(frame, mesh); }
  std::string path_of(int frame) const override { return files_.path_of(frame); }
  bool stages_files() const override { return true; }
  tear::TemporaryFile stage(int frame, const tear::Mesh& mesh, std::string& bytes) const override {
    std::unique_lock<std::mutex> lock(mutex_);
    teams_[frame] = omp_get_max_threads();
    began_.notify_all();
    if (frame == 1) began_.wait_for(lock, std::chrono::seconds(10), [&] { return teams_.count(2) > 0; });
    lock.unlock();
    return files_.stage(frame, mesh, bytes);
  }
  int team(int frame) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return teams_.count(frame) ? teams_.at(frame) : 0;
  }
  /// Waits (10 s at most) until frame `frame`'s stage has begun; whether it has.
  bool wait_until_began(int frame) const {
    std::unique_lock<std::mutex> lock(mutex_);
    return began_.wait_for(lock, std::chrono::seconds(10), [&] { return teams_.count(frame) > 0; });
  }

 private:
  tear::FrameFiles files_;
  mutable std::mutex mutex_;
  mutable std::condition_variable began_;
  mutable std::map<int, int> teams_;
};

}  // namespace

TEST_CASE("frame_writer: a frame written alone is encoded on all the OpenMP threads", "[writer]") {
  TempDir dir;
  const int available = omp_get_max_threads();
  for (int threads : {1, 2, 3, 64}) {
    INFO(threads << " writer threads, " << available << " OpenMP threads");
    TeamFrameFiles sink(dir / std::to_string(threads) / "f.##.obj");
    tear::FrameWriterOptions options;
    options.threads = threads;
    {
      tear::FrameWriter writer(sink, options);
      CHECK(writer.encode_threads() == std::max(1, available / threads));
      for (int frame = 1; frame <= 3; ++frame) {
        writer.write(frame, regular_sheet(), false, {});
        writer.finish();  // the next frame is handed over once this one is on disk
      }
    }
    CHECK(sink.least_threads() == available);
    CHECK(sink.most_threads() == available);
    CHECK(omp_get_max_threads() == available);  // the caller's own count is left alone
  }
}

TEST_CASE("frame_writer: frames written at once share the OpenMP threads", "[writer]") {
  TempDir dir;
  const int available = omp_get_max_threads();
  INFO(available << " OpenMP threads");
  GatedTeamFrameFiles sink(dir / "f.##.obj");
  tear::FrameWriterOptions options;
  options.threads = 2;
  {
    tear::FrameWriter writer(sink, options);
    writer.write(1, regular_sheet(), false, {});
    REQUIRE(sink.wait_until_began(1));  // frame 1 taken alone, before frame 2 is handed over
    for (int frame = 2; frame <= 6; ++frame) writer.write(frame, regular_sheet(), false, {});
    writer.finish();
  }
  REQUIRE(sink.wait_until_began(2));
  CHECK(sink.team(1) == available);                  // taken alone
  CHECK(sink.team(2) == std::max(1, available / 2));  // taken while frame 1 was written
  for (int frame = 3; frame <= 6; ++frame) {
    CHECK(sink.team(frame) >= std::max(1, available / 2));
    CHECK(sink.team(frame) <= available);
  }
}

TEST_CASE("frame_writer: frames written beside the run are the bytes of frames written one after the other",
          "[writer]") {
  TempDir dir;
  const tear::CutScript script = tear::parse_cut_script(falling_script, "falling.json");
  REQUIRE(regular_sheet().has_normals());
  for (const char* extension : {"obj", "ply", "gltf", "glb", "usda"}) {
    INFO(extension);
    const std::string name = std::string("f.####.") + extension;
    // One after the other: the frame loop, each frame's normals and file on this thread.
    const tear::FramePattern reference((dir / extension / "reference" / name).string());
    fs::create_directories(dir / extension / "reference");
    tear::UsdLayerOptions usd;
    usd.frames_per_second = script.simulation->fps;
    tear::Cloth cloth(regular_sheet(), test_device());
    tear::run_cuts(cloth, script, script.frames, [&](const tear::FrameResult& frame, const tear::Cloth& moved) {
      tear::Mesh mesh = moved.mesh();
      mesh.corner_normal = tear::area_weighted_corner_normals(mesh);
      const std::string path = reference.path(frame.frame);
      if (tear::is_usd_path(path))
        tear::write_file_atomically(path, tear::usda_layer_text(mesh, frame.frame, usd));
      else
        tear::write_mesh(mesh, path);
    });
    for (int threads : {1, 4}) {
      INFO(threads << " writer threads");
      const fs::path folder = dir / extension / std::to_string(threads);
      tear::run_to_files(regular_sheet(), "sheet", script, run_options(folder / name, threads));
      CHECK(files_under(folder).size() == 8);
      for (int frame = 1; frame <= 8; ++frame) {
        INFO("frame " << frame);
        CHECK(read_bytes(tear::expand_frame_path((folder / name).string(), frame)) ==
              read_bytes(reference.path(frame)));
      }
    }
  }
}

TEST_CASE("frame_writer: files are renamed in frame order, each followed by its on_written", "[writer]") {
  TempDir dir;
  constexpr int frame_count = 12;
  SlowFrameFiles sink(dir / "out/f.##.ply", frame_count);
  tear::FrameWriterOptions options;
  options.threads = 4;
  std::vector<int> written;
  {
    tear::FrameWriter writer(sink, options);
    CHECK(writer.threads() == 4);
    CHECK(writer.max_in_flight() == 8);
    for (int frame = 1; frame <= frame_count; ++frame) {
      writer.write(frame, regular_sheet(), frame % 2 == 0, [&, frame] {
        written.push_back(frame);
        // This frame is on disk, the next one is not yet, though its thread may have finished first.
        CHECK(fs::is_regular_file(sink.path_of(frame)));
        CHECK_FALSE(fs::exists(sink.path_of(frame + 1)));
      });
    }
    writer.finish();
  }
  std::vector<int> in_order(frame_count);
  for (int i = 0; i < frame_count; ++i) in_order[i] = i + 1;
  CHECK(written == in_order);
  CHECK(sink.most_staging() > 1);  // frames were written side by side
  CHECK(files_under(dir / "out").size() == frame_count);
}

TEST_CASE("frame_writer: no more than max_in_flight frames are in flight, the hand-over waits", "[writer]") {
  TempDir dir;
  constexpr int frame_count = 20;
  SlowFrameFiles sink(dir / "out/f.##.obj", frame_count);
  tear::FrameWriterOptions options;
  options.threads = 2;
  options.max_in_flight = 3;
  tear::FrameWriter writer(sink, options);
  CHECK(writer.max_in_flight() == 3);
  for (int frame = 1; frame <= frame_count; ++frame) writer.write(frame, regular_sheet(), false, {});
  writer.finish();
  // The hand-overs outrun the threads, so the writer fills up, and no further.
  CHECK(writer.most_in_flight() == 3);
  CHECK(sink.most_staging() <= 2);
  CHECK(files_under(dir / "out").size() == frame_count);
}

TEST_CASE(
    "frame_writer: a frame that cannot be written ends the run with its error, the frames before it on "
    "disk, nothing after it, no temporary file",
    "[writer]") {
  const tear::CutScript script = tear::parse_cut_script(falling_script, "falling.json");
  struct Case {
    const char* what;
    const char* pattern;
    const char* blocker;  // made before the run: frame 5's file is a folder, or its folder a file
    bool blocker_is_folder;
    const char* message_start;
  };
  for (const Case& c :
       {Case{"its rename fails", "out/f.####.obj", "out/f.0005.obj", true, "out/f.0005.obj: cannot write: "},
        Case{"its folder cannot be made", "out/f####/cloth.obj", "out/f0005", false,
             "out/f0005: cannot create the output folder: "}}) {
    INFO(c.what);
    TempDir dir;
    fs::create_directories(dir / "out");
    if (c.blocker_is_folder)
      fs::create_directories(dir / c.blocker);
    else
      dir.file(c.blocker, "not a folder");
    tear::RunOptions options = run_options(dir / c.pattern, 4);
    std::vector<int> on_disk;
    options.on_frame = [&](const tear::FrameResult& frame) { on_disk.push_back(frame.frame); };
    try {
      tear::run_to_files(regular_sheet(), "sheet", script, options);
      FAIL("no error");
    } catch (const tear::Error& e) {
      CHECK(e.kind() == tear::ErrorKind::runtime);
      CHECK(std::string(e.what()).rfind((dir / c.message_start).string(), 0) == 0);
    }
    CHECK(on_disk == std::vector<int>{1, 2, 3, 4});
    std::vector<std::string> expected;
    for (int frame = 1; frame <= 4; ++frame) expected.push_back(tear::expand_frame_path(c.pattern, frame).substr(4));
    if (!c.blocker_is_folder) expected.push_back("f0005");
    std::sort(expected.begin(), expected.end());
    CHECK(files_under(dir / "out") == expected);
  }
}

TEST_CASE(
    "frame_writer: a checkpoint names a frame on disk, a stop waits for the frames handed over, resuming "
    "gives the same bytes",
    "[writer][resume]") {
  TempDir dir;
  const tear::CutScript script = tear::parse_cut_script(falling_script, "falling.json");
  tear::run_to_files(regular_sheet(), "sheet", script, run_options(dir / "whole/f.####.ply"));

  const fs::path checkpoint = dir / "shot.ckpt";
  volatile std::sig_atomic_t stop = 0;
  // One thread, so two frames in flight: frame 1 is on disk (and sets the stop) by the hand-over of
  // frame 3 at the latest, and the run stops at the next hand-over, with a frame or two in flight.
  tear::RunOptions options = run_options(dir / "stopped/f.####.ply", 1);
  options.checkpoint_path = checkpoint.string();
  options.stop = &stop;
  options.on_frame = [&](const tear::FrameResult& frame) {
    INFO("frame " << frame.frame);
    CHECK(fs::is_regular_file(frame.path));
    // The checkpoint of this frame comes after this call; the one there is the previous frame's.
    if (frame.frame > 1) CHECK(tear::read_checkpoint(checkpoint.string()).frame == frame.frame - 1);
    if (frame.frame == 1) stop = 1;
  };
  int stopped_after = 0;
  try {
    tear::run_to_files(regular_sheet(), "sheet", script, options);
    FAIL("not stopped");
  } catch (const tear::Error& e) {
    CHECK(e.kind() == tear::ErrorKind::interrupted);
    stopped_after = tear::read_checkpoint(checkpoint.string()).frame;
    CHECK(std::string(e.what()).rfind("stopped after frame " + std::to_string(stopped_after) + " of 8", 0) == 0);
  }
  // Every frame up to the checkpoint's is on disk, none after it, and no temporary file.
  REQUIRE(stopped_after >= 2);
  REQUIRE(stopped_after <= 4);
  CHECK(files_under(dir / "stopped").size() == static_cast<std::size_t>(stopped_after));
  CHECK(fs::exists(tear::expand_frame_path((dir / "stopped/f.####.ply").string(), stopped_after)));

  stop = 0;
  options.resume = true;
  options.on_frame = {};
  tear::run_to_files(regular_sheet(), "sheet", script, options);
  CHECK(tear::read_checkpoint(checkpoint.string()).frame == 8);
  for (int frame = 1; frame <= 8; ++frame) {
    INFO("frame " << frame);
    CHECK(read_bytes(tear::expand_frame_path((dir / "stopped/f.####.ply").string(), frame)) ==
          read_bytes(tear::expand_frame_path((dir / "whole/f.####.ply").string(), frame)));
  }
}
