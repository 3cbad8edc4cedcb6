// PLY and glTF written so that vertex i is node i, with ids, velocities, origins and torn edges.
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "catch.h"
#include "io_support.h"
#include "tear/read_mesh.h"
#include "tear/write_mesh.h"

namespace {

using tear::test::blender_obj;
using tear::test::IoDir;

/// The number after `element vertex` in a PLY header.
long ply_vertex_count(const std::string& bytes) {
  const std::size_t at = bytes.find("element vertex ");
  REQUIRE(at != std::string::npos);
  return std::stol(bytes.substr(at + 15));
}

/// The vertex count of a glTF document's first primitive (its POSITION accessor).
long gltf_vertex_count(const std::string& text) {
  const nlohmann::json gltf = nlohmann::json::parse(text);
  const int position = gltf["meshes"][0]["primitives"][0]["attributes"]["POSITION"];
  return gltf["accessors"][position]["count"];
}

}  // namespace

TEST_CASE("write_mesh: signed zeros split no node, and PLY and glTF keep node i at vertex i", "[io]") {
  IoDir dir;
  const tear::Mesh mesh = tear::read_mesh(dir.file("cloth.obj", blender_obj));
  for (const char* format : {"ply", "glb", "gltf", "obj"}) {
    INFO("format " << format);
    const std::string path = dir / (std::string("frame.") + format);
    tear::write_mesh(mesh, path);
    const std::string bytes = tear::test::file_bytes(path);
    // -0 and +0 normals are one value: one vertex per node, no phantom seam.
    if (std::string(format) == "ply") CHECK(ply_vertex_count(bytes) == mesh.node_count());
    if (std::string(format) == "gltf") CHECK(gltf_vertex_count(bytes) == mesh.node_count());
    for (bool weld : {true, false}) {
      tear::ReadOptions options;
      options.weld = weld;
      const tear::Mesh back = tear::read_mesh(path, options);
      INFO((weld ? "welded" : "not welded"));
      CHECK(back.node_pos == mesh.node_pos);
      CHECK(back.face_nodes == mesh.face_nodes);
      CHECK(tear::test::count_pieces(back) == 1);
    }
  }
}

TEST_CASE("write_mesh: a UV seam splits vertices after the nodes, in corner order", "[io]") {
  IoDir dir;
  // Two triangles sharing the edge 1-2 with different UVs on each side, and a node no face uses.
  tear::Mesh mesh;
  mesh.node_pos = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 5, 5, 5};
  mesh.face_nodes = {0, 1, 2, 1, 3, 2};
  mesh.corner_uv = {0, 0, 1, 0, 0, 1, 0.5f, 0, 1, 1, 0, 1};
  mesh.corner_normal = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, -0.0f, 0, 1};  // -0 == +0 at node 2
  tear::write_mesh(mesh, dir / "seam.gltf");
  const nlohmann::json gltf = nlohmann::json::parse(tear::test::file_bytes(dir / "seam.gltf"));
  // Nodes 0..4, then node 1 again with u = 0.5 (corner 3); corner 5's (0, 1) at node 2 is its first.
  CHECK(gltf["accessors"][0]["count"] == 6);
  const tear::Mesh back = tear::read_mesh(dir / "seam.gltf");
  CHECK(back.node_count() == 4);  // node 4 is used by no face: dropped
  CHECK(back.face_nodes == mesh.face_nodes);
  CHECK(back.corner_uv[6] == Approx(0.5f));

  tear::ReadOptions unwelded;
  unwelded.weld = false;
  const tear::Mesh split = tear::read_mesh(dir / "seam.gltf", unwelded);
  CHECK(split.node_count() == 5);  // the seam's extra vertex is a node of its own, after the others
  CHECK(split.face_nodes == std::vector<tear::index_t>{0, 1, 2, 4, 3, 2});
}

TEST_CASE("write_mesh: PLY round trip keeps ids, velocities, origins and torn edges", "[io][ply]") {
  IoDir dir;
  const tear::Mesh mesh = tear::test::two_pieces();
  tear::write_mesh(mesh, dir / "pieces.ply");
  const tear::Mesh back = tear::read_mesh(dir / "pieces.ply");
  CHECK(back.node_pos == mesh.node_pos);
  CHECK(back.face_nodes == mesh.face_nodes);
  CHECK(back.corner_uv == mesh.corner_uv);
  CHECK(back.corner_normal == mesh.corner_normal);
  CHECK(back.node_vel == mesh.node_vel);
  CHECK(back.node_origin_face == mesh.node_origin_face);
  CHECK(back.node_origin_bary == mesh.node_origin_bary);
  CHECK(back.torn_edge_nodes == mesh.torn_edge_nodes);
  CHECK(tear::test::count_pieces(back) == 2);

  // Without identity arrays: zero velocities and unknown (-1) origins are written, and unknown
  // origins read back as none.
  tear::Mesh plain = mesh;
  plain.node_vel.clear();
  plain.node_origin_face.clear();
  plain.node_origin_bary.clear();
  plain.torn_edge_nodes.clear();
  tear::write_mesh(plain, dir / "plain.ply");
  const std::string bytes = tear::test::file_bytes(dir / "plain.ply");
  CHECK(bytes.find("element edge") == std::string::npos);
  const tear::Mesh plain_back = tear::read_mesh(dir / "plain.ply");
  CHECK(plain_back.node_vel == std::vector<float>(18, 0.0f));
  CHECK_FALSE(plain_back.has_origins());
  CHECK(plain_back.torn_edge_nodes.empty());
}
