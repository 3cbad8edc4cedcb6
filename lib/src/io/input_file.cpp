#include "tear/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <climits>
#include <cstdlib>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>

#include "tear/error.h"

namespace tear {

namespace {

std::atomic<std::uint64_t> limit_bytes{default_max_input_bytes};

/// Throws unless `s` is a regular file of at most `limit` bytes.
void check_stat(const std::string& path, const std::string& what, const struct stat& s, std::uint64_t limit) {
  if (!S_ISREG(s.st_mode))
    throw input_error(path, "cannot read " + what + ": it is " + file_kind(s.st_mode) + ", not a regular file");
  const std::uint64_t size = static_cast<std::uint64_t>(s.st_size);
  if (size > limit)
    throw input_error(path, "cannot read " + what + ": it has " + std::to_string(size) + " bytes, more than the limit of " +
                                std::to_string(limit) + " (--max-input-bytes)");
}

}  // namespace

Confined confine_file(const std::string& folder, const std::string& name, std::string& path) {
  // A scheme (file:, http:, C:) is letters, digits, '+', '-', '.' before a ':'.
  const std::size_t colon = name.find(':');
  const bool scheme = colon != std::string::npos && colon > 0 &&
                      std::all_of(name.begin(), name.begin() + static_cast<std::ptrdiff_t>(colon), [](char c) {
                        return std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '-' || c == '.';
                      });
  if (name.empty() || scheme || name[0] == '/' || name[0] == '\\' || name.find('\0') != std::string::npos)
    return Confined::not_relative;
  for (std::size_t at = 0; at <= name.size();) {
    std::size_t end = name.find_first_of("/\\", at);
    if (end == std::string::npos) end = name.size();
    if (name.compare(at, end - at, "..") == 0) return Confined::goes_up;
    at = end + 1;
  }
  const auto real = [](const std::string& p) -> std::string {
    char resolved[PATH_MAX];
    return ::realpath(p.c_str(), resolved) == nullptr ? std::string() : std::string(resolved);
  };
  const std::string asked = folder.empty() ? name : folder.back() == '/' ? folder + name : folder + "/" + name;
  const std::string inside = real(folder.empty() ? "." : folder);
  const std::string target = real(asked);
  struct stat s {};
  const std::string prefix = inside == "/" ? inside : inside + "/";
  if (inside.empty() || target.empty() || target.compare(0, prefix.size(), prefix) != 0 ||
      ::stat(target.c_str(), &s) != 0 || !S_ISREG(s.st_mode))
    return Confined::not_a_file_inside;
  path = target;
  return Confined::ok;
}

std::uint64_t max_input_bytes() { return limit_bytes.load(std::memory_order_relaxed); }
void set_max_input_bytes(std::uint64_t bytes) { limit_bytes.store(bytes, std::memory_order_relaxed); }

std::string file_kind(unsigned mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISLNK(mode)) return "a symbolic link";
  if (S_ISREG(mode)) return "a regular file";
  return "not a regular file";
}

std::uint64_t check_input_file(const std::string& path, const std::string& what, std::uint64_t limit) {
  struct stat s {};
  if (path.empty() || ::stat(path.c_str(), &s) != 0) {
    const int error = path.empty() ? ENOENT : errno;
    throw input_error(path, "cannot read " + what + ": " + std::strerror(error));
  }
  check_stat(path, what, s, limit);
  return static_cast<std::uint64_t>(s.st_size);
}

std::string read_input_file(const std::string& path, const std::string& what, std::uint64_t limit) {
  // The path is checked before it is opened (opening a device can have effects of its own), then
  // the descriptor, which is what is read.
  check_input_file(path, what, limit);
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) {
    const int error = errno;
    throw input_error(path, "cannot read " + what + ": " + std::strerror(error));
  }
  struct stat s {};
  if (::fstat(fd, &s) != 0) {
    const int error = errno;
    ::close(fd);
    throw input_error(path, "cannot read " + what + ": " + std::strerror(error));
  }
  try {
    check_stat(path, what, s, limit);
  } catch (...) {
    ::close(fd);
    throw;
  }
  std::string bytes;
  try {
    bytes.resize(static_cast<std::size_t>(s.st_size));
  } catch (const std::bad_alloc&) {
    ::close(fd);
    throw runtime_error(path + ": out of memory reading " + what + " (" + std::to_string(s.st_size) + " bytes)");
  }
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::read(fd, &bytes[done], bytes.size() - done);
    if (n < 0 && (errno == EINTR)) continue;
    if (n <= 0) {
      const int error = n < 0 ? errno : 0;
      ::close(fd);
      throw input_error(path, "cannot read " + what + ": " +
                                  (n < 0 ? std::string(std::strerror(error)) : std::string("the file shrank while it was read")));
    }
    done += static_cast<std::size_t>(n);
  }
  ::close(fd);
  return bytes;
}

std::size_t json_nesting_depth(const char* text, std::size_t size) {
  std::size_t depth = 0, deepest = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < size; ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return deepest;
}

}  // namespace tear
