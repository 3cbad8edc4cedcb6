// tear: a frame's substeps, run the way the launch mode says; launch modes `graph` (a substep's
// launches recorded once as a CUDA graph and replayed) and `plain` (every kernel launched on its
// own).
// Part of the solver's device code, included by sim/pd_solver.inl alone.
#pragma once

#include <cmath>

#include <thrust/for_each.h>
#include <thrust/iterator/counting_iterator.h>

#include "sim/pd_solver_on.h"

namespace tear::backend {

template <class System>
void PdSolverOn<System>::step_frame(int frame) {
  last_frame_ = frame;
  if (!keyed_) {
    run_substeps(options_.substeps);
    return;
  }
  for (int s = 0; s < options_.substeps; ++s) {
    select_substep_motion(frame, s);
    run_substeps(1);
  }
}

template <class System>
void PdSolverOn<System>::step_substep_in_place(float* node_pos, float* node_vel, int frame, int s) {
  bind_state(node_pos, node_vel);
  last_frame_ = frame;
  if (keyed_) select_substep_motion(frame, s);
  run_substeps(1);
}

template <class System>
void PdSolverOn<System>::run_substeps(int count) {
  if (launch_mode_ != LaunchMode::graph && launch_mode_ != LaunchMode::plain && step_persistent(count)) return;
  const auto enqueue = [this](const auto& policy) { enqueue_substep(policy); };
  if (launch_mode_ == LaunchMode::plain) {
    for (int i = 0; i < count; ++i) enqueue(Traits<System>::policy());
    return;
  }
  // One substep is always the same launches with the same arguments: replayed as one graph.
  step_graph_->run(enqueue, count);
}

template <class System>
SubstepKernels PdSolverOn<System>::substep_kernels(const float* omega) {
  using namespace kernels;
  const double h = options_.step_seconds();
  const Vec3f gravity{static_cast<float>(options_.gravity[0]), static_cast<float>(options_.gravity[1]),
                      static_cast<float>(options_.gravity[2])};
  const PdConstraints model = constraints();
  SubstepKernels s{};
  // Inertial prediction (Bouaziz et al. 2014, eq. 9): the first iterate.
  const index_t pin_count = static_cast<index_t>(pin_motion_.size());
  s.predict = predict_positions{state_pos_,
                                state_vel_,
                                raw<std::uint8_t>(node_pinned_),
                                raw<float>(node_rest_),
                                raw<PdPinMotion>(pin_motion_),
                                pin_count,
                                static_cast<float>(h),
                                gravity,
                                raw<float>(node_pred_),
                                raw<float>(node_iter_[0]),
                                raw<float>(node_iter_[1])};
  // Local step: every constraint's projection at the current iterate (§4.1).
  s.project = project_constraints{model, nullptr, raw<float>(constraint_force_)};
  // Global step: one Chebyshev-weighted Jacobi update per node (Wang 2015, §4).
  s.update = jacobi_chebyshev_update{raw<index_t>(node_slot_offset_),
                                     raw<index_t>(node_slots_),
                                     raw<float>(node_slot_coef_),
                                     model,
                                     raw<float>(constraint_force_),
                                     raw<float>(node_mass_),
                                     raw<float>(node_diag_),
                                     raw<std::uint8_t>(node_pinned_),
                                     raw<float>(node_pred_),
                                     nullptr,
                                     nullptr,
                                     static_cast<float>(1.0 / (h * h)),
                                     0.0f,
                                     static_cast<float>(options_.chebyshev.gamma),
                                     nullptr};
  // Velocity update, damping and colliders.
  s.finish = finish_step{raw<std::uint8_t>(node_pinned_),
                         raw<PdPinMotion>(pin_motion_),
                         pin_count,
                         nullptr,
                         static_cast<float>(1.0 / h),
                         static_cast<float>(std::pow(1.0 - options_.damping, h)),
                         raw<PdCollider>(colliders_),
                         static_cast<index_t>(colliders_.size()),
                         state_pos_,
                         state_vel_};
  s.node_count = node_count_;
  s.constraint_count = constraint_count_;
  s.iterations = options_.iterations;
  s.omega = omega;
  for (int i = 0; i < 3; ++i) s.iter[i] = raw<float>(node_iter_[i]);
  return s;
}

template <class System>
template <class Policy>
void PdSolverOn<System>::enqueue_substep(const Policy& policy) {
  const thrust::counting_iterator<index_t> zero(0);
  SubstepKernels s = substep_kernels(omega_host_.data());
  thrust::for_each(policy, zero, zero + node_count_, s.predict);
  Iterates it = s.first_iterates();
  for (int k = 0; k < options_.iterations; ++k) {
    s.iteration(k, it);
    thrust::for_each(policy, zero, zero + constraint_count_, s.project);
    thrust::for_each(policy, zero, zero + node_count_, s.update);
    it.rotate();
  }
  s.finish_from(it);
  thrust::for_each(policy, zero, zero + node_count_, s.finish);
}

}  // namespace tear::backend
