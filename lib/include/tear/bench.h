// tear: the built-in benchmark of `tear bench`: remesh time per cut on generated sheets.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tear/cloth.h"
#include "tear/device.h"

namespace tear {

/// Options of `run_remesh_bench`; mirrored by `tear bench`'s flags.
struct BenchOptions {
  /// Sheet sizes in faces: the paper's Table 1 rows, then powers of two up to 4M.
  std::vector<index_t> face_counts{2822, 9022, 38298, 65536, 262144, 1048576, 4194304};
  int repeats = 7;    ///< timed runs per size and backend; the median is reported
  int warmup = 2;     ///< untimed runs first
  int segments = 16;  ///< segments of the cut's polyline (a zigzag across the sheet)
};

/// One size on one backend. Times are medians over the repeats, milliseconds.
struct BenchRow {
  index_t faces = 0;
  Device device = Device::cpu;
  std::string device_name;
  double remesh_ms = 0;  ///< a whole cut without stage timing (the figure to compare)
  std::array<double, static_cast<int>(CutStage::count)> stage_ms{};  ///< with a sync after each stage
  double faces_per_s = 0;  ///< faces of the input sheet over remesh_ms
  index_t nodes_after = 0, faces_after = 0;
};

/// The zigzag cut of the benchmark: `segments` segments across the unit sheet, in rest-xy.
CutLine bench_cut(int segments);

/// Runs the remesh benchmark for every size on `device`: each run cuts a fresh copy of an
/// irregular sheet (`make_sheet`, seed 1) once; uploading the sheet is not timed.
std::vector<BenchRow> run_remesh_bench(const BenchOptions& options, Device device);

nlohmann::json to_json(const BenchRow& row);

}  // namespace tear
