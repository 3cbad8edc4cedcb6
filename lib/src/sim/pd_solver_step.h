// tear: a frame's substeps, run the way the launch mode says, and the choice of launch for a mesh;
// launch modes `graph` (a substep's launches recorded once as a CUDA graph and replayed), `plain`
// (every kernel launched on its own) and `tiled` (its substep: prediction and end in the solver's
// place order, an iteration one launch of sim/pd_launch_tiled.h's kernel, replayed as a graph).
// Part of the solver's device code, included by sim/pd_solver.inl alone.
#pragma once

#include <cmath>
#include <string>

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
  if (launch_mode_ != LaunchMode::graph && launch_mode_ != LaunchMode::plain && launch_mode_ != LaunchMode::tiled &&
      step_persistent(count))
    return;
  if (tiled_used_) {
    step_graph_->run([this](const auto& policy) { enqueue_tiled_substep(policy); }, count);
    return;
  }
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

template <class System>
void PdSolverOn<System>::decide_launch(const float* node_rest) {
  tiled_used_ = false;
  persistent_ = {};
  if (launch_mode_ != LaunchMode::graph && launch_mode_ != LaunchMode::plain && launch_mode_ != LaunchMode::tiled)
    persistent_ = persistent_launch();
  using Kind = typename PersistentLaunch::Kind;
  // Tiled where no cooperative kernel holds the substep in registers or shared memory: it beats
  // two passes on every mesh measured that they do not hold (docs/BENCHMARKS.md).
  // The tiled layout holds edges' constraints alone: a membrane runs every other way.
  const bool try_tiled =
      membrane_face_count_ == 0 && (launch_mode_ == LaunchMode::tiled ||
                                    ((launch_mode_ == LaunchMode::persistent || persistent_.kind == Kind::none) &&
                                     launch_mode_ != LaunchMode::graph && launch_mode_ != LaunchMode::plain &&
                                     persistent_.kind != Kind::one_pass && persistent_.kind != Kind::shared));
#if TEAR_CUDA_SYSTEM
  if constexpr (std::is_same<System, Cuda>::value) {
    int device = 0, optin = 0;
    if (try_tiled && tiled_.plan(constraints(), node_count_, node_rest) && cudaGetDevice(&device) == cudaSuccess &&
        cudaDeviceGetAttribute(&optin, cudaDevAttrMaxSharedMemoryPerBlockOptin, device) == cudaSuccess &&
        tiled_.shared_bytes() <= static_cast<std::size_t>(optin) &&
        cudaFuncSetAttribute(tiled_iteration_kernel, cudaFuncAttributeMaxDynamicSharedMemorySize,
                             static_cast<int>(tiled_.shared_bytes())) == cudaSuccess) {
      // From here on the model's copies that the tiled kernel does not read are freed as soon as
      // the layout has taken what it needs of them: its build never holds more than the model did.
      static_cast<void>(constraint_count());  // counted while the records are there
      vec<float>().swap(node_slot_coef_);
      tiled_.write_records(constraints());
      for (auto* v : {&spring_weight_, &spring_rest_, &hinge_coef_, &hinge_weight_, &hinge_rest_})
        vec<float>().swap(*v);
      for (auto* v : {&spring_nodes_, &hinge_nodes_}) vec<index_t>().swap(*v);
      tiled_.write_slots(edge_count_, raw<index_t>(node_slot_offset_), raw<index_t>(node_slots_),
                         raw<float>(node_mass_), raw<float>(node_diag_), raw<std::uint8_t>(node_pinned_));
      vec<index_t>().swap(node_slots_);
      persistent_ = {};
      tiled_used_ = true;
      return;
    }
    cudaGetLastError();  // clear the error of a refused attribute
  }
#else
  static_cast<void>(try_tiled);
  static_cast<void>(node_rest);
#endif
  tiled_ = TiledLayout<System>();
  resize_for_overwrite(constraint_force_, 3 * static_cast<std::size_t>(constraint_count_));
}

template <class System>
template <class Policy>
void PdSolverOn<System>::enqueue_tiled_substep(const Policy& policy) {
#if TEAR_CUDA_SYSTEM
  if constexpr (std::is_same<System, Cuda>::value) {
    const thrust::counting_iterator<index_t> zero(0);
    SubstepKernels s = substep_kernels(omega_host_.data());
    thrust::for_each(policy, zero, zero + node_count_, tiled_predict{s.predict, raw<index_t>(tiled_.place_node)});
    // The iterates and the nodes' values by place.
    s.update.node_mass = raw<float>(tiled_.mass);
    s.update.node_diag = raw<float>(tiled_.diag);
    s.update.node_pinned = raw<std::uint8_t>(tiled_.pinned);
    const TiledModel model = tiled_.model();
    Policy stream_policy = policy;
    const cudaStream_t stream = thrust::cuda_cub::stream(stream_policy);
    const std::size_t bytes = tiled_.shared_bytes();
    Iterates it = s.first_iterates();
    for (int k = 0; k < options_.iterations; ++k) {
      s.iteration(k, it);
      tiled_iteration_kernel<<<static_cast<unsigned>(tiled_.tiles), tiled_block, bytes, stream>>>(model, s.update);
      const cudaError_t status = cudaGetLastError();
      if (status != cudaSuccess)
        throw runtime_error(std::string("the solver's kernel could not be launched: ") + cudaGetErrorString(status));
      it.rotate();
    }
    s.finish_from(it);
    thrust::for_each(policy, zero, zero + node_count_, tiled_finish{s.finish, raw<index_t>(tiled_.node_place)});
    return;
  }
#endif
  static_cast<void>(policy);
}

}  // namespace tear::backend
