#include "io/assimp/confined_io_system.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <cstring>

#include "tear/input_file.h"

namespace tear {
namespace {

/// A file opened by `ConfinedIoSystem`, read with `pread` up to the size `fstat` gave when it was
/// opened (a file that grows meanwhile is read as it was).
class FileStream final : public Assimp::IOStream {
 public:
  FileStream(int fd, std::size_t size) : fd_(fd), size_(size) {}
  ~FileStream() override { ::close(fd_); }

  /// As `fread`: up to `count` items of `size` bytes; returns the whole items read.
  std::size_t Read(void* buffer, std::size_t size, std::size_t count) override {
    if (size == 0 || count == 0 || position_ >= size_) return 0;
    const std::size_t left = size_ - position_;
    const std::size_t wanted = count > left / size ? left : size * count;
    std::size_t got = 0;
    while (got < wanted) {
      const ssize_t n = ::pread(fd_, static_cast<char*>(buffer) + got, wanted - got, static_cast<off_t>(position_ + got));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      got += static_cast<std::size_t>(n);
    }
    position_ += got;
    return got / size;
  }
  std::size_t Write(const void*, std::size_t, std::size_t) override { return 0; }
  /// As `fseek`: the offset is signed from the current position or the end.
  aiReturn Seek(std::size_t offset, aiOrigin origin) override {
    const std::ptrdiff_t signed_offset = static_cast<std::ptrdiff_t>(offset);
    const std::ptrdiff_t base = origin == aiOrigin_SET ? 0
                                : origin == aiOrigin_CUR ? static_cast<std::ptrdiff_t>(position_)
                                                         : static_cast<std::ptrdiff_t>(size_);
    const std::ptrdiff_t target = origin == aiOrigin_SET ? static_cast<std::ptrdiff_t>(offset) : base + signed_offset;
    if (target < 0 || static_cast<std::size_t>(target) > size_) return aiReturn_FAILURE;
    position_ = static_cast<std::size_t>(target);
    return aiReturn_SUCCESS;
  }
  std::size_t Tell() const override { return position_; }
  std::size_t FileSize() const override { return size_; }
  void Flush() override {}

 private:
  int fd_;
  std::size_t size_;
  std::size_t position_ = 0;
};

}  // namespace

ConfinedIoSystem::ConfinedIoSystem(std::string mesh_path, std::uint64_t max_bytes)
    : mesh_path_(std::move(mesh_path)), max_bytes_(max_bytes) {
  const std::size_t slash = mesh_path_.find_last_of('/');
  if (slash != std::string::npos) folder_ = slash == 0 ? "/" : mesh_path_.substr(0, slash);
}

std::string ConfinedIoSystem::shown(const std::string& file) const {
  if (folder_.empty()) return file;
  const std::string prefix = folder_ == "/" ? folder_ : folder_ + "/";
  return file.compare(0, prefix.size(), prefix) == 0 ? file.substr(prefix.size()) : file;
}

void ConfinedIoSystem::refuse(const std::string& file, const std::string& why) const {
  if (!refused_.empty()) return;
  refused_ = shown(file);
  refused_why_ = why;
}

std::string ConfinedIoSystem::allowed(const std::string& file, std::string& why) const {
  if (file == mesh_path_) return file;
  // The name inside the mesh's folder: assimp joins the folder and the name the file gives.
  std::string name = file;
  if (!folder_.empty()) {
    const std::string prefix = folder_ == "/" ? folder_ : folder_ + "/";
    if (file.compare(0, prefix.size(), prefix) != 0) {
      why = "outside the mesh's folder";
      return std::string();
    }
    name = file.substr(prefix.size());
  }
  while (name.compare(0, 2, "./") == 0) name.erase(0, 2);
  std::string path;
  switch (confine_file(folder_, name, path)) {
    case Confined::ok:
      return path;
    case Confined::not_a_file_inside:
      why = "not a regular file in the mesh's folder or below it";
      return std::string();
    default:
      why = "outside the mesh's folder";
      return std::string();
  }
}

bool ConfinedIoSystem::Exists(const char* file) const {
  if (file == nullptr) return false;
  std::string why;
  const std::string path = allowed(file, why);
  if (path.empty()) refuse(file, why);
  struct stat s {};
  return !path.empty() && ::stat(path.c_str(), &s) == 0 && S_ISREG(s.st_mode);
}

Assimp::IOStream* ConfinedIoSystem::Open(const char* file, const char* mode) {
  if (file == nullptr) return nullptr;
  // Read only: a mode that writes or appends is refused.
  if (mode != nullptr && std::strpbrk(mode, "wa+") != nullptr) {
    refuse(file, "opened for writing");
    return nullptr;
  }
  std::string why;
  const std::string path = allowed(file, why);
  if (path.empty()) {
    refuse(file, why);
    return nullptr;
  }
  // Never blocking: a FIFO put at the path since the check is seen by fstat, not read.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) return nullptr;
  struct stat s {};
  if (::fstat(fd, &s) != 0 || !S_ISREG(s.st_mode)) {
    ::close(fd);
    refuse(file, "not a regular file in the mesh's folder or below it");
    return nullptr;
  }
  if (static_cast<std::uint64_t>(s.st_size) > max_bytes_) {
    ::close(fd);
    refuse(file, "larger than --max-input-bytes (" + std::to_string(max_bytes_) + " bytes)");
    return nullptr;
  }
  return new FileStream(fd, static_cast<std::size_t>(s.st_size));
}

void ConfinedIoSystem::Close(Assimp::IOStream* stream) { delete stream; }

}  // namespace tear
