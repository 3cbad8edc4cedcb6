// The fuzz target of tear: mesh reading, cut script parsing and cutting, with a validity oracle.
//
// Input layout: byte 0 picks the mesh file's extension (`fuzz_extensions`, byte 0 modulo their
// count); the bytes after it, up to the line `fuzz_script_separator`, are the mesh file; the bytes
// after that line are a cut script. Without the separator the whole rest is the mesh and the cut
// is `fuzz_default_script`. Two values of byte 0 pick other inputs instead:
// - `fuzz_gltf_with_files`: a glTF and the files it names. The mesh part is split at the lines
//   `fuzz_file_separator`: the glTF first, then files written beside it as `a.bin`, `b.bin`, ... and
//   one in a subfolder, `sub/c.bin`, while a file outside the glTF's folder, `outside.bin`, holds a
//   marker: a mesh read with the marker's bytes in its positions fails (a uri got out);
// - `fuzz_checkpoint`: a checkpoint file (read_checkpoint, Cloth::load_state on a small sheet and
//   check_checkpoint_cloth must accept it whole or refuse it with an input error; what they accept
//   must be a valid mesh).
//
// What counts as a failure (abort, so that libFuzzer and the ctest replay report it):
// - any exception other than a `tear::Error` of kind input from reading the mesh or the script
//   (input problems must be input errors, exit 2, never internal errors);
// - a mesh that passes `validate_mesh` (cuttable) whose cut gives a mesh that does not: every
//   accepted mesh must give a valid result;
// - crashes, hangs, and whatever the sanitizers find, which libFuzzer reports itself.
//
// With TEAR_FUZZ_VERBOSE set, each input says on stderr how far it got (for replaying one by hand).
//
// Built two ways: with libFuzzer (`-DTEAR_FUZZ=ON`, clang; scripts/fuzz.sh runs it) and, in every
// test build, with `fuzz_replay.cpp`'s main, which runs the files of tests/fuzz/corpus and
// tests/fuzz/seeds as ctest tests.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tear/checkpoint.h"
#include "tear/cloth.h"
#include "tear/cut_script.h"
#include "tear/error.h"
#include "tear/make_sheet.h"
#include "tear/read_mesh.h"
#include "tear/validate_mesh.h"

namespace {

const char* const fuzz_extensions[] = {"obj", "ply", "gltf", "glb"};
constexpr std::uint8_t fuzz_gltf_with_files = 0xF0, fuzz_checkpoint = 0xF1;
const char fuzz_file_separator[] = "\n%%file\n";
// Outside the glTF's folder: positions made of these floats mean a uri reached it.
constexpr float outside_marker = 1234.5f;
const char fuzz_script_separator[] = "\n%%script\n";
const char fuzz_default_script[] =
    R"({"version": 1, "frames": 2, "cuts": [
         {"frame": 1, "plane": {"point": [0.3, 0.4, 0.5], "normal": [1, 0.3, 0.1]}},
         {"frame": 2, "space": "rest-xy", "polyline": [[-10, 0.45], [0.5, 0.55], [10, 0.6]]}]})";

// Limits that keep one input fast; larger inputs are skipped, not failures.
constexpr tear::index_t max_faces = 4096;
constexpr std::size_t max_cuts = 16;
constexpr std::size_t max_points = 256;

void note(const std::string& what) {
  static const bool verbose = std::getenv("TEAR_FUZZ_VERBOSE") != nullptr;
  if (verbose) std::fprintf(stderr, "tear fuzz: %s\n", what.c_str());
}

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "tear fuzz: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

/// A folder of this process for the mesh file; assimp reads files, not memory, through tear.
const std::string& scratch_folder() {
  static const std::string folder = [] {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/tear_fuzz.XXXXXX";
    if (!mkdtemp(pattern.data())) fail("cannot create a scratch folder under " + pattern);
    return pattern;
  }();
  return folder;
}

/// Runs `f`; an input `Error` means the input was refused (returns false), anything else fails.
template <class F>
bool accepted(const char* what, F f) {
  try {
    f();
    return true;
  } catch (const tear::Error& e) {
    if (e.kind() != tear::ErrorKind::input) fail(std::string(what) + ": not an input error: " + e.what());
    note(std::string(what) + ": refused: " + e.what());
    return false;
  } catch (const std::exception& e) {
    fail(std::string(what) + ": unexpected exception: " + e.what());
  }
}

bool small_enough(const tear::CutScript& script) {
  if (script.cuts.size() > max_cuts) return false;
  for (const tear::Cut& cut : script.cuts)
    if (cut.polyline2.size() > max_points || cut.polyline3.size() > max_points) return false;
  return true;
}

void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) fail("cannot write " + path);
}

/// A glTF with the files it names beside it, one below it, and a marked one outside its folder.
void fuzz_gltf_files(const std::string& bytes) {
  std::vector<std::string> parts;
  for (std::size_t at = 0;;) {
    const std::size_t next = bytes.find(fuzz_file_separator, at);
    parts.push_back(bytes.substr(at, next == std::string::npos ? std::string::npos : next - at));
    if (next == std::string::npos || parts.size() == 5) break;
    at = next + sizeof fuzz_file_separator - 1;
  }
  namespace fs = std::filesystem;
  const fs::path folder = fs::path(scratch_folder()) / "gltf";
  std::error_code ignored;
  fs::remove_all(folder, ignored);
  fs::create_directories(folder / "sub");
  std::string marker(4096, '\0');
  for (std::size_t i = 0; i + sizeof(float) <= marker.size(); i += sizeof(float))
    std::memcpy(&marker[i], &outside_marker, sizeof(float));
  write_file((fs::path(scratch_folder()) / "outside.bin").string(), marker);
  const char* names[] = {"a.bin", "b.bin", "sub/c.bin", "d.bin"};
  for (std::size_t i = 1; i < parts.size(); ++i) write_file((folder / names[i - 1]).string(), parts[i]);
  const std::string path = (folder / "mesh.gltf").string();
  write_file(path, parts[0]);
  tear::Mesh mesh;
  if (!accepted("read_mesh (glTF with files)", [&] { mesh = tear::read_mesh(path); })) return;
  for (float x : mesh.node_pos)
    if (x == outside_marker) fail("a glTF read the marked file outside its folder");
  const tear::MeshReport report = tear::validate_mesh(mesh, tear::Device::cpu);
  note("glTF with files: " + std::to_string(mesh.face_count()) + " faces, " + report.describe());
}

/// A checkpoint: read, loaded over a small sheet, checked; what is accepted must be a valid mesh.
void fuzz_checkpoint_file(const std::string& bytes) {
  const std::string path = scratch_folder() + "/state.ckpt";
  write_file(path, bytes);
  tear::Checkpoint checkpoint;
  const bool read = accepted("read_checkpoint", [&] { checkpoint = tear::read_checkpoint(path); });
  ::unlink(path.c_str());
  if (!read) return;
  tear::SheetOptions options;
  options.face_count = 32;  // 25 nodes on [0, 1]², as the seed checkpoint's run had
  const tear::Mesh sheet = tear::make_sheet(options);
  const tear::CutScript script = tear::parse_cut_script(fuzz_default_script, "fuzz.json");
  tear::Cloth cloth(sheet, tear::Device::cpu);
  if (!accepted("load_state", [&] {
        cloth.load_state(checkpoint.cloth_state, path);
        tear::check_checkpoint_cloth(path, checkpoint.frame, cloth, sheet, script);
      }))
    return;
  const tear::MeshReport result = tear::validate_mesh(cloth.mesh(), tear::Device::cpu);
  if (!result.ok()) fail("an accepted checkpoint gave an invalid mesh: " + result.describe());
  note("checkpoint of frame " + std::to_string(checkpoint.frame) + " accepted: " +
       std::to_string(cloth.face_count()) + " faces");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (data[0] == fuzz_gltf_with_files) {
    fuzz_gltf_files(bytes);
    return 0;
  }
  if (data[0] == fuzz_checkpoint) {
    fuzz_checkpoint_file(bytes);
    return 0;
  }
  const std::size_t separator = bytes.find(fuzz_script_separator);
  const std::string mesh_bytes = bytes.substr(0, separator);
  const std::string script_text = separator == std::string::npos
                                      ? std::string(fuzz_default_script)
                                      : bytes.substr(separator + sizeof fuzz_script_separator - 1);

  tear::CutScript script;
  if (!accepted("parse_cut_script", [&] { script = tear::parse_cut_script(script_text, "fuzz.json"); })) return 0;

  const char* extension = fuzz_extensions[data[0] % (sizeof fuzz_extensions / sizeof *fuzz_extensions)];
  const std::string path = scratch_folder() + "/mesh." + extension;
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(mesh_bytes.data(), static_cast<std::streamsize>(mesh_bytes.size()));
    if (!out) fail("cannot write " + path);
  }
  tear::Mesh mesh;
  const bool read = accepted("read_mesh", [&] { mesh = tear::read_mesh(path); });
  ::unlink(path.c_str());
  if (!read || mesh.face_count() > max_faces || !small_enough(script)) return 0;

  const tear::Device device = tear::Device::cpu;
  const tear::MeshReport input = tear::validate_mesh(mesh, device);
  note("mesh." + std::string(extension) + ": " + std::to_string(mesh.face_count()) + " faces, " + input.describe());
  if (!input.cuttable()) return 0;  // refused before a run (tear run exits 2)
  if (!accepted("check_script_against_mesh", [&] { tear::check_script_against_mesh(script, mesh, path); })) return 0;

  tear::Cloth cloth(mesh, device);
  tear::CutOptions options;
  options.snap = script.snap;
  for (int frame = 1; frame <= script.frames && frame <= 4; ++frame) {
    const std::vector<const tear::Cut*> cuts = script.cuts_of_frame(frame);
    if (cuts.empty()) continue;
    std::vector<tear::CutLine> lines;
    for (const tear::Cut* cut : cuts) lines.push_back(tear::to_cut_line(*cut));
    const tear::CutStats stats = cloth.cut(lines, options);
    note("frame " + std::to_string(frame) + ": " + std::to_string(lines.size()) + " cuts, " +
         std::to_string(stats.faces_before) + " -> " + std::to_string(stats.faces_after) + " faces");
    const tear::MeshReport result = tear::validate_mesh(cloth.mesh(), device);
    if (!result.ok())
      fail("frame " + std::to_string(frame) + ": a cuttable mesh of " + std::to_string(mesh.face_count()) +
           " faces gave an invalid mesh: " + result.describe());
  }
  return 0;
}
