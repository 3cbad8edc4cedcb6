#include "tear/write_mesh.h"

#include <omp.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "io/mesh/corner_numbering.h"
#include "io/mesh/parallel_pieces.h"
#include "tear/error.h"

namespace tear {
namespace {

/// The largest node count whose every index a float holds exactly (2^24).
constexpr index_t max_float_id = 1 << 24;

std::uint32_t float_bits(float value) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

/// Appends `%.9g` of `value` without the locale: 9 significant digits always read back to the
/// same float. Small magnitudes go to fixed notation where that is exact too, because fast OBJ
/// parsers (assimp's among them) scale by the exponent in float arithmetic and miss by one ulp on
/// a few percent of such numbers. The digits go through a buffer on the stack, so a frame of
/// hundreds of thousands of numbers allocates nothing per number.
void append_float(std::string& out, float value) {
  char text[64];
  const double wide = value;
  if (std::isfinite(value) && value != 0.0f && std::fabs(value) < 1e-4f) {
    const auto fixed = std::to_chars(text, text + sizeof text, wide, std::chars_format::fixed, 15);
    float back = 0.0f;
    const auto parsed = std::from_chars(text, fixed.ptr, back);
    if (parsed.ec == std::errc() && back == value) {
      out.append(text, fixed.ptr);
      return;
    }
  }
  const auto general = std::to_chars(text, text + sizeof text, wide, std::chars_format::general, 9);
  out.append(text, general.ptr);
}

/// The digits of `value` in decimal.
std::size_t decimal_digits(std::uint32_t value) {
  std::size_t digits = 1;
  for (; value >= 10; value /= 10) ++digits;
  return digits;
}

/// Rejects meshes whose arrays do not match, so a writer never reads out of range.
void check_mesh(const Mesh& mesh, const std::string& path, const PieceTeam& team) {
  auto fail = [&](const std::string& what) { return runtime_error(path + ": cannot write: " + what); };
  const std::size_t corner_count = mesh.face_nodes.size();
  const std::size_t node_count = static_cast<std::size_t>(mesh.node_count());
  if (mesh.node_pos.size() % 3 != 0) throw fail("node_pos size is not a multiple of 3");
  if (corner_count % 3 != 0) throw fail("face_nodes size is not a multiple of 3");
  if (mesh.has_uv() && mesh.corner_uv.size() != 2 * corner_count) throw fail("corner_uv has the wrong size");
  if (mesh.has_normals() && mesh.corner_normal.size() != 3 * corner_count) {
    throw fail("corner_normal has the wrong size");
  }
  if (mesh.has_velocities() && mesh.node_vel.size() != 3 * node_count) throw fail("node_vel has the wrong size");
  if (mesh.has_origins() && mesh.node_origin_face.size() != node_count) {
    throw fail("node_origin_face has the wrong size");
  }
  if (mesh.node_origin_bary.size() != 2 * mesh.node_origin_face.size())
    throw fail("node_origin_bary has the wrong size");
  // The first corner (in order) that uses a node out of range: each piece finds its first.
  const std::size_t piece_count = team.pieces(corner_count);
  std::vector<std::size_t> bad_corner(piece_count, corner_count);
  team.for_each_range(corner_count, piece_count, [&](std::size_t k, std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c) {
      const index_t node = mesh.face_nodes[c];
      if (node < 0 || node >= mesh.node_count()) {
        bad_corner[k] = c;
        return;
      }
    }
  });
  for (std::size_t c : bad_corner) {
    if (c == corner_count) continue;
    throw fail("face " + std::to_string(c / 3) + " uses node " + std::to_string(mesh.face_nodes[c]) + " of " +
               std::to_string(mesh.node_count()));
  }
  if (mesh.torn_edge_nodes.size() % 2 != 0) throw fail("torn_edge_nodes does not hold pairs");
  for (index_t node : mesh.torn_edge_nodes) {
    if (node < 0 || node >= mesh.node_count()) {
      throw fail("a torn edge uses node " + std::to_string(node) + " of " + std::to_string(mesh.node_count()));
    }
  }
}

/// Text written in pieces side by side, then joined in order. Pieces are added loop by loop; a
/// loop of one piece appends to the last piece instead, so that on one thread all the text goes
/// straight into the first piece, which is the output's own buffer.
class TextPieces {
 public:
  TextPieces(const PieceTeam& team, std::string& out) : team_(team), out_(out) {
    pieces_.emplace_back();
    pieces_[0].swap(out);
    pieces_[0].clear();
  }

  std::string& first() { return pieces_[0]; }

  /// Runs `write(text, i)` for each i in [0, count), in pieces; `bytes_each` is a guess of the
  /// bytes each writes, to reserve.
  template <typename Write>
  void add(std::size_t count, std::size_t bytes_each, Write write) {
    const std::size_t piece_count = team_.pieces(count);
    const std::size_t first = piece_count == 1 ? pieces_.size() - 1 : pieces_.size();
    pieces_.resize(first + piece_count);
    team_.for_each_range(count, piece_count, [&](std::size_t k, std::size_t begin, std::size_t end) {
      std::string& text = pieces_[first + k];
      const std::size_t wanted = text.size() + (end - begin) * bytes_each;
      if (text.capacity() < wanted) text.reserve(wanted);
      for (std::size_t i = begin; i < end; ++i) write(text, i);
    });
  }

  /// Puts the text together in the output, followed by `more` bytes to be written; returns where
  /// they go.
  char* join(std::size_t more) {
    std::vector<std::size_t> at(pieces_.size() + 1);
    for (std::size_t k = 0; k < pieces_.size(); ++k) at[k + 1] = at[k] + pieces_[k].size();
    out_.swap(pieces_[0]);
    out_.resize(at.back() + more);
    for_each_piece(
        pieces_.size() - 1,
        [&](std::size_t k) { std::memcpy(&out_[at[k + 1]], pieces_[k + 1].data(), pieces_[k + 1].size()); },
        team_.threads);
    return out_.data() + at.back();
  }

 private:
  const PieceTeam& team_;
  std::string& out_;
  std::vector<std::string> pieces_;
};

/// Appends a line of `keyword` and `width` floats.
void append_line(std::string& out, const char* keyword, const float* values, int width) {
  out += keyword;
  for (int k = 0; k < width; ++k) {
    out += ' ';
    append_float(out, values[k]);
  }
  out += '\n';
}

void put_obj_text(const Mesh& mesh, const PieceTeam& team, std::string& out) {
  TextPieces text(team, out);
  text.first() = "# tear\n";
  text.add(static_cast<std::size_t>(mesh.node_count()), 32,
           [&](std::string& line, std::size_t node) { append_line(line, "v", &mesh.node_pos[3 * node], 3); });
  ValueNumbers uv, normal;
  if (mesh.has_uv()) {
    uv = number_by_value(mesh.corner_uv, 2, team);
    text.add(uv.first_corner.size(), 24, [&](std::string& line, std::size_t i) {
      append_line(line, "vt", &mesh.corner_uv[2 * static_cast<std::size_t>(uv.first_corner[i])], 2);
    });
  }
  if (mesh.has_normals()) {
    normal = number_by_value(mesh.corner_normal, 3, team);
    text.add(normal.first_corner.size(), 32, [&](std::string& line, std::size_t i) {
      append_line(line, "vn", &mesh.corner_normal[3 * static_cast<std::size_t>(normal.first_corner[i])], 3);
    });
  }
  // `f` lines: their lengths are cheap to count, so they are counted, then written in place.
  const bool with_uv = mesh.has_uv(), with_normals = mesh.has_normals();
  auto corner_bytes = [&](std::size_t c) {
    return 1 + decimal_digits(mesh.face_nodes[c] + 1u) + (with_uv || with_normals) +
           (with_uv ? decimal_digits(uv.corner_value[c] + 1u) : 0) +
           (with_normals ? 1 + decimal_digits(normal.corner_value[c] + 1u) : 0);
  };
  const std::size_t face_count = static_cast<std::size_t>(mesh.face_count());
  const std::size_t piece_count = team.pieces(face_count);
  std::vector<std::size_t> face_start(piece_count);
  team.for_each_range(face_count, piece_count, [&](std::size_t k, std::size_t begin, std::size_t end) {
    std::size_t bytes = 0;
    for (std::size_t c = 3 * begin; c < 3 * end; ++c) bytes += corner_bytes(c);
    face_start[k] = bytes + 2 * (end - begin);
  });
  const std::size_t face_bytes = exclusive_sums(face_start);
  char* const faces = text.join(face_bytes);
  team.for_each_range(face_count, piece_count, [&](std::size_t k, std::size_t begin, std::size_t end) {
    char* at = faces + face_start[k];
    auto put = [&](std::uint32_t value) { at = std::to_chars(at, at + 10, value).ptr; };
    for (std::size_t c = 3 * begin; c < 3 * end; ++c) {
      if (c % 3 == 0) *at++ = 'f';
      *at++ = ' ';
      put(mesh.face_nodes[c] + 1u);
      if (with_uv || with_normals) *at++ = '/';
      if (with_uv) put(uv.corner_value[c] + 1u);
      if (with_normals) {
        *at++ = '/';
        put(normal.corner_value[c] + 1u);
      }
      if (c % 3 == 2) *at++ = '\n';
    }
  });
}

void append_u32(std::string& out, std::uint32_t value) {
  const char bytes[4] = {static_cast<char>(value & 0xFFu), static_cast<char>((value >> 8) & 0xFFu),
                         static_cast<char>((value >> 16) & 0xFFu), static_cast<char>((value >> 24) & 0xFFu)};
  out.append(bytes, 4);
}

/// Little endian at `at`, which moves on: binary arrays are written in place, in pieces.
void put_u32(char*& at, std::uint32_t value) {
  at[0] = static_cast<char>(value & 0xFFu);
  at[1] = static_cast<char>((value >> 8) & 0xFFu);
  at[2] = static_cast<char>((value >> 16) & 0xFFu);
  at[3] = static_cast<char>((value >> 24) & 0xFFu);
  at += 4;
}

void put_f32(char*& at, float value) { put_u32(at, float_bits(value)); }

/// A vertex's UV and normal: its first corner's, or zeros for a node no face uses.
float corner_value(const std::vector<float>& corner_values, int width, index_t corner, int k) {
  return corner == none ? 0.0f : corner_values[static_cast<std::size_t>(width) * corner + k];
}

void put_ply_bytes(const Mesh& mesh, const PieceTeam& team, std::string& out) {
  const SplitNodes split = split_nodes(mesh, team);
  out = "ply\nformat binary_little_endian 1.0\ncomment tear\n";
  out += "element vertex " + std::to_string(split.vertex_node.size()) + "\n";
  out += "property float x\nproperty float y\nproperty float z\n";
  if (mesh.has_normals()) out += "property float nx\nproperty float ny\nproperty float nz\n";
  if (mesh.has_uv()) out += "property float s\nproperty float t\n";
  // Identity (docs/io.md): the node each vertex is, its velocity (m/s) and its origin.
  out += "property int id\nproperty float vx\nproperty float vy\nproperty float vz\n";
  out += "property int origin_face\nproperty float origin_u\nproperty float origin_v\n";
  out += "element face " + std::to_string(mesh.face_count()) + "\n";
  out += "property list uchar int vertex_indices\n";
  const std::size_t torn_edge_count = mesh.torn_edge_nodes.size() / 2;
  if (torn_edge_count > 0) {
    out += "element edge " + std::to_string(torn_edge_count) + "\nproperty int vertex1\nproperty int vertex2\n";
  }
  out += "end_header\n";
  // Fixed-size records: each piece writes its vertices and faces at their offsets.
  const std::size_t vertex_size = 4 * (3 + (mesh.has_normals() ? 3 : 0) + (mesh.has_uv() ? 2 : 0) + 7);
  const std::size_t face_size = 1 + 3 * 4;
  const std::size_t vertex_count = split.vertex_node.size(), face_count = static_cast<std::size_t>(mesh.face_count());
  const std::size_t header_size = out.size();
  out.resize(header_size + vertex_count * vertex_size + face_count * face_size + 4 * mesh.torn_edge_nodes.size());
  char* const vertices = out.data() + header_size;
  char* const faces = vertices + vertex_count * vertex_size;
  team.for_each_range(vertex_count, [&](std::size_t, std::size_t begin, std::size_t end) {
    char* at = vertices + begin * vertex_size;
    for (std::size_t v = begin; v < end; ++v) {
      const index_t node = split.vertex_node[v];
      const index_t corner = split.vertex_corner[v];
      for (int k = 0; k < 3; ++k) put_f32(at, mesh.node_pos[3 * node + k]);
      for (int k = 0; mesh.has_normals() && k < 3; ++k) put_f32(at, corner_value(mesh.corner_normal, 3, corner, k));
      for (int k = 0; mesh.has_uv() && k < 2; ++k) put_f32(at, corner_value(mesh.corner_uv, 2, corner, k));
      put_u32(at, static_cast<std::uint32_t>(node));
      for (int k = 0; k < 3; ++k) put_f32(at, mesh.has_velocities() ? mesh.node_vel[3 * node + k] : 0.0f);
      put_u32(at, static_cast<std::uint32_t>(mesh.has_origins() ? mesh.node_origin_face[node] : none));
      for (int k = 0; k < 2; ++k) put_f32(at, mesh.has_origins() ? mesh.node_origin_bary[2 * node + k] : 0.0f);
    }
  });
  team.for_each_range(face_count, [&](std::size_t, std::size_t begin, std::size_t end) {
    char* at = faces + begin * face_size;
    for (std::size_t face = begin; face < end; ++face) {
      *at++ = 3;
      for (std::size_t c = 3 * face; c < 3 * face + 3; ++c)
        put_u32(at, static_cast<std::uint32_t>(split.corner_vertex[c]));
    }
  });
  // Vertex i is node i, so the torn edges' node pairs are vertex pairs.
  char* at = faces + face_count * face_size;
  for (index_t node : mesh.torn_edge_nodes) put_u32(at, static_cast<std::uint32_t>(node));
}

/// Appends the base64 of `bytes`, in pieces of whole 3-byte groups; the last group, when it is
/// not whole, is padded with '='.
void append_base64(const std::string& bytes, const PieceTeam& team, std::string& out) {
  static const char alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const std::size_t whole = bytes.size() / 3, rest = bytes.size() % 3;
  const std::size_t begin = out.size();
  out.resize(begin + 4 * (whole + (rest > 0)));
  char* const text = out.data() + begin;
  auto group_at = [&](std::size_t i) { return static_cast<std::uint32_t>(static_cast<std::uint8_t>(bytes[i])); };
  team.for_each_range(whole, [&](std::size_t, std::size_t first, std::size_t last) {
    for (std::size_t g = first; g < last; ++g) {
      const std::uint32_t group = group_at(3 * g) << 16 | group_at(3 * g + 1) << 8 | group_at(3 * g + 2);
      for (int k = 0; k < 4; ++k) text[4 * g + k] = alphabet[(group >> (18 - 6 * k)) & 63];
    }
  });
  if (rest == 0) return;
  std::uint32_t group = group_at(3 * whole) << 16;
  if (rest == 2) group |= group_at(3 * whole + 1) << 8;
  char* const last = text + 4 * whole;
  last[0] = alphabet[(group >> 18) & 63];
  last[1] = alphabet[(group >> 12) & 63];
  last[2] = rest == 2 ? alphabet[(group >> 6) & 63] : '=';
  last[3] = '=';
}

/// A float as the JSON number with the fewest digits that reads back to it.
double json_number(float value) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, value).ptr;
  double wide = value;
  std::from_chars(text, end, wide);
  return wide;
}

/// Where each array lies in the glTF buffer: positions, normals, UVs, ids, velocities, indices.
struct GltfLayout {
  std::size_t vertex_count = 0, corner_count = 0;
  bool normals = false, uv = false, ids = false;
  std::size_t positions = 0, normals_at = 0, uv_at = 0, ids_at = 0, velocities = 0, indices = 0, size = 0;

  GltfLayout() = default;
  GltfLayout(const Mesh& mesh, const SplitNodes& split)
      : vertex_count(split.vertex_node.size()),
        corner_count(split.corner_vertex.size()),
        normals(mesh.has_normals()),
        uv(mesh.has_uv()),
        ids(mesh.node_count() <= max_float_id) {
    normals_at = positions + 12 * vertex_count;
    uv_at = normals_at + (normals ? 12 * vertex_count : 0);
    ids_at = uv_at + (uv ? 8 * vertex_count : 0);
    velocities = ids_at + (ids ? 4 * vertex_count : 0);
    indices = velocities + 12 * vertex_count;
    size = indices + 4 * corner_count;
  }
};

/// The glTF document of a frame and what its buffer is made of. A frame without faces is a scene
/// without nodes and has no buffer (glTF forbids empty accessors and buffers).
struct GltfFrame {
  nlohmann::json document;
  SplitNodes split;
  GltfLayout layout;  ///< empty without faces
};

/// POSITION's min and max per coordinate: non-finite coordinates stay out of them (JSON has no
/// NaN). Each piece keeps the first of equal values (-0 and +0), and pieces are met in order, as
/// one pass in order would. Vertices past the nodes are copies of nodes and change nothing.
struct Bounds {
  float low[3], high[3];
  bool seen[3] = {false, false, false};

  void add(int k, float x) {
    if (!std::isfinite(x)) return;
    low[k] = seen[k] ? std::min(low[k], x) : x;
    high[k] = seen[k] ? std::max(high[k], x) : x;
    seen[k] = true;
  }
  void add(const Bounds& later) {
    for (int k = 0; k < 3; ++k) {
      if (!later.seen[k]) continue;
      low[k] = seen[k] && !(later.low[k] < low[k]) ? low[k] : later.low[k];
      high[k] = seen[k] && !(later.high[k] > high[k]) ? high[k] : later.high[k];
      seen[k] = true;
    }
  }
};

/// POSITION's bounds over the mesh's nodes, found in pieces: the accessor's min and max.
std::pair<nlohmann::json, nlohmann::json> position_bounds(const Mesh& mesh, const PieceTeam& team) {
  using nlohmann::json;
  const std::size_t node_count = static_cast<std::size_t>(mesh.node_count());
  const std::size_t piece_count = team.pieces(node_count);
  std::vector<Bounds> piece_bounds(piece_count);
  team.for_each_range(node_count, piece_count, [&](std::size_t k, std::size_t begin, std::size_t end) {
    for (std::size_t node = begin; node < end; ++node) {
      for (int j = 0; j < 3; ++j) piece_bounds[k].add(j, mesh.node_pos[3 * node + j]);
    }
  });
  Bounds bounds;
  for (const Bounds& piece : piece_bounds) bounds.add(piece);
  json min = json::array(), max = json::array();
  for (int k = 0; k < 3; ++k) {
    min.push_back(bounds.seen[k] ? json_number(bounds.low[k]) : 0.0);
    max.push_back(bounds.seen[k] ? json_number(bounds.high[k]) : 0.0);
  }
  return {min, max};
}

/// A frame document's buffer views and accessors, added one array of the buffer at a time.
struct GltfAccessors {
  static constexpr int array_buffer = 34962, element_array_buffer = 34963;
  static constexpr int float_type = 5126, unsigned_int_type = 5125;

  nlohmann::json buffer_views = nlohmann::json::array();
  nlohmann::json accessors = nlohmann::json::array();

  /// A view of bytes [begin, end) of the buffer for `target`, and an accessor of `count` values of
  /// `type` over it; returns the accessor's number.
  std::size_t add(std::size_t begin, std::size_t end, int target, int component_type, std::size_t count,
                  const char* type) {
    buffer_views.push_back({{"buffer", 0}, {"byteOffset", begin}, {"byteLength", end - begin}, {"target", target}});
    accessors.push_back(
        {{"bufferView", buffer_views.size() - 1}, {"componentType", component_type}, {"count", count}, {"type", type}});
    return accessors.size() - 1;
  }
};

GltfFrame gltf_frame(const Mesh& mesh, const PieceTeam& team) {
  using nlohmann::json;
  GltfFrame frame;
  json& document = frame.document;
  document["asset"] = {{"generator", "tear"}, {"version", "2.0"}};
  document["scene"] = 0;
  if (mesh.face_count() == 0) {
    document["scenes"] = json::array({json::object()});
    return frame;
  }
  document["scenes"] = json::array({{{"nodes", {0}}}});
  document["nodes"] = json::array({{{"mesh", 0}, {"name", "cloth"}}});

  frame.split = split_nodes(mesh, team);
  frame.layout = GltfLayout(mesh, frame.split);
  const GltfLayout& layout = frame.layout;
  const std::size_t vertex_count = layout.vertex_count;
  constexpr int array_buffer = GltfAccessors::array_buffer, float_type = GltfAccessors::float_type;
  GltfAccessors arrays;
  json attributes = json::object();
  attributes["POSITION"] =
      arrays.add(layout.positions, layout.normals_at, array_buffer, float_type, vertex_count, "VEC3");
  const auto [min, max] = position_bounds(mesh, team);
  arrays.accessors.back()["min"] = min;
  arrays.accessors.back()["max"] = max;
  if (layout.normals)
    attributes["NORMAL"] = arrays.add(layout.normals_at, layout.uv_at, array_buffer, float_type, vertex_count, "VEC3");
  if (layout.uv)
    attributes["TEXCOORD_0"] = arrays.add(layout.uv_at, layout.ids_at, array_buffer, float_type, vertex_count, "VEC2");
  // Identity (docs/io.md), as application-specific attributes: `_ID`, the node each vertex is,
  // and `_VELOCITY` (m/s). glTF allows no UNSIGNED_INT outside indices, and Blender imports a
  // SCALAR FLOAT (not a SHORT) as a point attribute, so ids are floats: exact up to 2^24 nodes,
  // and left out above that rather than rounded.
  if (layout.ids)
    attributes["_ID"] = arrays.add(layout.ids_at, layout.velocities, array_buffer, float_type, vertex_count, "SCALAR");
  attributes["_VELOCITY"] =
      arrays.add(layout.velocities, layout.indices, array_buffer, float_type, vertex_count, "VEC3");
  const std::size_t indices = arrays.add(layout.indices, layout.size, GltfAccessors::element_array_buffer,
                                         GltfAccessors::unsigned_int_type, layout.corner_count, "SCALAR");

  constexpr int triangles = 4;
  document["meshes"] = json::array(
      {{{"name", "cloth"},
        {"primitives", json::array({{{"attributes", attributes}, {"indices", indices}, {"mode", triangles}}})}}});
  document["accessors"] = arrays.accessors;
  document["bufferViews"] = arrays.buffer_views;
  document["buffers"] = json::array({{{"byteLength", layout.size}}});
  return frame;
}

/// Writes the glTF buffer of `frame` at `buffer` (`frame.layout.size` bytes), vertices and
/// corners in pieces, each array at its place.
void put_gltf_buffer(const Mesh& mesh, const GltfFrame& frame, const PieceTeam& team, char* buffer) {
  const SplitNodes& split = frame.split;
  const GltfLayout& layout = frame.layout;
  team.for_each_range(layout.vertex_count, [&](std::size_t, std::size_t begin, std::size_t end) {
    char* positions = buffer + layout.positions + 12 * begin;
    char* normals = buffer + layout.normals_at + 12 * begin;
    char* uv = buffer + layout.uv_at + 8 * begin;
    char* ids = buffer + layout.ids_at + 4 * begin;
    char* velocities = buffer + layout.velocities + 12 * begin;
    for (std::size_t v = begin; v < end; ++v) {
      const index_t node = split.vertex_node[v], corner = split.vertex_corner[v];
      for (int k = 0; k < 3; ++k) put_f32(positions, mesh.node_pos[3 * node + k]);
      for (int k = 0; layout.normals && k < 3; ++k) put_f32(normals, corner_value(mesh.corner_normal, 3, corner, k));
      if (layout.uv) {
        put_f32(uv, corner_value(mesh.corner_uv, 2, corner, 0));
        put_f32(uv, 1.0f - corner_value(mesh.corner_uv, 2, corner, 1));
      }
      if (layout.ids) put_f32(ids, static_cast<float>(node));
      for (int k = 0; k < 3; ++k) put_f32(velocities, mesh.has_velocities() ? mesh.node_vel[3 * node + k] : 0.0f);
    }
  });
  team.for_each_range(layout.corner_count, [&](std::size_t, std::size_t begin, std::size_t end) {
    char* indices = buffer + layout.indices + 4 * begin;
    for (std::size_t c = begin; c < end; ++c) put_u32(indices, static_cast<std::uint32_t>(split.corner_vertex[c]));
  });
}

void put_gltf_text(const Mesh& mesh, const PieceTeam& team, std::string& out) {
  GltfFrame frame = gltf_frame(mesh, team);
  if (frame.layout.size == 0) {
    out = frame.document.dump(2);
    out += '\n';
    return;
  }
  std::string buffer(frame.layout.size, '\0');
  put_gltf_buffer(mesh, frame, team, buffer.data());
  // The document is printed with the data URI's prefix only, and the base64 goes in after it:
  // its characters need no escaping in JSON, so the text is what printing the whole URI gives.
  const std::string prefix = "data:application/octet-stream;base64,";
  frame.document["buffers"][0]["uri"] = prefix;
  const std::string document = frame.document.dump(2);
  const std::size_t split_at = document.find('"' + prefix + '"') + 1 + prefix.size();
  out.assign(document, 0, split_at);
  append_base64(buffer, team, out);
  out.append(document, split_at, std::string::npos);
  out += '\n';
}

void put_glb_bytes(const Mesh& mesh, const PieceTeam& team, std::string& out) {
  const GltfFrame frame = gltf_frame(mesh, team);
  // Chunks are 4-byte aligned: JSON padded with spaces, the binary chunk with zeros.
  std::string json_chunk = frame.document.dump();
  json_chunk.resize((json_chunk.size() + 3) / 4 * 4, ' ');
  const std::size_t bin_size = (frame.layout.size + 3) / 4 * 4;
  const std::size_t total = 12 + 8 + json_chunk.size() + (bin_size == 0 ? 0 : 8 + bin_size);
  out.clear();
  out.reserve(total);
  append_u32(out, 0x46546C67u);  // "glTF"
  append_u32(out, 2);
  append_u32(out, static_cast<std::uint32_t>(total));
  append_u32(out, static_cast<std::uint32_t>(json_chunk.size()));
  append_u32(out, 0x4E4F534Au);  // "JSON"
  out += json_chunk;
  if (bin_size > 0) {
    append_u32(out, static_cast<std::uint32_t>(bin_size));
    append_u32(out, 0x004E4942u);  // "BIN\0"
    const std::size_t buffer_at = out.size();
    out.resize(total, '\0');
    put_gltf_buffer(mesh, frame, team, out.data() + buffer_at);
  }
}

}  // namespace

void write_mesh(const Mesh& mesh, const std::string& path) { write_mesh(mesh, path, format_from_path(path)); }

void encode_mesh(const Mesh& mesh, const std::string& path, MeshFormat format, std::string& bytes,
                 const EncodeOptions& options) {
  PieceTeam team;
  team.threads = options.threads > 0 ? options.threads : omp_get_max_threads();
  if (mesh.face_count() < options.parallel_from && mesh.node_count() < options.parallel_from) team.threads = 1;
  check_mesh(mesh, path, team);
  switch (format) {
    case MeshFormat::obj:
      return put_obj_text(mesh, team, bytes);
    case MeshFormat::ply:
      return put_ply_bytes(mesh, team, bytes);
    case MeshFormat::gltf:
      return put_gltf_text(mesh, team, bytes);
    case MeshFormat::glb:
      return put_glb_bytes(mesh, team, bytes);
  }
  throw Error(ErrorKind::usage, path + ": unknown mesh format");
}

void write_mesh(const Mesh& mesh, const std::string& path, MeshFormat format) {
  std::string bytes;
  encode_mesh(mesh, path, format, bytes);
  write_file_atomically(path, bytes);
}

}  // namespace tear
