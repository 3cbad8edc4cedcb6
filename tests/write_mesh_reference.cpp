// The encoders tear had before a frame was encoded in parallel, kept verbatim as the reference
// `encode_mesh` must match byte for byte at any thread count (test_encode_parallel.cpp); base64 is
// the tests' own (io_support.h), the same code.
#include "write_mesh_reference.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <numeric>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "io_support.h"

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

/// Appends `value` in decimal, as `std::to_string` spells it.
void append_int(std::string& out, long long value) {
  char text[24];
  out.append(text, std::to_chars(text, text + sizeof text, value).ptr);
}

/// Equal as numbers: -0 and +0 are one value (Blender writes both in normals), NaN is one value.
bool same_value(float a, float b) { return a == b || (std::isnan(a) && std::isnan(b)); }

/// Vertices for formats without per-corner indices (PLY, glTF). Vertex `i` is node `i` for every
/// `i < node_count`, with the UV and normal of the node's first corner; a corner whose UV or
/// normal differs (as numbers) from those of every vertex of its node so far gets a vertex of its
/// own, numbered after all the nodes in the order of the corners. So a reader that keeps vertex
/// order sees node `i` at vertex `i`, and identical attributes never split a node.
struct SplitNodes {
  std::vector<index_t> vertex_node;    ///< [vertex_count] node of each vertex
  std::vector<index_t> vertex_corner;  ///< [vertex_count] first corner using it (its UV and normal), -1 if none
  std::vector<index_t> corner_vertex;  ///< [face_count * 3] vertex of each corner
};

SplitNodes split_nodes(const Mesh& mesh) {
  auto same_attributes = [&](index_t a, std::size_t b) {
    for (int k = 0; mesh.has_uv() && k < 2; ++k) {
      if (!same_value(mesh.corner_uv[2 * a + k], mesh.corner_uv[2 * b + k])) return false;
    }
    for (int k = 0; mesh.has_normals() && k < 3; ++k) {
      if (!same_value(mesh.corner_normal[3 * a + k], mesh.corner_normal[3 * b + k])) return false;
    }
    return true;
  };
  const index_t node_count = mesh.node_count();
  SplitNodes split;
  split.vertex_node.resize(node_count);
  std::iota(split.vertex_node.begin(), split.vertex_node.end(), 0);
  split.vertex_corner.assign(node_count, none);
  split.corner_vertex.resize(mesh.face_nodes.size());
  // The vertices split off each node; a node has few distinct corner attributes, so a linear
  // search per corner is enough.
  std::vector<std::vector<index_t>> node_extra(node_count);
  for (std::size_t c = 0; c < mesh.face_nodes.size(); ++c) {
    const index_t node = mesh.face_nodes[c];
    index_t vertex = none;
    if (split.vertex_corner[node] == none) {
      split.vertex_corner[node] = static_cast<index_t>(c);
      vertex = node;
    } else if (same_attributes(split.vertex_corner[node], c)) {
      vertex = node;
    } else {
      for (index_t candidate : node_extra[node]) {
        if (same_attributes(split.vertex_corner[candidate], c)) {
          vertex = candidate;
          break;
        }
      }
    }
    if (vertex == none) {
      vertex = static_cast<index_t>(split.vertex_node.size());
      split.vertex_node.push_back(node);
      split.vertex_corner.push_back(static_cast<index_t>(c));
      node_extra[node].push_back(vertex);
    }
    split.corner_vertex[c] = vertex;
  }
  return split;
}

/// The bits of a `width`-float value, hashed for `number_by_value`.
template <int width>
struct ValueBits {
  std::array<std::uint32_t, width> bits;
  bool operator==(const ValueBits& other) const { return bits == other.bits; }
  struct Hash {
    std::size_t operator()(const ValueBits& value) const {
      std::uint64_t hash = 1469598103934665603ull;  // FNV-1a over the words
      for (std::uint32_t word : value.bits) hash = (hash ^ word) * 1099511628211ull;
      return static_cast<std::size_t>(hash ^ (hash >> 32));
    }
  };
};

/// Numbers distinct values (compared bit for bit) in order of first use, as OBJ's `vt`/`vn` lists.
/// The numbering depends on the order of use only, not on the table that finds the values.
template <int width>
std::vector<index_t> number_by_value(const std::vector<float>& corner_values, std::string& lines, const char* keyword) {
  std::unordered_map<ValueBits<width>, index_t, typename ValueBits<width>::Hash> value_index;
  std::vector<index_t> corner_index(corner_values.size() / width);
  value_index.reserve(corner_index.size() / 4);
  ValueBits<width> key;
  for (std::size_t c = 0; c < corner_index.size(); ++c) {
    for (int k = 0; k < width; ++k) key.bits[k] = float_bits(corner_values[width * c + k]);
    auto inserted = value_index.try_emplace(key, static_cast<index_t>(value_index.size()));
    if (inserted.second) {
      lines += keyword;
      for (int k = 0; k < width; ++k) {
        lines += ' ';
        append_float(lines, corner_values[width * c + k]);
      }
      lines += '\n';
    }
    corner_index[c] = inserted.first->second;
  }
  return corner_index;
}

void put_obj_text(const Mesh& mesh, std::string& text) {
  text = "# tear\n";
  for (index_t node = 0; node < mesh.node_count(); ++node) {
    text += 'v';
    for (int k = 0; k < 3; ++k) {
      text += ' ';
      append_float(text, mesh.node_pos[3 * node + k]);
    }
    text += '\n';
  }
  std::vector<index_t> corner_uv_index, corner_normal_index;
  if (mesh.has_uv()) corner_uv_index = number_by_value<2>(mesh.corner_uv, text, "vt");
  if (mesh.has_normals()) corner_normal_index = number_by_value<3>(mesh.corner_normal, text, "vn");
  for (std::size_t c = 0; c < mesh.face_nodes.size(); ++c) {
    text += c % 3 == 0 ? "f " : " ";
    append_int(text, mesh.face_nodes[c] + 1LL);
    if (mesh.has_uv() || mesh.has_normals()) text += '/';
    if (mesh.has_uv()) append_int(text, corner_uv_index[c] + 1LL);
    if (mesh.has_normals()) {
      text += '/';
      append_int(text, corner_normal_index[c] + 1LL);
    }
    if (c % 3 == 2) text += '\n';
  }
}

void append_u8(std::string& out, std::uint8_t value) { out += static_cast<char>(value); }

void append_u32(std::string& out, std::uint32_t value) {
  const char bytes[4] = {static_cast<char>(value & 0xFFu), static_cast<char>((value >> 8) & 0xFFu),
                         static_cast<char>((value >> 16) & 0xFFu), static_cast<char>((value >> 24) & 0xFFu)};
  out.append(bytes, 4);
}

void append_f32(std::string& out, float value) { append_u32(out, float_bits(value)); }

/// A vertex's UV and normal: its first corner's, or zeros for a node no face uses.
float corner_value(const std::vector<float>& corner_values, int width, index_t corner, int k) {
  return corner == none ? 0.0f : corner_values[static_cast<std::size_t>(width) * corner + k];
}

void put_ply_bytes(const Mesh& mesh, std::string& out) {
  const SplitNodes split = split_nodes(mesh);
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
  for (std::size_t v = 0; v < split.vertex_node.size(); ++v) {
    const index_t node = split.vertex_node[v];
    const index_t corner = split.vertex_corner[v];
    for (int k = 0; k < 3; ++k) append_f32(out, mesh.node_pos[3 * node + k]);
    for (int k = 0; mesh.has_normals() && k < 3; ++k) append_f32(out, corner_value(mesh.corner_normal, 3, corner, k));
    for (int k = 0; mesh.has_uv() && k < 2; ++k) append_f32(out, corner_value(mesh.corner_uv, 2, corner, k));
    append_u32(out, static_cast<std::uint32_t>(node));
    for (int k = 0; k < 3; ++k) append_f32(out, mesh.has_velocities() ? mesh.node_vel[3 * node + k] : 0.0f);
    append_u32(out, static_cast<std::uint32_t>(mesh.has_origins() ? mesh.node_origin_face[node] : none));
    for (int k = 0; k < 2; ++k) append_f32(out, mesh.has_origins() ? mesh.node_origin_bary[2 * node + k] : 0.0f);
  }
  for (index_t face = 0; face < mesh.face_count(); ++face) {
    append_u8(out, 3);
    for (int k = 0; k < 3; ++k) append_u32(out, static_cast<std::uint32_t>(split.corner_vertex[3 * face + k]));
  }
  // Vertex i is node i, so the torn edges' node pairs are vertex pairs.
  for (index_t node : mesh.torn_edge_nodes) append_u32(out, static_cast<std::uint32_t>(node));
}

/// A float as the JSON number with the fewest digits that reads back to it.
double json_number(float value) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, value).ptr;
  double wide = value;
  std::from_chars(text, end, wide);
  return wide;
}

/// The glTF document and its binary buffer (positions, normals, UVs, then indices).
std::pair<nlohmann::json, std::string> gltf_document(const Mesh& mesh) {
  using nlohmann::json;
  json document;
  document["asset"] = {{"generator", "tear"}, {"version", "2.0"}};
  document["scene"] = 0;
  if (mesh.face_count() == 0) {
    // glTF forbids empty accessors and buffers: an empty mesh is a scene without nodes.
    document["scenes"] = json::array({json::object()});
    return {document, std::string()};
  }
  document["scenes"] = json::array({{{"nodes", {0}}}});
  document["nodes"] = json::array({{{"mesh", 0}, {"name", "cloth"}}});

  const SplitNodes split = split_nodes(mesh);
  const std::size_t vertex_count = split.vertex_node.size();
  std::string buffer;
  json buffer_views = json::array();
  json accessors = json::array();
  json attributes = json::object();
  constexpr int array_buffer = 34962, element_array_buffer = 34963;
  constexpr int float_type = 5126, unsigned_int_type = 5125;

  auto add_view = [&](std::size_t begin, int target) {
    buffer_views.push_back(
        {{"buffer", 0}, {"byteOffset", begin}, {"byteLength", buffer.size() - begin}, {"target", target}});
  };

  // POSITION needs min and max; non-finite coordinates stay out of them (JSON has no NaN).
  std::size_t begin = buffer.size();
  float low[3], high[3];
  bool seen[3] = {false, false, false};
  for (index_t node : split.vertex_node) {
    for (int k = 0; k < 3; ++k) {
      const float x = mesh.node_pos[3 * node + k];
      append_f32(buffer, x);
      if (!std::isfinite(x)) continue;
      low[k] = seen[k] ? std::min(low[k], x) : x;
      high[k] = seen[k] ? std::max(high[k], x) : x;
      seen[k] = true;
    }
  }
  json min = json::array(), max = json::array();
  for (int k = 0; k < 3; ++k) {
    min.push_back(seen[k] ? json_number(low[k]) : 0.0);
    max.push_back(seen[k] ? json_number(high[k]) : 0.0);
  }
  add_view(begin, array_buffer);
  accessors.push_back({{"bufferView", buffer_views.size() - 1},
                       {"componentType", float_type},
                       {"count", vertex_count},
                       {"type", "VEC3"},
                       {"min", min},
                       {"max", max}});
  attributes["POSITION"] = accessors.size() - 1;

  if (mesh.has_normals()) {
    begin = buffer.size();
    for (index_t corner : split.vertex_corner) {
      for (int k = 0; k < 3; ++k) append_f32(buffer, corner_value(mesh.corner_normal, 3, corner, k));
    }
    add_view(begin, array_buffer);
    accessors.push_back({{"bufferView", buffer_views.size() - 1},
                         {"componentType", float_type},
                         {"count", vertex_count},
                         {"type", "VEC3"}});
    attributes["NORMAL"] = accessors.size() - 1;
  }
  if (mesh.has_uv()) {
    begin = buffer.size();
    for (index_t corner : split.vertex_corner) {
      append_f32(buffer, corner_value(mesh.corner_uv, 2, corner, 0));
      append_f32(buffer, 1.0f - corner_value(mesh.corner_uv, 2, corner, 1));
    }
    add_view(begin, array_buffer);
    accessors.push_back({{"bufferView", buffer_views.size() - 1},
                         {"componentType", float_type},
                         {"count", vertex_count},
                         {"type", "VEC2"}});
    attributes["TEXCOORD_0"] = accessors.size() - 1;
  }

  // Identity (docs/io.md), as application-specific attributes: `_ID`, the node each vertex is,
  // and `_VELOCITY` (m/s). glTF allows no UNSIGNED_INT outside indices, and Blender imports a
  // SCALAR FLOAT (not a SHORT) as a point attribute, so ids are floats: exact up to 2^24 nodes,
  // and left out above that rather than rounded.
  if (mesh.node_count() <= max_float_id) {
    begin = buffer.size();
    for (index_t node : split.vertex_node) append_f32(buffer, static_cast<float>(node));
    add_view(begin, array_buffer);
    accessors.push_back({{"bufferView", buffer_views.size() - 1},
                         {"componentType", float_type},
                         {"count", vertex_count},
                         {"type", "SCALAR"}});
    attributes["_ID"] = accessors.size() - 1;
  }
  begin = buffer.size();
  for (index_t node : split.vertex_node) {
    for (int k = 0; k < 3; ++k) append_f32(buffer, mesh.has_velocities() ? mesh.node_vel[3 * node + k] : 0.0f);
  }
  add_view(begin, array_buffer);
  accessors.push_back({{"bufferView", buffer_views.size() - 1},
                       {"componentType", float_type},
                       {"count", vertex_count},
                       {"type", "VEC3"}});
  attributes["_VELOCITY"] = accessors.size() - 1;

  begin = buffer.size();
  for (index_t vertex : split.corner_vertex) append_u32(buffer, static_cast<std::uint32_t>(vertex));
  add_view(begin, element_array_buffer);
  accessors.push_back({{"bufferView", buffer_views.size() - 1},
                       {"componentType", unsigned_int_type},
                       {"count", split.corner_vertex.size()},
                       {"type", "SCALAR"}});

  constexpr int triangles = 4;
  document["meshes"] = json::array(
      {{{"name", "cloth"},
        {"primitives",
         json::array({{{"attributes", attributes}, {"indices", accessors.size() - 1}, {"mode", triangles}}})}}});
  document["accessors"] = accessors;
  document["bufferViews"] = buffer_views;
  document["buffers"] = json::array({{{"byteLength", buffer.size()}}});
  return {document, buffer};
}

void put_gltf_text(const Mesh& mesh, std::string& out) {
  auto [document, buffer] = gltf_document(mesh);
  if (!buffer.empty()) {
    document["buffers"][0]["uri"] = "data:application/octet-stream;base64," + test::base64(buffer);
  }
  out = document.dump(2);
  out += '\n';
}

void put_glb_bytes(const Mesh& mesh, std::string& out) {
  const auto [document, buffer] = gltf_document(mesh);
  // Chunks are 4-byte aligned: JSON padded with spaces, the binary chunk with zeros.
  std::string json_chunk = document.dump();
  json_chunk.resize((json_chunk.size() + 3) / 4 * 4, ' ');
  const std::size_t bin_size = (buffer.size() + 3) / 4 * 4;
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
    out += buffer;
    out.resize(total, '\0');
  }
}

}  // namespace

std::string encode_mesh_reference(const Mesh& mesh, MeshFormat format) {
  std::string bytes;
  switch (format) {
    case MeshFormat::obj:
      put_obj_text(mesh, bytes);
      break;
    case MeshFormat::ply:
      put_ply_bytes(mesh, bytes);
      break;
    case MeshFormat::gltf:
      put_gltf_text(mesh, bytes);
      break;
    case MeshFormat::glb:
      put_glb_bytes(mesh, bytes);
      break;
  }
  return bytes;
}

}  // namespace tear
