// The strain rate limit on what a substep did (kernels/strain_rate.h, docs/simulation.md, *The
// recoil*): a thin face kept from turning over (free and against a pinned edge), rigid and slow
// motion left bit for bit, and notched pulls whose torn flanks must not stay folded over.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "catch.h"
#include "strain_rate.h"
#include "tear/mesh.h"
#include "tear/topology.h"
#include "torn_pulls.h"

using namespace tear::test::pulls;

namespace {

/// A substep of h = 1/96 s that moved `start` by `velocity` (x = x0 + h v, the node velocities v
/// as well), limited at `limit` as the stepping does: the positions and velocities after.
struct Limited {
  std::vector<float> pos, vel;
};
Limited limit_substep(const std::vector<index_t>& face_nodes, const std::vector<float>& start,
                      const std::vector<float>& velocity, const std::vector<std::uint8_t>& pinned, float limit,
                      int* excess = nullptr) {
  const index_t nodes = static_cast<index_t>(start.size() / 3);
  tear::Mesh mesh;
  mesh.node_pos = start;
  mesh.face_nodes = face_nodes;
  const tear::Topology topo = tear::build_topology(mesh, tear::test::test_device());
  const float h = 1.0f / 96;
  Limited out{start, velocity};
  for (std::size_t i = 0; i < start.size(); ++i) out.pos[i] = start[i] + h * velocity[i];
  std::vector<float> rate[2] = {std::vector<float>(start.size()), std::vector<float>(start.size())};
  tear::kernels::limit_strain_rate pass{face_nodes.data(), topo.node_face_offset.data(), topo.node_faces.data(), start.data(),
                                        pinned.data(), nullptr, nullptr, out.pos.data(), out.vel.data(), h, 1 / h,
                                        limit / h, false, excess};
  if (excess) std::fill(excess, excess + tear::kernels::strain_rate_passes, 0);
  for (int p = 0; p < tear::kernels::strain_rate_passes; ++p) {
    pass.vel_in = p == 0 ? nullptr : rate[(p + 1) % 2].data();
    pass.vel_out = rate[p % 2].data();
    pass.finish = p + 1 == tear::kernels::strain_rate_passes;
    pass.pass = p;
    // Each pass reads only what the one before wrote (the last writes positions the first read).
    for (index_t n = 0; n < nodes; ++n) pass(n);
  }
  return out;
}

/// The mean velocity a substep ended with, node n's component d.
float mean_velocity(const Limited& l, const std::vector<float>& start, index_t n, int d) {
  return (l.pos[3 * n + d] - start[3 * n + d]) * 96;
}

}  // namespace

TEST_CASE("strain rate: a thin face's altitude shrinks by at most the limit, so it does not turn over",
          "[tearing]") {
  // Corner 2 a millimetre above the 2 cm edge 0-1, moving down at 0.5 m/s: in one substep of
  // 1/96 s it would pass 4 mm under the edge (the face turned over) with the edges' lengths barely
  // changed. Limited, the altitude shrinks by a tenth.
  const std::vector<index_t> face{0, 1, 2};
  const std::vector<float> start{0, 0, 0, 0.02f, 0, 0, 0.01f, 0.001f, 0};
  const Limited l = limit_substep(face, start, {0, 0, 0, 0, 0, 0, 0, -0.5f, 0}, {0, 0, 0}, 0.1f);
  const auto altitude = [&](const std::vector<float>& x) {
    // Signed: corner 2's y over the line through 0 and 1 (in the xy plane).
    const float ex = x[3] - x[0], ey = x[4] - x[1];
    return ((x[6] - x[0]) * -ey + (x[7] - x[1]) * ex) / std::hypot(ex, ey);
  };
  CHECK(altitude(l.pos) > 0);
  CHECK(altitude(l.pos) >= 0.9f * 0.001f * 0.98f);  // the bound, less what the passes leave
  CHECK(altitude(l.pos) <= 0.001f);
  // The velocities changed by as much as the mean velocities did: the apex falls slower.
  CHECK(l.vel[7] == Approx(mean_velocity(l, start, 2, 1)).margin(1e-4));
  CHECK(l.vel[7] > -0.5f);
  // Against a pinned edge, the apex alone gives way: the edge stays where it was.
  const Limited p = limit_substep(face, start, {0, 0, 0, 0, 0, 0, 0, -0.5f, 0}, {1, 1, 0}, 0.1f);
  CHECK(p.pos[1] == 0.0f);
  CHECK(p.pos[4] == 0.0f);
  CHECK(altitude(p.pos) >= 0.9f * 0.001f * 0.98f);
}

TEST_CASE("strain rate: a face folded over at the start is free to turn back", "[tearing]") {
  // The square (0, 0) (1, 0) (1, 1) (0, 1) cut along its diagonal 0-2, its corner 3 pushed across
  // the diagonal to (0.8, 0.2): face 0-2-3 lies turned over on face 0-1-2. Corner 3 going back to
  // (0, 1) in one substep must pass through the diagonal's line, its altitude through zero.
  const std::vector<index_t> faces{0, 1, 2, 0, 2, 3};
  const std::vector<float> start{0, 0, 0, 1, 0, 0, 1, 1, 0, 0.8f, 0.2f, 0};
  const std::vector<float> back{0, 0, 0, 0, 0, 0, 0, 0, 0, -0.8f * 96, 0.8f * 96, 0};
  const Limited l = limit_substep(faces, start, back, {0, 0, 0, 0}, 0.1f);
  CHECK(l.vel == back);
  CHECK(l.pos[9] == Approx(0).margin(1e-5));
  CHECK(l.pos[10] == Approx(1).margin(1e-5));
  // The same corner moving the other way, from (0, 1) across the diagonal, is held back.
  const std::vector<float> flat{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  std::vector<float> across(12, 0.0f);
  across[9] = 0.8f * 96;
  across[10] = -0.8f * 96;
  const Limited held = limit_substep(faces, flat, across, {0, 0, 0, 0}, 0.1f);
  CHECK(held.pos[10] > held.pos[9]);  // still on its side of the diagonal y = x
}

TEST_CASE("strain rate: slow motion, and rigid motion however fast, are left bit for bit", "[tearing]") {
  const tear::Mesh sheet_mesh = sheet(800, true);
  const index_t nodes = sheet_mesh.node_count();
  const std::vector<float>& pos = sheet_mesh.node_pos;
  const std::vector<std::uint8_t> pinned(nodes, 0);
  // A spin of 20 rad/s about z through (0.5, 0.5) and a flight at 30 m/s: no edge changes length.
  std::vector<float> rigid(3 * nodes), slow(3 * nodes);
  for (index_t n = 0; n < nodes; ++n) {
    const float x = pos[3 * n] - 0.5f, y = pos[3 * n + 1] - 0.5f;
    rigid[3 * n] = -20 * y + 30;
    rigid[3 * n + 1] = 20 * x;
    rigid[3 * n + 2] = 30;
    // A stretch along x at 1 /s: each length changes by at most 1 % of itself over the substep.
    slow[3 * n] = x;
    slow[3 * n + 1] = 0;
    slow[3 * n + 2] = 0;
  }
  const Limited r = limit_substep(sheet_mesh.face_nodes, pos, rigid, pinned, 0.1f);
  double largest = 0;
  for (index_t n = 0; n < nodes; ++n)
    for (int d = 0; d < 3; ++d) largest = std::max(largest, double(std::abs(mean_velocity(r, pos, n, d) - rigid[3 * n + d])));
  CHECK(largest < 0.01);  // float rounding of x0 + h v only: the limit took nothing
  CHECK(r.vel == rigid);  // and left the velocities as they were
  const Limited s = limit_substep(sheet_mesh.face_nodes, pos, slow, pinned, 0.1f);
  CHECK(s.vel == slow);
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
    INFO(faces << " faces: folded over in the last frame " << t.last_inverted_at.size() << ", " << near_crack
                << " of them within 5 cm of the crack");
    CHECK(t.pieces == 2);
    CHECK(near_crack == 0);
  }
}

TEST_CASE("strain rate: passes after one that found nothing to limit, skipped, change no bit", "[tearing]") {
  // With the flags each pass raises where an altitude passes its bound, a pass computes shares only
  // where the one before it found some; the positions and velocities must be those of every pass run.
  const tear::Mesh sheet_mesh = sheet(800, true);
  const index_t nodes = sheet_mesh.node_count();
  const std::vector<float>& pos = sheet_mesh.node_pos;
  std::vector<std::uint8_t> pinned(nodes, 0);
  pinned[0] = 1;
  std::vector<float> squeeze(3 * nodes), slide(3 * nodes);
  for (index_t n = 0; n < nodes; ++n) {
    const float x = pos[3 * n] - 0.5f, y = pos[3 * n + 1] - 0.5f;
    // Squeezed along x at 200 /s: every altitude across x shrinks by twice itself in a substep.
    squeeze[3 * n] = -200 * x;
    squeeze[3 * n + 1] = 0.1f * y;
    squeeze[3 * n + 2] = 0.3f * x * y;
    slide[3 * n] = 2;
    slide[3 * n + 1] = -1;
    slide[3 * n + 2] = 0.5f;
  }
  constexpr int passes = tear::kernels::strain_rate_passes;
  for (const auto* velocity : {&squeeze, &slide}) {
    int excess[passes];
    const Limited all = limit_substep(sheet_mesh.face_nodes, pos, *velocity, pinned, 0.1f);
    const Limited skipping = limit_substep(sheet_mesh.face_nodes, pos, *velocity, pinned, 0.1f, excess);
    INFO((velocity == &squeeze ? "squeezed" : "sliding"));
    CHECK(excess[0] == (velocity == &squeeze ? 1 : 0));
    // Once a pass finds nothing, none after it does.
    for (int p = 1; p < passes; ++p) CHECK(excess[p] <= excess[p - 1]);
    CHECK(skipping.pos == all.pos);
    CHECK(skipping.vel == all.vel);
    if (velocity == &squeeze) CHECK(all.vel != *velocity);  // the limit did act there
  }
  // A lone thin face falling flat settles in a few passes: the later ones skip, with the same bits.
  const std::vector<index_t> face{0, 1, 2};
  const std::vector<float> start{0, 0, 0, 0.02f, 0, 0, 0.01f, 0.001f, 0}, fall{0, 0, 0, 0, 0, 0, 0, -0.5f, 0};
  int excess[passes];
  const Limited all = limit_substep(face, start, fall, {0, 0, 0}, 0.1f);
  const Limited skipping = limit_substep(face, start, fall, {0, 0, 0}, 0.1f, excess);
  CHECK(excess[0] == 1);
  CHECK(excess[passes - 1] == 0);
  CHECK(skipping.pos == all.pos);
  CHECK(skipping.vel == all.vel);
}
