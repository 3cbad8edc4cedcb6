// tear kernels: intersection of a frame's cuts with every face (paper §2.1, first half).
//
// One thread per face, for every cut: the crossings of the cut's polyline with the face's three
// edges (in the face's own 2D coordinates, so a UV-space cut never mixes charts across a seam),
// summed per half-edge for the per-edge average, and the pairs of edges the cut joins inside the
// face. A cut ending inside a face joins nothing there: it ends at the last edge it crossed.
#pragma once

#include <cstdint>

#include "cut_geometry.h"
#include "hd.h"

namespace tear::kernels {

/// At most this many crossings of one cut with one face are considered (a polyline wiggling more
/// than this inside one triangle is beyond the element's resolution anyway).
inline constexpr int max_face_events = 12;

/// Where a crossing lies in its face before snapping: 0..2 inside local edge k, 3..5 exactly on
/// local node k-3.
TEAR_HD inline int location_pair_bit(int a, int b) {
  const int i = a < b ? a : b, j = a < b ? b : a;
  return i * (11 - i) / 2 + (j - i - 1);  // the 15 unordered pairs of 6 locations
}

/// Per face: `half_hit_sum` / `half_hit_count` [face_count*3] of crossings inside the edge
/// (parameter along the edge from its low node to its high node), and `face_pairs` [face_count]
/// bit `location_pair_bit(a, b)`: some cut runs inside the face from location a to location b.
struct intersect_cuts {
  const index_t* face_nodes;
  const float* corner_uv;
  const float* node_rest;
  const float* node_pos;
  const CutPath* cuts;
  index_t cut_count;
  const double* point_x;
  const double* point_y;
  double* half_hit_sum;
  index_t* half_hit_count;
  std::uint16_t* face_pairs;

  /// A face's box in its 2D coordinates, and the margin it is grown by for the broad phase: more
  /// than cross_edge's tolerances (a crossing it accepts lies on the edge and within twice its
  /// tolerance of the segment).
  struct FaceBox {
    double lo_x, hi_x, lo_y, hi_y, margin;
  };
  TEAR_HD static FaceBox face_box(const Vec2* corner) {
    FaceBox box{corner[0].x, corner[0].x, corner[0].y, corner[0].y, 0.0};
    for (int k = 1; k < 3; ++k) {
      box.lo_x = fmin(box.lo_x, corner[k].x);
      box.hi_x = fmax(box.hi_x, corner[k].x);
      box.lo_y = fmin(box.lo_y, corner[k].y);
      box.hi_y = fmax(box.hi_y, corner[k].y);
    }
    const double magnitude = fmax(fmax(fabs(box.lo_x), fabs(box.hi_x)), fmax(fabs(box.lo_y), fabs(box.hi_y)));
    const double extent = (box.hi_x - box.lo_x) + (box.hi_y - box.lo_y);  // >= every edge's length
    box.margin = 4.0 * (on_line_tolerance * extent + on_line_float_tolerance * magnitude);
    return box;
  }

  /// The crossings of one cut with one face, in order along the cut: the polyline parameter of
  /// each and its location (location_pair_bit's numbering).
  struct FaceEvents {
    double s[max_face_events];
    int loc[max_face_events];
    int count = 0;
    /// Insertion by polyline parameter keeps events in order along the cut.
    TEAR_HD void add(double global_s, int location) {
      if (count >= max_face_events) return;
      int j = count++;
      while (j > 0 && s[j - 1] > global_s) {
        s[j] = s[j - 1];
        loc[j] = loc[j - 1];
        --j;
      }
      s[j] = global_s;
      loc[j] = location;
    }
  };

  TEAR_HD void operator()(index_t f) const {
    double sum[3] = {0, 0, 0};
    index_t count[3] = {0, 0, 0};
    std::uint16_t pairs = 0;
    index_t node[3];
    for (int k = 0; k < 3; ++k) node[k] = face_nodes[3 * f + k];
    for (index_t ci = 0; ci < cut_count; ++ci) {
      const CutPath cut = cuts[ci];
      Vec2 corner[3];
      for (int k = 0; k < 3; ++k) corner[k] = project_corner(cut, 3 * f + k, node[k], corner_uv, node_rest, node_pos);
      // Broad phase: a bounded segment whose box misses the face's grown box crosses none of its
      // edges; nor does a bounded path whose box misses it (most faces, far from a cut: one test
      // instead of one per segment).
      const FaceBox box = face_box(corner);
      if (path_box_misses(cut, box.lo_x, box.hi_x, box.lo_y, box.hi_y, box.margin)) continue;
      FaceEvents events;
      cross_face(cut, corner, node, box, sum, count, events);
      pairs |= joined_pairs(cut, corner, events);
    }
    for (int k = 0; k < 3; ++k) {
      half_hit_sum[3 * f + k] = sum[k];
      half_hit_count[3 * f + k] = count[k];
    }
    face_pairs[f] = pairs;
  }

  /// The crossings of `cut`'s segments with the face's edges: those inside an edge summed into
  /// `sum`/`count` (canonical parameter), every one (up to max_face_events) into `events`.
  TEAR_HD void cross_face(const CutPath& cut, const Vec2* corner, const index_t* node, const FaceBox& box, double* sum,
                          index_t* count, FaceEvents& events) const {
    for (index_t i = 0; i + 1 < cut.point_count; ++i) {
      const index_t pi = cut.point_begin + i;
      const Vec2 p{point_x[pi], point_y[pi]}, q{point_x[pi + 1], point_y[pi + 1]};
      double lo, hi;
      bool hi_closed;
      segment_range(cut, i, lo, hi, hi_closed);
      if (lo == 0.0 && hi == 1.0 &&
          (fmax(p.x, q.x) < box.lo_x - box.margin || fmin(p.x, q.x) > box.hi_x + box.margin ||
           fmax(p.y, q.y) < box.lo_y - box.margin || fmin(p.y, q.y) > box.hi_y + box.margin))
        continue;
      for (int k = 0; k < 3; ++k) {
        // Edge k runs from local node k+1 to local node k+2.
        const Vec2 a = corner[(k + 1) % 3], b = corner[(k + 2) % 3];
        double t, s;
        if (!cross_edge(a, b, p, q, lo, hi, hi_closed, t, s)) continue;
        const bool forward = node[(k + 1) % 3] < node[(k + 2) % 3];
        const double t_canonical = forward ? t : 1.0 - t;
        int loc = k;
        if (t == 0.0 || t == 1.0) {
          loc = 3 + (t == 0.0 ? (k + 1) % 3 : (k + 2) % 3);
        } else {
          sum[k] += t_canonical;
          ++count[k];
        }
        events.add(i + s, loc);
      }
    }
  }

  /// The location pairs (location_pair_bit) `cut` joins inside the face from its crossings there.
  TEAR_HD std::uint16_t joined_pairs(const CutPath& cut, const Vec2* corner, const FaceEvents& events) const {
    std::uint16_t pairs = 0;
    const double* event_s = events.s;
    const int* event_loc = events.loc;
    const int event_count = events.count;
    // Consecutive crossings at different places with the cut inside the face between them.
    // Two crossings at the same place of the polyline join too: the face then projects to a
    // line segment (a blade swept along a direction lying in the face's plane).
    const double area2 = cross(corner[1] - corner[0], corner[2] - corner[0]);
    for (int e = 0; e + 1 < event_count; ++e) {
      if (event_loc[e] == event_loc[e + 1]) continue;
      const double ds = event_s[e + 1] - event_s[e];
      bool joined = ds <= 1e-9;
      if (!joined && area2 != 0.0)
        joined = inside_triangle(corner, area2, polyline_point(cut, point_x, point_y, event_s[e] + 0.5 * ds));
      if (joined) pairs |= std::uint16_t(1u << location_pair_bit(event_loc[e], event_loc[e + 1]));
    }
    // A closed polyline (its last point is its first) goes on from its end into its start, so
    // the face's last and first crossings are consecutive too; else a closed curve would leave
    // the face holding its start uncut, a bridge of one element.
    const index_t last_pi = cut.point_begin + cut.point_count - 1;
    const bool closed = cut.unbounded == 0 && cut.point_count > 2 && point_x[cut.point_begin] == point_x[last_pi] &&
                        point_y[cut.point_begin] == point_y[last_pi];
    if (closed && event_count >= 2 && event_loc[event_count - 1] != event_loc[0]) {
      const double length = cut.point_count - 1;
      const double ds = event_s[0] + length - event_s[event_count - 1];
      double mid = event_s[event_count - 1] + 0.5 * ds;
      if (mid >= length) mid -= length;
      bool joined = ds <= 1e-9;
      if (!joined && area2 != 0.0) joined = inside_triangle(corner, area2, polyline_point(cut, point_x, point_y, mid));
      if (joined) pairs |= std::uint16_t(1u << location_pair_bit(event_loc[event_count - 1], event_loc[0]));
    }
    return pairs;
  }

  /// The polyline at global parameter s (segment index + local parameter); before its start and
  /// past its end (an unbounded cut's extensions, which reach any distance) along its first and
  /// last segments. The segment is picked in double: past the end `s` may exceed any index.
  TEAR_HD static Vec2 polyline_point(const CutPath& cut, const double* px, const double* py, double s) {
    const index_t last = cut.point_count - 2;
    const index_t i = !(s >= 0) ? 0 : s >= static_cast<double>(last) ? last : static_cast<index_t>(s);
    const double u = s - i;
    const index_t pi = cut.point_begin + i;
    return {px[pi] + u * (px[pi + 1] - px[pi]), py[pi] + u * (py[pi + 1] - py[pi])};
  }

  /// Inside or on the border of the triangle, with a tolerance relative to its size.
  TEAR_HD static bool inside_triangle(const Vec2* c, double area2, Vec2 x) {
    const double tol = 1e-9 * (area2 < 0 ? -area2 : area2);
    for (int k = 0; k < 3; ++k) {
      const double w = cross(c[(k + 2) % 3] - c[(k + 1) % 3], x - c[(k + 1) % 3]);
      if (area2 > 0 ? w < -tol : w > tol) return false;
    }
    return true;
  }
};

}  // namespace tear::kernels
