// tear: the built-in benchmark of `tear bench`: remesh time per cut and solver time per iteration
// on generated sheets, and the paper's scene frame by frame.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "tear/cloth.h"
#include "tear/demo_scene.h"
#include "tear/device.h"

namespace tear {

/// Options of `run_remesh_bench`; mirrored by `tear bench`'s flags.
struct BenchOptions {
  /// Sheet sizes in faces: the paper's Table 1 rows, then powers of two up to 4M (2M faces: about
  /// 1M nodes, the solver's reference size).
  std::vector<index_t> face_counts{2822, 9022, 38298, 65536, 262144, 1048576, 2097152, 4194304};
  int repeats = 7;    ///< timed runs per size and backend; the median is reported
  int warmup = 2;     ///< untimed runs first
  int segments = 16;  ///< segments of the cut's polyline (a zigzag across the sheet)
  int iterations = 100;  ///< solver iterations per step (`run_pd_bench`) and per frame (`run_scene_bench`)
  /// Resolutions of the paper's scene (`run_scene_bench`).
  std::vector<DemoResolution> resolutions{DemoResolution::low, DemoResolution::medium, DemoResolution::high};
};

/// The most faces of a benchmark sheet: 2^28, within reach of the 32-bit node indices of a cut
/// sheet with room to spare (and far beyond any memory the benchmark can fill).
inline constexpr index_t max_bench_faces = index_t(1) << 28;

/// Checks `options` before any benchmark runs, so that a bad size is refused before the first
/// table line: every face count even, at least 2, not 6 (what `make_sheet` can tile) and at most
/// `max_bench_faces`; repeats, warmup and iterations in the ranges of `tear bench`'s flags. Throws a
/// usage `Error` naming the flag ("--faces 3: ...").
void check_bench_options(const BenchOptions& options);

/// One size on one backend. Times are medians over the repeats, milliseconds.
struct BenchRow {
  index_t faces = 0;
  Device device = Device::cpu;
  std::string device_name;
  double remesh_ms = 0;  ///< a whole cut without stage timing (the figure to compare)
  std::array<double, static_cast<int>(CutStage::count)> stage_ms{};  ///< with a sync after each stage
  double faces_per_s = 0;  ///< faces of the input sheet over remesh_ms
  index_t nodes_after = 0, faces_after = 0;
  /// Most memory held during a cut, the cloth's arrays and scratch included (`memory_peak`).
  std::size_t peak_bytes = 0;
};

/// The solver on one size and backend: one step of `iterations` iterations (one substep) of a sheet
/// pinned along its top edge, default material. Times are medians, milliseconds.
struct PdBenchRow {
  index_t faces = 0, nodes = 0, constraints = 0;
  Device device = Device::cpu;
  std::string device_name;
  int iterations = 0;
  double step_ms = 0;                 ///< one step: prediction, the iterations, velocities
  double iteration_ms = 0;            ///< step_ms / iterations
  double node_iterations_per_s = 0;   ///< nodes × iterations / step time
  std::size_t bytes_per_iteration = 0;  ///< `PdSolver::bytes_per_iteration`
  double floor_ms = 0;                ///< iterations × bytes_per_iteration at the measured copy bandwidth
  std::size_t peak_bytes = 0;  ///< most memory held while building and stepping (`memory_peak`)
};

/// The paper's scene (`demo_script` at one resolution) run in memory with `iterations` solver
/// iterations per frame in one substep, as the paper's measurements do: remesh, solver rebuild
/// after cuts and simulation, no output. Wall times in milliseconds; the median run of the repeats.
struct SceneBenchRow {
  std::string resolution;
  index_t faces_start = 0, faces_end = 0;
  Device device = Device::cpu;
  std::string device_name;
  int frames = 0, iterations = 0;
  double frame_ms_mean = 0, frame_ms_max = 0;  ///< per frame, cut frames included
  double remesh_ms = 0, simulation_ms = 0;     ///< totals over the frames
};

/// The pull scene (`demo_script(DemoScene::pull)` at one resolution, its own substeps and
/// iterations) run in memory: what tearing costs against the solver. Per-frame means over the 48
/// frames, milliseconds (`TearStats`); the median run of the repeats, by `frame_ms_mean`.
struct TearBenchRow {
  std::string resolution;
  index_t faces_start = 0, faces_end = 0;
  Device device = Device::cpu;
  std::string device_name;
  int frames = 0;
  index_t tear_events = 0;     ///< faces torn over the run
  double frame_ms_mean = 0;    ///< wall per frame, everything included
  double solver_ms = 0;        ///< the substeps
  double check_ms = 0;         ///< deciding where to tear, after every substep
  double limit_ms = 0;         ///< of which the strain rate limit
  double view_ms = 0;          ///< of which waiting for crack growth's view after a tear
  double apply_ms = 0;         ///< laying the cracks (remesher) where a substep tore
  double rebuild_ms = 0;       ///< the solver's model rebuilt after a tear
  /// (check + apply + rebuild) / solver: tearing's share against the solver's time.
  double tear_fraction = 0;
};

/// A collision scene at one resolution run in memory: what the collision pass costs against the
/// solver. `fold`: the punch scene's horizontal sheet 5 cm above a floor, its left strip carried over
/// to its right side so that it folds onto itself; `drape`: the drape demo scene (`demo_script(
/// DemoScene::drape)`). Per-frame means, milliseconds (`TearStats`); the median run of the repeats.
struct CollisionBenchRow {
  std::string scene, resolution;
  index_t faces_start = 0, faces_end = 0;
  Device device = Device::cpu;
  std::string device_name;
  int frames = 0;
  double frame_ms_mean = 0;   ///< wall per frame, everything included
  double solver_ms = 0;       ///< the substeps
  double collision_ms = 0;    ///< the collision pass after them
  double collision_fraction = 0;  ///< collision / solver
  double bytes_per_face = 0;  ///< the collision pass's arrays at the end, per face
  std::int64_t held_nodes = 0;  ///< nodes sent back to the start of a substep (the last resort)
};

/// A frame written and read back in one format, the way `tear run` writes it: the mesh of a cloth
/// (`Cloth::mesh` on the CPU: UVs, normals, velocities, ids and origins) of an irregular sheet.
/// Medians over the repeats, milliseconds.
struct IoBenchRow {
  index_t faces = 0;
  std::string format;       ///< "obj", "ply", "gltf" or "glb"
  std::size_t bytes = 0;    ///< the file's size
  double encode_ms = 0;     ///< `encode_mesh` into a kept buffer
  double write_ms = 0;      ///< `write_file_atomically`: written, flushed to the disk and renamed
  double read_ms = 0;       ///< `read_mesh` of the file, its checks included
};

/// Copy bandwidth of `device`'s memory: bytes read plus bytes written per second by a copy of a
/// 256 MiB buffer (larger than any cache), the best of 10.
double measure_copy_bandwidth(Device device);

std::vector<PdBenchRow> run_pd_bench(const BenchOptions& options, Device device, double copy_bandwidth);
std::vector<SceneBenchRow> run_scene_bench(const BenchOptions& options, Device device);
/// The pull scene at each of `options.resolutions` (`options.iterations` is not used: the scene
/// keeps its own solver settings).
std::vector<TearBenchRow> run_tear_bench(const BenchOptions& options, Device device);

/// The fold and drape scenes at each of `options.resolutions`.
std::vector<CollisionBenchRow> run_collision_bench(const BenchOptions& options, Device device);

/// The fold scene of `run_collision_bench` (and of the collision tests' kind): its sheet at
/// `resolution` and its script (self-collision at `demo_collision_thickness`).
Mesh make_fold_mesh(DemoResolution resolution);
CutScript fold_script();

/// Every format at every size of `options.face_counts`, written in `folder` (which must exist; the
/// files are removed after each size).
std::vector<IoBenchRow> run_io_bench(const BenchOptions& options, const std::string& folder);

/// The zigzag cut of the benchmark: `segments` segments across the unit sheet, in rest-xy.
CutLine bench_cut(int segments);

/// Runs the remesh benchmark for every size on `device`: each run cuts a fresh copy of an
/// irregular sheet (`make_sheet`, seed 1) once; uploading the sheet is not timed.
std::vector<BenchRow> run_remesh_bench(const BenchOptions& options, Device device);

/// One JSON object per row, on one line, with every field (for `tear bench --json`).
std::string to_json(const BenchRow& row);
std::string to_json(const PdBenchRow& row);
std::string to_json(const SceneBenchRow& row);
std::string to_json(const TearBenchRow& row);
std::string to_json(const CollisionBenchRow& row);
std::string to_json(const IoBenchRow& row);

}  // namespace tear
