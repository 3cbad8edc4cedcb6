// Seeded random meshes for property tests: clean sheets, sheets with holes, permuted sheets,
// closed surfaces, tubes and triangle soups with every defect validate_mesh counts.
//
// Every generator is a pure function of its seed, on every platform: std::mt19937_64 is fully
// specified and the mapping to doubles below is ours (std::uniform_*_distribution is not).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "tear/make_sheet.h"
#include "tear/mesh.h"

namespace tear::test {

/// A sheet of about `faces` faces (`make_sheet`, regular unless `irregular`) turned into the xz plane
/// ([0,1] × {0} × [0,1]), so that gravity -y hangs it down when one edge is pinned.
inline Mesh horizontal_sheet(index_t faces, bool irregular = false) {
  SheetOptions o;
  o.face_count = faces;
  o.irregular = irregular;
  Mesh mesh = make_sheet(o);
  for (index_t n = 0; n < mesh.node_count(); ++n) {
    const float y = mesh.node_pos[3 * n + 1];
    mesh.node_pos[3 * n + 1] = 0;
    mesh.node_pos[3 * n + 2] = y;
  }
  return mesh;
}

/// A seeded random source with a portable mapping to doubles and integers.
class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  /// Uniform in [0, 1), 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * (1.0 / 9007199254740992.0); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform in [0, n), n > 0 (the modulo bias is negligible for the small n used here).
  index_t below(index_t n) { return static_cast<index_t>(engine_() % static_cast<std::uint64_t>(n)); }
  bool chance(double p) { return uniform() < p; }
  std::uint64_t bits() { return engine_(); }
  /// Fisher-Yates, driven by `below`.
  template <class T>
  void shuffle(std::vector<T>& items) {
    for (std::size_t i = items.size(); i > 1; --i)
      std::swap(items[i - 1], items[static_cast<std::size_t>(below(static_cast<index_t>(i)))]);
  }

 private:
  std::mt19937_64 engine_;
};

/// A random valid face count of `make_sheet` in [2, max_faces]: even and not 6.
inline index_t random_sheet_face_count(Random& random, index_t max_faces) {
  for (;;) {
    const index_t count = 2 * (1 + random.below(max_faces / 2));
    if (count != 6) return count;
  }
}

/// A regular or irregular sheet of random size, face count and layout seed.
inline Mesh random_sheet(std::uint64_t seed, index_t max_faces = 400) {
  Random random(seed);
  SheetOptions options;
  options.face_count = random_sheet_face_count(random, max_faces);
  options.irregular = random.chance(0.6);
  options.seed = random.bits();
  options.size = random.uniform(0.25, 4.0);
  return make_sheet(options);
}

/// Keeps the faces where `keep` is true, with their corner attributes; nodes are left as they
/// are (some may become unused).
inline Mesh keep_faces(const Mesh& mesh, const std::vector<bool>& keep) {
  Mesh out;
  out.node_pos = mesh.node_pos;
  for (std::size_t f = 0; f < keep.size(); ++f) {
    if (!keep[f]) continue;
    out.face_nodes.insert(out.face_nodes.end(), mesh.face_nodes.begin() + 3 * f, mesh.face_nodes.begin() + 3 * f + 3);
    if (mesh.has_uv())
      out.corner_uv.insert(out.corner_uv.end(), mesh.corner_uv.begin() + 6 * f, mesh.corner_uv.begin() + 6 * f + 6);
    if (mesh.has_normals())
      out.corner_normal.insert(out.corner_normal.end(), mesh.corner_normal.begin() + 9 * f,
                               mesh.corner_normal.begin() + 9 * f + 9);
  }
  return out;
}

/// A random sheet with a random fraction (up to 40 %) of its faces removed: holes, unused nodes,
/// and often bow-tie nodes where two removed faces meet at a corner.
inline Mesh sheet_with_holes(std::uint64_t seed) {
  Random random(seed);
  const Mesh sheet = random_sheet(random.bits());
  const double drop = random.uniform(0.02, 0.4);
  std::vector<bool> keep(static_cast<std::size_t>(sheet.face_count()));
  for (std::size_t f = 0; f < keep.size(); ++f) keep[f] = !random.chance(drop);
  return keep_faces(sheet, keep);
}

/// Renumbers the nodes by a random permutation, shuffles the faces and rotates each face's
/// corners (orientation kept): the same surface under different indices.
inline Mesh permute_mesh(const Mesh& mesh, std::uint64_t seed) {
  Random random(seed);
  std::vector<index_t> new_of_old(static_cast<std::size_t>(mesh.node_count()));
  for (std::size_t n = 0; n < new_of_old.size(); ++n) new_of_old[n] = static_cast<index_t>(n);
  random.shuffle(new_of_old);
  Mesh out;
  out.node_pos.resize(mesh.node_pos.size());
  for (std::size_t n = 0; n < new_of_old.size(); ++n)
    for (std::size_t d = 0; d < 3; ++d)
      out.node_pos[3 * static_cast<std::size_t>(new_of_old[n]) + d] = mesh.node_pos[3 * n + d];
  std::vector<index_t> face_order(static_cast<std::size_t>(mesh.face_count()));
  for (std::size_t f = 0; f < face_order.size(); ++f) face_order[f] = static_cast<index_t>(f);
  random.shuffle(face_order);
  for (index_t f : face_order) {
    const index_t turn = random.below(3);
    for (index_t k = 0; k < 3; ++k) {
      const index_t old = mesh.face_nodes[3 * static_cast<std::size_t>(f) + static_cast<std::size_t>((k + turn) % 3)];
      out.face_nodes.push_back(new_of_old[static_cast<std::size_t>(old)]);
    }
  }
  return out;
}

/// A random sheet, renumbered and shuffled by `permute_mesh`.
inline Mesh permuted_sheet(std::uint64_t seed) {
  Random random(seed);
  const Mesh sheet = random_sheet(random.bits());
  return permute_mesh(sheet, random.bits());
}

/// A regular octahedron of unit radius, faces counter-clockwise seen from outside.
inline Mesh octahedron() {
  Mesh m;
  m.node_pos = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
  m.face_nodes = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  return m;
}

/// The octahedron with every face split in four `levels` times (a closed sphere-like surface of
/// 8 * 4^levels faces), new nodes pushed out to the unit sphere.
inline Mesh subdivided_octahedron(int levels) {
  Mesh m = octahedron();
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<index_t, index_t>, index_t> midpoint;
    auto mid = [&](index_t a, index_t b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      const auto found = midpoint.find(key);
      if (found != midpoint.end()) return found->second;
      double p[3], length = 0;
      for (std::size_t d = 0; d < 3; ++d) {
        p[d] = 0.5 * (double(m.node_pos[3 * static_cast<std::size_t>(a) + d]) +
                      m.node_pos[3 * static_cast<std::size_t>(b) + d]);
        length += p[d] * p[d];
      }
      length = std::sqrt(length);
      const index_t node = m.node_count();
      for (double x : p) m.node_pos.push_back(static_cast<float>(x / length));
      midpoint.emplace(key, node);
      return node;
    };
    std::vector<index_t> faces;
    for (index_t f = 0; f < m.face_count(); ++f) {
      const index_t a = m.face_nodes[3 * f], b = m.face_nodes[3 * f + 1], c = m.face_nodes[3 * f + 2];
      const index_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      faces.insert(faces.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
    }
    m.face_nodes = faces;
  }
  return m;
}

/// A welded tube (closed around, open at both ends) of random resolution.
inline Mesh random_tube(std::uint64_t seed) {
  Random random(seed);
  TubeOptions options;
  options.segments = 3 + random.below(20);
  options.rings = 1 + random.below(10);
  options.radius = random.uniform(0.05, 1.0);
  options.length = random.uniform(0.2, 3.0);
  options.welded = true;
  return make_tube(options);
}

/// Appends a node and returns its index.
inline index_t add_node(Mesh& m, double x, double y, double z) {
  m.node_pos.insert(m.node_pos.end(), {static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)});
  return m.node_count() - 1;
}

inline void add_face(Mesh& m, index_t a, index_t b, index_t c) { m.face_nodes.insert(m.face_nodes.end(), {a, b, c}); }

/// What `random_soup` may put in.
struct SoupOptions {
  /// Faces listing one node twice. Their fans and orientation are not well defined, so tests
  /// comparing those counts can leave them out.
  bool repeated_nodes = true;
};

/// A random triangle soup over a small sheet: random extra faces over a small node pool (shared
/// edges of any multiplicity), fins (a third face on an edge), bow-ties (a second sheet touching
/// the first at one node), flipped faces, zero-area faces (collinear or coincident nodes, exact
/// in float) and, when allowed, faces repeating a node. Every index is in range and every
/// coordinate finite; node and face order are shuffled at the end.
inline Mesh random_soup(std::uint64_t seed, const SoupOptions& options = {}) {
  Random random(seed);
  Mesh m = random_sheet(random.bits(), 60);
  m.corner_uv.clear();
  m.corner_normal.clear();
  const index_t sheet_nodes = m.node_count();

  // Flipped faces: swapping two corners reverses the face against its neighbours.
  const index_t flips = random.below(4);
  for (index_t i = 0; i < flips; ++i) {
    const index_t f = random.below(m.face_count());
    std::swap(m.face_nodes[3 * f + 1], m.face_nodes[3 * f + 2]);
  }
  // Fins: a third (or fourth) face on an existing edge, standing out of the plane.
  const index_t fins = random.below(3);
  for (index_t i = 0; i < fins; ++i) {
    const index_t f = random.below(m.face_count()), k = random.below(3);
    const index_t a = m.face_nodes[3 * f + (k + 1) % 3], b = m.face_nodes[3 * f + (k + 2) % 3];
    add_face(m, a, b, add_node(m, random.uniform(), random.uniform(), random.uniform(0.5, 1.5)));
  }
  // Bow-ties: a separate fan of two or three faces sharing only one node with the sheet.
  const index_t bowties = random.below(3);
  for (index_t i = 0; i < bowties; ++i) {
    const index_t hub = random.below(sheet_nodes);
    const index_t fan = 2 + random.below(2);
    index_t prev = add_node(m, random.uniform(), random.uniform(), 2.0 + i);
    for (index_t j = 0; j < fan; ++j) {
      const index_t next = add_node(m, random.uniform(), random.uniform(), 2.5 + i + j);
      add_face(m, hub, prev, next);
      prev = next;
    }
  }
  // Random faces over a small pool of nodes: edges with one to many faces, either orientation.
  const index_t pool = 4 + random.below(5);
  std::vector<index_t> pool_nodes;
  for (index_t i = 0; i < pool; ++i)
    pool_nodes.push_back(add_node(m, random.uniform(-1, 0), random.uniform(-1, 0), random.uniform(-1, 1)));
  const index_t extra = random.below(12);
  for (index_t i = 0; i < extra; ++i) {
    const index_t a = random.below(pool), b = (a + 1 + random.below(pool - 1)) % pool;
    index_t c = random.below(pool);
    while (c == a || c == b) c = random.below(pool);
    add_face(m, pool_nodes[a], pool_nodes[b], pool_nodes[c]);
  }
  // Zero-area faces with distinct nodes: small integers on one line (exact in float), or three
  // nodes at one point.
  const index_t flat = random.below(3);
  for (index_t i = 0; i < flat; ++i) {
    const double px = random.below(5), py = random.below(5), dx = 1 + random.below(3), dy = random.below(3);
    if (random.chance(0.5)) {
      add_face(m, add_node(m, px, py, -3), add_node(m, px + dx, py + dy, -3),
               add_node(m, px + 2 * dx, py + 2 * dy, -3));
    } else {
      const index_t a = add_node(m, px, py, -4), b = add_node(m, px, py, -4), c = add_node(m, px, py, -4);
      add_face(m, a, b, c);
    }
  }
  if (options.repeated_nodes) {
    const index_t repeated = random.below(3);
    for (index_t i = 0; i < repeated; ++i) {
      const index_t a = random.below(m.node_count()), b = random.below(m.node_count());
      switch (random.below(3)) {
        case 0:
          add_face(m, a, a, b);
          break;
        case 1:
          add_face(m, a, b, a);
          break;
        default:
          add_face(m, b, a, a);
          break;
      }
    }
  }
  return permute_mesh(m, random.bits());
}

/// A mesh of one of the kinds above, chosen by the seed, with a name for failure messages.
struct NamedMesh {
  std::string name;
  Mesh mesh;
};

inline NamedMesh random_mesh(std::uint64_t seed, const SoupOptions& soup = {}) {
  Random random(seed);
  const std::uint64_t next = random.bits();
  switch (random.below(8)) {
    case 0:
      return {"sheet", random_sheet(next)};
    case 1:
      return {"sheet with holes", sheet_with_holes(next)};
    case 2:
      return {"permuted sheet", permuted_sheet(next)};
    case 3:
      return {"welded tube", random_tube(next)};
    case 4:
      return {"subdivided octahedron", permute_mesh(subdivided_octahedron(random.below(4)), next)};
    default:
      return {"triangle soup", random_soup(next, soup)};
  }
}

}  // namespace tear::test
