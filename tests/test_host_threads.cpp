// The host passes that run on the OpenMP threads give the same result on any number of them, and
// the result a plain one-thread reference gives: pieces (a concurrent union-find), welding by id
// (a table by id, or a sort for sparse ids), and the frame's face check and recomputed normals
// (each node's sum taken in face order). Meshes are large enough to take the parallel paths.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <numeric>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <omp.h>

#include "catch.h"
#include "cloth/face_pieces.h"
#include "tear/device.h"
#include "tear/make_sheet.h"
#include "tear/read_mesh.h"
#include "tear/run_cuts.h"
#include "test_support.h"

namespace {

using tear::index_t;

/// Runs `f` on 1 thread and on 4, restoring the team's size after.
template <class F>
auto on_one_and_four(F f) {
  const int before = omp_get_max_threads();
  omp_set_num_threads(1);
  auto one = f();
  omp_set_num_threads(4);
  auto four = f();
  omp_set_num_threads(before);
  return std::make_pair(one, four);
}

/// A jittered sheet of 40,000 faces, about two in three dropped at random (seeded): many pieces,
/// some nodes used by no face, some faces of a repeated node, some folded over.
tear::Mesh broken_sheet(std::uint64_t seed) {
  tear::SheetOptions options;
  options.face_count = 40000;
  options.seed = seed;
  tear::Mesh sheet = tear::make_sheet(options);
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  tear::Mesh mesh;
  mesh.node_pos = sheet.node_pos;
  for (std::size_t f = 0; f < sheet.face_nodes.size() / 3; ++f) {
    const float roll = unit(random);
    if (roll < 0.65f) continue;  // dropped
    std::array<index_t, 3> nodes{sheet.face_nodes[3 * f], sheet.face_nodes[3 * f + 1], sheet.face_nodes[3 * f + 2]};
    if (roll < 0.652f) nodes[1] = nodes[0];  // a repeated node
    if (roll > 0.995f) std::swap(nodes[1], nodes[2]);  // folded over
    mesh.face_nodes.insert(mesh.face_nodes.end(), nodes.begin(), nodes.end());
  }
  for (std::size_t i = 2; i < mesh.node_pos.size(); i += 3) mesh.node_pos[i] = 0.01f * unit(random);
  return mesh;
}

/// Pieces by a plain serial union-find, numbered by lowest face.
std::vector<index_t> reference_pieces(const std::vector<index_t>& face_nodes) {
  const std::size_t faces = face_nodes.size() / 3;
  std::vector<index_t> parent(faces);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](index_t x) {
    while (parent[x] != x) x = parent[x];
    return x;
  };
  index_t nodes = 0;
  for (index_t n : face_nodes) nodes = std::max(nodes, n + 1);
  std::vector<index_t> first(static_cast<std::size_t>(nodes), -1);
  for (std::size_t c = 0; c < face_nodes.size(); ++c) {
    index_t& at = first[face_nodes[c]];
    if (at < 0) {
      at = index_t(c / 3);
      continue;
    }
    const index_t a = find(at), b = find(index_t(c / 3));
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
  std::vector<index_t> number(faces, -1), piece(faces);
  index_t count = 0;
  for (std::size_t f = 0; f < faces; ++f) {
    const index_t root = find(index_t(f));
    if (number[root] < 0) number[root] = count++;
    piece[f] = number[root];
  }
  return piece;
}

/// Area-weighted normals summed face after face, one thread.
std::vector<std::array<double, 3>> reference_node_sums(const tear::Mesh& mesh) {
  std::vector<std::array<double, 3>> sum(static_cast<std::size_t>(mesh.node_count()), {0, 0, 0});
  for (std::size_t f = 0; f < mesh.face_nodes.size() / 3; ++f) {
    const index_t* n = &mesh.face_nodes[3 * f];
    double e[2][3];
    for (int k = 0; k < 2; ++k)
      for (int a = 0; a < 3; ++a)
        e[k][a] = double(mesh.node_pos[3 * std::size_t(n[k + 1]) + a]) - mesh.node_pos[3 * std::size_t(n[0]) + a];
    const double cross[3] = {e[0][1] * e[1][2] - e[0][2] * e[1][1], e[0][2] * e[1][0] - e[0][0] * e[1][2],
                             e[0][0] * e[1][1] - e[0][1] * e[1][0]};
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a) sum[n[k]][a] += cross[a];
  }
  return sum;
}

}  // namespace

TEST_CASE("host threads: pieces are numbered the same on 1 and 4 threads, as a serial union-find does",
          "[pieces][threads]") {
  const std::uint64_t seed = tear::test::test_seed(20261127);
  INFO("seed " << seed << " (TEAR_TEST_SEED)");
  const tear::Mesh mesh = broken_sheet(seed);
  const auto [one, four] = on_one_and_four([&] {
    std::vector<index_t> piece;
    const index_t count = tear::number_pieces(mesh.face_nodes, mesh.node_count(), piece);
    return std::make_pair(count, piece);
  });
  const std::vector<index_t> expected = reference_pieces(mesh.face_nodes);
  CHECK(one.second == expected);
  CHECK(four.second == expected);
  CHECK(one.first == *std::max_element(expected.begin(), expected.end()) + 1);
  CHECK(four.first == one.first);
  CHECK(one.first > 100);  // the test means something only with many pieces

  // Renumbered after a split: ids carried from an unsplit mesh (all 0) are shared out the same way.
  const auto [renumbered_one, renumbered_four] = on_one_and_four([&] {
    std::vector<index_t> piece(mesh.face_nodes.size() / 3, 0);
    const index_t next = tear::renumber_pieces(mesh.face_nodes, mesh.node_pos, piece);
    return std::make_pair(next, piece);
  });
  CHECK(renumbered_one == renumbered_four);
}

TEST_CASE("host threads: the face check and recomputed normals are the same bytes on 1 and 4 threads",
          "[quality][threads]") {
  const std::uint64_t seed = tear::test::test_seed(7);
  INFO("seed " << seed << " (TEAR_TEST_SEED)");
  const tear::Mesh mesh = broken_sheet(seed);
  const auto [quality_one, quality_four] = on_one_and_four([&] {
    const tear::FaceQuality q = tear::face_quality(mesh);
    return std::make_pair(q.degenerate, q.inverted);
  });
  CHECK(quality_one == quality_four);
  CHECK(quality_one.first > 0);
  CHECK(quality_one.second > 0);
  const auto [normals_one, normals_four] = on_one_and_four([&] { return tear::area_weighted_corner_normals(mesh); });
  REQUIRE(normals_one.size() == normals_four.size());
  CHECK(std::memcmp(normals_one.data(), normals_four.data(), normals_one.size() * sizeof(float)) == 0);
  // Each corner's normal is its node's sum, taken in face order, normalised.
  const std::vector<std::array<double, 3>> sum = reference_node_sums(mesh);
  std::size_t differing = 0;
  for (std::size_t c = 0; c < mesh.face_nodes.size(); ++c) {
    const std::array<double, 3>& s = sum[mesh.face_nodes[c]];
    const double length = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    if (!(length > 0)) continue;
    for (int a = 0; a < 3; ++a)
      if (normals_one[3 * c + a] != float(s[a] / length)) ++differing;
  }
  CHECK(differing == 0);
}

TEST_CASE("host threads: welding by id gives one mesh on 1 and 4 threads, dense ids or sparse", "[weld][threads]") {
  const std::uint64_t seed = tear::test::test_seed(11);
  INFO("seed " << seed << " (TEAR_TEST_SEED)");
  const tear::Mesh sheet = broken_sheet(seed);
  // Each face's corners as vertices of their own (a file that splits every corner), ids the nodes'
  // numbers shuffled: dense ids, and the same ids spread out (taking the sorting path).
  std::mt19937_64 random(seed);
  std::vector<index_t> shuffled(static_cast<std::size_t>(sheet.node_count()));
  std::iota(shuffled.begin(), shuffled.end(), 0);
  std::shuffle(shuffled.begin(), shuffled.end(), random);
  tear::Mesh split;
  std::vector<index_t> dense, sparse;
  for (std::size_t c = 0; c < sheet.face_nodes.size(); ++c) {
    const index_t node = sheet.face_nodes[c];
    for (int a = 0; a < 3; ++a) split.node_pos.push_back(sheet.node_pos[3 * std::size_t(node) + a]);
    split.face_nodes.push_back(index_t(c));
    dense.push_back(shuffled[node]);
    sparse.push_back(shuffled[node] * 1000 + 7);
  }
  auto weld = [&](const std::vector<index_t>& ids) {
    return on_one_and_four([&] {
      tear::Mesh mesh = split;
      tear::weld_nodes_by_id(mesh, ids);
      return mesh;
    });
  };
  const auto [dense_one, dense_four] = weld(dense);
  const auto [sparse_one, sparse_four] = weld(sparse);
  for (const tear::Mesh* m : {&dense_four, &sparse_one, &sparse_four}) {
    CHECK(m->face_nodes == dense_one.face_nodes);
    CHECK(m->node_pos == dense_one.node_pos);
  }
  // The faces of a repeated node are gone; the nodes are in ascending id.
  std::size_t kept = 0;
  for (std::size_t f = 0; f < sheet.face_nodes.size() / 3; ++f) {
    const index_t* n = &sheet.face_nodes[3 * f];
    if (n[0] != n[1] && n[1] != n[2] && n[2] != n[0]) ++kept;
  }
  REQUIRE(dense_one.face_nodes.size() == 3 * kept);
  std::vector<index_t> id_of(static_cast<std::size_t>(dense_one.node_count()), -1);
  std::size_t corner = 0, wrong_place = 0;
  for (std::size_t f = 0; f < sheet.face_nodes.size() / 3; ++f) {
    const index_t* n = &sheet.face_nodes[3 * f];
    if (n[0] == n[1] || n[1] == n[2] || n[2] == n[0]) continue;
    for (int k = 0; k < 3; ++k, ++corner) {
      const index_t welded = dense_one.face_nodes[corner];
      id_of[welded] = shuffled[n[k]];
      for (int a = 0; a < 3; ++a)
        if (dense_one.node_pos[3 * std::size_t(welded) + a] != sheet.node_pos[3 * std::size_t(n[k]) + a]) ++wrong_place;
    }
  }
  CHECK(wrong_place == 0);
  CHECK(std::find(id_of.begin(), id_of.end(), -1) == id_of.end());
  CHECK(std::adjacent_find(id_of.begin(), id_of.end(), std::greater_equal<index_t>()) == id_of.end());
}

TEST_CASE("host threads: a thread takes on the limit set_cpu_threads set when handed cpu_threads()", "[threads]") {
  const int before = tear::cpu_threads();
  tear::set_cpu_threads(3);
  CHECK(tear::cpu_threads() == 3);
  // A new thread begins with OpenMP's own limit (what `tear batch` hands on to its reading thread).
  const int limit = tear::cpu_threads();
  int seen = 0, handed = 0;
  std::thread([&] {
    seen = omp_get_max_threads();
    tear::set_cpu_threads(limit);
    handed = omp_get_max_threads();
  }).join();
  CHECK(handed == 3);
  CHECK(seen >= 1);
  tear::set_cpu_threads(before);
}
