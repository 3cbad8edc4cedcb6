// Properties of the remesher over seeded random cloths and cuts: every cut leaves a valid mesh of
// the same area, its new nodes lie on the cuts, UVs stay an interpolation inside one chart, and
// the same input gives the same arrays. TEAR_TEST_SEED reruns one failing seed.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "catch.h"
#include "random_meshes.h"
#include "reference_topology.h"
#include "remesh_checks.h"
#include "tear/cloth.h"
#include "tear/cut_script.h"
#include "tear/make_sheet.h"
#include "tear/read_mesh.h"
#include "test_support.h"

using namespace tear;
using tear::test::Random;

namespace {

using Point = std::array<double, 2>;

/// A cloth to cut, with what is known of it.
struct Subject {
  std::string name;
  Mesh mesh;
  double size = 1;      ///< sheets: side of the square
  bool sheet = false;   ///< flat in z = 0 with UV = (x, y) / size
  bool convex = false;  ///< a whole square sheet
  index_t tube_segments = 0;
  double tube_length = 0;
};

Mesh sheet_mesh(Random& random, bool irregular, double size) {
  SheetOptions o;
  o.face_count = 2 * (60 + random.below(200));  // 120..518 faces
  o.irregular = irregular;
  o.seed = random.bits();
  o.size = size;
  return make_sheet(o);
}

/// A regular or irregular sheet, a sheet with a hole, or a welded tube, chosen by the seed. A
/// sheet whose hole leaves a bow-tie node is replaced by one with a smaller hole.
Subject random_subject(std::uint64_t seed) {
  Random random(seed);
  Subject s;
  const index_t kind = random.below(5);
  if (kind == 4) {
    TubeOptions o;
    o.segments = 6 + random.below(20);
    o.rings = 3 + random.below(10);
    o.radius = random.uniform(0.1, 0.5);
    o.length = random.uniform(0.5, 2.0);
    o.welded = false;
    s.mesh = make_tube(o);
    weld_nodes(s.mesh, 0);
    s.name = "welded tube";
    s.tube_segments = o.segments;
    s.tube_length = o.length;
    return s;
  }
  s.size = random.uniform(0.5, 2.0);
  s.sheet = true;
  s.mesh = sheet_mesh(random, kind != 0, s.size);
  s.name = kind == 0 ? "regular sheet" : "irregular sheet";
  s.convex = kind <= 1;
  if (kind >= 2) {
    s.name += " with a hole";
    const double cx = random.uniform(0.3, 0.7) * s.size, cy = random.uniform(0.3, 0.7) * s.size;
    for (double r = random.uniform(0.1, 0.25); r > 0.01; r *= 0.8) {
      Mesh holed = tear::test::cut_disc_hole(s.mesh, cx, cy, r * s.size);
      if (holed.face_count() < s.mesh.face_count() && validate_mesh(holed, Device::cpu).ok()) {
        s.mesh = std::move(holed);
        break;
      }
    }
  }
  return s;
}

Point random_point(Random& random, double lo, double hi) { return {random.uniform(lo, hi), random.uniform(lo, hi)}; }

std::array<double, 3> random_unit(Random& random) {
  for (;;) {
    const std::array<double, 3> v{random.uniform(-1, 1), random.uniform(-1, 1), random.uniform(-1, 1)};
    const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (len > 0.1 && len <= 1) return {v[0] / len, v[1] / len, v[2] / len};
  }
}

/// A random cut for the subject: a polyline of 2..6 points (rest xy for sheets, UV for the tube)
/// reaching past the cloth, a world-space blade, or a plane.
CutLine random_cut(Random& random, const Subject& s) {
  const index_t kind = random.below(4);
  if (kind <= 1) {
    // Points anywhere, or on nodes (a cut through nodes), or on a node of a face of the previous
    // node (a cut along an edge).
    const index_t points = 2 + random.below(5);
    const Mesh& m = s.mesh;
    auto corner_point = [&](std::size_t corner) -> Point {
      if (s.sheet)
        return {m.node_pos[3 * std::size_t(m.face_nodes[corner])],
                m.node_pos[3 * std::size_t(m.face_nodes[corner]) + 1]};
      return {m.corner_uv[2 * corner], m.corner_uv[2 * corner + 1]};
    };
    std::vector<Point> line;
    std::size_t corner = 0;
    bool on_node = false;
    for (index_t i = 0; i < points; ++i) {
      const double r = random.uniform();
      if (on_node && r < 0.3) {
        const std::size_t f = corner / 3;  // along an edge of the previous node's face
        corner = 3 * f + (corner % 3 + 1 + std::size_t(random.below(2))) % 3;
        line.push_back(corner_point(corner));
      } else if (r < 0.5) {
        corner = std::size_t(random.below(3 * m.face_count()));
        on_node = true;
        line.push_back(corner_point(corner));
      } else {
        on_node = false;
        line.push_back(s.sheet ? random_point(random, -0.3 * s.size, 1.3 * s.size) : random_point(random, -0.2, 1.2));
      }
    }
    return s.sheet ? tear::test::cut_rest_xy(line) : tear::test::cut_uv(line);
  }
  // World-space cuts through the cloth's box.
  const double extent = s.sheet ? s.size : std::max(s.tube_length, 1.0);
  tear::Cut cut;
  if (kind == 2) {
    cut.kind = CutKind::plane;
    cut.point = {random.uniform(0, extent), random.uniform(0, extent), s.sheet ? 0.0 : random.uniform(-0.3, 0.3)};
    cut.normal = random_unit(random);
  } else {
    cut.kind = CutKind::blade;
    cut.direction = random_unit(random);
    const index_t points = 2 + random.below(3);
    for (index_t i = 0; i < points; ++i)
      cut.polyline3.push_back(
          {random.uniform(-0.3, 1.3) * extent, random.uniform(-0.3, 1.3) * extent, random.uniform(-0.5, 0.5)});
  }
  return to_cut_line(cut);
}

// --- 2D geometry of cuts, independent of the kernels ---

/// Parameter range of segment i of a cut (unbounded ends open wide).
void segment_range(const CutLine& c, std::size_t i, double& lo, double& hi) {
  lo = (i == 0 && c.unbounded_start) ? -1e300 : 0.0;
  hi = (i + 2 == c.polyline.size() && c.unbounded_end) ? 1e300 : 1.0;
}

/// Parameters t along a→b where the cut crosses it (t in [0, 1]).
void crossings(const CutLine& c, Point a, Point b, std::vector<double>& out) {
  for (std::size_t i = 0; i + 1 < c.polyline.size(); ++i) {
    const Point p = c.polyline[i], q = c.polyline[i + 1];
    const double rx = b[0] - a[0], ry = b[1] - a[1], sx = q[0] - p[0], sy = q[1] - p[1];
    const double d = rx * sy - ry * sx;
    if (d == 0) continue;
    const double t = ((p[0] - a[0]) * sy - (p[1] - a[1]) * sx) / d;
    const double u = ((p[0] - a[0]) * ry - (p[1] - a[1]) * rx) / d;
    double lo, hi;
    segment_range(c, i, lo, hi);
    const double eps = 1e-7;
    if (t >= -eps && t <= 1 + eps && u >= lo - eps && u <= hi + eps) out.push_back(t);
  }
}

/// Distance from x to the cut's polyline (its unbounded ends included).
double distance_to_cut(const CutLine& c, Point x) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < c.polyline.size(); ++i) {
    const Point p = c.polyline[i], q = c.polyline[i + 1];
    const double dx = q[0] - p[0], dy = q[1] - p[1], len2 = dx * dx + dy * dy;
    double lo, hi;
    segment_range(c, i, lo, hi);
    const double u = len2 > 0 ? std::clamp(((x[0] - p[0]) * dx + (x[1] - p[1]) * dy) / len2, lo, hi) : 0.0;
    best = std::min(best, std::hypot(p[0] + u * dx - x[0], p[1] + u * dy - x[1]));
  }
  return best;
}

/// Corner k of face f of the mesh before a cut, in a cut's 2D space.
struct Projector {
  const Mesh& mesh;
  const std::vector<float>& rest;
  Point operator()(const CutLine& c, index_t f, int k) const {
    const std::size_t corner = 3 * std::size_t(f) + k;
    if (c.source == CutLine::Source::corner_uv) return {mesh.corner_uv[2 * corner], mesh.corner_uv[2 * corner + 1]};
    const float* p =
        &(c.source == CutLine::Source::node_rest ? rest : mesh.node_pos)[3 * std::size_t(mesh.face_nodes[corner])];
    return {p[0] * c.axis_u[0] + p[1] * c.axis_u[1] + p[2] * c.axis_u[2],
            p[0] * c.axis_v[0] + p[1] * c.axis_v[1] + p[2] * c.axis_v[2]};
  }
};

double length(Point a, Point b) { return std::hypot(a[0] - b[0], a[1] - b[1]); }

/// The new nodes of a frame lie where its cuts put them, in the cuts' own 2D spaces:
/// - an edge point (two sources) lies on its old edge at a parameter inside the range of the
///   frame's crossings with that edge (exactly at the crossing when there is one; the average when
///   several cuts or several segments cross it), within 1e-5 of the parameter;
/// - a face point (three sources) lies inside its old face, at least about face_point_min_bary
///   from its sides, with weights summing to 1;
/// - an old node that splits lies within snap x (its longest edge) of a cut: it is on a cut
///   or a crossing was snapped onto it.
void check_new_nodes_on_cuts(const Mesh& before, const Topology& topo_before, const std::vector<float>& rest_before,
                             const Cloth& cloth, const std::vector<CutLine>& cuts, double snap) {
  const CutProvenance prov = cloth.provenance();
  const Projector project{before, rest_before};
  const index_t new_nodes = cloth.node_count();
  REQUIRE(prov.node_source.size() == 3 * std::size_t(new_nodes));
  // Faces of the old mesh around each old node, and for each old edge, from the topology.
  auto faces_with = [&](index_t a, index_t b, std::vector<std::pair<index_t, std::array<int, 2>>>& out) {
    out.clear();
    for (index_t i = topo_before.node_face_offset[a]; i < topo_before.node_face_offset[a + 1]; ++i) {
      const index_t f = topo_before.node_faces[i];
      int ka = -1, kb = -1;
      for (int k = 0; k < 3; ++k) {
        if (before.face_nodes[3 * f + k] == a) ka = k;
        if (before.face_nodes[3 * f + k] == b) kb = k;
      }
      if (kb >= 0 || b < 0) out.push_back({f, {ka, kb}});
    }
  };
  std::vector<std::pair<index_t, std::array<int, 2>>> faces;
  std::vector<index_t> copies(std::size_t(before.node_count()), 0);
  std::size_t edge_bad = 0, face_bad = 0, node_bad = 0, edge_points = 0;
  double worst_edge = 0;
  for (index_t n = 0; n < new_nodes; ++n) {
    const index_t* src = &prov.node_source[3 * std::size_t(n)];
    const float* w = &prov.node_source_weight[3 * std::size_t(n)];
    if (src[1] < 0) {
      ++copies[src[0]];
      continue;
    }
    if (src[2] < 0) {  // an edge point
      ++edge_points;
      const double t = w[1];
      faces_with(src[0], src[1], faces);
      double lo = 2, hi = -1;
      std::vector<double> ts;
      for (const auto& [f, k] : faces)
        for (const CutLine& c : cuts) {
          ts.clear();
          crossings(c, project(c, f, k[0]), project(c, f, k[1]), ts);
          for (double x : ts) {
            lo = std::min(lo, x);
            hi = std::max(hi, x);
          }
        }
      const double err = t < lo ? lo - t : t > hi ? t - hi : 0.0;
      worst_edge = std::max(worst_edge, hi < lo ? 1.0 : err);
      if (hi < lo || err > 1e-5) {
        ++edge_bad;
        UNSCOPED_INFO("edge point " << n << " on old edge " << src[0] << "-" << src[1] << " at t " << t
                                    << ", crossings in [" << lo << ", " << hi << "]");
      }
    } else {  // a face point
      const double sum = double(w[0]) + w[1] + w[2];
      if (std::abs(sum - 1) > 1e-5 || std::min({w[0], w[1], w[2]}) < 0.07f) ++face_bad;
    }
  }
  // Split old nodes: within snap x (longest incident edge) of some cut, in the cut's space; or
  // within the quality snap, which may move a point that would leave a sharp triangle.
  const double reach = snap > 0 ? std::max(snap, CutOptions{}.quality_snap) : 0.0;
  for (index_t a = 0; a < before.node_count(); ++a) {
    if (copies[a] < 2) continue;
    faces_with(a, -1, faces);
    double best = std::numeric_limits<double>::infinity();
    for (const CutLine& c : cuts)
      for (const auto& [f, k] : faces) {
        const Point x = project(c, f, k[0]);
        const double longest =
            std::max(length(x, project(c, f, (k[0] + 1) % 3)), length(x, project(c, f, (k[0] + 2) % 3)));
        best = std::min(best, distance_to_cut(c, x) - (reach + 1e-5) * longest);
      }
    if (best > 0) {
      ++node_bad;
      UNSCOPED_INFO("old node " << a << " split into " << copies[a] << " but lies " << best
                                << " beyond snap reach of every cut");
    }
  }
  INFO(edge_points << " edge points, worst parameter error " << worst_edge);
  CHECK(edge_bad == 0);
  CHECK(face_bad == 0);
  CHECK(node_bad == 0);
}

/// Tube: v = y / length at every corner (y is affine along the tube), and no face's u spans more
/// than one segment (nothing interpolated across the seam).
void check_tube_uv(const Mesh& m, const Subject& s) {
  std::size_t bad_v = 0, bad_u = 0;
  for (index_t f = 0; f < m.face_count(); ++f) {
    double lo = 2, hi = -2;
    for (int k = 0; k < 3; ++k) {
      const std::size_t c = 3 * std::size_t(f) + k;
      lo = std::min(lo, double(m.corner_uv[2 * c]));
      hi = std::max(hi, double(m.corner_uv[2 * c]));
      if (std::abs(m.corner_uv[2 * c + 1] - m.node_pos[3 * std::size_t(m.face_nodes[c]) + 1] / s.tube_length) > 1e-5)
        ++bad_v;
    }
    if (hi - lo > 1.0 / s.tube_segments + 1e-6) ++bad_u;
  }
  CHECK(bad_v == 0);
  CHECK(bad_u == 0);
}

/// The random frames of one seed: 1..3 frames of 1..2 cuts.
std::vector<std::vector<CutLine>> random_frames(Random& random, const Subject& s) {
  std::vector<std::vector<CutLine>> frames(std::size_t(1 + random.below(3)));
  for (auto& frame : frames) {
    const index_t cuts = 1 + random.below(2);
    for (index_t i = 0; i < cuts; ++i) frame.push_back(random_cut(random, s));
  }
  return frames;
}

constexpr int subject_count = 200;

}  // namespace

TEST_CASE("remesh properties: random cuts on random cloths keep every invariant", "[remesh][property]") {
  const std::uint64_t base = tear::test::test_seed(1);
  const bool one_seed = std::getenv("TEAR_TEST_SEED") != nullptr;
  for (int i = 0; i < (one_seed ? 1 : subject_count); ++i) {
    const std::uint64_t seed = base + std::uint64_t(i);
    INFO("seed " << seed);
    Random random(seed);
    const Subject s = random_subject(random.bits());
    INFO(s.name << ", " << s.mesh.face_count() << " faces");
    REQUIRE(validate_mesh(s.mesh, Device::cpu).ok());
    const double snap = random.chance(0.25) ? 0.0 : default_snap;
    INFO("snap " << snap);
    Cloth cloth(s.mesh, tear::test::test_device());
    const double area = tear::test::total_area(s.mesh);
    const auto frames = random_frames(random, s);
    for (std::size_t frame = 0; frame < frames.size(); ++frame) {
      INFO("frame " << frame + 1 << " of " << frames.size() << ", " << frames[frame].size() << " cuts");
      const Mesh before = cloth.mesh();
      const Topology topo_before = cloth.topology();
      const std::vector<float> rest_before = cloth.node_rest();
      const CutStats stats = cloth.cut(frames[frame], CutOptions{snap});
      tear::test::check_valid_after_cut(cloth, area, tear::test::test_device());
      const Mesh after = cloth.mesh();
      // The cut patches the topology where it changed faces: the same arrays as a build.
      CHECK(tear::test::topology_difference(cloth.topology(), build_topology(after, tear::test::test_device())) == "");
      if (stats.nodes_after != stats.nodes_before || stats.faces_after != stats.faces_before)
        check_new_nodes_on_cuts(before, topo_before, rest_before, cloth, frames[frame], snap);
      else
        tear::test::check_same_mesh(after, before);
      if (s.sheet) tear::test::check_uv_is_xy(after, s.size);
      if (s.tube_segments) check_tube_uv(after, s);
    }
  }
}

TEST_CASE("remesh properties: cuts across large sheets patch the topology a build would make", "[remesh][property]") {
  // Sheets whose cuts sum their counts in one tile, in several and on the whole device (CUDA).
  for (const index_t faces : {20000, 80000}) {
    SheetOptions o;
    o.face_count = faces;
    Cloth cloth(make_sheet(o), tear::test::test_device());
    INFO(faces << " faces");
    for (int frame = 0; frame < 2; ++frame) {
      const double y = 0.3 + 0.4 * frame;
      const CutStats stats = cloth.cut({tear::test::cut_rest_xy({{-0.1, y}, {0.5, y + 0.05}, {1.1, y - 0.05}})});
      CHECK(stats.faces_after > stats.faces_before);
      CHECK(tear::test::topology_difference(cloth.topology(), build_topology(cloth.mesh(), tear::test::test_device())) ==
            "");
    }
  }
}

TEST_CASE("remesh properties: cuts beside and through a node of hundreds of faces patch the topology a build would "
          "make",
          "[remesh][property]") {
  // A disc fanned from its centre: the centre's edges are too many for one pass over its faces, so
  // the patch sorts its half-edges, whether the cut splits the centre or passes beside it.
  const index_t rim = 300;
  Mesh disc;
  disc.node_pos = {0, 0, 0};
  for (index_t i = 0; i < rim; ++i) {
    const double a = 6.283185307179586 * i / rim;
    disc.node_pos.insert(disc.node_pos.end(), {float(std::cos(a)), float(std::sin(a)), 0.0f});
  }
  for (index_t i = 0; i < rim; ++i) disc.face_nodes.insert(disc.face_nodes.end(), {0, 1 + i, 1 + (i + 1) % rim});
  for (const double y : {0.5, 0.0013}) {
    INFO("cut at y = " << y);
    Cloth cloth(disc, tear::test::test_device());
    const CutStats stats = cloth.cut({tear::test::cut_rest_xy({{-1.5, y}, {1.5, y + 0.01}})});
    CHECK(stats.faces_after > stats.faces_before);
    CHECK(tear::test::topology_difference(cloth.topology(), build_topology(cloth.mesh(), tear::test::test_device())) ==
          "");
    CHECK(tear::test::topology_difference(cloth.topology(), tear::test::reference_topology(cloth.mesh())) == "");
  }
}

TEST_CASE("remesh properties: a straight line across a sheet makes two pieces and twice its length of border",
          "[remesh][property]") {
  // The tear is a path of chords, one per face crossed, from border to border; both sides of it
  // become border, so the border grows by twice the path's length P. Exact crossings lie on the
  // line; a crossing within snap x (edge length) of a node moves onto the node. Moving one point
  // of a path by d changes its length by at most 2 d, so |P - L| <= 2 N snap h, where L is the
  // line's chord inside the square, N the number of old nodes on the path (the nodes that split)
  // and h the longest edge. With snap 0 the path is the line itself: P = L up to float rounding.
  const std::uint64_t base = tear::test::test_seed(1000);
  const bool one_seed = std::getenv("TEAR_TEST_SEED") != nullptr;
  for (int i = 0; i < (one_seed ? 1 : 100); ++i) {
    const std::uint64_t seed = base + std::uint64_t(i);
    INFO("seed " << seed);
    Random random(seed);
    const double size = random.uniform(0.5, 2.0);
    const bool irregular = random.chance(0.7);
    const Mesh mesh = sheet_mesh(random, irregular, size);
    const double snap = random.chance(0.5) ? 0.0 : default_snap;
    INFO((irregular ? "irregular" : "regular") << " sheet, " << mesh.face_count() << " faces, snap " << snap);
    // A line through a point of the middle of the square, long enough to leave it both ways.
    const Point c{random.uniform(0.2, 0.8) * size, random.uniform(0.2, 0.8) * size};
    const double angle = random.uniform(0, 3.14159265358979323846);
    const Point d{std::cos(angle), std::sin(angle)};
    const CutLine line = tear::test::cut_rest_xy(
        {{c[0] - 2 * size * d[0], c[1] - 2 * size * d[1]}, {c[0] + 2 * size * d[0], c[1] + 2 * size * d[1]}});
    // Its chord inside [0, size]^2 (Liang-Barsky).
    double t0 = -2 * size, t1 = 2 * size;
    for (int axis = 0; axis < 2; ++axis) {
      if (d[axis] == 0) continue;
      double a = (0 - c[axis]) / d[axis], b = (size - c[axis]) / d[axis];
      if (a > b) std::swap(a, b);
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
    }
    const double chord = t1 - t0;
    const Topology topo = build_topology(mesh, Device::cpu);
    double longest = 0;
    for (index_t e = 0; e < topo.edge_count; ++e) {
      const float* a = &mesh.node_pos[3 * std::size_t(topo.edge_nodes[2 * e])];
      const float* b = &mesh.node_pos[3 * std::size_t(topo.edge_nodes[2 * e + 1])];
      longest = std::max(longest, std::hypot(double(a[0]) - b[0], double(a[1]) - b[1]));
    }

    Cloth cloth(mesh, tear::test::test_device());
    const CutStats stats = cloth.cut({line}, CutOptions{snap});
    const MeshInfo info = tear::test::check_valid_after_cut(cloth, size * size, tear::test::test_device());
    CHECK(info.components == 2);
    CHECK(info.boundary_loops == 2);
    const CutProvenance prov = cloth.provenance();
    std::vector<index_t> copies(std::size_t(mesh.node_count()), 0);
    index_t inside_edges = 0;
    for (index_t n = 0; n < cloth.node_count(); ++n) {
      if (prov.node_source[3 * std::size_t(n) + 1] < 0) ++copies[prov.node_source[3 * std::size_t(n)]];
      if (prov.node_source[3 * std::size_t(n) + 1] >= 0 && prov.node_source[3 * std::size_t(n) + 2] < 0) ++inside_edges;
    }
    // The cut's summary: one line crosses itself nowhere, and each point it leaves inside an edge
    // becomes a node on either side.
    CHECK(stats.face_points == 0);
    CHECK(2 * stats.edge_points == inside_edges);
    const auto on_path = std::count_if(copies.begin(), copies.end(), [](index_t k) { return k >= 2; });
    const double path =
        0.5 * (tear::test::boundary_length(cloth.mesh(), cloth.topology()) - tear::test::boundary_length(mesh, topo));
    INFO("chord " << chord << ", path " << path << ", nodes on the path " << on_path << ", longest edge " << longest);
    CHECK(std::abs(path - chord) <= 2.0 * double(on_path) * snap * longest + 1e-5 * chord);
  }
}

TEST_CASE("remesh properties: the smallest angle after cuts on irregular sheets with the default snap",
          "[remesh][property]") {
  // Irregular sheets have angles of at least sheet_min_angle_deg (14); the default snap keeps
  // every edge piece at least 0.2 of its edge, which bounds how thin one split can get, and the
  // quality snap (CutOptions::quality_angle_deg) moves a point within 0.3 of a node onto it where
  // a split would go under 5 degrees; neither bounds how thin splits of splits get over several
  // frames. Measured over seeds 2000..3999 (1 to 3 frames of random polylines): 1.93 degrees at
  // worst (1.03 before the quality snap). The documented bound is 1.5 degrees
  // (docs/remesher.md).
  const std::uint64_t base = tear::test::test_seed(2000);
  const bool one_seed = std::getenv("TEAR_TEST_SEED") != nullptr;
  double worst = 180;
  std::uint64_t worst_seed = 0;
  for (int i = 0; i < (one_seed ? 1 : 150); ++i) {
    const std::uint64_t seed = base + std::uint64_t(i);
    INFO("seed " << seed);
    Random random(seed);
    Subject s;
    s.size = 1;
    s.sheet = true;
    s.mesh = sheet_mesh(random, true, 1.0);
    Cloth cloth(s.mesh, tear::test::test_device());
    for (const auto& frame : random_frames(random, s)) {
      cloth.cut(frame);
      const double angle = tear::test::min_angle_deg(cloth.mesh());
      CHECK(angle >= 1.5);
      if (angle < worst) {
        worst = angle;
        worst_seed = seed;
      }
    }
  }
  INFO("worst smallest angle " << worst << " degrees, seed " << worst_seed);
  CHECK(worst >= 1.5);
}

TEST_CASE("remesh properties: the same cuts on two fresh cloths give the same arrays", "[remesh][property]") {
  const std::uint64_t base = tear::test::test_seed(3000);
  const bool one_seed = std::getenv("TEAR_TEST_SEED") != nullptr;
  for (int i = 0; i < (one_seed ? 1 : 40); ++i) {
    const std::uint64_t seed = base + std::uint64_t(i);
    INFO("seed " << seed);
    Random random(seed);
    const Subject s = random_subject(random.bits());
    const auto frames = random_frames(random, s);
    Cloth a(s.mesh, tear::test::test_device()), b(s.mesh, tear::test::test_device());
    for (const auto& frame : frames) {
      a.cut(frame);
      b.cut(frame);
    }
    tear::test::check_same_mesh(a.mesh(), b.mesh());
    CHECK(a.node_rest() == b.node_rest());
    const CutProvenance pa = a.provenance(), pb = b.provenance();
    CHECK(pa.node_source == pb.node_source);
    CHECK(pa.node_source_weight == pb.node_source_weight);
    CHECK(pa.face_parent == pb.face_parent);
  }
}

TEST_CASE("remesh properties: a straight cut again changes nothing", "[remesh][property]") {
  // A straight cut's tear runs through exact crossings and snapped nodes; cutting again along the
  // same line meets the same nodes and the tear's border, so nothing is left to split. (Two cuts
  // crossing in one face share an averaged edge point off both lines, so retracing those may
  // split more: the resolution the paper's truncated cut info trades away.)
  const std::uint64_t base = tear::test::test_seed(4000);
  const bool one_seed = std::getenv("TEAR_TEST_SEED") != nullptr;
  for (int i = 0; i < (one_seed ? 1 : 100); ++i) {
    const std::uint64_t seed = base + std::uint64_t(i);
    INFO("seed " << seed);
    Random random(seed);
    const Subject s = random_subject(random.bits());
    INFO(s.name << ", " << s.mesh.face_count() << " faces");
    const double snap = random.chance(0.25) ? 0.0 : default_snap;
    INFO("snap " << snap);
    CutLine line = random_cut(random, s);
    if (line.polyline.size() > 2) line.polyline.resize(2);  // straight: one segment
    const std::vector<CutLine> frame{line};
    Cloth cloth(s.mesh, tear::test::test_device());
    cloth.cut(frame, CutOptions{snap});
    const Mesh once = cloth.mesh();
    const CutStats again = cloth.cut(frame, CutOptions{snap});
    CHECK(again.nodes_after == again.nodes_before);
    CHECK(again.faces_after == again.faces_before);
    tear::test::check_same_mesh(cloth.mesh(), once);
  }
}
