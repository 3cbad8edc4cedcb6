// Outputs before a command writes them: no output may be an input, folders must be writable, and
// the temporary files of killed runs are cleared; through the library and through the binary.
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "catch.h"
#include "cli_support.h"
#include "tear/bench.h"
#include "tear/error.h"
#include "tear/frame_path.h"
#include "tear/output_files.h"
#include "tear/write_mesh.h"

namespace fs = std::filesystem;
using tear::NamedPath;
using tear::test::quoted;
using tear::test::read_bytes;
using tear::test::Run;
using tear::test::TempDir;

namespace {

/// The error `check_output_files` throws, or kind 0 with an empty message when it passes.
std::pair<int, std::string> outputs_error(const std::vector<NamedPath>& inputs, const std::string& pattern,
                                          int frame_count, const std::vector<NamedPath>& outputs) {
  try {
    if (pattern.empty()) {
      tear::check_output_files(inputs, nullptr, 0, outputs);
    } else {
      const tear::FramePattern frames(pattern);
      tear::check_output_files(inputs, &frames, frame_count, outputs);
    }
  } catch (const tear::Error& e) {
    return {e.exit_code(), e.what()};
  }
  return {0, ""};
}

std::vector<std::string> names_in(const fs::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

const char* const slit_script =
    R"({ "version": 1, "frames": 3, "cuts": [ { "frame": 1, "space": "rest-xy", "polyline": [[-0.1, 0.53], [0.56, 0.53]] } ] })";

}  // namespace

TEST_CASE("output_files: an output that is an input is refused, by any path to it", "[outputs]") {
  TempDir dir;
  const fs::path mesh = dir.file("cloth.obj", "v 0 0 0\n"), script = dir.file("shot.json", "{}");
  fs::create_directory(dir / "sub");
  fs::create_symlink(mesh, dir / "link.obj");
  fs::create_hard_link(mesh, dir / "hard.obj");
  const std::vector<NamedPath> inputs = {{"mesh", mesh.string()}, {"script", script.string()}};
  const std::string folder = dir.path.string();
  struct Case {
    std::string pattern;
    int frames;
    std::string report, names;
  };
  const Case cases[] = {
      {folder + "/cloth.obj", 1, "", "frame 1 is the input mesh"},
      {folder + "/sub/../cloth.obj", 1, "", "frame 1 is the input mesh"},
      {folder + "/new/../cloth.obj", 1, "", "frame 1 is the input mesh"},  // once new/ is made
      {folder + "/./link.obj", 1, "", "frame 1 is the input mesh"},
      {folder + "/hard.obj", 1, "", "frame 1 is the input mesh"},
      {folder + "/f.####.obj", 3, folder + "/shot.json", "the report is the input script"},
      {folder + "/f.####.obj", 3, folder + "/sub/../link.obj", "the report is the input mesh"},
  };
  for (const Case& c : cases) {
    INFO(c.pattern << " / " << c.report);
    const auto [code, message] = outputs_error(inputs, c.pattern, c.frames, {{"the report", c.report}});
    CHECK(code == 2);
    CHECK(message.find(c.names) != std::string::npos);
    CHECK(message.find("refusing to overwrite it") != std::string::npos);
  }
  // Frame 12 of "c{frame}.obj" would be c12.obj: an input there is found among the run's frames.
  dir.file("c12.obj", "");
  const auto [code, message] =
      outputs_error({{"mesh", (dir / "c12.obj").string()}}, folder + "/c{frame}.obj", 20, {});
  CHECK(code == 2);
  CHECK(message == (dir / "c12.obj").string() + ": frame 12 is the input mesh " + (dir / "c12.obj").string() +
                       "; refusing to overwrite it (choose another path)");
  CHECK(outputs_error({{"mesh", (dir / "c12.obj").string()}}, folder + "/c{frame}.obj", 11, {}).first == 0);
  // Other files are fine, and nothing was created.
  CHECK(outputs_error(inputs, folder + "/out/f.####.obj", 3, {{"the report", folder + "/out/r.json"}}).first == 0);
  CHECK_FALSE(fs::exists(dir / "out"));
  CHECK_FALSE(fs::exists(dir / "new"));
}

TEST_CASE("output_files: the report may not be a frame, and folders must be writable", "[outputs]") {
  TempDir dir;
  const std::string folder = dir.path.string();
  const auto same = outputs_error({}, folder + "/f.####.obj", 5, {{"the report", folder + "/./f.0004.obj"}});
  CHECK(same.first == 1);
  CHECK(same.second == folder + "/./f.0004.obj: the report is also frame 4");
  const auto twice = outputs_error({}, "", 0, {{"the report", "a/r.json"}, {"the JSON output", "a/../a/r.json"}});
  CHECK(twice.first == 1);
  CHECK(twice.second == "a/../a/r.json: the JSON output is also the report");

  dir.file("file", "");
  const auto under_file = outputs_error({}, folder + "/file/x/f.####.obj", 2, {});
  CHECK(under_file.first == 3);
  CHECK(under_file.second == folder + "/file/x: cannot create the output folder: Not a directory");
  const auto report = outputs_error({}, "", 0, {{"the report", folder + "/file/r.json"}});
  CHECK(report.first == 3);
  CHECK(report.second == folder + "/file: cannot write in the output folder: Not a directory");
  fs::create_directory(dir / "folder");
  const auto is_folder = outputs_error({}, "", 0, {{"the report", folder + "/folder"}});
  CHECK(is_folder.first == 2);
  CHECK(is_folder.second == folder + "/folder: cannot write the report: it is a folder");
  if (::geteuid() != 0) {  // root writes anywhere
    fs::create_directory(dir / "locked");
    ::chmod((dir / "locked").c_str(), 0555);
    const auto locked = outputs_error({}, folder + "/locked/deeper/f.####.obj", 1, {});
    CHECK(locked.first == 3);
    CHECK(locked.second == folder + "/locked/deeper: cannot create the output folder: Permission denied");
    ::chmod((dir / "locked").c_str(), 0755);
  }
}

TEST_CASE("output_files: temporaries of runs that are gone are removed, nothing else", "[outputs]") {
  TempDir dir;
  fs::create_directory(dir / "out");
  const std::string out = (dir / "out").string();
  // A pid that no process has (above the kernel's limit) and one that runs (this process's parent).
  const std::string gone = "999999999", alive = std::to_string(::getppid()), self = std::to_string(::getpid());
  for (const std::string& name : std::vector<std::string>{".f.0001.obj.tmp." + gone, ".f.0002.obj.tmp." + self, ".f.0001.obj.tmp." + alive, ".f.0009.obj.tmp." + gone,
        ".f.0001.obj.tmp.12x", ".f.0001.obj.tmpx." + gone, "f.0001.obj.tmp." + gone, ".r.json.tmp." + gone, "keep.txt"})
    dir.file("out/" + name, "partial");
  const std::size_t removed =
      tear::remove_stale_temporaries({out + "/f.0001.obj", out + "/f.0002.obj", out + "/r.json", out + "/missing/x"});
  CHECK(removed == 3);
  std::vector<std::string> kept = {".f.0001.obj.tmp." + alive, ".f.0001.obj.tmp.12x", ".f.0001.obj.tmpx." + gone,
                                   ".f.0009.obj.tmp." + gone, "f.0001.obj.tmp." + gone, "keep.txt"};
  std::sort(kept.begin(), kept.end());
  CHECK(names_in(dir / "out") == kept);
  // A bare file name lives in the current folder; a missing folder is no error.
  CHECK(tear::remove_stale_temporaries({(dir / "nowhere/f.obj").string(), ""}) == 0);
}

TEST_CASE("output_files: a temporary is removed only when no one holds its lock, whatever its process id",
          "[outputs]") {
  TempDir dir;
  fs::create_directory(dir / "out");
  const std::string out = (dir / "out").string();
  // Names of this tear's spelling. The process ids say nothing: another host's job may run under
  // a pid that is gone here, and a pid that runs here may be another host's abandoned job.
  const std::string alive = std::to_string(::getppid()), gone = "999999999";
  const std::string held_by_child = ".f.0001.obj.tmp." + gone + ".00000000000000aa";
  const std::string abandoned_alive = ".f.0001.obj.tmp." + alive + ".00000000000000bb";
  const std::string abandoned_gone = ".f.0002.obj.tmp." + gone + ".00000000000000cc";
  for (const std::string& name : {held_by_child, abandoned_alive, abandoned_gone}) dir.file("out/" + name, "partial");

  // Another process holds a lock on one of them, as a writer on another host would (a POSIX
  // record lock: what an NFS server passes between hosts). The child makes system calls only.
  int ready[2], release[2];
  REQUIRE(::pipe(ready) == 0);
  REQUIRE(::pipe(release) == 0);
  const std::string held_path = out + "/" + held_by_child;
  const pid_t child = ::fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    ::close(ready[0]);
    ::close(release[1]);
    const int fd = ::open(held_path.c_str(), O_RDWR);
    struct flock lock {};
    lock.l_type = F_WRLCK;
    lock.l_whence = SEEK_SET;
    char byte = fd >= 0 && ::fcntl(fd, F_SETLK, &lock) == 0 ? 'y' : 'n';
    if (::write(ready[1], &byte, 1) != 1) ::_exit(1);
    const ssize_t released = ::read(release[0], &byte, 1);  // until the parent is done, or gone
    ::_exit(released < 0 ? 1 : 0);
  }
  ::close(ready[1]);
  ::close(release[0]);
  char locked = 0;
  REQUIRE(::read(ready[0], &locked, 1) == 1);
  ::close(ready[0]);
  REQUIRE(locked == 'y');

  // This process writes a temporary of its own meanwhile: created locked, kept locked while open.
  std::string own;
  const int own_fd = tear::create_temporary_file(out + "/f.0003.obj", "", own);
  REQUIRE(own_fd >= 0);

  const std::vector<std::string> targets = {out + "/f.0001.obj", out + "/f.0002.obj", out + "/f.0003.obj"};
  CHECK(tear::remove_stale_temporaries(targets) == 2);
  std::vector<std::string> kept = {held_by_child, fs::path(own).filename().string()};
  std::sort(kept.begin(), kept.end());
  CHECK(names_in(dir / "out") == kept);

  // Once the child is gone and this process's file is closed, both are abandoned.
  ::close(release[1]);
  int status = 0;
  REQUIRE(::waitpid(child, &status, 0) == child);
  CHECK(tear::remove_stale_temporaries(targets) == 1);
  CHECK(names_in(dir / "out") == std::vector<std::string>{fs::path(own).filename().string()});
  ::close(own_fd);
  CHECK(tear::remove_stale_temporaries(targets) == 1);
  CHECK(names_in(dir / "out").empty());
}

TEST_CASE("output_files: a staged file stays locked until it is renamed", "[outputs]") {
  TempDir dir;
  const std::string target = (dir / "f.obj").string();
  tear::TemporaryFile staged = tear::write_temporary_file(target, "frame");
  // Another run's cleanup, between the write and the rename, leaves it alone.
  CHECK(tear::remove_stale_temporaries({target}) == 0);
  REQUIRE(fs::exists(staged.temporary));
  tear::commit_temporary_file(staged);
  CHECK(read_bytes(dir / "f.obj") == "frame");
  CHECK(names_in(dir.path) == std::vector<std::string>{"f.obj"});
}

TEST_CASE("run: an output that is an input is refused before anything is written", "[outputs][cli]") {
  TempDir dir;
  const fs::path mesh = dir / "sheet.obj";
  tear::write_mesh(tear::test::regular_sheet(), mesh.string());
  const fs::path script = dir.file("shot.json", slit_script);
  const std::string mesh_bytes = read_bytes(mesh), script_bytes = read_bytes(script);
  const std::string run = "run --device cpu " + quoted(mesh) + " " + quoted(script) + " ";
  const fs::path one = dir.file("one.json", R"({ "version": 1, "frames": 1 })");
  const std::pair<std::string, std::string> cases[] = {
      {"run --device cpu " + quoted(mesh) + " " + quoted(one) + " -o " + quoted(mesh), "frame 1 is the input mesh"},
      {run + "-o " + quoted(dir / "out/f.####.obj") + " --report " + quoted(mesh), "the report is the input mesh"},
      {run + "-o " + quoted(dir / "out/f.####.obj") + " --report " + quoted(script), "the report is the input script"},
      {run + "-o " + quoted(dir / "out/../sheet.obj") + " --frames 1", "frame 1 is the input mesh"},
  };
  for (const auto& [args, words] : cases) {
    const Run r = dir.tear(args);
    INFO(args << "\nstderr: " << r.err);
    CHECK(r.exit_code == 2);
    CHECK(r.out.empty());
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK(r.err.find(words) != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "out"));
  }
  CHECK(read_bytes(mesh) == mesh_bytes);
  CHECK(read_bytes(script) == script_bytes);
}

TEST_CASE("run: unwritable outputs are found before the first frame, stale temporaries cleared", "[outputs][cli]") {
  TempDir dir;
  const fs::path mesh = dir / "sheet.obj";
  tear::write_mesh(tear::test::regular_sheet(), mesh.string());
  const fs::path script = dir.file("shot.json", slit_script);
  dir.file("file", "");
  const std::string run = "run --device cpu " + quoted(mesh) + " " + quoted(script) + " ";
  const Run report = dir.tear(run + "-o " + quoted(dir / "out/f.####.obj") + " --report " + quoted(dir / "file/r.json"));
  INFO(report.err);
  CHECK(report.exit_code == 3);
  CHECK(report.err == "tear: " + (dir / "file").string() + ": cannot write in the output folder: Not a directory\n");
  CHECK_FALSE(fs::exists(dir / "out"));  // found before frame 1 was written

  // A killed run left a temporary file of frame 2: the next run removes it and writes the frame.
  fs::create_directory(dir / "out");
  dir.file("out/.f.0002.obj.tmp.999999999", "half a frame");
  dir.file("out/.other.obj.tmp.999999999", "not ours");
  const Run ok = dir.tear(run + "-o " + quoted(dir / "out/f.####.obj"));
  INFO(ok.err);
  CHECK(ok.exit_code == 0);
  CHECK(names_in(dir / "out") ==
        std::vector<std::string>{".other.obj.tmp.999999999", "f.0001.obj", "f.0002.obj", "f.0003.obj"});
}

TEST_CASE("bench: bad sizes and an unwritable --json are refused before the first line", "[outputs][cli][bench]") {
  TempDir dir;
  dir.file("file", "");
  for (const std::string faces : {"3", "6", "0", "2822,5", "536870912"}) {
    const Run r = dir.tear("bench --device cpu --only remesh --repeats 1 --warmup 0 --faces " + faces);
    INFO(faces << ": " << r.err);
    CHECK(r.exit_code == 1);
    CHECK(r.out.empty());
    CHECK(r.err.find("--faces") != std::string::npos);
  }
  const Run json = dir.tear("bench --device cpu --only remesh --repeats 1 --warmup 0 --faces 2822 --json " +
                            quoted(dir / "file/bench.json"));
  INFO(json.err);
  CHECK(json.exit_code == 3);
  CHECK(json.out.empty());
  CHECK(json.err == "tear: " + (dir / "file").string() + ": cannot write in the output folder: Not a directory\n");
}

TEST_CASE("bench: the io part writes and reads back every format and leaves nothing behind", "[outputs][cli][bench]") {
  TempDir dir;
  tear::BenchOptions options;
  options.face_counts = {200};
  options.repeats = 1;
  options.warmup = 0;
  const std::vector<tear::IoBenchRow> rows = tear::run_io_bench(options, dir.path.string());
  REQUIRE(rows.size() == 4);
  const std::vector<std::string> formats = {"obj", "ply", "gltf", "glb"};
  for (std::size_t i = 0; i < rows.size(); ++i) {
    INFO(tear::to_json(rows[i]));
    CHECK(rows[i].format == formats[i]);
    CHECK(rows[i].faces == 200);
    CHECK(rows[i].bytes > 200 * 3 * sizeof(float));
    CHECK(rows[i].encode_ms > 0);
    CHECK(rows[i].write_ms > 0);
    CHECK(rows[i].read_ms > 0);
  }
  CHECK(names_in(dir.path).empty());

  fs::create_directories(dir / "disk");
  const Run cli = dir.tear("bench --only io --faces 200,400 --repeats 1 --warmup 0 --io-folder " + quoted(dir / "disk") +
                           " --json " + quoted(dir / "io.json"));
  INFO(cli.err);
  CHECK(cli.exit_code == 0);
  CHECK(cli.out.find("\nio: ") != std::string::npos);
  CHECK(cli.out.find(" glb ") != std::string::npos);
  CHECK(names_in(dir / "disk").empty());
  const std::string json = read_bytes(dir / "io.json");
  CHECK(json.find("\"read_ms\"") != std::string::npos);
}
