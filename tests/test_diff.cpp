// diff_meshes, find_frames and `tear diff`: golden-file comparison of meshes and frame sequences.
#include <algorithm>
#include <filesystem>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "catch.h"
#include "cli_support.h"
#include "tear/diff_meshes.h"
#include "tear/error.h"
#include "tear/find_frames.h"
#include "tear/write_mesh.h"

namespace {

using namespace tear;
using tear::test::quoted;
using tear::test::regular_sheet;
using tear::test::TempDir;
namespace fs = std::filesystem;

/// Rotates face `f`'s corners by one (nodes, UVs, normals together): the same face.
void rotate_face(Mesh& mesh, index_t f) {
  std::rotate(&mesh.face_nodes[3 * f], &mesh.face_nodes[3 * f + 1], &mesh.face_nodes[3 * f + 3]);
  std::rotate(&mesh.corner_uv[6 * f], &mesh.corner_uv[6 * f + 2], &mesh.corner_uv[6 * f + 6]);
  std::rotate(&mesh.corner_normal[9 * f], &mesh.corner_normal[9 * f + 3], &mesh.corner_normal[9 * f + 9]);
}

/// Swaps faces `f` and `g` with their corners: another face order, the same set of faces.
void swap_faces(Mesh& mesh, index_t f, index_t g) {
  std::swap_ranges(&mesh.face_nodes[3 * f], &mesh.face_nodes[3 * f + 3], &mesh.face_nodes[3 * g]);
  std::swap_ranges(&mesh.corner_uv[6 * f], &mesh.corner_uv[6 * f + 6], &mesh.corner_uv[6 * g]);
  std::swap_ranges(&mesh.corner_normal[9 * f], &mesh.corner_normal[9 * f + 9], &mesh.corner_normal[9 * g]);
}

}  // namespace

TEST_CASE("diff_meshes: a mesh equals itself", "[diff]") {
  const Mesh a = regular_sheet();
  const MeshDiff diff = diff_meshes(a, a);
  CHECK(diff.equal());
  CHECK(diff.first.kind == DiffKind::None);
  CHECK(diff.max_position == 0);
  CHECK(diff.max_uv == 0);
}

TEST_CASE("diff_meshes: positions within and beyond the tolerance", "[diff]") {
  const Mesh a = regular_sheet();
  Mesh b = a;
  b.node_pos[3 * 5 + 1] += 4e-6f;
  MeshDiff diff = diff_meshes(a, b);
  CHECK(diff.equal());
  CHECK(diff.max_position > 3e-6);
  CHECK(diff.max_position < 5e-6);

  b.node_pos[3 * 5 + 1] += 1e-4f;
  b.node_pos[3 * 9 + 0] += 1e-4f;
  diff = diff_meshes(a, b);
  REQUIRE_FALSE(diff.equal());
  INFO(diff.first.describe());
  CHECK(diff.first.kind == DiffKind::Position);
  CHECK(diff.first.element == 5);  // the lowest node that differs
  CHECK(diff.first.component == 1);
  CHECK(diff.first.by > 1e-4);
  CHECK(diff.first.describe().rfind("node 5 y position", 0) == 0);

  DiffOptions loose;
  loose.tolerance = 1e-3;
  CHECK(diff_meshes(a, b, loose).equal());
}

TEST_CASE("diff_meshes: rotated corners and another face order are the same faces", "[diff]") {
  const Mesh a = regular_sheet();
  Mesh b = a;
  rotate_face(b, 3);
  rotate_face(b, 7);
  rotate_face(b, 7);
  swap_faces(b, 0, 199);
  const MeshDiff diff = diff_meshes(a, b);
  INFO(diff.first.describe());
  CHECK(diff.equal());
}

TEST_CASE("diff_meshes: a flipped face differs", "[diff]") {
  const Mesh a = regular_sheet();
  Mesh b = a;
  std::swap(b.face_nodes[3 * 4 + 1], b.face_nodes[3 * 4 + 2]);
  const MeshDiff diff = diff_meshes(a, b);
  REQUIRE_FALSE(diff.equal());
  CHECK(diff.first.kind == DiffKind::Face);
  CHECK(diff.first.element == 4);
  CHECK_FALSE(diff.first.in_b);
}

TEST_CASE("diff_meshes: node and face counts", "[diff]") {
  const Mesh a = regular_sheet();
  Mesh b = a;
  b.node_pos.insert(b.node_pos.end(), {0.5f, 0.5f, 0.0f});
  MeshDiff diff = diff_meshes(a, b);
  REQUIRE_FALSE(diff.equal());
  CHECK(diff.first.kind == DiffKind::NodeCount);
  CHECK(diff.first.value_a == a.node_count());
  CHECK(diff.first.value_b == a.node_count() + 1);

  Mesh c = a;
  c.face_nodes.resize(c.face_nodes.size() - 3);
  c.corner_uv.resize(c.corner_uv.size() - 6);
  c.corner_normal.resize(c.corner_normal.size() - 9);
  diff = diff_meshes(a, c);
  CHECK(diff.first.kind == DiffKind::FaceCount);
  CHECK(diff.max_position == 0);  // the rest still compared
}

TEST_CASE("diff_meshes: UVs and normals within the UV tolerance", "[diff]") {
  const Mesh a = regular_sheet();
  Mesh b = a;
  b.corner_uv[6 * 2 + 2 * 1 + 0] += 1e-3f;  // face 2, corner 1, u
  MeshDiff diff = diff_meshes(a, b);
  REQUIRE_FALSE(diff.equal());
  CHECK(diff.first.kind == DiffKind::Uv);
  CHECK(diff.first.element == 2);
  CHECK(diff.first.corner == 1);
  CHECK(diff.first.component == 0);
  CHECK(diff.max_uv > 9e-4);
  CHECK(diff.max_position == 0);

  DiffOptions loose;
  loose.uv_tolerance = 1e-2;
  CHECK(diff_meshes(a, b, loose).equal());

  // Matched through the rotation: the differing corner keeps its number in a.
  rotate_face(b, 2);
  diff = diff_meshes(a, b);
  CHECK(diff.first.kind == DiffKind::Uv);
  CHECK(diff.first.corner == 1);

  Mesh no_uv = a;
  no_uv.corner_uv.clear();
  CHECK(diff_meshes(a, no_uv).first.kind == DiffKind::Uv);

  Mesh normal = a;
  normal.corner_normal[9 * 6 + 2] = 0.9f;
  diff = diff_meshes(a, normal);
  CHECK(diff.first.kind == DiffKind::Normal);
  CHECK(diff.first.element == 6);
}

TEST_CASE("diff_meshes: velocities only where both meshes carry them", "[diff]") {
  Mesh a = regular_sheet();
  Mesh b = a;
  b.node_vel.assign(b.node_pos.size(), 0.0f);
  b.node_vel[3 * 8 + 2] = 1.0f;
  CHECK(diff_meshes(a, b).equal());
  a.node_vel.assign(a.node_pos.size(), 0.0f);
  const MeshDiff diff = diff_meshes(a, b);
  CHECK(diff.first.kind == DiffKind::Velocity);
  CHECK(diff.first.element == 8);
  CHECK(diff.max_velocity == 1.0);
}

TEST_CASE("find_frames: the frames a pattern writes, padding included", "[diff]") {
  TempDir dir;
  for (const char* name : {"f.0001.ply", "f.0002.ply", "f.0010.ply", "f.1.ply", "f.0003.obj", "notes.txt"})
    dir.file(name, "x");
  fs::create_directories(dir / "f.0004.ply");  // a folder is not a frame
  CHECK(find_frames(FramePattern((dir / "f.####.ply").string())) == std::vector<int>{1, 2, 10});
  CHECK(find_frames(FramePattern((dir / "f.{frame}.ply").string())) == std::vector<int>{1});
  CHECK(find_frames(FramePattern((dir / "g.####.ply").string())).empty());
  CHECK_THROWS_AS(find_frames(FramePattern((dir / "f.ply").string())), Error);
}

TEST_CASE("tear diff: equal files, tolerances and exit codes 0 and 5", "[diff][cli]") {
  TempDir dir;
  const Mesh a = regular_sheet();
  Mesh b = a;
  b.node_pos[3 * 12 + 0] += 5e-5f;
  write_mesh(a, (dir / "a.ply").string());
  write_mesh(a, (dir / "same.ply").string());
  write_mesh(b, (dir / "b.ply").string());

  auto run = dir.tear("diff " + quoted(dir / "a.ply") + " " + quoted(dir / "same.ply"));
  CHECK(run.exit_code == 0);
  CHECK(run.out.empty());
  CHECK(run.err.empty());

  run = dir.tear("diff " + quoted(dir / "a.ply") + " " + quoted(dir / "b.ply"));
  CHECK(run.exit_code == 5);
  CHECK(std::count(run.out.begin(), run.out.end(), '\n') == 1);
  CHECK(run.out.find("node 12 x position") != std::string::npos);
  CHECK(run.err.empty());

  run = dir.tear("diff " + quoted(dir / "a.ply") + " " + quoted(dir / "b.ply") + " --tolerance 1e-4");
  CHECK(run.exit_code == 0);
  CHECK(run.out.empty());

  run = dir.tear("diff " + quoted(dir / "a.ply") + " " + quoted(dir / "b.ply") + " --tolerance nan");
  CHECK(run.exit_code == 1);
}

TEST_CASE("tear diff: one frame as PLY, OBJ and GLB compares equal", "[diff][cli]") {
  TempDir dir;
  const Mesh a = regular_sheet();
  for (const char* name : {"a.ply", "a.obj", "a.glb"}) write_mesh(a, (dir / name).string());
  for (const char* other : {"a.obj", "a.glb"}) {
    const auto run = dir.tear("diff " + quoted(dir / "a.ply") + " " + quoted(dir / other));
    INFO(other << ": " << run.out << run.err);
    CHECK(run.exit_code == 0);
    CHECK(run.out.empty());
  }
}

TEST_CASE("tear diff: frame sequences, a missing frame, JSON", "[diff][cli]") {
  TempDir dir;
  write_mesh(regular_sheet(), (dir / "sheet.obj").string());
  const std::string script = std::string(TEAR_SOURCE_DIR) + "/examples/scripts/plane.json";
  fs::create_directories(dir / "out");
  fs::create_directories(dir / "golden");
  for (const char* pattern : {"out/f.####.ply", "golden/f.####.glb"}) {
    const auto run = dir.tear("run " + quoted(dir / "sheet.obj") + " " + quoted(fs::path(script)) + " -o " +
                              quoted(dir / pattern) + " --progress none");
    REQUIRE(run.exit_code == 0);
  }
  const std::string out = quoted(dir / "out/f.####.ply"), golden = quoted(dir / "golden/f.####.glb");

  // The torn frame reads back torn from both (ids), so PLY and GLB agree.
  auto run = dir.tear("diff " + out + " " + golden);
  INFO(run.out << run.err);
  CHECK(run.exit_code == 0);
  CHECK(run.out.empty());

  run = dir.tear("diff " + out + " " + golden + " --json");
  CHECK(run.exit_code == 0);
  auto summary = nlohmann::json::parse(run.out);
  CHECK(summary["frames_compared"] == 2);
  CHECK(summary["frames_differing"] == 0);
  CHECK(summary["max_position_difference"] == 0.0);

  fs::remove(dir / "golden/f.0002.glb");
  run = dir.tear("diff " + out + " " + golden);
  CHECK(run.exit_code == 5);
  CHECK(run.out.rfind("frame 2: missing in b", 0) == 0);
  CHECK(std::count(run.out.begin(), run.out.end(), '\n') == 1);

  run = dir.tear("diff " + out + " " + golden + " --json");
  CHECK(run.exit_code == 5);
  summary = nlohmann::json::parse(run.out);
  for (const char* key : {"frames_compared", "frames_differing", "max_position_difference", "max_uv_difference",
                          "max_normal_difference", "max_velocity_difference", "differences"})
    CHECK(summary.contains(key));
  CHECK(summary["frames_compared"] == 1);
  CHECK(summary["frames_differing"] == 1);
  CHECK(summary["differences"][0]["frame"] == 2);
}

TEST_CASE("tear diff: bad input exits 2 with one line naming the file", "[diff][cli]") {
  TempDir dir;
  write_mesh(regular_sheet(), (dir / "a.ply").string());
  const fs::path garbage = dir.file("garbage.ply", "ply\nnonsense\n");
  for (const fs::path& bad : {dir / "missing.ply", garbage}) {
    const auto run = dir.tear("diff " + quoted(dir / "a.ply") + " " + quoted(bad));
    CHECK(run.exit_code == 2);
    CHECK(run.out.empty());
    CHECK(run.err.rfind("tear: " + bad.string() + ":", 0) == 0);
    CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
  }
  auto run = dir.tear("diff " + quoted(dir / "a.ply") + " " + quoted(dir / "nothing.####.ply"));
  CHECK(run.exit_code == 1);  // a file against a pattern
  run = dir.tear("diff " + quoted(dir / "x.####.ply") + " " + quoted(dir / "y.####.ply"));
  CHECK(run.exit_code == 2);  // no frame at all
  CHECK(run.err.find("x.####.ply") != std::string::npos);
}

TEST_CASE("tear diff: torn OBJ, PLY and GLB frames of one run compare equal, node for node", "[diff][cli]") {
  TempDir dir;
  write_mesh(regular_sheet(), (dir / "sheet.obj").string());
  const std::string script = std::string(TEAR_SOURCE_DIR) + "/examples/scripts/plane.json";
  for (const char* pattern : {"f.####.obj", "f.####.ply", "f.####.glb"}) {
    const auto run = dir.tear("run " + quoted(dir / "sheet.obj") + " " + quoted(fs::path(script)) + " -o " +
                              quoted(dir / pattern) + " --progress none");
    REQUIRE(run.exit_code == 0);
  }
  // The torn frame's OBJ is not welded: its two sides of the tear stay two nodes, as in the PLY.
  for (const char* pair : {"f.####.obj f.####.ply", "f.####.obj f.####.glb", "f.####.ply f.####.glb"}) {
    std::string a = pair, b = a.substr(a.find(' ') + 1);
    a.resize(a.find(' '));
    const auto run = dir.tear("diff " + quoted(dir / a) + " " + quoted(dir / b));
    INFO(pair << ": " << run.out << run.err);
    CHECK(run.exit_code == 0);
    CHECK(run.out.empty());
  }
}

TEST_CASE("tear diff: a node no face uses still counts", "[diff][cli]") {
  TempDir dir;
  const Mesh a = regular_sheet();
  Mesh b = a;
  b.node_pos.insert(b.node_pos.end(), {2.f, 2.f, 0.f});  // an extra node, used by no face
  for (const char* ext : {"obj", "ply", "glb"}) {
    write_mesh(a, (dir / ("a." + std::string(ext))).string());
    write_mesh(b, (dir / ("b." + std::string(ext))).string());
    const auto run = dir.tear("diff " + quoted(dir / ("a." + std::string(ext))) + " " +
                              quoted(dir / ("b." + std::string(ext))));
    INFO(ext << ": " << run.out << run.err);
    CHECK(run.exit_code == 5);
    CHECK(run.out.find("node count 121 vs 122") != std::string::npos);
  }
}
