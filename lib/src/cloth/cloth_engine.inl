// tear::Cloth on either backend: one DeviceCloth, and the engine's three jobs on it: cut (scripted
// cuts and tears through the remesher, cloth_cutting.h), step (the solver and the tearing check,
// cloth_stepping.h) and transfer (upload, frames, checkpoints, cloth_transfer.h). Nothing goes
// through the host between frames but what a frame writes.
#include <algorithm>
#include <cstring>
#include <string>
#include <type_traits>

#include <thrust/copy.h>
#include <thrust/functional.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/transform_reduce.h>

#include "backend/backend.h"
#include "cloth/cloth_cutting.h"
#include "cloth/cloth_engine.h"
#include "cloth/cloth_stepping.h"
#include "cloth/cloth_transfer.h"
#include "cloth/face_pieces.h"
#include "cloth_data/device_cloth.h"
#include "tear/pending_mesh.h"
#include "topology/device_topology.h"

namespace tear::backend {

namespace {
/// Whether component i of a position or of a velocity is not finite.
struct state_not_finite {
  const float* pos;
  const float* vel;
  TEAR_HD bool operator()(std::size_t i) const { return !kernels::is_finite(pos[i]) || !kernels::is_finite(vel[i]); }
};
}  // namespace

template <class System>
class ClothEngine final : public Cloth::Engine {
 public:
  explicit ClothEngine(const Mesh& mesh) {
    upload_cloth(cloth_, mesh, cutter_.remesher().topology_scratch(), cutter_.remesher().allocator());
    // Pieces numbered afresh, in order of their lowest face.
    std::vector<index_t> pieces;
    piece_count_ = number_pieces(mesh.face_nodes, mesh.node_count(), pieces);
    assign_from_host(cloth_.face_piece, pieces);
  }

  Device device() const override { return std::is_same<System, Omp>::value ? Device::cpu : Device::cuda; }
  index_t node_count() const override { return cloth_.node_count(); }
  index_t face_count() const override { return cloth_.face_count(); }

  CutStats cut(const std::vector<CutLine>& cuts, const CutOptions& options) override {
    bool changed = false;
    const CutStats stats = cutter_.cut(cloth_, cuts, options, changed);
    if (changed) {
      stepper_.mesh_changed();  // the solver's model is the old mesh's: rebuilt by the next step
      renumber_pieces_now();
    }
    return stats;
  }

  void simulate(const SimulationOptions& options) override {
    simulated_ = true;
    frames_stepped_ = 0;
    // Listed pins name nodes of the cloth as it is now; from here on the pins are carried by the
    // cuts (the copies of a pinned node stay pinned) and boxes pin again what a cut makes in them.
    // Boxes are applied on the backend: here they hold no node, keeping their place in the list.
    SimulationOptions listed = options;
    for (Pin& p : listed.pins)
      if (p.kind == Pin::Kind::box) {
        p.kind = Pin::Kind::nodes;
        p.nodes.clear();
      }
    assign_from_host(cloth_.node_pinned, resolve_pins(listed, std::vector<float>(), node_count()));
    std::vector<double> boxes;
    for (std::size_t i = 0; i < options.pins.size(); ++i) {
      const Pin& p = options.pins[i];
      if (p.kind != Pin::Kind::box) continue;
      boxes.insert(boxes.end(), p.min.begin(), p.min.end());
      boxes.insert(boxes.end(), p.max.begin(), p.max.end());
      boxes.push_back(static_cast<double>(i + 1));
    }
    cutter_.set_pin_boxes(cloth_, boxes);
    stepper_.start(cloth_, options);
  }
  bool simulated() const override { return simulated_; }

  bool step(int frame, const volatile std::sig_atomic_t* stop) override {
    if (!simulated_) throw Error(ErrorKind::usage, "Cloth::step: no simulation (call Cloth::simulate first)");
    if (frame < 1) frame = frames_stepped_ + 1;
    const bool whole = stepper_.step(cloth_, cutter_, frame, last_tear_, stop);
    frames_stepped_ = frame;
    if (last_tear_.events > 0) renumber_pieces_now();  // once per frame, over all its substeps' tears
    return whole;
  }

  TearStats last_tear() const override { return last_tear_; }

  bool state_is_finite() const override {
    // Positions and velocities in one reduction and one read-back (a frame's only wait).
    const thrust::counting_iterator<std::size_t> zero(0);
    return !thrust::transform_reduce(Traits<System>::policy(), zero, zero + cloth_.node_pos.size(),
                                     state_not_finite{raw<float>(cloth_.node_pos), raw<float>(cloth_.node_vel)}, false,
                                     thrust::logical_or<bool>());
  }

  PendingMesh mesh_later(bool corner_normals) const override { return download_cloth_later(cloth_, corner_normals); }
  index_t piece_count() const override { return piece_count_; }
  bool has_corner_normals() const override { return !cloth_.corner_normal.empty(); }
  std::vector<index_t> face_nodes() const override { return to_host<index_t>(cloth_.face_nodes); }
  Topology topology() const override { return download(cloth_.topo); }
  std::vector<float> node_pos() const override { return to_host<float>(cloth_.node_pos); }
  std::vector<float> node_rest() const override { return to_host<float>(cloth_.node_rest); }
  std::vector<float> node_vel() const override { return to_host<float>(cloth_.node_vel); }
  std::vector<std::uint8_t> node_pinned() const override { return to_host<std::uint8_t>(cloth_.node_pinned); }
  CutProvenance provenance() const override { return cutter_.remesher().provenance(); }
  std::string save_state() const override { return save_cloth(cloth_, frames_stepped_); }

  void load_state(const std::string& state, const std::string& source) override {
    DeviceCloth<System> c;
    int frames = 0;
    load_cloth(c, frames, state, source, cutter_.remesher().topology_scratch(), cutter_.remesher().allocator());
    cloth_ = std::move(c);
    frames_stepped_ = frames;
    const std::vector<index_t> pieces = to_host<index_t>(cloth_.face_piece);
    piece_count_ = 0;
    for (index_t p : pieces) {
      if (p < 0 || p >= face_count())
        throw input_error(source, "a face's piece is out of range (a damaged or foreign checkpoint)");
      piece_count_ = std::max(piece_count_, p + 1);
    }
    stepper_.mesh_changed();
  }

  void set_node_state(const std::vector<float>& node_pos, const std::vector<float>& node_vel) override {
    // Into the arrays in place: a solver bound to them stays valid.
    thrust::copy(node_pos.begin(), node_pos.end(), cloth_.node_pos.begin());
    thrust::copy(node_vel.begin(), node_vel.end(), cloth_.node_vel.begin());
  }

  const float* node_pos_data() const override {
    Traits<System>::synchronize();
    return raw<float>(cloth_.node_pos);
  }
  void copy_node_pos_from(const float* data) override {
    Traits<System>::copy_in(raw<float>(cloth_.node_pos), data, cloth_.node_pos.size() * sizeof(float));
    Traits<System>::synchronize();
  }

 private:
  /// The pieces after a cut or tear: each face's carried id renumbered for the pieces it is in now.
  void renumber_pieces_now() {
    std::vector<index_t> pieces = to_host<index_t>(cloth_.face_piece);
    piece_count_ = renumber_pieces(to_host<index_t>(cloth_.face_nodes), to_host<float>(cloth_.node_rest), pieces);
    assign_from_host(cloth_.face_piece, pieces);
  }

  DeviceCloth<System> cloth_;
  index_t piece_count_ = 0;  // the pieces (ids 0 .. piece_count_ - 1)
  CutJob<System> cutter_;
  StepJob<System> stepper_;
  bool simulated_ = false;
  int frames_stepped_ = 0;  // the frame stepped last, 0 before the first
  TearStats last_tear_;     // what the last step tore
};

template <class System>
std::unique_ptr<Cloth::Engine> make_cloth_engine(const Mesh& mesh) {
  return std::make_unique<ClothEngine<System>>(mesh);
}

#define TEAR_INSTANTIATE(S) template std::unique_ptr<Cloth::Engine> make_cloth_engine<S>(const Mesh&);
TEAR_FOR_EACH_SYSTEM(TEAR_INSTANTIATE)
#undef TEAR_INSTANTIATE

}  // namespace tear::backend
