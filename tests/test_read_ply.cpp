// PLY read by hand: ASCII and both binary byte orders, tear's identity properties, hostile files.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "catch.h"
#include "io_support.h"
#include "random_meshes.h"
#include "tear/error.h"
#include "tear/read_mesh.h"
#include "tear/write_mesh.h"
#include "test_support.h"

namespace {

using tear::test::IoDir;
using tear::test::le_bytes;

template <typename T>
std::string be_bytes(T value) {
  std::string bytes = le_bytes(value);
  std::reverse(bytes.begin(), bytes.end());
  return bytes;
}

/// The input error `read_mesh(path)` throws: one line starting with the path.
std::string input_error_of(const std::string& path) {
  try {
    tear::read_mesh(path);
  } catch (const tear::Error& e) {
    const std::string message = e.what();
    INFO(message);
    CHECK(e.kind() == tear::ErrorKind::input);
    CHECK(message.rfind(path + ": ", 0) == 0);
    CHECK(message.find('\n') == std::string::npos);
    return message;
  }
  FAIL("no error for " << path);
  return {};
}

}  // namespace

TEST_CASE("read_mesh: ASCII PLY with ids welds by id, node i being id i", "[io][ply]") {
  IoDir dir;
  // Vertices out of id order, id 1 split in two (a UV seam), a vertex no face uses (id 4).
  const std::string path = dir.file("ids.ply",
                                    "ply\r\nformat ascii 1.0\r\ncomment written by hand\r\n"
                                    "element vertex 6\r\n"
                                    "property float x\r\nproperty float y\r\nproperty float z\r\n"
                                    "property float u\r\nproperty float v\r\n"
                                    "property int id\r\nproperty float vx\r\nproperty float vy\r\nproperty float vz\r\n"
                                    "property int origin_face\r\nproperty float origin_u\r\nproperty float origin_v\r\n"
                                    "element face 2\r\nproperty list uchar int vertex_indices\r\n"
                                    "element edge 1\r\nproperty int vertex1\r\nproperty int vertex2\r\n"
                                    "end_header\r\n"
                                    "1 0 0  1 0  1  0.5 0 0  0 1 0\r\n"
                                    "0 0 0  0 0  0  0 0 0  0 0 0\r\n"
                                    "9 9 9  0 0  4  0 0 0  -1 0 0\r\n"
                                    "0 1 0  0 1  2  0 0.25 0  0 0 1\r\n"
                                    "1 1 0  1 1  3  0 0 1  1 0.5 0.5\r\n"
                                    "1 0 0  0.5 0  1  7 7 7  3 0 0\r\n"
                                    "3 1 0 3\r\n"
                                    "3 5 4 3\r\n"
                                    "1 0\r\n");
  const tear::Mesh mesh = tear::read_mesh(path);
  CHECK(mesh.node_pos == std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
  CHECK(mesh.face_nodes == std::vector<tear::index_t>{0, 1, 2, 1, 3, 2});
  // Each node takes the values of its id's first vertex.
  CHECK(mesh.node_vel == std::vector<float>{0, 0, 0, 0.5f, 0, 0, 0, 0.25f, 0, 0, 0, 1});
  CHECK(mesh.node_origin_face == std::vector<tear::index_t>{0, 0, 0, 1});
  CHECK(mesh.node_origin_bary == std::vector<float>{0, 0, 1, 0, 0, 1, 0.5f, 0.5f});
  // The seam stays in the corners' UVs.
  CHECK(mesh.corner_uv == std::vector<float>{0, 0, 1, 0, 0, 1, 0.5f, 0, 1, 1, 0, 1});
  // The edge of vertices 1 and 0 (ids 0 and 1) is on the boundary: a torn edge.
  CHECK(mesh.torn_edge_nodes == std::vector<tear::index_t>{0, 1});

  tear::ReadOptions unwelded;
  unwelded.weld = false;
  const tear::Mesh split = tear::read_mesh(path, unwelded);
  CHECK(split.node_count() == 5);
  CHECK(split.face_nodes == std::vector<tear::index_t>{1, 0, 2, 4, 3, 2});
}

TEST_CASE("read_mesh: binary PLY in either byte order, any list and index types, polygons", "[io][ply]") {
  IoDir dir;
  for (bool big : {false, true}) {
    INFO((big ? "big endian" : "little endian"));
    auto f32 = [&](float v) { return big ? be_bytes(v) : le_bytes(v); };
    auto u16 = [&](std::uint16_t v) { return big ? be_bytes(v) : le_bytes(v); };
    auto i32 = [&](std::int32_t v) { return big ? be_bytes(v) : le_bytes(v); };
    std::string bytes = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                        " 1.0\nelement vertex 5\nproperty double x\nproperty double y\nproperty float z\n"
                        "property uchar red\nproperty float texture_u\nproperty float texture_v\n"
                        "element material 1\nproperty list uchar uchar name\n"
                        "element face 2\nproperty uchar flags\nproperty list ushort uint vertex_index\n"
                        "end_header\n";
    const double xy[5][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 0.5}, {0, 1}};
    for (int v = 0; v < 5; ++v) {
      const double x = xy[v][0], y = xy[v][1];
      bytes += big ? be_bytes(x) + be_bytes(y) : le_bytes(x) + le_bytes(y);
      bytes += f32(0.0f) + std::string(1, '\x7f') + f32(static_cast<float>(x) / 2) + f32(static_cast<float>(y));
    }
    bytes += std::string("\x03") + "abc";
    bytes += std::string(1, '\0') + u16(5) + i32(0) + i32(1) + i32(2) + i32(3) + i32(4);  // concave at vertex 3
    bytes += std::string(1, '\0') + u16(2) + i32(0) + i32(1);                             // two corners: no face
    const std::string path = dir.file(big ? "big.ply" : "little.ply", bytes);
    const tear::Mesh mesh = tear::read_mesh(path);
    CHECK(mesh.node_count() == 5);
    CHECK(mesh.face_count() == 3);
    CHECK(tear::test::count_pieces(mesh) == 1);
    // Not a fan from vertex 0 (its second triangle would be flat): ears, in the polygon's orientation.
    CHECK(mesh.face_nodes == std::vector<tear::index_t>{1, 2, 3, 0, 1, 3, 0, 3, 4});
    REQUIRE(mesh.has_uv());
    CHECK(mesh.corner_uv[2] == 1.0f);
  }
}

TEST_CASE("read_mesh: a face texcoord list gives corner UVs, ASCII numbers may have a plus sign", "[io][ply]") {
  IoDir dir;
  const std::string path = dir.file("texcoord.ply",
                                    "ply\nformat ascii 1.0\nelement vertex 4\n"
                                    "property float x\nproperty float y\nproperty float z\n"
                                    "element face 1\nproperty list uchar int vertex_indices\n"
                                    "property list uchar float texcoord\nend_header\n"
                                    "0 0 0\n+1 0 0\n1 1 0\n0 1 0\n"
                                    "4 0 1 2 3 8 0 0 0.5 0 0.5 0.5 0 0.5\n");
  const tear::Mesh mesh = tear::read_mesh(path);
  CHECK(mesh.face_nodes == std::vector<tear::index_t>{0, 1, 2, 0, 2, 3});
  CHECK(mesh.corner_uv == std::vector<float>{0, 0, 0.5f, 0, 0.5f, 0.5f, 0, 0, 0.5f, 0.5f, 0, 0.5f});
  CHECK(mesh.node_pos[3] == 1.0f);
}

TEST_CASE("read_mesh: malformed PLY files are one-line input errors, found before allocating", "[io][ply]") {
  IoDir dir;
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
      "property float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  std::string body;
  for (float v : {0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f}) body += le_bytes(v);
  const std::string face = std::string("\x03") + le_bytes(0) + le_bytes(1) + le_bytes(2);
  REQUIRE(tear::read_mesh(dir.file("good.ply", header + body + face)).face_count() == 1);

  CHECK(input_error_of(dir.file("no_end.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"))
            .find("end_header") != std::string::npos);
  // A header cut short in the middle of binary data.
  CHECK(!input_error_of(dir.file("cut_header.ply", header.substr(0, 60) + body)).empty());
  // A billion vertices declared in a few bytes: refused before anything is allocated.
  std::string huge = header;
  huge.replace(huge.find("vertex 3"), 8, "vertex 1000000000");
  CHECK(input_error_of(dir.file("huge.ply", huge + body + face)).find("1000000000") != std::string::npos);
  std::string huge_faces = header;
  huge_faces.replace(huge_faces.find("face 1"), 6, "face 4000000000");
  input_error_of(dir.file("huge_faces.ply", huge_faces + body + face));
  // Data cut short, in the vertices and in a face's list.
  input_error_of(dir.file("short_vertices.ply", header + body.substr(0, 20)));
  input_error_of(dir.file("short_face.ply", header + body + face.substr(0, 7)));
  // A list that claims more items than the file has.
  input_error_of(dir.file("long_list.ply", header + body + "\xff" + le_bytes(0) + le_bytes(1) + le_bytes(2)));
  // Indices out of range, non-finite values, unknown types and formats.
  CHECK(input_error_of(dir.file("index.ply", header + body + "\x03" + le_bytes(0) + le_bytes(1) + le_bytes(3)))
            .find("out of range") != std::string::npos);
  input_error_of(dir.file("negative.ply", header + body + "\x03" + le_bytes(0) + le_bytes(1) + le_bytes(-1)));
  std::string nan_body = body;
  nan_body.replace(4, 4, le_bytes(std::numeric_limits<float>::quiet_NaN()));
  CHECK(input_error_of(dir.file("nan.ply", header + nan_body + face)).find("non-finite") != std::string::npos);
  input_error_of(dir.file("inf.ply",
                          "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                          "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                          "end_header\n0 0 0 1 0 inf 0 1 0 3 0 1 2\n"));
  input_error_of(dir.file("word.ply",
                          "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                          "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                          "end_header\n0 0 0 1 0 zero 0 1 0 3 0 1 2\n"));
  input_error_of(dir.file("type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n1\n"));
  input_error_of(dir.file("format.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n"));
  input_error_of(dir.file("no_xyz.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float w\nend_header\n1\n"));
  input_error_of(dir.file("not_ply.ply", "solid cube\n"));
  input_error_of(dir.file("empty.ply", ""));
}

namespace {

/// The outcome of reading `path` unwelded: the mesh, or the error's message after the path.
struct PlyOutcome {
  tear::Mesh mesh;
  std::string error;
};
PlyOutcome read_outcome(const std::string& path) {
  PlyOutcome out;
  tear::ReadOptions unwelded;
  unwelded.weld = false;
  try {
    out.mesh = tear::read_mesh(path, unwelded);
  } catch (const tear::Error& e) {
    out.error = std::string(e.what()).substr(path.size());
  }
  return out;
}

}  // namespace

TEST_CASE("read_mesh: binary PLY read all at once gives the mesh and the errors of reading it value by value",
          "[io][ply]") {
  // The same data twice: laid out as tear writes it (read on OpenMP threads, all instances at
  // once), and with one more property on each element (a list on the vertices, a scalar on the
  // faces), which the reader takes value by value. Sizes reach past the size the fast paths split
  // among threads at; some files carry a NaN, an index out of range or a face of another size.
  const std::uint64_t seed = tear::test::test_seed(20261124);
  INFO("seed " << seed << " (TEAR_TEST_SEED reproduces it)");
  tear::test::Random random(seed);
  IoDir dir;
  for (int round = 0; round < 24; ++round) {
    INFO("round " << round);
    const bool big = random.chance(0.3), normals = random.chance(0.6), uvs = random.chance(0.6),
               identity = random.chance(0.5);
    const int corners = random.chance(0.8) ? 3 : 4;
    const std::size_t faces = random.chance(0.4) ? 5000 + random.below(3000) : 1 + random.below(50);
    const std::size_t vertices = 3 + random.below(static_cast<tear::index_t>(faces));
    const int flaw = static_cast<int>(random.below(5));  // 0, 1: none; 2: NaN; 3: index; 4: corner count
    auto f32 = [&](float v) { return big ? be_bytes(v) : le_bytes(v); };
    auto i32 = [&](std::int32_t v) { return big ? be_bytes(v) : le_bytes(v); };
    std::string header[2], body[2];
    for (int serial = 0; serial < 2; ++serial) {
      header[serial] = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                       " 1.0\nelement vertex " + std::to_string(vertices) + "\nproperty float x\nproperty float y\n" +
                       "property float z\n" + (normals ? "property float nx\nproperty float ny\nproperty float nz\n" : "") +
                       (uvs ? "property float s\nproperty float t\n" : "") +
                       (identity ? "property int id\nproperty float vx\nproperty float vy\nproperty float vz\n"
                                   "property int origin_face\nproperty float origin_u\nproperty float origin_v\n"
                                 : "") +
                       (serial ? "property list uchar int extra\n" : "") + "element face " + std::to_string(faces) +
                       "\n" + (serial ? "property uchar flags\n" : "") + "property list uchar int vertex_indices\n" +
                       "end_header\n";
    }
    const std::size_t nan_vertex = random.below(static_cast<tear::index_t>(vertices));
    const std::size_t bad_face = random.below(static_cast<tear::index_t>(faces));
    for (std::size_t v = 0; v < vertices; ++v) {
      std::string record;
      for (int a = 0; a < 3; ++a) {
        const bool nan = flaw == 2 && v == nan_vertex && a == 1;
        record += f32(nan ? std::numeric_limits<float>::quiet_NaN() : static_cast<float>(random.uniform(-2, 2)));
      }
      if (normals)
        for (int a = 0; a < 3; ++a) record += f32(static_cast<float>(random.uniform(-1, 1)));
      if (uvs)
        for (int a = 0; a < 2; ++a) record += f32(static_cast<float>(random.uniform()));
      if (identity) {
        record += i32(static_cast<std::int32_t>(v));
        for (int a = 0; a < 3; ++a) record += f32(static_cast<float>(random.uniform(-1, 1)));
        record += i32(static_cast<std::int32_t>(random.below(7)) - 1);
        for (int a = 0; a < 2; ++a) record += f32(static_cast<float>(random.uniform()));
      }
      body[0] += record;
      body[1] += record + std::string(1, '\0');  // the extra list, empty
    }
    for (std::size_t f = 0; f < faces; ++f) {
      const int count = flaw == 4 && f == bad_face ? 5 : corners;
      std::string record(1, static_cast<char>(count));
      for (int c = 0; c < count; ++c) {
        const bool out_of_range = flaw == 3 && f == bad_face && c == 2;
        record += i32(out_of_range ? static_cast<std::int32_t>(vertices)
                                   : static_cast<std::int32_t>(random.below(static_cast<tear::index_t>(vertices))));
      }
      body[0] += record;
      body[1] += std::string(1, '\x07') + record;  // the flags, then the corners
    }
    const PlyOutcome fast = read_outcome(dir.file("fast" + std::to_string(round) + ".ply", header[0] + body[0]));
    const PlyOutcome slow = read_outcome(dir.file("slow" + std::to_string(round) + ".ply", header[1] + body[1]));
    CHECK(fast.error == slow.error);
    if (flaw == 2 || flaw == 3) CHECK(!fast.error.empty());
    if (flaw != 2 && flaw != 3) REQUIRE(fast.error.empty());  // a face of another size is read, value by value
    CHECK(fast.mesh.node_pos == slow.mesh.node_pos);
    CHECK(fast.mesh.face_nodes == slow.mesh.face_nodes);
    CHECK(fast.mesh.corner_uv == slow.mesh.corner_uv);
    CHECK(fast.mesh.corner_normal == slow.mesh.corner_normal);
    CHECK(fast.mesh.node_vel == slow.mesh.node_vel);
    CHECK(fast.mesh.node_origin_face == slow.mesh.node_origin_face);
    CHECK(fast.mesh.node_origin_bary == slow.mesh.node_origin_bary);
  }
}
