// tear: the collision pass of the cloth engine, run after the solver's iterations of every substep
// when the cloth collides with itself or with mesh colliders (docs/simulation.md, *Collision*;
// the kernels are kernels/collision.h).
//
// A pass: the vertices (cloth nodes, then the bodies') and the cloth's edges are entered in a grid,
// the faces and edges find their candidate pairs, then `iterations` rounds move each node by the
// average of its contacts' moves. Where a pair still crosses over the substep after two such
// passes, its free nodes go back to where they started the substep (nothing crossed there), and the
// check runs again until nothing crosses. The nodes' velocities gain the moves.
// Only for device code (the .inl files).
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include <thrust/copy.h>
#include <thrust/count.h>
#include <thrust/fill.h>
#include <thrust/functional.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/sort.h>
#include <thrust/transform_reduce.h>

#include "backend/backend.h"
#include "cloth_data/device_cloth.h"
#include "collision.h"
#include "sim/substep_records.h"
#include "tear/simulation_options.h"
#include "topology/device_topology.h"

namespace tear::backend {

template <class System>
class CollisionJob {
  template <class T>
  using vec = vector<System, T>;

 public:
  /// Starts with `options`: the mesh colliders' faces and edges go to the backend once.
  void start(const DeviceCloth<System>& cloth, const SimulationOptions& options) {
    options_ = options;
    bodies_.clear();
    std::vector<index_t> faces, edges;
    index_t first = 0;
    for (const Collider& c : options.colliders) {
      if (c.kind != Collider::Kind::mesh) continue;
      bodies_.push_back(&c);
      for (index_t v : c.mesh->face_nodes) faces.push_back(first + v);
      first += c.mesh->vertex_count();
    }
    body_vertex_count_ = first;
    // The bodies' edges: each undirected edge once, in order.
    std::vector<std::pair<index_t, index_t>> pairs;
    for (std::size_t f = 0; f < faces.size(); f += 3)
      for (int k = 0; k < 3; ++k) {
        const index_t a = faces[f + k], b = faces[f + (k + 1) % 3];
        pairs.emplace_back(std::min(a, b), std::max(a, b));
      }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    for (const auto& e : pairs) edges.push_back(e.first), edges.push_back(e.second);
    assign_from_host(body_faces_, faces);
    assign_from_host(body_edges_, edges);
    body_face_count_ = static_cast<index_t>(faces.size() / 3);
    body_edge_count_ = static_cast<index_t>(edges.size() / 2);
    // Cells twice an edge across; from the cloth's rest bounds, a grid of 2²¹ cells a side centred
    // on the cloth.
    const std::vector<float> rest = to_host<float>(cloth.node_rest);
    const std::vector<index_t> face_nodes = to_host<index_t>(cloth.face_nodes);
    double length = 0;
    std::array<double, 3> lo{0, 0, 0}, hi{0, 0, 0};
    for (std::size_t n = 0; n < rest.size(); n += 3)
      for (int a = 0; a < 3; ++a) {
        lo[a] = n == 0 ? rest[n + a] : std::min<double>(lo[a], rest[n + a]);
        hi[a] = n == 0 ? rest[n + a] : std::max<double>(hi[a], rest[n + a]);
      }
    for (std::size_t f = 0; f < face_nodes.size(); f += 3)
      for (int k = 0; k < 3; ++k) {
        const index_t a = face_nodes[f + k], b = face_nodes[f + (k + 1) % 3];
        double d = 0;
        for (int c = 0; c < 3; ++c) d += std::pow(double(rest[3 * a + c]) - rest[3 * b + c], 2);
        length += std::sqrt(d);
      }
    const double mean = face_nodes.empty() ? 0 : length / static_cast<double>(face_nodes.size());
    // An entry must fit a cell: an edge, grown by the thickness on each side, moving a little.
    const double cell = std::max(2 * mean + 2 * options.collision.thickness, 1e-6);
    grid_.inv_cell = static_cast<float>(1 / cell);
    const double half = 0.5 * kernels::CollisionGrid::side * cell;
    grid_.origin = {static_cast<float>(0.5 * (lo[0] + hi[0]) - half), static_cast<float>(0.5 * (lo[1] + hi[1]) - half),
                    static_cast<float>(0.5 * (lo[2] + hi[2]) - half)};
  }

  /// Before a substep: where the nodes start it.
  void begin(const DeviceCloth<System>& cloth) {
    resize_for_overwrite(x0_, cloth.node_pos.size());
    thrust::copy(Traits<System>::policy(), cloth.node_pos.begin(), cloth.node_pos.end(), x0_.begin());
  }

  /// After substep `s` (0-based) of frame `frame`: the contacts resolved in `cloth`'s state.
  void resolve(DeviceCloth<System>& cloth, int frame, int s) {
    const auto policy = Traits<System>::policy();
    const index_t nodes = cloth.node_count();
    resize_for_overwrite(solved_, cloth.node_pos.size());
    thrust::copy(policy, cloth.node_pos.begin(), cloth.node_pos.end(), solved_.begin());
    upload_bodies(frame, s);
    std::vector<kernels::PdPinMotion> pins;
    std::vector<kernels::PdCollider> colliders;
    substep_records(options_, frame, s, pins, colliders);
    assign_from_host(colliders_, colliders);
    const CollisionOptions& o = options_.collision;
    const thrust::counting_iterator<index_t> zero(0);
    index_t crossing = 0;
    static const bool debug = std::getenv("TEAR_DEBUG_COLLISION") != nullptr;
    for (int pass = 0; pass < 2; ++pass) {
      const auto t0 = std::chrono::steady_clock::now();
      const index_t pairs = find_pairs(cloth);
      if (debug)
        std::fprintf(stderr, "collision: pass %d, %d pairs, found in %.3f ms\n", pass, pairs,
                     std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      if (pairs == 0) break;
      const kernels::CollisionVertices x = vertices(cloth);
      build_csr_by_counting<System>(policy, kernels::ContactSlots{raw<kernels::CollisionPair>(pairs_), x}, 4 * pairs,
                                    nodes, -1, tally_, slot_offset_, slots_);
      resize_for_overwrite(moves_, 4 * static_cast<std::size_t>(pairs));
      const kernels::CollisionGeometry geometry{x, static_cast<float>(o.thickness)};
      for (int r = 0; r < o.iterations; ++r) {
        for_each_index<System>(pairs,
                               kernels::resolve_contacts{geometry, raw<kernels::CollisionPair>(pairs_),
                                                         static_cast<float>(o.friction), raw<kernels::Vec3f>(moves_)});
        for_each_index<System>(
            nodes, kernels::apply_contact_moves{raw<index_t>(slot_offset_), raw<index_t>(slots_),
                                                raw<kernels::Vec3f>(moves_), raw<kernels::PdCollider>(colliders_),
                                                static_cast<index_t>(colliders.size()), raw<float>(cloth.node_pos)});
      }
      crossing = thrust::transform_reduce(policy, zero, zero + pairs,
                                          kernels::crossing_of{geometry, raw<kernels::CollisionPair>(pairs_)},
                                          index_t(0), thrust::plus<index_t>());
      if (debug) std::fprintf(stderr, "collision: pass %d, %d crossing\n", pass, crossing);
      if (crossing == 0) break;
    }
    // What still crosses goes back to where it started, until nothing does.
    for (int round = 0; crossing > 0 && round < max_hold_rounds; ++round) {
      const index_t pairs = find_pairs(cloth);
      const kernels::CollisionVertices x = vertices(cloth);
      const kernels::CollisionGeometry geometry{x, static_cast<float>(o.thickness)};
      resize_for_overwrite(held_, static_cast<std::size_t>(nodes));
      thrust::fill(policy, held_.begin(), held_.end(), std::uint8_t(0));
      for_each_index<System>(
          pairs, kernels::hold_crossing{geometry, raw<kernels::CollisionPair>(pairs_), raw<std::uint8_t>(held_)});
      crossing = static_cast<index_t>(thrust::count(policy, held_.begin(), held_.end(), std::uint8_t(1)));
      held_nodes_ += crossing;
      if (debug) std::fprintf(stderr, "collision: hold round %d, %d nodes held\n", round, crossing);
      for_each_index<System>(
          nodes, kernels::hold_nodes{raw<std::uint8_t>(held_), raw<float>(x0_), raw<float>(cloth.node_pos)});
    }
    const double h = options_.step_seconds();
    for_each_index<System>(nodes,
                           kernels::add_contact_velocity{raw<float>(solved_), raw<float>(cloth.node_pos),
                                                         static_cast<float>(std::pow(1.0 - options_.damping, h) / h),
                                                         raw<float>(cloth.node_vel)});
  }

  /// Nodes sent back to the start of their substep since the job started (the last resort).
  std::int64_t held_nodes() const { return held_nodes_; }

  /// Bytes the pass's arrays hold.
  std::size_t bytes() const {
    std::size_t total = 0;
    const auto add = [&](const auto& v) {
      total += v.capacity() * sizeof(typename std::decay_t<decltype(v)>::value_type);
    };
    add(body_faces_), add(body_edges_), add(body_x0_), add(body_x1_), add(x0_), add(solved_), add(colliders_);
    add(pair_count_), add(entry_count_), add(vertex_keys_), add(edge_keys_), add(vertex_items_), add(edge_items_), add(pairs_);
    add(tally_), add(slot_offset_), add(slots_), add(moves_), add(held_);
    return total;
  }

 private:
  static constexpr int max_hold_rounds = 8;
  /// Cloth pairs closer than this (times the thickness) in the rest shape take no part: the two
  /// sides of a tear, which lie on each other there.
  static constexpr float rest_gap_fraction = 0.01f;

  kernels::CollisionVertices vertices(const DeviceCloth<System>& cloth) const {
    return {raw<float>(x0_),
            raw<float>(cloth.node_pos),
            raw<float>(cloth.node_rest),
            raw<std::uint8_t>(cloth.node_pinned),
            body_vertex_count_ ? raw<float>(body_x0_) : nullptr,
            body_vertex_count_ ? raw<float>(body_x1_) : nullptr,
            cloth.node_count(),
            cloth.node_count() + body_vertex_count_};
  }

  /// The bodies where they are at the substep's start and end.
  void upload_bodies(int frame, int s) {
    if (bodies_.empty()) return;
    const double start = substep_end_time(frame, s - 1, options_.substeps);
    const double end = substep_end_time(frame, s, options_.substeps);
    for (auto [time, host, device] :
         {std::make_tuple(start, &body_host_x0_, &body_x0_), std::make_tuple(end, &body_host_x1_, &body_x1_)}) {
      host->clear();
      for (const Collider* c : bodies_) {
        collider_positions(*c, time, body_one_);
        host->insert(host->end(), body_one_.begin(), body_one_.end());
      }
      assign_from_host(*device, *host);
    }
  }

  /// Runs `f` over [0, n) counting what each index will write (into `counts`), scans the counts
  /// into offsets and points `f` at them for its second run, which writes; returns the total.
  template <class F>
  index_t count_then_offsets(F& f, index_t n, vec<index_t>& counts) {
    resize_for_overwrite(counts, static_cast<std::size_t>(n) + 1);
    f.count = raw<index_t>(counts);
    f.offset = nullptr;
    for_each_index<System>(n, f);
    counts[n] = 0;
    exclusive_sum<System>(Traits<System>::policy(), raw<index_t>(counts), raw<index_t>(counts), n + 1);
    f.offset = raw<index_t>(counts);
    return counts[n];
  }

  /// Enters `count` items (vertices, or cloth edges) in the grid, each in the cells it meets:
  /// `keys`/`items` sorted by cell.
  kernels::GridEntries enter(const kernels::EnterItems& base, index_t count, vec<std::uint64_t>& keys,
                             vec<index_t>& items) {
    const auto policy = Traits<System>::policy();
    kernels::EnterItems e = base;
    const index_t total = count_then_offsets(e, count, entry_count_);
    resize_for_overwrite(keys, static_cast<std::size_t>(total));
    resize_for_overwrite(items, static_cast<std::size_t>(total));
    e.keys = raw<std::uint64_t>(keys);
    e.items = raw<index_t>(items);
    for_each_index<System>(count, e);
    // Stable: within a cell the items stay in their order.
    thrust::stable_sort_by_key(policy, keys.begin(), keys.begin() + total, items.begin());
    return {raw<std::uint64_t>(keys), raw<index_t>(items), total};
  }

  /// The candidate pairs of the vertices' motion now, into `pairs_`; returns how many.
  index_t find_pairs(const DeviceCloth<System>& cloth) {
    const kernels::CollisionVertices x = vertices(cloth);
    const float thickness = static_cast<float>(options_.collision.thickness);
    const kernels::CollisionFaces faces{raw<index_t>(cloth.face_nodes), raw<index_t>(body_faces_), cloth.face_count(),
                                        cloth.face_count() + body_face_count_, cloth.node_count()};
    const kernels::CollisionEdges edges{raw<index_t>(cloth.topo.edge_nodes), raw<index_t>(body_edges_),
                                        cloth.topo.edge_count, cloth.topo.edge_count + body_edge_count_,
                                        cloth.node_count()};
    kernels::EnterItems enter_vertices{x, edges, grid_, thickness, false, nullptr, nullptr, nullptr, nullptr};
    const kernels::GridEntries vertex_entries = enter(enter_vertices, x.vertex_count, vertex_keys_, vertex_items_);
    kernels::EnterItems enter_edges = enter_vertices;
    enter_edges.of_edges = true;
    // Cloth edges are entered for the cloth's own pairs and for the bodies' edges.
    const bool edge_pairs = options_.collision.self || body_edge_count_ > 0;
    const kernels::GridEntries edge_entries = edge_pairs
                                                  ? enter(enter_edges, edges.cloth_count, edge_keys_, edge_items_)
                                                  : kernels::GridEntries{nullptr, nullptr, 0};
    const index_t queries = faces.count + (edge_pairs ? edges.count : 0);
    kernels::find_pairs find{x,
                             faces,
                             edges,
                             grid_,
                             vertex_entries,
                             edge_entries,
                             thickness,
                             rest_gap_fraction * thickness,
                             options_.collision.self,
                             nullptr,
                             nullptr,
                             nullptr};
    const index_t total = count_then_offsets(find, queries, pair_count_);
    resize_for_overwrite(pairs_, static_cast<std::size_t>(total));
    find.pairs = raw<kernels::CollisionPair>(pairs_);
    for_each_index<System>(queries, find);
    return total;
  }

  SimulationOptions options_;
  std::vector<const Collider*> bodies_;  // the mesh colliders, in the script's order
  index_t body_vertex_count_ = 0, body_face_count_ = 0, body_edge_count_ = 0;
  vec<index_t> body_faces_, body_edges_;
  std::vector<float> body_host_x0_, body_host_x1_, body_one_;  // kept: filled every substep
  vec<float> body_x0_, body_x1_;
  kernels::CollisionGrid grid_{};
  vec<float> x0_, solved_;
  vec<kernels::PdCollider> colliders_;  // the plane and sphere colliders at the substep's end
  vec<index_t> pair_count_, entry_count_;
  vec<std::uint64_t> vertex_keys_, edge_keys_;
  vec<index_t> vertex_items_, edge_items_;
  vec<kernels::CollisionPair> pairs_;
  vec<index_t> tally_, slot_offset_, slots_;
  vec<kernels::Vec3f> moves_;
  vec<std::uint8_t> held_;
  std::int64_t held_nodes_ = 0;
};

}  // namespace tear::backend
