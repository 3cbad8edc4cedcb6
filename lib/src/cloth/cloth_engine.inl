// tear::Cloth on either backend: one DeviceCloth, cut in place by the remesher and stepped in place
// by the solver; nothing goes through the host between frames but what a frame writes.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <string>
#include <type_traits>

#include <thrust/copy.h>
#include <thrust/fill.h>
#include <thrust/for_each.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/functional.h>
#include <thrust/transform_reduce.h>

#include "backend/backend.h"
#include "cloth/cloth_engine.h"
#include "cloth/device_cloth.h"
#include "node_identity.h"
#include "tear/pending_mesh.h"
#include "remesh/remesher.h"
#include "sim/pd_solver_device.h"
#include "topology/device_topology.h"

namespace tear::backend {

namespace {
/// Bit j of input face f: its edge j (opposite corner j) is on the border.
struct mark_input_face_border {
  const index_t* face_edges;
  const index_t* edge_faces;
  std::uint8_t* input_face_border;
  TEAR_HD void operator()(index_t f) const {
    std::uint8_t bits = 0;
    for (int j = 0; j < 3; ++j)
      if (edge_faces[2 * face_edges[3 * f + j] + 1] < 0) bits |= std::uint8_t(1u << j);
    input_face_border[f] = bits;
  }
};

/// The unit weights of corner k of its own face: (1,0,0), (0,1,0), (0,0,1).
struct unit_corner_weights {
  float* corner_origin;
  TEAR_HD void operator()(index_t c) const {
    for (int j = 0; j < 3; ++j) corner_origin[3 * c + j] = (c % 3 == j) ? 1.f : 0.f;
  }
};

/// Pins every node whose rest position lies in one of the boxes ([box * 7]: min xyz, max xyz, the
/// pin's value p + 1) to the first pin that holds it: a node already held by an earlier pin keeps it.
struct pin_boxes {
  const float* node_rest;
  const double* boxes;
  int box_count;
  std::uint8_t* node_pinned;
  TEAR_HD void operator()(index_t n) const {
    for (int b = 0; b < box_count; ++b) {
      bool inside = true;
      for (int a = 0; a < 3; ++a) {
        const double x = node_rest[3 * n + a];
        inside = inside && x >= boxes[7 * b + a] && x <= boxes[7 * b + 3 + a];
      }
      const auto pin = static_cast<std::uint8_t>(boxes[7 * b + 6]);
      if (inside && (node_pinned[n] == 0 || node_pinned[n] > pin)) node_pinned[n] = pin;
    }
  }
};

/// Whether component i of a position or of a velocity is not finite.
struct state_not_finite {
  const float* pos;
  const float* vel;
  TEAR_HD bool operator()(std::size_t i) const { return !kernels::is_finite(pos[i]) || !kernels::is_finite(vel[i]); }
};
}  // namespace

/// A frame on its way to the host (`Cloth::mesh_later`): its arrays in one block of backend memory,
/// copied to the host beside the backend's later work; `take` builds the mesh from the copy.
template <class System>
struct MeshCopy final : PendingMesh::Source {
  index_t nodes = 0, faces = 0;
  std::size_t uv = 0, normal = 0;  // floats of corner UVs and normals copied (0: none)
  std::size_t at_pos = 0, at_vel = 0, at_origin_bary = 0, at_origin_face = 0, at_faces = 0, at_uv = 0, at_normal = 0,
              at_torn = 0, bytes = 0;  // byte offsets in `frame`, and its size
  vector<System, char> frame;          // before `copy`: freed after the copy is waited for
  typename Traits<System>::HostCopy copy;

  void lay_out() {
    const std::size_t n = static_cast<std::size_t>(nodes), f = static_cast<std::size_t>(faces);
    const auto place = [&](std::size_t size) {
      const std::size_t at = bytes;
      bytes = (bytes + size + 15) / 16 * 16;
      return at;
    };
    at_pos = place(3 * n * sizeof(float));
    at_vel = place(3 * n * sizeof(float));
    at_origin_bary = place(2 * n * sizeof(float));
    at_origin_face = place(n * sizeof(index_t));
    at_faces = place(3 * f * sizeof(index_t));
    at_uv = place(uv * sizeof(float));
    at_normal = place(normal * sizeof(float));
    at_torn = place(3 * f);
  }

  Mesh take() override {
    const char* host = static_cast<const char*>(copy.wait());
    const std::size_t n = static_cast<std::size_t>(nodes), f = static_cast<std::size_t>(faces);
    Mesh m;
    assign(m.node_pos, host + at_pos, 3 * n);
    assign(m.node_vel, host + at_vel, 3 * n);
    assign(m.node_origin_bary, host + at_origin_bary, 2 * n);
    assign(m.node_origin_face, host + at_origin_face, n);
    assign(m.face_nodes, host + at_faces, 3 * f);
    assign(m.corner_uv, host + at_uv, uv);
    assign(m.corner_normal, host + at_normal, normal);
    const auto* torn = reinterpret_cast<const std::uint8_t*>(host + at_torn);
    for (std::size_t corner = 0; corner < 3 * f; ++corner)
      if (torn[corner]) {
        const std::size_t face = corner / 3, k = corner % 3;
        m.torn_edge_nodes.push_back(m.face_nodes[3 * face + k]);
        m.torn_edge_nodes.push_back(m.face_nodes[3 * face + (k + 1) % 3]);
      }
    return m;
  }

 private:
  template <class T>
  static void assign(std::vector<T>& v, const char* from, std::size_t count) {
    v.resize(count);
    if (count > 0) std::memcpy(v.data(), from, count * sizeof(T));
  }
};

template <class System>
class ClothEngine final : public Cloth::Engine {
  template <class T>
  using vec = vector<System, T>;

 public:
  explicit ClothEngine(const Mesh& mesh) {
    DeviceCloth<System>& c = cloth_;
    assign_from_host(c.face_nodes, mesh.face_nodes);
    assign_from_host(c.node_rest, mesh.node_pos);
    assign_from_host(c.node_pos, mesh.node_pos);
    if (mesh.node_vel.size() == mesh.node_pos.size())
      assign_from_host(c.node_vel, mesh.node_vel);
    else
      c.node_vel.assign(mesh.node_pos.size(), 0.0f);
    if (!mesh.corner_uv.empty()) assign_from_host(c.corner_uv, mesh.corner_uv);
    if (!mesh.corner_normal.empty()) assign_from_host(c.corner_normal, mesh.corner_normal);
    c.node_pinned.assign(mesh.node_pos.size() / 3, 0);
    build_device_topology(c.topo, c.face_nodes, mesh.node_count(), remesher_.topology_scratch(), remesher_.allocator());
    // The mesh as read is its own origin: face f lies in input face f, each corner at its own corner.
    const index_t f_count = c.face_count();
    const thrust::counting_iterator<index_t> zero(0);
    const auto policy = Traits<System>::policy();
    c.face_origin.resize(f_count);
    thrust::copy(policy, zero, zero + f_count, c.face_origin.begin());
    c.corner_origin.resize(9 * std::size_t(f_count));
    thrust::for_each(policy, zero, zero + 3 * f_count, unit_corner_weights{raw<float>(c.corner_origin)});
    c.input_face_border.resize(f_count);
    thrust::for_each(policy, zero, zero + f_count,
                     mark_input_face_border{raw<index_t>(c.topo.face_edges), raw<index_t>(c.topo.edge_faces),
                                            raw<std::uint8_t>(c.input_face_border)});
  }

  Device device() const override { return std::is_same<System, Omp>::value ? Device::cpu : Device::cuda; }
  index_t node_count() const override { return cloth_.node_count(); }
  index_t face_count() const override { return cloth_.face_count(); }

  CutStats cut(const std::vector<CutLine>& cuts, const CutOptions& options) override {
    CutStats stats;
    stats.nodes_before = stats.nodes_after = cloth_.node_count();
    stats.faces_before = stats.faces_after = cloth_.face_count();
    StageClock clock(options.time_stages, stats.stage_ms.data());
    if (remesher_.cut_info_from_paths(cloth_, cuts, options, clock) &&
        remesher_.apply_cut_info(cloth_, options, stats, clock)) {
      solver_stale_ = true;  // its model is the old mesh's: rebuilt by the next step
      reapply_box_pins();
    }
    Traits<System>::synchronize();
    stats.total_ms = clock.total_ms();
    return stats;
  }

  void simulate(const SimulationOptions& options) override {
    options_ = options;
    simulated_ = true;
    solver_.reset();
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
    const std::vector<std::uint8_t> pinned = resolve_pins(listed, std::vector<float>(), node_count());
    assign_from_host(cloth_.node_pinned, pinned);
    std::vector<double> boxes;
    for (std::size_t i = 0; i < options.pins.size(); ++i) {
      const Pin& p = options.pins[i];
      if (p.kind != Pin::Kind::box) continue;
      boxes.insert(boxes.end(), p.min.begin(), p.min.end());
      boxes.insert(boxes.end(), p.max.begin(), p.max.end());
      boxes.push_back(static_cast<double>(i + 1));
    }
    assign_from_host(pin_boxes_, boxes);
    reapply_box_pins();
  }
  bool simulated() const override { return simulated_; }

  void step(int frame) override {
    if (!simulated_) throw Error(ErrorKind::usage, "Cloth::step: no simulation (call Cloth::simulate first)");
    if (frame < 1) frame = frames_stepped_ + 1;
    last_tear_ = TearStats{};
    if (!options_.tearing.enabled()) {
      refresh_solver();
      solver_->step_in_place(raw<float>(cloth_.node_pos), raw<float>(cloth_.node_vel), frame);
    } else {
      // Torn between substeps: the next substep steps the torn cloth with its new model. Nothing
      // waits for the device but the read-backs the stages need; marks in the backend's queue time
      // the parts, read once the step's work is done.
      const int substeps = options_.substeps;
      if (step_mark_count_ < substeps) {
        step_marks_ = std::make_unique<StepMarks[]>(static_cast<std::size_t>(substeps));
        step_mark_count_ = substeps;
      }
      for (int s = 0; s < substeps; ++s) {
        StepMarks& m = step_marks_[s];
        m.rebuilt = !solver_ || solver_stale_;
        if (m.rebuilt) m.rebuild_start.record();
        refresh_solver();
        if (m.rebuilt) m.rebuild_end.record();
        m.substep_start.record();
        solver_->step_substep_in_place(raw<float>(cloth_.node_pos), raw<float>(cloth_.node_vel), frame, s);
        m.substep_end.record();
        m.applied = tear(m);
      }
      Traits<System>::synchronize();
      for (int s = 0; s < substeps; ++s) {
        const StepMarks& m = step_marks_[s];
        if (m.rebuilt) last_tear_.rebuild_ms += QueueMark::elapsed_ms(m.rebuild_start, m.rebuild_end);
        last_tear_.solver_ms += QueueMark::elapsed_ms(m.substep_start, m.substep_end);
        last_tear_.check_ms += QueueMark::elapsed_ms(m.substep_end, m.check_end);
        if (m.applied) last_tear_.apply_ms += QueueMark::elapsed_ms(m.check_end, m.apply_end);
      }
    }
    frames_stepped_ = frame;
  }

  TearStats last_tear() const override { return last_tear_; }

  bool state_is_finite() const override {
    // Positions and velocities in one reduction and one read-back (a frame's only wait).
    const thrust::counting_iterator<std::size_t> zero(0);
    return !thrust::transform_reduce(Traits<System>::policy(), zero, zero + cloth_.node_pos.size(),
                                     state_not_finite{raw<float>(cloth_.node_pos), raw<float>(cloth_.node_vel)}, false,
                                     thrust::logical_or<bool>());
  }

  PendingMesh mesh_later(bool corner_normals) const override {
    const DeviceCloth<System>& c = cloth_;
    auto copy = std::make_unique<MeshCopy<System>>();
    MeshCopy<System>& m = *copy;
    m.nodes = c.node_count();
    m.faces = c.face_count();
    const std::size_t f = static_cast<std::size_t>(m.faces);
    m.uv = c.corner_uv.empty() ? 0 : 6 * f;
    m.normal = !corner_normals || c.corner_normal.empty() ? 0 : 9 * f;
    m.lay_out();
    resize_for_overwrite(m.frame, m.bytes);
    char* base = raw<char>(m.frame);
    // The frame's arrays into one block of backend memory, queued behind its work: the cloth goes on
    // while the block is copied to the host.
    const auto policy = Traits<System>::policy();
    const auto into = [&](const auto& v, std::size_t at) {
      using T = typename std::decay_t<decltype(v)>::value_type;
      const T* from = raw<T>(v);
      thrust::copy(policy, from, from + v.size(), reinterpret_cast<T*>(base + at));
    };
    into(c.node_pos, m.at_pos);
    into(c.node_vel, m.at_vel);
    into(c.face_nodes, m.at_faces);
    if (m.uv) into(c.corner_uv, m.at_uv);
    if (m.normal) into(c.corner_normal, m.at_normal);
    // Origins and torn edges, derived on the backend from the carried face and corner origins.
    for_each_index<System>(m.nodes, kernels::gather_node_origins{
                                        raw<index_t>(c.face_nodes), raw<index_t>(c.topo.node_face_offset),
                                        raw<index_t>(c.topo.node_faces), raw<index_t>(c.face_origin),
                                        raw<float>(c.corner_origin), reinterpret_cast<index_t*>(base + m.at_origin_face),
                                        reinterpret_cast<float*>(base + m.at_origin_bary)});
    for_each_index<System>(3 * m.faces, kernels::mark_torn_corners{
                                            raw<index_t>(c.topo.face_edges), raw<index_t>(c.topo.edge_faces),
                                            raw<index_t>(c.face_origin), raw<float>(c.corner_origin),
                                            raw<std::uint8_t>(c.input_face_border),
                                            reinterpret_cast<std::uint8_t*>(base + m.at_torn)});
    m.copy.start(base, m.bytes);
    return PendingMesh(std::move(copy));
  }
  bool has_corner_normals() const override { return !cloth_.corner_normal.empty(); }
  std::vector<index_t> face_nodes() const override { return to_host<index_t>(cloth_.face_nodes); }
  Topology topology() const override { return download(cloth_.topo); }
  std::vector<float> node_pos() const override { return to_host<float>(cloth_.node_pos); }
  std::vector<float> node_rest() const override { return to_host<float>(cloth_.node_rest); }
  std::vector<float> node_vel() const override { return to_host<float>(cloth_.node_vel); }
  std::vector<std::uint8_t> node_pinned() const override { return to_host<std::uint8_t>(cloth_.node_pinned); }
  CutProvenance provenance() const override { return remesher_.provenance(); }
  std::string save_state() const override {
    std::string out;
    const DeviceCloth<System>& c = cloth_;
    put(out, c.face_nodes);
    put(out, c.node_rest);
    put(out, c.corner_uv);
    put(out, c.corner_normal);
    put(out, c.node_pos);
    put(out, c.node_vel);
    put(out, c.node_pinned);
    put(out, c.face_origin);
    put(out, c.corner_origin);
    put(out, c.input_face_border);
    put(out, vec<std::int64_t>(std::size_t(1), std::int64_t(frames_stepped_)));
    return out;
  }

  void load_state(const std::string& state, const std::string& source) override {
    DeviceCloth<System> c;
    std::size_t at = 0;
    take(state, at, c.face_nodes, source);
    take(state, at, c.node_rest, source);
    take(state, at, c.corner_uv, source);
    take(state, at, c.corner_normal, source);
    take(state, at, c.node_pos, source);
    take(state, at, c.node_vel, source);
    take(state, at, c.node_pinned, source);
    take(state, at, c.face_origin, source);
    take(state, at, c.corner_origin, source);
    take(state, at, c.input_face_border, source);
    vec<std::int64_t> frames_stepped;
    take(state, at, frames_stepped, source);
    const std::size_t f = c.face_nodes.size() / 3, n = c.node_rest.size() / 3;
    const bool sizes = at == state.size() && c.face_nodes.size() == 3 * f && c.node_rest.size() == 3 * n &&
                       (c.corner_uv.empty() || c.corner_uv.size() == 6 * f) &&
                       (c.corner_normal.empty() || c.corner_normal.size() == 9 * f) && c.node_pos.size() == 3 * n &&
                       c.node_vel.size() == 3 * n && c.node_pinned.size() == n && c.face_origin.size() == f &&
                       c.corner_origin.size() == 9 * f && frames_stepped.size() == 1;
    if (!sizes) throw input_error(source, "the cloth's arrays do not fit together (a damaged or foreign checkpoint)");
    const std::vector<index_t> nodes = to_host<index_t>(c.face_nodes);
    const std::vector<index_t> origins = to_host<index_t>(c.face_origin);
    const index_t input_faces = static_cast<index_t>(c.input_face_border.size());
    if (std::any_of(nodes.begin(), nodes.end(), [&](index_t v) { return v < 0 || v >= index_t(n); }) ||
        std::any_of(origins.begin(), origins.end(), [&](index_t v) { return v < 0 || v >= input_faces; }))
      throw input_error(source, "a face names a node or an input face out of range (a damaged or foreign checkpoint)");
    build_device_topology(c.topo, c.face_nodes, static_cast<index_t>(n), remesher_.topology_scratch(),
                          remesher_.allocator());
    const std::int64_t frame = frames_stepped[0];
    if (frame < 0 || frame > max_frames)
      throw input_error(source, "the cloth's frame count is out of range (a damaged or foreign checkpoint)");
    cloth_ = std::move(c);
    frames_stepped_ = static_cast<int>(frame);
    solver_stale_ = true;
  }

  void set_node_state(const std::vector<float>& node_pos, const std::vector<float>& node_vel) override {
    // Into the arrays in place: a solver bound to them stays valid.
    thrust::copy(node_pos.begin(), node_pos.end(), cloth_.node_pos.begin());
    thrust::copy(node_vel.begin(), node_vel.end(), cloth_.node_vel.begin());
  }

 private:
  /// An array as its element count (8 bytes, little endian as the machine) and its bytes.
  template <class T>
  static void put(std::string& out, const vec<T>& v) {
    const std::vector<T> host = to_host<T>(v);
    const std::uint64_t count = host.size();
    out.append(reinterpret_cast<const char*>(&count), sizeof count);
    out.append(reinterpret_cast<const char*>(host.data()), host.size() * sizeof(T));
  }
  template <class T>
  static void take(const std::string& in, std::size_t& at, vec<T>& v, const std::string& source) {
    std::uint64_t count = 0;
    if (in.size() - at < sizeof count) throw input_error(source, "the cloth's arrays are cut short");
    std::memcpy(&count, in.data() + at, sizeof count);
    at += sizeof count;
    if (count > (in.size() - at) / sizeof(T)) throw input_error(source, "the cloth's arrays are cut short");
    std::vector<T> host(count);
    std::memcpy(host.data(), in.data() + at, count * sizeof(T));
    at += count * sizeof(T);
    assign_from_host(v, host);
  }

  void refresh_solver() {
    if (solver_ && !solver_stale_) return;
    if (solver_)
      rebuild_pd_solver<System>(*solver_, cloth_);  // in the old model's memory, grown where needed
    else
      solver_ = make_pd_solver<System>(cloth_, options_);
    solver_stale_ = false;
  }

  using QueueMark = typename Traits<System>::QueueMark;
  /// A torn substep's parts, marked in the backend's queue: the model's rebuild (where the mesh
  /// changed), the substep, the check, the tear's application (where faces tore).
  struct StepMarks {
    QueueMark rebuild_start, rebuild_end, substep_start, substep_end, check_end, apply_end;
    bool rebuilt = false, applied = false;
  };

  /// Tears the faces stretched beyond the limit, as a cut would split them (docs/simulation.md).
  /// Marks the end of the check and, where faces tore, of their application in `m`; returns
  /// whether it applied a tear.
  bool tear(StepMarks& m) {
    CutOptions cut_options;
    cut_options.snap = options_.tearing.snap;
    CutStats stats;
    StageClock clock(false, stats.stage_ms.data());
    TearCut torn;
    const bool over = remesher_.cut_info_from_strain(cloth_, options_.tearing, cut_options, torn, clock);
    m.check_end.record();
    if (!over) return false;
    if (remesher_.apply_cut_info(cloth_, cut_options, stats, clock, false)) {
      solver_stale_ = true;
      reapply_box_pins();
      last_tear_.events += torn.faces;
      last_tear_.length += remesher_.tear_length();
    }
    m.apply_end.record();
    return true;
  }

  void reapply_box_pins() {
    if (pin_boxes_.empty()) return;
    const thrust::counting_iterator<index_t> zero(0);
    thrust::for_each(Traits<System>::policy(), zero, zero + cloth_.node_count(),
                     pin_boxes{raw<float>(cloth_.node_rest), raw<double>(pin_boxes_),
                               static_cast<int>(pin_boxes_.size() / 7), raw<std::uint8_t>(cloth_.node_pinned)});
  }

  DeviceCloth<System> cloth_;
  Remesher<System> remesher_;
  bool simulated_ = false;
  SimulationOptions options_;
  vec<double> pin_boxes_;                      // [box * 7] of the simulation's box pins (pin_boxes)
  int frames_stepped_ = 0;                     // the frame stepped last, 0 before the first
  std::unique_ptr<PdSolver::Impl> solver_;     // the model of the mesh it was built for
  bool solver_stale_ = false;                  // a cut or tear changed the mesh since
  TearStats last_tear_;                        // what the last step tore
  std::unique_ptr<StepMarks[]> step_marks_;  // [step_mark_count_], one per substep
  int step_mark_count_ = 0;
};

template <class System>
std::unique_ptr<Cloth::Engine> make_cloth_engine(const Mesh& mesh) {
  return std::make_unique<ClothEngine<System>>(mesh);
}

#define TEAR_INSTANTIATE(S) template std::unique_ptr<Cloth::Engine> make_cloth_engine<S>(const Mesh&);
TEAR_FOR_EACH_SYSTEM(TEAR_INSTANTIATE)
#undef TEAR_INSTANTIATE

}  // namespace tear::backend
