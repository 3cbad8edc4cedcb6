// Helpers of the mesh reading and writing tests: files written inline, counts of pieces.
#pragma once

#include <stdlib.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include "catch.h"
#include "tear/mesh.h"

namespace tear::test {

/// A fresh folder, removed with everything in it at the end of the test.
struct IoDir {
  std::filesystem::path path;
  IoDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "tear_test_io.XXXXXX").string();
    REQUIRE(mkdtemp(pattern.data()) != nullptr);
    path = pattern;
  }
  ~IoDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
  IoDir(const IoDir&) = delete;
  IoDir& operator=(const IoDir&) = delete;
  std::string operator/(const std::string& name) const { return (path / name).string(); }
  std::string file(const std::string& name, const std::string& bytes) const {
    std::ofstream(path / name, std::ios::binary) << bytes;
    return (path / name).string();
  }
};

inline std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

/// Groups of faces connected through shared nodes (what `tear info` calls components).
inline int count_pieces(const Mesh& mesh) {
  std::vector<index_t> parent(mesh.node_count());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](index_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  for (std::size_t c = 0; c < mesh.face_nodes.size(); c += 3) {
    for (int k = 1; k < 3; ++k) parent[find(mesh.face_nodes[c + k])] = find(mesh.face_nodes[c]);
  }
  std::vector<std::uint8_t> used(mesh.node_count(), 0);
  for (index_t node : mesh.face_nodes) used[node] = 1;
  int pieces = 0;
  for (index_t node = 0; node < mesh.node_count(); ++node) pieces += used[node] && find(node) == node;
  return pieces;
}

/// As Blender writes it: `v` lines in its own order, faces using them in another, `-0.0000` in
/// normals, `s 0`, and a vertex no face uses (v 7).
inline const char* const blender_obj =
    "# Blender 4.1.1\n"
    "mtllib cloth.mtl\n"
    "o Cloth\n"
    "v 1.000000 1.000000 0.000000\n"
    "v 0.000000 0.000000 0.000000\n"
    "v 1.000000 0.000000 0.000000\n"
    "v 0.000000 1.000000 0.000000\n"
    "v 2.000000 0.000000 0.000000\n"
    "v 2.000000 1.000000 0.000000\n"
    "v 9.000000 9.000000 9.000000\n"
    "vn -0.0000 -0.0000 1.0000\n"
    "vn 0.0000 0.0000 1.0000\n"
    "vt 0.500000 1.000000\n"
    "vt 0.000000 0.000000\n"
    "vt 0.500000 0.000000\n"
    "vt 0.000000 1.000000\n"
    "vt 1.000000 0.000000\n"
    "vt 1.000000 1.000000\n"
    "s 0\n"
    "usemtl Fabric\n"
    "f 2/2/1 3/3/2 1/1/1 4/4/2\n"
    "f 3/3/1 5/5/2 6/6/2 1/1/2\n";

inline const std::vector<float> blender_positions = {1, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 2, 1, 0};

/// Little-endian bytes of a value, for binary files written inline.
template <typename T>
std::string le_bytes(T value) {
  std::string out(sizeof(T), '\0');
  for (std::size_t k = 0; k < sizeof(T); ++k) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &value, sizeof(T));
    out[k] = static_cast<char>((bits >> (8 * k)) & 0xFF);
  }
  return out;
}

/// Base64 of `bytes`, for glTF buffers written inline as data URIs.
inline std::string base64(const std::string& bytes) {
  static const char alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t group = static_cast<std::uint8_t>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) group |= static_cast<std::uint8_t>(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) group |= static_cast<std::uint8_t>(bytes[i + 2]);
    out += alphabet[(group >> 18) & 63];
    out += alphabet[(group >> 12) & 63];
    out += i + 1 < bytes.size() ? alphabet[(group >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? alphabet[group & 63] : '=';
  }
  return out;
}

/// Two triangles side by side that share the positions of an edge but not its nodes: two pieces,
/// as a cut leaves them. Nodes 1 and 3, 2 and 4 lie at the same place.
inline Mesh two_pieces() {
  Mesh mesh;
  mesh.node_pos = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  mesh.face_nodes = {0, 1, 2, 3, 5, 4};
  mesh.corner_uv = {0, 0, 1, 0, 0, 1, 1, 0, 1, 1, 0, 1};
  mesh.corner_normal = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  mesh.node_vel = {0, 0, 0, 0.5f, 0, 0, 0, 0.25f, 0, -0.5f, 0, 0, 0, -0.25f, 0, 0, 0, 1};
  mesh.node_origin_face = {0, 0, 0, 0, 0, 1};
  mesh.node_origin_bary = {0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0.5f, 0.5f};
  mesh.torn_edge_nodes = {1, 2, 3, 4};
  return mesh;
}

}  // namespace tear::test
