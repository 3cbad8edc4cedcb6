// tear: the GPU remesher (paper §2) on either backend, in two halves with one seam between them:
//
//   cut_info_from_paths  §2.1  where scripted polylines, blades and planes cross the mesh: cut
//                              points on edges and in faces, 6-bit face / 2-bit edge cut info
//   apply_cut_info       §2.2–2.4  counts → scans → writes of new nodes and faces → node mapping →
//                              carried attributes → topology
//
// The second half reads only `CutInfo`, so any source of cut info (scripted paths, cracks) feeds it.
// Both sources write the same crossings (per-face half-edge hits and the pairs of places a line
// joins) and share the rest of §2.1: snapping, face and edge cut info.
// Each stage is a count, a scan or a write over one kind of element. Scratch arrays live with the
// remesher and only grow, so once they reach capacity a cut allocates nothing for its own arrays.
// Only for device code (the .inl files).
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <thrust/copy.h>
#include <thrust/count.h>
#include <thrust/fill.h>
#include <thrust/for_each.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/scan.h>
#include <thrust/sort.h>

#include "backend/backend.h"
#include "carry_attributes.h"
#include "cloth_data/device_cloth.h"
#include "count_new_nodes.h"
#include "cut_info.h"
#include "intersect_cuts.h"
#include "map_nodes.h"
#include "split_table.h"
#include "tear/cloth.h"
#include "tear/error.h"
#include "tear/simulation_options.h"
#include "topology/device_topology.h"
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

/// The seam between the halves: what a cut does to each edge and face (paper §2.1).
template <class System>
struct CutInfo {
  template <class T>
  using vec = vector<System, T>;
  vec<std::uint8_t> edge_point;    ///< [edge_count] edge_point_inside or not (kernels/cut_info.h)
  vec<float> edge_point_t;         ///< [edge_count] where along the edge, from its lower node
  vec<std::uint8_t> edge_cut;      ///< [edge_count] 2-bit edge cut info: a cut line along each half
  vec<std::uint16_t> face_state;   ///< [face_count] split code: cut state and split variant
  vec<float> face_point_bary;      ///< [face_count * 3] face point, where the face has one
};

template <class System>
class Remesher {
  template <class T>
  using vec = vector<System, T>;

 public:
  Remesher() : table_(kernels::split_table(), kernels::split_table() + kernels::split_table_size) {}

  /// §2.1: cut info of `cuts` on `cloth`. Returns false when no cut path is usable (nothing to do).
  bool cut_info_from_paths(const DeviceCloth<System>& cloth, const std::vector<CutLine>& cuts,
                           const CutOptions& options, StageClock& clock);

  /// §2.2–2.4: applies the cut info to `cloth` in place. Returns false when it splits nothing (the
  /// cloth is left as it was). With `summary` false, `stats`' counts of edge points, cut edges and
  /// face points are left alone (a reduction and a read-back fewer: tearing has no use for them).
  bool apply_cut_info(DeviceCloth<System>& cloth, const CutOptions& options, CutStats& stats, StageClock& clock,
                      bool summary = true);

  CutProvenance provenance() const {
    CutProvenance p;
    p.node_source = to_host<index_t>(node_source_);
    p.node_source_weight = to_host<float>(node_source_weight_);
    p.face_parent = to_host<index_t>(new_face_parent_);
    return p;
  }

  TemporaryAllocator<System>& allocator() { return alloc_; }
  TopologyScratch<System>& topology_scratch() { return topo_scratch_; }

 private:
  template <class F>
  void for_each_index(index_t count, F f) {
    backend::for_each_index<System>(count, f);
  }
  void upload_cuts(const std::vector<CutLine>& cuts);
  /// §2.1 after the crossings: snapped edge points, face and edge cut info.
  void resolve_cut_info(const DeviceCloth<System>& cloth, const CutOptions& options, StageClock& clock);
  kernels::SectorMesh sector_mesh(const DeviceCloth<System>& cloth) const;
  /// With `CutOptions::check_writes`: fills `v` with a value no writer writes, before its writer.
  template <class T>
  void fill_unwritten(const CutOptions& options, vec<T>& v, std::size_t size, T unwritten);
  /// With `CutOptions::check_writes`: throws when a writer left a slot of its scanned count unwritten.
  template <class T>
  void check_written(const CutOptions& options, const vec<T>& v, std::size_t size, T unwritten, const char* stage);

  // §2.2–2.4 stages.
  /// With `stats`, also its counts of edges with a cut point, edges with a cut line along them and
  /// faces with a face point, read back with the totals.
  void count_and_scan(const DeviceCloth<System>& cloth, CutStats* stats);
  void write_new_nodes(DeviceCloth<System>& cloth, const CutOptions& options);
  void write_new_faces(DeviceCloth<System>& cloth, const CutOptions& options);
  void map_nodes(const DeviceCloth<System>& cloth, const CutOptions& options);
  void carry_attributes(DeviceCloth<System>& cloth);

  TopologyScratch<System> topo_scratch_;
  DeviceTopology<System> next_topo_;  // a cut's patched topology, swapped in (then the one before it)
  TemporaryAllocator<System> alloc_;  // Thrust's sort and scan buffers, reused cut after cut
  ReadBack<System> read_back_;        // a cut's totals (and a tear's crack lengths), read in one wait
  Upload<System> upload_;             // a cut's paths, sent without waiting
  vec<kernels::SplitCase> table_;

  // The frame's cuts.
  vec<kernels::CutPath> cut_paths_;
  vec<double> cut_point_x_, cut_point_y_;

  // §2.1 working arrays, and the cut info it leaves.
  vec<double> half_hit_sum_;
  vec<index_t> half_hit_count_;
  vec<std::uint16_t> face_pairs_;
  vec<std::uint8_t> face_along_;
  vec<std::int8_t> face_snap_edge_;
  CutInfo<System> info_;

  // §2.2, §2.3 counts and offsets: the nodes' extra copies, then edge points', then face points',
  // in one array; new faces per face.
  vec<index_t> point_new_offset_, face_new_face_offset_;
  vec<index_t> summary_;  // [3] edges with a cut point, cut edges, faces with a face point
  index_t new_node_count_ = 0, new_face_count_ = 0;

  // The mesh being written (provenance of the last cut included), swapped in at the end.
  vec<index_t> new_face_nodes_, new_face_parent_, node_source_;
  vec<float> node_source_weight_;
  std::array<vec<float>, kernels::NodeAttributes::value_capacity> new_node_values_;
  std::array<vec<std::uint8_t>, kernels::NodeAttributes::flag_capacity> new_node_flags_;
  std::array<vec<index_t>, kernels::FaceAttributes::capacity> new_face_index_values_;
  std::array<vec<float>, kernels::FaceAttributes::capacity> new_face_float_values_;
  /// The new face values of the table's face attributes of type T, by slot.
  template <class T>
  std::array<vec<T>, kernels::FaceAttributes::capacity>& new_face_values() {
    if constexpr (std::is_same<T, float>::value)
      return new_face_float_values_;
    else
      return new_face_index_values_;
  }
  std::array<vec<float>, 3> new_corner_values_;
};

template <class System>
void Remesher<System>::upload_cuts(const std::vector<CutLine>& cuts) {
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
    if (p.point_count < 2) continue;
    kernels::set_path_box(p, xs.data(), ys.data());
    paths.push_back(p);
  }
  upload_.begin(Upload<System>::template bytes_for<kernels::CutPath>(paths.size()) +
                2 * Upload<System>::template bytes_for<double>(xs.size()));
  upload_.send(cut_paths_, paths);
  upload_.send(cut_point_x_, xs);
  upload_.send(cut_point_y_, ys);
}

template <class System>
kernels::SectorMesh Remesher<System>::sector_mesh(const DeviceCloth<System>& cloth) const {
  const auto& topo = cloth.topo;
  return {raw<index_t>(cloth.face_nodes),      raw<index_t>(topo.face_edges), raw<index_t>(topo.edge_nodes),
          raw<index_t>(topo.edge_faces),       raw<index_t>(topo.node_face_offset), raw<index_t>(topo.node_faces),
          raw<std::uint16_t>(info_.face_state), raw<std::uint8_t>(info_.edge_cut), raw<kernels::SplitCase>(table_)};
}

template <class System>
template <class T>
void Remesher<System>::fill_unwritten(const CutOptions& options, vec<T>& v, std::size_t size, T unwritten) {
  if (options.check_writes) thrust::fill(Traits<System>::policy(), v.begin(), v.begin() + size, unwritten);
}

template <class System>
template <class T>
void Remesher<System>::check_written(const CutOptions& options, const vec<T>& v, std::size_t size, T unwritten,
                                     const char* stage) {
  if (!options.check_writes) return;
  const auto left = thrust::count(Traits<System>::policy(), v.begin(), v.begin() + size, unwritten);
  if (left != 0)
    throw runtime_error(std::string("remesher: ") + stage + " left " + std::to_string(left) + " of its " +
                        std::to_string(size) + " slots unwritten");
}

template <class System>
bool Remesher<System>::cut_info_from_paths(const DeviceCloth<System>& cloth, const std::vector<CutLine>& cuts,
                                           const CutOptions& options, StageClock& clock) {
  using namespace kernels;
  const auto& topo = cloth.topo;
  const index_t f_count = topo.face_count;
  read_back_.clear();
  upload_cuts(cuts);
  if (cut_paths_.empty() || f_count == 0) return false;
  const bool has_uv = !cloth.corner_uv.empty();

  // Every cut against every face, one averaged and snapped point per edge, then the 6-bit face cut
  // info (with the face point where lines cross) and the 2-bit edge cut info.
  resize_for_overwrite(half_hit_sum_, 3 * std::size_t(f_count));
  resize_for_overwrite(half_hit_count_, 3 * std::size_t(f_count));
  resize_for_overwrite(face_pairs_, f_count);
  for_each_index(f_count, intersect_cuts{raw<index_t>(cloth.face_nodes), has_uv ? raw<float>(cloth.corner_uv) : nullptr,
                                         raw<float>(cloth.node_rest), raw<float>(cloth.node_pos), raw<CutPath>(cut_paths_),
                                         static_cast<index_t>(cut_paths_.size()), raw<double>(cut_point_x_),
                                         raw<double>(cut_point_y_), raw<double>(half_hit_sum_),
                                         raw<index_t>(half_hit_count_), raw<std::uint16_t>(face_pairs_)});
  clock.mark<System>(CutStage::intersection);
  resolve_cut_info(cloth, options, clock);
  return true;
}

template <class System>
void Remesher<System>::resolve_cut_info(const DeviceCloth<System>& cloth, const CutOptions& options,
                                        StageClock& clock) {
  using namespace kernels;
  const auto& topo = cloth.topo;
  const index_t f_count = topo.face_count, e_count = topo.edge_count;
  resize_for_overwrite(info_.edge_point, e_count);
  resize_for_overwrite(info_.edge_point_t, e_count);
  for_each_index(e_count, snap_edge_points{raw<index_t>(topo.edge_faces), raw<index_t>(topo.face_edges),
                                           raw<double>(half_hit_sum_), raw<index_t>(half_hit_count_), options.snap,
                                           raw<float>(info_.edge_point_t), raw<std::uint8_t>(info_.edge_point)});
  resize_for_overwrite(info_.face_state, f_count);
  resize_for_overwrite(face_along_, f_count);
  resize_for_overwrite(info_.face_point_bary, 3 * std::size_t(f_count));
  const face_cut_info face_info{raw<index_t>(cloth.face_nodes),       raw<index_t>(topo.face_edges),
                                raw<std::uint16_t>(face_pairs_),      raw<std::uint8_t>(info_.edge_point),
                                raw<float>(info_.edge_point_t),       raw<std::uint16_t>(info_.face_state),
                                raw<std::uint8_t>(face_along_),       raw<float>(info_.face_point_bary),
                                raw<float>(cloth.node_rest),          raw<SplitCase>(table_)};
  for_each_index(f_count, face_info);
  // Points that would leave a triangle sharper than the quality angle move onto their nearer node
  // (within the quality snap distance), and the faces whose points may have moved are resolved
  // again. Two passes: a snap can change the split of the face across the edge. `snap` 0 asks for
  // exact cut points: no snapping.
  resize_for_overwrite(face_snap_edge_, f_count);
  const double max_cosine = std::cos(options.quality_angle_deg * 3.14159265358979323846 / 180.0);
  const double quality_limit = std::min(options.quality_snap, 0.5);
  for (int pass = 0; pass < 2 && options.quality_angle_deg > 0 && options.snap > 0; ++pass) {
    for_each_index(f_count, request_quality_snaps{raw<index_t>(cloth.face_nodes), raw<index_t>(topo.face_edges),
                                                  raw<std::uint16_t>(info_.face_state), raw<float>(info_.edge_point_t),
                                                  raw<float>(info_.face_point_bary), raw<float>(cloth.node_rest),
                                                  raw<SplitCase>(table_), max_cosine, quality_limit,
                                                  raw<std::int8_t>(face_snap_edge_)});
    for_each_index(e_count, apply_quality_snaps{raw<index_t>(topo.edge_faces), raw<index_t>(topo.face_edges),
                                                raw<std::int8_t>(face_snap_edge_), raw<std::uint8_t>(info_.edge_point),
                                                raw<float>(info_.edge_point_t)});
    for_each_index(f_count, refresh_snapped_faces{face_info, raw<index_t>(topo.edge_faces), raw<std::int8_t>(face_snap_edge_)});
  }
  resize_for_overwrite(info_.edge_cut, e_count);
  for_each_index(e_count, edge_cut_info{raw<index_t>(cloth.face_nodes), raw<index_t>(topo.edge_faces),
                                        raw<index_t>(topo.edge_nodes), raw<index_t>(topo.face_edges),
                                        raw<std::uint8_t>(face_along_), raw<std::uint8_t>(info_.edge_cut)});
  // Cut points no line uses are dropped, so they split no face.
  for_each_index(e_count, drop_unused_edge_points{raw<index_t>(topo.edge_faces), raw<index_t>(topo.face_edges),
                                                  raw<std::uint16_t>(info_.face_state), raw<std::uint8_t>(info_.edge_cut),
                                                  raw<std::uint8_t>(info_.edge_point)});
  for_each_index(f_count, refresh_face_cut_info{face_info});
  clock.mark<System>(CutStage::cut_info);
}

template <class System>
bool Remesher<System>::apply_cut_info(DeviceCloth<System>& cloth, const CutOptions& options, CutStats& stats,
                                      StageClock& clock, bool summary) {
  count_and_scan(cloth, summary ? &stats : nullptr);  // §2.2 and §2.3 counts and scans
  clock.mark<System>(CutStage::counts_and_scans);
  const index_t n_count = cloth.node_count(), f_count = cloth.face_count();
  if (new_node_count_ == n_count && new_face_count_ == f_count) return false;  // the cuts split nothing
  write_new_nodes(cloth, options);  // §2.2 write: provenance of every new node
  clock.mark<System>(CutStage::node_write);
  write_new_faces(cloth, options);  // §2.3 write: parents and corner attributes of the new faces
  clock.mark<System>(CutStage::face_write);
  map_nodes(cloth, options);  // §2.4 node mapping: every point hands out its copies
  clock.mark<System>(CutStage::node_mapping);
  carry_attributes(cloth);  // state, pins and origins onto the new nodes and faces; swapped in
  // §2.4 adjacency of the new faces: the old one patched where the cut changed faces (the old face
  // nodes are in `new_face_nodes_` since the swap).
  patch_device_topology(next_topo_, cloth.topo, new_face_nodes_, face_new_face_offset_, cloth.face_nodes,
                        new_node_count_, topo_scratch_, alloc_);
  cloth.topo.swap(next_topo_);
  clock.mark<System>(CutStage::adjacency);
  stats.nodes_after = new_node_count_;
  stats.faces_after = new_face_count_;
  return true;
}

template <class System>
void Remesher<System>::count_and_scan(const DeviceCloth<System>& cloth, CutStats* stats) {
  using namespace kernels;
  const auto policy = Traits<System>::policy(alloc_);
  const index_t n_count = cloth.node_count(), f_count = cloth.face_count(), e_count = cloth.topo.edge_count;
  // New nodes: the extra copies of each node, one copy per sector of each edge and face point,
  // then one exclusive scan over the three. The counts are written where their offsets go and
  // scanned in place; later stages take a count as the difference of consecutive offsets.
  const SectorMesh sectors = sector_mesh(cloth);
  const std::size_t point_count = std::size_t(n_count) + e_count + f_count;
  resize_for_overwrite(point_new_offset_, point_count + 1);
  index_t* node_extra_count = raw<index_t>(point_new_offset_);
  index_t* edge_new_count = node_extra_count + n_count;
  index_t* face_new_count = edge_new_count + e_count;
  // New faces per face: counts from the split table (paper §2.3), in the same launch as the copies.
  resize_for_overwrite(face_new_face_offset_, std::size_t(f_count) + 1);
  const count_new_faces count_faces{raw<std::uint16_t>(info_.face_state), raw<SplitCase>(table_),
                                    raw<index_t>(face_new_face_offset_)};
  for_each_index(n_count + e_count + f_count + 1,
                 make_over_three_ranges(count_node_copies{sectors, node_extra_count},
                                        count_edge_copies{sectors, raw<std::uint8_t>(info_.edge_point), edge_new_count},
                                        count_face_copies_and_triangles{count_face_copies{sectors, face_new_count},
                                                                        count_faces, f_count},
                                        n_count, e_count));
  exclusive_sum<System>(policy, raw<index_t>(point_new_offset_), raw<index_t>(point_new_offset_),
                        static_cast<index_t>(point_count + 1));
  exclusive_sum<System>(policy, raw<index_t>(face_new_face_offset_), raw<index_t>(face_new_face_offset_), f_count + 1);

  // The summary's counts (integer sums: the same whatever the order), queued with the totals.
  std::size_t summary_at = 0;
  if (stats) {
    resize_for_overwrite(summary_, 3);
    thrust::fill(policy, summary_.begin(), summary_.end(), 0);
    for_each_index(std::max(e_count, f_count),
                   summarize_cut{raw<std::uint8_t>(info_.edge_point), raw<std::uint8_t>(info_.edge_cut),
                                 raw<index_t>(point_new_offset_) + n_count + e_count, e_count, f_count,
                                 raw<index_t>(summary_)});
    summary_at = read_back_.queue(raw<index_t>(summary_), 3);
  }
  // The totals in one wait.
  const std::size_t new_points_at = read_back_.queue(raw<index_t>(point_new_offset_) + point_count, 1);
  const std::size_t new_faces_at = read_back_.queue(raw<index_t>(face_new_face_offset_) + f_count, 1);
  read_back_.wait();
  new_node_count_ = n_count + *read_back_.template at<index_t>(new_points_at);
  new_face_count_ = *read_back_.template at<index_t>(new_faces_at);
  if (stats) {
    const index_t* counts = read_back_.template at<index_t>(summary_at);
    stats->edge_points = counts[0];
    stats->cut_edges = counts[1];
    stats->face_points = counts[2];
  }
}

template <class System>
void Remesher<System>::write_new_nodes(DeviceCloth<System>& cloth, const CutOptions& options) {
  using namespace kernels;
  const index_t n_count = cloth.node_count(), f_count = cloth.face_count(), e_count = cloth.topo.edge_count;
  const std::size_t slots = 3 * std::size_t(new_node_count_);
  resize_for_overwrite(node_source_, slots);
  resize_for_overwrite(node_source_weight_, slots);
  fill_unwritten(options, node_source_, slots, index_t(-2));
  const NodeSources sources{raw<index_t>(node_source_), raw<float>(node_source_weight_)};
  const index_t* node_extra_offset = raw<index_t>(point_new_offset_);
  const index_t* edge_new_offset = node_extra_offset + n_count;
  const index_t* face_new_offset = edge_new_offset + e_count;
  for_each_index(n_count + e_count + f_count,
                 make_over_three_ranges(write_node_sources{node_extra_offset, n_count, sources},
                                        write_edge_sources{raw<index_t>(cloth.topo.edge_nodes),
                                                           raw<float>(info_.edge_point_t), edge_new_offset, n_count,
                                                           sources},
                                        write_face_sources{raw<index_t>(cloth.face_nodes),
                                                           raw<float>(info_.face_point_bary), face_new_offset, n_count,
                                                           sources},
                                        n_count, e_count));
  check_written(options, node_source_, slots, index_t(-2), "the node write");
}

template <class System>
void Remesher<System>::write_new_faces(DeviceCloth<System>& cloth, const CutOptions& options) {
  using namespace kernels;
  const index_t f_count = cloth.face_count();
  resize_for_overwrite(new_face_parent_, new_face_count_);
  fill_unwritten(options, new_face_parent_, new_face_count_, index_t(-2));
  // The table's corner values (interpolated in the parent face) and face values (the parent's).
  CornerAttributes corners;
  FaceAttributes face_values;
  int corner_slot = 0, face_slot = 0;
  cloth.for_each_attribute([&](const auto& a, auto& values) {
    using T = typename std::decay_t<decltype(values)>::value_type;
    if constexpr (std::is_same<T, float>::value) {
      if (a.element == Element::corner && a.carry != Carry::written) {
        auto& next = new_corner_values_[corner_slot++];
        resize_for_overwrite(next, values.empty() ? 0 : 3 * std::size_t(a.comps) * new_face_count_);
        if (!values.empty())
          corners.at[corners.count++] = {raw<float>(values), raw<float>(next), a.comps, a.carry == Carry::unit};
      }
    }
    if constexpr (sizeof(T) == 4) {
      if (a.element != Element::face || a.carry != Carry::parent) return;
      auto& next = new_face_values<T>()[face_slot++];
      resize_for_overwrite(next, values.empty() ? 0 : std::size_t(new_face_count_));
      if (!values.empty())
        face_values.at[face_values.count++] = {reinterpret_cast<const std::uint32_t*>(raw<T>(values)),
                                               reinterpret_cast<std::uint32_t*>(raw<T>(next))};
    }
  });
  if (corner_slot > CornerAttributes::capacity || face_slot > FaceAttributes::capacity)
    throw runtime_error("remesher: the cloth's table has more carried attributes than the carry holds");
  for_each_index(f_count, kernels::write_new_faces{raw<index_t>(cloth.face_nodes), raw<index_t>(cloth.topo.face_edges),
                                                   raw<std::uint16_t>(info_.face_state), raw<SplitCase>(table_),
                                                   raw<float>(info_.edge_point_t), raw<float>(info_.face_point_bary),
                                                   raw<index_t>(face_new_face_offset_), corners, face_values,
                                                   raw<index_t>(new_face_parent_)});
  check_written(options, new_face_parent_, new_face_count_, index_t(-2), "the face write");
}

template <class System>
void Remesher<System>::map_nodes(const DeviceCloth<System>& cloth, const CutOptions& options) {
  using namespace kernels;
  const index_t n_count = cloth.node_count(), f_count = cloth.face_count(), e_count = cloth.topo.edge_count;
  const std::size_t corners = 3 * std::size_t(new_face_count_);
  resize_for_overwrite(new_face_nodes_, corners);
  fill_unwritten(options, new_face_nodes_, corners, index_t(-2));
  const SectorMesh sectors = sector_mesh(cloth);
  const index_t* face_tri_offset = raw<index_t>(face_new_face_offset_);
  const index_t* node_extra_offset = raw<index_t>(point_new_offset_);
  const index_t* edge_new_offset = node_extra_offset + n_count;
  const index_t* face_new_offset = edge_new_offset + e_count;
  index_t* corners_out = raw<index_t>(new_face_nodes_);
  for_each_index(n_count + e_count + f_count,
                 make_over_three_ranges(map_node_copies{sectors, face_tri_offset, node_extra_offset, n_count, corners_out},
                                        map_edge_copies{sectors, face_tri_offset, edge_new_offset, n_count, corners_out},
                                        map_face_copies{sectors, face_tri_offset, face_new_offset, n_count, corners_out},
                                        n_count, e_count));
  check_written(options, new_face_nodes_, corners, index_t(-2), "the node mapping");
}

template <class System>
void Remesher<System>::carry_attributes(DeviceCloth<System>& cloth) {
  using namespace kernels;
  // Node values and flags in one pass over the new nodes; face values and corner values were
  // written with the new faces. Then every new array is swapped in.
  NodeAttributes nodes;
  int value_slot = 0, flag_slot = 0;
  cloth.for_each_attribute([&](const auto& a, auto& values) {
    using T = typename std::decay_t<decltype(values)>::value_type;
    if (a.element != Element::node) return;
    if constexpr (std::is_same<T, float>::value) {
      if (a.carry != Carry::interpolate) return;
      auto& next = new_node_values_[value_slot++];
      resize_for_overwrite(next, std::size_t(a.comps) * new_node_count_);
      nodes.values[nodes.value_count++] = {raw<float>(values), raw<float>(next), a.comps};
    } else if constexpr (std::is_same<T, std::uint8_t>::value) {
      if (a.carry != Carry::copy) return;
      auto& next = new_node_flags_[flag_slot++];
      resize_for_overwrite(next, new_node_count_);
      nodes.flags[nodes.flag_count++] = {raw<std::uint8_t>(values), raw<std::uint8_t>(next)};
    }
  });
  for_each_index(new_node_count_, carry_node_attributes{raw<index_t>(node_source_), raw<float>(node_source_weight_), nodes});
  // Every carried array swapped for its new one, in the table's order (the slots were handed out in it).
  value_slot = flag_slot = 0;
  int face_slot = 0, corner_slot = 0;
  cloth.for_each_attribute([&](const auto& a, auto& values) {
    using T = typename std::decay_t<decltype(values)>::value_type;
    if constexpr (std::is_same<T, float>::value) {
      if (a.element == Element::node && a.carry == Carry::interpolate) values.swap(new_node_values_[value_slot++]);
      if (a.element == Element::corner && a.carry != Carry::written) values.swap(new_corner_values_[corner_slot++]);
    }
    if constexpr (std::is_same<T, std::uint8_t>::value)
      if (a.element == Element::node && a.carry == Carry::copy) values.swap(new_node_flags_[flag_slot++]);
    if constexpr (sizeof(T) == 4)
      if (a.element == Element::face && a.carry == Carry::parent) values.swap(new_face_values<T>()[face_slot++]);
  });
  cloth.face_nodes.swap(new_face_nodes_);
}

}  // namespace tear::backend
