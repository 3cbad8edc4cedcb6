// Whole `tear run`s compared byte for byte with committed files (tests/golden/README.md).
#include <stdlib.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "catch.h"
#include "tear/device.h"
#include "tear/make_sheet.h"
#include "tear/write_mesh.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace {

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

bool update_goldens() {
  const char* env = std::getenv("TEAR_UPDATE_GOLDENS");
  return env && std::string(env) == "1";
}

/// The first line where `a` and `b` differ (from 1), for the failure message.
std::size_t first_different_line(const std::string& a, const std::string& b) {
  std::size_t line = 1;
  for (std::size_t i = 0; i < a.size() && i < b.size() && a[i] == b[i]; ++i)
    if (a[i] == '\n') ++line;
  return line;
}

/// Runs `command` through the shell, its standard output and error into `dir/output.txt`; returns
/// its exit code (REQUIREs that it exited).
int run_tear(const std::string& command, const fs::path& dir) {
  const std::string full = command + " >'" + (dir / "output.txt").string() + "' 2>&1";
  const int status = std::system(full.c_str());
  INFO(full);
  INFO("output: " << read_bytes(dir / "output.txt"));
  REQUIRE(status != -1);
  REQUIRE(WIFEXITED(status));
  return WEXITSTATUS(status);
}

/// Runs `tear run` on the CPU backend (goldens are its bytes) on the 200-face regular sheet with
/// `script`, and compares the frame `frame_count` with `tests/golden/<name>.obj` byte for byte, or
/// rewrites that file when TEAR_UPDATE_GOLDENS=1. Where a GPU is present, the same run on the CUDA
/// backend (same topology, positions equal only to a tolerance) is compared with the golden by
/// `tear diff` at its default tolerance, as a user's golden test across backends would.
void check_golden(const std::string& name, const std::string& script, int frame_count) {
  std::string folder = (fs::temp_directory_path() / "tear_test_golden.XXXXXX").string();
  REQUIRE(mkdtemp(folder.data()) != nullptr);
  struct Cleanup {
    fs::path path;
    ~Cleanup() {
      std::error_code ignored;
      fs::remove_all(path, ignored);
    }
  } cleanup{folder};
  const fs::path dir = folder;

  tear::SheetOptions sheet;
  sheet.face_count = 200;
  sheet.irregular = false;
  tear::write_mesh(tear::make_sheet(sheet), (dir / "sheet.obj").string());
  std::ofstream(dir / "script.json", std::ios::binary) << script;

  const std::string tear = "'" + std::string(TEAR_BINARY) + "'";
  const std::string inputs = " '" + (dir / "sheet.obj").string() + "' '" + (dir / "script.json").string() + "'";
  REQUIRE(run_tear(tear + " run --device cpu" + inputs + " -o '" + (dir / "frame.####.obj").string() + "'", dir) == 0);

  char frame_name[32];
  std::snprintf(frame_name, sizeof frame_name, "frame.%04d.obj", frame_count);
  const std::string actual = read_bytes(dir / frame_name);
  REQUIRE_FALSE(actual.empty());
  const fs::path golden = tear::test::source_path("tests/golden/" + name + ".obj");
  if (update_goldens()) {
    std::ofstream(golden, std::ios::binary) << actual;
    WARN("rewrote " << golden.string());
    return;
  }
  REQUIRE(fs::exists(golden));
  if (tear::cuda_available()) {
    REQUIRE(run_tear(tear + " run --device cuda" + inputs + " -o '" + (dir / "cuda.####.obj").string() + "'", dir) == 0);
    std::snprintf(frame_name, sizeof frame_name, "cuda.%04d.obj", frame_count);
    const int diff = run_tear(tear + " diff '" + golden.string() + "' '" + (dir / frame_name).string() + "'", dir);
    INFO("tear diff of the CPU golden and the CUDA run: " << read_bytes(dir / "output.txt"));
    CHECK(diff == 0);  // 5: they differ beyond tear diff's default tolerance
  } else {
    WARN("no GPU: the CUDA run is not compared with " << golden.string());
  }
  const std::string expected = read_bytes(golden);
  if (actual != expected)
    FAIL(golden.string()
         << " differs from this run's output (first at line " << first_different_line(actual, expected)
         << "); if the change is intended, regenerate with TEAR_UPDATE_GOLDENS=1 tear_tests \"[golden]\" "
            "and review the diff (tests/golden/README.md)");
  SUCCEED(golden.string() + " matches");
}

}  // namespace

TEST_CASE("golden: a rest-xy slit from the border of the 200-face sheet", "[golden]") {
  check_golden("slit_from_border", R"({ "version": 1, "frames": 1, "cuts": [
    { "frame": 1, "space": "rest-xy", "polyline": [[-0.1, 0.43], [0.56, 0.43]] } ] })",
               1);
}

TEST_CASE("golden: two crossing cuts in one frame", "[golden]") {
  check_golden("crossing_cuts", R"({ "version": 1, "frames": 1, "cuts": [
    { "frame": 1, "space": "rest-xy", "polyline": [[0.13, 0.17], [0.87, 0.79]] },
    { "frame": 1, "space": "rest-xy", "polyline": [[0.16, 0.84], [0.83, 0.21]] } ] })",
               1);
}

TEST_CASE("golden: a bent uv cut across an earlier slit", "[golden]") {
  check_golden("uv_cut", R"({ "version": 1, "frames": 2, "cuts": [
    { "frame": 1, "space": "rest-xy", "polyline": [[0.22, 0.64], [0.78, 0.64]] },
    { "frame": 2, "space": "uv", "polyline": [[0.47, -0.1], [0.47, 0.42], [0.73, 1.1]] } ] })",
               2);
}
