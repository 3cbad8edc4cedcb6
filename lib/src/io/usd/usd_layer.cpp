#include "tear/usd_layer.h"

#include <fcntl.h>
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <deque>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "io/usd/usda_text.h"
#include "tear/error.h"
#include "tear/output_files.h"
#include "tear/write_mesh.h"

namespace tear {

namespace {

std::string lower_extension(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  std::string extension = path.substr(dot + 1);
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

Error write_error(const std::string& path, int error) {
  return runtime_error(path + ": cannot write: " + std::strerror(error));
}

using namespace usda;

/// A file descriptor closed on scope exit.
struct FileDescriptor {
  int fd = -1;
  ~FileDescriptor() {
    if (fd >= 0) ::close(fd);
  }
};

void write_all(int fd, const char* data, std::size_t size, const std::string& path) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw write_error(path, errno);
    data += n;
    size -= static_cast<std::size_t>(n);
  }
}

}  // namespace

const char* to_string(UpAxis axis) { return axis == UpAxis::z ? "Z" : "Y"; }

UpAxis parse_up_axis(const std::string& text) {
  if (text == "Y" || text == "y") return UpAxis::y;
  if (text == "Z" || text == "z") return UpAxis::z;
  throw Error(ErrorKind::usage, "--up-axis: expected Y or Z, got '" + text + "'");
}

bool is_usd_path(const std::string& path) {
  const std::string extension = lower_extension(path);
  return extension == "usda" || extension == "usd";
}

std::vector<std::string> usd_layer_sample_paths(const std::string& path) {
  std::vector<std::string> paths;
  for (const Declaration& d : declarations) paths.push_back(path + "." + d.file_tag);
  return paths;
}

std::string usda_layer_text(const Mesh& mesh, int frame, const UsdLayerOptions& options) {
  check_arrays(mesh, "USD layer");
  const AttributeSet attributes = AttributeSet::of(mesh);
  Text text, value;
  text << layer_head(frame, frame, options);
  const FrameSamples samples(mesh, nullptr, 0);
  for (int i = 0; i < attribute_count; ++i) {
    const Attribute a = static_cast<Attribute>(i);
    if (!attributes.has(a)) continue;
    text << attribute_open(a);
    value.clear();
    put_value(value, a, samples);
    put_sample_line(text, frame, value.data(), value.size());
    text << attribute_close;
  }
  text << layer_tail;
  return std::move(text.str());
}

/// One layer for many frames: each attribute's samples streamed to a temporary file of its own.
/// A thread of the layer's own formats and appends the samples, so that encoding and writing run
/// beside the simulation rather than on its path; at most `max_pending` frames wait for it (their
/// meshes copied), so memory stays bounded. It takes frames in order, so the bytes do not depend
/// on its timing.
struct UsdLayer::Sequence {
  static constexpr std::size_t max_pending = 2;

  std::string path;
  AttributeSet attributes;
  std::FILE* files[attribute_count] = {};
  std::string file_paths[attribute_count];
  std::string assembled_path;  // the layer before its rename
  int first_frame = 0, last_frame = 0;
  bool opened = false, finished = false;
  double frames_per_second = 24;
  // The writer's, one per attribute: the frame's value, the lines it appends, and the value last
  // written, at `written_frame`, which later frames held until `held_until` (a value is written
  // only at the frames where it changes).
  Text values[attribute_count], lines[attribute_count];
  std::string last_value[attribute_count];
  int written_frame[attribute_count] = {}, held_until[attribute_count] = {};
  bool written[attribute_count] = {};
  std::vector<float> previous_vel;  // the frame before's velocities, for accelerations
  int previous_frame = 0;
  bool has_previous = false;

  std::thread writer;
  std::mutex mutex;
  std::condition_variable changed;
  std::deque<std::pair<int, Mesh>> pending;  // guarded by `mutex`; the front one is being written
  bool closing = false, abandoning = false;  // guarded by `mutex`
  std::exception_ptr failure;                // the writer's, guarded by `mutex`

  explicit Sequence(std::string layer_path) : path(std::move(layer_path)) {}
  ~Sequence() {
    stop(true);
    remove_temporaries();
  }

  /// Queues frame `frame` for the writer, waiting while `max_pending` frames wait; rethrows a
  /// failure of the writer.
  void push(int frame, const Mesh& mesh) {
    if (!writer.joinable()) {
      // The writer's OpenMP teams keep the limit of the thread that runs the layer (--threads).
      const int limit = omp_get_max_threads();
      writer = std::thread([this, limit] {
        omp_set_num_threads(limit);
        write_pending();
      });
    }
    std::unique_lock<std::mutex> lock(mutex);
    changed.wait(lock, [&] { return failure || pending.size() < max_pending; });
    if (failure) std::rethrow_exception(failure);
    pending.emplace_back(frame, mesh);
    changed.notify_all();
  }

  /// The writer: appends the pending frames in order until closed (and, unless abandoning, empty).
  void write_pending() {
    for (;;) {
      std::unique_lock<std::mutex> lock(mutex);
      changed.wait(lock, [&] { return closing || !pending.empty(); });
      if (pending.empty() || abandoning) return;
      // A deque keeps references to its elements when the other end grows.
      const std::pair<int, Mesh>& next = pending.front();
      lock.unlock();
      try {
        append(next.second, next.first);
      } catch (...) {
        lock.lock();
        failure = std::current_exception();
        pending.clear();
        changed.notify_all();
        return;
      }
      lock.lock();
      pending.pop_front();
      changed.notify_all();
    }
  }

  /// Ends the writer once it has written every pending frame (`abandon`: at once); rethrows its
  /// failure unless abandoning.
  void stop(bool abandon) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      closing = true;
      abandoning = abandon;
    }
    changed.notify_all();
    if (writer.joinable()) writer.join();
    if (!abandon && failure) std::rethrow_exception(failure);
  }

  void open(const AttributeSet& set) {
    attributes = set;
    opened = true;
    for (int i = 0; i < attribute_count; ++i) {
      if (!attributes.has(static_cast<Attribute>(i))) continue;
      const int fd = create_temporary_file(path, declarations[i].file_tag, file_paths[i]);
      files[i] = ::fdopen(fd, "w+b");
      if (!files[i]) {
        const int error = errno;
        ::close(fd);
        throw write_error(path, error);
      }
    }
  }

  /// Encodes and appends frame `frame` of every attribute. The attributes are independent (each
  /// has its own text and file), so they are encoded side by side, the largest first (normals
  /// and UVs, one value per corner); each file's bytes are the same whatever the threads do.
  void append(const Mesh& mesh, int frame) {
    static constexpr Attribute by_size[attribute_count] = {
        Attribute::st_indices, Attribute::normal_indices, Attribute::face_vertex_indices, Attribute::tear_edge,
        Attribute::points,     Attribute::velocities,     Attribute::accelerations,       Attribute::normals,
        Attribute::st,         Attribute::rest,           Attribute::id,                  Attribute::piece,
        Attribute::face_vertex_counts, Attribute::extent};
    const double per_second = has_previous && frame > previous_frame ? frames_per_second / (frame - previous_frame) : 0;
    const FrameSamples frame_samples(mesh, has_previous && mesh.has_velocities() ? &previous_vel : nullptr, per_second);
    int errors[attribute_count] = {};
    std::exception_ptr failures[attribute_count];
    const int threads = std::max(1, std::min({4, omp_get_num_procs(), omp_get_max_threads()}));
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (int k = 0; k < attribute_count; ++k) {
      const int i = static_cast<int>(by_size[k]);
      if (!files[i]) continue;
      try {
        Text& value = values[i];
        value.clear();
        put_value(value, static_cast<Attribute>(i), frame_samples);
        std::string& last = last_value[i];
        if (written[i] && !declarations[i].every_frame && last.size() == value.size() && std::memcmp(last.data(), value.data(), value.size()) == 0) {
          held_until[i] = frame;  // unchanged: not written again
          continue;
        }
        Text& text = lines[i];
        text.clear();
        // USD interpolates floating-point samples linearly: a value held since an earlier frame is
        // written again at the frame before the change, so the frames between keep it exactly.
        if (written[i] && declarations[i].interpolated && held_until[i] > written_frame[i])
          put_sample_line(text, held_until[i], last.data(), last.size());
        put_sample_line(text, frame, value.data(), value.size());
        last.assign(value.data(), value.size());
        written[i] = true;
        written_frame[i] = held_until[i] = frame;
        if (std::fwrite(text.data(), 1, text.size(), files[i]) != text.size()) errors[i] = errno ? errno : EIO;
      } catch (...) {
        failures[i] = std::current_exception();
      }
    }
    for (int i = 0; i < attribute_count; ++i) {
      if (failures[i]) std::rethrow_exception(failures[i]);
      if (errors[i]) throw write_error(path, errors[i]);
    }
    previous_vel = mesh.node_vel;
    previous_frame = frame;
    has_previous = true;
  }

  void assemble(const UsdLayerOptions& options) {
    stop(false);
    // The samples' files stay open, and so locked against a cleanup (tear/output_files.h), until
    // they are copied and removed; they are read through the same descriptors.
    for (int i = 0; i < attribute_count; ++i)
      if (files[i] && std::fflush(files[i]) != 0) throw write_error(path, errno);
    FileDescriptor out{create_temporary_file(path, "", assembled_path)};
    if (out.fd < 0) throw write_error(path, errno);
    const std::string head = layer_head(first_frame, last_frame, options);
    write_all(out.fd, head.data(), head.size(), path);
    std::vector<char> buffer(std::size_t(1) << 20);
    for (int i = 0; i < attribute_count; ++i) {
      if (file_paths[i].empty()) continue;
      const std::string open_text = attribute_open(static_cast<Attribute>(i));
      write_all(out.fd, open_text.data(), open_text.size(), path);
      const int in = ::fileno(files[i]);
      if (::lseek(in, 0, SEEK_SET) != 0) throw write_error(path, errno);
      // The kernel copies the samples file to file where it can (no pass through this process);
      // where it cannot (another file system, an old kernel), read and write.
      bool copied = false;
      for (;;) {
        const ssize_t n = ::copy_file_range(in, nullptr, out.fd, nullptr, std::size_t(1) << 30, 0);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0 && (errno == EXDEV || errno == ENOSYS || errno == EINVAL || errno == EOPNOTSUPP || errno == EBADF))
          break;
        if (n < 0) throw write_error(path, errno);
        if (n == 0) {
          copied = true;
          break;
        }
      }
      while (!copied) {
        const ssize_t n = ::read(in, buffer.data(), buffer.size());
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) throw write_error(path, errno);
        if (n == 0) break;
        write_all(out.fd, buffer.data(), static_cast<std::size_t>(n), path);
      }
      write_all(out.fd, attribute_close, std::strlen(attribute_close), path);
      // Each attribute's file goes as soon as it is copied, so the disk holds the samples about
      // once plus one attribute.
      ::unlink(file_paths[i].c_str());
      file_paths[i].clear();
      std::fclose(files[i]);
      files[i] = nullptr;
    }
    write_all(out.fd, layer_tail, std::strlen(layer_tail), path);
    // Without fsync a crash right after the rename could leave an empty file under the final name.
    if (::fsync(out.fd) != 0 && errno != EINVAL && errno != EROFS) throw write_error(path, errno);
    // Renamed while still open, and so locked: the descriptor is closed by `out` after.
    check_replaceable(path);
    if (std::rename(assembled_path.c_str(), path.c_str()) != 0) throw write_error(path, errno);
    assembled_path.clear();
    finished = true;
  }

  void remove_temporaries() {
    for (int i = 0; i < attribute_count; ++i) {
      if (!file_paths[i].empty()) ::unlink(file_paths[i].c_str());  // before the close lets the lock go
      file_paths[i].clear();
      if (files[i]) std::fclose(files[i]);
      files[i] = nullptr;
    }
    if (!assembled_path.empty()) ::unlink(assembled_path.c_str());
    assembled_path.clear();
  }
};

UsdLayer::UsdLayer(FramePattern pattern, UsdLayerOptions options) : pattern_(std::move(pattern)), options_(options) {
  if (!is_usd_path(pattern_.pattern()))
    throw Error(ErrorKind::usage, "output pattern '" + pattern_.pattern() + "': not a USD layer (.usda or .usd)");
}

UsdLayer::~UsdLayer() = default;

TemporaryFile UsdLayer::stage(int frame, const Mesh& mesh, std::string& bytes) const {
  if (!pattern_.has_frame_number()) return FrameSink::stage(frame, mesh, bytes);
  const std::string path = pattern_.path(frame);
  create_folder_of(path);
  check_arrays(mesh, path);
  bytes = usda_layer_text(mesh, frame, options_);
  return write_temporary_file(path, bytes);
}

void UsdLayer::write(int frame, const Mesh& mesh) {
  if (pattern_.has_frame_number()) {
    std::string bytes;
    commit_temporary_file(stage(frame, mesh, bytes));
    return;
  }
  check_arrays(mesh, pattern_.pattern());
  const AttributeSet attributes = AttributeSet::of(mesh);
  if (!sequence_) {
    create_folder_of(pattern_.pattern());
    sequence_ = std::make_unique<Sequence>(pattern_.pattern());
    sequence_->first_frame = frame;
    sequence_->frames_per_second = options_.frames_per_second;
  }
  if (sequence_->finished)
    throw runtime_error(sequence_->path + ": cannot write frame " + std::to_string(frame) + ": the layer is finished");
  // Any failure drops the sequence, which removes its temporaries: nothing half-written stays.
  try {
    Sequence& s = *sequence_;
    if (s.opened) {
      if (frame <= s.last_frame)
        throw runtime_error(s.path + ": cannot write frame " + std::to_string(frame) + " after frame " +
                            std::to_string(s.last_frame) + " (frames go in increasing order)");
      if (!(attributes == s.attributes))
        throw runtime_error(s.path + ": frame " + std::to_string(frame) +
                            " has other attributes (UVs, normals, pieces, rest positions) than the first frame of the layer");
    } else {
      s.open(attributes);
    }
    s.push(frame, mesh);
    s.last_frame = frame;
  } catch (...) {
    sequence_.reset();
    throw;
  }
}

void UsdLayer::finish() {
  if (!sequence_ || sequence_->finished) return;
  try {
    sequence_->assemble(options_);
  } catch (...) {
    sequence_.reset();
    throw;
  }
}

}  // namespace tear
