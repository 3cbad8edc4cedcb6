// The nodes of a mesh as read keep the file's vertex order (docs/io.md).
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "catch.h"
#include "io_support.h"
#include "tear/error.h"
#include "tear/read_mesh.h"

using tear::test::blender_obj;
using tear::test::blender_positions;
using tear::test::IoDir;

TEST_CASE("read_mesh: OBJ nodes are the v lines in order, whatever order the faces use them in", "[io]") {
  IoDir dir;
  const std::string path = dir.file("cloth.obj", blender_obj);
  const tear::Mesh mesh = tear::read_mesh(path);
  // v 7 is used by no face and dropped; the others keep their order.
  CHECK(mesh.node_pos == blender_positions);
  // Quads become fans from their first corner, in the file's face order.
  CHECK(mesh.face_nodes == std::vector<tear::index_t>{1, 2, 0, 1, 0, 3, 2, 4, 5, 2, 5, 0});
  REQUIRE(mesh.has_normals());
  REQUIRE(mesh.has_uv());
  // The normals are read as written, signed zeros included.
  CHECK(std::signbit(mesh.corner_normal[0]));
  CHECK_FALSE(std::signbit(mesh.corner_normal[3]));
  CHECK(mesh.corner_uv[0] == 0.0f);
  CHECK(mesh.corner_uv[4] == 0.5f);
  CHECK(mesh.corner_uv[5] == 1.0f);

  // No weld: the same nodes here, since the file repeats no position.
  tear::ReadOptions unwelded;
  unwelded.weld = false;
  CHECK(tear::read_mesh(path, unwelded).node_pos == blender_positions);
}

TEST_CASE("read_mesh: glTF nodes weld at split seams in the order of first appearance", "[io]") {
  IoDir dir;
  // Two quads side by side whose shared edge is split (a UV seam), vertices in a scrambled order:
  // v0 (1,1) right, v1 (2,0), v2 (1,0) right, v3 (0,0), v4 (1,0) left, v5 (1,1) left, v6 (0,1), v7 (2,1).
  const float xy[8][2] = {{1, 1}, {2, 0}, {1, 0}, {0, 0}, {1, 0}, {1, 1}, {0, 1}, {2, 1}};
  const float uv[8][2] = {{0.6f, 1}, {1, 0}, {0.6f, 0}, {0, 0}, {0.5f, 0}, {0.5f, 1}, {0, 1}, {1, 1}};
  const std::uint16_t indices[12] = {3, 4, 5, 3, 5, 6, 2, 1, 7, 2, 7, 0};
  std::string buffer;
  for (const auto& p : xy)
    buffer += tear::test::le_bytes(p[0]) + tear::test::le_bytes(p[1]) + tear::test::le_bytes(0.0f);
  for (const auto& t : uv) buffer += tear::test::le_bytes(t[0]) + tear::test::le_bytes(1.0f - t[1]);
  for (std::uint16_t i : indices) buffer += tear::test::le_bytes(i);
  const std::string uri = "data:application/octet-stream;base64," + tear::test::base64(buffer);
  const std::string gltf = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2}]}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3"},
                  {"bufferView": 1, "componentType": 5126, "count": 8, "type": "VEC2"},
                  {"bufferView": 2, "componentType": 5123, "count": 12, "type": "SCALAR"}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 96},
                    {"buffer": 0, "byteOffset": 96, "byteLength": 64},
                    {"buffer": 0, "byteOffset": 160, "byteLength": 24}],
    "buffers": [{"byteLength": 184, "uri": ")" +
                           uri + R"("}]})";
  REQUIRE(buffer.size() == 184);
  const std::string path = dir.file("seam.gltf", gltf);

  const tear::Mesh mesh = tear::read_mesh(path);
  // Each group keeps its first vertex: v0, v1, v2, v3, v6, v7 (v4 welds into v2, v5 into v0).
  CHECK(mesh.node_pos == std::vector<float>{1, 1, 0, 2, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1, 0, 2, 1, 0});
  CHECK(mesh.face_nodes == std::vector<tear::index_t>{3, 2, 0, 3, 0, 4, 2, 1, 5, 2, 5, 0});
  CHECK(tear::test::count_pieces(mesh) == 1);
  // The seam stays in the UVs: node 0 has u = 0.5 in the left quad, 0.6 in the right one.
  CHECK(mesh.corner_uv[2 * 2] == Approx(0.5f));
  CHECK(mesh.corner_uv[2 * 11] == Approx(0.6f));
  CHECK(mesh.corner_uv[2 * 2 + 1] == Approx(1.0f));

  tear::ReadOptions unwelded;
  unwelded.weld = false;
  const tear::Mesh split = tear::read_mesh(path, unwelded);
  CHECK(split.node_count() == 8);
  CHECK(split.face_nodes == std::vector<tear::index_t>{3, 4, 5, 3, 5, 6, 2, 1, 7, 2, 7, 0});
  CHECK(tear::test::count_pieces(split) == 2);
}

TEST_CASE("read_mesh: glTF accessors read the same tightly packed, interleaved, normalized and with any index type",
          "[io]") {
  IoDir dir;
  // The two quads above, split at their shared edge, read without welding: node i is vertex i.
  const float xy[8][2] = {{1, 1}, {2, 0}, {1, 0}, {0, 0}, {1, 0}, {1, 1}, {0, 1}, {2, 1}};
  const std::uint16_t uv16[8][2] = {{39321, 0}, {65535, 65535}, {39321, 65535}, {0, 65535},
                                    {32768, 65535}, {32768, 0}, {0, 0}, {65535, 0}};
  const std::uint32_t indices[12] = {3, 4, 5, 3, 5, 6, 2, 1, 7, 2, 7, 0};
  const auto uv_of = [&](int v, int k) { return static_cast<float>(uv16[v][k] / 65535.0); };
  const auto gltf = [](const std::string& buffer, const std::string& accessors, const std::string& views) {
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2}]}],
      "accessors": [)" + accessors + R"(], "bufferViews": [)" + views + R"(],
      "buffers": [{"byteLength": )" + std::to_string(buffer.size()) +
           R"(, "uri": "data:application/octet-stream;base64,)" + tear::test::base64(buffer) + R"("}]})";
  };
  using tear::test::le_bytes;
  tear::ReadOptions unwelded;
  unwelded.weld = false;

  // Tightly packed: positions, float UVs, 16-bit indices, each in a view of its own.
  std::string tight;
  for (const auto& p : xy) tight += le_bytes(p[0]) + le_bytes(p[1]) + le_bytes(0.0f);
  for (int v = 0; v < 8; ++v) tight += le_bytes(uv_of(v, 0)) + le_bytes(uv_of(v, 1));
  for (std::uint32_t i : indices) tight += le_bytes(static_cast<std::uint16_t>(i));
  const tear::Mesh a = tear::read_mesh(
      dir.file("tight.gltf",
               gltf(tight,
                    R"({"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3"},
                       {"bufferView": 1, "componentType": 5126, "count": 8, "type": "VEC2"},
                       {"bufferView": 2, "componentType": 5123, "count": 12, "type": "SCALAR"})",
                    R"({"buffer": 0, "byteOffset": 0, "byteLength": 96}, {"buffer": 0, "byteOffset": 96, "byteLength": 64},
                       {"buffer": 0, "byteOffset": 160, "byteLength": 24})")),
      unwelded);
  std::vector<float> expected_pos;
  for (const auto& p : xy) expected_pos.insert(expected_pos.end(), {p[0], p[1], 0.0f});
  CHECK(a.node_pos == expected_pos);
  CHECK(a.face_nodes == std::vector<tear::index_t>(indices, indices + 12));
  REQUIRE(a.corner_uv.size() == 24);
  for (int c = 0; c < 12; ++c) {
    CHECK(a.corner_uv[2 * c] == uv_of(static_cast<int>(indices[c]), 0));
    CHECK(a.corner_uv[2 * c + 1] == 1.0f - uv_of(static_cast<int>(indices[c]), 1));
  }

  // Interleaved: position and UV of a vertex one after the other in one view of stride 20; 8-bit indices.
  std::string interleaved;
  for (int v = 0; v < 8; ++v)
    interleaved += le_bytes(xy[v][0]) + le_bytes(xy[v][1]) + le_bytes(0.0f) + le_bytes(uv_of(v, 0)) + le_bytes(uv_of(v, 1));
  for (std::uint32_t i : indices) interleaved += le_bytes(static_cast<std::uint8_t>(i));
  const tear::Mesh b = tear::read_mesh(
      dir.file("interleaved.gltf",
               gltf(interleaved,
                    R"({"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3"},
                       {"bufferView": 0, "byteOffset": 12, "componentType": 5126, "count": 8, "type": "VEC2"},
                       {"bufferView": 1, "componentType": 5121, "count": 12, "type": "SCALAR"})",
                    R"({"buffer": 0, "byteOffset": 0, "byteLength": 160, "byteStride": 20},
                       {"buffer": 0, "byteOffset": 160, "byteLength": 12})")),
      unwelded);
  CHECK(b.node_pos == a.node_pos);
  CHECK(b.face_nodes == a.face_nodes);
  CHECK(b.corner_uv == a.corner_uv);

  // Normalized 16-bit UVs (k / 65535, as glTF defines them) and 32-bit indices.
  std::string normalized;
  for (const auto& p : xy) normalized += le_bytes(p[0]) + le_bytes(p[1]) + le_bytes(0.0f);
  for (const auto& t : uv16) normalized += le_bytes(t[0]) + le_bytes(t[1]);
  for (std::uint32_t i : indices) normalized += le_bytes(i);
  const tear::Mesh c = tear::read_mesh(
      dir.file("normalized.gltf",
               gltf(normalized,
                    R"({"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3"},
                       {"bufferView": 1, "componentType": 5123, "normalized": true, "count": 8, "type": "VEC2"},
                       {"bufferView": 2, "componentType": 5125, "count": 12, "type": "SCALAR"})",
                    R"({"buffer": 0, "byteOffset": 0, "byteLength": 96}, {"buffer": 0, "byteOffset": 96, "byteLength": 32},
                       {"buffer": 0, "byteOffset": 128, "byteLength": 48})")),
      unwelded);
  CHECK(c.node_pos == a.node_pos);
  CHECK(c.face_nodes == a.face_nodes);
  CHECK(c.corner_uv == a.corner_uv);
}

TEST_CASE("read_mesh: OBJ polygons are triangulated in place, concave ones by ear clipping", "[io]") {
  IoDir dir;
  // An L-shaped hexagon (concave at v4) between a triangle and a quad; relative indices in the quad.
  const std::string path = dir.file("polygons.obj",
                                    "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\n"
                                    "v 3 0 0\nv 3 1 0\n"
                                    "f 2 7 3\n"
                                    "f 1 2 3 4 5 6\n"
                                    "f -7 -2 -1 -6\n");
  const tear::Mesh mesh = tear::read_mesh(path);
  REQUIRE(mesh.face_count() == 1 + 4 + 2);
  CHECK(std::vector<tear::index_t>(mesh.face_nodes.begin(), mesh.face_nodes.begin() + 3) ==
        std::vector<tear::index_t>{1, 6, 2});
  CHECK(std::vector<tear::index_t>(mesh.face_nodes.begin() + 3, mesh.face_nodes.begin() + 15) ==
        std::vector<tear::index_t>{0, 1, 2, 0, 2, 3, 5, 0, 3, 3, 4, 5});
  CHECK(std::vector<tear::index_t>(mesh.face_nodes.begin() + 15, mesh.face_nodes.end()) ==
        std::vector<tear::index_t>{1, 6, 7, 1, 7, 2});
}

TEST_CASE("read_mesh: an OBJ with a UTF-8 byte order mark reads like one without", "[io]") {
  IoDir dir;
  const std::string plain = dir.file("plain.obj", blender_obj);
  const std::string bom = dir.file("bom.obj", std::string("\xEF\xBB\xBF") + "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  CHECK(tear::read_mesh(bom).node_pos == std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0});
  CHECK(tear::read_mesh(dir.file("bom2.obj", "\xEF\xBB\xBF" + std::string(blender_obj))).node_pos ==
        tear::read_mesh(plain).node_pos);
}

TEST_CASE("read_mesh: OBJ groups select meshes, and OBJ errors name the file", "[io]") {
  IoDir dir;
  const std::string path = dir.file("groups.obj",
                                    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                                    "g sleeve left\nf 1 2 3\n"
                                    "o body\nf 2 4 3\n");
  tear::ReadOptions options;
  for (const char* name : {"sleeve left", "left", "sleeve"}) {
    options.mesh_name = name;
    INFO(name);
    CHECK(tear::read_mesh(path, options).face_count() == 1);
  }
  options.mesh_name = "body";
  const tear::Mesh body = tear::read_mesh(path, options);
  CHECK(body.node_pos == std::vector<float>{1, 0, 0, 0, 1, 0, 1, 1, 0});

  const std::vector<std::string> bad = {
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n",                // index 0
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n",               // relative index before the first v
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n",  // vt out of range
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n",       // vn out of range
  };
  for (std::size_t i = 0; i < bad.size(); ++i) {
    const std::string file = dir.file("bad" + std::to_string(i) + ".obj", bad[i]);
    INFO(bad[i]);
    try {
      tear::read_mesh(file);
      FAIL("no error");
    } catch (const tear::Error& e) {
      const std::string message = e.what();
      INFO(message);
      CHECK(e.kind() == tear::ErrorKind::input);
      CHECK(message.rfind(file + ": ", 0) == 0);
      CHECK(message.find('\n') == std::string::npos);
    }
  }
}
