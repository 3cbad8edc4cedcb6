// The face split table checked over every reachable cut state, on real geometry: two triangles
// (one with an obtuse corner), edge points at several parameters, and the face point where the
// straight cut lines actually cross.
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "../kernels/split_table.h"
#include "catch.h"

namespace {

using tear::kernels::point_code;
using tear::kernels::PointKind;
using tear::kernels::SplitCase;
using tear::kernels::to_string_state;

constexpr double pi = 3.14159265358979323846;

struct Vec2 {
  double x, y;
};
Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
double signed_area(Vec2 a, Vec2 b, Vec2 c) { return 0.5 * cross(b - a, c - a); }

int node(int k) { return point_code(PointKind::node, k % 3); }
int edge(int k) { return point_code(PointKind::edge, k % 3); }
const int face = point_code(PointKind::face, 0);

bool has_bit(int state, int bit) { return (state >> bit) & 1; }
bool has_edge_point(int state, int k) { return has_bit(state, k % 3); }
bool has_edge_node_line(int state, int k) { return has_bit(state, 3 + k); }
bool has_edge_edge_line(int state, int k) { return has_bit(state, 6 + k); }

/// The reachability rule, written here again from its definition.
bool reachable(int state) {
  for (int k = 0; k < 3; ++k) {
    if (has_edge_node_line(state, k) && !has_edge_point(state, k)) return false;
    if (has_edge_edge_line(state, k) && !(has_edge_point(state, k + 1) && has_edge_point(state, k + 2))) return false;
  }
  return true;
}
int edge_point_count(int state) { return has_bit(state, 0) + has_bit(state, 1) + has_bit(state, 2); }
int edge_node_line_count(int state) { return has_bit(state, 3) + has_bit(state, 4) + has_bit(state, 5); }
int edge_edge_line_count(int state) { return has_bit(state, 6) + has_bit(state, 7) + has_bit(state, 8); }

using Side = std::pair<int, int>;  // point codes
Side unordered(int a, int b) { return a < b ? Side{a, b} : Side{b, a}; }

/// One face of the test with its cut state laid out: point positions by code, the straight cut
/// lines, where they cross, and the cut-line pieces the split must keep.
struct Face {
  int state = 0;
  std::map<int, Vec2> point;  // present points only
  std::vector<Side> lines;
  bool lines_cross = false;
  std::set<Side> pieces;
  std::vector<int> boundary;  // ccw: N0 [E2] N1 [E0] N2 [E1]
  double area = 0;

  Face(int state_, const Vec2 (&node_pos)[3], const double (&edge_t)[3]) : state(state_) {
    for (int k = 0; k < 3; ++k) point[node(k)] = node_pos[k];
    for (int k = 0; k < 3; ++k) {
      if (!has_edge_point(state, k)) continue;
      const Vec2 a = node_pos[(k + 1) % 3], b = node_pos[(k + 2) % 3];
      point[edge(k)] = {a.x + edge_t[k] * (b.x - a.x), a.y + edge_t[k] * (b.y - a.y)};
    }
    for (int k = 0; k < 3; ++k)
      if (has_edge_node_line(state, k)) lines.push_back({edge(k), node(k)});
    for (int k = 0; k < 3; ++k)
      if (has_edge_edge_line(state, k)) lines.push_back({edge(k + 1), edge(k + 2)});

    // P: the average of the proper crossings of the straight lines.
    Vec2 sum{0, 0};
    int crossings = 0;
    for (size_t i = 0; i < lines.size(); ++i) {
      for (size_t j = i + 1; j < lines.size(); ++j) {
        const Vec2 a = point[lines[i].first], b = point[lines[i].second];
        const Vec2 c = point[lines[j].first], d = point[lines[j].second];
        const double c_side = cross(b - a, c - a), d_side = cross(b - a, d - a);
        const double a_side = cross(d - c, a - c), b_side = cross(d - c, b - c);
        const double scale = 1e-12 * dot(b - a, b - a) * dot(d - c, d - c);
        if (!(c_side * d_side < -scale && a_side * b_side < -scale)) continue;  // shared end or apart
        const double s = a_side / (a_side - b_side);
        sum.x += a.x + s * (b.x - a.x);
        sum.y += a.y + s * (b.y - a.y);
        ++crossings;
      }
    }
    lines_cross = crossings > 0;
    if (lines_cross) point[face] = {sum.x / crossings, sum.y / crossings};
    for (const Side& line : lines) {
      if (lines_cross) {
        pieces.insert(unordered(face, line.first));
        pieces.insert(unordered(face, line.second));
      } else {
        pieces.insert(unordered(line.first, line.second));
      }
    }
    for (int k = 0; k < 3; ++k) {
      boundary.push_back(node(k));
      if (has_edge_point(state, k + 2)) boundary.push_back(edge(k + 2));
    }
    area = signed_area(node_pos[0], node_pos[1], node_pos[2]);
  }

  bool present(int code) const { return point.count(code) != 0; }
  Vec2 at(int code) const { return point.at(code); }
  int boundary_next(int code) const {
    for (size_t i = 0; i < boundary.size(); ++i)
      if (boundary[i] == code) return boundary[(i + 1) % boundary.size()];
    return -1;
  }
  int boundary_prev(int code) const {
    for (size_t i = 0; i < boundary.size(); ++i)
      if (boundary[i] == code) return boundary[(i + boundary.size() - 1) % boundary.size()];
    return -1;
  }
  /// Local edge k holds the side (a, b) when both ends lie on it; -1 when none does.
  int boundary_edge_of(int a, int b) const {
    for (int k = 0; k < 3; ++k) {
      const std::set<int> on_edge{node(k + 1), node(k + 2), edge(k)};
      if (on_edge.count(a) && on_edge.count(b)) return k;
    }
    return -1;
  }
};

struct Geometry {
  const char* name;
  Vec2 node_pos[3];
  double edge_t[3];
};

// A scalene acute-ish triangle and one with an obtuse corner at N2, each with edge points at
// midpoints and at uneven parameters.
const Geometry geometries[] = {
    {"scalene, midpoints", {{0, 0}, {4, 0.5}, {1.2, 3}}, {0.5, 0.5, 0.5}},
    {"scalene, uneven", {{0, 0}, {4, 0.5}, {1.2, 3}}, {0.3, 0.62, 0.45}},
    {"scalene, near nodes", {{0, 0}, {4, 0.5}, {1.2, 3}}, {0.17, 0.81, 0.93}},
    {"scalene, mixed", {{0, 0}, {4, 0.5}, {1.2, 3}}, {0.9, 0.08, 0.35}},
    {"obtuse, midpoints", {{0, 0}, {6, 0.4}, {1.0, 1.1}}, {0.5, 0.5, 0.5}},
    {"obtuse, uneven", {{0, 0}, {6, 0.4}, {1.0, 1.1}}, {0.3, 0.62, 0.45}},
    {"obtuse, near nodes", {{0, 0}, {6, 0.4}, {1.0, 1.1}}, {0.17, 0.81, 0.93}},
    {"obtuse, mixed", {{0, 0}, {6, 0.4}, {1.0, 1.1}}, {0.9, 0.08, 0.35}},
};

std::vector<int> reachable_states() {
  std::vector<int> states;
  for (int state = 0; state < tear::kernels::face_cut_state_count; ++state)
    if (reachable(state)) states.push_back(state);
  return states;
}

const SplitCase& split_of(int state, int variant) {
  return tear::kernels::split_table()[tear::kernels::face_split_code(state, variant)];
}

/// Every split of every reachable state: (state, variant).
std::vector<std::pair<int, int>> reachable_splits() {
  std::vector<std::pair<int, int>> splits;
  for (int state : reachable_states())
    for (int v = 0; v < split_of(state, 0).variant_count; ++v) splits.push_back({state, v});
  return splits;
}

/// The triangles of a split as rotation-free keys (corners rotated to start at the lowest code).
std::set<std::vector<int>> triangle_set(const SplitCase& c) {
  std::set<std::vector<int>> tris;
  for (int t = 0; t < c.tri_count; ++t) {
    int first = 0;
    for (int s = 1; s < 3; ++s)
      if (c.tri[t][s] < c.tri[t][first]) first = s;
    tris.insert({c.tri[t][first], c.tri[t][(first + 1) % 3], c.tri[t][(first + 2) % 3]});
  }
  return tris;
}

/// Counter-clockwise angle from direction `from` to direction `to`, in [0, 2 pi).
double ccw_angle(Vec2 from, Vec2 to) {
  double angle = std::atan2(cross(from, to), dot(from, to));
  if (angle < 0) angle += 2 * pi;
  return angle;
}

}  // namespace

TEST_CASE("split_table: reachable states are marked and the rest are empty", "[split]") {
  const SplitCase* table = tear::kernels::split_table();
  // Reachable: with e edge points, each EN line of a present point and each EE line with both
  // points is free: 1 + 3*2 + 3*(4*2) + 8*8 = 95.
  int expected = 0;
  for (int edges = 0; edges < 8; ++edges) {
    int free_lines = 0;
    for (int k = 0; k < 3; ++k) {
      free_lines += (edges >> k) & 1;
      free_lines += ((edges >> ((k + 1) % 3)) & 1) && ((edges >> ((k + 2) % 3)) & 1);
    }
    expected += 1 << free_lines;
  }
  CHECK(expected == 95);
  int reachable_count = 0;
  const auto is_empty = [](const SplitCase& c) {
    bool empty = c.reachable == 0 && c.tri_count == 0 && c.face_point == 0;
    for (int p = 0; p < 7; ++p) empty = empty && c.fan_count[p] == 0 && c.fan_cut[p] == 0;
    for (int t = 0; t < 6; ++t) empty = empty && c.tri_cut[t] == 0;
    return empty;
  };
  for (int state = 0; state < tear::kernels::face_cut_state_count; ++state) {
    INFO("state " << state << ": " << to_string_state(state));
    const SplitCase& c = table[tear::kernels::face_split_code(state, 0)];
    CHECK(bool(c.reachable) == reachable(state));
    CHECK(tear::kernels::is_reachable_face_cut(state) == reachable(state));
    const int variants = c.variant_count;
    CHECK(variants >= 1);
    CHECK(variants <= tear::kernels::max_split_variants);
    if (c.reachable) {
      ++reachable_count;
      for (int v = 0; v < variants; ++v) {
        INFO("variant " << v);
        const SplitCase& cv = table[tear::kernels::face_split_code(state, v)];
        CHECK(cv.reachable == 1);
        CHECK(cv.variant_count == variants);
        CHECK(cv.tri_count >= 1);
        CHECK(cv.tri_count <= 6);
      }
    } else {
      CHECK(variants == 1);
      CHECK(c.variant_count == 1);
      SplitCase copy = c;
      copy.variant_count = 0;
      CHECK(is_empty(copy));
    }
    // Unused variant slots hold nothing, so a wrong index shows up as a face without triangles.
    for (int v = variants; v < tear::kernels::max_split_variants; ++v) {
      INFO("unused variant " << v);
      const SplitCase& cv = table[tear::kernels::face_split_code(state, v)];
      CHECK(cv.variant_count == 0);
      CHECK(is_empty(cv));
    }
  }
  CHECK(reachable_count == expected);
  CHECK(to_string_state(0) == "none");
  CHECK(to_string_state(0x1 | 0x2 | 0x8 | 0x100) == "E0 E1 EN0 EE2");
}

TEST_CASE("split_table: a face point exactly where the lines cross", "[split]") {
  for (const Geometry& g : geometries) {
    for (const auto& [state, variant] : reachable_splits()) {
      INFO(g.name << ", state " << state << ": " << to_string_state(state) << ", variant " << variant);
      const Face f(state, g.node_pos, g.edge_t);
      CHECK(bool(split_of(state, variant).face_point) == f.lines_cross);
      CHECK(tear::kernels::has_face_point(state) == f.lines_cross);
    }
  }
}

TEST_CASE("split_table: triangles tile the face, counter-clockwise, without T-junctions", "[split]") {
  for (const Geometry& g : geometries) {
    for (const auto& [state, variant] : reachable_splits()) {
      INFO(g.name << ", state " << state << ": " << to_string_state(state) << ", variant " << variant);
      const Face f(state, g.node_pos, g.edge_t);
      const SplitCase& c = split_of(state, variant);

      // Corners are present, distinct points; areas positive and summing to the face.
      bool corners_valid = true;
      for (int t = 0; t < c.tri_count; ++t)
        for (int s = 0; s < 3; ++s)
          corners_valid = corners_valid && f.present(c.tri[t][s]) && c.tri[t][s] != c.tri[t][(s + 1) % 3];
      REQUIRE(corners_valid);
      double area_sum = 0;
      for (int t = 0; t < c.tri_count; ++t) {
        const double a = signed_area(f.at(c.tri[t][0]), f.at(c.tri[t][1]), f.at(c.tri[t][2]));
        INFO("triangle " << t);
        CHECK(a > 1e-9 * f.area);
        area_sum += a;
      }
      CHECK(std::abs(area_sum - f.area) <= 1e-12 * f.area);

      // No point strictly inside a side of a triangle.
      for (int t = 0; t < c.tri_count; ++t) {
        for (int s = 0; s < 3; ++s) {
          const int a = c.tri[t][(s + 1) % 3], b = c.tri[t][(s + 2) % 3];
          const Vec2 pa = f.at(a), ab = f.at(b) - pa;
          for (const auto& [code, q] : f.point) {
            if (code == a || code == b) continue;
            const double along = dot(q - pa, ab) / dot(ab, ab);
            const double off = std::abs(cross(ab, q - pa)) / dot(ab, ab);
            INFO("triangle " << t << " side " << s << ", point code " << code);
            CHECK_FALSE((along > 1e-9 && along < 1 - 1e-9 && off < 1e-9));
          }
        }
      }
      // Every edge point (and P) is a corner.
      for (const auto& entry : f.point) {
        const int code = entry.first;
        bool used = false;
        for (int t = 0; t < c.tri_count; ++t)
          for (int s = 0; s < 3; ++s) used = used || c.tri[t][s] == code;
        INFO("point code " << code);
        CHECK(used);
      }

      // Inner sides are shared by two triangles with opposite directions; boundary sides are
      // exactly the original edges, split at their edge points, each once and in the face's direction.
      std::multiset<Side> directed;
      for (int t = 0; t < c.tri_count; ++t)
        for (int s = 0; s < 3; ++s) directed.insert({c.tri[t][s], c.tri[t][(s + 1) % 3]});
      std::multiset<Side> boundary_sides, expected_boundary;
      for (int k = 0; k < 3; ++k) {
        if (has_edge_point(state, k)) {
          expected_boundary.insert({node(k + 1), edge(k)});
          expected_boundary.insert({edge(k), node(k + 2)});
        } else {
          expected_boundary.insert({node(k + 1), node(k + 2)});
        }
      }
      for (const Side& side : directed) {
        if (f.boundary_edge_of(side.first, side.second) >= 0) {
          boundary_sides.insert(side);
        } else {
          INFO("inner side " << side.first << " -> " << side.second);
          CHECK(directed.count(side) == 1);
          CHECK(directed.count({side.second, side.first}) == 1);
        }
      }
      CHECK(boundary_sides == expected_boundary);
    }
  }
}

TEST_CASE("split_table: every cut-line piece is a triangle side, and tri_cut marks exactly those", "[split]") {
  for (const auto& [state, variant] : reachable_splits()) {
    INFO("state " << state << ": " << to_string_state(state) << ", variant " << variant);
    const Face f(state, geometries[1].node_pos, geometries[1].edge_t);
    const SplitCase& c = split_of(state, variant);
    std::set<Side> sides;
    for (int t = 0; t < c.tri_count; ++t) {
      for (int s = 0; s < 3; ++s) {
        const Side side = unordered(c.tri[t][(s + 1) % 3], c.tri[t][(s + 2) % 3]);
        sides.insert(side);
        INFO("triangle " << t << " side " << s);
        CHECK(bool((c.tri_cut[t] >> s) & 1) == (f.pieces.count(side) == 1));
      }
      CHECK((c.tri_cut[t] >> 3) == 0);
    }
    for (const Side& piece : f.pieces) {
      INFO("piece " << piece.first << " - " << piece.second);
      CHECK(sides.count(piece) == 1);
    }
    for (int t = c.tri_count; t < 6; ++t) CHECK(c.tri_cut[t] == 0);
  }
}

TEST_CASE("split_table: fans list the corners at each point counter-clockwise", "[split]") {
  for (const Geometry& g : geometries) {
    for (const auto& [state, variant] : reachable_splits()) {
      INFO(g.name << ", state " << state << ": " << to_string_state(state) << ", variant " << variant);
      const Face f(state, g.node_pos, g.edge_t);
      const SplitCase& c = split_of(state, variant);
      for (int slot = 0; slot < 7; ++slot) {
        const int code = tear::kernels::slot_point_code(slot);
        INFO("point code " << code);
        CHECK(tear::kernels::point_slot(code) == slot);
        if (!f.present(code)) {
          CHECK(c.fan_count[slot] == 0);
          CHECK(c.fan_cut[slot] == 0);
          continue;
        }
        std::set<std::pair<int, int>> corners, listed;
        for (int t = 0; t < c.tri_count; ++t)
          for (int s = 0; s < 3; ++s)
            if (c.tri[t][s] == code) corners.insert({t, s});
        const int n = c.fan_count[slot];
        REQUIRE(n == static_cast<int>(corners.size()));
        for (int i = 0; i < n; ++i)
          listed.insert(
              {tear::kernels::fan_entry_tri(c.fan[slot][i]), tear::kernels::fan_entry_corner(c.fan[slot][i])});
        REQUIRE(listed == corners);

        // Each corner spans from its next corner to its previous one (ccw); along the fan the
        // spans follow each other, from the start direction round to the end direction.
        const bool is_face = code == face;
        const int start = is_face ? node(0) : f.boundary_next(code);
        const int end = is_face ? node(0) : f.boundary_prev(code);
        const Vec2 p = f.at(code), reference = f.at(start) - p;
        double last_angle = -1;
        int expected_next = start;
        int cut_bits = 0;
        for (int i = 0; i < n; ++i) {
          const int t = tear::kernels::fan_entry_tri(c.fan[slot][i]),
                    s = tear::kernels::fan_entry_corner(c.fan[slot][i]);
          const int next = c.tri[t][(s + 1) % 3], prev = c.tri[t][(s + 2) % 3];
          const double next_angle = ccw_angle(reference, f.at(next) - p);
          const double prev_angle = ccw_angle(reference, f.at(prev) - p);
          INFO("fan entry " << i);
          CHECK(next == expected_next);  // shares a side with the entry before (or starts at the start)
          CHECK(next_angle > last_angle);
          CHECK((prev_angle > next_angle || (is_face && i == n - 1)));
          last_angle = next_angle;
          expected_next = prev;
          const bool shared = i < n - 1 || is_face;
          if (shared && f.pieces.count(unordered(code, prev))) cut_bits |= 1 << i;
        }
        CHECK(expected_next == end);
        CHECK(c.fan_cut[slot] == cut_bits);
      }
    }
  }
}

TEST_CASE("split_table: triangle counts follow the paper's cases", "[split]") {
  for (const auto& [state, variant] : reachable_splits()) {
    INFO("state " << state << ": " << to_string_state(state) << ", variant " << variant);
    const SplitCase& c = split_of(state, variant);
    const int points = edge_point_count(state);
    const int edge_node_lines = edge_node_line_count(state), edge_edge_lines = edge_edge_line_count(state);
    if (c.face_point) {
      CHECK(c.tri_count == 3 + points);  // a fan around P, one triangle per boundary side
    } else if (edge_node_lines == 1) {
      CHECK(c.tri_count == 2 + (points - 1));  // two along the line, each split again at an edge point
    } else if (edge_edge_lines == 1) {
      CHECK(c.tri_count == (points == 3 ? 4 : 3));
    } else if (edge_edge_lines >= 2) {
      CHECK(c.tri_count == 4);
    } else {
      CHECK(c.tri_count == 1 + points);  // no lines: 1, 1->2, 1->3, 1->4
    }
  }
  CHECK(split_of(0, 0).variant_count == 1);
  CHECK(split_of(0, 0).tri_count == 1);
  CHECK(split_of(0, 0).tri[0][0] == node(0));
  CHECK(split_of(0, 0).tri[0][1] == node(1));
  CHECK(split_of(0, 0).tri[0][2] == node(2));

  // Three edge points without lines, or two or three EE lines: the 1-to-4 pattern (three corners
  // and the middle triangle E0 E1 E2) as variant 0; with two EE lines, the diagonal rule picks the
  // side that completes it.
  const std::set<std::set<int>> one_to_four{{node(0), edge(2), edge(1)},
                                            {node(1), edge(0), edge(2)},
                                            {node(2), edge(1), edge(0)},
                                            {edge(0), edge(1), edge(2)}};
  using namespace tear::kernels::face_cut;
  for (int state : {e0 | e1 | e2, e0 | e1 | e2 | ee0 | ee1 | ee2, e0 | e1 | e2 | ee0 | ee1, e0 | e1 | e2 | ee1 | ee2,
                    e0 | e1 | e2 | ee2}) {
    INFO("state " << to_string_state(state));
    const SplitCase& c = split_of(state, 0);
    std::set<std::set<int>> tris;
    for (int t = 0; t < c.tri_count; ++t) tris.insert({c.tri[t][0], c.tri[t][1], c.tri[t][2]});
    CHECK(tris == one_to_four);
  }
}

TEST_CASE("split_table: the documented choices among valid splits", "[split]") {
  using namespace tear::kernels::face_cut;
  const int edge_point_bit[3] = {e0, e1, e2}, edge_edge_bit[3] = {ee0, ee1, ee2};
  for (int k = 0; k < 3; ++k) {
    // EE_k alone with E_k absent leaves the quadrilateral E_{k+2} N_{k+1} N_{k+2} E_{k+1}; its
    // diagonal is N_{k+1}-E_{k+1}.
    const int state = edge_point_bit[(k + 1) % 3] | edge_point_bit[(k + 2) % 3] | edge_edge_bit[k];
    INFO("state " << to_string_state(state));
    const SplitCase& c = split_of(state, 0);
    int diagonal_sides = 0;
    for (int t = 0; t < c.tri_count; ++t)
      for (int s = 0; s < 3; ++s)
        diagonal_sides +=
            unordered(c.tri[t][(s + 1) % 3], c.tri[t][(s + 2) % 3]) == unordered(node(k + 1), edge(k + 1));
    CHECK(diagonal_sides == 2);
  }
  // One or two edge points without lines: the fan starts from the flat edge point with the lowest
  // index (three take the 1-to-4 pattern, above).
  for (int state = 1; state < 7; ++state) {
    INFO("state " << to_string_state(state));
    const int lowest = (state & 1) ? 0 : (state & 2) ? 1 : 2;
    const SplitCase& c = split_of(state, 0);
    for (int t = 0; t < c.tri_count; ++t)
      CHECK((c.tri[t][0] == edge(lowest) || c.tri[t][1] == edge(lowest) || c.tri[t][2] == edge(lowest)));
  }
}

TEST_CASE("split_table: variants of a state are distinct and differ only in the free choices", "[split]") {
  using namespace tear::kernels::face_cut;
  for (int state : reachable_states()) {
    INFO("state " << state << ": " << to_string_state(state));
    const int variants = split_of(state, 0).variant_count;
    for (int v = 0; v < variants; ++v) {
      for (int u = 0; u < v; ++u) {
        INFO("variants " << u << " and " << v);
        CHECK(triangle_set(split_of(state, u)) != triangle_set(split_of(state, v)));
        CHECK(split_of(state, u).face_point == split_of(state, v).face_point);
      }
    }
    // With P the fan around it leaves no choice.
    if (tear::kernels::has_face_point(state)) CHECK(variants == 1);
  }

  // The free choices: both diagonals of the quadrilateral EE_k leaves without E_k; the fan apex
  // among two flat edge points; the 1-to-4 pattern or a fan from any of three flat edge points.
  const int edge_point_bit[3] = {e0, e1, e2}, edge_edge_bit[3] = {ee0, ee1, ee2};
  for (int k = 0; k < 3; ++k) {
    const int state = edge_point_bit[(k + 1) % 3] | edge_point_bit[(k + 2) % 3] | edge_edge_bit[k];
    INFO("state " << to_string_state(state));
    REQUIRE(split_of(state, 0).variant_count == 2);
    const std::vector<int> diagonal_0{std::min(node(k + 1), edge(k + 1)), std::max(node(k + 1), edge(k + 1))};
    const std::vector<int> diagonal_1{std::min(node(k + 2), edge(k + 2)), std::max(node(k + 2), edge(k + 2))};
    for (int v = 0; v < 2; ++v) {
      std::set<std::vector<int>> sides;
      const SplitCase& c = split_of(state, v);
      for (int t = 0; t < c.tri_count; ++t)
        for (int s = 0; s < 3; ++s) {
          const int a = c.tri[t][s], b = c.tri[t][(s + 1) % 3];
          sides.insert({std::min(a, b), std::max(a, b)});
        }
      CHECK(sides.count(v == 0 ? diagonal_0 : diagonal_1) == 1);
      CHECK(sides.count(v == 0 ? diagonal_1 : diagonal_0) == 0);
    }
  }
  for (int state = 1; state < 8; ++state) {
    INFO("state " << to_string_state(state));
    const int points = edge_point_count(state);
    CHECK(split_of(state, 0).variant_count == (points == 1 ? 1 : points == 2 ? 2 : 4));
    // Variants after the first are fans from the flat edge points, lowest index first.
    int v = points == 3 ? 1 : 0;
    for (int k = 0; k < 3; ++k) {
      if (!has_edge_point(state, k)) continue;
      INFO("fan from E" << k << " as variant " << v);
      const SplitCase& c = split_of(state, v++);
      int uses = 0;
      for (int t = 0; t < c.tri_count; ++t)
        uses += c.tri[t][0] == edge(k) || c.tri[t][1] == edge(k) || c.tri[t][2] == edge(k);
      CHECK(uses == c.tri_count);
    }
  }
}

TEST_CASE("split_table: a face's split code carries its state and variant", "[split]") {
  using namespace tear::kernels;
  const SplitCase* table = split_table();
  std::set<unsigned> codes;
  for (int state : reachable_states()) {
    INFO("state " << state << ": " << to_string_state(state));
    // Variant 0 sits at the plain state, so a face state without variant bits takes the rule's split.
    CHECK(face_split_code(state, 0) == static_cast<unsigned>(state));
    for (int v = 0; v < split_of(state, 0).variant_count; ++v) {
      const unsigned code = face_split_code(state, v);
      CHECK(face_split_state(code) == static_cast<unsigned>(state));
      CHECK(face_split_variant(code) == v);
      CHECK(code < static_cast<unsigned>(split_table_size));
      CHECK(split_case(table, code).reachable == 1);
      codes.insert(code);
    }
  }
  CHECK(codes.size() == reachable_splits().size());
}

namespace {

/// The smallest corner angle (degrees) of a split laid out on a face, from the test's own geometry.
double smallest_angle_deg(const SplitCase& c, const Face& f) {
  double smallest = 180;
  for (int t = 0; t < c.tri_count; ++t)
    for (int s = 0; s < 3; ++s) {
      const Vec2 p = f.at(c.tri[t][s]);
      const Vec2 a = f.at(c.tri[t][(s + 1) % 3]) - p, b = f.at(c.tri[t][(s + 2) % 3]) - p;
      smallest = std::min(smallest, std::abs(std::atan2(cross(a, b), dot(a, b))) * 180 / pi);
    }
  return smallest;
}

/// The face's points in 3D slots, on a tilted plane (a rotation and a shift keep every angle).
void point_slots_3d(const Face& f, double (*pos)[3]) {
  const double u[3] = {0.6, 0.0, 0.8}, v[3] = {0.0, 1.0, 0.0}, shift[3] = {10.0, -3.0, 2.5};
  for (int slot = 0; slot < tear::kernels::face_point_slot_count; ++slot) {
    const int code = tear::kernels::slot_point_code(slot);
    // Absent points get a value that would ruin any angle they took part in.
    const Vec2 q = f.present(code) ? f.at(code) : Vec2{1e6, -1e6};
    for (int d = 0; d < 3; ++d) pos[slot][d] = shift[d] + q.x * u[d] + q.y * v[d];
  }
}

}  // namespace

TEST_CASE("split_table: best_split_variant takes the split with the largest smallest angle", "[split]") {
  const SplitCase* table = tear::kernels::split_table();
  int improved = 0;
  for (const Geometry& g : geometries) {
    for (int state : reachable_states()) {
      INFO(g.name << ", state " << state << ": " << to_string_state(state));
      const Face f(state, g.node_pos, g.edge_t);
      double pos[7][3];
      point_slots_3d(f, pos);
      const int chosen = tear::kernels::best_split_variant(table, state, pos);
      const int variants = split_of(state, 0).variant_count;
      REQUIRE(chosen >= 0);
      REQUIRE(chosen < variants);
      const double chosen_angle = smallest_angle_deg(split_of(state, chosen), f);
      for (int v = 0; v < variants; ++v) {
        INFO("variant " << v << " against the chosen " << chosen);
        const double angle = smallest_angle_deg(split_of(state, v), f);
        CHECK(angle <= chosen_angle + 1e-6);
        if (v < chosen) CHECK(angle < chosen_angle - 1e-9);  // a lower variant only loses when worse
      }
      improved += chosen != 0;
    }
  }
  CHECK(improved > 0);  // the geometries above do prefer other variants somewhere

  // Ties keep variant 0: a square's quadrilateral with its edge points at midpoints is symmetric.
  using namespace tear::kernels::face_cut;
  const Geometry right{"right isosceles", {{0, 0}, {1, 0}, {0, 1}}, {0.5, 0.5, 0.5}};
  const int state = e1 | e2 | ee0;
  const Face f(state, right.node_pos, right.edge_t);
  double pos[7][3];
  point_slots_3d(f, pos);
  CHECK(smallest_angle_deg(split_of(state, 0), f) == Approx(smallest_angle_deg(split_of(state, 1), f)));
  CHECK(tear::kernels::best_split_variant(table, state, pos) == 0);

  // A long quadrilateral takes the diagonal that avoids the sliver, whichever variant that is. EE0
  // without E0 leaves E2 N1 N2 E1; variant 0 takes N1-E1, variant 1 N2-E2.
  std::set<int> chosen;
  for (const Geometry& g : {Geometry{"long along edge 2", {{0, 0}, {10, 0}, {0, 1}}, {0.5, 0.5, 0.5}},
                            Geometry{"long along edge 1", {{0, 0}, {1, 0}, {0, 10}}, {0.5, 0.5, 0.5}}}) {
    INFO(g.name);
    const Face lf(state, g.node_pos, g.edge_t);
    point_slots_3d(lf, pos);
    const double angle_0 = smallest_angle_deg(split_of(state, 0), lf),
                 angle_1 = smallest_angle_deg(split_of(state, 1), lf);
    INFO("smallest angles " << angle_0 << " and " << angle_1);
    REQUIRE(std::abs(angle_0 - angle_1) > 1.0);
    const int best = tear::kernels::best_split_variant(table, state, pos);
    CHECK(best == (angle_0 > angle_1 ? 0 : 1));
    chosen.insert(best);
  }
  CHECK(chosen == std::set<int>{0, 1});
}
