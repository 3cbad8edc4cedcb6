// tear: building a solver from a mesh already on a backend (a cloth's arrays and topology), for
// device code only (the .inl files).
#pragma once

#include <memory>
#include <vector>

#include "backend/backend.h"
#include "topology/device_topology.h"
#include "sim/pd_solver.h"

namespace tear::backend {

/// The solver of the mesh `face_nodes`/`node_rest` whose topology is `topo`, all on `System`;
/// `node_pinned` [node_count] is already resolved. Nothing goes through the host but the pins.
template <class System>
std::unique_ptr<PdSolver::Impl> make_pd_solver(const vector<System, index_t>& face_nodes,
                                               const vector<System, float>& node_rest,
                                               const DeviceTopology<System>& topo, const SimulationOptions& options,
                                               const std::vector<std::uint8_t>& node_pinned);

}  // namespace tear::backend
