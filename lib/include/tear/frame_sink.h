// tear: where the frames of a run go. One interface, several sinks: one file per frame
// (`FrameFiles`), one USD layer for a whole sequence (`UsdLayer`, tear/usd_layer.h).
#pragma once

#include <string>

#include "tear/frame_path.h"
#include "tear/mesh.h"
#include "tear/write_mesh.h"

namespace tear {

/// Receives the frames of a run in order. `write` is called once per frame with the frame's number
/// as outputs show it and the cloth's mesh after that frame (positions, faces, corner attributes,
/// identity arrays); `finish` once after the last frame. Either throws a runtime `Error` naming
/// the file when it cannot write; nothing is then left half-written.
class FrameSink {
 public:
  virtual ~FrameSink() = default;
  virtual void write(int frame, const Mesh& mesh) = 0;
  virtual void finish() {}
  /// The file frame `frame` goes to, for progress lines and reports.
  virtual std::string path_of(int frame) const = 0;

  /// True when every frame is a file of its own that `stage` writes: frames may then be staged
  /// several at once, on any threads, and each is written once its file is renamed
  /// (`commit_temporary_file`), in whatever order the caller renames them (`FrameWriter`: frame
  /// order). False for a sink that must take its frames in order through `write`.
  virtual bool stages_files() const { return false; }
  /// For a sink that `stages_files`: creates the folders of frame `frame`'s file and writes the
  /// frame to its temporary file (`write_temporary_file`), encoding it into `bytes`, a buffer the
  /// caller keeps from frame to frame. `write` is `stage` then the rename. A runtime `Error` naming
  /// the file when it cannot be written (no temporary file left); others throw a usage `Error`.
  virtual TemporaryFile stage(int frame, const Mesh& mesh, std::string& bytes) const;
};

/// One file per frame, named by a `FramePattern`, in the format of its extension (`write_mesh`),
/// each written atomically; the folders are created as needed (a folder that cannot be created is
/// a runtime `Error` naming it).
class FrameFiles final : public FrameSink {
 public:
  explicit FrameFiles(FramePattern pattern) : pattern_(std::move(pattern)) {}
  void write(int frame, const Mesh& mesh) override;
  std::string path_of(int frame) const override { return pattern_.path(frame); }
  bool stages_files() const override { return true; }
  TemporaryFile stage(int frame, const Mesh& mesh, std::string& bytes) const override;

 private:
  FramePattern pattern_;
};

/// Creates the folder `path` would be written in, with its parents; a runtime `Error` naming the
/// folder when it cannot be created.
void create_folder_of(const std::string& path);

}  // namespace tear
