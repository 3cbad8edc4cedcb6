// The cut-info stage picks each face's split variant from the face's rest shape: one face with an
// EE line and no third edge point (a quadrilateral with a free diagonal), run through
// `face_cut_info` on two shapes that want different diagonals.
#include <cmath>
#include <cstdint>
#include <set>

#include "../kernels/cut_info.h"
#include "../kernels/intersect_cuts.h"
#include "../kernels/split_table.h"
#include "catch.h"

namespace {

using namespace tear::kernels;

/// Smallest corner angle (degrees) of the triangles of a split, on 3D slot positions.
double smallest_angle_deg(const SplitCase& c, const double (&pos)[7][3]) {
  double smallest = 180;
  for (int t = 0; t < c.tri_count; ++t)
    for (int s = 0; s < 3; ++s) {
      const double* p = pos[point_slot(c.tri[t][s])];
      const double* a = pos[point_slot(c.tri[t][(s + 1) % 3])];
      const double* b = pos[point_slot(c.tri[t][(s + 2) % 3])];
      double uv = 0, uu = 0, vv = 0;
      for (int d = 0; d < 3; ++d) {
        uv += (a[d] - p[d]) * (b[d] - p[d]);
        uu += (a[d] - p[d]) * (a[d] - p[d]);
        vv += (b[d] - p[d]) * (b[d] - p[d]);
      }
      smallest = std::min(smallest, std::acos(uv / std::sqrt(uu * vv)) * 180 / 3.14159265358979323846);
    }
  return smallest;
}

}  // namespace

TEST_CASE("face_cut_info: a face takes the split variant best shaped on its rest shape", "[split]") {
  // One face N0 N1 N2 (nodes 0 1 2); a cut enters through edge 1 (N2-N0) and leaves through edge 2
  // (N0-N1), both at their midpoints: EE0 cuts off N0 and leaves the quadrilateral E2 N1 N2 E1.
  const index_t face_nodes[3] = {0, 1, 2}, face_edges[3] = {0, 1, 2};
  const std::uint16_t face_pairs[1] = {std::uint16_t(1u << location_pair_bit(1, 2))};
  const std::uint8_t edge_point[3] = {edge_point_none, edge_point_inside, edge_point_inside};
  const float edge_point_t[3] = {0.0f, 0.5f, 0.5f};
  const unsigned state = face_cut::e1 | face_cut::e2 | face_cut::ee0;
  const SplitCase* table = split_table();
  REQUIRE(table[face_split_code(state, 0)].variant_count == 2);

  std::set<int> chosen;
  // A sheet long along edge 2, one long along edge 1, both tilted out of the xy plane.
  const float shapes[2][9] = {{0, 0, 0, 10, 0, 3, 0, 1, 0}, {0, 0, 0, 1, 0, 0.3f, 0, 10, 1}};
  for (const auto& node_rest : shapes) {
    std::uint16_t face_state[1] = {0xffff};
    std::uint8_t face_along[1] = {0xff};
    float face_point_bary[3] = {};
    face_cut_info{face_nodes, face_edges, face_pairs,      edge_point, edge_point_t,
                  face_state, face_along, face_point_bary, node_rest,  table}(0);
    INFO("rest shape " << node_rest[3] << " " << node_rest[7]);
    CHECK(face_split_state(face_state[0]) == state);
    CHECK(face_along[0] == 0);

    // Slots N0..N2, E0 (absent, far away), E1 = mid N2-N0, E2 = mid N0-N1, P (absent).
    double pos[7][3] = {};
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) pos[k][d] = node_rest[3 * k + d];
    for (int d = 0; d < 3; ++d) {
      pos[3][d] = pos[6][d] = 1e6;
      pos[4][d] = 0.5 * (pos[2][d] + pos[0][d]);
      pos[5][d] = 0.5 * (pos[0][d] + pos[1][d]);
    }
    const double angle_0 = smallest_angle_deg(table[face_split_code(state, 0)], pos);
    const double angle_1 = smallest_angle_deg(table[face_split_code(state, 1)], pos);
    INFO("smallest angles " << angle_0 << " and " << angle_1);
    REQUIRE(std::abs(angle_0 - angle_1) > 1.0);
    CHECK(face_split_variant(face_state[0]) == (angle_0 > angle_1 ? 0 : 1));
    chosen.insert(face_split_variant(face_state[0]));
  }
  CHECK(chosen == std::set<int>{0, 1});
}
