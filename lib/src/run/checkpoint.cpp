#include "tear/checkpoint.h"

#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include "tear/error.h"
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

std::uint64_t digest_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw input_error(path, "cannot read");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw input_error(path, "cannot read");
  return digest_bytes(bytes);
}

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
  std::ifstream in(path, std::ios::binary);
  if (!in) throw input_error(path, "cannot read the checkpoint");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
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

std::string inputs_mismatch(const RunInputs& inputs, const RunInputs& now) {
  if (inputs.mesh_digest != now.mesh_digest)
    return "the mesh changed (digest " + hex(inputs.mesh_digest) + ", now " + hex(now.mesh_digest) + ")";
  if (inputs.script_digest != now.script_digest)
    return "the script changed (digest " + hex(inputs.script_digest) + ", now " + hex(now.script_digest) + ")";
  if (inputs.options != now.options) return "the options changed (" + inputs.options + ", now " + now.options + ")";
  return {};
}

}  // namespace tear
