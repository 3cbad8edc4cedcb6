// `tear bench`: the built-in benchmark on generated sheets.
#include <cstdio>
#include <string>
#include <vector>

#include "commands.h"
#include "tear/bench.h"
#include "tear/error.h"
#include "tear/write_mesh.h"

namespace tear::cli {

namespace {
struct BenchArgs {
  std::string device = "auto";
  std::vector<index_t> faces;
  int repeats = 7;
  std::string json_path;
  bool no_cpu = false;
};

void print_row(const BenchRow& r, const BenchRow* cpu) {
  std::printf("%10d  %-4s  %10.3f  %12.3e", r.faces, to_string(r.device), r.remesh_ms, r.faces_per_s);
  for (double ms : r.stage_ms) std::printf("  %8.3f", ms);
  if (cpu && r.remesh_ms > 0) std::printf("  %8.1fx", cpu->remesh_ms / r.remesh_ms);
  std::printf("\n");
}

void run_bench(const BenchArgs& args) {
  const Device device = select_device(args.device);
  BenchOptions options;
  if (!args.faces.empty()) options.face_counts = args.faces;
  options.repeats = args.repeats;
  std::printf("tear bench: remesh by a %d-segment cut, median of %d runs (ms)\n", options.segments, options.repeats);
  std::printf("device: %s\n", device_name(device).c_str());
  std::printf("%10s  %-4s  %10s  %12s", "faces", "dev", "remesh", "faces/s");
  for (int s = 0; s < static_cast<int>(CutStage::count); ++s) std::printf("  %8.8s", to_string(static_cast<CutStage>(s)));
  std::printf("%s\n", device == Device::cuda && !args.no_cpu ? "  cpu/gpu" : "");
  std::fflush(stdout);

  nlohmann::json rows = nlohmann::json::array();
  for (index_t faces : options.face_counts) {
    BenchOptions one = options;
    one.face_counts = {faces};
    const BenchRow row = run_remesh_bench(one, device)[0];
    rows.push_back(to_json(row));
    if (device == Device::cuda && !args.no_cpu) {
      const BenchRow cpu = run_remesh_bench(one, Device::cpu)[0];
      rows.push_back(to_json(cpu));
      print_row(cpu, nullptr);
      print_row(row, &cpu);
    } else {
      print_row(row, nullptr);
    }
    std::fflush(stdout);
  }
  if (!args.json_path.empty()) {
    const nlohmann::json doc = {{"benchmark", "remesh"}, {"segments", options.segments}, {"repeats", options.repeats},
                                {"device_name", device_name(device)}, {"rows", rows}};
    write_file_atomically(args.json_path, doc.dump(2) + "\n");
  }
}
}  // namespace

void add_bench_command(CLI::App& app) {
  auto args = std::make_shared<BenchArgs>();
  CLI::App* cmd = app.add_subcommand("bench", "Benchmark the remesher on generated irregular square sheets");
  cmd->footer(
      "Each size is an irregular sheet (the paper's Table 1 sizes, then powers of two up to 4M faces) cut "
      "once by a zigzag of 16 segments; every run cuts a fresh copy. Times are medians, in milliseconds; "
      "stage columns come from separate runs with a device synchronisation after each stage. On the GPU "
      "the CPU backend of the same binary runs too, for the cpu/gpu ratio. No time is asserted.");
  add_device_option(*cmd, args->device);
  cmd->add_option("--faces", args->faces, "Sheet sizes in faces, comma separated (even, >= 2)")->delimiter(',');
  cmd->add_option("--repeats", args->repeats, "Timed runs per size and backend (median reported)")->check(CLI::Range(1, 1000));
  cmd->add_option("--json", args->json_path, "Also write every number to this JSON file");
  cmd->add_flag("--no-cpu", args->no_cpu, "On the GPU, skip the CPU-backend comparison");
  cmd->callback([args] { run_bench(*args); });
}

}  // namespace tear::cli
