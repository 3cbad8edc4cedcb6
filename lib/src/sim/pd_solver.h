// tear: the per-backend implementation behind tear::PdSolver.
#pragma once

#include <memory>

#include "backend/systems.h"
#include "tear/simulation.h"

namespace tear {

class PdSolver::Impl {
 public:
  virtual ~Impl() = default;
  virtual Device device() const = 0;
  virtual index_t node_count() const = 0;
  virtual index_t constraint_count() const = 0;
  virtual std::size_t bytes_per_iteration() const = 0;
  virtual const SimulationOptions& options() const = 0;
  /// Steps frame `frame` (1-based: keys are evaluated at its substeps).
  virtual void step_frame(int frame) = 0;
  /// The frame stepped last, 0 before the first.
  virtual int last_frame() const = 0;
  /// Steps frame `frame` of a state held elsewhere in this backend's memory (a cloth's),
  /// [node_count * 3] each, in place: the solver's own state is not used.
  virtual void step_in_place(float* node_pos, float* node_vel, int frame) = 0;
  /// The same for substep `s` (0-based) of frame `frame` alone: a cloth that tears checks itself
  /// between substeps (and a torn cloth steps the frame's next substep with a new model).
  virtual void step_substep_in_place(float* node_pos, float* node_vel, int frame, int s) = 0;
  virtual void set_state(const std::vector<float>& node_pos, const std::vector<float>& node_vel) = 0;
  virtual std::vector<float> node_pos() const = 0;
  virtual std::vector<float> node_vel() const = 0;
  virtual std::vector<float> node_mass() const = 0;
  virtual std::vector<std::uint8_t> node_pinned() const = 0;
};

namespace backend {
/// Builds the model of the mesh on `System`; `node_pinned` [node_count] (0 free, p + 1 held by pin
/// p) is already resolved.
template <class System>
std::unique_ptr<PdSolver::Impl> make_pd_solver(const std::vector<index_t>& face_nodes,
                                               const std::vector<float>& node_rest, index_t node_count,
                                               const SimulationOptions& options,
                                               const std::vector<std::uint8_t>& node_pinned);
}  // namespace backend

}  // namespace tear
