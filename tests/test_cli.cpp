// The `tear` binary end to end: output, exit codes and one-line messages.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "catch.h"
#include "tear/device.h"

namespace {

namespace fs = std::filesystem;

struct Run {
  int exit_code = -1;
  std::string out, err;
};

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::size_t line_count(const std::string& text) { return std::count(text.begin(), text.end(), '\n'); }

/// A scratch folder for one test case, removed at the end.
class TempDir {
 public:
  TempDir() {
    static int counter = 0;
    path_ =
        fs::temp_directory_path() / ("tear_test_cli_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  fs::path file(const std::string& name, const std::string& text) const {
    const fs::path path = path_ / name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
  /// Runs `tear ARGS` through the shell, capturing stdout and stderr. A crash (signal) fails the test.
  Run tear(const std::string& args) const {
    const fs::path out = path_ / "stdout.txt", err = path_ / "stderr.txt";
    const std::string command =
        "'" + std::string(TEAR_BINARY) + "' " + args + " >'" + out.string() + "' 2>'" + err.string() + "'";
    const int status = std::system(command.c_str());
    INFO(command);
    REQUIRE(status != -1);
    REQUIRE(WIFEXITED(status));
    return {WEXITSTATUS(status), read_text(out), read_text(err)};
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

std::string quoted(const fs::path& path) { return "'" + path.string() + "'"; }

/// A 2 x 2 grid of unit quads with UVs, as OBJ quads (the reader triangulates them).
const char* const grid_obj =
    "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nv 0 2 0\nv 1 2 0\nv 2 2 0\n"
    "vt 0 0\nvt 0.5 0\nvt 1 0\nvt 0 0.5\nvt 0.5 0.5\nvt 1 0.5\nvt 0 1\nvt 0.5 1\nvt 1 1\n"
    "f 1/1 2/2 5/5 4/4\nf 2/2 3/3 6/6 5/5\nf 4/4 5/5 8/8 7/7\nf 5/5 6/6 9/9 8/8\n";

/// One line on stderr that names `file`, nothing on stdout.
void check_one_line_error(const Run& run, const std::string& file) {
  INFO("stderr: " << run.err);
  CHECK(run.out.empty());
  CHECK(line_count(run.err) == 1);
  CHECK(run.err.rfind("tear: ", 0) == 0);
  CHECK(run.err.find(file) != std::string::npos);
}

}  // namespace

TEST_CASE("cli: info --json prints one object with the counts of an OBJ", "[cli]") {
  TempDir dir;
  const fs::path mesh = dir.file("grid.obj", grid_obj);
  const Run run = dir.tear("info --json --device cpu " + quoted(mesh));
  INFO("stderr: " << run.err);
  REQUIRE(run.exit_code == 0);
  CHECK(run.err.empty());
  nlohmann::json j;
  REQUIRE_NOTHROW(j = nlohmann::json::parse(run.out));  // throws on anything after the object too
  REQUIRE(j.is_object());
  CHECK(j["file"] == mesh.string());
  CHECK(j["device"] == "cpu");
  CHECK_FALSE(j["device_name"].get<std::string>().empty());
  CHECK(j["nodes"] == 9);  // the v lines: every one is used
  CHECK(j["faces"] == 8);
  CHECK(j["edges"] == 16);
  CHECK(j["boundary_edges"] == 8);
  CHECK(j["boundary_loops"] == 1);
  CHECK(j["components"] == 1);
  CHECK(j["euler_characteristic"] == 1);
  CHECK(j["non_manifold_edges"] == 0);
  CHECK(j["non_manifold_nodes"] == 0);
  CHECK(j["degenerate_faces"] == 0);
  CHECK(j["inconsistent_edges"] == 0);
  CHECK(j["area"].get<double>() == Approx(4.0));
  CHECK(j["min_angle_deg"].get<double>() == Approx(45.0));
  CHECK(j["has_uv"] == true);
  CHECK(j["bbox_min"] == nlohmann::json::array({0.0, 0.0, 0.0}));
  CHECK(j["bbox_max"] == nlohmann::json::array({2.0, 2.0, 0.0}));
}

TEST_CASE("cli: info prints an aligned table with the backend", "[cli]") {
  TempDir dir;
  const fs::path mesh = dir.file("grid.obj", grid_obj);
  const Run run = dir.tear("info --device cpu " + quoted(mesh));
  REQUIRE(run.exit_code == 0);
  CHECK(run.err.empty());
  CHECK(run.out.find("backend:") != std::string::npos);
  CHECK(run.out.find("cpu") != std::string::npos);
  // Every value starts in the same column.
  std::istringstream lines(run.out);
  std::string line;
  std::size_t column = 0;
  int rows = 0;
  while (std::getline(lines, line)) {
    INFO(line);
    const std::size_t colon = line.find(':');
    REQUIRE(colon != std::string::npos);
    const std::size_t value = line.find_first_not_of(' ', colon + 1);
    if (rows++ == 0) column = value;
    CHECK(value == column);
    if (line.rfind("faces:", 0) == 0) CHECK(line.substr(value) == "8");
    if (line.rfind("boundary loops:", 0) == 0) CHECK(line.substr(value) == "1");
  }
  CHECK(rows > 10);
}

TEST_CASE("cli: info on a missing file is bad input", "[cli]") {
  TempDir dir;
  const fs::path missing = dir.path() / "no_such_mesh.obj";
  const Run run = dir.tear("info --json " + quoted(missing));
  CHECK(run.exit_code == 2);
  check_one_line_error(run, "no_such_mesh.obj");
}

TEST_CASE("cli: info on a face index out of range is bad input", "[cli]") {
  TempDir dir;
  const fs::path mesh = dir.file("out_of_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n");
  const Run run = dir.tear("info " + quoted(mesh));
  CHECK(run.exit_code == 2);
  check_one_line_error(run, "out_of_range.obj");
}

TEST_CASE("cli: info on a NaN coordinate is bad input", "[cli]") {
  TempDir dir;
  const fs::path mesh = dir.file("nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n");
  const Run run = dir.tear("info --json " + quoted(mesh));
  CHECK(run.exit_code == 2);
  check_one_line_error(run, "nan.obj");
}

TEST_CASE("cli: unknown flags and bad option values are usage errors", "[cli]") {
  TempDir dir;
  const fs::path mesh = dir.file("grid.obj", grid_obj);
  const std::string m = quoted(mesh);
  const std::vector<std::string> bad_args = {"info --no-such-flag " + m,
                                             "info --weld-tolerance -1 " + m,
                                             "info --weld-tolerance nan " + m,
                                             "info --weld-tolerance inf " + m,
                                             "info --device gpu " + m,
                                             "info",
                                             "",
                                             "no-such-command"};
  for (const std::string& args : bad_args) {
    INFO("tear " << args);
    const Run run = dir.tear(args);
    CHECK(run.exit_code == 1);
    CHECK(run.out.empty());
    CHECK(line_count(run.err) == 1);
    CHECK(run.err.rfind("tear: ", 0) == 0);
  }
}

TEST_CASE("cli: a wrong device is a usage error before the input is read", "[cli]") {
  TempDir dir;
  const Run run = dir.tear("info --device cpu:1 " + quoted(dir.path() / "missing.obj"));
  CHECK(run.exit_code == 1);
  CHECK(run.err.find("--device") != std::string::npos);
}

TEST_CASE("cli: --device cuda without a usable GPU is a usage error", "[cli]") {
  if (tear::cuda_available()) {
    WARN("a CUDA GPU is usable here; nothing to check");
    return;
  }
  TempDir dir;
  const fs::path mesh = dir.file("grid.obj", grid_obj);
  const Run run = dir.tear("info --device cuda " + quoted(mesh));
  INFO("stderr: " << run.err);
  CHECK(run.exit_code == 1);
  CHECK(run.out.empty());
  CHECK(line_count(run.err) == 1);
  CHECK(run.err.find("--device cuda") != std::string::npos);
  const bool says_why =
      run.err.find("no CUDA backend") != std::string::npos || run.err.find("no usable CUDA GPU") != std::string::npos;
  CHECK(says_why);
}

TEST_CASE("cli: --help explains every option and exits 0", "[cli]") {
  TempDir dir;
  const Run top = dir.tear("--help");
  CHECK(top.exit_code == 0);
  CHECK(top.out.find("info") != std::string::npos);
  CHECK(top.out.find("Exit codes") != std::string::npos);
  const Run info = dir.tear("info --help");
  CHECK(info.exit_code == 0);
  for (const char* option : {"MESH", "--json", "--device", "--mesh-name", "--weld-tolerance"}) {
    INFO(option);
    CHECK(info.out.find(option) != std::string::npos);
  }
}

TEST_CASE("cli: --version prints the version and exits 0", "[cli]") {
  TempDir dir;
  const Run run = dir.tear("--version");
  CHECK(run.exit_code == 0);
  CHECK(run.out.rfind("tear ", 0) == 0);
  CHECK(line_count(run.out) == 1);
}
