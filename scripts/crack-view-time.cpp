// Times the construction of crack growth's view of the rest mesh (CrackField, rebuilt after every
// tear) on the high pull sheet (38,366 faces) with a slit, 40 times; prints the best and the mean.
// Its border edges all count as torn here (no corner_torn), which is more work than a run's view.
// Built against a build's libtear.so, with the crack growth sources compiled in (they take the
// place of the library's, so an older tree's sources give that tree's time):
//   g++ -std=c++17 -O2 -fopenmp -ISRC/lib/src -Ilib/include -Ilib/src -Ikernels scripts/crack-view-time.cpp \
//     SRC/lib/src/cloth/crack_field.cpp SRC/lib/src/cloth/crack_growth.cpp -Lbuild-cpu/lib -ltear \
//     -Wl,-rpath,build-cpu/lib -o crack-view-time
// (SRC: this tree, or an older one's checkout; docs/BENCHMARKS.md has the figures).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <utility>
#include <vector>

#include "cloth/crack_growth.h"
#include "tear/cloth.h"
#include "tear/cut_script.h"
#include "tear/demo_scene.h"

int main() {
  const tear::Mesh mesh = tear::make_demo_mesh(tear::DemoScene::pull, tear::DemoResolution::high);
  tear::Cloth cloth(mesh, tear::Device::cpu);
  tear::Cut cut;
  cut.kind = tear::CutKind::polyline;
  cut.space = tear::CutSpace::rest_xy;
  cut.polyline2 = {{0.5, -0.1}, {0.5, 0.6}};
  cloth.cut({tear::to_cut_line(cut)});
  tear::CrackMesh m;
  m.node_rest = cloth.node_rest();
  m.face_nodes = cloth.face_nodes();
  m.topo = cloth.topology();
  tear::TearingOptions options;
  options.stretch = 1.3;
  const int runs = 40;
  double best = 1e300, total = 0;
  for (int i = 0; i < runs; ++i) {
    tear::CrackMesh copy = m;
    const auto t0 = std::chrono::steady_clock::now();
    const tear::CrackField field(std::move(copy), options);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    best = std::min(best, ms);
    total += ms;
  }
  std::printf("%d faces: CrackField built in %.3f ms at best, %.3f ms on average over %d\n", m.topo.face_count, best,
              total / runs, runs);
}
