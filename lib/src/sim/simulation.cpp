#include "tear/simulation.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

#include "sim/pd_solver.h"
#include "backend/systems.h"
#include "tear/error.h"

namespace tear {

std::vector<std::uint8_t> resolve_pins(const SimulationOptions& options, const std::vector<float>& node_rest,
                                       index_t node_count) {
  if (options.pins.size() > static_cast<std::size_t>(simulation_limits::max_pins))
    throw input_error(options.source, "simulation.pins: expected at most " +
                                          std::to_string(simulation_limits::max_pins) + " pins, got " +
                                          std::to_string(options.pins.size()));
  std::vector<std::uint8_t> node_pinned(static_cast<std::size_t>(std::max<index_t>(node_count, 0)), 0);
  // A node held by several pins follows the first of them.
  const auto hold = [&](index_t n, std::size_t p) {
    if (node_pinned[n] == 0) node_pinned[n] = static_cast<std::uint8_t>(p + 1);
  };
  for (std::size_t p = 0; p < options.pins.size(); ++p) {
    const Pin& pin = options.pins[p];
    if (pin.kind == Pin::Kind::box) {
      for (index_t n = 0; n < node_count; ++n) {
        bool inside = true;
        for (int a = 0; a < 3; ++a) {
          const double x = node_rest[3 * static_cast<std::size_t>(n) + a];
          inside = inside && x >= pin.min[a] && x <= pin.max[a];
        }
        if (inside) hold(n, p);
      }
    } else {
      for (std::size_t i = 0; i < pin.nodes.size(); ++i) {
        const index_t n = pin.nodes[i];
        if (n < 0 || n >= node_count)
          throw input_error(options.source, pin.key_path + ".nodes[" + std::to_string(i) + "]: node " +
                                                std::to_string(n) + " is out of range (the mesh has " +
                                                std::to_string(node_count) + " nodes)");
        hold(n, p);
      }
    }
  }
  return node_pinned;
}

// ---- the solver ---------------------------------------------------------------------------------

namespace {
void check_mesh(const std::vector<index_t>& face_nodes, const std::vector<float>& node_rest, index_t node_count) {
  if (node_count < 0 || node_rest.size() != 3 * static_cast<std::size_t>(node_count))
    throw runtime_error("PdSolver: node_rest holds " + std::to_string(node_rest.size()) + " floats, expected 3 × " +
                        std::to_string(node_count));
  if (face_nodes.size() % 3 != 0) throw runtime_error("PdSolver: face_nodes is not a multiple of 3 long");
  for (const index_t n : face_nodes)
    if (n < 0 || n >= node_count)
      throw runtime_error("PdSolver: face_nodes holds node " + std::to_string(n) + ", out of range for " +
                          std::to_string(node_count) + " nodes");
}
}  // namespace

PdSolver::PdSolver(const std::vector<index_t>& face_nodes, const std::vector<float>& node_rest, index_t node_count,
                   const SimulationOptions& options, Device device)
    : PdSolver(face_nodes, node_rest, node_count, options, device,
               (check_mesh(face_nodes, node_rest, node_count), resolve_pins(options, node_rest, node_count))) {}

PdSolver::PdSolver(const std::vector<index_t>& face_nodes, const std::vector<float>& node_rest, index_t node_count,
                   const SimulationOptions& options, Device device, const std::vector<std::uint8_t>& node_pinned) {
  check_mesh(face_nodes, node_rest, node_count);
  if (node_pinned.size() != static_cast<std::size_t>(node_count))
    throw runtime_error("PdSolver: node_pinned holds " + std::to_string(node_pinned.size()) + " flags, expected " +
                        std::to_string(node_count));
  impl_ = backend::dispatch(device, [&](auto system) {
    return backend::make_pd_solver<decltype(system)>(face_nodes, node_rest, node_count, options, node_pinned);
  });
}

PdSolver::~PdSolver() = default;
PdSolver::PdSolver(PdSolver&&) noexcept = default;
PdSolver& PdSolver::operator=(PdSolver&&) noexcept = default;

Device PdSolver::device() const { return impl_->device(); }
index_t PdSolver::node_count() const { return impl_->node_count(); }
index_t PdSolver::constraint_count() const { return impl_->constraint_count(); }
std::size_t PdSolver::bytes_per_iteration() const { return impl_->bytes_per_iteration(); }
const SimulationOptions& PdSolver::options() const { return impl_->options(); }

void PdSolver::step() { impl_->step_frame(impl_->last_frame() + 1); }

void PdSolver::step_frame(int frame) { impl_->step_frame(frame); }

void PdSolver::step(std::vector<float>& node_pos, std::vector<float>& node_vel) {
  set_state(node_pos, node_vel);
  impl_->step_frame(impl_->last_frame() + 1);
  node_pos = impl_->node_pos();
  node_vel = impl_->node_vel();
}

void PdSolver::set_state(const std::vector<float>& node_pos, const std::vector<float>& node_vel) {
  const std::size_t size = 3 * static_cast<std::size_t>(impl_->node_count());
  if (node_pos.size() != size || node_vel.size() != size)
    throw runtime_error("PdSolver::set_state: expected " + std::to_string(size) + " floats each, got " +
                        std::to_string(node_pos.size()) + " and " + std::to_string(node_vel.size()));
  impl_->set_state(node_pos, node_vel);
}

std::vector<float> PdSolver::node_pos() const { return impl_->node_pos(); }
std::vector<float> PdSolver::node_vel() const { return impl_->node_vel(); }
std::vector<float> PdSolver::node_mass() const { return impl_->node_mass(); }
std::vector<std::uint8_t> PdSolver::node_pinned() const { return impl_->node_pinned(); }

}  // namespace tear
