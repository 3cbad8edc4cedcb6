// Pulls torn whole and measured in the rest shape, for the crack growth tests
// (test_crack_growth.cpp, test_strength_map.cpp): pieces, shreds, folded faces, smallest angle,
// torn boundary and its length, and the meshes pulled.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "catch.h"
#include "cloth/crack_growth.h"
#include "remesh_checks.h"
#include "tear/cloth.h"
#include "tear/cut_script.h"
#include "tear/make_sheet.h"
#include "tear/run_cuts.h"
#include "test_support.h"

namespace tear::test::pulls {

using tear::index_t;
constexpr double pi = 3.14159265358979323846;


/// Pieces (connected through faces) of a mesh: per face, its piece; `count` of them.
inline std::vector<index_t> face_pieces(const tear::Mesh& m, index_t& count) {
  const std::vector<index_t> node_root = tear::test::node_piece_roots(m);
  const auto find = [&](index_t n) { return node_root[n]; };
  std::vector<index_t> root(m.face_count()), ids;
  for (index_t f = 0; f < m.face_count(); ++f) root[f] = find(m.face_nodes[3 * f]);
  ids = root;
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  for (index_t& r : root) r = static_cast<index_t>(std::lower_bound(ids.begin(), ids.end(), r) - ids.begin());
  count = static_cast<index_t>(ids.size());
  return root;
}

inline double face_area(const std::vector<float>& p, const index_t* f) {
  double e1[3], e2[3];
  for (int d = 0; d < 3; ++d) {
    e1[d] = p[3 * f[1] + d] - p[3 * f[0] + d];
    e2[d] = p[3 * f[2] + d] - p[3 * f[0] + d];
  }
  const double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
  return 0.5 * std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
}

/// What a pull leaves, measured in the rest shape.
struct Torn {
  index_t pieces = 0;
  double smallest_piece = 0;              ///< fraction of the rest area, over every frame
  double worst_inverted = 0;              ///< fraction of faces folded over, over every frame
  std::vector<std::array<double, 2>> last_inverted_at;  ///< rest centroids of faces folded over in the last frame
  double smallest_angle = 180;            ///< degrees, rest shape, over every frame
  double shortest_edge = 1e9;             ///< metres, rest shape, over every frame
  index_t events = 0;                     ///< tear events
  index_t late_events = 0;                ///< tear events from `quiet` frames after the cloth first split on
  std::vector<std::array<double, 2>> boundary;  ///< torn edges' rest points (sampled), final frame
  double torn_length = 0;                 ///< one side's rest length of the torn edges, final frame
  std::vector<float> rest;
  tear::Mesh mesh;
  std::vector<index_t> piece;
};

inline Torn run(const tear::Mesh& sheet, const std::string& script_text, int frames, int quiet = 2,
                const std::string& script_path = "pull.json") {
  const tear::CutScript script = tear::parse_cut_script(script_text, script_path);
  tear::Cloth cloth(sheet, tear::test::test_device());
  Torn t;
  const double area = tear::test::total_area(sheet);
  t.smallest_piece = 1;
  int split = 0;  // the frame the cloth first fell into pieces
  tear::run_cuts(cloth, script, frames, [&](const tear::FrameResult& frame, const tear::Cloth& c) {
    t.events += frame.tear_events;
    if (split > 0 && frame.frame > split + quiet) t.late_events += frame.tear_events;
    const tear::Mesh m = c.mesh();
    const std::vector<float> rest = c.node_rest();
    index_t count = 0;
    const std::vector<index_t> piece = face_pieces(m, count);
    if (count > 1 && split == 0) split = frame.frame;
    std::vector<double> piece_area(count, 0.0);
    index_t inverted = 0;
    for (index_t f = 0; f < m.face_count(); ++f) {
      const index_t* fn = &m.face_nodes[3 * f];
      piece_area[piece[f]] += face_area(rest, fn);
      // Folded over: the current normal against the rest normal (the sheets lie in z = 0 at rest).
      const auto nz = [&](const std::vector<float>& p) {
        return (p[3 * fn[1]] - p[3 * fn[0]]) * (p[3 * fn[2] + 1] - p[3 * fn[0] + 1]) -
               (p[3 * fn[1] + 1] - p[3 * fn[0] + 1]) * (p[3 * fn[2]] - p[3 * fn[0]]);
      };
      if (nz(m.node_pos) * nz(rest) < 0) {
        ++inverted;
        if (frame.frame == frames)
          t.last_inverted_at.push_back({(rest[3 * fn[0]] + rest[3 * fn[1]] + rest[3 * fn[2]]) / 3.0,
                                        (rest[3 * fn[0] + 1] + rest[3 * fn[1] + 1] + rest[3 * fn[2] + 1]) / 3.0});
      }
      for (int k = 0; k < 3; ++k) {
        double a[3], b[3];
        for (int d = 0; d < 3; ++d) {
          a[d] = rest[3 * fn[(k + 1) % 3] + d] - rest[3 * fn[k] + d];
          b[d] = rest[3 * fn[(k + 2) % 3] + d] - rest[3 * fn[k] + d];
        }
        const double la = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        const double lb = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
        const double cosine = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (la * lb);
        t.smallest_angle = std::min(t.smallest_angle, std::acos(std::max(-1.0, std::min(1.0, cosine))) * 180 / pi);
        t.shortest_edge = std::min(t.shortest_edge, la);
      }
    }
    for (double a : piece_area) t.smallest_piece = std::min(t.smallest_piece, a / area);
    t.worst_inverted = std::max(t.worst_inverted, double(inverted) / m.face_count());
  });
  t.mesh = cloth.mesh();
  t.rest = cloth.node_rest();
  t.piece = face_pieces(t.mesh, t.pieces);
  for (std::size_t e = 0; e + 1 < t.mesh.torn_edge_nodes.size(); e += 2) {
    const index_t a = t.mesh.torn_edge_nodes[e], b = t.mesh.torn_edge_nodes[e + 1];
    const double ax = t.rest[3 * a], ay = t.rest[3 * a + 1], bx = t.rest[3 * b], by = t.rest[3 * b + 1];
    const double length = std::hypot(bx - ax, by - ay);
    t.torn_length += 0.5 * length;
    const int samples = 1 + static_cast<int>(length / 0.002);
    for (int s = 0; s <= samples; ++s) {
      const double u = double(s) / samples;
      t.boundary.push_back({ax + u * (bx - ax), ay + u * (by - ay)});
    }
  }
  return t;
}

/// The Hausdorff distance between two sampled boundaries (metres).
inline double hausdorff(const std::vector<std::array<double, 2>>& a, const std::vector<std::array<double, 2>>& b) {
  const auto one_way = [](const auto& p, const auto& q) {
    double worst = 0;
    for (const auto& x : p) {
      double best = 1e18;
      for (const auto& y : q) best = std::min(best, std::hypot(x[0] - y[0], x[1] - y[1]));
      worst = std::max(worst, best);
    }
    return worst;
  };
  return std::max(one_way(a, b), one_way(b, a));
}

/// The torn boundary's points above the notch (y >= 0.25), for comparing the cracks alone.
inline std::vector<std::array<double, 2>> crack_points(const Torn& t) {
  std::vector<std::array<double, 2>> out;
  for (const auto& p : t.boundary)
    if (p[1] >= 0.25) out.push_back(p);
  return out;
}

constexpr int pull_frames = 24;

/// The notched pull of test_tearing.cpp: the slit from the bottom border to (0.5, 0.25), the left
/// and right strips pulled 0.15 m apart each over `pull_frames` frames; `tearing` the block's keys.
inline std::string notched_pull(const std::string& tearing) {
  return R"({"version": 1, "frames": 24,
    "cuts": [{"frame": 1, "space": "rest-xy", "polyline": [[0.5, -0.1], [0.5, 0.25]]}],
    "simulation": {"gravity": [0, 0, 0], "substeps": 4, "iterations": 40,
      "pins": [
        {"box": {"min": [-1, -1, -1], "max": [0.04, 2, 1]}, "keys": [{"frame": 0, "offset": [0, 0, 0]}, {"frame": 24, "offset": [-0.15, 0, 0]}]},
        {"box": {"min": [0.96, -1, -1], "max": [2, 2, 1]}, "keys": [{"frame": 0, "offset": [0, 0, 0]}, {"frame": 24, "offset": [0.15, 0, 0]}]}],
      "tearing": {)" +
         tearing + "}}}";
}

/// What crack growth reads of `cloth`: its rest shape, faces and topology.
inline tear::CrackMesh crack_mesh_of(const tear::Cloth& cloth) {
  tear::CrackMesh mesh;
  mesh.node_rest = cloth.node_rest();
  mesh.face_nodes = cloth.face_nodes();
  mesh.topo = cloth.topology();
  return mesh;
}

inline tear::Mesh sheet(index_t faces, bool irregular) {
  tear::SheetOptions options;
  options.face_count = faces;
  options.irregular = irregular;
  return tear::make_sheet(options);
}

/// What crack growth reads of the sheet of `faces` faces cut along `polyline` (rest xy, metres).
inline tear::CrackMesh slit_sheet(index_t faces, bool irregular, std::vector<std::array<double, 2>> polyline) {
  tear::Cloth cloth(sheet(faces, irregular), tear::test::test_device());
  tear::CutLine line;
  line.polyline = std::move(polyline);
  cloth.cut({line}, tear::CutOptions{});
  return crack_mesh_of(cloth);
}

/// The mesh's median rest edge length.
inline double median_edge(const tear::Mesh& m) {
  std::vector<double> lengths;
  for (index_t f = 0; f < m.face_count(); ++f)
    for (int k = 0; k < 3; ++k) {
      const index_t a = m.face_nodes[3 * f + k], b = m.face_nodes[3 * f + (k + 1) % 3];
      lengths.push_back(std::hypot(m.node_pos[3 * a] - m.node_pos[3 * b], m.node_pos[3 * a + 1] - m.node_pos[3 * b + 1]));
    }
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  return lengths[lengths.size() / 2];
}

inline void check_clean(const Torn& t, const tear::Mesh& input) {
  CHECK(t.smallest_piece >= 0.01);  // no shred in any frame
  CHECK(t.smallest_angle >= 1.5);  // the scripted cut's guarantee (docs/remesher.md)
  CHECK(t.shortest_edge >= 0.1 * median_edge(input));
}

/// A 1 × 0.3 m strip of 50 × 15 jittered quads with alternating diagonals; with a neck, its width
/// narrowed smoothly to 0.18 m around x = 0.3. With `uvs`, corner UVs u = x, v = y / 0.3.
inline tear::Mesh strip_mesh(bool neck, bool uvs = false) {
  tear::Mesh m;
  const int nx = 50, ny = 15;
  std::uint64_t state = 12345;
  const auto jitter = [&]() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return (double((state >> 11) % 1000000) / 1000000 - 0.5) * 0.3;
  };
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      double x = double(i) / nx, y = double(j) / ny;
      if (i > 0 && i < nx) x += jitter() / nx;
      if (j > 0 && j < ny) y += jitter() / ny;
      const double width = 0.3 * (neck ? 1 - 0.4 * std::exp(-std::pow((x - 0.3) / 0.12, 2)) : 1.0);
      m.node_pos.insert(m.node_pos.end(), {float(x), float(0.15 + (y - 0.5) * width), 0.f});
    }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const index_t a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
      const bool flip = (i + j) % 2 == 1;
      const index_t faces[6] = {a, b, flip ? c : d, flip ? b : a, d, c};
      m.face_nodes.insert(m.face_nodes.end(), faces, faces + 6);
    }
  if (uvs)
    for (index_t f = 0; f < m.face_count(); ++f)
      for (int k = 0; k < 3; ++k) {
        const index_t n = m.face_nodes[3 * f + k];
        m.corner_uv.push_back(m.node_pos[3 * n]);
        m.corner_uv.push_back(m.node_pos[3 * n + 1] / 0.3f);
      }
  return m;
}

}  // namespace tear::test::pulls
