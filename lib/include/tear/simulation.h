// tear: cloth simulation by projective dynamics (Bouaziz et al. 2014) with a Jacobi global step
// accelerated by Chebyshev semi-iteration (Wang 2015); docs/simulation.md is its reference.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "tear/device.h"
#include "tear/mesh.h"
#include "tear/simulation_options.h"

namespace tear {

/// The pins of the nodes [node_count] (0 free, p + 1 held by `options.pins[p]`, the first pin that
/// holds the node) on a mesh with rest positions `node_rest` [node_count * 3]. A listed node outside
/// [0, node_count) is an input error naming `options.source` and the pin's key path, and so are more
/// than `simulation_limits::max_pins` pins.
std::vector<std::uint8_t> resolve_pins(const SimulationOptions& options, const std::vector<float>& node_rest,
                                       index_t node_count);

/// The solver of one mesh given as host arrays: its model (masses, constraints, the Jacobi
/// diagonal, pins) is built on the device from the mesh and stays fixed; the state (positions and
/// velocities) lives on the device between steps. A `Cloth` simulates itself with the same solver
/// (`Cloth::simulate`, `Cloth::step`), its model rebuilt on the device after each cut.
///
/// Constraints: an edge spring per edge (stretch) and a hinge per interior edge (bending, the
/// dihedral-neighbour Laplacian of the two faces). Each Jacobi node update gathers its own
/// constraints through a node→constraint CSR in a fixed order, so results are the same bits run
/// after run on one backend.
class PdSolver {
 public:
  /// `face_nodes` [face_count * 3], `node_rest` [node_count * 3] rest positions (metres). Pins come
  /// from `options.pins` (`resolve_pins`). The state starts at rest: positions = rest, velocities 0.
  PdSolver(const std::vector<index_t>& face_nodes, const std::vector<float>& node_rest, index_t node_count,
           const SimulationOptions& options, Device device);
  /// The same with the nodes' pins given [node_count] (0 free, p + 1 held by `options.pins[p]`, as
  /// `resolve_pins` gives them), for a cloth whose pins were carried through cuts; a value naming no
  /// pin of `options.pins` holds its node where it is.
  PdSolver(const std::vector<index_t>& face_nodes, const std::vector<float>& node_rest, index_t node_count,
           const SimulationOptions& options, Device device, const std::vector<std::uint8_t>& node_pinned);
  ~PdSolver();
  PdSolver(PdSolver&&) noexcept;
  PdSolver& operator=(PdSolver&&) noexcept;

  Device device() const;
  index_t node_count() const;
  /// Constraints with a non-zero weight (edge springs and hinges).
  index_t constraint_count() const;
  /// The least memory traffic of one iteration, bytes: every array the iteration reads or writes
  /// touched once (gathered neighbours served by the cache). Over the device's copy bandwidth it is
  /// the time an iteration cannot beat (`tear bench`).
  std::size_t bytes_per_iteration() const;
  const SimulationOptions& options() const;

  /// Advances the held state by one frame (1 / fps seconds, `substeps` steps): the frame after the
  /// one stepped last, frame 1 first. Queues device work without waiting for it; reading the state
  /// back synchronises.
  void step();
  /// Advances the held state through frame `frame` (1-based, as a script counts), whose substeps
  /// the keys of pins and colliders are evaluated at; later `step` calls go on from it.
  void step_frame(int frame);
  /// Uploads `node_pos` and `node_vel` [node_count * 3], steps one frame and downloads them.
  void step(std::vector<float>& node_pos, std::vector<float>& node_vel);

  /// Replaces the state; both [node_count * 3]. Nodes of pins without keys are held where
  /// `node_pos` puts them.
  void set_state(const std::vector<float>& node_pos, const std::vector<float>& node_vel);
  std::vector<float> node_pos() const;  ///< [node_count * 3] metres
  std::vector<float> node_vel() const;  ///< [node_count * 3] m/s

  std::vector<float> node_mass() const;           ///< [node_count] kg (density × a third of each face's area)
  std::vector<std::uint8_t> node_pinned() const;  ///< [node_count] 0 free, p + 1 held by pin p

  class Impl;  ///< the per-backend implementation

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace tear
