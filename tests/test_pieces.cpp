// Piece ids per face (docs/identity.md, *Pieces*): numbered by lowest face at the start, the
// larger part of a split keeping its id, carried through checkpoints, written by PLY, GLB and USD.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <array>
#include <cmath>
#include <map>
#include <sstream>
#include <numeric>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "catch.h"
#include "cli_support.h"
#include "cloth/face_pieces.h"
#include "tear/cloth.h"
#include "tear/device.h"
#include "tear/usd_layer.h"
#include "tear/write_mesh.h"
#include "test_support.h"

namespace {

using tear::index_t;

/// The pieces of `mesh` found here independently: faces joined through shared nodes, each set
/// named by its lowest face.
std::vector<index_t> components(const tear::Mesh& mesh) {
  const std::size_t faces = mesh.face_nodes.size() / 3;
  std::vector<index_t> parent(faces);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](index_t x) {
    while (parent[x] != x) x = parent[x];
    return x;
  };
  std::map<index_t, index_t> node_face;
  for (std::size_t f = 0; f < faces; ++f)
    for (int k = 0; k < 3; ++k) {
      const auto [it, fresh] = node_face.emplace(mesh.face_nodes[3 * f + k], index_t(f));
      if (fresh) continue;
      const index_t a = find(it->second), b = find(index_t(f));
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  std::vector<index_t> root(faces);
  for (std::size_t f = 0; f < faces; ++f) root[f] = find(index_t(f));
  return root;
}

/// Checks that `mesh.face_piece` names exactly its connected pieces (one id per piece, ids 0..n-1).
void check_pieces_are_components(const tear::Mesh& mesh, index_t expected_count) {
  REQUIRE(mesh.face_piece.size() == mesh.face_nodes.size() / 3);
  const std::vector<index_t> root = components(mesh);
  std::map<index_t, index_t> id_of_root, root_of_id;
  for (std::size_t f = 0; f < root.size(); ++f) {
    const auto a = id_of_root.emplace(root[f], mesh.face_piece[f]);
    const auto b = root_of_id.emplace(mesh.face_piece[f], root[f]);
    REQUIRE(a.first->second == mesh.face_piece[f]);
    REQUIRE(b.first->second == root[f]);
  }
  CHECK(index_t(id_of_root.size()) == expected_count);
  CHECK(root_of_id.begin()->first == 0);
  CHECK(root_of_id.rbegin()->first == expected_count - 1);
}

/// Rest area of the faces of piece `id` (the sheet is flat in z = 0: positions before any step).
double piece_area(const tear::Mesh& mesh, index_t id) {
  double area = 0;
  for (std::size_t f = 0; f < mesh.face_piece.size(); ++f) {
    if (mesh.face_piece[f] != id) continue;
    const float* a = &mesh.node_pos[3 * mesh.face_nodes[3 * f]];
    const float* b = &mesh.node_pos[3 * mesh.face_nodes[3 * f + 1]];
    const float* c = &mesh.node_pos[3 * mesh.face_nodes[3 * f + 2]];
    area += 0.5 * std::abs(double(b[0] - a[0]) * (c[1] - a[1]) - double(b[1] - a[1]) * (c[0] - a[0]));
  }
  return area;
}

tear::CutLine line(std::array<double, 2> a, std::array<double, 2> b) {
  tear::CutLine cut;
  cut.polyline = {a, b};
  return cut;
}

// Across the whole sheet at y = 0.35: the part above (0.65 m²) keeps id 0 although the part below
// has face 0. Then down from the top at x = 0.25 into the first cut: of the upper part, the right
// (0.4875 m²) keeps 0 and the left (0.1625 m²), with the lower faces, takes id 2; the cut runs on
// into the lower part as a slit, which splits nothing.
const tear::CutLine first_cut = line({-0.1, 0.35}, {1.1, 0.35});
const tear::CutLine second_cut = line({0.25, 1.1}, {0.25, 0.2});

/// Piece `id` of a binary PLY tear wrote: the `piece` of every vertex and of every face.
void ply_pieces(const std::string& bytes, std::vector<index_t>& vertex_piece, std::vector<index_t>& face_piece) {
  const std::size_t end = bytes.find("end_header\n");
  REQUIRE(end != std::string::npos);
  std::istringstream header(bytes.substr(0, end));
  std::string line_text, element;
  std::size_t vertices = 0, faces = 0;
  std::map<std::string, std::vector<std::string>> props;
  while (std::getline(header, line_text)) {
    std::istringstream words(line_text);
    std::string word;
    words >> word;
    if (word == "element") {
      std::size_t count = 0;
      words >> element >> count;
      (element == "vertex" ? vertices : element == "face" ? faces : count) = count;
    } else if (word == "property") {
      std::string type, name;
      words >> type;
      if (type == "list") words >> type >> type;
      words >> name;
      props[element].push_back(name);
    }
  }
  const std::vector<std::string>& vertex_props = props["vertex"];
  const auto vertex_at = std::find(vertex_props.begin(), vertex_props.end(), "piece");
  REQUIRE(vertex_at != vertex_props.end());
  REQUIRE(props["face"] == std::vector<std::string>{"vertex_indices", "piece"});
  const char* data = bytes.data() + end + 11;
  const std::size_t vertex_size = 4 * vertex_props.size();
  const std::size_t piece_at = 4 * std::size_t(vertex_at - vertex_props.begin());
  vertex_piece.resize(vertices);
  for (std::size_t v = 0; v < vertices; ++v) std::memcpy(&vertex_piece[v], data + v * vertex_size + piece_at, 4);
  const char* face_data = data + vertices * vertex_size;
  face_piece.resize(faces);
  for (std::size_t f = 0; f < faces; ++f) std::memcpy(&face_piece[f], face_data + f * 17 + 13, 4);
}

/// The `_PIECE` attribute of a GLB tear wrote, per vertex.
std::vector<index_t> glb_pieces(const std::string& bytes) {
  std::uint32_t json_size = 0;
  std::memcpy(&json_size, bytes.data() + 12, 4);
  const nlohmann::json gltf = nlohmann::json::parse(bytes.substr(20, json_size));
  const char* bin = bytes.data() + 20 + json_size + 8;
  const auto& attributes = gltf["meshes"][0]["primitives"][0]["attributes"];
  REQUIRE(attributes.contains("_PIECE"));
  const auto& accessor = gltf["accessors"][attributes["_PIECE"].get<int>()];
  const auto& view = gltf["bufferViews"][accessor["bufferView"].get<int>()];
  const std::size_t count = accessor["count"], at = view["byteOffset"];
  std::vector<index_t> pieces(count);
  for (std::size_t v = 0; v < count; ++v) {
    float x = 0;
    std::memcpy(&x, bin + at + 4 * v, 4);
    pieces[v] = static_cast<index_t>(x);
  }
  return pieces;
}

/// The last time sample of `primvars:piece` in a USDA layer, and its interpolation.
std::vector<index_t> usd_pieces(const std::string& text) {
  const std::size_t declared = text.find("int[] primvars:piece (");
  REQUIRE(declared != std::string::npos);
  CHECK(text.find("interpolation = \"uniform\"", declared) < text.find(".timeSamples", declared));
  const std::size_t samples = text.find("int[] primvars:piece.timeSamples");
  REQUIRE(samples != std::string::npos);
  const std::size_t close = text.find("    }\n", samples);
  const std::size_t open = text.rfind(": [", close);
  std::vector<index_t> pieces;
  std::istringstream values(text.substr(open + 3, text.find(']', open) - open - 3));
  std::string value;
  while (std::getline(values, value, ',')) pieces.push_back(std::stoi(value));
  return pieces;
}

}  // namespace

TEST_CASE("pieces: numbered by lowest face, renumbered after a split by rest area", "[pieces]") {
  // Three triangles: 0 and 2 share node 2, 1 stands alone. Numbered afresh: 0, 1, 0.
  const std::vector<index_t> faces = {0, 1, 2, 3, 4, 5, 2, 6, 7};
  std::vector<index_t> piece;
  CHECK(tear::number_pieces(faces, 8, piece) == 2);
  CHECK(piece == std::vector<index_t>{0, 1, 0});
  // Face 2 cut off face 0 (its node 2 copied as node 8): of old piece 0, face 2 is larger and keeps 0.
  const std::vector<index_t> cut = {0, 1, 2, 3, 4, 5, 8, 6, 7};
  std::vector<float> rest(27, 0.f);
  auto at = [&](int n, float x, float y) { rest[3 * n] = x, rest[3 * n + 1] = y; };
  at(0, 0, 0), at(1, 1, 0), at(2, 0, 1);      // area 0.5
  at(3, 5, 0), at(4, 6, 0), at(5, 5, 1);      // area 0.5
  at(8, 0, 1), at(6, 3, 1), at(7, 0, 4);      // area 4.5
  CHECK(tear::renumber_pieces(cut, rest, piece) == 3);
  CHECK(piece == std::vector<index_t>{2, 1, 0});
  // A tie goes to the lowest face.
  at(6, 1, 1), at(7, 0, 2);
  piece = {0, 1, 0};
  CHECK(tear::renumber_pieces(cut, rest, piece) == 3);
  CHECK(piece == std::vector<index_t>{0, 1, 2});
  CHECK(tear::node_pieces(cut, piece, 9) == std::vector<index_t>{0, 0, 0, 1, 1, 1, 2, 2, 2});
  CHECK(tear::node_pieces(faces, {0, 1, 0}, 9).back() == -1);  // node 8, which no face uses
}

TEST_CASE("pieces: a sheet split twice keeps its ids, through a checkpoint too", "[pieces]") {
  const tear::Mesh sheet = tear::test::regular_sheet();
  tear::Cloth cloth(sheet, tear::test::test_device());
  tear::Mesh m = cloth.mesh();
  check_pieces_are_components(m, 1);
  CHECK(cloth.piece_count() == 1);

  cloth.cut({first_cut});
  m = cloth.mesh();
  check_pieces_are_components(m, 2);
  CHECK(cloth.piece_count() == 2);
  CHECK(m.face_piece[0] == 1);  // face 0 is in the lower, smaller part
  CHECK(piece_area(m, 0) == Approx(0.65).epsilon(1e-4));
  CHECK(piece_area(m, 1) == Approx(0.35).epsilon(1e-4));
  const std::string state = cloth.save_state();

  cloth.cut({second_cut});
  const tear::Mesh twice = cloth.mesh();
  check_pieces_are_components(twice, 3);
  CHECK(piece_area(twice, 0) == Approx(0.4875).epsilon(1e-4));
  CHECK(piece_area(twice, 1) == Approx(0.35).epsilon(1e-4));
  CHECK(piece_area(twice, 2) == Approx(0.1625).epsilon(1e-4));

  // Resumed from the checkpoint between the cuts: the same ids.
  tear::Cloth resumed(sheet, tear::test::test_device());
  resumed.load_state(state, "state");
  CHECK(resumed.piece_count() == 2);
  CHECK(resumed.mesh().face_piece == m.face_piece);
  resumed.cut({second_cut});
  CHECK(resumed.mesh().face_piece == twice.face_piece);
  CHECK(resumed.piece_count() == 3);
}

TEST_CASE("pieces: PLY, GLB and USD frames carry the same pieces", "[pieces][io]") {
  tear::Cloth cloth(tear::test::regular_sheet(), tear::test::test_device());
  cloth.cut({first_cut});
  cloth.cut({second_cut});
  const tear::Mesh m = cloth.mesh();
  const std::vector<index_t> node_piece = tear::node_pieces(m.face_nodes, m.face_piece, m.node_count());

  std::string ply, glb;
  tear::encode_mesh(m, "f.ply", tear::MeshFormat::ply, ply);
  tear::encode_mesh(m, "f.glb", tear::MeshFormat::glb, glb);
  std::vector<index_t> ply_vertex, ply_face;
  ply_pieces(ply, ply_vertex, ply_face);
  CHECK(ply_face == m.face_piece);
  const std::vector<index_t> glb_vertex = glb_pieces(glb);
  // Vertex i is node i; vertices past the nodes (UV seams) are copies in the same piece.
  REQUIRE(ply_vertex.size() >= node_piece.size());
  CHECK(std::vector<index_t>(ply_vertex.begin(), ply_vertex.begin() + m.node_count()) == node_piece);
  CHECK(glb_vertex == ply_vertex);
  CHECK(usd_pieces(tear::usda_layer_text(m, 1)) == m.face_piece);
}

TEST_CASE("pieces: tear run reports the pieces of every frame", "[pieces][cli]") {
  tear::test::TempDir dir;
  tear::write_mesh(tear::test::regular_sheet(), (dir / "sheet.obj").string());
  dir.file("cuts.json", R"({"version": 1, "frames": 5, "cuts": [
    {"frame": 2, "space": "rest-xy", "polyline": [[-0.1, 0.35], [1.1, 0.35]]},
    {"frame": 4, "space": "rest-xy", "polyline": [[0.25, 1.1], [0.25, 0.2]]}]})");
  const tear::test::Run run =
      dir.tear("run " + tear::test::quoted(dir / "sheet.obj") + " " + tear::test::quoted(dir / "cuts.json") + " -o " +
               tear::test::quoted(dir / "f.####.ply") + " --report " + tear::test::quoted(dir / "report.json") +
               " --device " + std::string(tear::to_string(tear::test::test_device())));
  REQUIRE(run.exit_code == 0);
  const nlohmann::json report = nlohmann::json::parse(tear::test::read_bytes(dir / "report.json"));
  std::vector<int> pieces;
  for (const auto& frame : report["frames"]) pieces.push_back(frame["pieces"]);
  CHECK(pieces == std::vector<int>{1, 2, 2, 3, 3});
  const tear::test::Run info = dir.tear("info --json " + tear::test::quoted(dir / "f.0005.ply"));
  REQUIRE(info.exit_code == 0);
  CHECK(nlohmann::json::parse(info.out)["pieces"] == 3);
}
