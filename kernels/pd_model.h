// tear kernels: the projective dynamics model of a mesh: node masses, constraints and the
// node→constraint CSR that the Jacobi step gathers through.
//
// A constraint c acts on up to four nodes with coefficients kᵢ: A_c x = Σ kᵢ x_{nᵢ}; its
// projection keeps |A_c x| at a rest value (pd_math.h). Stretch constraint e is edge e's spring,
// bending constraint edge_count + e its hinge; unused slots hold node -1 and weight 0.
#pragma once

#include <cstdint>

#include "hd.h"
#include "pd_math.h"

namespace tear::kernels {

using index_t = std::int32_t;

inline constexpr int pd_constraint_nodes = 4;  ///< node slots per constraint

/// Mass of each node: density × a third of the rest area of each of its faces, kg. A gather over
/// the node→faces CSR in face order.
struct compute_node_masses {
  const index_t* face_nodes;
  const float* node_rest;
  const index_t* node_face_offset;
  const index_t* node_faces;
  double density;  // kg/m²
  float* node_mass;
  TEAR_HD void operator()(index_t n) const {
    double area = 0;
    for (index_t i = node_face_offset[n]; i < node_face_offset[n + 1]; ++i) {
      const index_t f = node_faces[i];
      area +=
          triangle_area(load3<double>(node_rest, face_nodes[3 * f]), load3<double>(node_rest, face_nodes[3 * f + 1]),
                        load3<double>(node_rest, face_nodes[3 * f + 2]));
    }
    node_mass[n] = static_cast<float>(density * area / 3.0);
  }
};

/// The node of face `f` that is neither `a` nor `b`.
TEAR_HD inline index_t opposite_node(const index_t* face_nodes, index_t f, index_t a, index_t b) {
  for (int k = 0; k < 3; ++k) {
    const index_t n = face_nodes[3 * f + k];
    if (n != a && n != b) return n;
  }
  return -1;
}

/// The constraints as the kernels see them. Constraint e < edge_count is the spring of edge e:
/// nodes spring_nodes[2e], [2e + 1] with coefficients +1 and −1 (both nodes −1 when it has no
/// weight). Constraint edge_count + e is the hinge of edge e: four nodes and coefficients (unused
/// slots node −1, coefficient 0). With the membrane model (`face_count` > 0), constraint
/// 2 edge_count + 2 f + j is column j of face f's deformation gradient: its three nodes with the
/// coefficients that make Σ kᵢ xᵢ that column (`make_membrane_constraints`). A slot is one node of
/// one constraint: slot s < 2 edge_count is node s % 2 of spring s / 2, slot 2 edge_count + 4 e + j
/// node j of hinge e, slot 6 edge_count + 3 c + i node i of membrane column c; slots are numbered in
/// constraint order. A spring takes 16 bytes (nodes, weight, rest length), a hinge 40, a face's
/// membrane 40 (nodes, six coefficients, weight).
struct PdConstraints {
  index_t edge_count;
  const index_t* spring_nodes;  // [edge_count * 2]
  const float* spring_weight;   // [edge_count]
  const float* spring_rest;     // [edge_count]
  const index_t* hinge_nodes;   // [edge_count * 4]
  const float* hinge_coef;      // [edge_count * 4]
  const float* hinge_weight;    // [edge_count]
  const float* hinge_rest;      // [edge_count]
  index_t face_count = 0;       // faces with a membrane (0: the spring model)
  const index_t* membrane_nodes = nullptr;  // [face_count * 3]
  const float* membrane_coef = nullptr;     // [face_count * 6]: column 0's three, then column 1's
  const float* membrane_weight = nullptr;   // [face_count]

  TEAR_HD index_t slot_count() const { return 6 * edge_count + 6 * face_count; }
  TEAR_HD index_t constraint_of_slot(index_t s) const {
    if (s < 2 * edge_count) return s / 2;
    if (s < 6 * edge_count) return edge_count + (s - 2 * edge_count) / pd_constraint_nodes;
    return 2 * edge_count + (s - 6 * edge_count) / 3;
  }
  TEAR_HD index_t slot_node(index_t s) const {
    if (s < 2 * edge_count) return spring_nodes[s];
    if (s < 6 * edge_count) return hinge_nodes[s - 2 * edge_count];
    const index_t m = s - 6 * edge_count;  // 3 × column + node
    return membrane_nodes[3 * (m / 6) + m % 3];
  }
  TEAR_HD float slot_coef(index_t s) const {
    if (s < 2 * edge_count) return s % 2 ? -1.0f : 1.0f;
    if (s < 6 * edge_count) return hinge_coef[s - 2 * edge_count];
    return membrane_coef[s - 6 * edge_count];
  }
  TEAR_HD float weight(index_t c) const {
    if (c < edge_count) return spring_weight[c];
    if (c < 2 * edge_count) return hinge_weight[c - edge_count];
    return membrane_weight[(c - 2 * edge_count) / 2];
  }
  /// Σ |kⱼ| over the constraint's slots.
  TEAR_HD float coef_abs_sum(index_t c) const {
    if (c < edge_count) return 2.0f;
    const float* k = c < 2 * edge_count ? hinge_coef + pd_constraint_nodes * (c - edge_count)
                                        : membrane_coef + 3 * (c - 2 * edge_count);
    const int count = c < 2 * edge_count ? pd_constraint_nodes : 3;
    float sum = 0.0f;
    for (int j = 0; j < count; ++j) sum += fabsf(k[j]);
    return sum;
  }
};

/// Constraint e: the spring of edge e, weight stretch_stiffness × A_e / L² (A_e: a third of the
/// rest area of its faces), so the energy w/2 (|d| − L)² is stiffness/2 × strain² × A_e.
/// Constraint edge_count + e: the hinge of interior edge e, weight bend_stiffness × 3 L² /
/// (A₀ + A₁) (the discrete-shell scaling of θ², Grinspun et al. 2003), rest value its rest fold.
struct make_pd_constraints {
  const index_t* face_nodes;
  const float* node_rest;
  const index_t* edge_nodes;
  const index_t* edge_faces;
  const index_t* edge_face_count;
  index_t edge_count;
  double stretch_stiffness;  // N/m
  double bend_stiffness;     // N·m
  index_t* spring_nodes;     // [edge_count * 2]
  float* spring_weight;      // [edge_count]
  float* spring_rest;        // [edge_count]
  index_t* hinge_nodes;      // [edge_count * 4]
  float* hinge_coef;         // [edge_count * 4]
  float* hinge_weight;       // [edge_count]
  float* hinge_rest;         // [edge_count]

  TEAR_HD void operator()(index_t e) const {
    spring_nodes[2 * e] = spring_nodes[2 * e + 1] = -1;
    spring_weight[e] = spring_rest[e] = 0.0f;
    for (int j = 0; j < pd_constraint_nodes; ++j) {
      hinge_nodes[pd_constraint_nodes * e + j] = -1;
      hinge_coef[pd_constraint_nodes * e + j] = 0.0f;
    }
    hinge_weight[e] = hinge_rest[e] = 0.0f;
    const index_t a = edge_nodes[2 * e], b = edge_nodes[2 * e + 1];
    const Vec3d xa = load3<double>(node_rest, a), xb = load3<double>(node_rest, b);
    const double len2 = dot(xb - xa, xb - xa);
    double face_area[2] = {0, 0};
    index_t opposite[2] = {-1, -1};
    const index_t faces = edge_face_count[e] < 2 ? edge_face_count[e] : 2;
    for (index_t i = 0; i < faces; ++i) {
      const index_t f = edge_faces[2 * e + i];
      opposite[i] = opposite_node(face_nodes, f, a, b);
      if (opposite[i] >= 0) face_area[i] = triangle_area(xa, xb, load3<double>(node_rest, opposite[i]));
    }

    const double stretch_weight = stretch_stiffness * (face_area[0] + face_area[1]) / 3.0 / len2;
    if (len2 > 0 && stretch_weight > 0) {
      spring_nodes[2 * e] = a;
      spring_nodes[2 * e + 1] = b;
      spring_weight[e] = static_cast<float>(stretch_weight);
      spring_rest[e] = static_cast<float>(sqrt(len2));
    }

    // A hinge needs exactly two faces (a non-manifold edge's fans have no single dihedral angle).
    if (edge_face_count[e] != 2 || opposite[0] < 0 || opposite[1] < 0 || !(bend_stiffness > 0)) return;
    const index_t hinge[4] = {a, b, opposite[0], opposite[1]};
    double k[4];
    if (!hinge_coefficients(xa, xb, load3<double>(node_rest, opposite[0]), load3<double>(node_rest, opposite[1]), k))
      return;
    Vec3d fold{0, 0, 0};
    for (int j = 0; j < 4; ++j) {
      hinge_nodes[pd_constraint_nodes * e + j] = hinge[j];
      hinge_coef[pd_constraint_nodes * e + j] = static_cast<float>(k[j]);
      fold = fold + k[j] * load3<double>(node_rest, hinge[j]);
    }
    hinge_weight[e] = static_cast<float>(bend_stiffness * 3.0 * len2 / (face_area[0] + face_area[1]));
    hinge_rest[e] = static_cast<float>(norm(fold));
  }
};

/// Face f's membrane: the two columns of its deformation gradient F = [x₁ − x₀, x₂ − x₀] D⁻¹ (D:
/// the rest edges in the face's own orthonormal frame), as coefficients of its three nodes, and the
/// weight stretch_stiffness × 3/8 × A. The energy w/2 ‖F − R‖² then resists stretch and shear
/// alike in every direction (isotropic, whatever the face's shape), and a sheet of equilateral faces
/// is as stiff under a one-way stretch as with the spring model's springs at the same stiffness
/// (their energy density is stiffness/2 × 3/8 × ε² there). A face with no area compared with its
/// longest edge squared gets no membrane (nodes −1, weight 0).
struct make_membrane_constraints {
  const index_t* face_nodes;
  const float* node_rest;
  double stretch_stiffness;  // N/m
  index_t* membrane_nodes;   // [face_count * 3]
  float* membrane_coef;      // [face_count * 6]
  float* membrane_weight;    // [face_count]
  TEAR_HD void operator()(index_t f) const {
    for (int i = 0; i < 3; ++i) membrane_nodes[3 * f + i] = -1;
    for (int i = 0; i < 6; ++i) membrane_coef[6 * f + i] = 0.0f;
    membrane_weight[f] = 0.0f;
    const index_t n[3] = {face_nodes[3 * f], face_nodes[3 * f + 1], face_nodes[3 * f + 2]};
    const Vec3d x0 = load3<double>(node_rest, n[0]);
    const Vec3d e1 = load3<double>(node_rest, n[1]) - x0, e2 = load3<double>(node_rest, n[2]) - x0;
    const double a = norm(e1);
    const double twice_area = norm(cross(e1, e2));
    const double longest2 = fmax(dot(e1, e1), fmax(dot(e2, e2), dot(e2 - e1, e2 - e1)));
    if (!(a > 0) || !(twice_area > 1e-8 * longest2) || !(stretch_stiffness > 0)) return;
    // D = [a b; 0 c] in the frame (e1/a, its normal in the face's plane); D⁻¹ = [1/a −b/(ac); 0 1/c].
    const double b = dot(e1, e2) / a, c = twice_area / a;
    const double inv[2][2] = {{1.0 / a, -b / (a * c)}, {0.0, 1.0 / c}};
    for (int j = 0; j < 2; ++j) {
      membrane_coef[6 * f + 3 * j + 0] = static_cast<float>(-(inv[0][j] + inv[1][j]));
      membrane_coef[6 * f + 3 * j + 1] = static_cast<float>(inv[0][j]);
      membrane_coef[6 * f + 3 * j + 2] = static_cast<float>(inv[1][j]);
    }
    for (int i = 0; i < 3; ++i) membrane_nodes[3 * f + i] = n[i];
    membrane_weight[f] = static_cast<float>(stretch_stiffness * 0.375 * 0.5 * twice_area);
  }
};

/// The faces whose membrane is in use.
struct count_membranes {
  const float* membrane_weight;  // [face_count]
  TEAR_HD index_t operator()(index_t f) const { return index_t(membrane_weight[f] > 0.0f); }
};

/// The constraints of edge `e` in use: its spring and its hinge, each where its weight is positive.
struct count_edge_constraints {
  const float* spring_weight;  // [edge_count]
  const float* hinge_weight;   // [edge_count]
  TEAR_HD index_t operator()(index_t e) const {
    return index_t(spring_weight[e] > 0.0f) + index_t(hinge_weight[e] > 0.0f);
  }
};

/// The used constraint slots keyed by their node, valued by themselves: node→constraint slots, in
/// slot (so constraint) order once counted and sorted (build_topology.h `count_keys`).
struct ConstraintSlots {
  PdConstraints constraints;
  TEAR_HD index_t key(index_t s) const { return constraints.slot_node(s); }
  TEAR_HD index_t value(index_t s) const { return s; }
};

/// The Jacobi diagonal: M/h² + Σ_c w_c βᵢ kᵢ² at each node, gathered over its slots, with
/// βᵢ = max(1, Σⱼ|kⱼ| / (2|kᵢ|)) per constraint. With β = 1 it is the diagonal of the global matrix
/// M/h² + Σ w AᵀA; the βs make D ≥ A/2 for every constraint alone (w k kᵀ ≤ 2 w diag(β k²) by
/// Cauchy–Schwarz with weights |kᵢ|), so λ(D⁻¹A) < 2 on any mesh and the under-relaxed Jacobi
/// iteration cannot diverge. An edge spring (k = ±1) keeps β = 1: its term is exact. A hinge gets
/// β = 2 at most nodes of a well-shaped one; on a sliver its small coefficients get the large βs, so
/// that one stiff hinge cannot drive its nodes into oscillation (it would with β = 1: a hinge alone
/// has λ(D⁻¹A) = 4).
///
/// Also copies each slot's coefficient beside the slot in the CSR (`node_slot_coef`), so that the
/// Jacobi update reads its coefficients in a run instead of one scattered load per hinge slot.
struct compute_jacobi_diagonal {
  const index_t* node_slot_offset;
  const index_t* node_slots;
  PdConstraints constraints;
  const float* node_mass;
  float inv_h2;  // 1/s²
  float* node_diag;
  float* node_slot_coef;  // [slots], in CSR order
  TEAR_HD void operator()(index_t n) const {
    float d = node_mass[n] * inv_h2;
    for (index_t i = node_slot_offset[n]; i < node_slot_offset[n + 1]; ++i) {
      const index_t s = node_slots[i];
      const index_t c = constraints.constraint_of_slot(s);
      const float coef = constraints.slot_coef(s);
      node_slot_coef[i] = coef;
      const float k = fabsf(coef);
      const float sum = constraints.coef_abs_sum(c);
      d += constraints.weight(c) * k * (0.5f * sum > k ? 0.5f * sum : k);
    }
    node_diag[n] = d;
  }
};

}  // namespace tear::kernels
