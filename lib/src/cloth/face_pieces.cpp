// tear: piece ids per face (face_pieces.h).
#include "cloth/face_pieces.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numeric>

#include "topology/lower_to.h"

namespace tear {

namespace {

/// The pieces of a mesh: for every face the number of its piece, pieces numbered in order of
/// their lowest face.
struct Pieces {
  std::vector<index_t> of_face;       // [face_count]
  std::vector<index_t> lowest_face;   // [piece_count]
};

/// Meshes of this many faces or more are numbered on the OpenMP threads.
constexpr std::int64_t parallel_faces = 1 << 14;

/// The root of `x`'s set, halving the path on the way; other threads may link and halve at once.
/// Every link points to a lower face, so a root is the lowest face of its set.
index_t find(std::vector<index_t>& parent, index_t x) {
  for (;;) {
    index_t p = __atomic_load_n(&parent[x], __ATOMIC_RELAXED);
    if (p == x) return x;
    const index_t grandparent = __atomic_load_n(&parent[p], __ATOMIC_RELAXED);
    if (grandparent != p) __atomic_compare_exchange_n(&parent[x], &p, grandparent, false, __ATOMIC_RELAXED, __ATOMIC_RELAXED);
    x = grandparent;
  }
}

/// Joins the sets of `a` and `b`: the higher root is linked under the lower one, retried when
/// another thread linked it first.
void unite(std::vector<index_t>& parent, index_t a, index_t b) {
  for (;;) {
    a = find(parent, a);
    b = find(parent, b);
    if (a == b) return;
    if (a < b) std::swap(a, b);
    index_t expected = a;
    if (__atomic_compare_exchange_n(&parent[a], &expected, b, false, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) return;
  }
}

/// The sets are the pieces whatever order the threads join them in, and each set's root is its
/// lowest face, so the numbering is the same on any number of threads.
Pieces find_pieces(const std::vector<index_t>& face_nodes) {
  const std::int64_t faces = static_cast<std::int64_t>(face_nodes.size() / 3), corners = 3 * faces;
  const bool parallel = faces >= parallel_faces;
  index_t node_count = 0;
#pragma omp parallel for schedule(static) reduction(max : node_count) if (parallel)
  for (std::int64_t c = 0; c < corners; ++c) node_count = std::max(node_count, face_nodes[c] + 1);
  // Every face joins the lowest face at each of its nodes.
  std::vector<index_t> lowest_at(static_cast<std::size_t>(node_count), std::numeric_limits<index_t>::max());
#pragma omp parallel for schedule(static) if (parallel)
  for (std::int64_t c = 0; c < corners; ++c)
    if (face_nodes[c] >= 0) lower_to(lowest_at[face_nodes[c]], static_cast<index_t>(c / 3));
  std::vector<index_t> parent(static_cast<std::size_t>(faces));
  std::iota(parent.begin(), parent.end(), index_t(0));
#pragma omp parallel for schedule(static) if (parallel)
  for (std::int64_t c = 0; c < corners; ++c)
    if (face_nodes[c] >= 0) unite(parent, static_cast<index_t>(c / 3), lowest_at[face_nodes[c]]);
  // Pieces in order of their lowest face, the root: its number is the count of roots before it.
  std::vector<index_t> root(static_cast<std::size_t>(faces));
#pragma omp parallel for schedule(static) if (parallel)
  for (std::int64_t f = 0; f < faces; ++f) root[f] = find(parent, static_cast<index_t>(f));
  Pieces p;
  std::vector<index_t> number(static_cast<std::size_t>(faces), none);
  for (std::int64_t f = 0; f < faces; ++f)
    if (root[f] == f) {
      number[f] = static_cast<index_t>(p.lowest_face.size());
      p.lowest_face.push_back(static_cast<index_t>(f));
    }
  p.of_face.resize(static_cast<std::size_t>(faces));
#pragma omp parallel for schedule(static) if (parallel)
  for (std::int64_t f = 0; f < faces; ++f) p.of_face[f] = number[root[f]];
  return p;
}

double rest_area(const std::vector<index_t>& face_nodes, const std::vector<float>& node_rest, std::size_t f) {
  double e[2][3];
  const index_t a = face_nodes[3 * f];
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 3; ++j) e[k][j] = double(node_rest[3 * face_nodes[3 * f + 1 + k] + j]) - node_rest[3 * a + j];
  const double x = e[0][1] * e[1][2] - e[0][2] * e[1][1], y = e[0][2] * e[1][0] - e[0][0] * e[1][2],
               z = e[0][0] * e[1][1] - e[0][1] * e[1][0];
  return 0.5 * std::sqrt(x * x + y * y + z * z);
}

}  // namespace

index_t number_pieces(const std::vector<index_t>& face_nodes, index_t, std::vector<index_t>& face_piece) {
  Pieces p = find_pieces(face_nodes);
  face_piece = std::move(p.of_face);
  return static_cast<index_t>(p.lowest_face.size());
}

index_t renumber_pieces(const std::vector<index_t>& face_nodes, const std::vector<float>& node_rest,
                        std::vector<index_t>& face_piece) {
  const Pieces p = find_pieces(face_nodes);
  const std::size_t faces = face_nodes.size() / 3, count = p.lowest_face.size();
  // Each piece's area summed in face order (the areas themselves on the threads).
  std::vector<double> face_area(faces);
  const std::int64_t face_total = static_cast<std::int64_t>(faces);
#pragma omp parallel for schedule(static) if (face_total >= parallel_faces)
  for (std::int64_t f = 0; f < face_total; ++f) face_area[f] = rest_area(face_nodes, node_rest, f);
  std::vector<double> area(count, 0.0);
  for (std::size_t f = 0; f < faces; ++f) area[p.of_face[f]] += face_area[f];
  // Each piece's old id: that of its lowest face (cuts split pieces, never join them).
  index_t next = 0;
  for (index_t id : face_piece) next = std::max(next, id + 1);
  std::vector<index_t> old_id(count), new_id(count, none);
  for (std::size_t q = 0; q < count; ++q) old_id[q] = std::max(face_piece[p.lowest_face[q]], index_t(0));
  // The keeper of each old id: the largest area, then the lowest face (pieces are in that order).
  std::vector<index_t> keeper(static_cast<std::size_t>(next) + 1, none);
  for (std::size_t q = 0; q < count; ++q) {
    index_t& k = keeper[old_id[q]];
    if (k == none || area[q] > area[k]) k = static_cast<index_t>(q);
  }
  for (std::size_t q = 0; q < count; ++q)
    new_id[q] = keeper[old_id[q]] == static_cast<index_t>(q) ? old_id[q] : next++;
#pragma omp parallel for schedule(static) if (face_total >= parallel_faces)
  for (std::int64_t f = 0; f < face_total; ++f) face_piece[f] = new_id[p.of_face[f]];
  return std::max(next, index_t(count));
}

index_t count_pieces(const std::vector<index_t>& face_piece) {
  std::vector<index_t> ids(face_piece);
  std::sort(ids.begin(), ids.end());
  return static_cast<index_t>(std::unique(ids.begin(), ids.end()) - ids.begin());
}

std::vector<index_t> node_pieces(const std::vector<index_t>& face_nodes, const std::vector<index_t>& face_piece,
                                 index_t node_count) {
  std::vector<index_t> piece(static_cast<std::size_t>(node_count), none);
  if (face_piece.size() * 3 != face_nodes.size()) return piece;
  for (std::size_t c = 0; c < face_nodes.size(); ++c) {
    const index_t n = face_nodes[c];
    if (n >= 0 && n < node_count && piece[n] == none) piece[n] = face_piece[c / 3];
  }
  return piece;
}

}  // namespace tear
