// tear: the projective dynamics solver on one backend system (`PdSolverOn<System>`): its state,
// model arrays and the members defined inline; the rest is in pd_solver_model.h, pd_solver_step.h
// and pd_launch_persistent.h.
// Part of the solver's device code, included by sim/pd_solver.inl alone.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <vector>

#include <thrust/copy.h>
#include <thrust/fill.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/transform_reduce.h>

#include "backend/backend.h"
#include "backend/replay_graph.h"
#include "pd_model.h"
#include "pd_step.h"
#include "sim/pd_launch_tiled.h"
#include "sim/pd_solver.h"
#include "sim/pd_solver_device.h"
#include "sim/pd_substep.h"
#include "sim/substep_records.h"
#include "tear/error.h"
#include "tear/simulation_options.h"
#include "topology/device_topology.h"

namespace tear::backend {

template <class System>
class PdSolverOn final : public PdSolver::Impl {
  template <class T>
  using vec = vector<System, T>;

 public:
  /// From host arrays: uploads them and builds their topology.
  PdSolverOn(const std::vector<index_t>& face_nodes_host, const std::vector<float>& node_rest_host, index_t node_count,
             const SimulationOptions& options, const std::vector<std::uint8_t>& node_pinned)
      : PdSolverOn(options, node_count, node_pinned, true) {
    const vec<float> node_rest(node_rest_host.begin(), node_rest_host.end());
    {
      const vec<index_t> face_nodes(face_nodes_host.begin(), face_nodes_host.end());
      DeviceTopology<System> topo;
      build_device_topology(topo, face_nodes, node_count_);
      build_model(face_nodes, node_rest, topo);
    }
    decide_launch(raw<float>(node_rest));
  }

  /// From a cloth on this backend: its faces, rest shape, topology and pins; nothing leaves the device.
  /// The model only: the cloth's state is stepped in place (`step_in_place`), and the solver holds
  /// no positions or velocities of its own.
  PdSolverOn(const DeviceCloth<System>& cloth, const SimulationOptions& options)
      : PdSolverOn(options, cloth.node_count(), std::vector<std::uint8_t>(), false) {
    thrust::copy(Traits<System>::policy(), cloth.node_pinned.begin(), cloth.node_pinned.end(), node_pinned_.begin());
    build_model(cloth.face_nodes, cloth.node_rest, cloth.topo);
    decide_launch(raw<float>(cloth.node_rest));
  }

  /// The model of `cloth`'s mesh as it is now (after a cut or a tear), built into this solver's
  /// arrays, which only grow: what the constructor from a cloth builds, without allocating, filling
  /// and uploading again what does not depend on the mesh (the iterations' ω, the pins' and
  /// colliders' records). The next step records its launches again.
  void rebuild(const DeviceCloth<System>& cloth) {
    node_count_ = cloth.node_count();
    const std::size_t n3 = 3 * static_cast<std::size_t>(node_count_);
    resize_for_overwrite(node_pinned_, static_cast<std::size_t>(node_count_));
    thrust::copy(Traits<System>::policy(), cloth.node_pinned.begin(), cloth.node_pinned.end(), node_pinned_.begin());
    for (auto* v : {&node_pred_, &node_iter_[0], &node_iter_[1], &node_iter_[2]}) resize_for_overwrite(*v, n3);
    // A cloth's solver: `step_in_place` binds the cloth's state.
    state_pos_ = state_vel_ = nullptr;
    step_graph_ = std::make_unique<ReplayGraph<System>>();
    build_model(cloth.face_nodes, cloth.node_rest, cloth.topo);
    decide_launch(raw<float>(cloth.node_rest));  // the launch depends on the mesh
  }

 private:
  /// `held_state`: the solver holds a state of its own (the standalone `PdSolver`), at rest.
  PdSolverOn(const SimulationOptions& options, index_t node_count, const std::vector<std::uint8_t>& node_pinned,
             bool held_state)
      : options_(options),
        node_count_(node_count),
        node_pinned_(static_cast<std::size_t>(node_count), 0),
        node_pos_(held_state ? 3 * static_cast<std::size_t>(node_count) : 0, 0.0f),
        node_vel_(held_state ? 3 * static_cast<std::size_t>(node_count) : 0, 0.0f),
        held_state_(held_state) {
    if (!node_pinned.empty()) thrust::copy(node_pinned.begin(), node_pinned.end(), node_pinned_.begin());
    state_pos_ = held_state ? raw<float>(node_pos_) : nullptr;
    state_vel_ = held_state ? raw<float>(node_vel_) : nullptr;
    launch_mode_ = launch_mode();
    const auto& cheb = options.chebyshev;
    omega_host_.resize(static_cast<std::size_t>(options.iterations));
    double omega = 1.0;
    for (int k = 0; k < options.iterations; ++k)
      omega_host_[k] = static_cast<float>(omega = kernels::chebyshev_omega(k, cheb.delay, cheb.rho, omega));
    assign_from_host(omega_, omega_host_);
    node_pred_.resize(3 * static_cast<std::size_t>(node_count));
    for (auto& iter : node_iter_) iter.resize(3 * static_cast<std::size_t>(node_count));
    for (const Pin& p : options.pins) keyed_ = keyed_ || !p.keys.empty();
    for (const Collider& c : options.colliders) keyed_ = keyed_ || (!c.keys.empty() && c.kind != Collider::Kind::mesh);
    // Without keys the pins' and colliders' records never change; with keys they are those of the
    // first substep until a frame is stepped.
    std::vector<kernels::PdPinMotion> pins;
    std::vector<kernels::PdCollider> colliders;
    substep_motion(0, 0, pins, colliders);
    assign_from_host(pin_motion_, pins);
    assign_from_host(colliders_, colliders);
  }

  /// The pins' and colliders' records of substep `s` of frame `frame` (`substep_records`).
  void substep_motion(int frame, int s, std::vector<kernels::PdPinMotion>& pins,
                      std::vector<kernels::PdCollider>& colliders) const {
    substep_records(options_, frame, s, pins, colliders);
  }

 public:
  Device device() const override { return std::is_same<System, Omp>::value ? Device::cpu : Device::cuda; }
  index_t node_count() const override { return node_count_; }
  /// Counted when asked (a reduction and a read-back no rebuild after a tear needs).
  index_t constraint_count() const override {
    if (active_constraint_count_ < 0) {
      const thrust::counting_iterator<index_t> zero(0);
      active_constraint_count_ = thrust::transform_reduce(
          Traits<System>::policy(), zero, zero + edge_count_,
          kernels::count_edge_constraints{raw<float>(spring_weight_), raw<float>(hinge_weight_)}, index_t(0),
          thrust::plus<index_t>());
      if (membrane_face_count_ > 0)
        active_constraint_count_ +=
            2 * thrust::transform_reduce(Traits<System>::policy(), zero, zero + membrane_face_count_,
                                         kernels::count_membranes{raw<float>(membrane_weight_)}, index_t(0),
                                         thrust::plus<index_t>());
    }
    return active_constraint_count_;
  }
  std::size_t bytes_per_iteration() const override {
    if (tiled_used_) return tiled_.bytes_per_iteration();
    const std::size_t e = static_cast<std::size_t>(edge_count_), n = static_cast<std::size_t>(node_count_),
                      s = static_cast<std::size_t>(used_slot_count()), c = static_cast<std::size_t>(constraint_count_);
    // Local step: a spring's record (2 nodes, weight, rest length) or a hinge's (4 nodes, 4
    // coefficients, weight, rest value) read, its force written; each iterate read once. Global
    // step: a node's CSR offset, mass, diagonal, pin, prediction and two iterates read and the next
    // written; a slot's index and its coefficient (both in CSR order) read; each force read once.
    // A face's membrane: 3 nodes, 6 coefficients and a weight, read once for each of its columns.
    const std::size_t records =
        e * (2 * sizeof(index_t) + 2 * sizeof(float)) +
        e * (4 * sizeof(index_t) + 4 * sizeof(float) + 2 * sizeof(float)) +
        static_cast<std::size_t>(membrane_face_count_) * 2 * (3 * sizeof(index_t) + 7 * sizeof(float));
    const std::size_t forces = 2 * c * 3 * sizeof(float);
    const std::size_t node = sizeof(index_t) + 2 * sizeof(float) + 1 + 4 * 3 * sizeof(float);
    return records + forces + n * 3 * sizeof(float) + n * node + s * (sizeof(index_t) + sizeof(float));
  }
  const SimulationOptions& options() const override { return options_; }

  void step_frame(int frame) override;
  int last_frame() const override { return last_frame_; }
  void step_in_place(float* node_pos, float* node_vel, int frame) override {
    bind_state(node_pos, node_vel);
    step_frame(frame);
  }
  void step_substep_in_place(float* node_pos, float* node_vel, int frame, int s) override;

  void set_state(const std::vector<float>& node_pos, const std::vector<float>& node_vel) override {
    if (!held_state_) throw Error(ErrorKind::usage, "PdSolver::set_state: a cloth's solver holds no state");
    bind_state(raw<float>(node_pos_), raw<float>(node_vel_));
    thrust::copy(node_pos.begin(), node_pos.end(), node_pos_.begin());
    thrust::copy(node_vel.begin(), node_vel.end(), node_vel_.begin());
  }
  std::vector<float> node_pos() const override { return to_host<float>(node_pos_); }
  std::vector<float> node_vel() const override { return to_host<float>(node_vel_); }
  std::vector<float> node_mass() const override { return to_host<float>(node_mass_); }
  std::vector<std::uint8_t> node_pinned() const override { return to_host<std::uint8_t>(node_pinned_); }

 private:
  /// Steps the state at `node_pos`/`node_vel` from now on; a recorded substep holds the old
  /// pointers, so it is recorded again.
  void bind_state(float* node_pos, float* node_vel) {
    if (node_pos == state_pos_ && node_vel == state_vel_) return;
    state_pos_ = node_pos;
    state_vel_ = node_vel;
    step_graph_ = std::make_unique<ReplayGraph<System>>();
  }
  /// Masses, constraints, the node→constraint CSR and the Jacobi diagonal of the mesh; the state
  /// starts at rest (positions = rest positions, no velocity).
  void build_model(const vec<index_t>& face_nodes, const vec<float>& node_rest, const DeviceTopology<System>& topo);
  /// The slots the CSR holds (a read-back: for the figures, not the steps).
  index_t used_slot_count() const { return node_count_ > 0 ? static_cast<index_t>(node_slot_offset_[node_count_]) : 0; }
  kernels::PdConstraints constraints() const {
    return {edge_count_,
            raw<index_t>(spring_nodes_),
            raw<float>(spring_weight_),
            raw<float>(spring_rest_),
            raw<index_t>(hinge_nodes_),
            raw<float>(hinge_coef_),
            raw<float>(hinge_weight_),
            raw<float>(hinge_rest_),
            membrane_face_count_,
            raw<index_t>(membrane_nodes_),
            raw<float>(membrane_coef_),
            raw<float>(membrane_weight_)};
  }
  /// The substep's kernels; `omega` is where ω lives for whoever reads it.
  SubstepKernels substep_kernels(const float* omega);
  template <class Policy>
  void enqueue_substep(const Policy& policy);
  /// How this mesh's substeps run, decided once its model is built: the cooperative kernel
  /// (`persistent_`), or tiled (`tiled_used_`, its layout built from the model and the rest shape
  /// `node_rest`) where the launch mode is `tiled`, or `persistent` and no kernel holds the
  /// substep on chip. Frees what of the model the chosen launch does not read.
  void decide_launch(const float* node_rest);
  template <class Policy>
  void enqueue_tiled_substep(const Policy& policy);
  /// How a substep runs as one cooperative kernel on this mesh and device.
  struct PersistentLaunch {
    enum class Kind { none, one_pass, shared, two_pass } kind = Kind::none;  // none: as `graph`
    int blocks = 0;
    int lanes = 0;          // per node, one pass
    std::size_t bytes = 0;  // of shared memory per block, shared
  };
  PersistentLaunch persistent_launch() const;
  /// Runs `count` substeps as persistent kernels; false where they are not used.
  bool step_persistent(int count);
  /// Runs `count` substeps the way `launch_mode_` says.
  void run_substeps(int count);
  /// Keyed runs: uploads the pin and collider records of every substep of frame `frame` at once
  /// (once per frame), then copies substep `s`'s on the backend to where the substep's launches
  /// (a recorded graph, the persistent kernel) always read them.
  void select_substep_motion(int frame, int s);

  SimulationOptions options_;
  index_t node_count_ = 0;
  index_t constraint_count_ = 0;                  // 2 per edge and 2 per membrane, weightless ones included
  mutable index_t active_constraint_count_ = -1;  // -1: not counted since the model was built
  vec<std::uint8_t> node_pinned_;
  vec<float> node_pos_, node_vel_;  // the standalone solver's state; empty for a cloth's
  bool held_state_ = true;
  // Model.
  vec<float> node_mass_, node_diag_;
  index_t edge_count_ = 0;
  vec<index_t> spring_nodes_, hinge_nodes_;
  vec<float> spring_weight_, spring_rest_, hinge_coef_, hinge_weight_, hinge_rest_;
  index_t membrane_face_count_ = 0;  // the mesh's faces with the membrane model, else 0
  vec<index_t> membrane_nodes_;
  vec<float> membrane_coef_, membrane_weight_;
  vec<index_t> node_slot_offset_, node_slots_;  // node_slots_ sized for every slot, used or not
  vec<float> node_slot_coef_;                   // each CSR slot's coefficient, sized as node_slots_
  vec<index_t> node_tally_;                     // the CSR's counts and cursors
  // Pins and colliders as the substep being run sees them ([pin_count], [collider_count]); with
  // keys, rewritten before each substep from the frame's records ([substeps × count] each).
  bool keyed_ = false;
  vec<kernels::PdPinMotion> pin_motion_, frame_pin_motion_;
  vec<kernels::PdCollider> colliders_, frame_colliders_;
  vec<float> node_rest_;  // [node_count * 3], kept only for keyed pins
  int last_frame_ = 0;
  int uploaded_frame_ = -1;  // the frame whose records frame_pin_motion_ and frame_colliders_ hold
  // Scratch of a step.
  vec<float> node_pred_, constraint_force_;
  vec<float> node_iter_[3];
  float* state_pos_ = nullptr;  // the state stepped: the solver's own or a cloth's, [node_count * 3]
  float* state_vel_ = nullptr;
  std::unique_ptr<ReplayGraph<System>> step_graph_ =
      std::make_unique<ReplayGraph<System>>();  // one substep, recorded on the first step
  LaunchMode launch_mode_ = LaunchMode::persistent;
  PersistentLaunch persistent_;  // this mesh's (`decide_launch`)
  bool tiled_used_ = false;      // this mesh's substeps run tiled (`decide_launch`)
  TiledLayout<System> tiled_;
  std::vector<float> omega_host_;  // ω of each iteration (Wang 2015, eq. 11)
  vec<float> omega_;               // the same on the backend, for the persistent kernel
};

}  // namespace tear::backend
