// tear kernels: strain rate limiting (Bridson, Fedkiw and Anderson 2002, "Robust treatment of
// collisions, contact and friction for cloth animation", section 7.2), run on the velocities before
// a substep: no edge may shorten or lengthen, from its nodes' velocities over the substep, by more
// than `limit` times its length.
//
// A tear releases stretched cloth at once: its flanks spring back, and where a node's step is
// longer than its faces are wide, the implicit step lands on the far side of the face across from
// it. Springs hold a face folded over as well as flat (its edges keep their lengths), so the fold
// stays. Limiting the rate spreads the recoil over several substeps without touching slower motion.
//
// Each pass is a Jacobi sweep over the nodes: a node looks at its edges (through its faces, so an
// inner edge twice and a border edge once, the same at both ends), takes for each edge whose
// relative speed along it passes the bound its share of the excess (half; all of it against a pinned
// node), and moves by the mean of those shares along the edges. Sums run in the node's face order:
// the same bits on every run. Example: two free nodes 1 cm apart closing at 2 m/s, h = 1/96 s,
// limit 0.1: the bound is 0.1 × 0.01 × 96 = 0.096 m/s; each node gives up half of the 1.904 m/s
// excess, and they close at 0.096 m/s.
#pragma once

#include <cstdint>

#include "hd.h"
#include "pd_math.h"

namespace tear::kernels {

/// Passes of `limit_strain_rate` per substep (an even count, so the velocities end where they began).
inline constexpr int strain_rate_passes = 4;

/// One pass at node n: `vel_out` = `vel_in` moved by the mean of its limited edges' shares.
struct limit_strain_rate {
  const index_t* face_nodes;
  const index_t* node_face_offset;
  const index_t* node_faces;
  const float* node_pos;
  const std::uint8_t* node_pinned;
  const float* vel_in;
  float* vel_out;
  float rate;  // limit / h: the bound on an edge's relative speed per metre of its length, 1/s
  TEAR_HD void operator()(index_t n) const {
    const Vec3f v = load3<float>(vel_in, n);
    if (node_pinned[n]) {
      store3(vel_out, n, v);
      return;
    }
    const Vec3f x = load3<float>(node_pos, n);
    Vec3f sum{0, 0, 0};
    int count = 0;
    for (index_t i = node_face_offset[n]; i < node_face_offset[n + 1]; ++i) {
      const index_t f = node_faces[i];
      for (int k = 0; k < 3; ++k) {
        const index_t m = face_nodes[3 * f + k];
        if (m == n) continue;
        const Vec3f d = load3<float>(node_pos, m) - x;
        const float l = norm(d);
        if (!(l > 0.0f)) continue;
        const Vec3f u = (1.0f / l) * d;
        const float closing = dot(load3<float>(vel_in, m) - v, u);  // < 0: the edge shortens
        const float bound = rate * l;
        const float excess = closing > bound ? closing - bound : closing < -bound ? closing + bound : 0.0f;
        if (excess == 0.0f) continue;
        sum = sum + ((node_pinned[m] ? 1.0f : 0.5f) * excess) * u;
        ++count;
      }
    }
    store3(vel_out, n, count > 0 ? v + (1.0f / static_cast<float>(count)) * sum : v);
  }
};

}  // namespace tear::kernels
