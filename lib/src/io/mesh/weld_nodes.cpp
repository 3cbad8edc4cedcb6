#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numeric>
#include <parallel/algorithm>
#include <string>
#include <unordered_map>
#include <vector>

#include "tear/error.h"
#include "tear/read_mesh.h"

#include "topology/disjoint_sets.h"

namespace tear {
namespace {

bool node_is_finite(const std::vector<float>& node_pos, index_t node) {
  return std::isfinite(node_pos[3 * node]) && std::isfinite(node_pos[3 * node + 1]) &&
         std::isfinite(node_pos[3 * node + 2]);
}

/// Rejects arrays that do not match, so welding never reads out of range.
void check_arrays(const Mesh& mesh, const char* who) {
  auto fail = [&](const std::string& what) { return Error(ErrorKind::input, std::string(who) + ": " + what); };
  const index_t node_count = mesh.node_count();
  const index_t face_count = mesh.face_count();
  for (std::size_t c = 0; c < mesh.face_nodes.size(); ++c) {
    const index_t node = mesh.face_nodes[c];
    if (node < 0 || node >= node_count) {
      throw fail("face " + std::to_string(c / 3) + " uses node " + std::to_string(node) + " of " +
                 std::to_string(node_count));
    }
  }
  if ((mesh.has_uv() && mesh.corner_uv.size() != 6 * static_cast<std::size_t>(face_count)) ||
      (mesh.has_normals() && mesh.corner_normal.size() != 9 * static_cast<std::size_t>(face_count))) {
    throw fail("corner_uv or corner_normal does not have one entry per face corner");
  }
  const std::size_t n = static_cast<std::size_t>(node_count);
  if ((mesh.has_velocities() && mesh.node_vel.size() != 3 * n) ||
      (mesh.has_origins() && mesh.node_origin_face.size() != n) ||
      (mesh.node_origin_bary.size() != 2 * mesh.node_origin_face.size())) {
    throw fail("node_vel, node_origin_face or node_origin_bary does not have one entry per node");
  }
  if (mesh.torn_edge_nodes.size() % 2 != 0) throw fail("torn_edge_nodes does not hold pairs");
  for (index_t node : mesh.torn_edge_nodes) {
    if (node < 0 || node >= node_count) {
      throw fail("a torn edge uses node " + std::to_string(node) + " of " + std::to_string(node_count));
    }
  }
}

/// Loops over this many faces or nodes, or more, run on the OpenMP threads; each writes only its
/// own elements, or stores a flag atomically.
constexpr std::int64_t parallel_items = 1 << 14;

std::vector<std::uint8_t> used_nodes(const Mesh& mesh) {
  std::vector<std::uint8_t> used(mesh.node_count(), 0);
  const std::int64_t corners = static_cast<std::int64_t>(mesh.face_nodes.size());
#pragma omp parallel for schedule(static) if (corners >= parallel_items)
  for (std::int64_t c = 0; c < corners; ++c) {
#pragma omp atomic write
    used[mesh.face_nodes[c]] = 1;
  }
  return used;
}

bool repeats_a_node(const index_t* n) { return n[0] == n[1] || n[1] == n[2] || n[2] == n[0]; }

/// values[i] = values[kept[i]] for each node of `width` values. In place when `kept` ascends (each
/// node moves down, never past one not yet read), else through a copy.
template <typename T>
void gather(std::vector<T>& values, int width, const std::vector<index_t>& kept) {
  if (values.empty()) return;
  const std::size_t w = static_cast<std::size_t>(width);
  if (std::is_sorted(kept.begin(), kept.end())) {
    for (std::size_t i = 0; i < kept.size(); ++i) {
      std::copy(values.begin() + w * kept[i], values.begin() + w * kept[i] + w, values.begin() + w * i);
    }
    values.resize(w * kept.size());
    return;
  }
  std::vector<T> out(w * kept.size());
  for (std::size_t i = 0; i < kept.size(); ++i) {
    std::copy(values.begin() + w * kept[i], values.begin() + w * kept[i] + w, out.begin() + w * i);
  }
  values = std::move(out);
}

std::uint64_t edge_key(index_t a, index_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
}

bool same_position(const std::vector<float>& node_pos, index_t a, index_t b) {
  for (int k = 0; k < 3; ++k)
    if (node_pos[3 * std::size_t(a) + k] != node_pos[3 * std::size_t(b) + k]) return false;
  return true;
}

/// The median length of the faces' edges of non-zero length (0 when there is none).
double median_edge(const Mesh& mesh) {
  std::vector<double> length;
  length.reserve(mesh.face_nodes.size());
  for (std::size_t f = 0; f + 2 < mesh.face_nodes.size(); f += 3)
    for (int k = 0; k < 3; ++k) {
      const float* p = &mesh.node_pos[3 * std::size_t(mesh.face_nodes[f + k])];
      const float* q = &mesh.node_pos[3 * std::size_t(mesh.face_nodes[f + (k + 1) % 3])];
      const double d = std::hypot(double(p[0]) - q[0], double(p[1]) - q[1], double(p[2]) - q[2]);
      if (d > 0 && std::isfinite(d)) length.push_back(d);
    }
  if (length.empty()) return 0;
  std::nth_element(length.begin(), length.begin() + length.size() / 2, length.end());
  return length[length.size() / 2];
}

/// What merging into `node_group` does to data the file kept apart (`WeldReport`): faces of three
/// different nodes left with a repeated node, where the two nodes joined were apart in the file.
/// Nodes at different positions were (joined by a tolerance, or by one id); nodes at one float32
/// position are taken to have been when float32 keeps fewer than `precision_steps` steps along
/// the mesh's median edge at its largest coordinate (coordinates far from the origin): otherwise
/// they were the same point in the file too, and the face was degenerate there already, dropped
/// without a word as a face repeating a vertex is.
void count_collapsed(const Mesh& mesh, const std::vector<index_t>& node_group, WeldReport& report) {
  constexpr double precision_steps = 1024;
  const std::int64_t values = static_cast<std::int64_t>(mesh.node_pos.size());
  double largest = report.largest_coordinate;
#pragma omp parallel for schedule(static) reduction(max : largest) if (values >= parallel_items)
  for (std::int64_t i = 0; i < values; ++i)
    if (std::isfinite(mesh.node_pos[i])) largest = std::max(largest, std::fabs(double(mesh.node_pos[i])));
  report.largest_coordinate = largest;
  const std::int64_t faces = static_cast<std::int64_t>(mesh.face_count());
  int any_joined = 0;  // a face of three nodes with two of them in one group: the only faces looked at below
#pragma omp parallel for schedule(static) reduction(max : any_joined) if (faces >= parallel_items)
  for (std::int64_t f = 0; f < faces; ++f) {
    const index_t* n = &mesh.face_nodes[3 * f];
    const index_t group[3] = {node_group[n[0]], node_group[n[1]], node_group[n[2]]};
    if (!repeats_a_node(n) && repeats_a_node(group)) any_joined = 1;
  }
  if (!any_joined) return;
  int exponent = 0;
  std::frexp(report.largest_coordinate, &exponent);
  const double step = report.largest_coordinate > 0 ? std::ldexp(1.0, exponent - 24) : 0.0;
  int coarse = -1;  // whether float32 is too coarse for the mesh: found when first needed
  std::vector<index_t> joined;  // nodes of lost faces joined to another corner of theirs
  const std::size_t face_count = static_cast<std::size_t>(mesh.face_count());
  for (std::size_t f = 0; f < face_count; ++f) {
    const index_t* n = &mesh.face_nodes[3 * f];
    if (repeats_a_node(n)) continue;
    bool lost = false;
    for (int k = 0; k < 3; ++k) {
      const index_t a = n[k], b = n[(k + 1) % 3];
      if (node_group[a] != node_group[b]) continue;
      if (same_position(mesh.node_pos, a, b)) {
        if (coarse < 0) coarse = step * precision_steps > median_edge(mesh) ? 1 : 0;
        if (!coarse) continue;
      }
      lost = true;
      joined.insert(joined.end(), {a, b});
    }
    if (lost) ++report.collapsed_faces;
  }
  if (joined.empty()) return;
  std::sort(joined.begin(), joined.end());
  joined.erase(std::unique(joined.begin(), joined.end()), joined.end());
  std::vector<index_t> groups(joined.size());
  for (std::size_t i = 0; i < joined.size(); ++i) groups[i] = node_group[joined[i]];
  std::sort(groups.begin(), groups.end());
  const std::size_t group_count = static_cast<std::size_t>(std::unique(groups.begin(), groups.end()) - groups.begin());
  report.joined_nodes += static_cast<std::int64_t>(joined.size() - group_count);
}

/// `nodes` (ascending) stably sorted by `key[node]`: as (key, node) pairs in one 64-bit word, sorted
/// on the OpenMP threads, where every key fits in 32 bits (ids do); else by comparisons.
void order_by_key(std::vector<index_t>& nodes, const std::vector<std::int64_t>& key) {
  const bool packs = std::all_of(nodes.begin(), nodes.end(),
                                 [&](index_t node) { return key[node] >= 0 && key[node] <= 0xFFFFFFFFll; });
  if (!packs) {
    std::stable_sort(nodes.begin(), nodes.end(), [&](index_t a, index_t b) { return key[a] < key[b]; });
    return;
  }
  std::vector<std::uint64_t> pairs(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i)
    pairs[i] = (static_cast<std::uint64_t>(key[nodes[i]]) << 32) | static_cast<std::uint32_t>(nodes[i]);
  // The pairs are distinct, so any sort puts them in the one order a stable sort by key gives.
  __gnu_parallel::sort(pairs.begin(), pairs.end());
  for (std::size_t i = 0; i < nodes.size(); ++i) nodes[i] = static_cast<index_t>(pairs[i] & 0xFFFFFFFFu);
}

/// Each face's nodes replaced by their groups' representatives; faces left with a repeated node
/// dropped with their corner attributes.
void merge_faces(Mesh& mesh, const std::vector<index_t>& node_group) {
  const index_t face_count = mesh.face_count();
  std::vector<index_t>& face_nodes = mesh.face_nodes;
  std::vector<float>&corner_uv = mesh.corner_uv, &corner_normal = mesh.corner_normal;
  const std::int64_t faces = face_count;
  int any_dropped = 0;
#pragma omp parallel for schedule(static) reduction(max : any_dropped) if (faces >= parallel_items)
  for (std::int64_t f = 0; f < faces; ++f) {
    const index_t group[3] = {node_group[face_nodes[3 * f]], node_group[face_nodes[3 * f + 1]],
                              node_group[face_nodes[3 * f + 2]]};
    if (repeats_a_node(group)) any_dropped = 1;
  }
  if (!any_dropped) {  // each face keeps its place
    const std::int64_t corners = 3 * faces;
#pragma omp parallel for schedule(static) if (corners >= parallel_items)
    for (std::int64_t c = 0; c < corners; ++c) face_nodes[c] = node_group[face_nodes[c]];
    return;
  }
  // Compacted in place: a kept face moves to its running count, never past where it was read.
  std::size_t kept_faces = 0;
  for (index_t face = 0; face < face_count; ++face) {
    index_t merged[3];
    for (int k = 0; k < 3; ++k) merged[k] = node_group[face_nodes[3 * face + k]];
    if (repeats_a_node(merged)) continue;
    std::copy(merged, merged + 3, face_nodes.begin() + 3 * kept_faces);
    if (mesh.has_uv()) {
      std::copy(corner_uv.begin() + 6 * face, corner_uv.begin() + 6 * face + 6, corner_uv.begin() + 6 * kept_faces);
    }
    if (mesh.has_normals()) {
      std::copy(corner_normal.begin() + 9 * face, corner_normal.begin() + 9 * face + 9,
                corner_normal.begin() + 9 * kept_faces);
    }
    ++kept_faces;
  }
  const bool with_uv = mesh.has_uv(), with_normals = mesh.has_normals();
  face_nodes.resize(3 * kept_faces);
  if (with_uv) corner_uv.resize(6 * kept_faces);
  if (with_normals) corner_normal.resize(9 * kept_faces);
}

/// Merges every node into its group's representative `node_group[node]` (a node of the group,
/// `node_group[rep] == rep`), then keeps the representatives some face still uses, ordered by
/// `group_key[rep]` (ascending, ties by index; by index alone when `group_key` is empty).
/// Faces left with a repeated node are dropped with their corner attributes; the node arrays
/// (positions, velocities, origins) take the representative's values; torn edges follow their
/// nodes and are kept only while they are still an edge of exactly one face.
void merge_nodes(Mesh& mesh, const std::vector<index_t>& node_group, const std::vector<std::int64_t>& group_key,
                 WeldReport* report = nullptr) {
  if (report) count_collapsed(mesh, node_group, *report);
  merge_faces(mesh, node_group);
  std::vector<index_t>& face_nodes = mesh.face_nodes;

  // The representatives still in use, in the order of their keys.
  std::vector<index_t> kept;
  {
    const std::vector<std::uint8_t> in_use = used_nodes(mesh);
    for (index_t node = 0; node < mesh.node_count(); ++node) {
      if (in_use[node]) kept.push_back(node);
    }
  }
  if (!group_key.empty()) order_by_key(kept, group_key);
  std::vector<index_t> new_index(mesh.node_count(), none);
  for (std::size_t i = 0; i < kept.size(); ++i) new_index[kept[i]] = static_cast<index_t>(i);
  const std::int64_t corners = static_cast<std::int64_t>(face_nodes.size());
#pragma omp parallel for schedule(static) if (corners >= parallel_items)
  for (std::int64_t c = 0; c < corners; ++c) face_nodes[c] = new_index[face_nodes[c]];

  // Torn edges: mapped to the merged nodes, kept while they are an edge of exactly one face.
  std::vector<index_t> torn_edge_nodes;
  if (!mesh.torn_edge_nodes.empty()) {
    std::unordered_map<std::uint64_t, int> edge_faces;
    std::vector<index_t> mapped;
    for (std::size_t e = 0; e + 1 < mesh.torn_edge_nodes.size(); e += 2) {
      const index_t a = new_index[node_group[mesh.torn_edge_nodes[e]]];
      const index_t b = new_index[node_group[mesh.torn_edge_nodes[e + 1]]];
      if (a == none || b == none || a == b) continue;
      mapped.insert(mapped.end(), {a, b});
      edge_faces.emplace(edge_key(a, b), 0);
    }
    for (std::size_t f = 0; f < face_nodes.size(); f += 3) {
      for (int k = 0; k < 3; ++k) {
        auto found = edge_faces.find(edge_key(face_nodes[f + (k + 1) % 3], face_nodes[f + (k + 2) % 3]));
        if (found != edge_faces.end()) ++found->second;
      }
    }
    for (std::size_t e = 0; e < mapped.size(); e += 2) {
      if (edge_faces[edge_key(mapped[e], mapped[e + 1])] == 1) {
        torn_edge_nodes.insert(torn_edge_nodes.end(), {mapped[e], mapped[e + 1]});
      }
    }
  }

  gather(mesh.node_pos, 3, kept);
  gather(mesh.node_vel, 3, kept);
  gather(mesh.node_origin_face, 1, kept);
  gather(mesh.node_origin_bary, 2, kept);
  mesh.torn_edge_nodes = std::move(torn_edge_nodes);
}

/// Exact welding: sort by position (ties by index), so each run of equal positions starts with its
/// lowest index. The keys carry their positions, and the sort runs on the OpenMP threads (its
/// order is unique, ties being broken by index, so it is the same on any number of threads).
void link_identical(const std::vector<float>& node_pos, const std::vector<index_t>& nodes, DisjointSets& sets) {
  struct Key {
    float pos[3];
    index_t node;
  };
  std::vector<Key> order(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const float* p = &node_pos[3 * static_cast<std::size_t>(nodes[i])];
    order[i] = Key{{p[0], p[1], p[2]}, nodes[i]};
  }
  auto less = [](const Key& a, const Key& b) {
    for (int k = 0; k < 3; ++k) {
      if (a.pos[k] != b.pos[k]) return a.pos[k] < b.pos[k];
    }
    return a.node < b.node;
  };
  __gnu_parallel::sort(order.begin(), order.end(), less);
  for (std::size_t i = 1; i < order.size(); ++i) {
    const Key &a = order[i - 1], &b = order[i];
    if (a.pos[0] == b.pos[0] && a.pos[1] == b.pos[1] && a.pos[2] == b.pos[2]) sets.unite(a.node, b.node);
  }
}

/// Welding within `tolerance`: nodes are binned in a grid of cell size `tolerance`, so two nodes
/// within tolerance of each other lie in the same or in neighbouring cells.
void link_within(const std::vector<float>& node_pos, const std::vector<index_t>& nodes, double tolerance,
                 DisjointSets& sets) {
  // Clamping far-away cells only merges cells (more candidates), the exact test below decides.
  constexpr double cell_limit = 1e15;
  auto cell_of = [&](index_t node, int k) {
    const double c = std::floor(static_cast<double>(node_pos[3 * node + k]) / tolerance);
    return static_cast<std::int64_t>(std::clamp(c, -cell_limit, cell_limit));
  };
  struct Cell {
    std::int64_t x, y, z;
    bool operator==(const Cell& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct CellHash {
    std::size_t operator()(const Cell& c) const {
      std::uint64_t h = static_cast<std::uint64_t>(c.x) * 0x9E3779B97F4A7C15ull;
      h ^= static_cast<std::uint64_t>(c.y) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
      h ^= static_cast<std::uint64_t>(c.z) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
      return static_cast<std::size_t>(h);
    }
  };
  std::unordered_map<Cell, std::vector<index_t>, CellHash> cell_nodes;
  cell_nodes.reserve(nodes.size());
  for (index_t node : nodes) cell_nodes[Cell{cell_of(node, 0), cell_of(node, 1), cell_of(node, 2)}].push_back(node);

  auto close = [&](index_t a, index_t b) {
    for (int k = 0; k < 3; ++k) {
      const double d = static_cast<double>(node_pos[3 * a + k]) - static_cast<double>(node_pos[3 * b + k]);
      if (!(std::fabs(d) <= tolerance)) return false;
    }
    return true;
  };
  for (index_t node : nodes) {
    const Cell home{cell_of(node, 0), cell_of(node, 1), cell_of(node, 2)};
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          auto found = cell_nodes.find(Cell{home.x + dx, home.y + dy, home.z + dz});
          if (found == cell_nodes.end()) continue;
          for (index_t other : found->second) {
            if (other > node && close(node, other)) sets.unite(node, other);
          }
        }
      }
    }
  }
}

}  // namespace

void weld_nodes(Mesh& mesh, double tolerance, WeldReport* report) {
  if (!std::isfinite(tolerance) || tolerance < 0.0) {
    throw Error(ErrorKind::usage, "weld tolerance must be a finite number >= 0, got " + std::to_string(tolerance));
  }
  check_arrays(mesh, "weld_nodes");
  const index_t node_count = mesh.node_count();

  // Only nodes some face uses take part, so an unused node never links two used ones.
  const std::vector<std::uint8_t> node_used = used_nodes(mesh);
  std::vector<index_t> weldable;
  for (index_t node = 0; node < node_count; ++node) {
    if (node_used[node] && node_is_finite(mesh.node_pos, node)) weldable.push_back(node);
  }
  DisjointSets sets(node_count);
  if (tolerance == 0.0) {
    link_identical(mesh.node_pos, weldable, sets);
  } else {
    link_within(mesh.node_pos, weldable, tolerance, sets);
  }
  std::vector<index_t> node_group(node_count);
  for (index_t node = 0; node < node_count; ++node) node_group[node] = sets.find(node);
  merge_nodes(mesh, node_group, {}, report);
}

void weld_nodes_by_id(Mesh& mesh, const std::vector<index_t>& node_id, WeldReport* report) {
  check_arrays(mesh, "weld_nodes_by_id");
  const index_t node_count = mesh.node_count();
  if (node_id.size() != static_cast<std::size_t>(node_count)) {
    throw Error(ErrorKind::input, "weld_nodes_by_id: " + std::to_string(node_id.size()) + " ids for " +
                                      std::to_string(node_count) + " nodes");
  }
  const std::vector<std::uint8_t> node_used = used_nodes(mesh);
  std::vector<index_t> order;
  index_t largest_id = -1;
  for (index_t node = 0; node < node_count; ++node) {
    if (!node_used[node]) continue;
    if (node_id[node] < 0) {
      throw Error(ErrorKind::input, "weld_nodes_by_id: node " + std::to_string(node) + " has the negative id " +
                                        std::to_string(node_id[node]));
    }
    order.push_back(node);
    largest_id = std::max(largest_id, node_id[node]);
  }
  // Each id's representative is its node of the lowest index.
  std::vector<index_t> node_group(node_count);
  std::iota(node_group.begin(), node_group.end(), 0);
  if (static_cast<std::int64_t>(largest_id) <= 4 * static_cast<std::int64_t>(order.size()) + 1024) {
    // Ids about as many as the nodes (tear's own files number them 0, 1, ...): a table by id.
    std::vector<index_t> first(static_cast<std::size_t>(largest_id) + 1, none);
    for (index_t node : order) {
      index_t& representative = first[node_id[node]];
      if (representative == none) representative = node;
      node_group[node] = representative;
    }
  } else {
    // Sorted by (id, index): each run of one id starts with its lowest index, the representative.
    // (id, index) in one 64-bit key sorts without looking the ids up; ids are >= 0 here.
    std::vector<std::uint64_t> id_node(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
      id_node[i] = (static_cast<std::uint64_t>(node_id[order[i]]) << 32) | static_cast<std::uint32_t>(order[i]);
    }
    __gnu_parallel::sort(id_node.begin(), id_node.end());
    for (std::size_t i = 1; i < id_node.size(); ++i) {
      if (id_node[i] >> 32 == id_node[i - 1] >> 32) {
        node_group[static_cast<index_t>(id_node[i] & 0xFFFFFFFFu)] =
            node_group[static_cast<index_t>(id_node[i - 1] & 0xFFFFFFFFu)];
      }
    }
  }
  std::vector<std::int64_t> group_key(node_id.begin(), node_id.end());
  merge_nodes(mesh, node_group, group_key, report);
}

std::string WeldReport::describe() const {
  char where[160];
  // float32's step at the largest coordinate: 2^(exponent - 23).
  int exponent = 0;
  std::frexp(largest_coordinate, &exponent);
  std::snprintf(where, sizeof where, "coordinates reach %.3g, where float32 has steps of %.3g", largest_coordinate,
                largest_coordinate > 0 ? std::ldexp(1.0, exponent - 24) : 0.0);
  return std::to_string(collapsed_faces) + (collapsed_faces == 1 ? " face" : " faces") +
         " lost in reading: welding joined corners of theirs, different vertices in the file, into one node (" +
         std::to_string(joined_nodes) + (joined_nodes == 1 ? " node" : " nodes") + " lost so); " + where;
}

void drop_unused_nodes(Mesh& mesh) {
  check_arrays(mesh, "drop_unused_nodes");
  std::vector<index_t> node_group(mesh.node_count());
  std::iota(node_group.begin(), node_group.end(), 0);
  merge_nodes(mesh, node_group, {});
}

}  // namespace tear
