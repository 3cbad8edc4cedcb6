// A good neighbour on a shared node: passive OpenMP waits, and the CPU threads limited by
// --threads, OMP_NUM_THREADS or a Slurm job's SLURM_CPUS_PER_TASK (docs/cli.md, *Threads*).
#include <string>

#include <nlohmann/json.hpp>

#include "catch.h"
#include "cli_support.h"
#include "tear/write_mesh.h"

namespace {

using tear::test::quoted;
using tear::test::TempDir;

/// `tear info --json` of the sheet with `env` before the program and `args` after, on the CPU.
nlohmann::json info(const TempDir& dir, const std::string& env, const std::string& args) {
  const std::string command = "env -u OMP_NUM_THREADS -u SLURM_CPUS_PER_TASK " + env + " " + quoted(TEAR_BINARY) +
                              " info --device cpu --json " + quoted(dir / "sheet.obj") + " " + args + " >" +
                              quoted(dir / "out.json") + " 2>" + quoted(dir / "err.txt");
  INFO(command);
  REQUIRE(std::system(command.c_str()) == 0);
  return nlohmann::json::parse(tear::test::read_bytes(dir / "out.json"));
}

}  // namespace

/// The spin count the OpenMP runtime last printed with OMP_DISPLAY_ENV=verbose (libgomp: 0 when
/// waits are passive, 300000 by default, more when active), or -1 when it printed none.
long long last_spin_count(const std::string& err) {
  const std::string key = "GOMP_SPINCOUNT = '";
  const std::size_t at = err.rfind(key);
  return at == std::string::npos ? -1 : std::stoll(err.substr(at + key.size()));
}

TEST_CASE("threads: OpenMP waits passively unless the environment says otherwise", "[threads][cli]") {
  TempDir dir;
  tear::write_mesh(tear::test::regular_sheet(), (dir / "sheet.obj").string());
  // OMP_DISPLAY_ENV=verbose makes the OpenMP runtime print its settings as it starts.
  info(dir, "-u OMP_WAIT_POLICY OMP_DISPLAY_ENV=verbose", "");
  const long long passive = last_spin_count(tear::test::read_bytes(dir / "err.txt"));
  if (passive < 0) {
    WARN("this OpenMP runtime does not print GOMP_SPINCOUNT: the wait policy is not checked");
    return;
  }
  CHECK(passive == 0);
  info(dir, "OMP_WAIT_POLICY=active OMP_DISPLAY_ENV=verbose", "");
  CHECK(last_spin_count(tear::test::read_bytes(dir / "err.txt")) > 300000);
}

TEST_CASE("threads: --threads, OMP_NUM_THREADS and SLURM_CPUS_PER_TASK limit the CPU threads", "[threads][cli]") {
  TempDir dir;
  tear::write_mesh(tear::test::regular_sheet(), (dir / "sheet.obj").string());
  CHECK(info(dir, "", "--threads 3")["device_name"] == "CPU (3 threads)");
  CHECK(info(dir, "OMP_NUM_THREADS=2", "")["device_name"] == "CPU (2 threads)");
  CHECK(info(dir, "SLURM_CPUS_PER_TASK=5", "")["device_name"] == "CPU (5 threads)");
  // OMP_NUM_THREADS wins over Slurm's count, --threads over both.
  CHECK(info(dir, "SLURM_CPUS_PER_TASK=5 OMP_NUM_THREADS=2", "")["device_name"] == "CPU (2 threads)");
  CHECK(info(dir, "OMP_NUM_THREADS=2", "--threads 1")["device_name"] == "CPU (1 threads)");
  const tear::test::Run bad = dir.tear("info " + quoted(dir / "sheet.obj") + " --threads 0");
  CHECK(bad.exit_code == 1);
}
