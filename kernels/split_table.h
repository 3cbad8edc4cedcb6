// tear kernels: how one face splits into new triangles, for each of its 512 cut states and the
// variants of its free choices (paper §2.3 "new faces" and §2.4 "node info / face info").
// docs/split-table.md has the rule.
//
// Conventions: local node k (N_k) is opposite local edge k; edge k joins N_{k+1} and N_{k+2}
// (mod 3); faces are counter-clockwise. E_k is the cut point inside edge k, P the face point.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

#include "hd.h"

namespace tear::kernels {

/// Bits of a face cut state (9 bits; paper §2.1's 6 line bits plus 3 edge-point bits).
namespace face_cut {
enum Bits : std::uint16_t {
  none = 0,
  e0 = 1u << 0,  ///< edge k carries a cut point E_k strictly inside it (a snapped point is a node)
  e1 = 1u << 1,
  e2 = 1u << 2,
  en0 = 1u << 3,  ///< edge–node line EN_k from E_k to the opposite node N_k
  en1 = 1u << 4,
  en2 = 1u << 5,
  ee0 = 1u << 6,  ///< edge–edge line EE_k between E_{k+1} and E_{k+2}; it cuts off N_k
  ee1 = 1u << 7,
  ee2 = 1u << 8,
};
}  // namespace face_cut

constexpr int face_cut_state_count = 512;

TEAR_HD constexpr unsigned face_cut_edge_point(int k) { return 1u << k; }
TEAR_HD constexpr unsigned face_cut_edge_node_line(int k) { return 1u << (3 + k); }
TEAR_HD constexpr unsigned face_cut_edge_edge_line(int k) { return 1u << (6 + k); }

/// A state is reachable iff every line has its edge points: EN_k needs E_k, EE_k needs E_{k+1} and E_{k+2}.
TEAR_HD constexpr bool is_reachable_face_cut(unsigned state) {
  if (state >= static_cast<unsigned>(face_cut_state_count)) return false;
  for (int k = 0; k < 3; ++k) {
    if ((state & face_cut_edge_node_line(k)) && !(state & face_cut_edge_point(k))) return false;
    if ((state & face_cut_edge_edge_line(k)) &&
        !((state & face_cut_edge_point((k + 1) % 3)) && (state & face_cut_edge_point((k + 2) % 3))))
      return false;
  }
  return true;
}

/// The face has its own cut point P iff its lines cross (paper §2.1): EN_k with EE_k for some k,
/// or two or more EN lines (two cevians always cross). EE lines never cross each other.
TEAR_HD constexpr bool has_face_point(unsigned state) {
  int edge_node_lines = 0;
  for (int k = 0; k < 3; ++k) {
    if (state & face_cut_edge_node_line(k)) {
      ++edge_node_lines;
      if (state & face_cut_edge_edge_line(k)) return true;
    }
  }
  return edge_node_lines >= 2;
}

/// Kind of a point of a split face: the paper's 2-bit element kind of a node info.
enum class PointKind : std::uint8_t { node = 0, edge = 1, face = 2 };

/// A point code (the paper's 4-bit node info): kind << 2 | local. node N_local, edge point E_local,
/// face point P (local 0).
TEAR_HD constexpr std::uint8_t point_code(PointKind kind, int local) {
  return static_cast<std::uint8_t>((static_cast<int>(kind) << 2) | local);
}
TEAR_HD constexpr PointKind point_kind(std::uint8_t code) { return static_cast<PointKind>(code >> 2); }
TEAR_HD constexpr int point_local(std::uint8_t code) { return code & 3; }

/// The 7 points of a face in a fixed order (fan slots): 0..2 = N_k, 3..5 = E_k, 6 = P.
constexpr int face_point_slot_count = 7;
TEAR_HD constexpr int point_slot(std::uint8_t code) { return 3 * (code >> 2) + (code & 3); }
TEAR_HD constexpr std::uint8_t slot_point_code(int slot) {
  return point_code(static_cast<PointKind>(slot / 3), slot % 3);
}

/// Packing of a fan entry: the triangle of the split and its corner (0..2) at the fan's point.
TEAR_HD constexpr std::uint8_t fan_entry(int tri, int corner) { return static_cast<std::uint8_t>(tri << 2 | corner); }
TEAR_HD constexpr int fan_entry_tri(std::uint8_t entry) { return entry >> 2; }
TEAR_HD constexpr int fan_entry_corner(std::uint8_t entry) { return entry & 3; }

/// Alternative splits per state: they differ only in choices the cut lines leave free (the
/// diagonal of a quadrilateral, the corner a polygon is fanned from), so each face can take the
/// best-shaped one. Variant 0 is the fixed rule of docs/split-table.md.
constexpr int max_split_variants = 4;
constexpr int split_table_size = face_cut_state_count * max_split_variants;

/// The split of a face in one cut state. Plain bytes, so the table copies to the device as is.
struct SplitCase {
  /// 0 for a state no face can have (the rest 0 but variant_count 1) and for a variant slot past
  /// variant_count (all 0)
  std::uint8_t reachable;
  std::uint8_t face_point;     ///< 1 when the face has its own cut point P
  std::uint8_t tri_count;      ///< 1..6 new triangles (0 when unreachable)
  std::uint8_t variant_count;  ///< 1..max_split_variants splits of this state (1 when unreachable)
  std::uint8_t tri[6][3];      ///< corners of each triangle as point codes, counter-clockwise
  /// Bit s of tri_cut[t]: side s of triangle t (opposite its corner s) lies on a piece of a cut line.
  std::uint8_t tri_cut[6];
  /// Rotational fans, per point slot: the triangle corners at that point in counter-clockwise order.
  /// N_k: from the side along edge k+2 (towards N_{k+1}) to the side along edge k+1 (towards N_{k+2}).
  /// E_k: from the side towards N_{k+2} round to the side towards N_{k+1}.
  /// P: a full circle, starting with the triangle whose first boundary corner is N0.
  /// 0 entries for an absent point.
  std::uint8_t fan_count[7];
  std::uint8_t fan[7][6];  ///< fan_entry(triangle, corner)
  /// Bit i: the side shared by fan[i] and fan[i+1] lies on a cut-line piece; for P, bit fan_count-1
  /// is the wrap-around side between the last and the first entry.
  std::uint8_t fan_cut[7];
};

/// A face's split code (the remesher's `face_state`): the 9-bit cut state, and in bits 9..10 the
/// variant of its split. It is also the split's index in the table: variant-major, so variant 0 of
/// every state comes first, at the index of the plain state.
constexpr int split_variant_shift = 9;
TEAR_HD constexpr std::uint16_t face_split_code(unsigned state, int variant) {
  return static_cast<std::uint16_t>(state | static_cast<unsigned>(variant) << split_variant_shift);
}
TEAR_HD constexpr unsigned face_split_state(unsigned code) { return code & (face_cut_state_count - 1u); }
TEAR_HD constexpr int face_split_variant(unsigned code) { return static_cast<int>(code >> split_variant_shift); }
static_assert(face_split_code(face_cut_state_count - 1, max_split_variants - 1) == split_table_size - 1,
              "split codes index the table");

/// The split of every face cut state and variant, at face_split_code(state, variant)
/// (split_table_size entries, host memory; built at compile time, split_table_rule.h). The
/// remesher copies it to the device once.
inline const SplitCase* split_table();

/// The split a face takes, from its split code.
TEAR_HD inline const SplitCase& split_case(const SplitCase* table, unsigned code) { return table[code]; }

/// Cosine of the smallest corner angle of a split (the largest cosine over its triangle corners:
/// a triangle's smallest angle is below 60 degrees, where the cosine decreases). `point_pos` holds
/// the positions of the 7 point slots; a zero-length side counts as a zero angle.
TEAR_HD inline double split_worst_cosine(const SplitCase& c, const double (*point_pos)[3]) {
  double worst = -1.0;
  for (int t = 0; t < c.tri_count; ++t) {
    for (int s = 0; s < 3; ++s) {
      const double* p = point_pos[point_slot(c.tri[t][s])];
      const double* a = point_pos[point_slot(c.tri[t][(s + 1) % 3])];
      const double* b = point_pos[point_slot(c.tri[t][(s + 2) % 3])];
      double uv = 0, uu = 0, vv = 0;
      for (int d = 0; d < 3; ++d) {
        const double u = a[d] - p[d], v = b[d] - p[d];
        uv += u * v;
        uu += u * u;
        vv += v * v;
      }
      const double length = sqrt(uu * vv);
      const double cosine = length > 0.0 ? uv / length : 1.0;
      worst = cosine > worst ? cosine : worst;
    }
  }
  return worst;
}

/// A variant must beat the best so far by this much (in cosine) to be taken, so exact ties (a
/// symmetric face, common on regular meshes) keep the lower variant whatever the rounding: the
/// choice, hence the topology, can differ between the CPU and the GPU (fused multiply-adds) only
/// when two variants differ by about the margin itself.
constexpr double split_variant_margin = 1e-9;

/// The variant of `state` whose smallest triangle angle is largest, on the positions of the face's
/// 7 point slots (N0..N2, E0..E2, P; absent points are not read). Ties go to the lowest variant.
TEAR_HD inline int best_split_variant(const SplitCase* table, unsigned state, const double (*point_pos)[3]) {
  const int count = table[face_split_code(state, 0)].variant_count;
  if (count <= 1) return 0;
  int best = 0;
  double best_cosine = split_worst_cosine(table[face_split_code(state, 0)], point_pos);
  for (int v = 1; v < count; ++v) {
    const double cosine = split_worst_cosine(table[face_split_code(state, v)], point_pos);
    if (cosine < best_cosine - split_variant_margin) {
      best = v;
      best_cosine = cosine;
    }
  }
  return best;
}

/// The bits of a face cut state by name, e.g. "E0 E1 EN0 EE2" ("none" for 0), for messages.
inline std::string to_string_state(int state);

}  // namespace tear::kernels

#include "split_table_rule.h"  // defines split_table() and to_string_state()
