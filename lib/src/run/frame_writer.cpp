#include "tear/frame_writer.h"

#include <omp.h>

#include <algorithm>
#include <climits>
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

#include "tear/run_cuts.h"
#include "tear/write_mesh.h"

namespace tear {

struct FrameWriter::Pool {
  /// A frame handed over, from the hand-over to its rename.
  struct Frame {
    enum class Stage { waiting, writing, written, failed };
    int frame = 0;
    PendingMesh pending;  // taken into `mesh` by the thread that writes the frame
    Mesh mesh;            // released once its file is written
    bool recompute_normals = false;
    std::function<void()> on_written;
    std::function<void(const Mesh&)> inspect;
    Stage stage = Stage::waiting;
    TemporaryFile file;          // a sink of files: the frame's file before its rename
    std::exception_ptr failure;  // Stage::failed
  };

  FrameSink& sink;
  const bool stages_files;
  std::size_t max_in_flight = 0;
  int openmp_threads = 1;  // P: omp_get_max_threads() where the writer was made
  std::vector<std::thread> threads;

  std::mutex mutex;
  std::condition_variable to_write;  // a frame was handed over, or the writer stops
  std::condition_variable written;   // a thread is done with a frame
  // In frame order; the front is the next to rename. Pointers stay valid while others come and go.
  std::deque<std::unique_ptr<Frame>> frames;
  int failed_frame = INT_MAX;  // the earliest frame that failed
  std::exception_ptr failure;  // once thrown, thrown again by every later call
  std::size_t most_in_flight = 0;
  bool stopping = false;

  Pool(FrameSink& frame_sink, const FrameWriterOptions& options)
      : sink(frame_sink), stages_files(frame_sink.stages_files()) {
    // At most as many writer threads as this thread's OpenMP limit (--threads, OMP_NUM_THREADS).
    const int hardware = std::min(static_cast<int>(std::thread::hardware_concurrency()), omp_get_max_threads());
    const int count = options.threads > 0 ? options.threads : std::max(1, std::min(4, hardware));
    max_in_flight = options.max_in_flight > 0 ? static_cast<std::size_t>(options.max_in_flight)
                                              : 2 * static_cast<std::size_t>(count);
    openmp_threads = omp_get_max_threads();
    threads.reserve(static_cast<std::size_t>(count));
    try {
      for (int i = 0; i < count; ++i) threads.emplace_back([this] { work(); });
    } catch (...) {
      stop();
      throw;
    }
  }

  /// The first frame waiting for a thread, unless a frame before it failed (nothing after a
  /// failure is written); null when none.
  Frame* next_to_write() {
    for (const std::unique_ptr<Frame>& f : frames)
      if (f->stage == Frame::Stage::waiting) return f->frame < failed_frame ? f.get() : nullptr;
    return nullptr;
  }

  /// max(1, P / the frames being written or waiting for a thread, at most one per thread); under the lock.
  int team_size() const {
    std::size_t busy = 0;
    for (const std::unique_ptr<Frame>& f : frames)
      if ((f->stage == Frame::Stage::writing || f->stage == Frame::Stage::waiting) && f->frame < failed_frame) ++busy;
    busy = std::min(std::max<std::size_t>(busy, 1), threads.size());
    return std::max(1, openmp_threads / static_cast<int>(busy));
  }

  /// A thread: takes the frames in order and writes each one's file (or only its normals, for a
  /// sink that takes its frames in order).
  void work() {
    // This thread's encoding buffer: its memory serves frame after frame.
    std::string bytes;
    std::unique_lock<std::mutex> lock(mutex);
    for (;;) {
      Frame* frame = nullptr;
      to_write.wait(lock, [&] { return stopping || (frame = next_to_write()) != nullptr; });
      if (stopping) return;
      frame->stage = Frame::Stage::writing;
      // The OpenMP team this frame is encoded on (encode_mesh's, tear/write_mesh.h): the share of P
      // of each frame now being written or waiting for a thread (this one included), so that the
      // threads encoding at once ask for about as many threads as there are, and a frame written
      // alone (the one frame of a run, the last of a run) has them all.
      omp_set_num_threads(team_size());
      lock.unlock();
      std::exception_ptr failure;
      try {
        frame->mesh = frame->pending.take();
        Mesh& mesh = frame->mesh;
        if (frame->recompute_normals) mesh.corner_normal = area_weighted_corner_normals(mesh);
        if (frame->inspect) frame->inspect(mesh);
        if (stages_files) {
          frame->file = sink.stage(frame->frame, mesh, bytes);
          mesh = Mesh();
        }
      } catch (...) {
        failure = std::current_exception();
      }
      lock.lock();
      if (failure) {
        frame->stage = Frame::Stage::failed;
        frame->failure = failure;
        failed_frame = std::min(failed_frame, frame->frame);
      } else {
        frame->stage = Frame::Stage::written;
      }
      written.notify_all();
    }
  }

  /// Renames the written frames at the front, in order, calling their `on_written`, until at most
  /// `keep` frames are in flight and no failure is pending; waits for the threads meanwhile.
  /// Throws the failure of the first frame that failed once it is at the front.
  void commit_ready(std::unique_lock<std::mutex>& lock, std::size_t keep) {
    if (failure) std::rethrow_exception(failure);
    for (;;) {
      Frame* front = frames.empty() ? nullptr : frames.front().get();
      if (front != nullptr && front->stage == Frame::Stage::failed) {
        failure = front->failure;
        std::rethrow_exception(failure);
      }
      if (front != nullptr && front->stage == Frame::Stage::written) {
        std::unique_ptr<Frame> done = std::move(frames.front());
        frames.pop_front();
        lock.unlock();
        try {
          if (stages_files)
            commit_temporary_file(done->file);
          else
            sink.write(done->frame, done->mesh);
          if (done->on_written) done->on_written();
        } catch (...) {
          lock.lock();
          failure = std::current_exception();
          throw;
        }
        lock.lock();
        continue;
      }
      if (frames.size() <= keep && failed_frame == INT_MAX) return;
      written.wait(lock);
    }
  }

  /// Ends the threads once each is done with its frame.
  void stop() {
    {
      std::lock_guard<std::mutex> lock(mutex);
      stopping = true;
    }
    to_write.notify_all();
    for (std::thread& thread : threads) thread.join();
  }

  ~Pool() {
    stop();
    // The frames never renamed: a failure, or a run that stopped on an error of its own.
    for (const std::unique_ptr<Frame>& frame : frames)
      if (frame->stage == Frame::Stage::written && stages_files) remove_temporary_file(frame->file);
  }
};

FrameWriter::FrameWriter(FrameSink& sink, FrameWriterOptions options) : pool_(std::make_unique<Pool>(sink, options)) {}

FrameWriter::~FrameWriter() = default;

void FrameWriter::write(int frame, Mesh mesh, bool recompute_normals, std::function<void()> on_written) {
  write(frame, PendingMesh(std::move(mesh)), recompute_normals, std::move(on_written));
}

void FrameWriter::write(int frame, PendingMesh mesh, bool recompute_normals, std::function<void()> on_written) {
  write(frame, std::move(mesh), recompute_normals, std::move(on_written), {});
}

void FrameWriter::write(int frame, PendingMesh mesh, bool recompute_normals, std::function<void()> on_written,
                        std::function<void(const Mesh&)> inspect) {
  Pool& pool = *pool_;
  std::unique_lock<std::mutex> lock(pool.mutex);
  pool.commit_ready(lock, pool.max_in_flight - 1);
  auto handed = std::make_unique<Pool::Frame>();
  handed->frame = frame;
  handed->pending = std::move(mesh);
  handed->recompute_normals = recompute_normals;
  handed->on_written = std::move(on_written);
  handed->inspect = std::move(inspect);
  pool.frames.push_back(std::move(handed));
  pool.most_in_flight = std::max(pool.most_in_flight, pool.frames.size());
  pool.to_write.notify_one();
}

void FrameWriter::finish() {
  std::unique_lock<std::mutex> lock(pool_->mutex);
  pool_->commit_ready(lock, 0);
}

int FrameWriter::threads() const { return static_cast<int>(pool_->threads.size()); }

int FrameWriter::encode_threads() const { return std::max(1, pool_->openmp_threads / threads()); }

std::size_t FrameWriter::max_in_flight() const { return pool_->max_in_flight; }

std::size_t FrameWriter::most_in_flight() const {
  std::lock_guard<std::mutex> lock(pool_->mutex);
  return pool_->most_in_flight;
}

}  // namespace tear
