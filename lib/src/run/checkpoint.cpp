#include "tear/checkpoint.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>
#include <sstream>

#include "tear/error.h"
#include "tear/input_file.h"
#include "tear/validate_mesh.h"
#include "tear/write_mesh.h"

namespace tear {

namespace {

constexpr char magic[8] = {'T', 'E', 'A', 'R', 'C', 'K', 'P', 'T'};
constexpr std::uint32_t format_version = 4;

template <class T>
void put(std::string& out, T value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}
void put_string(std::string& out, const std::string& s) {
  put<std::uint64_t>(out, s.size());
  out += s;
}

/// Reads fields in order, refusing to run past the end.
class Reader {
 public:
  Reader(const std::string& bytes, const std::string& path) : bytes_(bytes), path_(path) {}
  template <class T>
  T get() {
    T value{};
    need(sizeof value);
    std::memcpy(&value, bytes_.data() + at_, sizeof value);
    at_ += sizeof value;
    return value;
  }
  std::string get_string() {
    const std::uint64_t size = get<std::uint64_t>();
    need(size);
    std::string s = bytes_.substr(at_, size);
    at_ += size;
    return s;
  }

 private:
  void need(std::uint64_t size) const {
    if (size > bytes_.size() - at_) throw input_error(path_, "the checkpoint is cut short");
  }
  const std::string& bytes_;
  const std::string& path_;
  std::size_t at_ = 0;
};

std::string hex(std::uint64_t v) {
  std::ostringstream s;
  s << std::hex << v;
  return s.str();
}

}  // namespace

std::uint64_t digest_bytes(const std::string& bytes) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (const unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}

std::uint64_t digest_file(const std::string& path) { return digest_bytes(read_input_file(path, "the file")); }

void write_checkpoint(const std::string& path, const Checkpoint& checkpoint) {
  std::string out(magic, sizeof magic);
  put<std::uint32_t>(out, format_version);
  put<std::int32_t>(out, checkpoint.frame);
  put<std::uint64_t>(out, checkpoint.inputs.mesh_digest);
  put<std::uint64_t>(out, checkpoint.inputs.script_digest);
  put_string(out, checkpoint.inputs.options);
  put_string(out, checkpoint.cloth_state);
  put<std::uint64_t>(out, digest_bytes(out));
  write_file_atomically(path, out);
}

Checkpoint read_checkpoint(const std::string& path) {
  const std::string bytes = read_input_file(path, "the checkpoint");
  if (bytes.size() < sizeof magic + 8 || std::memcmp(bytes.data(), magic, sizeof magic) != 0)
    throw input_error(path, "not a tear checkpoint");
  std::uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + bytes.size() - sizeof stored, sizeof stored);
  const std::string body = bytes.substr(0, bytes.size() - sizeof stored);
  if (digest_bytes(body) != stored) throw input_error(path, "the checkpoint is damaged (its checksum does not match)");
  Reader r(body, path);
  for (std::size_t i = 0; i < sizeof magic; ++i) r.get<char>();
  const std::uint32_t version = r.get<std::uint32_t>();
  if (version != format_version)
    throw input_error(path, "a checkpoint of format " + std::to_string(version) + ", this tear reads format " +
                                std::to_string(format_version));
  Checkpoint c;
  c.frame = r.get<std::int32_t>();
  c.inputs.mesh_digest = r.get<std::uint64_t>();
  c.inputs.script_digest = r.get<std::uint64_t>();
  c.inputs.options = r.get_string();
  c.cloth_state = r.get_string();
  if (c.frame < 1) throw input_error(path, "the checkpoint names frame " + std::to_string(c.frame));
  return c;
}

void check_checkpoint_cloth(const std::string& path, int frame, const Cloth& cloth, const Mesh& mesh,
                            const CutScript& script) {
  auto refuse = [&](const std::string& what) {
    return input_error(path, "cannot resume from this checkpoint: " + what);
  };
  if (frame < 1 || frame > script.frames)
    throw refuse("it names frame " + std::to_string(frame) + ", outside the script's frames 1.." +
                 std::to_string(script.frames));
  const index_t nodes = cloth.node_count(), faces = cloth.face_count();
  if (nodes < mesh.node_count())
    throw refuse("its cloth has " + std::to_string(nodes) + " nodes, fewer than the mesh's " +
                 std::to_string(mesh.node_count()));
  // The box of the mesh's rest shape: every node a cut makes interpolates nodes of it.
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}, largest = 0;
  for (index_t n = 0; n < mesh.node_count(); ++n)
    for (int a = 0; a < 3; ++a) {
      const double x = mesh.node_pos[3 * static_cast<std::size_t>(n) + a];
      lo[a] = n == 0 ? x : std::min(lo[a], x);
      hi[a] = n == 0 ? x : std::max(hi[a], x);
      largest = std::max(largest, std::abs(x));
    }
  const std::vector<float> pos = cloth.node_pos(), rest = cloth.node_rest(), vel = cloth.node_vel();
  const std::size_t values = 3 * static_cast<std::size_t>(nodes);
  if (pos.size() != values || rest.size() != values || (!vel.empty() && vel.size() != values))
    throw refuse("its arrays do not match its node count");
  constexpr double max_distance = 1e9, max_speed = 1e6;
  for (std::size_t i = 0; i < values; ++i) {
    const int a = static_cast<int>(i % 3);
    const double slack = 1e-5 * (hi[a] - lo[a]) + 1e-6 * std::max(std::abs(lo[a]), std::abs(hi[a])) + 1e-30;
    if (!std::isfinite(rest[i]) || rest[i] < lo[a] - slack || rest[i] > hi[a] + slack)
      throw refuse("node " + std::to_string(i / 3) + " has a rest position outside the mesh's rest shape");
    if (!std::isfinite(pos[i]) || std::abs(pos[i]) > max_distance + largest)
      throw refuse("node " + std::to_string(i / 3) + " has a position that is not finite or beyond 1e9 m");
    if (!vel.empty() && (!std::isfinite(vel[i]) || std::abs(vel[i]) > max_speed))
      throw refuse("node " + std::to_string(i / 3) + " has a velocity that is not finite or beyond 1e6 m/s");
  }
  const std::vector<index_t> face_nodes = cloth.face_nodes();
  if (face_nodes.size() != 3 * static_cast<std::size_t>(faces)) throw refuse("its faces do not match its face count");
  for (std::size_t f = 0; f < static_cast<std::size_t>(faces); ++f) {
    const index_t* v = &face_nodes[3 * f];
    for (int k = 0; k < 3; ++k)
      if (v[k] < 0 || v[k] >= nodes) throw refuse("face " + std::to_string(f) + " uses a node out of range");
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) throw refuse("face " + std::to_string(f) + " repeats a node");
  }
  Mesh rest_shape;
  rest_shape.node_pos = rest;
  rest_shape.face_nodes = face_nodes;
  const MeshReport report = validate_mesh(rest_shape, Device::cpu);
  if (report.non_manifold_edges || report.non_manifold_nodes || report.inconsistent_edges || report.duplicate_faces) {
    MeshReport shown;
    shown.non_manifold_edges = report.non_manifold_edges;
    shown.non_manifold_nodes = report.non_manifold_nodes;
    shown.inconsistent_edges = report.inconsistent_edges;
    shown.duplicate_faces = report.duplicate_faces;
    throw refuse("its cloth cannot be cut: " + shown.describe());
  }
  const std::size_t pins = script.simulation ? script.simulation->pins.size() : 0;
  const std::vector<std::uint8_t> pinned = cloth.node_pinned();
  for (std::size_t n = 0; n < pinned.size(); ++n)
    if (pinned[n] > pins) throw refuse("node " + std::to_string(n) + " is held by a pin the script does not have");
}

std::string inputs_mismatch(const RunInputs& inputs, const RunInputs& now) {
  if (inputs.mesh_digest != now.mesh_digest)
    return "the mesh changed (digest " + hex(inputs.mesh_digest) + ", now " + hex(now.mesh_digest) + ")";
  if (inputs.script_digest != now.script_digest)
    return "the script changed (digest " + hex(inputs.script_digest) + ", now " + hex(now.script_digest) + ")";
  if (inputs.options != now.options) return "the options changed (" + inputs.options + ", now " + now.options + ")";
  return {};
}

}  // namespace tear
