#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

#include "tear/error.h"
#include "tear/write_mesh.h"

namespace tear {

void write_file_atomically(const std::string& path, const std::string& text) {
  // The temporary file lives in the target's directory: rename is atomic only within one file system.
  const std::size_t slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
  const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  const std::string temp = dir + "." + name + ".tmp." + std::to_string(::getpid());

  auto fail = [&](int error, bool remove_temp) {
    if (remove_temp) ::unlink(temp.c_str());
    return runtime_error(path + ": cannot write: " + std::strerror(error));
  };

  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) throw fail(errno, false);
  std::size_t written = 0;
  while (written < text.size()) {
    const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
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
  if (std::rename(temp.c_str(), path.c_str()) != 0) throw fail(errno, true);
}

}  // namespace tear
