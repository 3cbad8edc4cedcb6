// tear: the per-backend implementation behind tear::Cloth.
#pragma once

#include <memory>
#include <string>

#include "backend/systems.h"
#include "tear/cloth.h"
#include "tear/pending_mesh.h"
#include "tear/simulation.h"

namespace tear {

class Cloth::Engine {
 public:
  virtual ~Engine() = default;
  virtual Device device() const = 0;
  virtual index_t node_count() const = 0;
  virtual index_t face_count() const = 0;
  virtual CutStats cut(const std::vector<CutLine>& cuts, const CutOptions& options) = 0;
  virtual void simulate(const SimulationOptions& options) = 0;
  virtual bool simulated() const = 0;
  /// Steps frame `frame` (1-based), or the one after the frame stepped last where `frame` < 1;
  /// false when `stop` (may be null) was set before its last substep (`Cloth::step_frame`).
  virtual bool step(int frame, const volatile std::sig_atomic_t* stop) = 0;
  virtual bool state_is_finite() const = 0;
  virtual TearStats last_tear() const = 0;
  /// The mesh, its copy to the host queued (`Cloth::mesh_later`).
  virtual PendingMesh mesh_later(bool corner_normals) const = 0;
  virtual bool has_corner_normals() const = 0;
  virtual index_t piece_count() const = 0;
  virtual std::vector<index_t> face_nodes() const = 0;
  virtual Topology topology() const = 0;
  virtual std::vector<float> node_pos() const = 0;
  virtual std::vector<float> node_rest() const = 0;
  virtual std::vector<float> node_vel() const = 0;
  virtual std::vector<std::uint8_t> node_pinned() const = 0;
  virtual CutProvenance provenance() const = 0;
  virtual std::string save_state() const = 0;
  /// Throws an input `Error` naming `source` when `state` is not a consistent cloth.
  virtual void load_state(const std::string& state, const std::string& source) = 0;
  /// Sizes already checked by `Cloth::set_node_state`.
  virtual void set_node_state(const std::vector<float>& node_pos, const std::vector<float>& node_vel) = 0;
  virtual const float* node_pos_data() const = 0;
  virtual void copy_node_pos_from(const float* data) = 0;
};

namespace backend {
template <class System>
std::unique_ptr<Cloth::Engine> make_cloth_engine(const Mesh& mesh);
}  // namespace backend

}  // namespace tear
