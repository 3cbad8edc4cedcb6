// Mesh files through the `tear` binary: hostile inputs, --no-weld, frames read back.
#include <sys/wait.h>

#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "catch.h"
#include "cli_support.h"
#include "io_support.h"
#include "tear/make_sheet.h"
#include "tear/write_mesh.h"

namespace {

using tear::test::le_bytes;
using tear::test::quoted;
using tear::test::Run;
using tear::test::TempDir;

/// Runs `tear ARGS` with its data (heap) limited to 2 GiB and its time to two minutes, so that a
/// file that makes the reader allocate or loop without bound fails the test instead of the machine.
/// Under AddressSanitizer, which reserves terabytes of address space for its shadow memory and so
/// cannot start under a data limit, no single allocation may exceed 2 GiB instead: one that does
/// is a sanitizer report, which stops the program and fails the test.
Run bounded_tear(const TempDir& dir, const std::string& args) {
  const auto out = dir / "stdout.txt", err = dir / "stderr.txt";
#if defined(TEAR_SANITIZED)
  const std::string limit =
      "ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}max_allocation_size_mb=2048\" ";
#else
  const std::string limit = "ulimit -d 2097152; ";
#endif
  const std::string command =
      limit + "timeout 120 " + quoted(TEAR_BINARY) + " " + args + " >" + quoted(out) + " 2>" + quoted(err);
  INFO(command);
  const int status = std::system(command.c_str());
  REQUIRE(status != -1);
  REQUIRE(WIFEXITED(status));
  return {WEXITSTATUS(status), tear::test::read_bytes(out), tear::test::read_bytes(err)};
}

/// A glTF of one triangle whose index buffer holds `indices` (three vertices).
std::string triangle_gltf(const std::vector<std::uint16_t>& indices) {
  std::string buffer;
  for (float v : {0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f}) buffer += le_bytes(v);
  for (std::uint16_t i : indices) buffer += le_bytes(i);
  const std::string uri = "data:application/octet-stream;base64," + tear::test::base64(buffer);
  return R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                  {"bufferView": 1, "componentType": 5123, "count": )" +
         std::to_string(indices.size()) + R"(, "type": "SCALAR"}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                    {"buffer": 0, "byteOffset": 36, "byteLength": )" +
         std::to_string(2 * indices.size()) + R"(}],
    "buffers": [{"byteLength": )" +
         std::to_string(buffer.size()) + R"(, "uri": ")" + uri + R"("}]})";
}

std::string ply_header(const std::string& vertex_count) {
  return "ply\nformat binary_little_endian 1.0\nelement vertex " + vertex_count +
         "\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
}

}  // namespace

TEST_CASE("cli: hostile mesh files are one-line input errors in bounded time and memory", "[cli][io]") {
  TempDir dir;
  std::string vertices;
  for (float v : {0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f}) vertices += le_bytes(v);
  const std::string face = std::string("\x03") + le_bytes(0) + le_bytes(1) + le_bytes(2);
  std::string padding(5000, ' ');

  // A GLB whose JSON chunk claims 0xFFFFFFF0 bytes.
  const std::string json = "{\"asset\":{\"version\":\"2.0\"}}";
  const std::string glb = std::string("glTF") + le_bytes(2u) + le_bytes(static_cast<std::uint32_t>(20 + json.size())) +
                          le_bytes(0xFFFFFFF0u) + "JSON" + json;
  const std::vector<std::pair<std::string, std::string>> files = {
      {"no_end_header.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n" + padding},
      {"header_into_data.ply", ply_header("3").substr(0, 70) + vertices + face},
      {"billion.ply", ply_header("1000000000") + vertices + face + padding},
      {"truncated.ply", ply_header("3") + vertices.substr(0, 30)},
      {"truncated_face.ply", ply_header("3") + vertices + face.substr(0, 9)},
      {"chunk.glb", glb},
      {"index.gltf", triangle_gltf({0, 1, 9})},
      {"index_in_range_then_not.gltf", triangle_gltf({0, 1, 2, 2, 1, 3})},
      {"garbage.glb", std::string("glTF") + std::string(40, '\xff')},
  };
  for (const auto& [name, bytes] : files) {
    INFO(name);
    const auto path = dir.file(name, bytes);
    const Run run = bounded_tear(dir, "info --device cpu " + quoted(path));
    INFO("stderr: " << run.err);
    CHECK(run.exit_code == 2);
    CHECK(run.out.empty());
    CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
    CHECK(run.err.rfind("tear: " + path.string() + ": ", 0) == 0);
  }
}

TEST_CASE("cli: an OBJ with a UTF-8 byte order mark is read", "[cli][io]") {
  TempDir dir;
  const auto path = dir.file("bom.obj", "\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\n");
  const Run run = bounded_tear(dir, "info --json --device cpu " + quoted(path));
  INFO("stderr: " << run.err);
  REQUIRE(run.exit_code == 0);
  const nlohmann::json info = nlohmann::json::parse(run.out);
  CHECK(info["nodes"] == 4);
  CHECK(info["faces"] == 2);
}

TEST_CASE("cli: --no-weld keeps a torn OBJ torn, tear's PLY and GLB stay torn without it", "[cli][io]") {
  TempDir dir;
  const tear::Mesh mesh = tear::test::two_pieces();
  for (const char* format : {"obj", "ply", "glb"}) {
    INFO("format " << format);
    const auto path = dir / (std::string("pieces.") + format);
    tear::write_mesh(mesh, path.string());
    for (bool weld : {true, false}) {
      const Run run =
          bounded_tear(dir, "info --json --device cpu " + std::string(weld ? "" : "--no-weld ") + quoted(path));
      INFO("stderr: " << run.err);
      REQUIRE(run.exit_code == 0);
      const nlohmann::json info = nlohmann::json::parse(run.out);
      const bool closed = weld && std::string(format) == "obj";
      CHECK(info["nodes"] == (closed ? 4 : 6));
      CHECK(info["components"] == (closed ? 1 : 2));
    }
  }
  for (const char* command : {"info", "run", "validate"}) {
    const Run help = bounded_tear(dir, std::string(command) + " --help");
    INFO(command);
    CHECK(help.out.find("--no-weld") != std::string::npos);
  }
}

TEST_CASE("cli: a torn frame tear run wrote reads back with the nodes it was written with", "[cli][io]") {
  TempDir dir;
  tear::SheetOptions sheet;
  sheet.face_count = 200;
  sheet.irregular = false;
  tear::write_mesh(tear::make_sheet(sheet), (dir / "sheet.obj").string());
  const auto script = dir.file("slit.json", R"({ "version": 1, "frames": 1, "cuts": [
    { "frame": 1, "space": "rest-xy", "polyline": [[-0.1, 0.43], [0.56, 0.43]] } ] })");
  for (const char* format : {"ply", "glb", "obj"}) {
    INFO("format " << format);
    const auto frame = dir / (std::string("frame.") + format);
    const Run run = bounded_tear(dir, "run --device cpu " + quoted(dir / "sheet.obj") + " " + quoted(script) + " -o " +
                                          quoted(frame) + " --report " + quoted(dir / "report.json"));
    INFO("stderr: " << run.err);
    REQUIRE(run.exit_code == 0);
    const nlohmann::json report = nlohmann::json::parse(tear::test::read_bytes(dir / "report.json"));
    const int written = report["frames"][0]["nodes"];
    const bool has_ids = std::string(format) != "obj";
    const Run info =
        bounded_tear(dir, "info --json --device cpu " + std::string(has_ids ? "" : "--no-weld ") + quoted(frame));
    REQUIRE(info.exit_code == 0);
    CHECK(nlohmann::json::parse(info.out)["nodes"] == written);
    // The slit is a tear: more boundary than the uncut sheet's 40 edges.
    CHECK(nlohmann::json::parse(info.out)["boundary_edges"] > 40);
    // And the validate command takes the same flag.
    const Run validate = bounded_tear(dir, "validate --device cpu --no-weld " + quoted(script) + " " + quoted(frame));
    INFO("validate stderr: " << validate.err);
    CHECK(validate.exit_code == 0);
  }
}

TEST_CASE("cli: deep glTF node chains and deeply nested JSON are refused without a crash", "[cli][io]") {
  TempDir dir;
  // 100,000 nodes, each the only child of the one before: no stack holds a recursion that deep.
  std::string nodes;
  for (int i = 0; i < 100000; ++i) nodes += (i ? ",{\"children\":[" : "{\"children\":[") + std::to_string(i + 1) + "]}";
  nodes += ",{}";
  const auto chain =
      dir.file("chain.gltf", R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[)" + nodes + "]}");
  const auto nested = dir.file("nested.gltf", R"({"asset":{"version":"2.0"},"extras":)" + std::string(100000, '[') +
                                                  std::string(100000, ']') + "}");
  for (const auto& path : {chain, nested}) {
    const Run run = bounded_tear(dir, "info --device cpu " + quoted(path));
    INFO("stderr: " << run.err);
    CHECK(run.exit_code == 2);
    CHECK(run.err.rfind("tear: " + path.string() + ": ", 0) == 0);
  }
}
