// A frame tear wrote reads back with its identity: node order, pieces, velocities (docs/io.md).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "catch.h"
#include "io_support.h"
#include "tear/error.h"
#include "tear/read_mesh.h"
#include "tear/write_mesh.h"

using tear::test::IoDir;

TEST_CASE("read_mesh: a two-piece mesh reads back in two pieces from PLY and glTF, by id", "[io]") {
  IoDir dir;
  const tear::Mesh mesh = tear::test::two_pieces();
  for (const char* format : {"ply", "glb", "gltf"}) {
    INFO("format " << format);
    const std::string path = dir / (std::string("pieces.") + format);
    tear::write_mesh(mesh, path);
    const tear::Mesh back = tear::read_mesh(path);
    CHECK(back.node_count() == 6);
    CHECK(back.node_pos == mesh.node_pos);
    CHECK(back.face_nodes == mesh.face_nodes);
    CHECK(tear::test::count_pieces(back) == 2);
    CHECK(back.node_vel == mesh.node_vel);
    // A tolerance that would weld the copies is not used for a file with ids.
    tear::ReadOptions loose;
    loose.weld_tolerance = 0.5;
    CHECK(tear::test::count_pieces(tear::read_mesh(path, loose)) == 2);
  }
}

TEST_CASE("read_mesh: a two-piece OBJ welds by position, and stays in pieces without welding", "[io]") {
  IoDir dir;
  const tear::Mesh mesh = tear::test::two_pieces();
  const std::string path = dir / "pieces.obj";
  tear::write_mesh(mesh, path);
  // OBJ carries no ids: welding closes the cut, as for any exporter's copies at a seam.
  const tear::Mesh welded = tear::read_mesh(path);
  CHECK(welded.node_count() == 4);
  CHECK(tear::test::count_pieces(welded) == 1);
  CHECK(welded.face_nodes == std::vector<tear::index_t>{0, 1, 2, 1, 3, 2});

  tear::ReadOptions options;
  options.weld = false;
  const tear::Mesh torn = tear::read_mesh(path, options);
  CHECK(torn.node_pos == mesh.node_pos);
  CHECK(torn.face_nodes == mesh.face_nodes);
  CHECK(tear::test::count_pieces(torn) == 2);
  CHECK(torn.corner_uv == mesh.corner_uv);
}

TEST_CASE("read_mesh: a glTF with _ID welds by id, one without by position", "[io]") {
  IoDir dir;
  const tear::Mesh mesh = tear::test::two_pieces();
  tear::write_mesh(mesh, dir / "pieces.gltf");
  nlohmann::json gltf = nlohmann::json::parse(tear::test::file_bytes(dir / "pieces.gltf"));
  auto& attributes = gltf["meshes"][0]["primitives"][0]["attributes"];
  REQUIRE(attributes.contains("_ID"));
  REQUIRE(attributes.contains("_VELOCITY"));
  CHECK(gltf["accessors"][attributes["_ID"].get<int>()]["componentType"] == 5126);
  CHECK(gltf["accessors"][attributes["_ID"].get<int>()]["type"] == "SCALAR");
  CHECK(gltf["accessors"][attributes["_VELOCITY"].get<int>()]["type"] == "VEC3");

  // Ids 5, 4, ..., 0: node i is id i, so the nodes come back in reverse.
  nlohmann::json reversed = gltf;
  std::string ids;
  for (int v = 5; v >= 0; --v) ids += tear::test::le_bytes(static_cast<float>(v));
  const int count = reversed["buffers"].size();
  reversed["buffers"].push_back(
      {{"byteLength", ids.size()}, {"uri", "data:application/octet-stream;base64," + tear::test::base64(ids)}});
  reversed["bufferViews"].push_back({{"buffer", count}, {"byteLength", ids.size()}});
  reversed["accessors"].push_back(
      {{"bufferView", reversed["bufferViews"].size() - 1}, {"componentType", 5126}, {"count", 6}, {"type", "SCALAR"}});
  reversed["meshes"][0]["primitives"][0]["attributes"]["_ID"] = reversed["accessors"].size() - 1;
  const tear::Mesh back = tear::read_mesh(dir.file("reversed.gltf", reversed.dump()));
  CHECK(back.face_nodes == std::vector<tear::index_t>{5, 4, 3, 2, 0, 1});
  CHECK(back.node_pos[0] == 1.0f);  // node 0 is vertex 5, at (1, 1, 0)
  CHECK(tear::test::count_pieces(back) == 2);

  // Without _ID, as another exporter writes it: welded by position.
  attributes.erase("_ID");
  const tear::Mesh foreign = tear::read_mesh(dir.file("foreign.gltf", gltf.dump()));
  CHECK(foreign.node_count() == 4);
  CHECK(tear::test::count_pieces(foreign) == 1);
  CHECK(foreign.node_vel.size() == 12);
}

TEST_CASE("read_mesh: every frame of a run reads back with the nodes and pieces written", "[io]") {
  IoDir dir;
  tear::Mesh mesh = tear::test::two_pieces();
  // A third piece on top, sharing one corner's position with the first: still apart by id.
  mesh.node_pos.insert(mesh.node_pos.end(), {0, 0, 0, -1, 0, 0, 0, -1, 0});
  mesh.face_nodes.insert(mesh.face_nodes.end(), {6, 8, 7});
  mesh.corner_uv.insert(mesh.corner_uv.end(), 6, 0.0f);
  mesh.corner_normal.insert(mesh.corner_normal.end(), {0, 0, 1, 0, 0, 1, 0, 0, 1});
  mesh.node_vel.insert(mesh.node_vel.end(), 9, 0.0f);
  mesh.node_origin_face.insert(mesh.node_origin_face.end(), {2, 2, 2});
  mesh.node_origin_bary.insert(mesh.node_origin_bary.end(), {0, 0, 1, 0, 0, 1});
  for (const char* format : {"ply", "glb"}) {
    INFO("format " << format);
    const std::string path = dir / (std::string("frame.") + format);
    tear::write_mesh(mesh, path);
    const tear::Mesh back = tear::read_mesh(path);
    CHECK(back.node_pos == mesh.node_pos);
    CHECK(back.face_nodes == mesh.face_nodes);
    CHECK(tear::test::count_pieces(back) == 3);
  }
}
