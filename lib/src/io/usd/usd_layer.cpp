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

#include "tear/error.h"
#include "tear/write_mesh.h"

#ifndef TEAR_VERSION
#define TEAR_VERSION "unknown"
#endif

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

/// Text built with `std::to_chars`: no locale, and for a float the shortest digits that read back
/// to the same float, so the same values always give the same bytes. Numbers are written straight
/// into the buffer (a layer is mostly numbers: 700,000 per frame of the paper's high-resolution
/// scene).
class Text {
 public:
  std::string& str() {
    text_.resize(size_);
    return text_;
  }
  const char* data() const { return text_.data(); }
  std::size_t size() const { return size_; }
  void clear() { size_ = 0; }
  template <std::size_t n>
  Text& operator<<(const char (&literal)[n]) {
    append(literal, n - 1);
    return *this;
  }
  Text& operator<<(const std::string& s) {
    append(s.data(), s.size());
    return *this;
  }
  Text& operator<<(char c) {
    *room(1) = c;
    ++size_;
    return *this;
  }
  Text& operator<<(float value) { return number(value); }
  Text& operator<<(double value) { return number(value); }
  Text& operator<<(int value) { return number(value); }

  /// `(x, y, z)` or `(s, t)`: `width` floats in parentheses.
  void tuple(const float* values, int width) {
    char* out = room(2 + static_cast<std::size_t>(width) * (max_digits + 2));
    char* const start = out;
    *out++ = '(';
    for (int k = 0; k < width; ++k) {
      if (k) *out++ = ',', *out++ = ' ';
      out = std::to_chars(out, out + max_digits, values[k]).ptr;
    }
    *out++ = ')';
    size_ += static_cast<std::size_t>(out - start);
  }

  /// Appends a copy of `[begin, begin + count)` of this text.
  void repeat(std::size_t begin, std::size_t count) {
    char* out = room(count);
    std::memcpy(out, text_.data() + begin, count);
    size_ += count;
  }

  void append(const char* s, std::size_t count) {
    std::memcpy(room(count), s, count);
    size_ += count;
  }

 private:
  static constexpr std::size_t max_digits = 24;  // a float's shortest text is at most 15 chars, a double's 24

  /// Room for `count` more chars at the end; returns where they go.
  char* room(std::size_t count) {
    if (size_ + count > text_.size()) text_.resize(std::max(2 * text_.size(), size_ + count + 4096));
    return text_.data() + size_;
  }
  template <typename T>
  Text& number(T value) {
    char* out = room(max_digits);
    size_ += static_cast<std::size_t>(std::to_chars(out, out + max_digits, value).ptr - out);
    return *this;
  }

  std::string text_;  // [0, size_) is the text; the rest is room
  std::size_t size_ = 0;
};

/// The attributes of the mesh, in the order the layer holds them.
enum class Attribute {
  face_vertex_counts,
  face_vertex_indices,
  points,
  velocities,
  extent,
  normals,
  st,
  tear_edge,
  count
};
constexpr int attribute_count = static_cast<int>(Attribute::count);

/// An attribute's USD type and name, the tag of its temporary file, and whether it is faceVarying.
struct Declaration {
  const char* type_and_name;
  const char* file_tag;  // in the temporary file's name
  bool face_varying;
};

constexpr Declaration declarations[attribute_count] = {
    {"int[] faceVertexCounts", "faceVertexCounts", false},
    {"int[] faceVertexIndices", "faceVertexIndices", false},
    {"point3f[] points", "points", false},
    {"vector3f[] velocities", "velocities", false},
    {"float3[] extent", "extent", false},
    {"normal3f[] normals", "normals", true},
    {"texCoord2f[] primvars:st", "st", true},
    {"int[] primvars:tear_edge", "tear_edge", true},
};

const Declaration& declaration(Attribute a) { return declarations[static_cast<int>(a)]; }

/// Which attributes a layer holds: normals and UVs only when the mesh has them.
struct AttributeSet {
  bool normals = false, st = false;
  bool has(Attribute a) const { return a == Attribute::normals ? normals : a == Attribute::st ? st : true; }
  static AttributeSet of(const Mesh& mesh) { return {mesh.has_normals(), mesh.has_uv()}; }
};

/// Refuses a mesh whose arrays do not match, so that no sample reads out of range.
void check_arrays(const Mesh& mesh, const std::string& path) {
  auto fail = [&](const std::string& what) { return runtime_error(path + ": cannot write: " + what); };
  const std::size_t corner_count = mesh.face_nodes.size();
  if (mesh.node_pos.size() % 3 != 0) throw fail("node_pos size is not a multiple of 3");
  if (corner_count % 3 != 0) throw fail("face_nodes size is not a multiple of 3");
  if (mesh.has_uv() && mesh.corner_uv.size() != 2 * corner_count) throw fail("corner_uv has the wrong size");
  if (mesh.has_normals() && mesh.corner_normal.size() != 3 * corner_count)
    throw fail("corner_normal has the wrong size");
  if (mesh.has_velocities() && mesh.node_vel.size() != mesh.node_pos.size()) throw fail("node_vel has the wrong size");
  for (std::size_t c = 0; c < corner_count; ++c)
    if (mesh.face_nodes[c] < 0 || mesh.face_nodes[c] >= mesh.node_count())
      throw fail("face " + std::to_string(c / 3) + " uses node " + std::to_string(mesh.face_nodes[c]) + " of " +
                 std::to_string(mesh.node_count()));
}

/// Per-corner values `corner_values` [corner_count * width] as tuples. The corners of one node
/// mostly share their value (a node's UV away from seams, its normal away from hard edges), so a
/// corner whose value is bit for bit that of its node's previous corner copies that corner's text.
void put_corner_tuples(Text& text, const Mesh& mesh, const std::vector<float>& corner_values, int width) {
  struct Previous {
    std::size_t corner = 0, begin = 0, count = 0;
  };
  std::vector<Previous> node_previous(static_cast<std::size_t>(mesh.node_count()));
  const std::size_t bytes = static_cast<std::size_t>(width) * sizeof(float);
  for (std::size_t c = 0; c < mesh.face_nodes.size(); ++c) {
    if (c) text << ", ";
    const float* value = &corner_values[width * c];
    Previous& previous = node_previous[static_cast<std::size_t>(mesh.face_nodes[c])];
    if (previous.count > 0 && std::memcmp(value, &corner_values[width * previous.corner], bytes) == 0) {
      text.repeat(previous.begin, previous.count);
      continue;
    }
    const std::size_t begin = text.size();
    text.tuple(value, width);
    previous = {c, begin, text.size() - begin};
  }
}

/// 1 for each corner whose edge to the next corner of its face is a torn edge, else 0.
std::vector<char> corner_tear_edge(const Mesh& mesh) {
  std::vector<std::uint64_t> torn;
  torn.reserve(mesh.torn_edge_nodes.size() / 2);
  auto key = [](index_t a, index_t b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
  };
  for (std::size_t e = 0; e + 1 < mesh.torn_edge_nodes.size(); e += 2)
    torn.push_back(key(mesh.torn_edge_nodes[e], mesh.torn_edge_nodes[e + 1]));
  std::sort(torn.begin(), torn.end());
  std::vector<char> marks(mesh.face_nodes.size(), 0);
  if (torn.empty()) return marks;
  for (std::size_t c = 0; c < mesh.face_nodes.size(); ++c) {
    const std::size_t next = c % 3 == 2 ? c - 2 : c + 1;
    marks[c] = std::binary_search(torn.begin(), torn.end(), key(mesh.face_nodes[c], mesh.face_nodes[next]));
  }
  return marks;
}

/// Appends the time sample `frame` of attribute `a` of `mesh`: `        <frame>: <value>,\n`.
void put_sample(Text& text, Attribute a, int frame, const Mesh& mesh) {
  text << "        " << frame << ": [";
  const std::size_t node_count = static_cast<std::size_t>(mesh.node_count());
  const std::size_t corner_count = mesh.face_nodes.size();
  switch (a) {
    case Attribute::face_vertex_counts:
      for (std::size_t f = 0; f < corner_count / 3; ++f) {
        if (f) text << ", ";
        text << '3';
      }
      break;
    case Attribute::face_vertex_indices:
      for (std::size_t c = 0; c < corner_count; ++c) {
        if (c) text << ", ";
        text << static_cast<int>(mesh.face_nodes[c]);
      }
      break;
    case Attribute::points:
      for (std::size_t n = 0; n < node_count; ++n) {
        if (n) text << ", ";
        text.tuple(&mesh.node_pos[3 * n], 3);
      }
      break;
    case Attribute::velocities: {
      const float zero[3] = {0, 0, 0};
      for (std::size_t n = 0; n < node_count; ++n) {
        if (n) text << ", ";
        text.tuple(mesh.has_velocities() ? &mesh.node_vel[3 * n] : zero, 3);
      }
      break;
    }
    case Attribute::extent: {
      if (node_count == 0) break;
      float lo[3], hi[3];
      for (int k = 0; k < 3; ++k) lo[k] = hi[k] = mesh.node_pos[k];
      for (std::size_t n = 1; n < node_count; ++n)
        for (int k = 0; k < 3; ++k) {
          lo[k] = std::min(lo[k], mesh.node_pos[3 * n + k]);
          hi[k] = std::max(hi[k], mesh.node_pos[3 * n + k]);
        }
      text.tuple(lo, 3);
      text << ", ";
      text.tuple(hi, 3);
      break;
    }
    case Attribute::normals:
      put_corner_tuples(text, mesh, mesh.corner_normal, 3);
      break;
    case Attribute::st:
      put_corner_tuples(text, mesh, mesh.corner_uv, 2);
      break;
    case Attribute::tear_edge: {
      const std::vector<char> marks = corner_tear_edge(mesh);
      for (std::size_t c = 0; c < corner_count; ++c) {
        if (c) text << ", ";
        text << (marks[c] ? '1' : '0');
      }
      break;
    }
    case Attribute::count:
      break;
  }
  text << "],\n";
}

/// The layer's opening: metadata, and the mesh's uniform attributes.
std::string layer_head(int first_frame, int last_frame, const UsdLayerOptions& options) {
  Text text;
  text << "#usda 1.0\n(\n"
       << "    defaultPrim = \"cloth\"\n"
       << "    doc = \"tear " TEAR_VERSION ": a torn cloth, one time sample per frame\"\n"
       << "    endTimeCode = " << last_frame << "\n"
       << "    framesPerSecond = " << options.frames_per_second << "\n"
       << "    metersPerUnit = " << options.meters_per_unit << "\n"
       << "    startTimeCode = " << first_frame << "\n"
       << "    timeCodesPerSecond = " << options.frames_per_second << "\n"
       << "    upAxis = \"" << std::string(to_string(options.up_axis)) << "\"\n"
       << ")\n\n"
       << "def Mesh \"cloth\"\n{\n"
       // Cloth is seen from both sides; the triangles are the surface (no subdivision), which
       // also keeps the authored normals in use.
       << "    uniform bool doubleSided = 1\n"
       << "    uniform token orientation = \"rightHanded\"\n"
       << "    uniform token subdivisionScheme = \"none\"\n";
  return std::move(text.str());
}

/// What comes before attribute `a`'s samples, and after them.
std::string attribute_open(Attribute a) {
  const Declaration& d = declaration(a);
  std::string text = "    ";
  if (d.face_varying) text += std::string(d.type_and_name) + " (\n        interpolation = \"faceVarying\"\n    )\n    ";
  return text + d.type_and_name + ".timeSamples = {\n";
}
const char* const attribute_close = "    }\n";
const char* const layer_tail = "}\n";

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

/// `.<name>.<tag>.tmp.<pid>` beside `path` (`tag` empty: `.<name>.tmp.<pid>`, write_mesh's name).
std::string temporary_path(const std::string& path, const std::string& tag) {
  const std::size_t slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
  const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  return dir + "." + name + (tag.empty() ? "" : "." + tag) + ".tmp." + std::to_string(::getpid());
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
  Text text;
  text << layer_head(frame, frame, options);
  for (int i = 0; i < attribute_count; ++i) {
    const Attribute a = static_cast<Attribute>(i);
    if (!attributes.has(a)) continue;
    text << attribute_open(a);
    put_sample(text, a, frame, mesh);
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
  Text samples[attribute_count];  // the writer's, one per attribute

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
    if (!writer.joinable()) writer = std::thread([this] { write_pending(); });
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
      file_paths[i] = temporary_path(path, declarations[i].file_tag);
      files[i] = std::fopen(file_paths[i].c_str(), "wb");
      if (!files[i]) throw write_error(path, errno);
    }
  }

  /// Encodes and appends frame `frame` of every attribute. The attributes are independent (each
  /// has its own text and file), so they are encoded side by side, the largest first (normals
  /// and UVs, one value per corner); each file's bytes are the same whatever the threads do.
  void append(const Mesh& mesh, int frame) {
    static constexpr Attribute by_size[attribute_count] = {
        Attribute::normals,    Attribute::st,        Attribute::face_vertex_indices, Attribute::points,
        Attribute::velocities, Attribute::tear_edge, Attribute::face_vertex_counts, Attribute::extent};
    int errors[attribute_count] = {};
    std::exception_ptr failures[attribute_count];
    const int threads = std::max(1, std::min(4, omp_get_num_procs()));
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (int k = 0; k < attribute_count; ++k) {
      const int i = static_cast<int>(by_size[k]);
      if (!files[i]) continue;
      try {
        Text& text = samples[i];
        text.clear();
        put_sample(text, static_cast<Attribute>(i), frame, mesh);
        if (std::fwrite(text.data(), 1, text.size(), files[i]) != text.size()) errors[i] = errno ? errno : EIO;
      } catch (...) {
        failures[i] = std::current_exception();
      }
    }
    for (int i = 0; i < attribute_count; ++i) {
      if (failures[i]) std::rethrow_exception(failures[i]);
      if (errors[i]) throw write_error(path, errors[i]);
    }
  }

  void assemble(const UsdLayerOptions& options) {
    stop(false);
    for (int i = 0; i < attribute_count; ++i) {
      if (!files[i]) continue;
      const int failed = std::fclose(files[i]);
      files[i] = nullptr;
      if (failed != 0) throw write_error(path, errno);
    }
    assembled_path = temporary_path(path, "");
    FileDescriptor out{::open(assembled_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666)};
    if (out.fd < 0) throw write_error(path, errno);
    const std::string head = layer_head(first_frame, last_frame, options);
    write_all(out.fd, head.data(), head.size(), path);
    std::vector<char> buffer(std::size_t(1) << 20);
    for (int i = 0; i < attribute_count; ++i) {
      if (file_paths[i].empty()) continue;
      const std::string open_text = attribute_open(static_cast<Attribute>(i));
      write_all(out.fd, open_text.data(), open_text.size(), path);
      FileDescriptor in{::open(file_paths[i].c_str(), O_RDONLY | O_CLOEXEC)};
      if (in.fd < 0) throw write_error(path, errno);
      // The kernel copies the samples file to file where it can (no pass through this process);
      // where it cannot (another file system, an old kernel), read and write.
      bool copied = false;
      for (;;) {
        const ssize_t n = ::copy_file_range(in.fd, nullptr, out.fd, nullptr, std::size_t(1) << 30, 0);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0 && (errno == EXDEV || errno == ENOSYS || errno == EINVAL || errno == EOPNOTSUPP || errno == EBADF)) break;
        if (n < 0) throw write_error(path, errno);
        if (n == 0) {
          copied = true;
          break;
        }
      }
      while (!copied) {
        const ssize_t n = ::read(in.fd, buffer.data(), buffer.size());
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
    }
    write_all(out.fd, layer_tail, std::strlen(layer_tail), path);
    // Without fsync a crash right after the rename could leave an empty file under the final name.
    if (::fsync(out.fd) != 0 && errno != EINVAL && errno != EROFS) throw write_error(path, errno);
    const int fd = out.fd;
    out.fd = -1;
    if (::close(fd) != 0) throw write_error(path, errno);
    if (std::rename(assembled_path.c_str(), path.c_str()) != 0) throw write_error(path, errno);
    assembled_path.clear();
    finished = true;
  }

  void remove_temporaries() {
    for (int i = 0; i < attribute_count; ++i) {
      if (files[i]) std::fclose(files[i]);
      files[i] = nullptr;
      if (!file_paths[i].empty()) ::unlink(file_paths[i].c_str());
      file_paths[i].clear();
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
      if (attributes.normals != s.attributes.normals || attributes.st != s.attributes.st)
        throw runtime_error(s.path + ": frame " + std::to_string(frame) +
                            " has other corner attributes (UVs, normals) than the first frame of the layer");
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
