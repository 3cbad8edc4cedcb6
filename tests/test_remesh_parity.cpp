// The remesher on the GPU against the CPU: identical topology, positions within 1e-6 relative.
#include <cmath>
#include <cstdint>
#include <random>

#include "catch.h"
#include "random_meshes.h"
#include "remesh_checks.h"
#include "tear/cloth.h"
#include "tear/cut_script.h"
#include "tear/make_sheet.h"
#include "test_support.h"

using namespace tear;

namespace {

/// Cuts the same cloth on both backends frame by frame and compares after every frame.
void check_parity(const Mesh& mesh, const std::vector<std::vector<CutLine>>& frames, double snap) {
  Cloth gpu(mesh, Device::cuda), cpu(mesh, Device::cpu);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    INFO("frame " << i + 1);
    const CutStats gs = gpu.cut(frames[i], {snap}), cs = cpu.cut(frames[i], {snap});
    CHECK(gs.nodes_after == cs.nodes_after);
    CHECK(gs.faces_after == cs.faces_after);
    CHECK(gs.edge_points == cs.edge_points);
    CHECK(gs.cut_edges == cs.cut_edges);
    CHECK(gs.face_points == cs.face_points);
    const Mesh g = gpu.mesh(), c = cpu.mesh();
    REQUIRE(g.face_nodes == c.face_nodes);
    REQUIRE(g.node_pos.size() == c.node_pos.size());
    double worst = 0;
    for (std::size_t k = 0; k < g.node_pos.size(); ++k)
      worst = std::max(worst, std::abs(double(g.node_pos[k]) - c.node_pos[k]) / (1.0 + std::abs(double(c.node_pos[k]))));
    CHECK(worst <= 1e-6);
    const Topology gt = gpu.topology(), ct = cpu.topology();
    CHECK(gt.edge_nodes == ct.edge_nodes);
    CHECK(gt.edge_faces == ct.edge_faces);
    CHECK(gt.node_faces == ct.node_faces);
    CHECK(g.corner_uv.size() == c.corner_uv.size());
  }
}

}  // namespace

TEST_CASE("remesh: CUDA and CPU backends agree", "[remesh][parity]") {
  if (!cuda_available()) {
    WARN("no GPU: parity not checked");
    return;
  }
  SECTION("the paper's scene on the three Table 1 sheets") {
    const CutScript script = read_cut_script(test::source_path("examples/paper_scene.json"));
    for (index_t faces : {2822, 9022, 38298}) {
      SheetOptions o;
      o.face_count = faces;
      std::vector<std::vector<CutLine>> frames;
      for (int f = 1; f <= script.frames; ++f) {
        frames.emplace_back();
        for (const Cut* cut : script.cuts_of_frame(f)) frames.back().push_back(to_cut_line(*cut));
      }
      INFO("faces " << faces);
      check_parity(make_sheet(o), frames, script.snap);
    }
  }
  SECTION("random polylines over random sheets") {
    const std::uint64_t seed = test::test_seed(4242);
    std::mt19937_64 random(seed);
    auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * double(random() >> 11) * 0x1.0p-53; };
    for (int trial = 0; trial < 30; ++trial) {
      INFO("seed " << seed << ", trial " << trial);
      const Mesh mesh = test::random_sheet(seed + trial, 2000);
      std::vector<std::vector<CutLine>> frames(3);
      for (auto& frame : frames) {
        const int cuts = 1 + int(random() % 2);
        for (int c = 0; c < cuts; ++c) {
          std::vector<std::array<double, 2>> points;
          const int n = 2 + int(random() % 5);
          for (int p = 0; p < n; ++p) points.push_back({uniform(-0.2, 1.2), uniform(-0.2, 1.2)});
          frame.push_back(test::cut_rest_xy(points));
        }
      }
      check_parity(mesh, frames, default_snap);
    }
  }
  SECTION("1M faces, one zigzag cut") {
    SheetOptions o;
    o.face_count = 1 << 20;
    std::vector<std::vector<CutLine>> frames{{test::cut_rest_xy({{-0.05, 0.47}, {0.3, 0.53}, {0.6, 0.46}, {1.05, 0.52}})}};
    check_parity(make_sheet(o), frames, default_snap);
  }
}
