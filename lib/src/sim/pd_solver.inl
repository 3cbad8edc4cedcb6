// The projective dynamics solver on either backend: the model is built once per mesh (topology,
// masses, constraints, node→constraint CSR, Jacobi diagonal), then each step is a fixed sequence of
// kernel launches with no read-back, so a CUDA step queues without waiting.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <mutex>
#include <string>
#include <type_traits>

#include <thrust/copy.h>
#include <thrust/for_each.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/transform_reduce.h>

#include "backend/backend.h"
#include "build_topology.h"
#include "topology/device_topology.h"
#include "pd_model.h"
#include "sim/pd_solver.h"
#include "sim/pd_solver_device.h"
#include "pd_step.h"
#include "backend/replay_graph.h"
#if TEAR_CUDA_SYSTEM
#include <cooperative_groups.h>
#endif
#include "tear/error.h"

namespace tear::backend {

/// How the CUDA backend launches a substep, from TEAR_CUDA_LAUNCH: `persistent` (the default: one
/// cooperative kernel runs the whole substep, as `one-pass` on a mesh of a few thousand nodes, as
/// `shared` on one whose blocks' shares fit in shared memory, as `two-pass` on a mesh the resident
/// threads cover in a few rounds, else as `graph`), `one-pass` (one cooperative kernel, each
/// iteration one pass and one grid barrier: a group of lanes per node computes its constraints'
/// forces and sums them), `shared` (one cooperative kernel, a block per multiprocessor holding its
/// run of nodes and their constraints in shared memory; as `two-pass` where they do not fit),
/// `two-pass` (one cooperative kernel, each iteration a pass over the constraints and one over the
/// nodes, the grid synchronising between them), `graph` (the substep's launches recorded once as a
/// CUDA graph and replayed) or `plain` (every kernel launched on its own). Where the device has no
/// cooperative launch the first four run as `graph`. All of them compute the same operations in the
/// same order: the same bits.
enum class LaunchMode { persistent, one_pass, shared, two_pass, graph, plain };

inline LaunchMode launch_mode() {
  const char* setting = std::getenv("TEAR_CUDA_LAUNCH");
  if (!setting || !*setting) return LaunchMode::persistent;
  const std::string mode = setting;
  if (mode == "persistent") return LaunchMode::persistent;
  if (mode == "one-pass") return LaunchMode::one_pass;
  if (mode == "shared") return LaunchMode::shared;
  if (mode == "two-pass") return LaunchMode::two_pass;
  if (mode == "graph") return LaunchMode::graph;
  if (mode == "plain") return LaunchMode::plain;
  throw runtime_error("TEAR_CUDA_LAUNCH=" + mode + ": expected persistent, one-pass, shared, two-pass, graph or plain");
}

/// The three iterate buffers of a substep's iterations: the one an iteration reads (`cur`), the one
/// before it (`prev`) and the one it writes (`next`). Held as pointers, not as indices into
/// `SubstepKernels::iter`: a kernel indexing that array by a variable would keep the whole
/// `SubstepKernels` in local memory and read every argument from there, inside each iteration.
struct Iterates {
  float* cur;
  float* prev;
  float* next;
  /// After an iteration: the next becomes current, the current previous, the previous free.
  TEAR_HD void rotate() {
    float* const old_prev = prev;
    prev = cur;
    cur = next;
    next = old_prev;
  }
};

/// The kernels of one substep with their arguments, built in one place for every way of launching
/// them. The iterate pointers and ω are set per iteration (`iteration`), the last iterate for the
/// velocity update (`finish_from`).
struct SubstepKernels {
  kernels::predict_positions predict;
  kernels::project_constraints project;
  kernels::jacobi_chebyshev_update update;
  kernels::finish_step finish;
  index_t node_count, constraint_count;
  int iterations;
  const float* omega;  // [iterations], ω of each iteration (on the backend for the persistent kernel)
  float* iter[3];

  /// The iterates of the first iteration: prediction's two copies, then the free buffer.
  TEAR_HD Iterates first_iterates() const { return {iter[0], iter[1], iter[2]}; }
  /// Iteration k reads iterates `it.cur` and `it.prev` and writes `it.next`.
  TEAR_HD void iteration(int k, const Iterates& it) {
    project.node_iter = it.cur;
    update.node_iter = it.cur;
    update.node_iter_prev = it.prev;
    update.node_iter_next = it.next;
    update.omega = omega[k];
  }
  TEAR_HD void finish_from(const Iterates& it) { finish.node_iter = it.cur; }
};

#if TEAR_CUDA_SYSTEM
inline constexpr int persistent_block = 256;  ///< threads per block of the persistent kernel

/// The nodes block `block` of `blocks` takes in a cooperative substep kernel: an equal run each,
/// [begin, end). The host sizes the shared-memory kernel's blocks with the same split.
struct BlockNodes {
  index_t run, begin, end;
};
TEAR_HD inline BlockNodes block_nodes_of(index_t node_count, index_t blocks, index_t block) {
  const index_t run = (node_count + blocks - 1) / blocks;
  const index_t begin = block * run;
  return {run, begin, begin + run < node_count ? begin + run : node_count};
}
__device__ inline BlockNodes block_nodes(index_t node_count) {
  return block_nodes_of(node_count, static_cast<index_t>(gridDim.x), static_cast<index_t>(blockIdx.x));
}

/// The whole substep in one cooperative kernel: each pass a loop over its elements calling the
/// same functor as its own launch would, the grid synchronised between passes. The grid is sized
/// for the constraints (the larger pass); the nodes, a third as many or fewer, are dealt to every
/// block in equal runs rather than to the first blocks only, so that the gather's loads, the
/// longest chain of an iteration, are spread over every multiprocessor's caches and load units
/// (H100, 100 iterations: 0.76 → 0.69 ms at 2,822 faces, whose 1,486 nodes the first 6 of 34
/// blocks gathered; 1.15 → 0.88 ms at 38,298 faces). Each node's gather issues 16 slots' loads at
/// a time, where the graph's large meshes take 8 (9,022 faces 0.71 → 0.66 ms; 8 keeps 2M faces at
/// 23.5 ms, which 16 made 25.5).
__global__ void two_pass_substep_kernel(SubstepKernels s) {
  cooperative_groups::grid_group grid = cooperative_groups::this_grid();
  const index_t first = static_cast<index_t>(blockIdx.x * blockDim.x + threadIdx.x);
  const index_t stride = static_cast<index_t>(gridDim.x * blockDim.x);
  const BlockNodes nodes = block_nodes(s.node_count);
  const index_t node_first = nodes.begin + static_cast<index_t>(threadIdx.x);
  const index_t node_stride = static_cast<index_t>(blockDim.x);
  for (index_t n = node_first; n < nodes.end; n += node_stride) s.predict(n);
  grid.sync();
  Iterates it = s.first_iterates();
  for (int k = 0; k < s.iterations; ++k) {
    s.iteration(k, it);
    for (index_t c = first; c < s.constraint_count; c += stride) s.project(c);
    grid.sync();
    for (index_t n = node_first; n < nodes.end; n += node_stride) s.update.update<16>(n);
    grid.sync();
    it.rotate();
  }
  s.finish_from(it);
  for (index_t n = node_first; n < nodes.end; n += node_stride) s.finish(n);
}

/// Slots of a node whose products the lanes of its group hold before the group sums them.
inline constexpr int group_chunk = 32;

/// Adds to g the products that the lanes of a group hold for slots [c·group_chunk,
/// (c + 1)·group_chunk) of a node of `count` slots, in slot order: every lane gets the same sum.
template <int group_lanes>
__device__ void sum_group_products(const kernels::Vec3f (&product)[group_chunk / group_lanes], int c, index_t count,
                                   kernels::Vec3f& g) {
  using kernels::Vec3f;
#pragma unroll
  for (int r = 0; r < group_chunk / group_lanes; ++r)
#pragma unroll
    for (int l = 0; l < group_lanes; ++l) {
      const Vec3f p{__shfl_sync(0xffffffffu, product[r].x, l, group_lanes),
                    __shfl_sync(0xffffffffu, product[r].y, l, group_lanes),
                    __shfl_sync(0xffffffffu, product[r].z, l, group_lanes)};
      if (c * group_chunk + r * group_lanes + l < count) g = g + p;
    }
}

/// One Jacobi-Chebyshev update of node n (`active`) by a group of `group_lanes` lanes: each lane
/// computes the forces of some of the node's constraints itself (`compute_constraint_force`, as
/// the local step would) times their coefficients, and every lane sums the products in slot order
/// through shuffles, so the result is the bits of `jacobi_chebyshev_update` after
/// `project_constraints`, without the forces' trip through memory and the barrier between them.
/// Every lane of the warp calls it the same number of times (inactive groups too).
template <int group_lanes>
__device__ void group_update(const kernels::jacobi_chebyshev_update& u, index_t n, bool active) {
  using kernels::Vec3f;
  constexpr int group_rounds = group_chunk / group_lanes;
  const int lane = static_cast<int>(threadIdx.x) % group_lanes;
  index_t begin = 0, count = 0;
  Vec3f x{0, 0, 0}, s{0, 0, 0}, g{0, 0, 0};
  if (active) {
    x = kernels::load3<float>(u.node_iter, n);
    begin = u.node_slot_offset[n];
    count = u.node_slot_offset[n + 1] - begin;
    s = kernels::load3<float>(u.node_pred, n);
    g = u.inertial_term(n, x, s);
  }
  const int chunks =
      __reduce_max_sync(0xffffffffu, static_cast<unsigned>((count + group_chunk - 1) / group_chunk));
  for (int c = 0; c < chunks; ++c) {
    Vec3f product[group_rounds];
#pragma unroll
    for (int r = 0; r < group_rounds; ++r) {
      const index_t j = c * group_chunk + r * group_lanes + lane;
      product[r] = Vec3f{0, 0, 0};
      if (j < count) {
        const index_t slot = u.node_slots[begin + j];
        product[r] = u.node_slot_coef[begin + j] *
                     kernels::compute_constraint_force(u.constraints, u.node_iter, u.constraints.constraint_of_slot(slot));
      }
    }
    sum_group_products<group_lanes>(product, c, count, g);
  }
  if (active && lane == 0) kernels::store3(u.node_iter_next, n, u.next_from_sum(n, x, s, g));
}

/// A node's values that do not change within a substep (prediction, mass, diagonal, pin) and its
/// last two iterates, as a kernel holds them instead of reading them each iteration: in registers
/// (`HeldGroupNode`) or in shared memory (`SharedNode`).
struct HeldNodeState {
  kernels::Vec3f s, x, x_prev;
  float mass, diag;
  std::int32_t pinned;

  /// Node n before the first iteration: `u` set for it.
  __device__ static HeldNodeState load(const kernels::jacobi_chebyshev_update& u, index_t n) {
    return {kernels::load3<float>(u.node_pred, n), kernels::load3<float>(u.node_iter, n),
            kernels::load3<float>(u.node_iter_prev, n), u.node_mass[n], u.node_diag[n], u.node_pinned[n]};
  }
  /// The update's sum's first term, m/h² (s − x).
  __device__ kernels::Vec3f inertial_term(const kernels::jacobi_chebyshev_update& u) const {
    return u.inertial_term_of(mass, x, s);
  }
  /// x⁽ᵏ⁺¹⁾ from the summed g, which becomes the held iterate; returns it.
  __device__ kernels::Vec3f advance(const kernels::jacobi_chebyshev_update& u, const kernels::Vec3f& g) {
    const kernels::Vec3f next = u.next_from_held(pinned != 0, diag, x, x_prev, s, g);
    x_prev = x;
    x = next;
    return next;
  }
};

/// `group_update` of a node whose group keeps, in registers, all that an iteration reads of it
/// except the iterate's neighbours: its constraints' terms and coefficients (a node of at most
/// `group_chunk` slots), its mass, diagonal, pin and prediction, and its own last two iterates.
/// The model does not change within a substep, so each iteration's chain of dependent loads
/// (offsets → slots → constraints → positions) becomes the positions' loads alone. Same
/// operations on the same values as `group_update`: the same bits.
template <int group_lanes>
struct HeldGroupNode {
  static constexpr int rounds = group_chunk / group_lanes;
  kernels::ConstraintTerms terms[rounds];
  float coef[rounds];
  index_t count = 0;
  bool active = false;
  HeldNodeState node{};

  /// Reads node n (`active`) before the first iteration: `u` set for it.
  __device__ void load(const kernels::jacobi_chebyshev_update& u, index_t n, bool is_active) {
    active = is_active;
    if (!active) return;
    const int lane = static_cast<int>(threadIdx.x) % group_lanes;
    const index_t begin = u.node_slot_offset[n];
    count = u.node_slot_offset[n + 1] - begin;
#pragma unroll
    for (int r = 0; r < rounds; ++r) {
      const index_t j = r * group_lanes + lane;
      if (j < count) {
        terms[r] = kernels::constraint_terms(u.constraints, u.constraints.constraint_of_slot(u.node_slots[begin + j]));
        coef[r] = u.node_slot_coef[begin + j];
      }
    }
    node = HeldNodeState::load(u, n);
  }

  /// One iteration: `u` set for it (the iterates it reads and writes, ω).
  __device__ void update(const kernels::jacobi_chebyshev_update& u, index_t n) {
    using kernels::Vec3f;
    const int lane = static_cast<int>(threadIdx.x) % group_lanes;
    Vec3f g{0, 0, 0};
    if (active) g = node.inertial_term(u);
    Vec3f product[rounds];
#pragma unroll
    for (int r = 0; r < rounds; ++r) {
      product[r] = Vec3f{0, 0, 0};
      if (r * group_lanes + lane < count) product[r] = coef[r] * kernels::constraint_force(terms[r], u.node_iter);
    }
    sum_group_products<group_lanes>(product, 0, count, g);
    if (!active) return;
    const Vec3f next = node.advance(u, g);
    if (lane == 0) kernels::store3(u.node_iter_next, n, next);
  }
};

/// The whole substep in one cooperative kernel with one pass and one grid barrier per iteration:
/// each node updated by a group of `group_lanes` lanes (`group_update`). The nodes are dealt to the
/// blocks in equal runs, as in `two_pass_substep_kernel`. Where each group has one node (the grid
/// as `persistent_launch` sizes it) and none of a warp's nodes has more than `group_chunk` slots,
/// the groups hold their nodes (`HeldGroupNode`).
template <int group_lanes>
__global__ void one_pass_substep_kernel(SubstepKernels s) {
  cooperative_groups::grid_group grid = cooperative_groups::this_grid();
  const BlockNodes nodes = block_nodes(s.node_count);
  const index_t node_first = nodes.begin + static_cast<index_t>(threadIdx.x);
  const index_t node_stride = static_cast<index_t>(blockDim.x);
  for (index_t n = node_first; n < nodes.end; n += node_stride) s.predict(n);
  grid.sync();
  const index_t groups = static_cast<index_t>(blockDim.x) / group_lanes;
  const index_t rounds = (nodes.run + groups - 1) / groups;  // the same in every block: warps stay whole
  const index_t group = static_cast<index_t>(threadIdx.x) / group_lanes;
  Iterates it = s.first_iterates();
  HeldGroupNode<group_lanes> held;
  const index_t held_node = nodes.begin + group;
  bool holding = false;
  if (rounds == 1) {
    s.iteration(0, it);
    held.load(s.update, held_node, held_node < nodes.end);
    holding = __all_sync(0xffffffffu, held.count <= group_chunk);
  }
  for (int k = 0; k < s.iterations; ++k) {
    s.iteration(k, it);
    if (holding) {
      held.update(s.update, held_node);
    } else {
      for (index_t r = 0; r < rounds; ++r) {
        const index_t n = nodes.begin + r * groups + group;
        group_update<group_lanes>(s.update, n, n < nodes.end);
      }
    }
    grid.sync();
    it.rotate();
  }
  s.finish_from(it);
  for (index_t n = node_first; n < nodes.end; n += node_stride) s.finish(n);
}

/// Threads per block of the shared-memory substep kernel: one block per multiprocessor.
inline constexpr int shared_block = 1024;

/// A slot as a block of the shared-memory kernel holds it: its constraint's terms and its
/// coefficient.
struct SharedSlot {
  kernels::ConstraintTerms terms;
  float coef;
};
/// A node as that block holds it: its held state and its slots' range in the block's slots.
struct SharedNode {
  HeldNodeState state;
  index_t slot_begin, slot_end;
};

/// Shared memory a block of the shared-memory kernel needs for `slots` slots and `nodes` nodes.
inline std::size_t shared_bytes(long long slots, long long nodes) {
  return static_cast<std::size_t>(slots) * (sizeof(SharedSlot) + sizeof(kernels::Vec3f)) +
         static_cast<std::size_t>(nodes) * sizeof(SharedNode);
}

/// The whole substep in one cooperative kernel, each block holding its run of nodes and their
/// slots in shared memory for the substep (the model does not change within one): a block's nodes
/// are consecutive, so their slots are one run of the CSR. Each iteration computes the products
/// coefficient × force of the block's slots (`constraint_force`, as the local step would), synchronises
/// the block, sums each node's products in slot order into its update (the bits of
/// `jacobi_chebyshev_update`) and synchronises the grid: the only loads from memory an iteration
/// makes are its slots' nodes' positions.
__global__ void __launch_bounds__(shared_block, 1) shared_substep_kernel(SubstepKernels s) {
  using kernels::Vec3f;
  cooperative_groups::grid_group grid = cooperative_groups::this_grid();
  extern __shared__ __align__(16) unsigned char shared_held[];
  const BlockNodes nodes = block_nodes(s.node_count);
  const index_t first = static_cast<index_t>(threadIdx.x), stride = static_cast<index_t>(blockDim.x);
  for (index_t n = nodes.begin + first; n < nodes.end; n += stride) s.predict(n);
  grid.sync();
  Iterates it = s.first_iterates();
  s.iteration(0, it);
  const index_t node_count = nodes.end > nodes.begin ? nodes.end - nodes.begin : 0;
  const index_t slot_base = node_count > 0 ? s.update.node_slot_offset[nodes.begin] : 0;
  const index_t slot_count = node_count > 0 ? s.update.node_slot_offset[nodes.end] - slot_base : 0;
  SharedSlot* slots = reinterpret_cast<SharedSlot*>(shared_held);
  Vec3f* products = reinterpret_cast<Vec3f*>(slots + slot_count);
  SharedNode* held = reinterpret_cast<SharedNode*>(products + slot_count);
  {
    const kernels::jacobi_chebyshev_update& u = s.update;
    for (index_t i = first; i < slot_count; i += stride)
      slots[i] = {kernels::constraint_terms(u.constraints, u.constraints.constraint_of_slot(u.node_slots[slot_base + i])),
                  u.node_slot_coef[slot_base + i]};
    for (index_t j = first; j < node_count; j += stride) {
      const index_t n = nodes.begin + j;
      held[j] = {HeldNodeState::load(u, n), u.node_slot_offset[n] - slot_base, u.node_slot_offset[n + 1] - slot_base};
    }
  }
  __syncthreads();
  for (int k = 0; k < s.iterations; ++k) {
    s.iteration(k, it);
    const kernels::jacobi_chebyshev_update& u = s.update;
    for (index_t i = first; i < slot_count; i += stride)
      products[i] = slots[i].coef * kernels::constraint_force(slots[i].terms, u.node_iter);
    __syncthreads();
    for (index_t j = first; j < node_count; j += stride) {
      SharedNode& v = held[j];
      Vec3f g = v.state.inertial_term(u);
      for (index_t i = v.slot_begin; i < v.slot_end; ++i) g = g + products[i];
      kernels::store3(u.node_iter_next, nodes.begin + j, v.state.advance(u, g));
    }
    grid.sync();
    it.rotate();
  }
  s.finish_from(it);
  for (index_t n = nodes.begin + first; n < nodes.end; n += stride) s.finish(n);
}
#endif

template <class System>
class PdSolverOn final : public PdSolver::Impl {
  template <class T>
  using vec = vector<System, T>;

 public:
  /// From host arrays: uploads them and builds their topology.
  PdSolverOn(const std::vector<index_t>& face_nodes_host, const std::vector<float>& node_rest_host, index_t node_count,
             const SimulationOptions& options, const std::vector<std::uint8_t>& node_pinned)
      : PdSolverOn(options, node_count, node_pinned) {
    const vec<index_t> face_nodes(face_nodes_host.begin(), face_nodes_host.end());
    const vec<float> node_rest(node_rest_host.begin(), node_rest_host.end());
    DeviceTopology<System> topo;
    build_device_topology(topo, face_nodes, node_count_);
    build_model(face_nodes, node_rest, topo);
  }

  /// From a cloth on this backend: its faces, rest shape, topology and pins; nothing leaves the device.
  PdSolverOn(const DeviceCloth<System>& cloth, const SimulationOptions& options)
      : PdSolverOn(options, cloth.node_count(), std::vector<std::uint8_t>()) {
    thrust::copy(Traits<System>::policy(), cloth.node_pinned.begin(), cloth.node_pinned.end(), node_pinned_.begin());
    build_model(cloth.face_nodes, cloth.node_rest, cloth.topo);
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
    for (auto* v : {&node_pos_, &node_vel_, &node_pred_, &node_iter_[0], &node_iter_[1], &node_iter_[2]})
      resize_for_overwrite(*v, n3);
    // As built: the solver's own state at rest and bound; `step_in_place` binds a cloth's again.
    thrust::fill(Traits<System>::policy(), node_vel_.begin(), node_vel_.end(), 0.0f);
    state_pos_ = raw<float>(node_pos_);
    state_vel_ = raw<float>(node_vel_);
    step_graph_ = std::make_unique<ReplayGraph<System>>();
    persistent_decided_ = false;  // the launch depends on the mesh's size
    build_model(cloth.face_nodes, cloth.node_rest, cloth.topo);
  }

 private:
  PdSolverOn(const SimulationOptions& options, index_t node_count, const std::vector<std::uint8_t>& node_pinned)
      : options_(options),
        node_count_(node_count),
        node_pinned_(static_cast<std::size_t>(node_count), 0),
        node_pos_(3 * static_cast<std::size_t>(node_count), 0.0f),
        node_vel_(3 * static_cast<std::size_t>(node_count), 0.0f) {
    if (!node_pinned.empty()) thrust::copy(node_pinned.begin(), node_pinned.end(), node_pinned_.begin());
    state_pos_ = raw<float>(node_pos_);
    state_vel_ = raw<float>(node_vel_);
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
    for (const Collider& c : options.colliders) keyed_ = keyed_ || !c.keys.empty();
    // Without keys the pins' and colliders' records never change; with keys they are those of the
    // first substep until a frame is stepped.
    std::vector<kernels::PdPinMotion> pins;
    std::vector<kernels::PdCollider> colliders;
    substep_motion(0, 0, pins, colliders);
    assign_from_host(pin_motion_, pins);
    assign_from_host(colliders_, colliders);
  }

  /// The pins' and colliders' records of substep `s` (0-based) of frame `frame` (1-based), appended:
  /// each keyed one where its keys put it at the substep's end, moving by the change of its offset
  /// over the substep. The substep spans times (frame − 1 + s/S, frame − 1 + (s+1)/S), in frames.
  void substep_motion(int frame, int s, std::vector<kernels::PdPinMotion>& pins,
                      std::vector<kernels::PdCollider>& colliders) const {
    const double start = substep_end_time(frame, s - 1, options_.substeps);
    const double end = substep_end_time(frame, s, options_.substeps);
    const double inv_h = 1.0 / options_.step_seconds();
    // The offset at the substep's end; its change over the substep, as a velocity.
    const auto motion = [&](const std::vector<Key>& keys, float* velocity) {
      const std::array<double, 3> a = key_offset(keys, start), b = key_offset(keys, end);
      for (int i = 0; i < 3; ++i) velocity[i] = static_cast<float>((b[i] - a[i]) * inv_h);
      return b;
    };
    for (const Pin& p : options_.pins) {
      kernels::PdPinMotion k{};
      k.keyed = p.keys.empty() ? 0 : 1;
      const std::array<double, 3> offset = motion(p.keys, k.velocity);
      for (int a = 0; a < 3; ++a) k.offset[a] = static_cast<float>(offset[a]);
      pins.push_back(k);
    }
    for (const Collider& c : options_.colliders) {
      kernels::PdCollider k{};
      k.kind = c.kind == Collider::Kind::plane ? 0 : 1;
      const double len = std::sqrt(c.normal[0] * c.normal[0] + c.normal[1] * c.normal[1] + c.normal[2] * c.normal[2]);
      const std::array<double, 3> offset = motion(c.keys, k.velocity);
      for (int a = 0; a < 3; ++a) {
        // Without keys the point as given, not point + 0 (which turns −0 into +0).
        k.point[a] = static_cast<float>(c.keys.empty() ? c.point[a] : c.point[a] + offset[a]);
        k.normal[a] = static_cast<float>(len > 0 ? c.normal[a] / len : 0.0);
      }
      k.radius = static_cast<float>(c.radius);
      colliders.push_back(k);
    }
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
    }
    return active_constraint_count_;
  }
  std::size_t bytes_per_iteration() const override {
    const std::size_t e = static_cast<std::size_t>(edge_count_), n = static_cast<std::size_t>(node_count_),
                      s = static_cast<std::size_t>(used_slot_count()), c = static_cast<std::size_t>(constraint_count_);
    // Local step: a spring's record (2 nodes, weight, rest length) or a hinge's (4 nodes, 4
    // coefficients, weight, rest value) read, its force written; each iterate read once. Global
    // step: a node's CSR offset, mass, diagonal, pin, prediction and two iterates read and the next
    // written; a slot's index and its coefficient (both in CSR order) read; each force read once.
    const std::size_t records = e * (2 * sizeof(index_t) + 2 * sizeof(float)) +
                                e * (4 * sizeof(index_t) + 4 * sizeof(float) + 2 * sizeof(float));
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
    bind_state(raw<float>(node_pos_), raw<float>(node_vel_));
    thrust::copy(node_pos.begin(), node_pos.end(), node_pos_.begin());
    thrust::copy(node_vel.begin(), node_vel.end(), node_vel_.begin());
  }
  std::vector<float> node_pos() const override { return to_host<float>(node_pos_); }
  std::vector<float> node_vel() const override { return to_host<float>(node_vel_); }
  float* device_node_pos() override { return raw<float>(node_pos_); }
  float* device_node_vel() override { return raw<float>(node_vel_); }
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
  index_t used_slot_count() const {
    return node_count_ > 0 ? static_cast<index_t>(node_slot_offset_[node_count_]) : 0;
  }
  kernels::PdConstraints constraints() const {
    return {edge_count_,           raw<index_t>(spring_nodes_), raw<float>(spring_weight_), raw<float>(spring_rest_),
            raw<index_t>(hinge_nodes_), raw<float>(hinge_coef_),  raw<float>(hinge_weight_), raw<float>(hinge_rest_)};
  }
  /// The substep's kernels; `omega` is where ω lives for whoever reads it.
  SubstepKernels substep_kernels(const float* omega);
  template <class Policy>
  void enqueue_substep(const Policy& policy);
  /// How a substep runs as one cooperative kernel on this mesh and device.
  struct PersistentLaunch {
    enum class Kind { none, one_pass, shared, two_pass } kind = Kind::none;  // none: as `graph`
    int blocks = 0;
    int lanes = 0;           // per node, one pass
    std::size_t bytes = 0;   // of shared memory per block, shared
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
  index_t constraint_count_ = 0;  // 2 per edge, weightless ones included
  mutable index_t active_constraint_count_ = -1;  // -1: not counted since the model was built
  vec<std::uint8_t> node_pinned_;
  vec<float> node_pos_, node_vel_;
  // Model.
  vec<float> node_mass_, node_diag_;
  index_t edge_count_ = 0;
  vec<index_t> spring_nodes_, hinge_nodes_;
  vec<float> spring_weight_, spring_rest_, hinge_coef_, hinge_weight_, hinge_rest_;
  vec<index_t> node_slot_offset_, node_slots_;  // node_slots_ sized for every slot, used or not
  vec<float> node_slot_coef_;                    // each CSR slot's coefficient, sized as node_slots_
  vec<index_t> node_tally_;                      // the CSR's counts and cursors
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
  std::unique_ptr<ReplayGraph<System>> step_graph_ = std::make_unique<ReplayGraph<System>>();  // one substep, recorded on the first step
  LaunchMode launch_mode_ = LaunchMode::persistent;
  bool persistent_decided_ = false;  // persistent_ holds this mesh's launch
  PersistentLaunch persistent_;
  std::vector<float> omega_host_;   // ω of each iteration (Wang 2015, eq. 11)
  vec<float> omega_;                // the same on the backend, for the persistent kernel
};

template <class System>
void PdSolverOn<System>::build_model(const vec<index_t>& face_nodes, const vec<float>& node_rest,
                                     const DeviceTopology<System>& topo) {
  using namespace kernels;
  const auto policy = Traits<System>::policy();
  thrust::copy(policy, node_rest.begin(), node_rest.end(), node_pos_.begin());
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

  // Masses (per node) and constraints (per edge) in one launch.
  resize_for_overwrite(node_mass_, node_count_);
  const index_t edge_count = topo.edge_count;
  constraint_count_ = 2 * edge_count;
  edge_count_ = edge_count;
  resize_for_overwrite(spring_nodes_, 2 * static_cast<std::size_t>(edge_count));
  resize_for_overwrite(hinge_nodes_, pd_constraint_nodes * static_cast<std::size_t>(edge_count));
  resize_for_overwrite(hinge_coef_, pd_constraint_nodes * static_cast<std::size_t>(edge_count));
  for (auto* v : {&spring_weight_, &spring_rest_, &hinge_weight_, &hinge_rest_}) resize_for_overwrite(*v, edge_count);
  resize_for_overwrite(constraint_force_, 3 * static_cast<std::size_t>(constraint_count_));
  for_each_index<System>(node_count_ + edge_count,
      make_over_three_ranges(
          compute_node_masses{raw<index_t>(face_nodes), raw<float>(node_rest), raw<index_t>(topo.node_face_offset),
                              raw<index_t>(topo.node_faces), options_.density, raw<float>(node_mass_)},
          make_pd_constraints{raw<index_t>(face_nodes), raw<float>(node_rest), raw<index_t>(topo.edge_nodes),
                              raw<index_t>(topo.edge_faces), raw<index_t>(topo.edge_face_count), edge_count,
                              options_.stretch_stiffness, options_.bend_stiffness, raw<index_t>(spring_nodes_),
                              raw<float>(spring_weight_), raw<float>(spring_rest_), raw<index_t>(hinge_nodes_),
                              raw<float>(hinge_coef_), raw<float>(hinge_weight_), raw<float>(hinge_rest_)},
          no_pass{}, node_count_, edge_count));
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
  for_each_index<System>(node_count_,
      compute_jacobi_diagonal{raw<index_t>(node_slot_offset_), raw<index_t>(node_slots_), model, raw<float>(node_mass_),
                              static_cast<float>(1.0 / (h * h)),
                              raw<float>(node_diag_), raw<float>(node_slot_coef_)});
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
  s.predict = predict_positions{state_pos_, state_vel_, raw<std::uint8_t>(node_pinned_),
                                raw<float>(node_rest_), raw<PdPinMotion>(pin_motion_), pin_count,
                                static_cast<float>(h), gravity, raw<float>(node_pred_), raw<float>(node_iter_[0]),
                                raw<float>(node_iter_[1])};
  // Local step: every constraint's projection at the current iterate (§4.1).
  s.project = project_constraints{model, nullptr, raw<float>(constraint_force_)};
  // Global step: one Chebyshev-weighted Jacobi update per node (Wang 2015, §4).
  s.update = jacobi_chebyshev_update{raw<index_t>(node_slot_offset_), raw<index_t>(node_slots_),
                                     raw<float>(node_slot_coef_), model,
                                     raw<float>(constraint_force_), raw<float>(node_mass_), raw<float>(node_diag_),
                                     raw<std::uint8_t>(node_pinned_), raw<float>(node_pred_), nullptr, nullptr,
                                     static_cast<float>(1.0 / (h * h)), 0.0f,
                                     static_cast<float>(options_.chebyshev.gamma), nullptr};
  // Velocity update, damping and colliders.
  s.finish = finish_step{raw<std::uint8_t>(node_pinned_), raw<PdPinMotion>(pin_motion_), pin_count, nullptr, static_cast<float>(1.0 / h),
                         static_cast<float>(std::pow(1.0 - options_.damping, h)), raw<PdCollider>(colliders_),
                         static_cast<index_t>(colliders_.size()), state_pos_, state_vel_};
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
typename PdSolverOn<System>::PersistentLaunch PdSolverOn<System>::persistent_launch() const {
  return {};
}

#if TEAR_CUDA_SYSTEM
namespace {
/// The blocks of each cooperative substep kernel the device holds at once, asked once per device
/// (a solver is rebuilt after every tear); 0 where cooperative launches are not available.
struct ResidentBlocks {
  long long two_pass = 0, one_pass_16 = 0, one_pass_8 = 0;
  int sms = 0;
  std::size_t shared_bytes = 0;  // the most a block of the shared-memory kernel may take; 0: none
};

ResidentBlocks resident_blocks() {
  static std::mutex mutex;
  static std::map<int, ResidentBlocks> known;
  int device = 0;
  if (cudaGetDevice(&device) != cudaSuccess) {
    cudaGetLastError();
    return {};
  }
  const std::lock_guard<std::mutex> lock(mutex);
  auto found = known.find(device);
  if (found != known.end()) return found->second;
  ResidentBlocks resident;
  int cooperative = 0, sms = 0, two_pass = 0, one_pass_16 = 0, one_pass_8 = 0;
  if (cudaDeviceGetAttribute(&cooperative, cudaDevAttrCooperativeLaunch, device) == cudaSuccess && cooperative &&
      cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, device) == cudaSuccess &&
      cudaOccupancyMaxActiveBlocksPerMultiprocessor(&two_pass, two_pass_substep_kernel, persistent_block, 0) ==
          cudaSuccess &&
      cudaOccupancyMaxActiveBlocksPerMultiprocessor(&one_pass_16, one_pass_substep_kernel<16>, persistent_block, 0) ==
          cudaSuccess &&
      cudaOccupancyMaxActiveBlocksPerMultiprocessor(&one_pass_8, one_pass_substep_kernel<8>, persistent_block, 0) ==
          cudaSuccess)
    resident = {static_cast<long long>(sms) * two_pass, static_cast<long long>(sms) * one_pass_16,
                static_cast<long long>(sms) * one_pass_8, sms};
  int optin = 0;
  if (resident.sms > 0 && cudaDeviceGetAttribute(&optin, cudaDevAttrMaxSharedMemoryPerBlockOptin, device) == cudaSuccess &&
      cudaFuncSetAttribute(shared_substep_kernel, cudaFuncAttributeMaxDynamicSharedMemorySize, optin) == cudaSuccess)
    resident.shared_bytes = static_cast<std::size_t>(optin);
  cudaGetLastError();  // clear the error of a refused query
  known.emplace(device, resident);
  return resident;
}
}  // namespace

template <>
typename PdSolverOn<Cuda>::PersistentLaunch PdSolverOn<Cuda>::persistent_launch() const {
  using Kind = PersistentLaunch::Kind;
  const ResidentBlocks resident = resident_blocks();
  const auto blocks_for = [](long long threads, long long most) {
    const long long wanted = threads > 0 ? (threads + persistent_block - 1) / persistent_block : 1;
    return static_cast<int>(wanted < most ? wanted : most);
  };
  // One pass: a group of lanes per node, each group computing the node's constraints' forces
  // itself, three times the local step's arithmetic for one barrier an iteration instead of two
  // and no forces through memory. It wins while the device waits on latency, up to about 256
  // lanes per multiprocessor: 16 lanes a node where they fit, else 8, else shared memory. Measured
  // on an H100 (132 multiprocessors), ms per 100 iterations, 16 lanes / 8 lanes / two passes,
  // before the groups held their nodes in registers: 1,486 nodes 0.47 / 0.59 / 0.65; 4,646 nodes
  // 0.87 / 0.65 / 0.66; 10,201 nodes 1.19 / 0.80 / 0.72; 19,426 nodes 1.84 / 1.29 / 0.89. Holding
  // them, 1,486 nodes take 0.29, and 0.27 once the kernel's arguments left local memory.
  const long long lane_budget = 256LL * resident.sms;
  const long long nodes = node_count_;
  if (resident.one_pass_16 > 0 && resident.one_pass_8 > 0 &&
      (launch_mode_ == LaunchMode::one_pass || (launch_mode_ == LaunchMode::persistent && 8 * nodes <= lane_budget))) {
    if (16 * nodes <= lane_budget) return {Kind::one_pass, blocks_for(16 * nodes, resident.one_pass_16), 16};
    return {Kind::one_pass, blocks_for(8 * nodes, resident.one_pass_8), 8};
  }
  // Shared memory: each block holds its nodes and their slots (`shared_substep_kernel`), one block
  // per multiprocessor, where every block's fit (up to about 27,000 nodes of a sheet on an H100's
  // 227 KiB a block). Measured on an H100, ms per 100 iterations, shared memory against two passes
  // (before either stopped reading its arguments from local memory): 4,646 nodes 0.43 / 0.66;
  // 10,201 nodes 0.51 / 0.72; 19,426 nodes 0.64 / 0.89 (after: 0.28 and 0.49 at 4,646 and 19,426).
  // At 1,486 nodes one pass in registers takes 0.29 against its 0.39.
  if ((launch_mode_ == LaunchMode::shared || launch_mode_ == LaunchMode::persistent) && resident.shared_bytes > 0 &&
      nodes > 0) {
    const long long slots = used_slot_count();
    if (shared_bytes(slots, nodes) <= resident.shared_bytes * static_cast<std::size_t>(resident.sms)) {
      const index_t blocks = static_cast<index_t>(nodes < resident.sms ? nodes : resident.sms);
      const std::vector<index_t> offset = to_host<index_t>(node_slot_offset_);
      std::size_t most = 0;
      for (index_t block = 0; block < blocks; ++block) {
        const BlockNodes run = block_nodes_of(node_count_, blocks, block);
        if (run.end > run.begin)
          most = std::max(most, shared_bytes(offset[run.end] - offset[run.begin], run.end - run.begin));
      }
      int per_sm = 0;
      if (most <= resident.shared_bytes &&
          cudaOccupancyMaxActiveBlocksPerMultiprocessor(&per_sm, shared_substep_kernel, shared_block, most) ==
              cudaSuccess &&
          per_sm > 0)
        return {Kind::shared, static_cast<int>(blocks), 0, most};
      cudaGetLastError();
    }
  }
  if (resident.two_pass == 0) return {};
  // Two passes: only while each thread has at most a few elements per pass; on larger meshes
  // separate launches, replayed as a graph, measured faster. H100 (two blocks of the two-pass
  // kernel per multiprocessor), ms per 100 iterations, two passes against the graph: 49,595 nodes
  // (4.4 elements a thread) 1.23 against 1.38; 66,049 nodes (5.8) 1.42 against 1.46; 98,931 nodes
  // (8.8) 2.98 against 2.81.
  const long long work = node_count_ > constraint_count_ ? node_count_ : constraint_count_;
  if (launch_mode_ == LaunchMode::persistent && work > 7 * resident.two_pass * persistent_block) return {};
  return {Kind::two_pass, blocks_for(work, resident.two_pass), 0};
}
#endif

template <class System>
bool PdSolverOn<System>::step_persistent(int count) {
  if (!persistent_decided_) {  // the device and mesh do not change until a rebuild
    persistent_ = persistent_launch();
    persistent_decided_ = true;
  }
  if (persistent_.kind == PersistentLaunch::Kind::none) return false;
#if TEAR_CUDA_SYSTEM
  SubstepKernels s = substep_kernels(raw<float>(omega_));
  void* args[] = {&s};
  using Kind = typename PersistentLaunch::Kind;
  const void* kernel = persistent_.kind == Kind::two_pass ? reinterpret_cast<const void*>(two_pass_substep_kernel)
                       : persistent_.kind == Kind::shared ? reinterpret_cast<const void*>(shared_substep_kernel)
                       : persistent_.lanes == 16          ? reinterpret_cast<const void*>(one_pass_substep_kernel<16>)
                                                          : reinterpret_cast<const void*>(one_pass_substep_kernel<8>);
  const int block = persistent_.kind == Kind::shared ? shared_block : persistent_block;
  for (int i = 0; i < count; ++i) {
    const cudaError_t status = cudaLaunchCooperativeKernel(kernel, dim3(persistent_.blocks), dim3(block), args,
                                                           persistent_.bytes, 0);
    if (status != cudaSuccess)
      throw runtime_error(std::string("the solver's kernel could not be launched: ") + cudaGetErrorString(status));
  }
  return true;
#else
  static_cast<void>(count);
  return false;
#endif
}

template <class System>
std::unique_ptr<PdSolver::Impl> make_pd_solver(const std::vector<index_t>& face_nodes,
                                               const std::vector<float>& node_rest, index_t node_count,
                                               const SimulationOptions& options,
                                               const std::vector<std::uint8_t>& node_pinned) {
  return std::make_unique<PdSolverOn<System>>(face_nodes, node_rest, node_count, options, node_pinned);
}

template <class System>
std::unique_ptr<PdSolver::Impl> make_pd_solver(const DeviceCloth<System>& cloth, const SimulationOptions& options) {
  return std::make_unique<PdSolverOn<System>>(cloth, options);
}

template <class System>
void rebuild_pd_solver(PdSolver::Impl& solver, const DeviceCloth<System>& cloth) {
  static_cast<PdSolverOn<System>&>(solver).rebuild(cloth);
}

#define TEAR_INSTANTIATE(S)                                                                                          \
  template std::unique_ptr<PdSolver::Impl> make_pd_solver<S>(const std::vector<index_t>&, const std::vector<float>&, \
                                                             index_t, const SimulationOptions&,                      \
                                                             const std::vector<std::uint8_t>&);                      \
  template std::unique_ptr<PdSolver::Impl> make_pd_solver<S>(const DeviceCloth<S>&, const SimulationOptions&);   \
  template void rebuild_pd_solver<S>(PdSolver::Impl&, const DeviceCloth<S>&);
TEAR_FOR_EACH_SYSTEM(TEAR_INSTANTIATE)
#undef TEAR_INSTANTIATE

}  // namespace tear::backend
