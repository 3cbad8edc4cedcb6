// tear: piece ids per face (face_pieces.h).
#include "cloth/face_pieces.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numeric>

namespace tear {

namespace {

/// The pieces of a mesh: for every face the number of its piece, pieces numbered in order of
/// their lowest face.
struct Pieces {
  std::vector<index_t> of_face;       // [face_count]
  std::vector<index_t> lowest_face;   // [piece_count]
};

index_t find(std::vector<index_t>& parent, index_t x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}

Pieces find_pieces(const std::vector<index_t>& face_nodes) {
  const std::size_t faces = face_nodes.size() / 3;
  std::vector<index_t> parent(faces);
  std::iota(parent.begin(), parent.end(), index_t(0));
  // Every face joins the first face met at each of its nodes.
  index_t node_count = 0;
  for (index_t n : face_nodes) node_count = std::max(node_count, n + 1);
  std::vector<index_t> first_face(static_cast<std::size_t>(node_count), none);
  for (std::size_t f = 0; f < faces; ++f) {
    for (int k = 0; k < 3; ++k) {
      const index_t n = face_nodes[3 * f + k];
      if (n < 0) continue;
      if (first_face[n] == none) {
        first_face[n] = static_cast<index_t>(f);
        continue;
      }
      const index_t a = find(parent, first_face[n]), b = find(parent, static_cast<index_t>(f));
      if (a != b) parent[std::max(a, b)] = std::min(a, b);  // the root is the lowest face
    }
  }
  Pieces p;
  p.of_face.assign(faces, none);
  std::vector<index_t> number(faces, none);
  for (std::size_t f = 0; f < faces; ++f) {
    const index_t root = find(parent, static_cast<index_t>(f));
    if (number[root] == none) {
      number[root] = static_cast<index_t>(p.lowest_face.size());
      p.lowest_face.push_back(static_cast<index_t>(f));
    }
    p.of_face[f] = number[root];
  }
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
  std::vector<double> area(count, 0.0);
  for (std::size_t f = 0; f < faces; ++f) area[p.of_face[f]] += rest_area(face_nodes, node_rest, f);
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
  for (std::size_t f = 0; f < faces; ++f) face_piece[f] = new_id[p.of_face[f]];
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
