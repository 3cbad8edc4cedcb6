#include "tear/bench.h"

#include <algorithm>

#include "tear/make_sheet.h"

namespace tear {

namespace {
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}
}  // namespace

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
    for (int run = 0; run < options.warmup + 2 * options.repeats; ++run) {
      Cloth cloth(mesh, device);  // a fresh cloth each time: cutting a torn cloth again is a no-op
      CutOptions cut_options;
      const bool timed = run >= options.warmup, staged = timed && (run - options.warmup) % 2 == 1;
      cut_options.time_stages = staged;
      const CutStats stats = cloth.cut(cut, cut_options);
      row.nodes_after = stats.nodes_after;
      row.faces_after = stats.faces_after;
      if (!timed) continue;
      if (staged)
        for (std::size_t s = 0; s < stages.size(); ++s) stages[s].push_back(stats.stage_ms[s]);
      else
        totals.push_back(stats.total_ms);
    }
    row.remesh_ms = median(totals);
    for (std::size_t s = 0; s < stages.size(); ++s) row.stage_ms[s] = median(stages[s]);
    row.faces_per_s = row.remesh_ms > 0 ? faces / (row.remesh_ms * 1e-3) : 0;
    rows.push_back(row);
  }
  return rows;
}

nlohmann::json to_json(const BenchRow& row) {
  nlohmann::json stages = nlohmann::json::object();
  for (int s = 0; s < static_cast<int>(CutStage::count); ++s) stages[to_string(static_cast<CutStage>(s))] = row.stage_ms[s];
  return {{"faces", row.faces},           {"device", to_string(row.device)}, {"device_name", row.device_name},
          {"remesh_ms", row.remesh_ms},   {"stage_ms", stages},              {"faces_per_s", row.faces_per_s},
          {"nodes_after", row.nodes_after}, {"faces_after", row.faces_after}};
}

}  // namespace tear
