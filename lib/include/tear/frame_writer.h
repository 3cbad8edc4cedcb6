// tear: the frames of a run written beside the computation: a few threads compute each frame's
// normals, encode it and write it to a temporary file, while the thread that runs the frames only
// hands each mesh over; the files are renamed into place in frame order.
//
// Frames 1, 2, 3 of `out/f.####.obj` handed over to a writer of two threads: the threads write
// `out/.f.0001.obj.tmp.<pid>` and `out/.f.0002.obj.tmp.<pid>` at once, then frame 3's; whichever
// finishes first, the hand-overs and `finish` rename f.0001.obj, then f.0002.obj, then f.0003.obj,
// each followed by its frame's `on_written`, so a reader watching `out/` never sees frame 2 before
// frame 1 and a checkpoint written by `on_written` never names a frame that is not on disk.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>

#include "tear/frame_sink.h"
#include "tear/mesh.h"
#include "tear/pending_mesh.h"

namespace tear {

/// Options of `FrameWriter`; `RunOptions::writer_threads` and `tear run --writer-threads` set `threads`.
struct FrameWriterOptions {
  /// Threads that compute normals, encode and write the frames; 0: min(4, hardware threads).
  /// Each encodes a frame on a team of OpenMP threads of its own (`encode_mesh`): a large frame is
  /// encoded in pieces. The team is P / B threads (at least 1), P being `omp_get_max_threads()`
  /// where the writer is made (OMP_NUM_THREADS, else the hardware threads) and B the frames being
  /// written or waiting for a thread when the frame is taken, at most `threads`: a frame written
  /// alone has all P, and threads all busy have max(1, P / threads) each.
  int threads = 0;
  /// Frames handed over and not yet renamed, at most: a hand-over waits while there are this many,
  /// so memory stays bounded however many frames a run has. 0: twice the threads.
  int max_in_flight = 0;
};

/// Writes the frames of a run to a `FrameSink` on threads of its own, in frame order.
///
/// `write` hands a frame's mesh over (moved, not copied, or still on its way from the backend) and
/// returns at once unless `max_in_flight` frames are already in flight. A thread then waits for a
/// mesh on its way, computes the frame's normals when
/// asked (`area_weighted_corner_normals`) and, for a sink of one file per frame
/// (`FrameSink::stages_files`), encodes the frame and writes it to its temporary file
/// (`FrameSink::stage`); several frames are encoded at once, each on a team of OpenMP
/// threads that shares P among the frames being written (`FrameWriterOptions::threads`). Renaming happens on the thread that
/// calls `write` and `finish`, one frame after another in the order they were handed over:
/// each call first renames every frame at the front whose file is written (`commit_temporary_file`;
/// a sink that takes its frames in order, one USD layer for the run, gets `FrameSink::write`
/// there) and then calls that frame's `on_written`. So files appear in frame order and
/// `on_written` (progress, checkpoints) runs after its frame is on disk, on the caller's thread.
///
/// Errors: a frame that fails (a file that cannot be written: a runtime `Error` naming it) is
/// thrown by the `write` or `finish` that reaches it, once the frames before it are renamed, as
/// writing them one after the other would have: no frame after it is renamed, and its threads take
/// no later frame. The destructor (of a writer that threw, or was never finished) waits for the
/// threads and removes the temporary files of the frames not renamed, so nothing half-written is
/// left behind.
class FrameWriter {
 public:
  /// `sink` must outlive the writer.
  explicit FrameWriter(FrameSink& sink, FrameWriterOptions options = {});
  ~FrameWriter();
  FrameWriter(const FrameWriter&) = delete;
  FrameWriter& operator=(const FrameWriter&) = delete;

  /// Hands frame `frame` over (frames in increasing order). `recompute_normals`: its
  /// `corner_normal` is replaced by `area_weighted_corner_normals` of its positions first.
  /// `on_written` (may be empty) is called on this thread once the frame is on disk. Renames the
  /// frames that are written; waits while `max_in_flight` frames are in flight; throws the
  /// failure of a frame handed over earlier.
  void write(int frame, Mesh mesh, bool recompute_normals, std::function<void()> on_written);
  /// The same for a mesh still on its way from the backend (`Cloth::mesh_later`): the thread that
  /// writes the frame waits for it, this one does not.
  void write(int frame, PendingMesh mesh, bool recompute_normals, std::function<void()> on_written);
  /// The same, and `inspect` (may be empty) called with the frame's mesh on the thread that writes
  /// it, after its normals and before it is encoded; what it finds is for `on_written` to read.
  void write(int frame, PendingMesh mesh, bool recompute_normals, std::function<void()> on_written,
             std::function<void(const Mesh&)> inspect);

  /// Waits for every frame handed over and renames them (calling their `on_written`); throws the
  /// first failure as `write` does. The writer takes more frames afterwards. After a failure,
  /// throws it again.
  void finish();

  /// The threads (`FrameWriterOptions::threads` resolved), the OpenMP threads each encodes a frame
  /// with when all are busy (max(1, P / threads)), and the most frames in flight allowed.
  int threads() const;
  int encode_threads() const;
  std::size_t max_in_flight() const;
  /// The most frames that were in flight at once (handed over, not renamed): at most
  /// `max_in_flight`. For tests.
  std::size_t most_in_flight() const;

 private:
  struct Pool;
  std::unique_ptr<Pool> pool_;
};

}  // namespace tear
