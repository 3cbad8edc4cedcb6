// tear kernels: cut paths in 2D and their crossings with mesh edges (paper §2.1).
//
// Every cut is reduced to a 2D polyline and a way to project the mesh into the same plane:
// pattern-space cuts project rest positions on an axis plane or use the per-corner UVs; a
// world-space blade (a polyline swept along a direction) projects current positions along that
// direction; a plane is a blade whose polyline is one line unbounded at both ends.
#pragma once

#include <cmath>
#include <cstdint>

#include "hd.h"

namespace tear::kernels {

using index_t = std::int32_t;

/// Where a cut reads the mesh's 2D coordinates from.
enum class CutSource : std::int32_t { corner_uv = 0, node_rest = 1, node_pos = 2 };

/// One cut of a frame, as the kernels see it. 3D sources are projected to (p·axis_u, p·axis_v).
struct CutPath {
  CutSource source;
  double axis_u[3];
  double axis_v[3];
  index_t point_begin;  ///< first point of the polyline in the frame's point arrays
  index_t point_count;  ///< >= 2
  std::int32_t unbounded;  ///< bit 0: the first segment extends backwards without end; bit 1: the last, forwards
  /// With no unbounded end: the box of all its points (`path_box_misses`); else unused.
  double box_lo[2];
  double box_hi[2];
};

/// The box of a bounded path's points, for `path_box_misses` (a path with an unbounded end has none).
inline void set_path_box(CutPath& cut, const double* point_x, const double* point_y) {
  for (int a = 0; a < 2; ++a) {
    const double* v = a == 0 ? point_x : point_y;
    cut.box_lo[a] = cut.box_hi[a] = v[cut.point_begin];
    for (index_t i = 1; i < cut.point_count; ++i) {
      const double x = v[cut.point_begin + i];
      cut.box_lo[a] = x < cut.box_lo[a] ? x : cut.box_lo[a];
      cut.box_hi[a] = x > cut.box_hi[a] ? x : cut.box_hi[a];
    }
  }
}

/// Whether a bounded path's box misses the face box [lo, hi] grown by `margin`. Every segment's box
/// lies inside the path's, so the path then misses the face wherever its segments' boxes would: the
/// same comparisons `intersect_cuts` makes per segment, made once for all of them.
TEAR_HD inline bool path_box_misses(const CutPath& cut, double lo_x, double hi_x, double lo_y, double hi_y,
                                    double margin) {
  return cut.unbounded == 0 && (cut.box_hi[0] < lo_x - margin || cut.box_lo[0] > hi_x + margin ||
                                cut.box_hi[1] < lo_y - margin || cut.box_lo[1] > hi_y + margin);
}

struct Vec2 {
  double x, y;
};
TEAR_HD inline Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
TEAR_HD inline Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
TEAR_HD inline Vec2 operator*(double s, Vec2 a) { return {s * a.x, s * a.y}; }
TEAR_HD inline double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
TEAR_HD inline double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }

/// A point closer to a cut line than this fraction of the edge's length counts as on the line:
/// far below any snap tolerance, and far above float rounding of node positions.
inline constexpr double on_line_tolerance = 1e-5;

/// Node coordinates are floats, so a node an earlier cut placed exactly on a line is off it by
/// the rounding of its coordinates: a few float ulps of their magnitude. On an edge short next to
/// its distance from the origin (a sliver left with snap 0, a small cloth far from the origin)
/// that exceeds on_line_tolerance x its length, and retracing the tear would split it again.
/// So a point this close, relative to the coordinates' magnitude, counts as on the line too.
inline constexpr double on_line_float_tolerance = 4 * 1.1920928955078125e-7;  // 4 ulps of a float

/// The crossing of mesh edge a→b with cut segment p→q, whose parameter range along p→q is
/// [s_lo, s_hi) (s_hi included when `s_hi_closed`). On success `t` is the parameter along a→b in
/// [0, 1] (0 or 1 exactly when the line passes through an end) and `s` the one along p→q.
/// An edge lying on the cut's line does not cross it: a cut along an edge is represented by cut
/// points at its two nodes.
TEAR_HD inline bool cross_edge(Vec2 a, Vec2 b, Vec2 p, Vec2 q, double s_lo, double s_hi, bool s_hi_closed, double& t,
                               double& s) {
  const Vec2 dir = q - p;
  const double dir_len2 = dot(dir, dir);
  const Vec2 ab = b - a;
  const double ab_len = sqrt(dot(ab, ab));
  if (dir_len2 == 0.0 || ab_len == 0.0) return false;
  const double dir_len = sqrt(dir_len2);
  const double da = cross(dir, a - p) / dir_len, db = cross(dir, b - p) / dir_len;
  const double magnitude = fmax(fmax(fabs(a.x), fabs(a.y)), fmax(fabs(b.x), fabs(b.y)));
  const double tol = on_line_tolerance * ab_len + on_line_float_tolerance * magnitude;
  const bool a_on = da <= tol && da >= -tol, b_on = db <= tol && db >= -tol;
  if (a_on && b_on) return false;
  if (a_on)
    t = 0.0;
  else if (b_on)
    t = 1.0;
  else if ((da < 0.0) != (db < 0.0))
    t = da / (da - db);
  else
    return false;
  const Vec2 x = a + t * ab;
  s = dot(x - p, dir) / dir_len2;
  const double s_tol = tol / dir_len;
  if (s < s_lo - s_tol) return false;
  return s_hi_closed ? s <= s_hi + s_tol : s < s_hi - s_tol;
}

/// 2D coordinates of corner `c` (node `n`) for a cut.
TEAR_HD inline Vec2 project_corner(const CutPath& cut, index_t c, index_t n, const float* corner_uv, const float* node_rest,
                                   const float* node_pos) {
  if (cut.source == CutSource::corner_uv) return {corner_uv[2 * c], corner_uv[2 * c + 1]};
  const float* p = (cut.source == CutSource::node_rest ? node_rest : node_pos) + 3 * n;
  return {p[0] * cut.axis_u[0] + p[1] * cut.axis_u[1] + p[2] * cut.axis_u[2],
          p[0] * cut.axis_v[0] + p[1] * cut.axis_v[1] + p[2] * cut.axis_v[2]};
}

/// Parameter range of segment i of a cut: [0, 1), the last one closed, unbounded ends open wide.
TEAR_HD inline void segment_range(const CutPath& cut, index_t i, double& lo, double& hi, bool& hi_closed) {
  const index_t last = cut.point_count - 2;
  lo = (i == 0 && (cut.unbounded & 1)) ? -1e308 : 0.0;
  hi = (i == last && (cut.unbounded & 2)) ? 1e308 : 1.0;
  hi_closed = i == last;
}

}  // namespace tear::kernels
