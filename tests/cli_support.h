// Running the `tear` binary from tests: a temporary folder per test case and captured output.
#pragma once

#include <sys/wait.h>
#include <stdlib.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

#include "catch.h"
#include "tear/make_sheet.h"

namespace tear::test {

namespace fs = std::filesystem;

/// What one run of the binary did.
struct Run {
  int exit_code = -1;
  std::string out, err;
};

inline std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

/// A path quoted for the shell.
inline std::string quoted(const fs::path& path) { return "'" + path.string() + "'"; }

/// A fresh folder for one test case, removed with everything in it at the end.
struct TempDir {
  fs::path path;
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "tear_test.XXXXXX").string();
    REQUIRE(mkdtemp(pattern.data()) != nullptr);
    path = pattern;
  }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  fs::path operator/(const std::string& name) const { return path / name; }
  fs::path file(const std::string& name, const std::string& text) const {
    std::ofstream(path / name, std::ios::binary) << text;
    return path / name;
  }
  /// Runs `tear ARGS`, capturing stdout and stderr. A crash (signal) fails the test.
  Run tear(const std::string& args) const {
    const fs::path out = path / "stdout.txt", err = path / "stderr.txt";
    const std::string command = quoted(TEAR_BINARY) + " " + args + " >" + quoted(out) + " 2>" + quoted(err);
    INFO(command);
    const int status = std::system(command.c_str());
    REQUIRE(status != -1);
    REQUIRE(WIFEXITED(status));
    Run run{WEXITSTATUS(status), read_bytes(out), read_bytes(err)};
    fs::remove(out);
    fs::remove(err);
    return run;
  }
};

/// The regular 200-face sheet: a 10 x 10 grid of 0.1 m, node 0 at the origin.
inline Mesh regular_sheet() {
  SheetOptions options;
  options.face_count = 200;
  options.irregular = false;
  return make_sheet(options);
}

}  // namespace tear::test
