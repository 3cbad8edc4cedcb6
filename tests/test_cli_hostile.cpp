// Hostile assets and a shared farm, through the binary and the library: no file read or written
// outside what the user named, no hang on a FIFO or a device, bounded work, exit 4 on a stop at any
// moment, and a checkpoint checked as the input it is.
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "catch.h"
#include "cli_support.h"
#include "tear/checkpoint.h"
#include "tear/cloth.h"
#include "tear/error.h"
#include "tear/output_files.h"
#include "tear/read_mesh.h"
#include "tear/write_mesh.h"

namespace {

namespace fs = std::filesystem;
using tear::test::quoted;
using tear::test::Run;
using tear::test::TempDir;

/// `tear ARGS` in `dir`, stopped after 60 s: a read that blocks fails the test instead of hanging it.
Run timed_tear(const TempDir& dir, const std::string& args) {
  const fs::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string command = "cd " + quoted(dir.path) + " && timeout 60 " + quoted(TEAR_BINARY) + " " + args +
                              " >" + quoted(out) + " 2>" + quoted(err);
  INFO(command);
  const int status = std::system(command.c_str());
  REQUIRE(status != -1);
  REQUIRE(WIFEXITED(status));
  Run run{WEXITSTATUS(status), tear::test::read_bytes(out), tear::test::read_bytes(err)};
  fs::remove(out);
  fs::remove(err);
  return run;
}

/// One error line: exit `code`, nothing on standard output, one line holding `fragment`.
void check_refused(const Run& run, int code, const std::string& fragment) {
  INFO(run.err);
  CHECK(run.exit_code == code);
  CHECK(run.out.empty());
  CHECK(run.err.rfind("tear: ", 0) == 0);
  CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
  CHECK(run.err.find(fragment) != std::string::npos);
  CHECK(run.err.size() < 500);
}

std::string triangle_buffer() {
  std::string bytes;
  for (float v : {0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f}) bytes.append(reinterpret_cast<const char*>(&v), 4);
  return bytes;
}

/// A glTF of one triangle whose buffer is at `uri`, placed by `nodes` nodes; `image_uri`: an image too.
std::string triangle_gltf(const std::string& uri, std::size_t byte_length = 36, int nodes = 1,
                          const std::string& image_uri = "") {
  std::string node_list, scene;
  for (int i = 0; i < nodes; ++i) {
    node_list += std::string(i ? "," : "") + "{\"mesh\": 0}";
    scene += std::string(i ? "," : "") + std::to_string(i);
  }
  return R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [)" + scene + R"(]}], "nodes": [)" + node_list +
         R"(], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}],)" +
         (image_uri.empty() ? std::string() : R"("images": [{"uri": ")" + image_uri + R"("}],)") +
         R"("buffers": [{"byteLength": )" + std::to_string(byte_length) + R"(, "uri": ")" + uri + R"("}]})";
}

const char* const cut_script =
    R"({"version": 1, "frames": 2, "cuts": [{"frame": 1, "space": "rest-xy", "polyline": [[-0.1, 0.45], [1.1, 0.45]]}]})";

void write_sheet(const TempDir& dir) {
  tear::write_mesh(tear::test::regular_sheet(), (dir / "sheet.obj").string());
  dir.file("cut.json", cut_script);
}

/// A glTF 1.0 of one triangle whose buffer is at `uri`: tear's glTF reader reads 2.0 only and
/// hands 1.0 to assimp, whose importer opens the buffer's file itself.
std::string triangle_gltf1(const std::string& uri) {
  return R"({"asset": {"version": "1.0"}, "buffers": {"b": {"uri": ")" + uri + R"(", "byteLength": 36}},
    "bufferViews": {"bv": {"buffer": "b", "byteOffset": 0, "byteLength": 36, "target": 34962}},
    "accessors": {"acc": {"bufferView": "bv", "byteOffset": 0, "componentType": 5126, "count": 3, "type": "VEC3"}},
    "meshes": {"m": {"primitives": [{"attributes": {"POSITION": "acc"}, "mode": 4}]}},
    "nodes": {"n": {"meshes": ["m"]}}, "scenes": {"s": {"nodes": ["n"]}}, "scene": "s"})";
}

/// True when the tests run as root, where file permissions stop nothing and only tear's own checks
/// keep the files outside the named outputs as they are (CI runs as root). Not root: false, with a
/// warning that `what` was not tested, and a failure under TEAR_REQUIRE_ROOT=1 (CI's setting).
bool running_as_root(const std::string& what) {
  if (::geteuid() == 0) return true;
  const char* required = std::getenv("TEAR_REQUIRE_ROOT");
  if (required != nullptr && std::string(required) == "1")
    FAIL("TEAR_REQUIRE_ROOT=1, but the tests run as uid " << ::geteuid() << ": " << what << " is not tested");
  WARN("not root: " << what << " is not tested");
  return false;
}

/// What a file is, links not followed: its kind and mode, and for a regular file its bytes and
/// modification time, for a link its target (a FIFO or device is never opened).
struct FileState {
  unsigned mode = 0;
  std::int64_t mtime_ns = 0;
  std::string content;
  bool operator==(const FileState& o) const { return mode == o.mode && mtime_ns == o.mtime_ns && content == o.content; }
};

FileState file_state(const fs::path& path) {
  struct stat s {};
  if (::lstat(path.c_str(), &s) != 0) return {};
  FileState state;
  state.mode = s.st_mode;
  if (S_ISREG(s.st_mode)) {
    state.mtime_ns = std::int64_t(s.st_mtim.tv_sec) * 1000000000 + s.st_mtim.tv_nsec;
    state.content = tear::test::read_bytes(path);
  } else if (S_ISLNK(s.st_mode)) {
    state.content = fs::read_symlink(path).string();
  }
  return state;
}

/// Every file and folder below `root` (relative paths), links not followed. A folder's own time
/// is left out: the test's runs create and remove their captured output beside the files.
std::map<std::string, FileState> snapshot(const fs::path& root) {
  std::map<std::string, FileState> files;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    FileState state = file_state(entry.path());
    if (S_ISDIR(state.mode)) state.mtime_ns = 0;
    files[fs::relative(entry.path(), root).string()] = state;
  }
  return files;
}

/// The paths whose state differs between `before` and `after` (made, removed or changed), less
/// `allowed` (the named outputs) and the folders above them.
std::vector<std::string> changed_files(const std::map<std::string, FileState>& before,
                                       const std::map<std::string, FileState>& after,
                                       const std::vector<std::string>& allowed) {
  std::set<std::string> named;
  for (const std::string& path : allowed)
    for (fs::path p = path; !p.empty(); p = p.parent_path()) named.insert(p.string());
  std::vector<std::string> changed;
  for (const auto& [path, state] : before) {
    const auto now = after.find(path);
    if ((now == after.end() || !(now->second == state)) && !named.count(path)) changed.push_back(path);
  }
  for (const auto& [path, state] : after)
    if (!before.count(path) && !named.count(path)) changed.push_back(path);
  return changed;
}

}  // namespace

TEST_CASE("glTF: a buffer or image uri may only name a regular file in the glTF's folder or below", "[hostile][cli]") {
  TempDir dir;
  fs::create_directory(dir / "asset");
  fs::create_directory(dir / "asset" / "inner");
  dir.file("secret.bin", triangle_buffer());
  dir.file("asset/ok.bin", triangle_buffer());
  dir.file("asset/inner/deep.bin", triangle_buffer());
  fs::create_symlink("../secret.bin", dir / "asset" / "out.bin");
  fs::create_symlink("ok.bin", dir / "asset" / "in.bin");
  REQUIRE(::mkfifo((dir / "asset" / "fifo.bin").c_str(), 0600) == 0);
  const std::string secret = (dir / "secret.bin").string();

  // Allowed: a file beside the glTF or below it, by a link that stays inside, percent-encoded.
  for (const std::string& uri : std::vector<std::string>{"ok.bin", "inner/deep.bin", "in.bin", "inner%2Fdeep.bin", "./ok.bin"}) {
    dir.file("asset/good.gltf", triangle_gltf(uri));
    const Run run = timed_tear(dir, "info asset/good.gltf --json");
    INFO(uri << ": " << run.err);
    CHECK(run.exit_code == 0);
  }
  // Refused, naming the glTF and the buffer and nothing of the target, whatever the current folder.
  for (const std::string& uri : std::vector<std::string>{"../secret.bin", "%2E%2E/secret.bin", "..%2Fsecret.bin", "inner/../../secret.bin",
                                secret, "file://" + secret, "file:secret.bin", "out.bin", "fifo.bin", "inner",
                                ".", "missing.bin", "%00ok.bin"}) {
    dir.file("asset/bad.gltf", triangle_gltf(uri));
    INFO(uri);
    const Run run = timed_tear(dir, "info asset/bad.gltf");
    check_refused(run, 2, "asset/bad.gltf: buffer 0: ");
    CHECK(run.err.find("secret") == std::string::npos);
  }
  // Run from the glTF's folder: the current folder is no fallback for a file below it.
  dir.file("asset/inner/up.gltf", triangle_gltf("ok.bin"));
  check_refused(timed_tear(dir, "info asset/inner/up.gltf"), 2, "buffer 0: the uri does not name a regular file");
  // An image is held to the same rule (it is never decoded).
  dir.file("asset/image.gltf", triangle_gltf("ok.bin", 36, 1, "../secret.bin"));
  check_refused(timed_tear(dir, "info asset/image.gltf"), 2, "asset/image.gltf: image 0: ");
  // A wrong byteLength does not say the size of the file it found.
  dir.file("asset/length.gltf", triangle_gltf("ok.bin", 40));
  const Run length = timed_tear(dir, "info asset/length.gltf");
  check_refused(length, 2, "buffer 0: its file does not have the buffer's byteLength of 40 bytes");
  CHECK(length.err.find("36") == std::string::npos);
}

TEST_CASE("assimp: the files a mesh names are opened only inside its folder", "[hostile][cli]") {
  // Outside the mesh's folder: FIFOs nobody writes to, so that opening one hangs the read (the
  // 60 s guard of `timed_tear` then fails the test), and a secret.
  TempDir dir;
  fs::create_directory(dir / "asset");
  fs::create_directory(dir / "asset" / "inner");
  REQUIRE(::mkfifo((dir / "outside.bin").c_str(), 0600) == 0);
  REQUIRE(::mkfifo((dir / "outside.mtl").c_str(), 0600) == 0);
  REQUIRE(::mkfifo((dir / "asset" / "fifo.bin").c_str(), 0600) == 0);
  dir.file("secret.bin", triangle_buffer());
  dir.file("asset/ok.bin", triangle_buffer());
  dir.file("asset/inner/deep.bin", triangle_buffer());
  fs::create_symlink("../outside.bin", dir / "asset" / "out.bin");
  fs::create_symlink("../secret.bin", dir / "asset" / "secret.bin");
  const std::string outside = (dir / "outside.bin").string();

  // A glTF 1.0 (read by assimp): its buffer beside it or below it is read.
  for (const std::string uri : {"ok.bin", "inner/deep.bin"}) {
    dir.file("asset/good.gltf", triangle_gltf1(uri));
    const Run run = timed_tear(dir, "info asset/good.gltf --json");
    INFO(uri << ": " << run.err);
    CHECK(run.exit_code == 0);
  }
  // Up, absolute, through a link out of the folder, a FIFO inside: never opened (tear checks a
  // glTF 1.0's uris as it checks a glTF 2.0's, before assimp looks for them); exit 2 naming the
  // glTF and the buffer.
  for (const std::string& uri : {std::string("../outside.bin"), std::string("inner/../../outside.bin"), outside,
                                 std::string("out.bin"), std::string("fifo.bin"), std::string("secret.bin"),
                                 std::string("/etc/passwd")}) {
    dir.file("asset/bad.gltf", triangle_gltf1(uri));
    INFO(uri);
    check_refused(timed_tear(dir, "info asset/bad.gltf"), 2, "asset/bad.gltf: buffer b: the uri ");
  }
  // Its images and shaders too (assimp would look for them), each named by its key.
  std::string with_image = triangle_gltf1("ok.bin");
  with_image.insert(with_image.size() - 1, R"(, "images": {"skin": {"uri": "../secret.bin"}})");
  dir.file("asset/image.gltf", with_image);
  check_refused(timed_tear(dir, "info asset/image.gltf"), 2, "asset/image.gltf: image skin: the uri goes up with '..'");
  std::string with_shader = triangle_gltf1("ok.bin");
  with_shader.insert(with_shader.size() - 1, R"(, "shaders": {"vs": {"uri": "fifo.bin", "type": 35633}})");
  dir.file("asset/shader.gltf", with_shader);
  check_refused(timed_tear(dir, "info asset/shader.gltf"), 2,
                "asset/shader.gltf: shader vs: the uri does not name a regular file in the folder of the glTF or below");
  // A run reads the mesh the same way: refused before anything is written.
  dir.file("asset/bad.gltf", triangle_gltf1("../outside.bin"));
  dir.file("cut.json", cut_script);
  check_refused(timed_tear(dir, "run asset/bad.gltf cut.json -o out/f.####.obj"), 2, "asset/bad.gltf: ");
  CHECK_FALSE(fs::exists(dir / "out"));

  // An OBJ under another extension is read by assimp, whose OBJ importer opens its material
  // library: one outside the folder is skipped (never opened), and the mesh is read without it.
  for (const std::string& library : std::vector<std::string>{"../outside.mtl", (dir / "outside.mtl").string()}) {
    dir.file("asset/sheet.txt", "mtllib " + library + "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl cloth\nf 1 2 3\n");
    const Run run = timed_tear(dir, "info asset/sheet.txt --json");
    INFO(library << ": " << run.err);
    CHECK(run.exit_code == 0);
    CHECK(run.out.find("\"faces\":1,") != std::string::npos);
  }
  // The mesh's own size limit holds for the files it names.
  dir.file("asset/big.bin", triangle_buffer() + std::string(50000, '\0'));
  dir.file("asset/big.gltf", triangle_gltf1("big.bin"));
  CHECK(timed_tear(dir, "info asset/big.gltf --json").exit_code == 0);
  check_refused(timed_tear(dir, "info asset/big.gltf --max-input-bytes 10000"), 2,
                "asset/big.gltf: buffer b: its file is over the limit of 10000 bytes (--max-input-bytes)");
}

TEST_CASE("glTF: a bad data uri is not echoed whole, and instancing is bounded by --max-faces", "[hostile][cli]") {
  TempDir dir;
  dir.file("data.gltf", triangle_gltf("data:application/octet-stream;base64," + std::string(200000, '!')));
  check_refused(timed_tear(dir, "info data.gltf"), 2, "data.gltf: ");
  dir.file("ok.bin", triangle_buffer());
  dir.file("many.gltf", triangle_gltf("ok.bin", 36, 5000));
  check_refused(timed_tear(dir, "info many.gltf --max-faces 1000"), 2,
                "many.gltf: has 1001 triangles or more, over the limit of 1000 (--max-faces)");
  CHECK(timed_tear(dir, "info many.gltf --json").exit_code == 0);
  tear::ReadOptions options;
  options.max_faces = 10;
  CHECK_THROWS_AS(tear::read_mesh((dir / "many.gltf").string(), options), tear::Error);
}

TEST_CASE("glTF: what is left to assimp is checked where its importers trust the file", "[hostile][cli]") {
  // A strip or fan of fewer vertices than a triangle made assimp allocate for 2^32 faces (tens of
  // GB): refused first, in a glTF 1.0 and in a 2.0 that assimp decodes (Draco).
  TempDir dir;
  dir.file("ok.bin", triangle_buffer());
  std::string strip = triangle_gltf1("ok.bin");
  const std::string count = R"("count": 3)", mode = R"("mode": 4)";
  strip.replace(strip.find(count), count.size(), R"("count": 0)");
  strip.replace(strip.find(mode), mode.size(), R"("mode": 5)");
  dir.file("strip1.gltf", strip);
  check_refused(timed_tear(dir, "info strip1.gltf"), 2, "strip1.gltf: mesh m, primitive 0: a triangle strip of 0 vertices (it needs 3)");
  const std::string fan = R"({"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_draco_mesh_compression"],
    "buffers": [{"uri": "ok.bin", "byteLength": 36}], "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 1, "type": "VEC3"}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "mode": 6}]}], "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}]})";
  dir.file("fan.gltf", fan);
  check_refused(timed_tear(dir, "info fan.gltf"), 2, "fan.gltf: mesh 0, primitive 0: a triangle fan of 1 vertices (it needs 3)");
  // A document without a glTF 1.0 "asset" is not handed to assimp as one: tinygltf's error.
  dir.file("no_asset.gltf", R"({"arset": {"version": "2.0"}, "meshes": []})");
  check_refused(timed_tear(dir, "info no_asset.gltf"), 2, "no_asset.gltf: cannot read as glTF: ");
}

TEST_CASE("inputs: FIFOs, devices and folders are refused at once, never read", "[hostile][cli]") {
  TempDir dir;
  write_sheet(dir);
  REQUIRE(::mkfifo((dir / "fifo").c_str(), 0600) == 0);
  fs::create_directory(dir / "folder");
  // A FIFO nobody writes to would block a read forever.
  check_refused(timed_tear(dir, "info fifo"), 2, "fifo: cannot read the mesh: it is a FIFO, not a regular file");
  check_refused(timed_tear(dir, "run sheet.obj fifo -o out/f.####.obj"), 2,
                "fifo: cannot read the cut script: it is a FIFO");
  check_refused(timed_tear(dir, "validate fifo"), 2, "fifo: cannot read the cut script: it is a FIFO");
  check_refused(timed_tear(dir, "diff fifo sheet.obj"), 2, "fifo: cannot read the mesh: it is a FIFO");
  check_refused(timed_tear(dir, "diff sheet.obj fifo"), 2, "fifo: cannot read the mesh: it is a FIFO");
  check_refused(timed_tear(dir, "info folder"), 2, "folder: cannot read the mesh: it is a directory");
  // A character device that never ends (/dev/zero read as the script grew memory forever).
  check_refused(timed_tear(dir, "validate /dev/zero"), 2, "/dev/zero: cannot read the cut script: it is a character device");
  CHECK_FALSE(fs::exists(dir / "out"));
  // Sizes: the limit is known before a byte is read.
  check_refused(timed_tear(dir, "info sheet.obj --max-input-bytes 100"), 2, "more than the limit of 100 (--max-input-bytes)");
  dir.file("deep.json", std::string(100, '[') + std::string(100, ']'));
  check_refused(timed_tear(dir, "validate deep.json"), 2, "deep.json: the cut script nests arrays and objects deeper than 32");
  dir.file("big.json", "{\"frames\": 1, \"cuts\": []" + std::string(5 << 20, ' ') + "}");
  check_refused(timed_tear(dir, "validate big.json"), 2, "big.json: cannot read the cut script: it has");
}

TEST_CASE("outputs: a FIFO, device, folder or symbolic link at an output path is refused before any work",
          "[hostile][cli]") {
  TempDir dir;
  write_sheet(dir);
  dir.file("victim.txt", "keep me");
  REQUIRE(::mkfifo((dir / "fifo").c_str(), 0600) == 0);
  fs::create_directory(dir / "folder");
  fs::create_symlink("victim.txt", dir / "link.json");
  std::vector<std::string> targets = {"fifo", "folder", "link.json"};
  // A character device of our own (the numbers of /dev/null), where the tests may make one (root).
  if (running_as_root("a device node at an output path")) {
    REQUIRE(::mknod((dir / "device").c_str(), S_IFCHR | 0600, ::makedev(1, 3)) == 0);
    targets.push_back("device");
  }
  for (const std::string& target : targets) {
    for (const std::string option : {"--report", "--checkpoint"}) {
      INFO(option << " " << target);
      check_refused(timed_tear(dir, "run sheet.obj cut.json -o out/f.####.obj " + option + " " + target), 2,
                    target + ": cannot write the ");
      CHECK_FALSE(fs::exists(dir / "out"));
    }
  }
  // A frame's own path.
  REQUIRE(::mkfifo((dir / "frame.obj").c_str(), 0600) == 0);
  fs::create_symlink("victim.txt", dir / "frame.ply");
  check_refused(timed_tear(dir, "run sheet.obj cut.json --frames 1 -o frame.obj"), 2,
                "frame.obj: cannot write frame 1: it is a FIFO");
  check_refused(timed_tear(dir, "run sheet.obj cut.json --frames 1 -o frame.ply"), 2,
                "frame.ply: cannot write frame 1: it is a symbolic link");
  struct stat s {};
  REQUIRE(::lstat((dir / "fifo").c_str(), &s) == 0);
  CHECK(S_ISFIFO(s.st_mode));
  REQUIRE(::lstat((dir / "link.json").c_str(), &s) == 0);
  CHECK(S_ISLNK(s.st_mode));
  CHECK(tear::test::read_bytes(dir / "victim.txt") == "keep me");
}

TEST_CASE("outputs: hostile paths change no file but the named outputs, as root too", "[hostile][cli][root]") {
  // As root, no permission stands between tear and any file: what is checked here is tear's own
  // rules (refuse devices, FIFOs and links at output paths, never write through a link at a
  // temporary name, never read outside a mesh's folder), file by file over the whole test folder.
  const bool root = running_as_root("writing as root past hostile paths");
  TempDir dir;
  write_sheet(dir);
  fs::create_directory(dir / "sentinel");
  dir.file("sentinel/keep.txt", "keep me");
  ::chmod((dir / "sentinel" / "keep.txt").c_str(), 0444);  // read-only: stops a user, not root
  fs::create_symlink("sentinel/keep.txt", dir / "link.json");
  fs::create_directory(dir / "asset");
  fs::create_directory(dir / "out");
  // Links planted at temporary names of the frames and the report, both spellings, one to a folder.
  const std::vector<std::string> planted = {"out/.f.0001.obj.tmp.1", "out/.f.0001.obj.tmp.999999999.0123456789abcdef",
                                            "out/.f.0002.obj.tmp.999999999", "out/.r.json.tmp.1.00000000000000ff"};
  for (const std::string& link : planted) fs::create_symlink("../sentinel/keep.txt", dir / link);
  fs::create_symlink("../sentinel", dir / "out/.f.0002.obj.tmp.1.0123456789abcdef");
  // A device node: our own where we may make one (root), else the system's /dev/null (which a
  // user cannot replace anyway).
  std::string device = "/dev/null";
  if (root) {
    REQUIRE(::mknod((dir / "device").c_str(), S_IFCHR | 0666, ::makedev(1, 3)) == 0);
    device = "device";
  }
  // glTF uris to /etc/passwd: read by tear's reader (glTF 2.0), and by assimp's (glTF 1.0).
  dir.file("asset/passwd.gltf", triangle_gltf("/etc/passwd"));
  dir.file("asset/assimp.gltf", triangle_gltf1("/etc/passwd"));
  dir.file("asset/up.gltf", triangle_gltf1("../sentinel/keep.txt"));
  const FileState passwd = file_state("/etc/passwd");

  struct Case {
    std::string args;
    int exit_code;
    std::vector<std::string> outputs;  // the named outputs, which may change
  };
  const std::string run = "run sheet.obj cut.json -o out/f.####.obj";
  const std::vector<Case> cases = {
      {run + " --report " + device, 2, {}},
      {run + " --report link.json", 2, {}},
      {run + " --checkpoint link.json", 2, {}},
      {run + " --report sentinel", 2, {}},
      {"run asset/passwd.gltf cut.json -o out/g.####.obj --report out/g.json", 2, {}},
      {"run asset/assimp.gltf cut.json -o out/g.####.obj --report out/g.json", 2, {}},
      {"info asset/assimp.gltf", 2, {}},
      {"info asset/up.gltf", 2, {}},
      {run + " --report out/r.json --checkpoint out/c.ckpt", 0, {"out/f.0001.obj", "out/f.0002.obj", "out/r.json", "out/c.ckpt"}},
  };
  for (const Case& c : cases) {
    const auto before = snapshot(dir.path);
    const Run result = timed_tear(dir, c.args);
    INFO(c.args << "\nstderr: " << result.err);
    CHECK(result.exit_code == c.exit_code);
    CHECK(changed_files(before, snapshot(dir.path), c.outputs).empty());
  }
  CHECK(tear::test::read_bytes(dir / "sentinel" / "keep.txt") == "keep me");
  for (const std::string& link : planted) CHECK(fs::is_symlink(dir / link));
  CHECK(file_state("/etc/passwd") == passwd);
  if (root) {
    struct stat s {};
    REQUIRE(::lstat((dir / "device").c_str(), &s) == 0);
    CHECK(S_ISCHR(s.st_mode));
  }
}

TEST_CASE("outputs: temporaries are fresh files under random names, never written through a planted link",
          "[hostile][outputs]") {
  TempDir dir;
  dir.file("victim.txt", "keep me");
  const std::string target = (dir / "f.obj").string();
  // The names an older tear used, and names like this tear's: links planted at them are not followed.
  fs::create_symlink(dir / "victim.txt", dir / (".f.obj.tmp." + std::to_string(::getpid())));
  std::string first, second;
  const int a = tear::create_temporary_file(target, "", first);
  const int b = tear::create_temporary_file(target, "", second);
  REQUIRE(a >= 0);
  REQUIRE(b >= 0);
  ::close(a);
  ::close(b);
  CHECK(first != second);
  const std::string prefix = (dir / (".f.obj.tmp." + std::to_string(::getpid()) + ".")).string();
  CHECK(first.rfind(prefix, 0) == 0);
  CHECK(first.size() == prefix.size() + 16);
  fs::remove(first);
  fs::remove(second);
  tear::write_file_atomically(target, "frame");
  CHECK(tear::test::read_bytes(dir / "f.obj") == "frame");
  CHECK(tear::test::read_bytes(dir / "victim.txt") == "keep me");
  // A symbolic link put at the target after the checks is not replaced either.
  fs::remove(dir / "f.obj");
  fs::create_symlink(dir / "victim.txt", dir / "f.obj");
  CHECK_THROWS_AS(tear::write_file_atomically(target, "frame"), tear::Error);
  CHECK(tear::test::read_bytes(dir / "victim.txt") == "keep me");
  // Stale temporaries of both spellings are cleared; this run's own random names are recognised.
  dir.file(".g.obj.tmp.999999999.0123456789abcdef", "");
  dir.file(".g.obj.tmp.999999999.0123456789abcdeg", "");
  CHECK(tear::remove_stale_temporaries({(dir / "g.obj").string()}) == 1);
  CHECK(fs::exists(dir / ".g.obj.tmp.999999999.0123456789abcdeg"));
}

TEST_CASE("signals: SIGTERM before the first frame ends in exit 4", "[hostile][cli]") {
  TempDir dir;
  // A long command with no frames: the stop lands while it works, and ends it with exit 4.
  const std::string command = "cd " + quoted(dir.path) + " && (" + quoted(TEAR_BINARY) +
                              " bench --device cpu --only pd --faces 262144 --iterations 1000 --repeats 1000 --no-cpu >/dev/null "
                              "2>err.txt & pid=$!; sleep 1; kill -TERM $pid; wait $pid; exit $?)";
  const int status = std::system(command.c_str());
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 4);
  CHECK(tear::test::read_bytes(dir / "err.txt").find("tear: stopped before the first frame") != std::string::npos);
}

TEST_CASE("checkpoint: a checkpoint whose checksum matches is still checked as input", "[hostile][resume]") {
  TempDir dir;
  write_sheet(dir);
  dir.file("cut.json", R"({"version": 1, "frames": 4, "cuts": [{"frame": 1, "space": "rest-xy",
    "polyline": [[-0.1, 0.45], [1.1, 0.45]]}]})");
  const Run first = timed_tear(dir, "run sheet.obj cut.json -o out/f.####.ply --frames 2 --checkpoint c.ckpt");
  REQUIRE(first.exit_code == 0);
  const tear::Checkpoint good = tear::read_checkpoint((dir / "c.ckpt").string());
  const tear::Mesh sheet = tear::read_mesh((dir / "sheet.obj").string());

  auto resume_with = [&](const tear::Checkpoint& bad, const std::string& fragment) {
    tear::write_checkpoint((dir / "c.ckpt").string(), bad);
    const Run run = timed_tear(dir, "run sheet.obj cut.json -o out/f.####.ply --checkpoint c.ckpt --resume");
    check_refused(run, 2, "c.ckpt: cannot resume from this checkpoint: " + fragment);
  };
  auto with_state = [&](const std::vector<float>& pos, const std::vector<float>& vel) {
    tear::Cloth cloth(sheet, tear::Device::cpu);
    cloth.load_state(good.cloth_state, "c.ckpt");
    cloth.set_node_state(pos, vel);
    tear::Checkpoint bad = good;
    bad.cloth_state = cloth.save_state();
    return bad;
  };
  tear::Cloth cloth(sheet, tear::Device::cpu);
  cloth.load_state(good.cloth_state, "c.ckpt");
  const std::vector<float> pos = cloth.node_pos(), vel = cloth.node_vel();

  tear::Checkpoint bad = good;
  bad.frame = INT_MAX;
  resume_with(bad, "it names frame 2147483647, outside the script's frames 1..4");
  std::vector<float> v = vel;
  v.assign(pos.size(), 0.0f);
  v[4] = 1e30f;
  resume_with(with_state(pos, v), "node 1 has a velocity that is not finite or beyond 1e6 m/s");
  std::vector<float> p = pos;
  p[0] = std::numeric_limits<float>::infinity();
  resume_with(with_state(p, std::vector<float>(pos.size(), 0.0f)), "node 0 has a position that is not finite");
  // The good one still resumes.
  tear::write_checkpoint((dir / "c.ckpt").string(), good);
  CHECK(timed_tear(dir, "run sheet.obj cut.json -o out/f.####.ply --checkpoint c.ckpt --resume").exit_code == 0);
}

TEST_CASE("validate: at most 256 cuts are tried on the mesh, however long the script", "[hostile][cli]") {
  TempDir dir;
  write_sheet(dir);
  std::string cuts;
  for (int i = 0; i < 300; ++i)
    cuts += std::string(i ? "," : "") + R"({"frame": 1, "space": "rest-xy", "polyline": [[5, 5], [6, 6]]})";
  dir.file("many.json", R"({"version": 1, "frames": 1, "cuts": [)" + cuts + "]}");
  const Run run = timed_tear(dir, "validate many.json sheet.obj --device cpu");
  INFO(run.err.substr(0, 400));
  CHECK(run.exit_code == 0);
  CHECK(run.err.find("cuts[255]: changes nothing") != std::string::npos);
  CHECK(run.err.find("cuts[256]: changes nothing") == std::string::npos);
  CHECK(run.err.find("many.json: only the first 256 polyline cuts were tried on the rest shape of sheet.obj (44 more "
                     "not tried)") != std::string::npos);
}

TEST_CASE("reading: small files of one face repeated, one huge polygon or many concave ones end, as they should",
          "[hostile][cli]") {
  // Each took minutes to hours on 2 cores (work quadratic in a node's faces, or in the corners of
  // an ear-clipped polygon); made here, not kept (megabytes each). timed_tear stops a command after
  // 60 s, which a regression would reach.
  TempDir dir;
  // 300,000 copies of one triangle (2.4 MB): read, reported, refused as not cuttable.
  std::string repeated = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  for (int i = 0; i < 300000; ++i) repeated += "f 1 2 3\n";
  dir.file("repeated.obj", repeated);
  const Run info = timed_tear(dir, "info repeated.obj --json");
  INFO(info.err);
  CHECK(info.exit_code == 0);
  CHECK(info.out.find("\"duplicate_faces\":300000") != std::string::npos);
  write_sheet(dir);
  check_refused(timed_tear(dir, "run repeated.obj cut.json --frames 1 -o out/f.obj"), 2,
                "repeated.obj: cannot be cut: 3 non-manifold edges (more than two faces), 3 non-manifold (bow-tie) "
                "nodes, 300000 faces on the same three nodes as another face");

  // One polygon of 200,000 corners on a circle (6 MB): fanned from its first corner, whose 199,998
  // faces and edges are one node's.
  std::string polygon, face = "f";
  const int corners = 200000;
  for (int i = 0; i < corners; ++i) {
    const double a = 6.283185307179586 * i / corners;
    polygon += "v " + std::to_string(std::cos(a)) + " " + std::to_string(std::sin(a)) + " 0\n";
    face += " " + std::to_string(i + 1);
  }
  dir.file("polygon.obj", polygon + face + "\n");
  const Run fan = timed_tear(dir, "info polygon.obj --json");
  INFO(fan.err);
  CHECK(fan.exit_code == 0);
  CHECK(fan.out.find("\"faces\":199998") != std::string::npos);

  // 6,000 concave 128-gons, stars on the same 128 nodes (3 MB): ear-clipped, each corner's faces
  // in the thousands.
  std::string stars, star = "f";
  for (int i = 0; i < 128; ++i) {
    const double a = 6.283185307179586 * i / 128, r = i % 2 ? 0.3 : 1.0;
    stars += "v " + std::to_string(r * std::cos(a)) + " " + std::to_string(r * std::sin(a)) + " 0\n";
    star += " " + std::to_string(i + 1);
  }
  for (int i = 0; i < 6000; ++i) stars += star + "\n";
  dir.file("stars.obj", stars);
  const Run concave = timed_tear(dir, "info stars.obj --json");
  INFO(concave.err);
  CHECK(concave.exit_code == 0);
  CHECK(concave.out.find("\"faces\":756000") != std::string::npos);
}

TEST_CASE("validate: a script of 80,000 cuts is read in time linear in its cuts", "[hostile][cli]") {
  // nlohmann's parse callback made each cut scan the cuts before it (80,000 cuts: seconds).
  TempDir dir;
  write_sheet(dir);
  std::string cuts;
  for (int i = 0; i < 80000; ++i)
    cuts += std::string(i ? "," : "") + R"({"frame":1,"space":"uv","polyline":[[0,0],[1,1]]})";
  dir.file("many.json", R"({"version":1,"frames":1,"cuts":[)" + cuts + "]}");
  const Run run = timed_tear(dir, "validate many.json");
  INFO(run.err);
  CHECK(run.exit_code == 0);
  CHECK(run.out == "many.json: ok (80000 cuts over 1 frame)\n");
  // A duplicate key still names its key path, found while parsing.
  dir.file("twice.json", R"({"version":1,"frames":1,"cuts":[{"frame":1,"frame":1}]})");
  check_refused(timed_tear(dir, "validate twice.json"), 2, "twice.json: cuts[0].frame: duplicate key");
}

TEST_CASE("frames: degenerate or inverted faces are counted in the report and warned about, and --strict stops the run",
          "[hostile][cli]") {
  TempDir dir;
  // All nodes held, the middle one moved 0.6 m along x in frame 1: past its neighbours, so faces
  // around it turn over.
  tear::SheetOptions options;
  options.face_count = 32;
  options.irregular = false;
  const tear::Mesh sheet = tear::make_sheet(options);
  REQUIRE(sheet.node_count() == 25);
  tear::write_mesh(sheet, (dir / "sheet.obj").string());
  dir.file("push.json", R"({"version": 1, "frames": 2, "simulation": {"gravity": [0, 0, 0], "pins": [
    {"nodes": [12], "keys": [{"frame": 0, "offset": [0, 0, 0]}, {"frame": 1, "offset": [0.6, 0, 0]}]},
    {"box": {"min": [-1, -1, -1], "max": [2, 2, 1]}}]}})");
  const Run run = timed_tear(dir, "run sheet.obj push.json -o out/f.####.obj --report out/report.json");
  INFO(run.err);
  CHECK(run.exit_code == 0);
  CHECK(run.err.find("tear: warning: out/f.0001.obj: frame 1 has 2 inverted faces\n") != std::string::npos);
  const std::string report = tear::test::read_bytes(dir / "out" / "report.json");
  CHECK(report.find("\"inverted_faces\": 2") != std::string::npos);
  CHECK(report.find("\"degenerate_faces\": 0") != std::string::npos);
  fs::remove_all(dir / "out");
  const Run strict = timed_tear(dir, "run sheet.obj push.json -o out/f.####.obj --strict");
  check_refused(strict, 3, "out/f.0001.obj: frame 1 has 2 inverted faces (--strict)");
  CHECK_FALSE(fs::exists(dir / "out" / "f.0002.obj"));
  // A sheet that only hangs has nothing to say.
  dir.file("hold.json", R"({"version": 1, "frames": 2, "simulation": {"pins": [{"box": {"min": [-1, 0.9, -1], "max": [2, 2, 1]}}]}})");
  const Run quiet = timed_tear(dir, "run sheet.obj hold.json -o out/g.####.obj --strict");
  INFO(quiet.err);
  CHECK(quiet.exit_code == 0);
  CHECK(quiet.err.empty());
}
