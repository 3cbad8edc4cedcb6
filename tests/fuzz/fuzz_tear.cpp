// The fuzz target of tear: mesh reading, cut script parsing and cutting, with a validity oracle.
//
// Input layout: byte 0 picks the mesh file's extension (`fuzz_extensions`, byte 0 modulo their
// count); the bytes after it, up to the line `fuzz_script_separator`, are the mesh file; the bytes
// after that line are a cut script. Without the separator the whole rest is the mesh and the cut
// is `fuzz_default_script`.
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
#include <exception>
#include <fstream>
#include <string>
#include <vector>

#include "tear/cloth.h"
#include "tear/cut_script.h"
#include "tear/error.h"
#include "tear/read_mesh.h"
#include "tear/validate_mesh.h"

namespace {

const char* const fuzz_extensions[] = {"obj", "ply", "gltf", "glb"};
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

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
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
  if (!input.ok()) return 0;  // refused before a run (tear run exits 2)
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
