// tear: the solver of a cloth already on a backend, for device code only (the .inl files).
#pragma once

#include <memory>

#include "backend/backend.h"
#include "cloth_data/device_cloth.h"
#include "sim/pd_solver.h"

namespace tear::backend {

/// The solver of `cloth`'s current mesh, its model (masses, constraints, pins) built on `System`
/// from the cloth's faces, rest shape, topology and carried pins; nothing goes through the host.
/// Step the cloth's own state with `step_in_place`.
template <class System>
std::unique_ptr<PdSolver::Impl> make_pd_solver(const DeviceCloth<System>& cloth, const SimulationOptions& options);

/// `solver`, made by `make_pd_solver` on `System`, rebuilt for `cloth`'s mesh as it is now (after
/// a cut or a tear) in its own memory, which only grows: the same model a new solver would have,
/// without a new solver's allocations and uploads.
template <class System>
void rebuild_pd_solver(PdSolver::Impl& solver, const DeviceCloth<System>& cloth);

}  // namespace tear::backend
