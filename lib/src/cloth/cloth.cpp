#include "tear/cloth.h"

#include <cmath>

#include "cloth/cloth_engine.h"
#include "tear/error.h"

namespace tear {


const char* to_string(CutStage stage) {
  switch (stage) {
    case CutStage::intersection: return "intersection";
    case CutStage::cut_info: return "cut_info";
    case CutStage::counts_and_scans: return "counts_and_scans";
    case CutStage::node_write: return "node_write";
    case CutStage::face_write: return "face_write";
    case CutStage::node_mapping: return "node_mapping";
    case CutStage::adjacency: return "adjacency";
    default: return "?";
  }
}


Cloth::Cloth(const Mesh& mesh, Device device)
    : engine_(backend::dispatch(device, [&](auto system) { return backend::make_cloth_engine<decltype(system)>(mesh); })) {}
Cloth::~Cloth() = default;
Cloth::Cloth(Cloth&&) noexcept = default;
Cloth& Cloth::operator=(Cloth&&) noexcept = default;

Device Cloth::device() const { return engine_->device(); }
index_t Cloth::node_count() const { return engine_->node_count(); }
index_t Cloth::face_count() const { return engine_->face_count(); }
CutStats Cloth::cut(const std::vector<CutLine>& cuts, const CutOptions& options) { return engine_->cut(cuts, options); }
Mesh Cloth::mesh() const { return engine_->mesh_later(true).take(); }
PendingMesh Cloth::mesh_later(bool corner_normals) const { return engine_->mesh_later(corner_normals); }
bool Cloth::has_corner_normals() const { return engine_->has_corner_normals(); }
index_t Cloth::piece_count() const { return engine_->piece_count(); }
std::vector<index_t> Cloth::face_nodes() const { return engine_->face_nodes(); }
Topology Cloth::topology() const { return engine_->topology(); }
std::vector<float> Cloth::node_pos() const { return engine_->node_pos(); }
std::vector<float> Cloth::node_rest() const { return engine_->node_rest(); }
std::vector<float> Cloth::node_vel() const { return engine_->node_vel(); }
const float* Cloth::node_pos_data() const { return engine_->node_pos_data(); }
void Cloth::copy_node_pos_from(const float* data) {
  if (data == nullptr && node_count() > 0) throw Error(ErrorKind::usage, "Cloth::copy_node_pos_from: no data");
  engine_->copy_node_pos_from(data);
}
CutProvenance Cloth::provenance() const { return engine_->provenance(); }
std::vector<std::uint8_t> Cloth::node_pinned() const { return engine_->node_pinned(); }
void Cloth::simulate(const SimulationOptions& options) { engine_->simulate(options); }
bool Cloth::simulated() const { return engine_->simulated(); }
void Cloth::step() { engine_->step(0, nullptr); }
void Cloth::step_frame(int frame) { step_frame(frame, nullptr); }
bool Cloth::step_frame(int frame, const volatile std::sig_atomic_t* stop) {
  if (frame < 1)
    throw Error(ErrorKind::usage, "Cloth::step_frame: expected a frame >= 1, got " + std::to_string(frame));
  return engine_->step(frame, stop);
}
bool Cloth::state_is_finite() const { return engine_->state_is_finite(); }
TearStats Cloth::last_tear() const { return engine_->last_tear(); }
std::string Cloth::save_state() const { return engine_->save_state(); }
void Cloth::load_state(const std::string& state, const std::string& source) { engine_->load_state(state, source); }

void Cloth::set_node_state(const std::vector<float>& node_pos, const std::vector<float>& node_vel) {
  const std::size_t expected = 3 * std::size_t(node_count());
  if (node_pos.size() != expected || node_vel.size() != expected)
    throw Error(ErrorKind::usage, "Cloth::set_node_state: expected " + std::to_string(expected) +
                                      " coordinates each, got " + std::to_string(node_pos.size()) + " positions and " +
                                      std::to_string(node_vel.size()) + " velocities");
  engine_->set_node_state(node_pos, node_vel);
}

PendingMesh::PendingMesh() = default;
PendingMesh::PendingMesh(Mesh mesh) : mesh_(std::move(mesh)) {}
PendingMesh::PendingMesh(std::unique_ptr<Source> source) : source_(std::move(source)) {}
PendingMesh::~PendingMesh() = default;
PendingMesh::PendingMesh(PendingMesh&&) noexcept = default;
PendingMesh& PendingMesh::operator=(PendingMesh&&) noexcept = default;

Mesh PendingMesh::take() {
  if (!source_) {
    Mesh mesh = std::move(mesh_);
    mesh_ = Mesh();
    return mesh;
  }
  // The source goes as soon as its mesh is built: its memory on both sides is released here.
  const std::unique_ptr<Source> source = std::move(source_);
  return source->take();
}

}  // namespace tear
