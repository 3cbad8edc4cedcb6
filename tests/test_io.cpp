#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "catch.h"
#include "tear/error.h"
#include "tear/read_mesh.h"
#include "tear/topology.h"
#include "tear/write_mesh.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace {

/// A fresh directory, removed with everything in it at the end of the test.
struct TempDir {
  fs::path path;
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "tear_test_io.XXXXXX").string();
    REQUIRE(mkdtemp(pattern.data()) != nullptr);
    path = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

/// A wavy sheet of `nx` by `ny` quads with shared nodes. Heights span magnitudes from 1e-7 to 1
/// so that float printing is exercised. With attributes: UVs with a seam down the middle column
/// (the right half is shifted by 0.5 in u) and flat per-face normals (a crease at every node).
tear::Mesh sheet(int nx, int ny, bool with_attributes, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(1.0f, 10.0f);
  tear::Mesh mesh;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      const float height = (rng() % 2 ? 1.0f : -1.0f) * unit(rng) * std::pow(10.0f, -static_cast<float>(rng() % 8));
      mesh.node_pos.insert(mesh.node_pos.end(), {0.137f * i + 0.001f * unit(rng), 0.093f * j - 0.3f, height});
    }
  }
  auto node = [&](int i, int j) { return static_cast<tear::index_t>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int quad[2][3][2] = {{{i, j}, {i + 1, j}, {i + 1, j + 1}}, {{i, j}, {i + 1, j + 1}, {i, j + 1}}};
      for (const auto& face : quad) {
        for (const auto& corner : face) mesh.face_nodes.push_back(node(corner[0], corner[1]));
        if (!with_attributes) continue;
        const float* p[3];
        for (int k = 0; k < 3; ++k) p[k] = &mesh.node_pos[3 * node(face[k][0], face[k][1])];
        const float e1[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
        const float e2[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
        float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        const float length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (float& x : n) x /= length;
        for (const auto& corner : face) {
          const float u = static_cast<float>(corner[0]) / nx + (i >= nx / 2 ? 0.5f : 0.0f);
          mesh.corner_uv.insert(mesh.corner_uv.end(), {u, static_cast<float>(corner[1]) / ny});
          mesh.corner_normal.insert(mesh.corner_normal.end(), n, n + 3);
        }
      }
    }
  }
  return mesh;
}

/// Checks that `read` is `written` up to a renumbering of nodes: same counts, same position at
/// every face corner (exact), the same corners share a node, and the same corner attributes.
void check_same_mesh(const tear::Mesh& written, const tear::Mesh& read, float attribute_tolerance) {
  REQUIRE(read.face_count() == written.face_count());
  CHECK(read.node_count() == written.node_count());
  std::map<tear::index_t, tear::index_t> written_to_read;
  std::set<tear::index_t> read_used;
  int position_mismatches = 0, renumbering_mismatches = 0;
  for (std::size_t c = 0; c < written.face_nodes.size(); ++c) {
    const tear::index_t a = written.face_nodes[c], b = read.face_nodes[c];
    for (int k = 0; k < 3; ++k) position_mismatches += written.node_pos[3 * a + k] != read.node_pos[3 * b + k];
    auto inserted = written_to_read.emplace(a, b);
    if (inserted.second) {
      renumbering_mismatches += !read_used.insert(b).second;
    } else {
      renumbering_mismatches += inserted.first->second != b;
    }
  }
  CHECK(position_mismatches == 0);
  CHECK(renumbering_mismatches == 0);

  REQUIRE(read.has_uv() == written.has_uv());
  REQUIRE(read.has_normals() == written.has_normals());
  float uv_error = 0.0f, normal_error = 0.0f;
  for (std::size_t i = 0; i < written.corner_uv.size(); ++i) {
    uv_error = std::max(uv_error, std::fabs(written.corner_uv[i] - read.corner_uv[i]));
  }
  for (std::size_t i = 0; i < written.corner_normal.size(); ++i) {
    normal_error = std::max(normal_error, std::fabs(written.corner_normal[i] - read.corner_normal[i]));
  }
  CHECK(uv_error <= attribute_tolerance);
  CHECK(normal_error <= attribute_tolerance);
}

/// Connected components of the face graph and closed loops of boundary edges.
struct BoundaryCount {
  tear::index_t boundary_edges = 0;
  int boundary_loops = 0;
  int components = 0;
};

tear::index_t find_root(std::vector<tear::index_t>& parent, tear::index_t a) {
  while (parent[a] != a) a = parent[a] = parent[parent[a]];
  return a;
}

int count_roots(std::vector<tear::index_t>& parent, const std::vector<std::uint8_t>& member) {
  int count = 0;
  for (std::size_t a = 0; a < parent.size(); ++a) {
    count += member[a] && find_root(parent, static_cast<tear::index_t>(a)) == static_cast<tear::index_t>(a);
  }
  return count;
}

BoundaryCount count_boundary(const tear::Mesh& mesh) {
  const tear::Topology topology = tear::build_topology(mesh, tear::test::test_device());
  std::vector<tear::index_t> face_parent(mesh.face_count()), node_parent(mesh.node_count());
  std::iota(face_parent.begin(), face_parent.end(), 0);
  std::iota(node_parent.begin(), node_parent.end(), 0);
  BoundaryCount count;
  std::vector<std::uint8_t> node_on_boundary(mesh.node_count(), 0);
  for (tear::index_t e = 0; e < topology.edge_count; ++e) {
    const tear::index_t f0 = topology.edge_faces[2 * e], f1 = topology.edge_faces[2 * e + 1];
    if (f1 != tear::none) face_parent[find_root(face_parent, f0)] = find_root(face_parent, f1);
    if (!topology.edge_boundary[e]) continue;
    ++count.boundary_edges;
    const tear::index_t a = topology.edge_nodes[2 * e], b = topology.edge_nodes[2 * e + 1];
    node_on_boundary[a] = node_on_boundary[b] = 1;
    node_parent[find_root(node_parent, a)] = find_root(node_parent, b);
  }
  count.components = count_roots(face_parent, std::vector<std::uint8_t>(mesh.face_count(), 1));
  count.boundary_loops = count_roots(node_parent, node_on_boundary);
  return count;
}

const char* const formats[] = {"obj", "ply", "gltf", "glb"};

}  // namespace

TEST_CASE("write_mesh: each format reads back to the same mesh", "[io]") {
  TempDir dir;
  for (const char* format : formats) {
    for (bool with_attributes : {true, false}) {
      INFO("format " << format << (with_attributes ? " with" : " without") << " UVs and normals");
      const tear::Mesh mesh = sheet(7, 5, with_attributes, 11);
      const std::string path = dir / (std::string("sheet.") + format);
      tear::write_mesh(mesh, path);
      const tear::Mesh read = tear::read_mesh(path);
      // glTF stores 1 - v; the reader flips it back, which may round.
      check_same_mesh(mesh, read, std::string(format).rfind("gl", 0) == 0 ? 1e-6f : 0.0f);
    }
  }
}

TEST_CASE("write_mesh: UVs without normals and normals without UVs read back", "[io]") {
  TempDir dir;
  for (const char* format : formats) {
    for (bool keep_uv : {true, false}) {
      INFO("format " << format << (keep_uv ? " UVs only" : " normals only"));
      tear::Mesh mesh = sheet(4, 3, true, 5);
      (keep_uv ? mesh.corner_normal : mesh.corner_uv).clear();
      const std::string path = dir / (std::string("part.") + format);
      tear::write_mesh(mesh, path);
      check_same_mesh(mesh, tear::read_mesh(path), 1e-6f);
    }
  }
}

TEST_CASE("write_mesh: the same mesh gives the same bytes", "[io]") {
  TempDir dir;
  const tear::Mesh mesh = sheet(6, 6, true, 3);
  for (const char* format : formats) {
    INFO("format " << format);
    const std::string first = dir / (std::string("a.") + format), second = dir / (std::string("b.") + format);
    tear::write_mesh(mesh, first);
    tear::write_mesh(mesh, second);
    const std::string bytes = read_bytes(first);
    CHECK(!bytes.empty());
    CHECK(bytes == read_bytes(second));
    // Writing over an existing file replaces it.
    tear::write_mesh(sheet(2, 2, false, 4), first);
    CHECK(read_bytes(first) != bytes);
  }
  std::vector<std::string> leftovers;
  for (const auto& entry : fs::directory_iterator(dir.path)) {
    if (entry.path().filename().string().find(".tmp.") != std::string::npos) leftovers.push_back(entry.path());
  }
  CHECK(leftovers.empty());
}

TEST_CASE("write_mesh: OBJ text has per-corner indices and deduplicated attributes", "[io]") {
  TempDir dir;
  tear::Mesh mesh;
  mesh.node_pos = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  mesh.face_nodes = {0, 1, 2, 1, 3, 2};
  mesh.corner_uv = {0, 0, 0.5f, 0, 0, 1, 0.75f, 0, 1, 1, 0, 1};
  mesh.corner_normal = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  const std::string path = dir / "quad.obj";
  tear::write_mesh(mesh, path);
  CHECK(read_bytes(path) ==
        "# tear\n"
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
        "vt 0 0\nvt 0.5 0\nvt 0 1\nvt 0.75 0\nvt 1 1\n"
        "vn 0 0 1\n"
        "f 1/1/1 2/2/1 3/3/1\nf 2/4/1 4/5/1 3/3/1\n");
}

TEST_CASE("write_mesh: glTF and GLB follow the container layout", "[io]") {
  TempDir dir;
  const tear::Mesh mesh = sheet(3, 2, true, 9);
  tear::write_mesh(mesh, dir / "m.gltf");
  const nlohmann::json gltf = nlohmann::json::parse(read_bytes(dir / "m.gltf"));
  CHECK(gltf["asset"]["version"] == "2.0");
  CHECK(gltf["buffers"][0]["uri"].get<std::string>().rfind("data:application/octet-stream;base64,", 0) == 0);
  const auto& primitive = gltf["meshes"][0]["primitives"][0];
  const auto& position = gltf["accessors"][primitive["attributes"]["POSITION"].get<int>()];
  CHECK(position.contains("min"));
  CHECK(position.contains("max"));
  for (int k = 0; k < 3; ++k) {
    float low = mesh.node_pos[k], high = mesh.node_pos[k];
    for (tear::index_t node = 0; node < mesh.node_count(); ++node) {
      low = std::min(low, mesh.node_pos[3 * node + k]);
      high = std::max(high, mesh.node_pos[3 * node + k]);
    }
    CHECK(static_cast<float>(position["min"][k].get<double>()) == low);
    CHECK(static_cast<float>(position["max"][k].get<double>()) == high);
  }
  CHECK(gltf["accessors"][primitive["indices"].get<int>()]["componentType"] == 5125);
  CHECK(primitive["attributes"].contains("NORMAL"));
  CHECK(primitive["attributes"].contains("TEXCOORD_0"));

  tear::write_mesh(mesh, dir / "m.glb");
  const std::string glb = read_bytes(dir / "m.glb");
  REQUIRE(glb.size() > 20);
  CHECK(glb.substr(0, 4) == "glTF");
  std::uint32_t header[3];
  std::memcpy(header, glb.data(), sizeof header);
  CHECK(header[1] == 2u);
  CHECK(header[2] == glb.size());
  CHECK(glb.size() % 4 == 0);
}

TEST_CASE("read_mesh: quads with UV seams in two objects", "[io]") {
  TempDir dir;
  const std::string path = dir / "quads.obj";
  // Two quads side by side share the edge v2-v3 but not its UVs (a seam); a triangle apart.
  write_bytes(path,
              "o left\n"
              "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
              "vt 0 0\nvt 0.5 0\nvt 0.5 1\nvt 0 1\nvt 0.6 0\nvt 1 0\nvt 1 1\nvt 0.6 1\n"
              "f 1/1 2/2 3/3 4/4\n"
              "f 2/5 5/6 6/7 3/8\n"
              "o right\n"
              "v 0 0 5\nv 1 0 5\nv 1 1 5\n"
              "f 7/1 8/2 9/3\n");
  const tear::Mesh mesh = tear::read_mesh(path);
  CHECK(mesh.face_count() == 5);
  CHECK(mesh.node_count() == 9);
  REQUIRE(mesh.has_uv());
  CHECK_FALSE(mesh.has_normals());

  // Each corner's UV is the vt its quad gave to that position: left quad u = x/2, right quad 0.6 + 0.4 (x-1).
  for (tear::index_t face = 0; face < mesh.face_count(); ++face) {
    float centroid_x = 0.0f;
    for (int k = 0; k < 3; ++k) centroid_x += mesh.node_pos[3 * mesh.face_nodes[3 * face + k]] / 3.0f;
    for (int k = 0; k < 3; ++k) {
      const float* p = &mesh.node_pos[3 * mesh.face_nodes[3 * face + k]];
      const float* uv = &mesh.corner_uv[2 * (3 * face + k)];
      INFO("face " << face << " corner " << k << " at " << p[0] << " " << p[1] << " " << p[2]);
      if (p[2] == 5.0f || centroid_x < 1.0f) {
        CHECK(uv[0] == Approx(p[0] / 2));
      } else {
        CHECK(uv[0] == Approx(0.6f + 0.4f * (p[0] - 1)));
      }
      CHECK(uv[1] == Approx(p[1]));
    }
    // Counter-clockwise seen from +z, as written.
    const float* a = &mesh.node_pos[3 * mesh.face_nodes[3 * face]];
    const float* b = &mesh.node_pos[3 * mesh.face_nodes[3 * face + 1]];
    const float* c = &mesh.node_pos[3 * mesh.face_nodes[3 * face + 2]];
    CHECK((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0.0f);
  }

  // The seam does not split the topology: one 2x1 rectangle and one triangle.
  const BoundaryCount count = count_boundary(mesh);
  CHECK(count.components == 2);
  CHECK(count.boundary_edges == 6 + 3);
  CHECK(count.boundary_loops == 2);
}

TEST_CASE("read_mesh: --mesh-name picks one object, an unknown name lists them", "[io]") {
  TempDir dir;
  const std::string path = dir / "two.obj";
  write_bytes(path,
              "o first\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"
              "o second\nv 0 0 1\nv 1 0 1\nv 1 1 1\nf 5 6 7\nl 5 6\n");
  CHECK(tear::read_mesh(path).face_count() == 3);

  tear::ReadOptions options;
  options.mesh_name = "first";
  const tear::Mesh first = tear::read_mesh(path, options);
  CHECK(first.face_count() == 2);
  CHECK(first.node_count() == 4);
  options.mesh_name = "second";
  const tear::Mesh second = tear::read_mesh(path, options);
  CHECK(second.face_count() == 1);
  CHECK(second.node_count() == 3);
  CHECK(second.node_pos[2] == 1.0f);

  options.mesh_name = "third";
  try {
    tear::read_mesh(path, options);
    FAIL("no error");
  } catch (const tear::Error& e) {
    const std::string message = e.what();
    CHECK(e.kind() == tear::ErrorKind::input);
    CHECK(message.find(path) != std::string::npos);
    CHECK(message.find("third") != std::string::npos);
    CHECK(message.find("'first'") != std::string::npos);
    CHECK(message.find("'second'") != std::string::npos);
    CHECK(message.find('\n') == std::string::npos);
  }
}

TEST_CASE("read_mesh: a tube with a duplicated seam column is one component with two boundary loops", "[io]") {
  TempDir dir;
  const int ring = 12, rows = 5;
  // As exporters write it: the seam column appears twice, with u = 0 and u = 1.
  tear::Mesh tube;
  for (int j = 0; j <= rows; ++j) {
    for (int i = 0; i <= ring; ++i) {
      const float angle = 2.0f * static_cast<float>(M_PI) * static_cast<float>(i % ring) / ring;
      tube.node_pos.insert(tube.node_pos.end(), {std::cos(angle), std::sin(angle), 0.25f * j});
    }
  }
  auto node = [&](int i, int j) { return static_cast<tear::index_t>(j * (ring + 1) + i); };
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < ring; ++i) {
      const int quad[2][3][2] = {{{i, j}, {i + 1, j}, {i + 1, j + 1}}, {{i, j}, {i + 1, j + 1}, {i, j + 1}}};
      for (const auto& face : quad) {
        for (const auto& corner : face) {
          const tear::index_t n = node(corner[0], corner[1]);
          tube.face_nodes.push_back(n);
          tube.corner_uv.insert(tube.corner_uv.end(),
                                {static_cast<float>(corner[0]) / ring, static_cast<float>(corner[1]) / rows});
          tube.corner_normal.insert(tube.corner_normal.end(), {tube.node_pos[3 * n], tube.node_pos[3 * n + 1], 0.0f});
        }
      }
    }
  }
  const std::string path = dir / "tube.gltf";
  tear::write_mesh(tube, path);
  nlohmann::json gltf = nlohmann::json::parse(read_bytes(path));
  REQUIRE(gltf["accessors"][0]["count"] == (ring + 1) * (rows + 1));
  // Without tear's node ids, as another exporter writes it (with them the seam would stay open).
  gltf["meshes"][0]["primitives"][0]["attributes"].erase("_ID");
  write_bytes(path, gltf.dump());

  const tear::Mesh mesh = tear::read_mesh(path);
  CHECK(mesh.node_count() == ring * (rows + 1));
  CHECK(mesh.face_count() == 2 * ring * rows);
  const BoundaryCount count = count_boundary(mesh);
  CHECK(count.components == 1);
  CHECK(count.boundary_edges == 2 * ring);
  CHECK(count.boundary_loops == 2);
  // The seam survives in the UVs: corners of the last column still have u = 1.
  CHECK(std::count(mesh.corner_uv.begin(), mesh.corner_uv.end(), 1.0f) > 0);
}

TEST_CASE("read_mesh: instances are placed by their node transforms", "[io]") {
  TempDir dir;
  const tear::Mesh mesh = sheet(2, 2, true, 21);
  const std::string plain = dir / "plain.gltf";
  tear::write_mesh(mesh, plain);
  nlohmann::json gltf = nlohmann::json::parse(read_bytes(plain));
  // The same mesh twice more: moved along x, and mirrored in x.
  gltf["nodes"].push_back({{"mesh", 0}, {"name", "moved"}, {"translation", {5, 0, 0}}});
  gltf["nodes"].push_back({{"mesh", 0}, {"name", "mirrored"}, {"translation", {-5, 0, 0}}, {"scale", {-1, 1, 1}}});
  gltf["scenes"][0]["nodes"] = {0, 1, 2};
  const std::string path = dir / "instances.gltf";
  write_bytes(path, gltf.dump());

  const tear::Mesh all = tear::read_mesh(path);
  CHECK(all.face_count() == 3 * mesh.face_count());
  CHECK(all.node_count() == 3 * mesh.node_count());

  tear::ReadOptions options;
  options.mesh_name = "mirrored";
  const tear::Mesh mirrored = tear::read_mesh(path, options);
  REQUIRE(mirrored.face_count() == mesh.face_count());
  for (std::size_t c = 0; c < mesh.face_nodes.size(); ++c) {
    INFO("corner " << c);
    // Mirroring swaps two corners of each face to keep it counter-clockwise.
    const std::size_t face = c / 3, k = c % 3, source = 3 * face + (k == 0 ? 0 : 3 - k);
    const float* p = &mesh.node_pos[3 * mesh.face_nodes[source]];
    const float* q = &mirrored.node_pos[3 * mirrored.face_nodes[c]];
    CHECK(q[0] == Approx(-5.0f - p[0]));
    CHECK(q[1] == p[1]);
    CHECK(q[2] == p[2]);
    const float* n = &mesh.corner_normal[3 * source];
    const float* m = &mirrored.corner_normal[3 * c];
    CHECK(m[0] == Approx(-n[0]).margin(1e-6));
    CHECK(m[1] == Approx(n[1]).margin(1e-6));
    CHECK(m[2] == Approx(n[2]).margin(1e-6));
  }
  // Faces still agree with their normals after mirroring.
  for (tear::index_t face = 0; face < mirrored.face_count(); ++face) {
    const float* a = &mirrored.node_pos[3 * mirrored.face_nodes[3 * face]];
    const float* b = &mirrored.node_pos[3 * mirrored.face_nodes[3 * face + 1]];
    const float* c = &mirrored.node_pos[3 * mirrored.face_nodes[3 * face + 2]];
    const float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const float cross[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                            e1[0] * e2[1] - e1[1] * e2[0]};
    const float* n = &mirrored.corner_normal[9 * face];
    CHECK(cross[0] * n[0] + cross[1] * n[1] + cross[2] * n[2] > 0.0f);
  }
}

TEST_CASE("read_mesh: missing, garbage and empty files are input errors naming the file", "[io]") {
  TempDir dir;
  auto expect_input_error = [](const std::string& path) {
    try {
      tear::read_mesh(path);
      FAIL("no error for " << path);
    } catch (const tear::Error& e) {
      const std::string message = e.what();
      INFO(message);
      CHECK(e.kind() == tear::ErrorKind::input);
      CHECK(message.find(path) != std::string::npos);
      CHECK(message.find('\n') == std::string::npos);
    }
  };
  expect_input_error(dir / "missing.obj");
  expect_input_error(dir.path.string());

  const auto seed = tear::test::test_seed(77);
  INFO("seed " << seed);
  std::mt19937 rng(static_cast<unsigned>(seed));
  for (int round = 0; round < 5; ++round) {
    std::string garbage(4096, '\0');
    for (char& byte : garbage) byte = static_cast<char>(rng() & 0xFF);
    write_bytes(dir / "garbage.obj", garbage);
    expect_input_error(dir / "garbage.obj");
  }
  write_bytes(dir / "lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n");
  expect_input_error(dir / "lines.obj");
  write_bytes(dir / "broken.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [");
  expect_input_error(dir / "broken.gltf");
}

TEST_CASE("write_mesh: an unwritable path is a runtime error and leaves no temporary file", "[io]") {
  TempDir dir;
  const tear::Mesh mesh = sheet(2, 2, true, 1);
  for (const char* format : formats) {
    INFO("format " << format);
    const std::string path = dir / (std::string("missing/out.") + format);
    try {
      tear::write_mesh(mesh, path);
      FAIL("no error");
    } catch (const tear::Error& e) {
      const std::string message = e.what();
      CHECK(e.kind() == tear::ErrorKind::runtime);
      CHECK(message.find(path) != std::string::npos);
      CHECK(message.find("cannot write") != std::string::npos);
    }
  }
  // A directory in the way: the temporary file is written, the rename fails, the file is removed.
  fs::create_directory(dir / "taken.obj");
  CHECK_THROWS_AS(tear::write_mesh(mesh, dir / "taken.obj"), tear::Error);
  CHECK_THROWS_AS(tear::write_file_atomically(dir / "taken.obj", "text"), tear::Error);
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir.path)) names.push_back(entry.path().filename().string());
  CHECK(names == std::vector<std::string>{"taken.obj"});
}

TEST_CASE("format_from_path: extension decides, case-insensitively", "[io]") {
  CHECK(tear::format_from_path("a/b.obj") == tear::MeshFormat::obj);
  CHECK(tear::format_from_path("frame.0001.PLY") == tear::MeshFormat::ply);
  CHECK(tear::format_from_path("x.GlTf") == tear::MeshFormat::gltf);
  CHECK(tear::format_from_path("x.glb") == tear::MeshFormat::glb);
  for (const char* path : {"mesh.stl", "mesh", "dir.obj/mesh"}) {
    try {
      tear::format_from_path(path);
      FAIL("no error for " << path);
    } catch (const tear::Error& e) {
      const std::string message = e.what();
      CHECK(e.kind() == tear::ErrorKind::usage);
      CHECK(message.find(path) != std::string::npos);
      CHECK(message.find(".obj, .ply, .gltf, .glb") != std::string::npos);
    }
  }
}
