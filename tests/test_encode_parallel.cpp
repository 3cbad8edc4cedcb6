// One frame encoded in pieces on several threads gives the bytes the sequential encoders gave
// (write_mesh_reference.cpp), whatever the threads and the pieces.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "catch.h"
#include "random_meshes.h"
#include "tear/error.h"
#include "tear/make_sheet.h"
#include "tear/write_mesh.h"
#include "test_support.h"
#include "write_mesh_reference.h"

namespace {

using tear::index_t;
using tear::Mesh;
using tear::MeshFormat;
using tear::test::Random;

float float_of_bits(std::uint32_t bits) {
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

/// Values that make numbering and splitting hard: -0 and +0 (equal as numbers, not as bits), two
/// NaNs of other bits (one value when splitting, two when numbering), infinities, numbers printed
/// in fixed notation, and a few plain ones that repeat.
const std::vector<float>& awkward_values() {
  static const std::vector<float> values = {0.0f,
                                            -0.0f,
                                            std::numeric_limits<float>::quiet_NaN(),
                                            float_of_bits(0xFFC00001u),
                                            std::numeric_limits<float>::infinity(),
                                            -std::numeric_limits<float>::infinity(),
                                            1.0f,
                                            0.5f,
                                            -0.25f,
                                            3.0e-5f,
                                            1.0e-30f,
                                            3.14159274f};
  return values;
}

/// A mesh as a frame can hold it, not necessarily a sane one: nodes no face uses, degenerate
/// faces, corners of a node that agree or disagree on UV and normal (so nodes split, some into
/// several vertices), positions with NaN and signed zeros, identity arrays or none, torn edges.
Mesh random_frame(Random& random) {
  Mesh mesh;
  const bool large = random.chance(0.15);
  const index_t node_count = large ? 200 + random.below(3000) : random.below(40);
  const index_t face_count = node_count == 0 ? 0 : (large ? random.below(6000) : random.below(80));
  const std::vector<float>& awkward = awkward_values();
  auto value = [&](double awkward_share) {
    return random.chance(awkward_share) ? awkward[random.below(static_cast<index_t>(awkward.size()))]
                                        : static_cast<float>(random.uniform(-2.0, 2.0));
  };
  // Sometimes positions of a few values only, so that POSITION's min and max meet -0 and +0 (the
  // first in vertex order is written).
  const bool few_positions = random.chance(0.2);
  const float position_values[] = {0.0f, -0.0f, 1.0f, std::numeric_limits<float>::quiet_NaN()};
  for (index_t i = 0; i < 3 * node_count; ++i) {
    mesh.node_pos.push_back(few_positions ? position_values[random.below(4)] : value(0.2));
  }
  // Faces use some of the nodes only, a few of them often (many corners, many splits).
  const index_t used = node_count == 0 ? 0 : 1 + random.below(node_count);
  for (index_t i = 0; i < 3 * face_count; ++i) {
    const index_t node = random.chance(0.1) ? random.below(std::min<index_t>(used, 3)) : random.below(used);
    mesh.face_nodes.push_back(node);
  }
  // Per-corner values: mostly the node's own (so nodes do not split), else another value.
  auto corner_values = [&](int width, double own_share) {
    std::vector<float> node_value;
    for (index_t i = 0; i < width * node_count; ++i) node_value.push_back(value(0.3));
    std::vector<float> values;
    for (index_t node : mesh.face_nodes) {
      const bool own = random.chance(own_share);
      for (int k = 0; k < width; ++k) values.push_back(own ? node_value[width * node + k] : value(0.5));
    }
    return values;
  };
  if (random.chance(0.7)) mesh.corner_uv = corner_values(2, random.uniform());
  if (random.chance(0.7)) mesh.corner_normal = corner_values(3, random.uniform());
  if (random.chance(0.5)) {
    for (index_t i = 0; i < 3 * node_count; ++i) mesh.node_vel.push_back(value(0.2));
  }
  if (random.chance(0.5)) {
    for (index_t node = 0; node < node_count; ++node) {
      mesh.node_origin_face.push_back(random.chance(0.2) ? tear::none : random.below(1000));
      mesh.node_origin_bary.push_back(value(0.1));
      mesh.node_origin_bary.push_back(value(0.1));
    }
  }
  if (node_count > 0 && random.chance(0.5)) {
    const index_t edges = random.below(30);
    for (index_t i = 0; i < 2 * edges; ++i) mesh.torn_edge_nodes.push_back(random.below(node_count));
  }
  return mesh;
}

const MeshFormat all_formats[] = {MeshFormat::obj, MeshFormat::ply, MeshFormat::gltf, MeshFormat::glb};

const char* name_of(MeshFormat format) {
  switch (format) {
    case MeshFormat::obj:
      return "obj";
    case MeshFormat::ply:
      return "ply";
    case MeshFormat::gltf:
      return "gltf";
    case MeshFormat::glb:
      return "glb";
  }
  return "?";
}

/// The first byte where `a` and `b` differ, for the failure message.
std::size_t first_difference(const std::string& a, const std::string& b) {
  std::size_t i = 0;
  while (i < a.size() && i < b.size() && a[i] == b[i]) ++i;
  return i;
}

/// Encodes `mesh` in every format with 1, 2, 3 and 7 threads, in pieces however small the mesh,
/// and by default, and compares each with the sequential encoders' bytes.
void check_encodings(const Mesh& mesh) {
  for (MeshFormat format : all_formats) {
    const std::string expected = tear::encode_mesh_reference(mesh, format);
    const std::string path = std::string("frame.") + name_of(format);
    for (int threads : {1, 2, 3, 7, 0}) {
      tear::EncodeOptions options;
      options.threads = threads;
      if (threads > 0) options.parallel_from = 0;
      INFO(name_of(format) << ", " << threads << " threads" << (threads > 0 ? ", in pieces" : ", by default"));
      std::string bytes = "what the buffer held before";
      tear::encode_mesh(mesh, path, format, bytes, options);
      INFO(expected.size() << " bytes expected, " << bytes.size() << " encoded, first difference at byte "
                           << first_difference(expected, bytes));
      CHECK(bytes == expected);
    }
  }
}

}  // namespace

TEST_CASE("encode_mesh: random frames encode to the sequential bytes at any thread count", "[io][encode]") {
  const std::uint64_t base = tear::test::test_seed(4242);
  const bool one_seed = std::getenv("TEAR_TEST_SEED") != nullptr;
  for (int i = 0; i < (one_seed ? 1 : 150); ++i) {
    const std::uint64_t seed = base + std::uint64_t(i);
    INFO("seed " << seed << " (TEAR_TEST_SEED=" << seed << " reruns it)");
    Random random(seed);
    const Mesh mesh = random_frame(random);
    INFO(mesh.node_count() << " nodes, " << mesh.face_count() << " faces" << (mesh.has_uv() ? ", UVs" : "")
                           << (mesh.has_normals() ? ", normals" : ""));
    check_encodings(mesh);
  }
}

TEST_CASE("encode_mesh: a sheet of 20,000 faces with a UV seam and flat normals, by default and in pieces",
          "[io][encode]") {
  tear::SheetOptions options;
  options.face_count = 20000;
  options.irregular = true;
  Mesh mesh = tear::make_sheet(options);
  mesh.corner_uv.clear();
  mesh.corner_normal.clear();
  // UVs from the positions, shifted right of the middle (a seam); each face's own normal (every
  // node splits into one vertex per face around it).
  for (std::size_t c = 0; c < mesh.face_nodes.size(); ++c) {
    const float* p = &mesh.node_pos[3 * static_cast<std::size_t>(mesh.face_nodes[c])];
    const float* first = &mesh.node_pos[3 * static_cast<std::size_t>(mesh.face_nodes[c - c % 3])];
    mesh.corner_uv.push_back(p[0] + (first[0] > 0.0f ? 0.5f : 0.0f));
    mesh.corner_uv.push_back(p[1]);
    const float face = static_cast<float>(c / 3);
    mesh.corner_normal.insert(mesh.corner_normal.end(), {std::sin(face), std::cos(face), 0.0f});
  }
  check_encodings(mesh);
}

TEST_CASE("encode_mesh: a face using a missing node is named the same at any thread count", "[io][encode]") {
  Random random(7);
  Mesh mesh;
  for (int i = 0; i < 3 * 500; ++i) mesh.node_pos.push_back(static_cast<float>(random.uniform()));
  for (int i = 0; i < 3 * 2000; ++i) mesh.face_nodes.push_back(random.below(500));
  mesh.face_nodes[3 * 1234 + 1] = 500;
  mesh.face_nodes[3 * 1500] = -1;
  for (int threads : {1, 2, 7}) {
    INFO(threads << " threads");
    tear::EncodeOptions options;
    options.threads = threads;
    options.parallel_from = 0;
    std::string bytes;
    CHECK_THROWS_WITH(tear::encode_mesh(mesh, "out/f.ply", MeshFormat::ply, bytes, options),
                      "out/f.ply: cannot write: face 1234 uses node 500 of 500");
  }
}
