// tear kernels: a strain rate limit on what a substep did (after the strain rate limiting of
// Bridson, Fedkiw and Anderson 2002, "Robust treatment of collisions, contact and friction for
// cloth animation", section 7.2, applied to the faces' altitudes instead of their edges): no face's
// altitude, a corner's distance from the line of the opposite edge, may shrink over the substep by
// more than `limit` times itself.
//
// A tear releases stretched cloth at once: its flanks spring back, and where a node's step is
// longer than its faces are wide, the implicit step lands it on the far side of the face across
// from it. Springs hold a face folded over as well as flat (its edges keep their lengths), and a
// thin face turns over with hardly any change in its edges' lengths, so a limit on the edges alone
// does not stop it; an altitude that shrinks by at most a tenth per substep never reaches zero.
// Stretching, bending and any rigid motion however fast are left alone, as is a face that flattens
// slowly.
//
// The limit works on the nodes' mean velocities over the substep, v = (x - x0) / h, with the
// geometry of the substep's start x0: `strain_rate_passes` Jacobi passes over the nodes, each node
// summing over its faces (in its face order: the same bits every run, no atomics) its share of each
// altitude's excess, mass-free (a pinned node takes none), and moving by the mean of those shares;
// then x = x0 + h v and the node's velocity changes by as much as v did. A face already folded over
// at the substep's start is left free, so that it can turn back: its altitude must pass through
// zero to do so.
//
// Example: the face (0, 0, 0) (0.02, 0, 0) (0.01, 0.001, 0), its apex falling at 0.5 m/s towards the
// opposite edge over a substep of h = 1/96 s, limit 0.1: the altitude's bound is 0.1 × 0.001 × 96 =
// 0.0096 m/s; the apex takes 2/3 of the 0.4904 m/s excess and the edge's ends 1/6 each the other
// way, and the altitude shrinks by a tenth instead of passing through zero.
#pragma once

#include <cstdint>

#include "hd.h"
#include "pd_math.h"

namespace tear::kernels {

/// Passes of `limit_strain_rate` per substep: the mean of a node's shares under-corrects where its
/// faces share an excess, and a row of thin faces pushed by a recoil needs more than four.
inline constexpr int strain_rate_passes = 16;
static_assert(strain_rate_passes >= 2, "the first pass reads the positions the last one writes");

/// One pass at node n. The first reads the mean velocities from the positions (`vel_in` null); the
/// last (`finish`) writes positions and velocities instead of `vel_out`.
struct limit_strain_rate {
  const index_t* face_nodes;
  const index_t* node_face_offset;
  const index_t* node_faces;
  const float* node_start;  // x0, the substep's start: the geometry every pass measures
  const std::uint8_t* node_pinned;
  const float* vel_in;  // null: (x - x0) / h from `node_pos`
  float* vel_out;       // unless `finish`
  float* node_pos;      // read on the first pass, written on the last
  float* node_vel;      // written on the last pass
  float h, inv_h;
  float rate;  // limit / h: the bound on an altitude's shrinking per metre of it, 1/s
  bool finish;
  /// Where not null, `strain_rate_passes` flags cleared before the first pass: pass p raises
  /// excess[p] where any altitude of what it reads passes its bound. Without an excess a pass gives
  /// every node its own mean velocity back (no node has a share), so the pass after one that raised
  /// nothing only hands its input on, and after a first pass without one nothing is written at all:
  /// skipping changes no bit. A substep with nothing to limit costs one pass instead of all, and one
  /// whose limit settles after a few passes the faces' work of those few.
  int* excess = nullptr;
  int pass = 0;  // p: the flags it reads and raises

  TEAR_HD Vec3f velocity(index_t m) const {
    return vel_in ? load3<float>(vel_in, m) : inv_h * (load3<float>(node_pos, m) - load3<float>(node_start, m));
  }

  TEAR_HD void operator()(index_t n) const {
    if (idle()) return;
    const Vec3f v = velocity(n);
    Vec3f sum{0, 0, 0};
    int count = 0;
    if (takes_shares(n))
      for (index_t i = node_face_offset[n]; i < node_face_offset[n + 1]; ++i)
        face_shares(node_faces[i], n, v, [&](const Vec3f& share) {
          sum = sum + share;
          ++count;
        });
    finish_node(n, v, sum, count);
  }

  /// The whole pass does nothing: the first found nothing to limit.
  TEAR_HD bool idle() const { return excess != nullptr && pass > 0 && excess[0] == 0; }
  /// Whether node n's faces give it shares this pass: not where it is pinned, nor after a pass that
  /// found nothing to limit.
  TEAR_HD bool takes_shares(index_t n) const {
    return !node_pinned[n] && !(excess != nullptr && pass > 0 && excess[pass - 1] == 0);
  }
  /// Node n with the sum and count of its shares, added in its face order: the flag raised where it
  /// has any, and its limited velocity stored, or on the last pass its position and velocity.
  TEAR_HD void finish_node(index_t n, const Vec3f& v, const Vec3f& sum, int count) const {
    if (count > 0 && excess != nullptr) raise(&excess[pass]);
    const Vec3f limited = count > 0 ? v + (1.0f / static_cast<float>(count)) * sum : v;
    if (!finish) {
      store3(vel_out, n, limited);
      return;
    }
    // x = x0 + h v, and the velocity changed by as much as v was: a node left alone keeps its bits.
    const Vec3f before = inv_h * (load3<float>(node_pos, n) - load3<float>(node_start, n));
    if (limited.x == before.x && limited.y == before.y && limited.z == before.z) return;
    store3(node_pos, n, load3<float>(node_start, n) + h * limited);
    store3(node_vel, n, load3<float>(node_vel, n) + (limited - before));
  }

  /// Sets `*flag` to 1; threads race only to write the same value.
  TEAR_HD static void raise(int* flag) {
#if defined(__CUDA_ARCH__)
    *static_cast<volatile int*>(flag) = 1;
#else
    __atomic_store_n(flag, 1, __ATOMIC_RELAXED);
#endif
  }

  /// Face g's normal at the substep's start (the cross product of its edges, not unit).
  TEAR_HD Vec3f start_normal(index_t g) const {
    const Vec3f y0 = load3<float>(node_start, face_nodes[3 * g]);
    return cross(load3<float>(node_start, face_nodes[3 * g + 1]) - y0,
                 load3<float>(node_start, face_nodes[3 * g + 2]) - y0);
  }
  /// Whether face f is folded over at the substep's start: its normal against the summed normals of
  /// the other faces at its corners. A face folded over is left free, so that it can turn back: its
  /// altitude must pass through zero to do so.
  TEAR_HD bool folded_at_start(index_t f) const {
    Vec3f around{0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      const index_t c = face_nodes[3 * f + k];
      for (index_t i = node_face_offset[c]; i < node_face_offset[c + 1]; ++i)
        if (node_faces[i] != f) around = around + start_normal(node_faces[i]);
    }
    return dot(start_normal(f), around) < 0.0f;
  }

  /// Node n's shares of face f's three altitudes over their bounds, handed to `add` in altitude
  /// order. The altitude of corner a over the line of b-c, at the foot b + t (c - b), changes at
  /// g · u along the unit normal from the line to a, with g = (1, -(1 - t), -t) for (a, b, c); the
  /// correction moves each node along g_k λ, λ sharing the excess by the free nodes' g_k².
  template <class Add>
  TEAR_HD void face_shares(index_t f, index_t n, const Vec3f& v, Add&& add) const {
    Vec3f x[3], u[3];
    float w[3];
    int me = 0;
    for (int k = 0; k < 3; ++k) {
      const index_t c = face_nodes[3 * f + k];
      x[k] = load3<float>(node_start, c);
      u[k] = c == n ? v : velocity(c);
      w[k] = node_pinned[c] ? 0.0f : 1.0f;
      if (c == n) me = k;
    }
    int folded = -1;  // looked at once, where an altitude passes its bound
    for (int a = 0; a < 3; ++a) {
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      const Vec3f base = x[c] - x[b];
      const float bb = dot(base, base);
      if (!(bb > 0.0f)) continue;
      float t = dot(x[a] - x[b], base) / bb;
      t = t < 0.0f ? 0.0f : t > 1.0f ? 1.0f : t;
      const Vec3f up = x[a] - (x[b] + t * base);
      const float height = norm(up);
      if (!(height > 0.0f)) continue;
      const Vec3f normal = (1.0f / height) * up;
      float g[3];
      g[a] = 1.0f;
      g[b] = -(1.0f - t);
      g[c] = -t;
      const float growing = g[0] * dot(u[0], normal) + g[1] * dot(u[1], normal) + g[2] * dot(u[2], normal);
      const float bound = rate * height;
      if (!(growing < -bound)) continue;
      if (folded < 0) folded = folded_at_start(f) ? 1 : 0;
      if (folded) return;
      const float weight = w[0] * g[0] * g[0] + w[1] * g[1] * g[1] + w[2] * g[2] * g[2];
      if (!(weight > 0.0f)) continue;
      add((w[me] * g[me] * ((-bound - growing) / weight)) * normal);
    }
  }
};

/// `limit_strain_rate` a warp a node on a GPU (index i: node i / 32, lane i % 32): lane k takes the
/// shares of the node's k-th face, and lane 0 adds them up in the node's face order, altitude by
/// altitude, as one thread does (the device makes no fused multiply-adds: a share rounds the same
/// whether added where it is made or after a shuffle), so the bits are the same. A node of more
/// than 32 faces is lane 0's alone. On the CPU, one thread a node.
struct limit_strain_rate_by_warp {
  limit_strain_rate one;
  TEAR_HD void operator()(index_t i) const {
    const index_t n = i / 32;
    const int lane = static_cast<int>(i % 32);
#if defined(__CUDA_ARCH__)
    if (one.idle()) return;
    const index_t begin = one.node_face_offset[n], faces = one.node_face_offset[n + 1] - begin;
    if (faces > 32) {
      if (lane == 0) one(n);
      return;
    }
    const Vec3f v = one.velocity(n);
    Vec3f share[3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    int made = 0;
    if (lane < faces && one.takes_shares(n))
      one.face_shares(one.node_faces[begin + lane], n, v, [&](const Vec3f& s) { share[made++] = s; });
    Vec3f sum{0, 0, 0};
    int count = 0;
    for (int k = 0; k < faces; ++k) {
      const int from_k = __shfl_sync(0xffffffffu, made, k);
      for (int a = 0; a < from_k; ++a) {
        const Vec3f s{__shfl_sync(0xffffffffu, share[a].x, k), __shfl_sync(0xffffffffu, share[a].y, k),
                      __shfl_sync(0xffffffffu, share[a].z, k)};
        sum = sum + s;
        ++count;
      }
    }
    if (lane == 0) one.finish_node(n, v, sum, count);
#else
    if (lane == 0) one(n);
#endif
  }
};

}  // namespace tear::kernels
