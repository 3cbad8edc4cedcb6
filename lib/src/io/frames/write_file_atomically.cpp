#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "tear/error.h"
#include "tear/output_files.h"
#include "tear/write_mesh.h"

namespace tear {

namespace {

/// The folder of `path` with its trailing slash ("" for a bare name) and the file name.
std::pair<std::string, std::string> split_path(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return {std::string(), path};
  return {path.substr(0, slash + 1), path.substr(slash + 1)};
}

/// The one spelling of a temporary file: `.<name>[.<tag>].tmp.<pid>.<16 hex digits>` beside the
/// target. The temporary file lives in the target's directory: rename is atomic only within one
/// file system.
const char temporary_infix[] = ".tmp.";

std::string random_hex() {
  unsigned char bytes[8] = {};
  std::size_t got = 0;
  while (got < sizeof bytes) {
    const ssize_t n = ::getrandom(bytes + got, sizeof bytes - got, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw runtime_error(std::string("cannot draw a random temporary file name: ") + std::strerror(errno));
    got += static_cast<std::size_t>(n);
  }
  static const char digits[] = "0123456789abcdef";
  std::string hex;
  for (unsigned char b : bytes) {
    hex += digits[b >> 4];
    hex += digits[b & 15];
  }
  return hex;
}

/// True when `text` is a decimal pid, optionally followed by '.' and 16 hex digits; sets `pid`,
/// and `random` when the digits are there.
bool temporary_suffix(const std::string& text, long& pid, bool& random) {
  const std::size_t dot = text.find('.');
  const std::string digits = text.substr(0, dot);
  if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) return false;
  random = dot != std::string::npos;
  if (random) {
    const std::string hex = text.substr(dot + 1);
    if (hex.size() != 16 || hex.find_first_not_of("0123456789abcdef") != std::string::npos) return false;
  }
  pid = std::stol(digits);
  return true;
}

/// True when `pid` names no running process here (or this one).
bool process_gone(long pid) {
  if (pid == static_cast<long>(::getpid()) || pid <= 0) return true;
  return ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
}

/// Whether the kernel has open file description locks (F_OFD_SETLK, Linux 3.15): a lock of the
/// descriptor, not of the process, so a second descriptor of this process conflicts with it and
/// closing another descriptor of the file does not drop it. Without them, POSIX record locks
/// (F_SETLK), which a process never sees as conflicting with its own.
std::atomic<bool> description_locks{true};

/// Takes a lock of `type` (F_RDLCK, F_WRLCK) on the whole file open at `fd` without waiting: 0
/// when taken, EAGAIN when another holder's lock conflicts, else the errno of the failure (ENOLCK
/// on a file system that keeps no locks). Both kinds of lock reach an NFS server (NLM or NFSv4
/// locks), so holders on other hosts count.
int lock_whole_file(int fd, short type) {
  struct flock lock {};
  lock.l_type = type;
  lock.l_whence = SEEK_SET;
  lock.l_start = 0;
  lock.l_len = 0;  // to the end, however long the file grows
  for (;;) {
#ifdef F_OFD_SETLK
    const bool description = description_locks.load(std::memory_order_relaxed);
    lock.l_pid = 0;  // required of F_OFD_SETLK
    const int result = ::fcntl(fd, description ? F_OFD_SETLK : F_SETLK, &lock);
    if (result != 0 && errno == EINVAL && description) {
      description_locks.store(false, std::memory_order_relaxed);
      continue;
    }
#else
    const int result = ::fcntl(fd, F_SETLK, &lock);
#endif
    if (result == 0) return 0;
    if (errno == EINTR) continue;
    return errno == EACCES ? EAGAIN : errno;
  }
}

/// True when `fd` is the file `path` names (not followed): not removed or replaced since opened.
bool still_named(int fd, const std::string& path) {
  struct stat open_file {}, named {};
  return ::fstat(fd, &open_file) == 0 && ::lstat(path.c_str(), &named) == 0 && open_file.st_dev == named.st_dev &&
         open_file.st_ino == named.st_ino;
}

/// Removes the temporary file `file` when it is provably abandoned: a regular file whose lock is
/// free. The lock is held from before the check that the name is still the file opened until
/// after the unlink, so a writer that created the file and has not locked it yet finds its lock
/// taken (or, once let go, its name gone) and draws another name (`create_temporary_file`).
bool remove_if_abandoned(const std::string& file, long pid, bool random) {
  struct stat s {};
  // Never opened unless a regular file: opening a device or FIFO can act (or wait).
  if (::lstat(file.c_str(), &s) != 0 || !S_ISREG(s.st_mode)) return false;
  const int fd = ::open(file.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) return false;
  bool removed = false;
  struct stat opened {};
  if (::fstat(fd, &opened) == 0 && S_ISREG(opened.st_mode) && opened.st_dev == s.st_dev && opened.st_ino == s.st_ino) {
    // Without description locks this process's own lock would not conflict, and closing `fd`
    // would drop it: this process's files are left to it then.
    const bool own = pid == static_cast<long>(::getpid()) && !description_locks.load(std::memory_order_relaxed);
    if (!own && lock_whole_file(fd, F_RDLCK) == 0 && (random || process_gone(pid)) && still_named(fd, file))
      removed = ::unlink(file.c_str()) == 0;
  }
  ::close(fd);
  return removed;
}

}  // namespace

TemporaryFileLock& TemporaryFileLock::operator=(TemporaryFileLock&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = other.release();
  }
  return *this;
}

TemporaryFileLock::~TemporaryFileLock() {
  if (fd_ >= 0) ::close(fd_);
}

std::size_t remove_stale_temporaries(const std::vector<std::string>& paths) {
  std::map<std::string, std::set<std::string>> names_by_folder;
  for (const std::string& path : paths) {
    if (path.empty()) continue;
    const auto [dir, name] = split_path(path);
    if (!name.empty()) names_by_folder[dir].insert(name);
  }
  std::size_t removed = 0;
  for (const auto& [dir, names] : names_by_folder) {
    DIR* folder = ::opendir(dir.empty() ? "." : dir.c_str());
    if (folder == nullptr) continue;
    struct Candidate {
      std::string file;
      long pid;
      bool random;
    };
    std::vector<Candidate> candidates;
    while (const dirent* entry = ::readdir(folder)) {
      const std::string file = entry->d_name;
      const std::size_t infix = file.rfind(temporary_infix);
      if (file.size() < 2 || file[0] != '.' || infix == std::string::npos || infix < 2) continue;
      long pid = 0;
      bool random = false;
      if (!temporary_suffix(file.substr(infix + sizeof temporary_infix - 1), pid, random)) continue;
      if (names.count(file.substr(1, infix - 1)) == 0) continue;
      candidates.push_back({dir + file, pid, random});
    }
    ::closedir(folder);
    for (const Candidate& candidate : candidates)
      if (remove_if_abandoned(candidate.file, candidate.pid, candidate.random)) ++removed;
  }
  return removed;
}

int create_temporary_file(const std::string& path, const std::string& tag, std::string& temporary) {
  const auto [dir, name] = split_path(path);
  for (int attempt = 0;; ++attempt) {
    temporary = dir + "." + name + (tag.empty() ? "" : "." + tag) + temporary_infix +
                std::to_string(static_cast<long>(::getpid())) + "." + random_hex();
    const int fd = ::open(temporary.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd < 0) {
      const int error = errno;
      if (error == EEXIST && attempt < 16) continue;  // planted, or (1 in 2^64) drawn twice
      throw runtime_error(path + ": cannot write: " + std::strerror(error));
    }
    // Between the open and the lock a cleanup may take the file for abandoned: it then holds the
    // lock (EAGAIN here) and removes the file before letting go, so the name is gone once the
    // lock is ours. Either way the file is the cleanup's: another name is drawn.
    const int locked = lock_whole_file(fd, F_WRLCK);
    if (locked == 0 && still_named(fd, temporary)) return fd;
    if (locked != 0 && locked != EAGAIN) return fd;  // no locks on this file system: unlocked, never taken either
    ::close(fd);
    if (attempt >= 16) throw runtime_error(path + ": cannot write: its temporary files are removed as they are made");
  }
}

void check_replaceable(const std::string& path) {
  struct stat s {};
  if (::lstat(path.c_str(), &s) != 0 || S_ISREG(s.st_mode)) return;
  throw runtime_error(path + ": cannot write: it is " + std::string(S_ISLNK(s.st_mode) ? "a symbolic link" : S_ISDIR(s.st_mode) ? "a directory" : S_ISFIFO(s.st_mode) ? "a FIFO" : S_ISCHR(s.st_mode) || S_ISBLK(s.st_mode) ? "a device" : "not a regular file") +
                      "; only a regular file is replaced");
}

TemporaryFile write_temporary_file(const std::string& path, const std::string& bytes) {
  TemporaryFile file{path, std::string(), TemporaryFileLock()};
  std::string& temp = file.temporary;

  auto fail = [&](int error) {
    ::unlink(temp.c_str());  // while still locked: no cleanup takes the name meanwhile
    return runtime_error(path + ": cannot write: " + std::strerror(error));
  };

  file.lock = TemporaryFileLock(create_temporary_file(path, "", temp));
  const int fd = file.lock.fd();
  std::size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw fail(errno);
    written += static_cast<std::size_t>(n);
  }
  // Without fsync a crash right after the rename could leave an empty file under the final name.
  // The descriptor stays open, so the file stays locked, until it is renamed or removed.
  if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) throw fail(errno);
  return file;
}

void commit_temporary_file(const TemporaryFile& file) {
  try {
    check_replaceable(file.path);
  } catch (...) {
    ::unlink(file.temporary.c_str());
    throw;
  }
  if (std::rename(file.temporary.c_str(), file.path.c_str()) == 0) return;
  const int error = errno;
  ::unlink(file.temporary.c_str());
  throw runtime_error(file.path + ": cannot write: " + std::strerror(error));
}

void remove_temporary_file(const TemporaryFile& file) { ::unlink(file.temporary.c_str()); }

void write_file_atomically(const std::string& path, const std::string& text) {
  commit_temporary_file(write_temporary_file(path, text));
}

}  // namespace tear
