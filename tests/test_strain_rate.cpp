// The strain rate limit on the velocities before a substep (kernels/strain_rate.h,
// docs/simulation.md, *The recoil*): one edge's worked example, a pinned end, rigid motion left
// alone, slow motion left bit for bit, and notched pulls whose torn flanks must not stay folded over.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "catch.h"
#include "strain_rate.h"
#include "torn_pulls.h"

using namespace tear::test::pulls;

namespace {

/// One triangle: nodes 0 and 1 a centimetre apart on x, node 2 ten metres up (its edges barely
/// change length whatever 0 and 1 do along x).
struct Triangle {
  std::vector<index_t> face_nodes{0, 1, 2}, offsets{0, 1, 2, 3}, faces{0, 0, 0};
  std::vector<float> pos{0, 0, 0, 0.01f, 0, 0, 0.005f, 10, 0};
  std::vector<std::uint8_t> pinned{0, 0, 0};
  /// `passes` passes of the limit at `limit` with h = 1/96 s; returns the velocities.
  std::vector<float> limit(std::vector<float> vel, double limit, int passes = 1) const {
    std::vector<float> out(vel.size());
    for (int p = 0; p < passes; ++p) {
      const tear::kernels::limit_strain_rate pass{face_nodes.data(), offsets.data(), faces.data(), pos.data(),
                                                  pinned.data(), vel.data(), out.data(), static_cast<float>(limit * 96)};
      for (index_t n = 0; n < 3; ++n) pass(n);
      vel.swap(out);
    }
    return vel;
  }
};

}  // namespace

TEST_CASE("strain rate: an edge closing too fast closes at the bound, each end giving up half", "[tearing]") {
  Triangle t;
  // Closing at 2 m/s; the bound is 0.1 x 0.01 m x 96 /s = 0.096 m/s.
  const std::vector<float> v = t.limit({1, 0, 0, -1, 0, 0, 0, 0, 0}, 0.1);
  CHECK(v[0] == Approx(0.048).epsilon(1e-4));
  CHECK(v[3] == Approx(-0.048).epsilon(1e-4));
  CHECK(v[1] == 0.0f);
  CHECK(v[4] == 0.0f);
  CHECK(v[6] == 0.0f);  // node 2's edges change length by far less than their bound
  // Against a pinned end, the free node gives up the whole excess.
  t.pinned[1] = 1;
  const std::vector<float> w = t.limit({1, 0, 0, 0, 0, 0, 0, 0, 0}, 0.1);
  CHECK(w[0] == Approx(0.096).epsilon(1e-4));
  CHECK(w[3] == 0.0f);
}

TEST_CASE("strain rate: motion under the bound, and rigid motion however fast, are left bit for bit",
          "[tearing]") {
  const tear::Mesh sheet_mesh = sheet(800, true);
  const index_t nodes = sheet_mesh.node_count();
  std::vector<index_t> offsets(nodes + 1, 0), faces;
  for (index_t c = 0; c < 3 * sheet_mesh.face_count(); ++c) ++offsets[sheet_mesh.face_nodes[c] + 1];
  for (index_t n = 0; n < nodes; ++n) offsets[n + 1] += offsets[n];
  faces.resize(offsets[nodes]);
  std::vector<index_t> cursor(offsets.begin(), offsets.end() - 1);
  for (index_t c = 0; c < 3 * sheet_mesh.face_count(); ++c) faces[cursor[sheet_mesh.face_nodes[c]]++] = c / 3;
  const std::vector<float>& pos = sheet_mesh.node_pos;
  const std::vector<std::uint8_t> pinned(nodes, 0);
  const auto limited = [&](const std::vector<float>& vel) {
    std::vector<float> a = vel, b(vel.size());
    for (int p = 0; p < tear::kernels::strain_rate_passes; ++p) {
      const tear::kernels::limit_strain_rate pass{sheet_mesh.face_nodes.data(), offsets.data(), faces.data(),
                                                  pos.data(), pinned.data(), a.data(), b.data(), 0.1f * 96};
      for (index_t n = 0; n < nodes; ++n) pass(n);
      a.swap(b);
    }
    return a;
  };
  // A spin of 20 rad/s about z through (0.5, 0.5) and a flight at 30 m/s: no edge changes length.
  std::vector<float> rigid(3 * nodes), slow(3 * nodes);
  for (index_t n = 0; n < nodes; ++n) {
    const float x = pos[3 * n] - 0.5f, y = pos[3 * n + 1] - 0.5f;
    rigid[3 * n] = -20 * y + 30;
    rigid[3 * n + 1] = 20 * x;
    rigid[3 * n + 2] = 30;
    // A stretch along x at 1 /s: each edge's rate is at most its length per second, under 9.6 /s.
    slow[3 * n] = x;
    slow[3 * n + 1] = 0;
    slow[3 * n + 2] = 0;
  }
  const std::vector<float> r = limited(rigid);
  double largest = 0;
  for (index_t i = 0; i < 3 * nodes; ++i) largest = std::max(largest, double(std::abs(r[i] - rigid[i])));
  CHECK(largest < 1e-4);  // float rounding of the edges' directions only
  CHECK(limited(slow) == slow);
}

TEST_CASE("strain rate: the flanks of notched pulls do not stay folded over", "[tearing][quality]") {
  // Jittered sheets whose pull, without the limit, leaves faces folded over along the crack for
  // good (4 and 4 faces within a radius of it, measured; docs/simulation.md, *The recoil*): with
  // it, none there in the last frame. The pull's 24 frames, then 16 more with the pins held where
  // they stopped, so the recoil has died down by the end and what is still folded stays so.
  const auto script = [](const std::string& tearing) {
    std::string text = notched_pull(tearing);
    text.replace(text.find(R"("frames": 24)"), 12, R"("frames": 40)");
    return text;
  };
  for (const index_t faces : {1250, 4050}) {
    tear::SheetOptions options;
    options.face_count = faces;
    options.irregular = true;
    options.seed = 3;
    const tear::Mesh input = tear::make_sheet(options);
    const Torn t = run(input, script(R"("stretch": 1.3)"), 40);
    index_t near_crack = 0;
    for (const auto& c : t.last_inverted_at) {
      double nearest = 1e9;
      for (const auto& p : t.boundary) nearest = std::min(nearest, std::hypot(c[0] - p[0], c[1] - p[1]));
      near_crack += nearest < 0.05;
    }
    INFO(faces << " faces: folded over in the last frame " << t.last_inverted << ", " << near_crack
                << " of them within 5 cm of the crack");
    CHECK(t.pieces == 2);
    CHECK(near_crack == 0);
  }
}
