// The remesher on either backend (paper §2): a short list of named stages, each a count, a scan or
// a write over one kind of element. Scratch arrays live with the cloth and only grow, so once
// they reach capacity a cut allocates nothing for its own arrays.
#include <algorithm>
#include <chrono>
#include <cmath>

#include <thrust/copy.h>
#include <thrust/transform_reduce.h>
#include <thrust/fill.h>
#include <thrust/for_each.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/scan.h>

#include "backend/backend.h"
#include "cloth/cloth_engine.h"
#include "count_new_nodes.h"
#include "cut_info.h"
#include "topology/device_topology.h"
#include "intersect_cuts.h"
#include "map_nodes.h"
#include "sim/pd_solver_device.h"
#include "split_table.h"
#include "write_new_faces.h"
#include "write_new_nodes.h"

namespace tear::backend {

/// Stage timer of a cut: with timing on, waits for the device at each mark.
class StageClock {
 public:
  using clock = std::chrono::steady_clock;
  StageClock(bool enabled, double* ms) : enabled_(enabled), ms_(ms), start_(clock::now()), last_(start_) {}
  template <class System>
  void mark(CutStage stage) {
    if (!enabled_) return;
    Traits<System>::synchronize();
    const auto now = clock::now();
    ms_[static_cast<int>(stage)] = std::chrono::duration<double, std::milli>(now - last_).count();
    last_ = now;
  }
  double total_ms() const { return std::chrono::duration<double, std::milli>(clock::now() - start_).count(); }

 private:
  bool enabled_;
  double* ms_;
  clock::time_point start_, last_;
};

template <class System>
class ClothEngine final : public Cloth::Engine {
  template <class T>
  using vec = vector<System, T>;

 public:
  explicit ClothEngine(const Mesh& mesh)
      : node_pos_(mesh.node_pos.begin(), mesh.node_pos.end()),
        node_rest_(mesh.node_pos.begin(), mesh.node_pos.end()),
        node_vel_(mesh.node_pos.size(), 0.0f),
        face_nodes_(mesh.face_nodes.begin(), mesh.face_nodes.end()),
        corner_uv_(mesh.corner_uv.begin(), mesh.corner_uv.end()),
        corner_normal_(mesh.corner_normal.begin(), mesh.corner_normal.end()),
        table_(kernels::split_table(), kernels::split_table() + kernels::split_table_size) {
    build_device_topology(topo_, face_nodes_, mesh.node_count(), topo_scratch_, alloc_);
  }

  Device device() const override { return std::is_same<System, Omp>::value ? Device::cpu : Device::cuda; }
  index_t node_count() const override { return topo_.node_count; }
  index_t face_count() const override { return topo_.face_count; }

  CutStats cut(const std::vector<CutLine>& cuts, const CutOptions& options) override;
  void run_cut(const std::vector<CutLine>& cuts, const CutOptions& options, CutStats& stats, StageClock& clock);

  Mesh mesh() const override {
    Mesh m;
    m.node_pos = to_host<float>(node_pos_);
    m.face_nodes = to_host<index_t>(face_nodes_);
    m.corner_uv = to_host<float>(corner_uv_);
    m.corner_normal = to_host<float>(corner_normal_);
    return m;
  }
  Topology topology() const override { return download(topo_); }
  std::vector<float> node_pos() const override { return to_host<float>(node_pos_); }
  std::vector<float> node_rest() const override { return to_host<float>(node_rest_); }
  std::vector<float> node_vel() const override { return to_host<float>(node_vel_); }
  CutProvenance provenance() const override {
    CutProvenance p;
    p.node_source = to_host<index_t>(node_source_);
    p.node_source_weight = to_host<float>(node_source_weight_);
    p.face_parent = to_host<index_t>(face_parent_);
    return p;
  }
  std::unique_ptr<PdSolver::Impl> make_solver(const SimulationOptions& options,
                                              const std::vector<std::uint8_t>& node_pinned) const override {
    return make_pd_solver<System>(face_nodes_, node_rest_, topo_, options, node_pinned);
  }
  float* device_node_pos() override { return raw<float>(node_pos_); }
  float* device_node_vel() override { return raw<float>(node_vel_); }
  void set_node_state(const std::vector<float>& node_pos, const std::vector<float>& node_vel) override {
    node_pos_.assign(node_pos.begin(), node_pos.end());
    node_vel_.assign(node_vel.begin(), node_vel.end());
  }

 private:
  template <class F>
  void for_each_index(index_t count, F f) {
    thrust::counting_iterator<index_t> zero(0);
    thrust::for_each(Traits<System>::policy(), zero, zero + count, f);
  }

  void upload_cuts(const std::vector<CutLine>& cuts);
  kernels::SectorMesh sector_mesh() const;

  // Model and state.
  vec<float> node_pos_, node_rest_, node_vel_;
  vec<index_t> face_nodes_;
  vec<float> corner_uv_, corner_normal_;
  DeviceTopology<System> topo_;
  TopologyScratch<System> topo_scratch_;
  TemporaryAllocator<System> alloc_;  // Thrust's sort and scan buffers, reused cut after cut
  vec<kernels::SplitCase> table_;

  // The frame's cuts.
  vec<kernels::CutPath> cut_paths_;
  vec<double> cut_point_x_, cut_point_y_;

  // Cut info (§2.1).
  vec<double> half_hit_sum_;
  vec<index_t> half_hit_count_;
  vec<std::uint16_t> face_pairs_, face_state_;
  vec<std::uint8_t> edge_point_, face_along_, edge_cut_;
  vec<std::int8_t> face_snap_edge_;
  vec<float> edge_point_t_, face_point_bary_;

  // Counts and offsets (§2.2, §2.3): new nodes of nodes, edges and faces in one array.
  vec<index_t> point_new_offset_, face_new_face_offset_;

  // The mesh being written, and the provenance of the last cut.
  vec<index_t> new_face_nodes_, face_parent_, node_source_;
  vec<float> node_source_weight_, new_node_pos_, new_node_rest_, new_node_vel_, new_corner_uv_, new_corner_normal_;
};

template <class System>
void ClothEngine<System>::upload_cuts(const std::vector<CutLine>& cuts) {
  std::vector<kernels::CutPath> paths;
  std::vector<double> xs, ys;
  for (const CutLine& line : cuts) {
    kernels::CutPath p{};
    p.source = static_cast<kernels::CutSource>(line.source);
    for (int d = 0; d < 3; ++d) {
      p.axis_u[d] = line.axis_u[d];
      p.axis_v[d] = line.axis_v[d];
    }
    p.point_begin = static_cast<index_t>(xs.size());
    p.point_count = static_cast<index_t>(line.polyline.size());
    p.unbounded = (line.unbounded_start ? 1 : 0) | (line.unbounded_end ? 2 : 0);
    for (const auto& q : line.polyline) {
      xs.push_back(q[0]);
      ys.push_back(q[1]);
    }
    if (p.point_count >= 2) paths.push_back(p);
  }
  cut_paths_.assign(paths.begin(), paths.end());
  cut_point_x_.assign(xs.begin(), xs.end());
  cut_point_y_.assign(ys.begin(), ys.end());
}

template <class System>
kernels::SectorMesh ClothEngine<System>::sector_mesh() const {
  return {raw<index_t>(face_nodes_),          raw<index_t>(topo_.face_edges), raw<index_t>(topo_.edge_nodes),
          raw<index_t>(topo_.edge_faces),     raw<index_t>(topo_.node_face_offset), raw<index_t>(topo_.node_faces),
          raw<std::uint16_t>(face_state_),    raw<std::uint8_t>(edge_cut_),   raw<kernels::SplitCase>(table_)};
}

template <class System>
CutStats ClothEngine<System>::cut(const std::vector<CutLine>& cuts, const CutOptions& options) {
  CutStats stats;
  StageClock clock(options.time_stages, stats.stage_ms.data());
  run_cut(cuts, options, stats, clock);
  Traits<System>::synchronize();
  stats.total_ms = clock.total_ms();
  return stats;
}

template <class System>
void ClothEngine<System>::run_cut(const std::vector<CutLine>& cuts, const CutOptions& options, CutStats& stats, StageClock& clock) {
  using namespace kernels;
  const auto policy = Traits<System>::policy(alloc_);
  const index_t n_count = topo_.node_count, f_count = topo_.face_count, e_count = topo_.edge_count;
  stats.nodes_before = stats.nodes_after = n_count;
  stats.faces_before = stats.faces_after = f_count;
  upload_cuts(cuts);
  if (cut_paths_.empty() || f_count == 0) return;
  const bool has_uv = !corner_uv_.empty(), has_normal = !corner_normal_.empty();

  // §2.1 cut points: every cut against every face, one averaged and snapped point per edge, then
  // the 6-bit face cut info (with the face point where lines cross) and the 2-bit edge cut info.
  resize_with_headroom(half_hit_sum_, 3 * std::size_t(f_count));
  resize_with_headroom(half_hit_count_, 3 * std::size_t(f_count));
  resize_with_headroom(face_pairs_, f_count);
  for_each_index(f_count, intersect_cuts{raw<index_t>(face_nodes_), has_uv ? raw<float>(corner_uv_) : nullptr, raw<float>(node_rest_),
                                         raw<float>(node_pos_), raw<CutPath>(cut_paths_), static_cast<index_t>(cut_paths_.size()),
                                         raw<double>(cut_point_x_), raw<double>(cut_point_y_), raw<double>(half_hit_sum_),
                                         raw<index_t>(half_hit_count_), raw<std::uint16_t>(face_pairs_)});
  clock.mark<System>(CutStage::intersection);
  resize_with_headroom(edge_point_, e_count);
  resize_with_headroom(edge_point_t_, e_count);
  for_each_index(e_count, snap_edge_points{raw<index_t>(topo_.edge_faces), raw<index_t>(topo_.face_edges), raw<double>(half_hit_sum_),
                                           raw<index_t>(half_hit_count_), options.snap, raw<float>(edge_point_t_), raw<std::uint8_t>(edge_point_)});
  resize_with_headroom(face_state_, f_count);
  resize_with_headroom(face_along_, f_count);
  resize_with_headroom(face_point_bary_, 3 * std::size_t(f_count));
  const face_cut_info face_info{raw<index_t>(face_nodes_), raw<index_t>(topo_.face_edges), raw<std::uint16_t>(face_pairs_),
                                raw<std::uint8_t>(edge_point_), raw<float>(edge_point_t_), raw<std::uint16_t>(face_state_),
                                raw<std::uint8_t>(face_along_), raw<float>(face_point_bary_),
                                raw<float>(node_rest_), raw<SplitCase>(table_)};
  for_each_index(f_count, face_info);
  // Points that would leave a triangle sharper than the quality angle move onto their nearer node
  // (within the quality snap distance), and the faces whose points may have moved are resolved
  // again. Two passes: a snap can change the split of the face across the edge. `snap` 0 asks for
  // exact cut points: no snapping.
  resize_with_headroom(face_snap_edge_, f_count);
  const double max_cosine = std::cos(options.quality_angle_deg * 3.14159265358979323846 / 180.0);
  const double quality_limit = std::min(options.quality_snap, 0.5);
  for (int pass = 0; pass < 2 && options.quality_angle_deg > 0 && options.snap > 0; ++pass) {
    for_each_index(f_count, request_quality_snaps{raw<index_t>(face_nodes_), raw<index_t>(topo_.face_edges), raw<std::uint16_t>(face_state_),
                                                  raw<float>(edge_point_t_), raw<float>(face_point_bary_), raw<float>(node_rest_),
                                                  raw<SplitCase>(table_), max_cosine, quality_limit, raw<std::int8_t>(face_snap_edge_)});
    for_each_index(e_count, apply_quality_snaps{raw<index_t>(topo_.edge_faces), raw<index_t>(topo_.face_edges), raw<std::int8_t>(face_snap_edge_),
                                                raw<std::uint8_t>(edge_point_), raw<float>(edge_point_t_)});
    for_each_index(f_count, refresh_snapped_faces{face_info, raw<index_t>(topo_.edge_faces), raw<std::int8_t>(face_snap_edge_)});
  }
  resize_with_headroom(edge_cut_, e_count);
  for_each_index(e_count, edge_cut_info{raw<index_t>(face_nodes_), raw<index_t>(topo_.edge_faces), raw<index_t>(topo_.edge_nodes),
                                        raw<index_t>(topo_.face_edges), raw<std::uint8_t>(face_along_), raw<std::uint8_t>(edge_cut_)});
  // Cut points no line uses are dropped, so they split no face.
  for_each_index(e_count, drop_unused_edge_points{raw<index_t>(topo_.edge_faces), raw<index_t>(topo_.face_edges),
                                                  raw<std::uint16_t>(face_state_), raw<std::uint8_t>(edge_cut_),
                                                  raw<std::uint8_t>(edge_point_)});
  for_each_index(f_count, refresh_face_cut_info{face_info});
  clock.mark<System>(CutStage::cut_info);

  // §2.2 new nodes: count per node, edge and face (one per sector), then one exclusive scan over
  // the three, so node copies come first, then edge points', then face points'.
  const SectorMesh sectors = sector_mesh();
  const std::size_t point_count = std::size_t(n_count) + e_count + f_count;
  // The counts are written where their offsets go and scanned in place; later stages take a
  // point's count as the difference of consecutive offsets.
  resize_with_headroom(point_new_offset_, point_count + 1);
  index_t* node_new_count = raw<index_t>(point_new_offset_);
  index_t* edge_new_count = node_new_count + n_count;
  index_t* face_new_count = edge_new_count + e_count;
  for_each_index(n_count, count_node_copies{sectors, node_new_count});
  for_each_index(e_count, count_edge_copies{sectors, raw<std::uint8_t>(edge_point_), edge_new_count});
  for_each_index(f_count, count_face_copies{sectors, face_new_count});
  thrust::fill(policy, point_new_offset_.begin() + point_count, point_new_offset_.end(), 0);
  thrust::exclusive_scan(policy, point_new_offset_.begin(), point_new_offset_.end(), point_new_offset_.begin());

  // §2.3 new faces: count from the split table, exclusive scan.
  resize_with_headroom(face_new_face_offset_, std::size_t(f_count) + 1);  // counts, scanned in place
  for_each_index(f_count, count_new_faces{raw<std::uint16_t>(face_state_), raw<SplitCase>(table_), raw<index_t>(face_new_face_offset_)});
  thrust::fill(policy, face_new_face_offset_.begin() + f_count, face_new_face_offset_.end(), 0);
  thrust::exclusive_scan(policy, face_new_face_offset_.begin(), face_new_face_offset_.end(), face_new_face_offset_.begin());

  const index_t new_node_count = point_new_offset_.back();
  const index_t new_face_count = face_new_face_offset_.back();
  thrust::counting_iterator<index_t> zero(0);
  const CutSummary summary = thrust::transform_reduce(
      policy, zero, zero + std::max(e_count, f_count),
      summarize_cut{raw<std::uint8_t>(edge_point_), raw<std::uint8_t>(edge_cut_), raw<index_t>(point_new_offset_) + n_count + e_count, e_count, f_count}, CutSummary{},
      thrust::plus<CutSummary>());
  stats.edge_points = summary.edge_points;
  stats.cut_edges = summary.cut_edges;
  stats.face_points = summary.face_points;
  clock.mark<System>(CutStage::counts_and_scans);
  if (new_node_count == n_count && new_face_count == f_count) return;  // the cuts split nothing

  // §2.2 write: provenance of every new node, then its state gathered from its sources.
  resize_with_headroom(node_source_, 3 * std::size_t(new_node_count));
  resize_with_headroom(node_source_weight_, 3 * std::size_t(new_node_count));
  const NodeSources sources{raw<index_t>(node_source_), raw<float>(node_source_weight_)};
  const index_t* node_new_offset = raw<index_t>(point_new_offset_);
  const index_t* edge_new_offset = node_new_offset + n_count;
  const index_t* face_new_offset = edge_new_offset + e_count;
  for_each_index(n_count, write_node_sources{node_new_offset, sources});
  for_each_index(e_count, write_edge_sources{raw<index_t>(topo_.edge_nodes), raw<float>(edge_point_t_), edge_new_offset, sources});
  for_each_index(f_count, write_face_sources{raw<index_t>(face_nodes_), raw<float>(face_point_bary_), face_new_offset, sources});
  resize_with_headroom(new_node_pos_, 3 * std::size_t(new_node_count));
  resize_with_headroom(new_node_rest_, 3 * std::size_t(new_node_count));
  resize_with_headroom(new_node_vel_, 3 * std::size_t(new_node_count));
  for (auto [from, to] : {std::pair{&node_pos_, &new_node_pos_}, std::pair{&node_rest_, &new_node_rest_}, std::pair{&node_vel_, &new_node_vel_}})
    for_each_index(new_node_count, interpolate_nodes{raw<index_t>(node_source_), raw<float>(node_source_weight_), raw<float>(*from), raw<float>(*to)});
  clock.mark<System>(CutStage::node_write);

  // §2.3 write: parents and per-corner attributes of the new faces.
  resize_with_headroom(face_parent_, new_face_count);
  resize_with_headroom(new_corner_uv_, has_uv ? 6 * std::size_t(new_face_count) : 0);
  resize_with_headroom(new_corner_normal_, has_normal ? 9 * std::size_t(new_face_count) : 0);
  for_each_index(f_count, write_new_faces{raw<index_t>(face_nodes_), raw<index_t>(topo_.face_edges), raw<std::uint16_t>(face_state_),
                                          raw<SplitCase>(table_), raw<float>(edge_point_t_), raw<float>(face_point_bary_),
                                          raw<index_t>(face_new_face_offset_), has_uv ? raw<float>(corner_uv_) : nullptr,
                                          has_normal ? raw<float>(corner_normal_) : nullptr, raw<index_t>(face_parent_),
                                          has_uv ? raw<float>(new_corner_uv_) : nullptr, has_normal ? raw<float>(new_corner_normal_) : nullptr});
  clock.mark<System>(CutStage::face_write);

  // §2.4 node mapping: every point walks its new triangles and hands out its copies.
  resize_with_headroom(new_face_nodes_, 3 * std::size_t(new_face_count));
  const index_t* face_tri_offset = raw<index_t>(face_new_face_offset_);
  for_each_index(n_count, map_node_copies{sectors, face_tri_offset, node_new_offset, raw<index_t>(new_face_nodes_)});
  for_each_index(e_count, map_edge_copies{sectors, face_tri_offset, edge_new_offset, raw<index_t>(new_face_nodes_)});
  for_each_index(f_count, map_face_copies{sectors, face_tri_offset, face_new_offset, raw<index_t>(new_face_nodes_)});
  clock.mark<System>(CutStage::node_mapping);

  // The new mesh replaces the old; §2.4 adjacency rebuilt from the new faces.
  face_nodes_.swap(new_face_nodes_);
  node_pos_.swap(new_node_pos_);
  node_rest_.swap(new_node_rest_);
  node_vel_.swap(new_node_vel_);
  corner_uv_.swap(new_corner_uv_);
  corner_normal_.swap(new_corner_normal_);
  build_device_topology(topo_, face_nodes_, new_node_count, topo_scratch_, alloc_);
  clock.mark<System>(CutStage::adjacency);

  stats.nodes_after = new_node_count;
  stats.faces_after = new_face_count;
}

template <class System>
std::unique_ptr<Cloth::Engine> make_cloth_engine(const Mesh& mesh) {
  return std::make_unique<ClothEngine<System>>(mesh);
}

#define TEAR_INSTANTIATE(S) template std::unique_ptr<Cloth::Engine> make_cloth_engine<S>(const Mesh&);
TEAR_FOR_EACH_SYSTEM(TEAR_INSTANTIATE)
#undef TEAR_INSTANTIATE

}  // namespace tear::backend
