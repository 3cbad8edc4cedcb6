// `tear bench`: the built-in benchmark on generated sheets and the paper's scene.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "tear/bench.h"
#include "tear/error.h"
#include "tear/output_files.h"
#include "tear/write_mesh.h"

namespace tear::cli {

namespace {
struct BenchArgs {
  std::string device = "auto";
  std::vector<index_t> faces;
  int repeats = 7;
  int warmup = 2;
  int iterations = 100;
  std::vector<std::string> resolutions;
  std::vector<std::string> only;
  std::string json_path;
  std::string io_folder;
  bool no_cpu = false;
};

/// A folder of this process inside `parent`, removed with what is left in it when it goes.
class ScratchFolder {
 public:
  explicit ScratchFolder(const std::string& parent) {
    const std::filesystem::path base =
        parent.empty() ? std::filesystem::temp_directory_path() : std::filesystem::path(parent);
    path_ = base / ("tear-bench-io." + std::to_string(::getpid()));
    std::error_code error;
    std::filesystem::create_directories(path_, error);
    if (error) throw runtime_error(path_.string() + ": cannot create the benchmark's folder: " + error.message());
  }
  ~ScratchFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  std::string path() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

double mib(std::size_t bytes) { return double(bytes) / (1 << 20); }

void print_remesh_row(const BenchRow& r, const BenchRow* cpu) {
  std::printf("%10d  %-4s  %10.3f  %12.3e", r.faces, to_string(r.device), r.remesh_ms, r.faces_per_s);
  for (double ms : r.stage_ms) std::printf("  %8.3f", ms);
  std::printf("  %9.1f  %7.0f", mib(r.peak_bytes), double(r.peak_bytes) / r.faces);
  if (cpu && r.remesh_ms > 0) std::printf("  %8.1fx", cpu->remesh_ms / r.remesh_ms);
  std::printf("\n");
}

void print_pd_row(const PdBenchRow& r, const PdBenchRow* cpu) {
  std::printf("%10d  %9d  %-4s  %9.3f  %10.4f  %12.3e  %9.1f  %9.3f  %6.0f%%", r.faces, r.nodes, to_string(r.device),
              r.step_ms, r.iteration_ms, r.node_iterations_per_s, double(r.bytes_per_iteration) / r.nodes, r.floor_ms,
              r.step_ms > 0 ? 100.0 * r.floor_ms / r.step_ms : 0.0);
  std::printf("  %9.1f", mib(r.peak_bytes));
  if (cpu && r.step_ms > 0) std::printf("  %8.1fx", cpu->step_ms / r.step_ms);
  std::printf("\n");
}

void print_scene_row(const SceneBenchRow& r, const SceneBenchRow* cpu) {
  std::printf("%-7s  %8d  %8d  %-4s  %9.3f  %9.3f  %10.2f  %12.2f", r.resolution.c_str(), r.faces_start, r.faces_end,
              to_string(r.device), r.frame_ms_mean, r.frame_ms_max, r.remesh_ms, r.simulation_ms);
  if (cpu && r.frame_ms_mean > 0) std::printf("  %8.1fx", cpu->frame_ms_mean / r.frame_ms_mean);
  std::printf("\n");
}

void print_tear_row(const TearBenchRow& r, const TearBenchRow* cpu) {
  std::printf("%-7s  %8d  %8d  %-4s  %7d  %9.3f  %9.3f  %8.3f  %8.3f  %8.3f  %8.3f  %8.3f  %7.1f%%",
              r.resolution.c_str(), r.faces_start, r.faces_end, to_string(r.device), r.tear_events, r.frame_ms_mean,
              r.solver_ms, r.check_ms, r.limit_ms, r.view_ms, r.apply_ms, r.rebuild_ms, 100 * r.tear_fraction);
  if (cpu && r.frame_ms_mean > 0) std::printf("  %8.1fx", cpu->frame_ms_mean / r.frame_ms_mean);
  std::printf("\n");
}

void print_collision_row(const CollisionBenchRow& r, const CollisionBenchRow* cpu) {
  std::printf("%-6s  %-7s  %8d  %8d  %-4s  %9.3f  %9.3f  %9.3f  %8.1f%%  %9.0f  %6lld", r.scene.c_str(),
              r.resolution.c_str(), r.faces_start, r.faces_end, to_string(r.device), r.frame_ms_mean, r.solver_ms,
              r.collision_ms, 100 * r.collision_fraction, r.bytes_per_face, static_cast<long long>(r.held_nodes));
  if (cpu && r.frame_ms_mean > 0) std::printf("  %8.1fx", cpu->frame_ms_mean / r.frame_ms_mean);
  std::printf("\n");
  std::fflush(stdout);
}

void print_io_row(const IoBenchRow& r) {
  const double mb = double(r.bytes) * 1e-6;
  std::printf("%10d  %-6s  %9.1f  %9.3f  %9.3f  %9.3f  %9.0f  %9.0f\n", r.faces, r.format.c_str(), mb, r.encode_ms,
              r.write_ms, r.read_ms, r.encode_ms > 0 ? mb / (r.encode_ms * 1e-3) : 0.0,
              r.read_ms > 0 ? mb / (r.read_ms * 1e-3) : 0.0);
}

/// Runs one part size by size: `run(options of one size, device)` gives the size's row, printed
/// (after the CPU's, with the ratio, when `with_cpu`) and returned with the CPU's in the JSON rows.
template <class Run, class Print>
nlohmann::json run_sizes(const BenchOptions& options, Device device, bool with_cpu, Run run, Print print) {
  nlohmann::json rows = nlohmann::json::array();
  for (index_t faces : options.face_counts) {
    BenchOptions one = options;
    one.face_counts = {faces};
    const auto row = run(one, device);
    rows.push_back(nlohmann::json::parse(to_json(row)));
    if (with_cpu) {
      const auto cpu = run(one, Device::cpu);
      rows.push_back(nlohmann::json::parse(to_json(cpu)));
      print(cpu, nullptr);
      print(row, &cpu);
    } else {
      print(row, nullptr);
    }
    std::fflush(stdout);
  }
  return rows;
}

/// Prints and collects the rows of a part run on `device` and, when `with_cpu`, on the CPU too
/// (each CPU row first, then the device's with the ratio).
template <class Row, class Run, class Print>
nlohmann::json run_paired(Device device, bool with_cpu, Run run, Print print) {
  const std::vector<Row> gpu = run(device);
  std::vector<Row> cpu;
  if (with_cpu) cpu = run(Device::cpu);
  nlohmann::json rows = nlohmann::json::array();
  for (std::size_t i = 0; i < gpu.size(); ++i) {
    if (with_cpu) {
      print(cpu[i], nullptr);
      rows.push_back(nlohmann::json::parse(to_json(cpu[i])));
    }
    print(gpu[i], with_cpu ? &cpu[i] : nullptr);
    rows.push_back(nlohmann::json::parse(to_json(gpu[i])));
  }
  return rows;
}

bool wanted(const BenchArgs& args, const std::string& part) {
  if (args.only.empty()) return true;
  for (const std::string& p : args.only)
    if (p == part) return true;
  return false;
}

/// The benchmark's options from the command line; `--only` parts and `--resolutions` checked.
BenchOptions bench_options(const BenchArgs& args) {
  BenchOptions options;
  if (!args.faces.empty()) options.face_counts = args.faces;
  options.repeats = args.repeats;
  options.warmup = args.warmup;
  options.iterations = args.iterations;
  if (!args.resolutions.empty()) {
    options.resolutions.clear();
    for (const std::string& r : args.resolutions) {
      try {
        options.resolutions.push_back(parse_demo_resolution(r));
      } catch (const Error&) {
        throw Error(ErrorKind::usage, "--resolutions " + r + ": expected low, medium or high");
      }
    }
  }
  return options;
}

nlohmann::json bench_remesh(const BenchOptions& options, Device device, bool with_cpu) {
  std::printf("\nremesh: one cut by a %d-segment zigzag across an irregular sheet\n", options.segments);
  std::printf("%10s  %-4s  %10s  %12s", "faces", "dev", "remesh", "faces/s");
  for (int s = 0; s < static_cast<int>(CutStage::count); ++s)
    std::printf("  %8.8s", to_string(static_cast<CutStage>(s)));
  std::printf("  %9s  %7s%s\n", "peak MiB", "B/face", with_cpu ? "  cpu/gpu" : "");
  std::fflush(stdout);
  return run_sizes(
      options, device, with_cpu, [](const BenchOptions& one, Device d) { return run_remesh_bench(one, d)[0]; },
      print_remesh_row);
}

void bench_pd(const BenchOptions& options, Device device, bool with_cpu, nlohmann::json& doc) {
  const double bandwidth = measure_copy_bandwidth(device);
  const double cpu_bandwidth = with_cpu ? measure_copy_bandwidth(Device::cpu) : 0.0;
  std::printf("\nsolver: one step of %d iterations, sheet pinned along its top edge; copy bandwidth %.0f GB/s",
              options.iterations, bandwidth * 1e-9);
  if (with_cpu) std::printf(" (cpu %.0f GB/s)", cpu_bandwidth * 1e-9);
  std::printf("\n%10s  %9s  %-4s  %9s  %10s  %12s  %9s  %9s  %7s  %9s%s\n", "faces", "nodes", "dev", "step",
              "iteration", "node-it/s", "B/node-it", "floor", "of copy", "peak MiB", with_cpu ? "  cpu/gpu" : "");
  std::fflush(stdout);
  const nlohmann::json rows = run_sizes(
      options, device, with_cpu,
      [&](const BenchOptions& one, Device d) {
        return run_pd_bench(one, d, d == device ? bandwidth : cpu_bandwidth)[0];
      },
      print_pd_row);
  doc["copy_bandwidth_bytes_per_s"] = bandwidth;
  if (with_cpu) doc["cpu_copy_bandwidth_bytes_per_s"] = cpu_bandwidth;
  doc["pd"] = rows;
}

nlohmann::json bench_scene(const BenchOptions& options, Device device, bool with_cpu) {
  std::printf("\nscene: the paper's (tear demo), %d iterations per frame, no output; ms per frame\n",
              options.iterations);
  std::printf("%-7s  %8s  %8s  %-4s  %9s  %9s  %10s  %12s%s\n", "size", "faces", "at end", "dev", "mean", "max",
              "remesh", "simulation", with_cpu ? "  cpu/gpu" : "");
  std::fflush(stdout);
  return run_paired<SceneBenchRow>(
      device, with_cpu, [&](Device d) { return run_scene_bench(options, d); }, print_scene_row);
}

nlohmann::json bench_tear(const BenchOptions& options, Device device, bool with_cpu) {
  std::printf(
      "\ntear: the pull scene (tear demo --scene pull), its own substeps and iterations, no output; "
      "per-frame means in ms; limit and view are parts of check\n");
  std::printf("%-7s  %8s  %8s  %-4s  %7s  %9s  %9s  %8s  %8s  %8s  %8s  %8s  %8s%s\n", "size", "faces", "at end", "dev",
              "torn", "frame", "solver", "check", "(limit", "view)", "apply", "rebuild", "tear/sol",
              with_cpu ? "  cpu/gpu" : "");
  std::fflush(stdout);
  return run_paired<TearBenchRow>(
      device, with_cpu, [&](Device d) { return run_tear_bench(options, d); }, print_tear_row);
}

nlohmann::json bench_collide(const BenchOptions& options, Device device, bool with_cpu) {
  std::printf(
      "\ncollide: a sheet folded onto itself (fold) and one falling onto a turning box (tear demo --scene drape), "
      "self-collision on, no output; per-frame means in ms\n");
  std::printf("%-6s  %-7s  %8s  %8s  %-4s  %9s  %9s  %9s  %9s  %9s  %6s%s\n", "scene", "size", "faces", "at end", "dev",
              "frame", "solver", "collide", "col/sol", "B/face", "held", with_cpu ? "  cpu/gpu" : "");
  std::fflush(stdout);
  return run_paired<CollisionBenchRow>(
      device, with_cpu, [&](Device d) { return run_collision_bench(options, d); }, print_collision_row);
}

nlohmann::json bench_io(const BenchOptions& options, const std::string& io_folder) {
  const ScratchFolder folder(io_folder);
  std::printf(
      "\nio: a cloth's frame (UVs, normals, velocities, ids, origins) encoded, written atomically "
      "(flushed to the disk) and read back in %s\n",
      folder.path().c_str());
  std::printf("%10s  %-6s  %9s  %9s  %9s  %9s  %9s  %9s\n", "faces", "format", "MB", "encode", "write", "read",
              "enc MB/s", "read MB/s");
  std::fflush(stdout);
  nlohmann::json rows = nlohmann::json::array();
  for (index_t faces : options.face_counts) {
    BenchOptions one = options;
    one.face_counts = {faces};
    for (const IoBenchRow& row : run_io_bench(one, folder.path())) {
      print_io_row(row);
      rows.push_back(nlohmann::json::parse(to_json(row)));
    }
    std::fflush(stdout);
  }
  return rows;
}

void run_bench(const BenchArgs& args) {
  for (const std::string& part : args.only)
    if (part != "remesh" && part != "pd" && part != "scene" && part != "tear" && part != "collide" && part != "io")
      throw Error(ErrorKind::usage, "--only " + part + ": expected remesh, pd, scene, tear, collide or io");
  const Device device = select_device(args.device);
  const bool with_cpu = device == Device::cuda && !args.no_cpu;
  const BenchOptions options = bench_options(args);
  // Everything that can be refused is, before the first line of a table: the sizes, and that the
  // JSON file can be written.
  check_bench_options(options);
  check_output_files({}, nullptr, 0, {{"the JSON output", args.json_path}});
  if (!args.json_path.empty()) remove_stale_temporaries({args.json_path});
  std::printf("tear bench on %s%s; medians of %d runs after %d untimed, milliseconds\n", device_name(device).c_str(),
              with_cpu ? (" and " + device_name(Device::cpu)).c_str() : "", options.repeats, options.warmup);
  nlohmann::json doc = {{"device_name", device_name(device)}, {"cpu_name", device_name(Device::cpu)},
                        {"repeats", options.repeats},         {"warmup", options.warmup},
                        {"iterations", options.iterations},   {"segments", options.segments}};
  if (wanted(args, "remesh")) doc["remesh"] = bench_remesh(options, device, with_cpu);
  if (wanted(args, "pd")) bench_pd(options, device, with_cpu, doc);
  if (wanted(args, "scene")) doc["scene"] = bench_scene(options, device, with_cpu);
  if (wanted(args, "tear")) doc["tear"] = bench_tear(options, device, with_cpu);
  if (wanted(args, "collide")) doc["collide"] = bench_collide(options, device, with_cpu);
  if (wanted(args, "io")) doc["io"] = bench_io(options, args.io_folder);
  if (!args.json_path.empty()) write_file_atomically(args.json_path, doc.dump(2) + "\n");
}
}  // namespace

void add_bench_command(CLI::App& app) {
  auto args = std::make_shared<BenchArgs>();
  CLI::App* cmd = app.add_subcommand("bench", "Benchmark the remesher and the solver on generated sheets");
  cmd->footer(
      "Five parts. remesh: each size is an irregular sheet (the paper's Table 1 sizes, then powers of two up "
      "to 4M faces) cut once by a zigzag of 16 segments, a fresh copy each run; stage columns come from "
      "separate runs with a device synchronisation after each stage. pd: one solver step of --iterations "
      "iterations on each size, with the traffic floor at the measured copy bandwidth. scene: the paper's "
      "scene (tear demo) at its three resolutions with --iterations iterations per frame, in memory. tear: the "
      "pull scene (tear demo --scene pull) at the same resolutions with its own solver settings, in memory: "
      "the substeps, deciding where to tear, laying the cracks and rebuilding the solver's model, per frame, "
      "and tearing's share of the solver's time. io: at each size a cloth's frame encoded, written atomically "
      "and read back in OBJ, PLY, glTF and GLB, on the host (no backend). Times "
      "are medians in milliseconds; on the GPU the CPU backend of the same binary runs too, for the cpu/gpu "
      "ratio. No time is asserted.");
  add_device_option(*cmd, args->device);
  cmd->add_option("--faces", args->faces, "Sheet sizes in faces, comma separated (even, >= 2)")->delimiter(',');
  cmd->add_option("--repeats", args->repeats, "Timed runs per size and backend (median reported)")
      ->check(CLI::Range(1, 1000));
  cmd->add_option("--warmup", args->warmup, "Untimed runs before the timed ones")->check(CLI::Range(0, 1000));
  cmd->add_option("--iterations", args->iterations, "Solver iterations per step (pd) and per frame (scene)")
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--resolutions", args->resolutions,
                  "Resolutions of the scene part: low, medium, high (comma separated)")
      ->delimiter(',');
  cmd->add_option("--only", args->only, "Run only these parts: remesh, pd, scene, tear, collide, io (comma separated)")
      ->delimiter(',');
  cmd->add_option("--json", args->json_path, "Also write every number to this JSON file");
  cmd->add_option("--io-folder", args->io_folder,
                  "Folder the io part writes its files in (a folder of its own inside, removed after; default: "
                  "the system's temporary folder)");
  cmd->add_flag("--no-cpu", args->no_cpu, "On the GPU, skip the CPU-backend comparison");
  cmd->callback([args] { run_bench(*args); });
}

}  // namespace tear::cli
