#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

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

/// True when `text` is a decimal pid, optionally followed by '.' and 16 hex digits; sets `pid`.
bool temporary_suffix(const std::string& text, long& pid) {
  const std::size_t dot = text.find('.');
  const std::string digits = text.substr(0, dot);
  if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) return false;
  if (dot != std::string::npos) {
    const std::string hex = text.substr(dot + 1);
    if (hex.size() != 16 || hex.find_first_not_of("0123456789abcdef") != std::string::npos) return false;
  }
  pid = std::stol(digits);
  return true;
}

/// True when `pid` names no running process (or this one): its temporary files are left-overs.
bool process_gone(long pid) {
  if (pid == static_cast<long>(::getpid()) || pid <= 0) return true;
  return ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
}

}  // namespace

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
    std::vector<std::string> stale;
    while (const dirent* entry = ::readdir(folder)) {
      const std::string file = entry->d_name;
      const std::size_t infix = file.rfind(temporary_infix);
      if (file.size() < 2 || file[0] != '.' || infix == std::string::npos || infix < 2) continue;
      long pid = 0;
      if (!temporary_suffix(file.substr(infix + sizeof temporary_infix - 1), pid)) continue;
      if (names.count(file.substr(1, infix - 1)) == 0 || !process_gone(pid)) continue;
      stale.push_back(dir + file);
    }
    ::closedir(folder);
    for (const std::string& file : stale) {
      struct stat s {};
      if (::lstat(file.c_str(), &s) == 0 && S_ISREG(s.st_mode) && ::unlink(file.c_str()) == 0) ++removed;
    }
  }
  return removed;
}

int create_temporary_file(const std::string& path, const std::string& tag, std::string& temporary) {
  const auto [dir, name] = split_path(path);
  for (int attempt = 0;; ++attempt) {
    temporary = dir + "." + name + (tag.empty() ? "" : "." + tag) + temporary_infix +
                std::to_string(static_cast<long>(::getpid())) + "." + random_hex();
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd >= 0) return fd;
    const int error = errno;
    if (error == EEXIST && attempt < 16) continue;  // planted, or (1 in 2^64) drawn twice
    throw runtime_error(path + ": cannot write: " + std::strerror(error));
  }
}

void check_replaceable(const std::string& path) {
  struct stat s {};
  if (::lstat(path.c_str(), &s) != 0 || S_ISREG(s.st_mode)) return;
  throw runtime_error(path + ": cannot write: it is " + std::string(S_ISLNK(s.st_mode) ? "a symbolic link" : S_ISDIR(s.st_mode) ? "a directory" : S_ISFIFO(s.st_mode) ? "a FIFO" : S_ISCHR(s.st_mode) || S_ISBLK(s.st_mode) ? "a device" : "not a regular file") +
                      "; only a regular file is replaced");
}

TemporaryFile write_temporary_file(const std::string& path, const std::string& bytes) {
  TemporaryFile file{path, std::string()};
  std::string& temp = file.temporary;

  auto fail = [&](int error, bool remove_temp) {
    if (remove_temp) ::unlink(temp.c_str());
    return runtime_error(path + ": cannot write: " + std::strerror(error));
  };

  const int fd = create_temporary_file(path, "", temp);
  std::size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int error = errno;
      ::close(fd);
      throw fail(error, true);
    }
    written += static_cast<std::size_t>(n);
  }
  // Without fsync a crash right after the rename could leave an empty file under the final name.
  if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) {
    const int error = errno;
    ::close(fd);
    throw fail(error, true);
  }
  if (::close(fd) != 0) throw fail(errno, true);
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
