// glTF and GLB frames: the document, and its buffer written in pieces (base64 in a .gltf).
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
#include "io/mesh/encode_mesh.h"
#include "io/mesh/parallel_pieces.h"
#include "tear/error.h"

namespace tear::encode {
namespace {

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
  bool normals = false, uv = false, ids = false, pieces = false;
  std::size_t positions = 0, normals_at = 0, uv_at = 0, ids_at = 0, velocities = 0, pieces_at = 0, indices = 0,
              size = 0;

  GltfLayout() = default;
  GltfLayout(const Mesh& mesh, const SplitNodes& split)
      : vertex_count(split.vertex_node.size()),
        corner_count(split.corner_vertex.size()),
        normals(mesh.has_normals()),
        uv(mesh.has_uv()),
        ids(mesh.node_count() <= max_float_id),
        pieces(mesh.has_pieces() && mesh.face_count() <= max_float_id) {
    normals_at = positions + 12 * vertex_count;
    uv_at = normals_at + (normals ? 12 * vertex_count : 0);
    ids_at = uv_at + (uv ? 8 * vertex_count : 0);
    velocities = ids_at + (ids ? 4 * vertex_count : 0);
    pieces_at = velocities + 12 * vertex_count;
    indices = pieces_at + (pieces ? 4 * vertex_count : 0);
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
      arrays.add(layout.velocities, layout.pieces_at, array_buffer, float_type, vertex_count, "VEC3");
  // `_PIECE`: the connected piece of the vertex's node (docs/identity.md, *Pieces*), a float as `_ID`.
  if (layout.pieces)
    attributes["_PIECE"] = arrays.add(layout.pieces_at, layout.indices, array_buffer, float_type, vertex_count, "SCALAR");
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
    char* pieces = buffer + layout.pieces_at + 4 * begin;
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
      if (layout.pieces) put_f32(pieces, corner >= 0 ? static_cast<float>(mesh.face_piece[corner / 3]) : -1.0f);
    }
  });
  team.for_each_range(layout.corner_count, [&](std::size_t, std::size_t begin, std::size_t end) {
    char* indices = buffer + layout.indices + 4 * begin;
    for (std::size_t c = begin; c < end; ++c) put_u32(indices, static_cast<std::uint32_t>(split.corner_vertex[c]));
  });
}

}  // namespace

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

}  // namespace tear::encode
