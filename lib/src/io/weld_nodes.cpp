#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
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


/// Exact welding: sort by position (ties by index), so each run of equal positions starts with its
/// lowest index.
void link_identical(const std::vector<float>& node_pos, const std::vector<index_t>& nodes, DisjointSets& sets) {
  std::vector<index_t> order = nodes;
  auto less = [&](index_t a, index_t b) {
    for (int k = 0; k < 3; ++k) {
      if (node_pos[3 * a + k] != node_pos[3 * b + k]) return node_pos[3 * a + k] < node_pos[3 * b + k];
    }
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  for (std::size_t i = 1; i < order.size(); ++i) {
    const index_t a = order[i - 1], b = order[i];
    if (node_pos[3 * a] == node_pos[3 * b] && node_pos[3 * a + 1] == node_pos[3 * b + 1] &&
        node_pos[3 * a + 2] == node_pos[3 * b + 2]) {
      sets.unite(a, b);
    }
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

void weld_nodes(Mesh& mesh, double tolerance) {
  if (!std::isfinite(tolerance) || tolerance < 0.0) {
    throw Error(ErrorKind::usage, "weld tolerance must be a finite number >= 0, got " + std::to_string(tolerance));
  }
  const index_t node_count = mesh.node_count();
  const index_t face_count = mesh.face_count();
  for (std::size_t c = 0; c < mesh.face_nodes.size(); ++c) {
    const index_t node = mesh.face_nodes[c];
    if (node < 0 || node >= node_count) {
      throw Error(ErrorKind::input, "weld_nodes: face " + std::to_string(c / 3) + " uses node " + std::to_string(node) +
                                        " of " + std::to_string(node_count));
    }
  }

  if ((mesh.has_uv() && mesh.corner_uv.size() != 6 * static_cast<std::size_t>(face_count)) ||
      (mesh.has_normals() && mesh.corner_normal.size() != 9 * static_cast<std::size_t>(face_count))) {
    throw Error(ErrorKind::input, "weld_nodes: corner_uv or corner_normal does not have one entry per face corner");
  }

  // Only nodes some face uses take part, so an unused node never links two used ones.
  std::vector<std::uint8_t> node_used(node_count, 0);
  for (index_t node : mesh.face_nodes) node_used[node] = 1;
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

  // Faces whose corners collapsed onto fewer than three nodes are degenerate: drop them with their
  // corner attributes.
  std::vector<index_t> face_nodes;
  std::vector<float> corner_uv, corner_normal;
  face_nodes.reserve(mesh.face_nodes.size());
  corner_uv.reserve(mesh.corner_uv.size());
  corner_normal.reserve(mesh.corner_normal.size());
  for (index_t face = 0; face < face_count; ++face) {
    index_t welded[3];
    for (int k = 0; k < 3; ++k) welded[k] = sets.find(mesh.face_nodes[3 * face + k]);
    if (welded[0] == welded[1] || welded[1] == welded[2] || welded[2] == welded[0]) continue;
    face_nodes.insert(face_nodes.end(), welded, welded + 3);
    if (mesh.has_uv()) {
      corner_uv.insert(corner_uv.end(), mesh.corner_uv.begin() + 6 * face, mesh.corner_uv.begin() + 6 * face + 6);
    }
    if (mesh.has_normals()) {
      corner_normal.insert(corner_normal.end(), mesh.corner_normal.begin() + 9 * face,
                           mesh.corner_normal.begin() + 9 * face + 9);
    }
  }

  // Keep the representatives still in use, in ascending original index.
  std::vector<index_t> new_index(node_count, none);
  for (index_t node : face_nodes) new_index[node] = 0;
  std::vector<float> node_pos;
  index_t kept = 0;
  for (index_t node = 0; node < node_count; ++node) {
    if (new_index[node] == none) continue;
    new_index[node] = kept++;
    node_pos.insert(node_pos.end(), mesh.node_pos.begin() + 3 * node, mesh.node_pos.begin() + 3 * node + 3);
  }
  for (index_t& node : face_nodes) node = new_index[node];

  mesh.node_pos = std::move(node_pos);
  mesh.face_nodes = std::move(face_nodes);
  if (mesh.has_uv()) mesh.corner_uv = std::move(corner_uv);
  if (mesh.has_normals()) mesh.corner_normal = std::move(corner_normal);
}

}  // namespace tear
