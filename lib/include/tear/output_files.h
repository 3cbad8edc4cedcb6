// tear: the files a command writes, checked before anything is written, and the temporary files
// of killed runs cleared before a run writes again.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "tear/frame_path.h"

namespace tear {

/// A file a command reads or writes, and what it is for messages: {"input mesh", "cloth.obj"},
/// {"report", "out/report.json"}.
struct NamedPath {
  std::string what;
  std::string path;
};

/// Checks, before a command writes anything, that its outputs can be written without harm:
///
/// 1. no output is one of `inputs` (an input error, exit 2: "<output>: the report is the input
///    script shot.json; refusing to overwrite it"). Same file means same device and inode, so
///    another spelling of the path, a hard link or a symlink to the input are caught too; an
///    output that does not exist yet is no input;
/// 2. no two outputs are the same path (a usage error: "<output>: the report is also frame 3");
/// 3. every output that exists is a regular file: a folder, a FIFO, a device, a socket or a
///    symbolic link at an output path is an input error (exit 2), since renaming a file over it
///    would replace it (a device node, a FIFO another program reads) or write where the link
///    points;
/// 4. every output's folder exists and can be written, or can be created: its nearest existing
///    ancestor is a folder that can be written (a runtime error naming the folder, exit 3), and
///    an existing output is not a folder.
///
/// `frames` are the files of `pattern` numbered `first_number`.. (`frame_count` of them, named
/// "frame N" by their number); pass
/// `frame_count` 0 for a command without frames. Nothing is created: a folder that is missing is
/// made by the writer later. Empty paths in `outputs` are skipped.
void check_output_files(const std::vector<NamedPath>& inputs, const FramePattern* pattern, int frame_count,
                        const std::vector<NamedPath>& outputs, int first_number = 1);

/// The open descriptor of a temporary file being written, and with it the file's lock: closed
/// (the lock let go) when this is destroyed, after the file's rename or removal. Move-only.
class TemporaryFileLock {
 public:
  TemporaryFileLock() = default;
  explicit TemporaryFileLock(int fd) : fd_(fd) {}
  TemporaryFileLock(TemporaryFileLock&& other) noexcept : fd_(other.release()) {}
  TemporaryFileLock& operator=(TemporaryFileLock&& other) noexcept;
  TemporaryFileLock(const TemporaryFileLock&) = delete;
  TemporaryFileLock& operator=(const TemporaryFileLock&) = delete;
  ~TemporaryFileLock();
  int fd() const { return fd_; }
  /// Gives the descriptor up without closing it (the caller closes it, and the lock with it).
  int release() {
    const int fd = fd_;
    fd_ = -1;
    return fd;
  }

 private:
  int fd_ = -1;
};

/// Creates the temporary file of `path` for writing, beside it: `.<name>.tmp.<pid>.<16 hex
/// digits>` (`tag` not empty: `.<name>.<tag>.tmp....`), the digits random (getrandom), so that
/// names never collide, even between hosts or PID namespaces sharing a folder. Created with
/// O_CREAT|O_EXCL|O_NOFOLLOW, so a file or symbolic link planted at the name is never written
/// through (another name is drawn), and open for reading and writing. The file is locked (a write
/// lock on the whole file, `fcntl` F_OFD_SETLK, or F_SETLK where the kernel lacks it) before this
/// returns, and stays locked while the returned descriptor is open: the writer keeps it open until
/// the file is renamed or removed, and `remove_stale_temporaries` leaves a locked file alone. A
/// file system that keeps no locks (ENOLCK, EOPNOTSUPP) gives an unlocked file, which no cleanup can
/// then take either. Returns the open descriptor and sets `temporary`; throws a runtime `Error`
/// naming `path` when it cannot be created.
int create_temporary_file(const std::string& path, const std::string& tag, std::string& temporary);

/// Throws a runtime `Error` naming `path` unless nothing is at `path` or a regular file is
/// (symbolic links not followed): what a rename over `path` may replace.
void check_replaceable(const std::string& path);

/// Removes the temporary files that writers which are gone left beside `paths` (a killed run
/// leaves `.cloth.0036.obj.tmp.4242.<16 hex digits>` behind). Only files named
/// `.<name>.tmp.<pid>.<16 hex digits>` (or `.<name>.tmp.<pid>`, as tear spelled them before the
/// random digits) for a `<name>` of `paths`, in that path's folder, are candidates, and of those
/// only the provably abandoned go: a regular file whose lock this call can take without waiting
/// (a read lock on the whole file, F_OFD_SETLK) and which it removes while holding it. A file
/// locked by anyone (a writer on this host or another sharing the folder over NFS, in this
/// process or another PID namespace) is left alone, whatever process id its name holds; a file
/// that cannot be opened or locked (no lock support) is left too. The old spelling, written by a
/// tear that did not lock, goes only when also no process of its id runs here. Nothing else in
/// the folder is touched, and a folder that does not exist or cannot be listed is skipped.
/// Returns how many were removed. A run calls it once, after its checks, with every file it is
/// about to write.
std::size_t remove_stale_temporaries(const std::vector<std::string>& paths);

}  // namespace tear
