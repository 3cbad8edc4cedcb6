// Stopping and resuming a run as a farm does: SIGTERM and SIGKILL at random frames, resumed from
// the checkpoint each time, must give the bytes of a run never stopped.
#include <signal.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "catch.h"
#include "cli_support.h"
#include "random_meshes.h"
#include "tear/cloth.h"
#include "tear/cut_script.h"
#include "tear/make_sheet.h"
#include "tear/write_mesh.h"
#include "test_support.h"

namespace fs = std::filesystem;
using tear::test::TempDir;

namespace {

constexpr int frame_count = 24;

/// A hanging sheet cut three times while it falls: enough work per frame to be stopped mid-run.
const char* script_text = R"({
  "version": 1, "frames": 24,
  "cuts": [
    {"frame": 3, "space": "rest-xy", "polyline": [[-0.1, 0.55], [0.6, 0.5]]},
    {"frame": 9, "space": "rest-xy", "polyline": [[1.1, 0.3], [0.3, 0.45]]},
    {"frame": 15, "space": "rest-xy", "polyline": [[0.5, 1.1], [0.55, 0.7]]}],
  "simulation": {"iterations": 40, "pins": [{"box": {"min": [-1, 0.99, -1], "max": [2, 2, 1]}}]}
})";

/// Starts `tear ARGS` in the background; returns its pid.
pid_t start(const std::vector<std::string>& args, const fs::path& log) {
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> argv;
    std::string binary = TEAR_BINARY;
    argv.push_back(binary.data());
    std::vector<std::string> copy = args;
    for (std::string& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1);
    dup2(fd, 2);
    execv(binary.c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

int wait_exit(pid_t pid, int* signal_number) {
  int status = 0;
  waitpid(pid, &status, 0);
  *signal_number = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST_CASE("resume: runs stopped by SIGTERM and SIGKILL at random frames give the bytes of one never stopped", "[resume]") {
  const std::uint64_t seed = tear::test::test_seed(12);
  INFO("seed " << seed << " (TEAR_TEST_SEED reruns it)");
  tear::test::Random random(seed);
  TempDir dir;
  tear::SheetOptions sheet;
  sheet.face_count = 3000;
  tear::write_mesh(tear::make_sheet(sheet), (dir / "sheet.obj").string());
  const fs::path script = dir.file("shot.json", script_text);
  const std::string mesh_arg = (dir / "sheet.obj").string();
  // The backend under test (TEAR_TEST_DEVICE): the same bytes are asked of each, run against itself.
  const std::string device = tear::to_string(tear::test::test_device());

  const tear::test::Run whole =
      dir.tear("run " + tear::test::quoted(dir / "sheet.obj") + " " + tear::test::quoted(script) + " -o " +
               tear::test::quoted(dir / "whole" / "f.####.ply") + " --device " + device);
  REQUIRE(whole.exit_code == 0);

  // Stopped several times, each at a random frame, with each signal; resumed each time.
  const std::vector<std::string> args = {"run", mesh_arg, script.string(), "-o", (dir / "parts" / "f.####.ply").string(),
                                         "--device", device, "--checkpoint", (dir / "parts" / "shot.ckpt").string(),
                                         "--resume", "--progress", "lines"};
  auto frame_name = [](int f) { return "f." + std::string(4 - std::to_string(f).size(), '0') + std::to_string(f) + ".ply"; };
  int terms = 0, kills = 0, written = 0;  // frames on disk: 1..written
  for (int attempt = 0; attempt < 12 && written < frame_count - 1; ++attempt) {
    const int signal_to_send = attempt % 2 == 0 ? SIGTERM : SIGKILL;
    // A frame this attempt writes (frames on disk are not), so the signal lands while it runs.
    const int stop_at = written + 1 + static_cast<int>(random.uniform() * (frame_count - written - 1));
    const fs::path log = dir / ("log" + std::to_string(attempt) + ".txt");
    const pid_t pid = start(args, log);
    const fs::path frame = dir / "parts" / frame_name(stop_at);
    for (int i = 0; i < 20000 && !fs::exists(frame); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    kill(pid, signal_to_send);
    int signal_number = 0;
    const int code = wait_exit(pid, &signal_number);
    INFO("attempt " << attempt << ", signal " << signal_to_send << " at frame " << stop_at << ": exit " << code
                    << ", signal " << signal_number << "; log: " << tear::test::read_bytes(log));
    if (signal_to_send == SIGTERM) {
      CHECK((code == 4 || code == 0));  // stopped after a whole frame (0: it had finished)
      terms += code == 4;
    } else {
      CHECK((signal_number == SIGKILL || code == 0));
      kills += signal_number == SIGKILL;
    }
    while (written < frame_count && fs::exists(dir / "parts" / frame_name(written + 1))) ++written;
    if (code == 0) break;
  }
  CHECK(terms >= 1);
  CHECK(kills >= 1);
  // Resumed to the end.
  const tear::test::Run last = dir.tear([&] {
    std::string s;
    for (const std::string& a : args) s += tear::test::quoted(a) + " ";
    return s;
  }());
  REQUIRE(last.exit_code == 0);
  for (int f = 1; f <= frame_count; ++f) {
    const std::string name = frame_name(f);
    INFO(name);
    REQUIRE(fs::exists(dir / "parts" / name));
    CHECK(tear::test::read_bytes(dir / "whole" / name) == tear::test::read_bytes(dir / "parts" / name));
  }
  // Nothing temporary left beside the frames.
  for (const auto& entry : fs::directory_iterator(dir / "parts"))
    CHECK(entry.path().filename().string().find(".tmp.") == std::string::npos);
}

TEST_CASE("resume: a checkpoint of other inputs, or damaged, is refused with exit 2, SIGTERM exits 4", "[resume]") {
  TempDir dir;
  tear::write_mesh(tear::test::regular_sheet(), (dir / "sheet.obj").string());
  const fs::path script = dir.file("shot.json", R"({"version": 1, "frames": 3,
    "cuts": [{"frame": 1, "space": "rest-xy", "polyline": [[-0.1, 0.5], [0.5, 0.5]]}]})");
  const std::string base = tear::test::quoted(dir / "sheet.obj") + " " + tear::test::quoted(script) + " -o " +
                           tear::test::quoted(dir / "out" / "f.####.obj") + " --device cpu --checkpoint " +
                           tear::test::quoted(dir / "ck");
  REQUIRE(dir.tear("run " + base).exit_code == 0);
  REQUIRE(fs::exists(dir / "ck"));
  // The same inputs: resumed after frame 3, nothing left to do.
  CHECK(dir.tear("run " + base + " --resume").exit_code == 0);

  // Another script.
  dir.file("shot.json", R"({"version": 1, "frames": 3,
    "cuts": [{"frame": 1, "space": "rest-xy", "polyline": [[-0.1, 0.4], [0.5, 0.4]]}]})");
  tear::test::Run other = dir.tear("run " + base + " --resume");
  CHECK(other.exit_code == 2);
  CHECK(other.err.find("the script changed") != std::string::npos);
  CHECK(other.err.find((dir / "ck").string()) != std::string::npos);

  // Damaged: truncated, a byte flipped, not a checkpoint at all.
  const std::string bytes = tear::test::read_bytes(dir / "ck");
  for (const std::string& damaged : {bytes.substr(0, bytes.size() / 2), std::string("hello"),
                                     bytes.substr(0, 100) + char(bytes[100] ^ 0x5a) + bytes.substr(101)}) {
    std::ofstream(dir / "ck", std::ios::binary) << damaged;
    const tear::test::Run run = dir.tear("run " + base + " --resume");
    CHECK(run.exit_code == 2);
    CHECK(run.err.rfind("tear: " + (dir / "ck").string() + ": ", 0) == 0);
    CHECK(run.err.find('\n') == run.err.size() - 1);
  }
  // --resume needs --checkpoint.
  CHECK(dir.tear("run " + tear::test::quoted(dir / "sheet.obj") + " " + tear::test::quoted(script) + " -o " +
                 tear::test::quoted(dir / "o.####.obj") + " --resume")
            .exit_code == 1);
}

TEST_CASE("resume: --progress lines prints one parsable line per frame", "[resume]") {
  TempDir dir;
  tear::write_mesh(tear::test::regular_sheet(), (dir / "sheet.obj").string());
  const fs::path script = dir.file("shot.json", R"({"version": 1, "frames": 4, "cuts": []})");
  const tear::test::Run run = dir.tear("run " + tear::test::quoted(dir / "sheet.obj") + " " + tear::test::quoted(script) +
                                       " -o " + tear::test::quoted(dir / "f.####.obj") + " --progress lines");
  REQUIRE(run.exit_code == 0);
  CHECK(run.err ==
        "frame 1/4 (25%) Progress: 25%\nframe 2/4 (50%) Progress: 50%\nframe 3/4 (75%) Progress: 75%\n"
        "frame 4/4 (100%) Progress: 100%\n");
  // The expressions docs/cli.md gives the farm managers match every line.
  const std::regex deadline(R"(Progress: (\d+)%)"), full(R"(^frame (\d+)/(\d+) \((\d+)%\) Progress: (\d+)%$)");
  std::istringstream lines(run.err);
  std::string line;
  int count = 0;
  while (std::getline(lines, line)) {
    std::smatch m;
    REQUIRE(std::regex_search(line, m, deadline));
    CHECK(std::stoi(m[1]) == 25 * ++count);
    CHECK(std::regex_match(line, full));
  }
  CHECK(count == 4);
}

TEST_CASE("resume: a single USD layer cannot be checkpointed, one layer per frame can", "[resume]") {
  TempDir dir;
  tear::write_mesh(tear::test::regular_sheet(), (dir / "sheet.obj").string());
  const fs::path script = dir.file("shot.json", R"({"version": 1, "frames": 2, "cuts": []})");
  const std::string base = "run " + tear::test::quoted(dir / "sheet.obj") + " " + tear::test::quoted(script) +
                           " --device cpu --checkpoint " + tear::test::quoted(dir / "ck") + " -o ";
  const tear::test::Run single = dir.tear(base + tear::test::quoted(dir / "shot.usda"));
  CHECK(single.exit_code == 1);
  CHECK(single.err.find("single USD layer") != std::string::npos);
  CHECK(!fs::exists(dir / "shot.usda"));
  CHECK(dir.tear(base + tear::test::quoted(dir / "shot.####.usda")).exit_code == 0);
  CHECK(fs::exists(dir / "shot.0002.usda"));
}

TEST_CASE("resume: SIGTERM inside a long frame stops it there, and the resumed frames are those of a run never stopped",
          "[resume]") {
  // Frames of seconds each on 3,200 faces: 10,000 solver iterations (20 substeps of 500) on the
  // CPU (2,000 under the sanitizers), the most a frame may have (20 substeps of 50,000) on a GPU. The signal lands a
  // quarter of a frame into frame 3 (frame 1's file appears as frame 3 begins: a frame is renamed at the next
  // hand-over), measured on the run never stopped, not assumed.
  TempDir dir;
  tear::SheetOptions sheet;
  sheet.face_count = 3200;
  sheet.irregular = false;
  tear::write_mesh(tear::make_sheet(sheet), (dir / "sheet.obj").string());
  const bool gpu = tear::test::test_device() == tear::Device::cuda;
#if defined(TEAR_SANITIZED)
  // Under the sanitizers an iteration takes some ten times as long: a fifth of them still makes
  // frames of seconds.
  const char* cpu_iterations = "100";
#else
  const char* cpu_iterations = "500";
#endif
  const fs::path script =
      dir.file("shot.json", std::string(R"({"version": 1, "frames": 3,
    "simulation": {"substeps": 20, "iterations": )") +
                                (gpu ? "50000" : cpu_iterations) +
                                R"(, "pins": [{"box": {"min": [-1, 0.99, -1], "max": [2, 2, 1]}}]}})");
  const std::string device = tear::to_string(tear::test::test_device());
  const auto started = std::chrono::steady_clock::now();
  const tear::test::Run whole = dir.tear("run " + tear::test::quoted(dir / "sheet.obj") + " " + tear::test::quoted(script) +
                                         " -o " + tear::test::quoted(dir / "whole" / "f.####.ply") + " --device " + device);
  REQUIRE(whole.exit_code == 0);
  const auto frame_time = (std::chrono::steady_clock::now() - started) / 3;

  const std::vector<std::string> args = {"run", (dir / "sheet.obj").string(), script.string(), "-o",
                                         (dir / "parts" / "f.####.ply").string(), "--device", device,
                                         "--checkpoint", (dir / "parts" / "shot.ckpt").string(), "--resume"};
  const fs::path log = dir / "log.txt";
  const pid_t pid = start(args, log);
  for (int i = 0; i < 120000 && !fs::exists(dir / "parts" / "f.0001.ply"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  std::this_thread::sleep_for(frame_time / 4);
  kill(pid, SIGTERM);
  // A guard against a hang only: the stop lands within a substep, well inside this.
  int status = 0;
  for (int i = 0; i < 60000 && waitpid(pid, &status, WNOHANG) == 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  if (waitpid(pid, &status, WNOHANG) == 0) {
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
    FAIL("the run did not stop within 60 s of SIGTERM");
  }
  const std::string err = tear::test::read_bytes(log);
  INFO("log: " << err);
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 4);
  // Stopped inside frame 3, not after it: frame 3 never written, the checkpoint frame 2's.
  CHECK(err == "tear: stopped after frame 2 of 3, inside frame 3 (dropped: it is computed again on resume); "
               "'--resume' goes on from " + (dir / "parts" / "shot.ckpt").string() + "\n");
  CHECK(fs::exists(dir / "parts" / "f.0002.ply"));
  CHECK_FALSE(fs::exists(dir / "parts" / "f.0003.ply"));

  std::string resume;
  for (const std::string& a : args) resume += tear::test::quoted(a) + " ";
  REQUIRE(dir.tear(resume).exit_code == 0);
  for (const std::string name : {"f.0001.ply", "f.0002.ply", "f.0003.ply"}) {
    INFO(name);
    CHECK(tear::test::read_bytes(dir / "whole" / name) == tear::test::read_bytes(dir / "parts" / name));
  }
  for (const auto& entry : fs::directory_iterator(dir / "parts"))
    CHECK(entry.path().filename().string().find(".tmp.") == std::string::npos);
}

TEST_CASE("Cloth::step_frame: a stop looked at before every substep, with and without tearing", "[resume][simulation]") {
  tear::SheetOptions options;
  options.face_count = 200;
  for (const std::string block : {R"({"substeps": 4, "iterations": 5})",
                                  R"({"substeps": 4, "iterations": 5, "tearing": {"stretch": 1.25}})"}) {
    INFO(block);
    const tear::CutScript script =
        tear::parse_cut_script(R"({"version": 1, "frames": 2, "simulation": )" + block + "}", "s.json");
    tear::Cloth cloth(tear::make_sheet(options), tear::test::test_device());
    cloth.simulate(*script.simulation);
    const std::vector<float> rest = cloth.node_pos();
    volatile std::sig_atomic_t stop = 1;
    // Set before the frame: not a substep is stepped, and the frame is said to be unfinished.
    CHECK_FALSE(cloth.step_frame(1, &stop));
    CHECK(cloth.node_pos() == rest);
    // Not set: the frame is stepped whole, as without a flag.
    stop = 0;
    tear::Cloth same(tear::make_sheet(options), tear::test::test_device());
    same.simulate(*script.simulation);
    CHECK(same.step_frame(1, &stop));
    tear::Cloth plain(tear::make_sheet(options), tear::test::test_device());
    plain.simulate(*script.simulation);
    plain.step_frame(1);
    CHECK(same.node_pos() == plain.node_pos());
    CHECK(same.node_pos() != rest);
  }
}
