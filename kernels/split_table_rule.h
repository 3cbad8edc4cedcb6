// tear kernels: the face split table (paper §2.3, §2.4) with its variants, generated at compile
// time from the split rule of docs/split-table.md. A logic error in the rule is a `throw` reached
// during constant evaluation, so it stops the build instead of producing a wrong table.
// Included at the end of split_table.h, which declares what it defines.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "split_table.h"

namespace tear::kernels {
namespace split_rule {

constexpr std::uint8_t node_code(int k) { return point_code(PointKind::node, k % 3); }
constexpr std::uint8_t edge_code(int k) { return point_code(PointKind::edge, k % 3); }
constexpr std::uint8_t face_code = point_code(PointKind::face, 0);

constexpr bool is_edge_point(std::uint8_t code) { return point_kind(code) == PointKind::edge; }
constexpr bool is_node(std::uint8_t code) { return point_kind(code) == PointKind::node; }

/// A convex polygon of point codes, counter-clockwise. The face boundary has at most 6 corners.
struct Polygon {
  std::uint8_t corner[6] = {};
  int count = 0;
  constexpr std::uint8_t at(int i) const { return corner[((i % count) + count) % count]; }
  constexpr int find(std::uint8_t code) const {
    for (int i = 0; i < count; ++i)
      if (corner[i] == code) return i;
    return -1;
  }
};

/// The cut-line pieces of a face as unordered point pairs (duplicates allowed): at most 6 lines,
/// each two pieces when they meet at P.
struct Pieces {
  std::uint8_t end[12][2] = {};
  int count = 0;
  constexpr void add(std::uint8_t a, std::uint8_t b) {
    end[count][0] = a;
    end[count][1] = b;
    ++count;
  }
  constexpr bool contains(std::uint8_t a, std::uint8_t b) const {
    for (int i = 0; i < count; ++i)
      if ((end[i][0] == a && end[i][1] == b) || (end[i][0] == b && end[i][1] == a)) return true;
    return false;
  }
};

/// The face boundary, counter-clockwise: N0 [E2] N1 [E0] N2 [E1].
constexpr Polygon boundary_polygon(unsigned state) {
  Polygon p;
  for (int k = 0; k < 3; ++k) {
    p.corner[p.count++] = node_code(k);
    const int e = (k + 2) % 3;  // the edge from N_k to N_{k+1}
    if (state & face_cut_edge_point(e)) p.corner[p.count++] = edge_code(e);
  }
  return p;
}

/// Each line as its two end points, in the fixed order EN0..EN2, EE0..EE2.
struct Lines {
  std::uint8_t end[6][2] = {};
  int count = 0;
};
constexpr Lines face_lines(unsigned state) {
  Lines lines;
  for (int k = 0; k < 3; ++k) {
    if (state & face_cut_edge_node_line(k)) {
      lines.end[lines.count][0] = edge_code(k);
      lines.end[lines.count][1] = node_code(k);
      ++lines.count;
    }
  }
  for (int k = 0; k < 3; ++k) {
    if (state & face_cut_edge_edge_line(k)) {
      lines.end[lines.count][0] = edge_code(k + 1);
      lines.end[lines.count][1] = edge_code(k + 2);
      ++lines.count;
    }
  }
  return lines;
}

constexpr Pieces line_pieces(const Lines& lines, bool face_point) {
  Pieces pieces;
  for (int i = 0; i < lines.count; ++i) {
    if (face_point) {
      pieces.add(face_code, lines.end[i][0]);
      pieces.add(face_code, lines.end[i][1]);
    } else {
      pieces.add(lines.end[i][0], lines.end[i][1]);
    }
  }
  return pieces;
}

/// A triangulation of one convex sub-polygon (at most 6 corners, so at most 4 triangles).
struct Triangulation {
  std::uint8_t tri[4][3] = {};
  int count = 0;
  constexpr void add(std::uint8_t a, std::uint8_t b, std::uint8_t d) {
    if (count >= 4) throw std::logic_error("split table: a sub-polygon with more than 4 triangles");
    tri[count][0] = a;
    tri[count][1] = b;
    tri[count][2] = d;
    ++count;
  }
  constexpr bool has_triangle(const std::uint8_t (&t)[3]) const {
    for (int i = 0; i < count; ++i)
      for (int r = 0; r < 3; ++r)
        if (tri[i][r] == t[0] && tri[i][(r + 1) % 3] == t[1] && tri[i][(r + 2) % 3] == t[2]) return true;
    return false;
  }
  constexpr bool same_as(const Triangulation& other) const {
    if (count != other.count) return false;
    for (int i = 0; i < count; ++i)
      if (!other.has_triangle(tri[i])) return false;
    return true;
  }
};

/// Three corners on one side of the face (N_{k+1}, E_k, N_{k+2}) make a zero-area triangle.
constexpr bool is_flat_triangle(const std::uint8_t (&t)[3]) {
  for (int k = 0; k < 3; ++k) {
    int on_side = 0;
    for (int s = 0; s < 3; ++s) on_side += t[s] == node_code(k + 1) || t[s] == edge_code(k) || t[s] == node_code(k + 2);
    if (on_side == 3) return true;
  }
  return false;
}

constexpr Triangulation fan_from(const Polygon& p, int apex) {
  Triangulation t;
  for (int j = 1; j + 1 < p.count; ++j) t.add(p.at(apex), p.at(apex + j), p.at(apex + j + 1));
  return t;
}

/// The triangulations a sub-polygon may take, the rule's own first (variant 0).
struct Choices {
  Triangulation option[8];
  int count = 0;
  /// Keeps `t` unless it has a zero-area triangle or is already listed.
  constexpr void offer(const Triangulation& t) {
    for (int i = 0; i < t.count; ++i)
      if (is_flat_triangle(t.tri[i])) return;
    for (int i = 0; i < count; ++i)
      if (option[i].same_as(t)) return;
    if (count >= 8) throw std::logic_error("split table: too many triangulations of a sub-polygon");
    option[count++] = t;
  }
};

/// A corner E_k whose neighbours are N_{k+1} and N_{k+2} lies inside a straight side: the polygon
/// is flat there. Returns the position of the flat corner with the lowest k at or after `from_k`,
/// or -1.
constexpr int find_flat_corner(const Polygon& p, int from_k = 0) {
  for (int k = from_k; k < 3; ++k) {
    const int i = p.find(edge_code(k));
    if (i >= 0 && p.at(i - 1) == node_code(k + 1) && p.at(i + 1) == node_code(k + 2)) return i;
  }
  return -1;
}

/// The rule's triangulation of a convex sub-polygon without zero-area triangles (docs/split-table.md):
/// the whole face with three edge points takes the 1-to-4 pattern; a polygon with a flat corner is a
/// fan from it (every triangle then uses that corner, so none has three collinear corners);
/// otherwise a triangle, or a quadrilateral split by the diagonal rule.
constexpr Triangulation rule_triangulation(const Polygon& p) {
  Triangulation t;
  if (p.count == 6) {
    // The midpoint-style pattern: three corner triangles and the middle one, better shaped than a fan.
    for (int k = 0; k < 3; ++k) t.add(node_code(k), edge_code(k + 2), edge_code(k + 1));
    t.add(edge_code(0), edge_code(1), edge_code(2));
    return t;
  }
  const int flat = find_flat_corner(p);
  if (flat >= 0) return fan_from(p, flat);
  if (p.count == 3) return fan_from(p, 0);
  if (p.count != 4) throw std::logic_error("split table: a sub-polygon of more than 4 corners without a flat corner");
  // Diagonal between two edge points first: it completes the 1-to-4 pattern of two EE lines.
  int from = -1;
  if (is_edge_point(p.at(0)) && is_edge_point(p.at(2))) from = 0;
  if (is_edge_point(p.at(1)) && is_edge_point(p.at(3))) from = 1;
  // Otherwise (EE_k alone, E_k absent: E_{k+2} N_{k+1} N_{k+2} E_{k+1}) from the node that follows
  // an edge point, N_{k+1}, to E_{k+1}: the same choice for every k.
  for (int i = 0; i < 4 && from < 0; ++i)
    if (is_node(p.at(i)) && is_edge_point(p.at(i - 1))) from = i;
  if (from < 0) throw std::logic_error("split table: a quadrilateral without a diagonal rule");
  return fan_from(p, from);
}

/// Every triangulation of `p` without a zero-area triangle among the rule's, the fans from its flat
/// corners (lowest k first) and the fans from each of its corners, in that order.
constexpr Choices triangulation_choices(const Polygon& p) {
  Choices choices;
  choices.offer(rule_triangulation(p));
  for (int k = 0; k < 3; ++k) {
    const int flat = find_flat_corner(p, k);
    if (flat < 0) break;
    choices.offer(fan_from(p, flat));
    k = point_local(p.at(flat));
  }
  for (int i = 0; i < p.count; ++i) choices.offer(fan_from(p, i));
  if (choices.count == 0) throw std::logic_error("split table: a sub-polygon without a valid triangulation");
  return choices;
}

/// Splits the boundary polygon along non-crossing chords into convex sub-polygons.
struct Parts {
  Polygon part[7];
  int count = 0;
};
constexpr Parts split_by_lines(const Polygon& boundary, const Lines& lines) {
  Parts parts;
  parts.part[parts.count++] = boundary;
  for (int l = 0; l < lines.count; ++l) {
    int found = -1, ia = -1, ib = -1;
    for (int i = 0; i < parts.count && found < 0; ++i) {
      ia = parts.part[i].find(lines.end[l][0]);
      ib = parts.part[i].find(lines.end[l][1]);
      if (ia >= 0 && ib >= 0) found = i;
    }
    if (found < 0) throw std::logic_error("split table: lines cross without a face point");
    const Polygon whole = parts.part[found];
    Polygon first, second;
    for (int i = ia;; ++i) {
      first.corner[first.count++] = whole.at(i);
      if (whole.at(i) == lines.end[l][1]) break;
    }
    for (int i = ib;; ++i) {
      second.corner[second.count++] = whole.at(i);
      if (whole.at(i) == lines.end[l][0]) break;
    }
    if (first.count < 3 || second.count < 3) throw std::logic_error("split table: a line along the face boundary");
    parts.part[found] = first;
    parts.part[parts.count++] = second;
  }
  return parts;
}

constexpr void add_triangle(SplitCase& c, std::uint8_t a, std::uint8_t b, std::uint8_t d) {
  if (c.tri_count >= 6) throw std::logic_error("split table: more than 6 triangles");
  c.tri[c.tri_count][0] = a;
  c.tri[c.tri_count][1] = b;
  c.tri[c.tri_count][2] = d;
  ++c.tri_count;
}

/// Walks the triangles around `code` counter-clockwise, from the side towards `start_next` until
/// the side towards `end_prev` (for P both are N0: a full circle).
constexpr void build_fan(SplitCase& c, int slot, const Pieces& pieces, std::uint8_t start_next, std::uint8_t end_prev) {
  const std::uint8_t code = slot_point_code(slot);
  int corner_total = 0;
  for (int t = 0; t < c.tri_count; ++t)
    for (int s = 0; s < 3; ++s) corner_total += c.tri[t][s] == code;
  std::uint8_t next = start_next;
  int count = 0;
  for (;;) {
    int tri = -1, corner = -1;
    for (int t = 0; t < c.tri_count && tri < 0; ++t)
      for (int s = 0; s < 3; ++s)
        if (c.tri[t][s] == code && c.tri[t][(s + 1) % 3] == next) tri = t, corner = s;
    if (tri < 0 || count >= 6) throw std::logic_error("split table: a broken fan");
    c.fan[slot][count] = fan_entry(tri, corner);
    const std::uint8_t prev = c.tri[tri][(corner + 2) % 3];
    if (pieces.contains(code, prev) && (prev != end_prev || code == face_code))
      c.fan_cut[slot] |= static_cast<std::uint8_t>(1u << count);
    ++count;
    if (prev == end_prev) break;
    next = prev;
  }
  if (count != corner_total) throw std::logic_error("split table: a fan misses triangles");
  c.fan_count[slot] = static_cast<std::uint8_t>(count);
}

/// Fills the triangle cut bits and the fans of a case whose triangles are written.
constexpr void finish_split_case(SplitCase& c, const Polygon& boundary, const Pieces& pieces) {
  const int expected = (c.face_point ? 3 : 1) + boundary.count - 3;
  if (c.tri_count != expected) throw std::logic_error("split table: wrong triangle count");

  for (int t = 0; t < c.tri_count; ++t)
    for (int s = 0; s < 3; ++s)
      if (pieces.contains(c.tri[t][(s + 1) % 3], c.tri[t][(s + 2) % 3]))
        c.tri_cut[t] |= static_cast<std::uint8_t>(1u << s);

  for (int i = 0; i < boundary.count; ++i) {
    const std::uint8_t code = boundary.at(i);
    build_fan(c, point_slot(code), pieces, boundary.at(i + 1), boundary.at(i - 1));
  }
  if (c.face_point) build_fan(c, point_slot(face_code), pieces, node_code(0), node_code(0));
}

/// The variants of one state: every combination of the sub-polygons' triangulation choices, in
/// mixed-radix order with the first sub-polygon's choice changing fastest, up to max_split_variants.
struct StateSplits {
  SplitCase variant[max_split_variants] = {};
};

constexpr StateSplits make_state_splits(unsigned state) {
  StateSplits splits;
  splits.variant[0].variant_count = 1;
  if (!is_reachable_face_cut(state)) return splits;
  const bool face_point = has_face_point(state);
  const Polygon boundary = boundary_polygon(state);
  const Lines lines = face_lines(state);
  const Pieces pieces = line_pieces(lines, face_point);

  if (face_point) {
    // Every line passes through P, so a fan around P over the boundary makes each piece a side.
    SplitCase& c = splits.variant[0];
    c.reachable = 1;
    c.face_point = 1;
    for (int i = 0; i < boundary.count; ++i) add_triangle(c, face_code, boundary.at(i), boundary.at(i + 1));
    finish_split_case(c, boundary, pieces);
    return splits;
  }

  const Parts parts = split_by_lines(boundary, lines);
  Choices choices[7];
  int combinations = 1;
  for (int i = 0; i < parts.count; ++i) {
    choices[i] = triangulation_choices(parts.part[i]);
    combinations *= choices[i].count;
  }
  const int variant_count = combinations < max_split_variants ? combinations : max_split_variants;
  for (int v = 0; v < variant_count; ++v) {
    SplitCase& c = splits.variant[v];
    c.reachable = 1;
    c.variant_count = static_cast<std::uint8_t>(variant_count);
    int digits = v;
    for (int i = 0; i < parts.count; ++i) {
      const Triangulation& t = choices[i].option[digits % choices[i].count];
      digits /= choices[i].count;
      for (int j = 0; j < t.count; ++j) add_triangle(c, t.tri[j][0], t.tri[j][1], t.tri[j][2]);
    }
    finish_split_case(c, boundary, pieces);
  }
  return splits;
}

struct SplitTable {
  SplitCase cases[split_table_size] = {};
};

constexpr SplitTable make_split_table() {
  SplitTable table;
  for (int state = 0; state < face_cut_state_count; ++state) {
    const StateSplits splits = make_state_splits(static_cast<unsigned>(state));
    for (int v = 0; v < max_split_variants; ++v) table.cases[face_split_code(state, v)] = splits.variant[v];
  }
  return table;
}

}  // namespace split_rule

/// The table, evaluated once per translation unit at compile time; one copy per binary (an inline
/// function's static).
inline const SplitCase* split_table() {
  static constexpr split_rule::SplitTable table = split_rule::make_split_table();
  return table.cases;
}

inline std::string to_string_state(int state) {
  if (state < 0 || state >= face_cut_state_count) return "invalid state " + std::to_string(state);
  if (state == 0) return "none";
  static const char* const names[9] = {"E0", "E1", "E2", "EN0", "EN1", "EN2", "EE0", "EE1", "EE2"};
  std::string text;
  for (int bit = 0; bit < 9; ++bit) {
    if (!(state & (1 << bit))) continue;
    if (!text.empty()) text += ' ';
    text += names[bit];
  }
  return text;
}

}  // namespace tear::kernels
