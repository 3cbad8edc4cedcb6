#include "tear/bench.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <system_error>

#include <nlohmann/json.hpp>

#include "bench/bench_device.h"
#include "tear/demo_scene.h"
#include "tear/error.h"
#include "tear/make_sheet.h"
#include "tear/read_mesh.h"
#include "tear/run_cuts.h"
#include "tear/simulation.h"
#include "tear/write_mesh.h"

namespace tear {

namespace {
/// Device names come from drivers: replace bytes that are not UTF-8 rather than fail on them.
std::string json_text(const nlohmann::json& j) {
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

/// The median of `runs` by mean frame time (the scene and tear parts' rows).
template <class Row>
Row median_run(std::vector<Row> runs) {
  std::sort(runs.begin(), runs.end(), [](const Row& a, const Row& b) { return a.frame_ms_mean < b.frame_ms_mean; });
  return runs[runs.size() / 2];
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}
}  // namespace

void check_bench_options(const BenchOptions& options) {
  for (index_t faces : options.face_counts)
    if (faces < 2 || faces % 2 != 0 || faces == 6 || faces > max_bench_faces)
      throw Error(ErrorKind::usage, "--faces " + std::to_string(faces) +
                                        ": expected an even number of faces from 2 to " +
                                        std::to_string(max_bench_faces) + ", not 6 (what a sheet can be tiled with)");
  if (options.face_counts.empty()) throw Error(ErrorKind::usage, "--faces: expected at least one size");
  if (options.repeats < 1 || options.repeats > 1000)
    throw Error(ErrorKind::usage, "--repeats " + std::to_string(options.repeats) + ": expected 1..1000");
  if (options.warmup < 0 || options.warmup > 1000)
    throw Error(ErrorKind::usage, "--warmup " + std::to_string(options.warmup) + ": expected 0..1000");
  if (options.iterations < 1 || options.iterations > 100000)
    throw Error(ErrorKind::usage, "--iterations " + std::to_string(options.iterations) + ": expected 1..100000");
  if (options.segments < 1)
    throw Error(ErrorKind::usage, "segments " + std::to_string(options.segments) + ": expected >= 1");
}

CutLine bench_cut(int segments) {
  CutLine line;
  line.source = CutLine::Source::node_rest;
  for (int i = 0; i <= segments; ++i) {
    const double x = -0.05 + 1.1 * i / segments;
    line.polyline.push_back({x, i % 2 ? 0.53 : 0.47});
  }
  return line;
}

std::vector<BenchRow> run_remesh_bench(const BenchOptions& options, Device device) {
  std::vector<BenchRow> rows;
  const std::vector<CutLine> cut{bench_cut(options.segments)};
  for (index_t faces : options.face_counts) {
    SheetOptions sheet;
    sheet.face_count = faces;
    const Mesh mesh = make_sheet(sheet);
    BenchRow row;
    row.faces = faces;
    row.device = device;
    row.device_name = device_name(device);
    std::vector<double> totals;
    std::vector<std::vector<double>> stages(static_cast<int>(CutStage::count));
    std::size_t peak = 0;
    for (int run = 0; run < options.warmup + 2 * options.repeats; ++run) {
      reset_memory_peak(device);
      const std::size_t before = memory_in_use(device);
      Cloth cloth(mesh, device);  // a fresh cloth each time: cutting a torn cloth again is a no-op
      synchronize(device);        // the cloth's own setup, still queued on the device, is not the cut's
      CutOptions cut_options;
      const bool timed = run >= options.warmup, staged = timed && (run - options.warmup) % 2 == 1;
      cut_options.time_stages = staged;
      const CutStats stats = cloth.cut(cut, cut_options);
      row.nodes_after = stats.nodes_after;
      row.faces_after = stats.faces_after;
      peak = std::max(peak, memory_peak(device) - before);
      if (!timed) continue;
      if (staged)
        for (std::size_t s = 0; s < stages.size(); ++s) stages[s].push_back(stats.stage_ms[s]);
      else
        totals.push_back(stats.total_ms);
    }
    row.remesh_ms = median(totals);
    for (std::size_t s = 0; s < stages.size(); ++s) row.stage_ms[s] = median(stages[s]);
    row.faces_per_s = row.remesh_ms > 0 ? faces / (row.remesh_ms * 1e-3) : 0;
    row.peak_bytes = peak;
    rows.push_back(row);
  }
  return rows;
}

double measure_copy_bandwidth(Device device) {
  const std::size_t bytes = std::size_t(256) << 20;
  const double seconds = backend::dispatch(
      device, [&](auto system) { return backend::fastest_copy_seconds<decltype(system)>(bytes, 10); });
  return seconds > 0 ? 2.0 * double(bytes) / seconds : 0.0;
}

std::vector<PdBenchRow> run_pd_bench(const BenchOptions& options, Device device, double copy_bandwidth) {
  using Clock = std::chrono::steady_clock;
  std::vector<PdBenchRow> rows;
  for (index_t faces : options.face_counts) {
    SheetOptions sheet;
    sheet.face_count = faces;
    const Mesh mesh = make_sheet(sheet);
    SimulationOptions sim;
    sim.substeps = 1;
    sim.iterations = options.iterations;
    Pin top;
    top.min = {-1, 1 - 1e-6, -1};
    top.max = {2, 1 + 1e-6, 1};
    sim.pins = {top};
    reset_memory_peak(device);
    const std::size_t before = memory_in_use(device);
    PdSolver solver(mesh.face_nodes, mesh.node_pos, mesh.node_count(), sim, device);
    std::vector<double> times;
    for (int run = 0; run < options.warmup + options.repeats; ++run) {
      synchronize(device);
      const Clock::time_point start = Clock::now();
      solver.step();
      synchronize(device);
      if (run >= options.warmup)
        times.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
    }
    PdBenchRow row;
    row.faces = faces;
    row.nodes = mesh.node_count();
    row.constraints = solver.constraint_count();
    row.device = device;
    row.device_name = device_name(device);
    row.iterations = sim.iterations;
    row.step_ms = median(times);
    row.iteration_ms = row.step_ms / sim.iterations;
    row.node_iterations_per_s = row.step_ms > 0 ? double(row.nodes) * sim.iterations / (row.step_ms * 1e-3) : 0;
    row.bytes_per_iteration = solver.bytes_per_iteration();
    row.floor_ms = copy_bandwidth > 0 ? 1e3 * double(row.bytes_per_iteration) * sim.iterations / copy_bandwidth : 0;
    row.peak_bytes = memory_peak(device) - before;
    rows.push_back(row);
  }
  return rows;
}

std::vector<SceneBenchRow> run_scene_bench(const BenchOptions& options, Device device) {
  using Clock = std::chrono::steady_clock;
  std::vector<SceneBenchRow> rows;
  for (DemoResolution resolution : options.resolutions) {
    CutScript script = demo_script();
    script.simulation->substeps = 1;
    script.simulation->iterations = options.iterations;
    const Mesh mesh = make_demo_sheet(resolution);
    std::vector<SceneBenchRow> runs;
    for (int run = 0; run < options.warmup + options.repeats; ++run) {
      SceneBenchRow row;
      row.resolution = to_string(resolution);
      row.faces_start = mesh.face_count();
      row.device = device;
      row.device_name = device_name(device);
      row.iterations = options.iterations;
      Cloth cloth(mesh, device);
      synchronize(device);
      Clock::time_point last = Clock::now();
      double total = 0;
      run_cuts(cloth, script, script.frames, [&](const FrameResult& frame, const Cloth& c) {
        const Clock::time_point now = Clock::now();  // run_cuts waited for the frame's step
        const double ms = std::chrono::duration<double, std::milli>(now - last).count();
        last = now;
        total += ms;
        row.frame_ms_max = std::max(row.frame_ms_max, ms);
        row.remesh_ms += frame.remesh_ms;
        row.simulation_ms += frame.simulation_ms;
        row.frames = frame.frame;
        row.faces_end = c.face_count();
      });
      row.frame_ms_mean = row.frames > 0 ? total / row.frames : 0;
      if (run >= options.warmup) runs.push_back(row);
    }
    rows.push_back(median_run(std::move(runs)));
  }
  return rows;
}

std::vector<TearBenchRow> run_tear_bench(const BenchOptions& options, Device device) {
  using Clock = std::chrono::steady_clock;
  std::vector<TearBenchRow> rows;
  for (DemoResolution resolution : options.resolutions) {
    const CutScript script = demo_script(DemoScene::pull);
    const Mesh mesh = make_demo_mesh(DemoScene::pull, resolution);
    std::vector<TearBenchRow> runs;
    for (int run = 0; run < options.warmup + options.repeats; ++run) {
      TearBenchRow row;
      row.resolution = to_string(resolution);
      row.faces_start = mesh.face_count();
      row.device = device;
      row.device_name = device_name(device);
      Cloth cloth(mesh, device);
      synchronize(device);
      const Clock::time_point start = Clock::now();
      run_cuts(cloth, script, script.frames, [&](const FrameResult& frame, const Cloth& c) {
        const TearStats torn = c.last_tear();
        row.solver_ms += torn.solver_ms;
        row.check_ms += torn.check_ms;
        row.limit_ms += torn.limit_ms;
        row.view_ms += torn.view_ms;
        row.apply_ms += torn.apply_ms;
        row.rebuild_ms += torn.rebuild_ms;
        row.tear_events += torn.events;
        row.frames = frame.frame;
        row.faces_end = c.face_count();
      });
      const double total = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
      if (row.frames > 0) {
        row.frame_ms_mean = total / row.frames;
        for (double* ms : {&row.solver_ms, &row.check_ms, &row.limit_ms, &row.view_ms, &row.apply_ms, &row.rebuild_ms})
          *ms /= row.frames;
      }
      if (row.solver_ms > 0) row.tear_fraction = (row.check_ms + row.apply_ms + row.rebuild_ms) / row.solver_ms;
      if (run >= options.warmup) runs.push_back(row);
    }
    rows.push_back(median_run(std::move(runs)));
  }
  return rows;
}

Mesh make_fold_mesh(DemoResolution resolution) {
  Mesh mesh = make_demo_mesh(DemoScene::punch, resolution);
  for (std::size_t i = 1; i < mesh.node_pos.size(); i += 3) mesh.node_pos[i] = 0.05f;
  return mesh;
}

CutScript fold_script() {
  const nlohmann::json script = {
      {"version", 1},
      {"frames", 30},
      {"simulation",
       {{"substeps", 4},
        {"iterations", 40},
        {"colliders", {{{"plane", {{"point", {0, 0, 0}}, {"normal", {0, 1, 0}}}}}}},
        {"collision", {{"self", true}, {"thickness", demo_collision_thickness}, {"friction", 0.2}}},
        {"pins",
         {{{"box", {{"min", {-1, -1, -1}}, {"max", {0.03, 1, 2}}}},
           {"keys",
            {{{"frame", 0}, {"offset", {0, 0, 0}}},
             {{"frame", 10}, {"offset", {0.3, 0.25, 0}}},
             {{"frame", 20}, {"offset", {0.85, 0.05, 0}}}}}}}}}}};
  return parse_cut_script(script.dump(), "(bench scene: fold)");
}

std::vector<CollisionBenchRow> run_collision_bench(const BenchOptions& options, Device device) {
  using Clock = std::chrono::steady_clock;
  std::vector<CollisionBenchRow> rows;
  for (const char* scene : {"fold", "drape"})
    for (DemoResolution resolution : options.resolutions) {
      const bool fold = std::string(scene) == "fold";
      const CutScript script = fold ? fold_script() : demo_script(DemoScene::drape);
      const Mesh mesh = fold ? make_fold_mesh(resolution) : make_demo_mesh(DemoScene::drape, resolution);
      std::vector<CollisionBenchRow> runs;
      for (int run = 0; run < options.warmup + options.repeats; ++run) {
        CollisionBenchRow row;
        row.scene = scene;
        row.resolution = to_string(resolution);
        row.faces_start = mesh.face_count();
        row.device = device;
        row.device_name = device_name(device);
        Cloth cloth(mesh, device);
        synchronize(device);
        const Clock::time_point start = Clock::now();
        TearStats last;
        run_cuts(cloth, script, script.frames, [&](const FrameResult& frame, const Cloth& c) {
          last = c.last_tear();
          row.solver_ms += last.solver_ms;
          row.collision_ms += last.collision_ms;
          row.frames = frame.frame;
          row.faces_end = c.face_count();
        });
        const double total = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
        if (row.frames > 0) {
          row.frame_ms_mean = total / row.frames;
          row.solver_ms /= row.frames;
          row.collision_ms /= row.frames;
        }
        if (row.solver_ms > 0) row.collision_fraction = row.collision_ms / row.solver_ms;
        row.bytes_per_face = row.faces_end > 0 ? double(last.collision_bytes) / row.faces_end : 0;
        row.held_nodes = last.held_nodes;
        if (run >= options.warmup) runs.push_back(row);
      }
      rows.push_back(median_run(std::move(runs)));
    }
  return rows;
}

std::vector<IoBenchRow> run_io_bench(const BenchOptions& options, const std::string& folder) {
  using Clock = std::chrono::steady_clock;
  const auto ms_since = [](Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  };
  std::vector<IoBenchRow> rows;
  for (index_t faces : options.face_counts) {
    SheetOptions sheet;
    sheet.face_count = faces;
    const Mesh frame = Cloth(make_sheet(sheet), Device::cpu).mesh();
    for (const MeshFormat format : {MeshFormat::obj, MeshFormat::ply, MeshFormat::gltf, MeshFormat::glb}) {
      const char* name = format == MeshFormat::obj    ? "obj"
                         : format == MeshFormat::ply  ? "ply"
                         : format == MeshFormat::gltf ? "gltf"
                                                      : "glb";
      const std::string path = (std::filesystem::path(folder) / ("frame." + std::string(name))).string();
      std::vector<double> encode, write, read;
      std::string bytes;
      for (int run = 0; run < options.warmup + options.repeats; ++run) {
        Clock::time_point start = Clock::now();
        encode_mesh(frame, path, format, bytes);
        const double encoded = ms_since(start);
        start = Clock::now();
        write_file_atomically(path, bytes);
        const double written = ms_since(start);
        start = Clock::now();
        const Mesh back = read_mesh(path);
        const double read_back = ms_since(start);
        if (back.face_count() != frame.face_count())
          throw runtime_error(path + ": read back " + std::to_string(back.face_count()) + " faces, wrote " +
                              std::to_string(frame.face_count()));
        if (run < options.warmup) continue;
        encode.push_back(encoded);
        write.push_back(written);
        read.push_back(read_back);
      }
      std::error_code ignored;
      std::filesystem::remove(path, ignored);
      IoBenchRow row;
      row.faces = faces;
      row.format = name;
      row.bytes = bytes.size();
      row.encode_ms = median(encode);
      row.write_ms = median(write);
      row.read_ms = median(read);
      rows.push_back(row);
    }
  }
  return rows;
}

std::string to_json(const PdBenchRow& row) {
  return json_text({{"faces", row.faces},
                    {"nodes", row.nodes},
                    {"constraints", row.constraints},
                    {"device", to_string(row.device)},
                    {"device_name", row.device_name},
                    {"iterations", row.iterations},
                    {"step_ms", row.step_ms},
                    {"iteration_ms", row.iteration_ms},
                    {"node_iterations_per_s", row.node_iterations_per_s},
                    {"bytes_per_iteration", row.bytes_per_iteration},
                    {"floor_ms", row.floor_ms},
                    {"peak_bytes", row.peak_bytes}});
}

std::string to_json(const SceneBenchRow& row) {
  return json_text({{"resolution", row.resolution},
                    {"faces_start", row.faces_start},
                    {"faces_end", row.faces_end},
                    {"device", to_string(row.device)},
                    {"device_name", row.device_name},
                    {"frames", row.frames},
                    {"iterations", row.iterations},
                    {"frame_ms_mean", row.frame_ms_mean},
                    {"frame_ms_max", row.frame_ms_max},
                    {"remesh_ms", row.remesh_ms},
                    {"simulation_ms", row.simulation_ms}});
}

std::string to_json(const TearBenchRow& row) {
  return json_text({{"resolution", row.resolution},
                    {"faces_start", row.faces_start},
                    {"faces_end", row.faces_end},
                    {"device", to_string(row.device)},
                    {"device_name", row.device_name},
                    {"frames", row.frames},
                    {"tear_events", row.tear_events},
                    {"frame_ms_mean", row.frame_ms_mean},
                    {"solver_ms", row.solver_ms},
                    {"check_ms", row.check_ms},
                    {"limit_ms", row.limit_ms},
                    {"view_ms", row.view_ms},
                    {"apply_ms", row.apply_ms},
                    {"rebuild_ms", row.rebuild_ms},
                    {"tear_fraction", row.tear_fraction}});
}

std::string to_json(const CollisionBenchRow& row) {
  return json_text({{"scene", row.scene},
                    {"resolution", row.resolution},
                    {"faces_start", row.faces_start},
                    {"faces_end", row.faces_end},
                    {"device", to_string(row.device)},
                    {"device_name", row.device_name},
                    {"frames", row.frames},
                    {"frame_ms_mean", row.frame_ms_mean},
                    {"solver_ms", row.solver_ms},
                    {"collision_ms", row.collision_ms},
                    {"collision_fraction", row.collision_fraction},
                    {"bytes_per_face", row.bytes_per_face},
                    {"held_nodes", row.held_nodes}});
}

std::string to_json(const IoBenchRow& row) {
  return json_text({{"faces", row.faces},
                    {"format", row.format},
                    {"bytes", row.bytes},
                    {"encode_ms", row.encode_ms},
                    {"write_ms", row.write_ms},
                    {"read_ms", row.read_ms}});
}

std::string to_json(const BenchRow& row) {
  nlohmann::json stages = nlohmann::json::object();
  for (int s = 0; s < static_cast<int>(CutStage::count); ++s)
    stages[to_string(static_cast<CutStage>(s))] = row.stage_ms[s];
  return json_text({{"faces", row.faces},
                    {"device", to_string(row.device)},
                    {"device_name", row.device_name},
                    {"remesh_ms", row.remesh_ms},
                    {"stage_ms", stages},
                    {"faces_per_s", row.faces_per_s},
                    {"nodes_after", row.nodes_after},
                    {"faces_after", row.faces_after},
                    {"peak_bytes", row.peak_bytes}});
}

}  // namespace tear
