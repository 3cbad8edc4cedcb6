// The projective dynamics solver on either backend: the model is built once per mesh (topology,
// masses, constraints, node→constraint CSR, Jacobi diagonal), then each step is a fixed sequence of
// kernel launches with no read-back, so a CUDA step queues without waiting.
//
// The solver is split by concern into headers this file alone includes: sim/pd_substep.h (the
// launch modes and one substep's kernels), sim/pd_solver_on.h (the solver class),
// sim/pd_solver_model.h (the model), sim/pd_solver_step.h (stepping and choosing the launch; launch
// modes `graph`, `plain` and `tiled`, whose kernel and layout are in sim/pd_launch_tiled.h and
// sim/pd_tiled_layout.h),
// sim/pd_launch_persistent.h (launch mode `persistent`, choosing among the cooperative kernels of
// sim/pd_launch_one_pass.h, sim/pd_launch_shared.h and sim/pd_launch_two_pass.h).
#include <memory>
#include <vector>

#include "backend/backend.h"
#include "sim/pd_launch_persistent.h"
#include "sim/pd_solver.h"
#include "sim/pd_solver_device.h"
#include "sim/pd_solver_model.h"
#include "sim/pd_solver_on.h"
#include "sim/pd_solver_step.h"

namespace tear::backend {

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
  template std::unique_ptr<PdSolver::Impl> make_pd_solver<S>(const DeviceCloth<S>&, const SimulationOptions&);       \
  template void rebuild_pd_solver<S>(PdSolver::Impl&, const DeviceCloth<S>&);
TEAR_FOR_EACH_SYSTEM(TEAR_INSTANTIATE)
#undef TEAR_INSTANTIATE

}  // namespace tear::backend
