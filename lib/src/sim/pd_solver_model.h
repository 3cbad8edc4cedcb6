// tear: the solver's model of a mesh (masses, constraints, node→constraint CSR, Jacobi diagonal)
// and the keyed pins' and colliders' records of each substep.
// Part of the solver's device code, included by sim/pd_solver.inl alone.
#pragma once

#include <cstddef>
#include <vector>

#include <thrust/copy.h>

#include "build_topology.h"
#include "sim/pd_solver_on.h"

namespace tear::backend {

template <class System>
void PdSolverOn<System>::build_model(const vec<index_t>& face_nodes, const vec<float>& node_rest,
                                     const DeviceTopology<System>& topo) {
  using namespace kernels;
  const auto policy = Traits<System>::policy();
  if (held_state_) thrust::copy(policy, node_rest.begin(), node_rest.end(), node_pos_.begin());
  bool keyed_pins = false;
  for (const Pin& p : options_.pins) keyed_pins = keyed_pins || !p.keys.empty();
  if (keyed_pins) {  // into the kept array: a rebuild after every tear would allocate it again
    resize_for_overwrite(node_rest_, node_rest.size());
    thrust::copy(policy, node_rest.begin(), node_rest.end(), node_rest_.begin());
  }
  if (keyed_) {
    const std::size_t substeps = static_cast<std::size_t>(options_.substeps);
    frame_pin_motion_.resize(substeps * pin_motion_.size());
    frame_colliders_.resize(substeps * colliders_.size());
  }

  // Masses (per node), constraints (per edge) and membranes (per face) in one launch.
  resize_for_overwrite(node_mass_, node_count_);
  const index_t edge_count = topo.edge_count;
  const bool membrane = options_.stretch_model_used() == StretchModel::membrane;
  membrane_face_count_ = membrane ? static_cast<index_t>(face_nodes.size() / 3) : 0;
  constraint_count_ = 2 * edge_count + 2 * membrane_face_count_;
  edge_count_ = edge_count;
  resize_for_overwrite(membrane_nodes_, 3 * static_cast<std::size_t>(membrane_face_count_));
  resize_for_overwrite(membrane_coef_, 6 * static_cast<std::size_t>(membrane_face_count_));
  resize_for_overwrite(membrane_weight_, membrane_face_count_);
  resize_for_overwrite(spring_nodes_, 2 * static_cast<std::size_t>(edge_count));
  resize_for_overwrite(hinge_nodes_, pd_constraint_nodes * static_cast<std::size_t>(edge_count));
  resize_for_overwrite(hinge_coef_, pd_constraint_nodes * static_cast<std::size_t>(edge_count));
  for (auto* v : {&spring_weight_, &spring_rest_, &hinge_weight_, &hinge_rest_}) resize_for_overwrite(*v, edge_count);
  for_each_index<System>(
      node_count_ + edge_count + membrane_face_count_,
      make_over_three_ranges(
          compute_node_masses{raw<index_t>(face_nodes), raw<float>(node_rest), raw<index_t>(topo.node_face_offset),
                              raw<index_t>(topo.node_faces), options_.density, raw<float>(node_mass_)},
          make_pd_constraints{raw<index_t>(face_nodes), raw<float>(node_rest), raw<index_t>(topo.edge_nodes),
                              raw<index_t>(topo.edge_faces), raw<index_t>(topo.edge_face_count), edge_count,
                              membrane ? 0.0 : options_.stretch_stiffness, options_.bend_stiffness,
                              raw<index_t>(spring_nodes_), raw<float>(spring_weight_), raw<float>(spring_rest_),
                              raw<index_t>(hinge_nodes_), raw<float>(hinge_coef_), raw<float>(hinge_weight_),
                              raw<float>(hinge_rest_)},
          make_membrane_constraints{raw<index_t>(face_nodes), raw<float>(node_rest), options_.stretch_stiffness,
                                    raw<index_t>(membrane_nodes_), raw<float>(membrane_coef_),
                                    raw<float>(membrane_weight_)},
          node_count_, edge_count));
  active_constraint_count_ = -1;

  // Node→constraint CSR: the used slots counting-sorted by node, so a node's constraints come in
  // index order, the fixed order its Jacobi update sums them in. Its values are given room for
  // every slot, so that no count is read back: the used ones are a prefix.
  const PdConstraints model = constraints();
  build_csr_by_counting<System>(policy, ConstraintSlots{model}, model.slot_count(), node_count_, model.slot_count(),
                                node_tally_, node_slot_offset_, node_slots_);

  const double h = options_.step_seconds();
  resize_for_overwrite(node_diag_, node_count_);
  resize_for_overwrite(node_slot_coef_, node_slots_.size());
  for_each_index<System>(
      node_count_,
      compute_jacobi_diagonal{raw<index_t>(node_slot_offset_), raw<index_t>(node_slots_), model, raw<float>(node_mass_),
                              static_cast<float>(1.0 / (h * h)), raw<float>(node_diag_), raw<float>(node_slot_coef_)});
}

template <class System>
void PdSolverOn<System>::select_substep_motion(int frame, int s) {
  if (uploaded_frame_ != frame) {
    std::vector<kernels::PdPinMotion> pins;
    std::vector<kernels::PdCollider> colliders;
    for (int t = 0; t < options_.substeps; ++t) substep_motion(frame, t, pins, colliders);
    // (Thrust's copy of an empty range binds a reference to its destination's first element, which
    // an empty vector does not have: keyed colliders with no pin, keyed pins with no collider.)
    if (!pins.empty()) thrust::copy(pins.begin(), pins.end(), frame_pin_motion_.begin());
    if (!colliders.empty()) thrust::copy(colliders.begin(), colliders.end(), frame_colliders_.begin());
    uploaded_frame_ = frame;
  }
  const auto policy = Traits<System>::policy();
  const std::ptrdiff_t pin_count = static_cast<std::ptrdiff_t>(pin_motion_.size());
  const std::ptrdiff_t collider_count = static_cast<std::ptrdiff_t>(colliders_.size());
  const auto pin_first = frame_pin_motion_.begin() + s * pin_count;
  const auto collider_first = frame_colliders_.begin() + s * collider_count;
  if (pin_count > 0) thrust::copy(policy, pin_first, pin_first + pin_count, pin_motion_.begin());
  if (collider_count > 0) thrust::copy(policy, collider_first, collider_first + collider_count, colliders_.begin());
}

}  // namespace tear::backend
