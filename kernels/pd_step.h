// tear kernels: one implicit Euler step of projective dynamics (Bouaziz et al. 2014, §4) with the
// global step solved by Chebyshev-accelerated Jacobi iterations (Wang 2015, §4-5).
//
// Every kernel writes only its own element: the local step one constraint, the Jacobi update one
// node (gathering its constraints in CSR order). No atomics, so a step is deterministic.
#pragma once

#include <cstdint>

#include "hd.h"
#include "pd_math.h"
#include "pd_model.h"

namespace tear::kernels {

/// The motion of a pin during one substep as the kernels see it: a pin without keys holds its
/// nodes where they are; a keyed one holds them at rest + `offset` (the offset at the substep's
/// end) moving at `velocity` (the offset's change over the substep / h).
struct PdPinMotion {
  std::int32_t keyed;  ///< 0 holds nodes where they are, 1 at rest + offset
  float offset[3];     ///< metres
  float velocity[3];   ///< m/s
};

/// Where pinned node n is at the end of the substep: x for a pin without keys (or a pin value that
/// names no pin of `pin_motion`), rest + offset for a keyed one. `node_pinned` is 0 for a free
/// node, p + 1 for one held by pin p.
TEAR_HD inline const PdPinMotion* pin_motion_of(const std::uint8_t* node_pinned, const PdPinMotion* pin_motion,
                                                index_t pin_count, index_t n) {
  const index_t p = index_t(node_pinned[n]) - 1;
  return p >= 0 && p < pin_count && pin_motion[p].keyed ? &pin_motion[p] : nullptr;
}

TEAR_HD inline Vec3f pinned_position(const PdPinMotion* motion, const float* node_rest, const Vec3f& x, index_t n) {
  if (!motion) return x;
  return load3<float>(node_rest, n) + Vec3f{motion->offset[0], motion->offset[1], motion->offset[2]};
}

/// Inertial prediction s = x + h v + h² g (pinned nodes: s = their pinned position, x unless their
/// pin is keyed), which also starts the iterates.
struct predict_positions {
  const float* node_pos;
  const float* node_vel;
  const std::uint8_t* node_pinned;
  const float* node_rest;
  const PdPinMotion* pin_motion;  // [pin_count]
  index_t pin_count;
  float h;        // s
  Vec3f gravity;  // m/s²
  float* node_pred;
  float* node_iter;       // x⁽⁰⁾
  float* node_iter_prev;  // x⁽⁻¹⁾, only read once the acceleration starts
  TEAR_HD void operator()(index_t n) const { store(n, predicted(n)); }
  /// s of node n.
  TEAR_HD Vec3f predicted(index_t n) const {
    const Vec3f x = load3<float>(node_pos, n);
    return node_pinned[n] ? pinned_position(pin_motion_of(node_pinned, pin_motion, pin_count, n), node_rest, x, n)
                          : x + h * load3<float>(node_vel, n) + (h * h) * gravity;
  }
  /// s stored as the prediction and both first iterates of place i.
  TEAR_HD void store(index_t i, const Vec3f& s) const {
    store3(node_pred, i, s);
    store3(node_iter, i, s);
    store3(node_iter_prev, i, s);
  }
};

/// Constraint c as the local step reads it: up to four nodes with their coefficients (a spring's
/// two nodes with +1 and −1, then two unused slots), its rest value and weight. Nothing of it
/// changes within a substep, so a kernel may read it once and keep it.
///
/// Column j of a face's membrane is held in the same room: node[3] = −2 − j marks it, node[0..2] are
/// the face's nodes, and k = (own₁, own₂, other₁, other₂), the coefficients of nodes 1 and 2 in this
/// column and in the other (node 0's are minus their sum: the columns are read as edge differences).
struct ConstraintTerms {
  index_t node[pd_constraint_nodes];  ///< −1: unused
  float k[pd_constraint_nodes];
  float rest, weight;
};

TEAR_HD inline ConstraintTerms constraint_terms(const PdConstraints& constraints, index_t c) {
  ConstraintTerms t;
  if (c < constraints.edge_count) {
    t.node[0] = constraints.spring_nodes[2 * c];
    t.node[1] = constraints.spring_nodes[2 * c + 1];
    t.k[0] = 1.0f;
    t.k[1] = -1.0f;
    for (int j = 2; j < pd_constraint_nodes; ++j) {
      t.node[j] = -1;
      t.k[j] = 0.0f;
    }
    t.rest = constraints.spring_rest[c];
    t.weight = constraints.spring_weight[c];
  } else if (c >= 2 * constraints.edge_count) {
    const index_t m = c - 2 * constraints.edge_count, f = m / 2, j = m % 2;
    for (int i = 0; i < 3; ++i) t.node[i] = constraints.membrane_nodes[3 * f + i];
    t.node[3] = -2 - j;
    const float* own = constraints.membrane_coef + 6 * f + 3 * j;
    const float* other = constraints.membrane_coef + 6 * f + 3 * (1 - j);
    t.k[0] = own[1];
    t.k[1] = own[2];
    t.k[2] = other[1];
    t.k[3] = other[2];
    t.rest = 0.0f;
    t.weight = constraints.membrane_weight[f];
  } else {
    const index_t h = c - constraints.edge_count;
    for (int j = 0; j < pd_constraint_nodes; ++j) {
      t.node[j] = constraints.hinge_nodes[pd_constraint_nodes * h + j];
      t.k[j] = constraints.hinge_coef[pd_constraint_nodes * h + j];
    }
    t.rest = constraints.hinge_rest[h];
    t.weight = constraints.hinge_weight[h];
  }
  return t;
}

/// Whether terms `t` are a membrane column, and which: 0 or 1 (−1: a spring or a hinge).
TEAR_HD inline int membrane_column(const ConstraintTerms& t) { return t.node[3] < -1 ? -2 - t.node[3] : -1; }

/// The local step of both columns of the membrane whose column terms `t` are (either column's):
/// f0 and f1 the forces w (R − F) of columns 0 and 1. Every launch mode computes a membrane column's
/// force through here, one column or both, so each gets the same bits.
template <class Position>
TEAR_HD inline void membrane_forces_at(const ConstraintTerms& t, const Position& position, Vec3f& f0, Vec3f& f1) {
  if (t.node[0] < 0) {
    f0 = f1 = Vec3f{0, 0, 0};
    return;
  }
  const Vec3f x0 = position(t.node[0]);
  const Vec3f e1 = position(t.node[1]) - x0, e2 = position(t.node[2]) - x0;
  const Vec3f own = t.k[0] * e1 + t.k[1] * e2, other = t.k[2] * e1 + t.k[3] * e2;
  const Vec3f g0 = membrane_column(t) == 0 ? own : other, g1 = membrane_column(t) == 0 ? other : own;
  Vec3f r0, r1;
  project_rotation(g0, g1, r0, r1);
  f0 = t.weight * (r0 - g0);
  f1 = t.weight * (r1 - g1);
}

/// Local step of a constraint at the iterate x: f_c = w_c (p_c − A_c x), the constraint's pull
/// towards its projection p_c (pd_math.h `project_length`): newtons for a spring.
/// `position(i)` gives node i's iterate: from memory by default, from a copy in shared memory for
/// the tiled kernel (sim/pd_launch_tiled.h), whose terms name nodes by their place in that copy.
template <class Position>
TEAR_HD inline Vec3f constraint_force_at(const ConstraintTerms& t, const Position& position) {
  if (membrane_column(t) >= 0) {  // a membrane column: f_c = w (R's column − F's column)
    Vec3f f0, f1;
    membrane_forces_at(t, position, f0, f1);
    return membrane_column(t) == 0 ? f0 : f1;
  }
  Vec3f d{0, 0, 0};
  for (int j = 0; j < pd_constraint_nodes; ++j)
    if (t.node[j] >= 0) d = d + t.k[j] * position(t.node[j]);
  const Vec3f p = project_length(d, t.rest);
  return t.weight * (p - d);
}

TEAR_HD inline Vec3f constraint_force(const ConstraintTerms& t, const float* node_iter) {
  return constraint_force_at(t, [node_iter](index_t i) { return load3<float>(node_iter, i); });
}

TEAR_HD inline Vec3f compute_constraint_force(const PdConstraints& constraints, const float* node_iter, index_t c) {
  return constraint_force(constraint_terms(constraints, c), node_iter);
}

/// Local step of every constraint, stored for the global step (`jacobi_chebyshev_update`). A
/// membrane's column 0 computes both its columns, which share their projection; column 1 is left to
/// it.
struct project_constraints {
  PdConstraints constraints;
  const float* node_iter;
  float* constraint_force;  // [constraint_count * 3]
  TEAR_HD void operator()(index_t c) const {
    const ConstraintTerms t = constraint_terms(constraints, c);
    const auto position = [this](index_t i) { return load3<float>(node_iter, i); };
    const int column = membrane_column(t);
    if (column == 1) return;
    if (column == 0) {
      Vec3f f0, f1;
      membrane_forces_at(t, position, f0, f1);
      store3(constraint_force, c, f0);
      store3(constraint_force, c + 1, f1);
      return;
    }
    store3(constraint_force, c, constraint_force_at(t, position));
  }
};

/// Global step at node n: one Jacobi update of (M/h² + Σ w AᵀA) x = M s/h² + Σ w Aᵀ p,
///   x̂ = x + (m/h² (s − x) + Σ_c k_{c,n} f_c) / D_n,
/// then Chebyshev's x⁽ᵏ⁺¹⁾ = ω (γ (x̂ − x⁽ᵏ⁾) + x⁽ᵏ⁾ − x⁽ᵏ⁻¹⁾) + x⁽ᵏ⁻¹⁾ (Wang 2015, eq. 12 with
/// under-relaxation γ). Pinned nodes stay. A node with no mass and no constraint follows s.
///
/// The gather is latency-bound (a node's slots, then their forces, a chain of dependent loads per
/// slot): slots are read `gather_batch` at a time (`update<batch>`: 16 where a small mesh's
/// iteration waits on latency alone, 8 where a large one's needs the bandwidth) and their loads
/// issued before any is summed, and the sum still runs in slot order, so the bits are those of a
/// plain loop whatever the batch.
struct jacobi_chebyshev_update {
  static constexpr int gather_batch = 8;
  const index_t* node_slot_offset;
  const index_t* node_slots;
  const float* node_slot_coef;  // each slot's coefficient, in CSR order (`compute_jacobi_diagonal`)
  PdConstraints constraints;
  const float* constraint_force;  // [constraint_count * 3], from `project_constraints`
  const float* node_mass;
  const float* node_diag;
  const std::uint8_t* node_pinned;
  const float* node_pred;
  const float* node_iter;
  const float* node_iter_prev;
  float inv_h2;
  float omega;
  float gamma;
  float* node_iter_next;
  TEAR_HD void operator()(index_t n) const { update<gather_batch>(n); }
  template <int batch>
  TEAR_HD void update(index_t n) const {
    const Vec3f x = load3<float>(node_iter, n);
    if (node_pinned[n]) {
      store3(node_iter_next, n, x);
      return;
    }
    const Vec3f s = load3<float>(node_pred, n);
    const float diag = node_diag[n];
    if (!(diag > 0.0f)) {
      store3(node_iter_next, n, s);
      return;
    }
    Vec3f g = inertial_term(n, x, s);
    const index_t end = node_slot_offset[n + 1];
    for (index_t i = node_slot_offset[n]; i < end; i += batch) {
      const int count = end - i < batch ? static_cast<int>(end - i) : batch;
      // Zeroed only for the host compiler's sake: only the first `count` of each are read.
      index_t slot[batch] = {};
      float coef[batch] = {};
      Vec3f f[batch] = {};
TEAR_UNROLL
      for (int j = 0; j < batch; ++j)
        if (j < count) slot[j] = node_slots[i + j];
TEAR_UNROLL
      for (int j = 0; j < batch; ++j)
        if (j < count) {
          coef[j] = node_slot_coef[i + j];
          f[j] = load3<float>(constraint_force, constraints.constraint_of_slot(slot[j]));
        }
TEAR_UNROLL
      for (int j = 0; j < batch; ++j)
        if (j < count) g = g + coef[j] * f[j];
    }
    store3(node_iter_next, n, accelerated_from(x, load3<float>(node_iter_prev, n), diag, g));
  }

  // The update's two ends, shared with the CUDA solver's one-pass kernel, which sums g its own way
  // and may hold a node's values (mass, x⁽ᵏ⁻¹⁾, ...) instead of reading them each iteration.
  /// The sum's first term, m/h² (s − x).
  TEAR_HD Vec3f inertial_term(index_t n, const Vec3f& x, const Vec3f& s) const { return inertial_term_of(node_mass[n], x, s); }
  TEAR_HD Vec3f inertial_term_of(float mass, const Vec3f& x, const Vec3f& s) const { return (mass * inv_h2) * (s - x); }
  /// x⁽ᵏ⁺¹⁾ from the summed g of a free node with a positive diagonal: the Jacobi step, then
  /// Chebyshev's.
  TEAR_HD Vec3f accelerated_from(const Vec3f& x, const Vec3f& x_prev, float diag, const Vec3f& g) const {
    const Vec3f x_hat = x + (1.0f / diag) * g;
    return omega * (gamma * (x_hat - x) + x - x_prev) + x_prev;
  }
  /// x⁽ᵏ⁺¹⁾ of any node from its summed g: x for a pinned node, s for one without a positive
  /// diagonal, else `accelerated_from`.
  TEAR_HD Vec3f next_from_sum(index_t n, const Vec3f& x, const Vec3f& s, const Vec3f& g) const {
    return next_from_held(node_pinned[n] != 0, node_diag[n], x, load3<float>(node_iter_prev, n), s, g);
  }
  /// The same from the node's values as a kernel holds them.
  TEAR_HD Vec3f next_from_held(bool pinned, float diag, const Vec3f& x, const Vec3f& x_prev, const Vec3f& s,
                               const Vec3f& g) const {
    if (pinned) return x;
    return diag > 0.0f ? accelerated_from(x, x_prev, diag, g) : s;
  }
};

/// A collider as the kernels see it during one substep: a plane (point, unit normal) or a sphere
/// (centre, radius), where its keys put it at the substep's end, moving at `velocity`.
struct PdCollider {
  std::int32_t kind;  ///< 0 plane, 1 sphere
  float point[3];
  float normal[3];
  float radius;
  float velocity[3];  ///< m/s, 0 for a static collider
};

/// Pushes a node out of a collider along the surface normal and removes the velocity component,
/// relative to the collider, that points into it: a pushed node moves away at least as fast as the
/// collider's surface. No friction: the tangential velocity is kept.
TEAR_HD inline void collide(const PdCollider& c, Vec3f& x, Vec3f& v) {
  const Vec3f point{c.point[0], c.point[1], c.point[2]};
  Vec3f normal;
  float depth;  // > 0 inside
  if (c.kind == 0) {
    normal = Vec3f{c.normal[0], c.normal[1], c.normal[2]};
    depth = -dot(x - point, normal);
  } else {
    const Vec3f r = x - point;
    const float len = norm(r);
    // A node exactly at the centre has no outward direction; up is as good as any.
    normal = len > 0.0f ? (1.0f / len) * r : Vec3f{0, 1, 0};
    depth = c.radius - len;
  }
  if (!(depth > 0.0f)) return;
  x = x + depth * normal;
  const float vn = dot(v - Vec3f{c.velocity[0], c.velocity[1], c.velocity[2]}, normal);
  if (vn < 0.0f) v = v - vn * normal;
}

/// End of a step: v = (x − xₙ)/h scaled by the damping factor, x = the last iterate, then the
/// colliders in order. Pinned nodes take their pinned position (the last iterate holds it) and
/// their pin's velocity: none without keys.
struct finish_step {
  const std::uint8_t* node_pinned;
  const PdPinMotion* pin_motion;  // [pin_count]
  index_t pin_count;
  const float* node_iter;
  float inv_h;
  float velocity_scale;  // (1 − damping)^h
  const PdCollider* colliders;
  index_t collider_count;
  float* node_pos;
  float* node_vel;
  TEAR_HD void operator()(index_t n) const { finish(n, n); }
  /// Node n's end of step from its last iterate, at place i of `node_iter`.
  TEAR_HD void finish(index_t n, index_t i) const {
    if (node_pinned[n]) {
      const PdPinMotion* motion = pin_motion_of(node_pinned, pin_motion, pin_count, n);
      if (!motion) {
        store3(node_vel, n, Vec3f{0, 0, 0});
        return;
      }
      store3(node_pos, n, load3<float>(node_iter, i));
      store3(node_vel, n, Vec3f{motion->velocity[0], motion->velocity[1], motion->velocity[2]});
      return;
    }
    Vec3f x = load3<float>(node_iter, i);
    Vec3f v = (velocity_scale * inv_h) * (x - load3<float>(node_pos, n));
    for (index_t i = 0; i < collider_count; ++i) collide(colliders[i], x, v);
    store3(node_pos, n, x);
    store3(node_vel, n, v);
  }
};

/// Chebyshev weight ω of iteration k (0-based) given the previous one (Wang 2015, eq. 11): 1 for
/// the first `delay` iterations, then 2/(2 − ρ²), then 4/(4 − ρ² ω), rising towards
/// 2/(1 + √(1 − ρ²)).
TEAR_HD inline double chebyshev_omega(int k, int delay, double rho, double previous_omega) {
  if (k < delay) return 1.0;
  if (k == delay) return 2.0 / (2.0 - rho * rho);
  return 4.0 / (4.0 - rho * rho * previous_omega);
}

}  // namespace tear::kernels
