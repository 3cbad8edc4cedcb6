#include "tear/triangulate_polygon.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

namespace tear {
namespace {

struct Point2 {
  double x, y;
};

/// Twice the signed area of (a, b, c): positive when they turn left (counter-clockwise).
double turn(const Point2& a, const Point2& b, const Point2& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

bool same_point(const Point2& a, const Point2& b) { return a.x == b.x && a.y == b.y; }

/// Inside or on the border of the counter-clockwise triangle (a, b, c).
bool in_triangle(const Point2& p, const Point2& a, const Point2& b, const Point2& c) {
  return turn(a, b, p) >= 0.0 && turn(b, c, p) >= 0.0 && turn(c, a, p) >= 0.0;
}

/// Ear clipping is quadratic in the corner count (each step a pass over the ring); beyond this many
/// corners a concave polygon is fanned, so that no file can make reading take hours. Cloth meshes
/// have triangles and quads, exporters' n-gons far fewer corners than this.
constexpr index_t ear_clipping_limit = 128;

void fan(index_t corner_count, std::vector<index_t>& triangles) {
  for (index_t k = 1; k + 1 < corner_count; ++k) triangles.insert(triangles.end(), {0, k, k + 1});
}

/// Triangulates the counter-clockwise outline `point` by ear clipping, appending to `triangles`.
void clip_ears(const std::vector<Point2>& point, std::vector<index_t>& triangles) {
  const index_t corner_count = static_cast<index_t>(point.size());
  // Ear clipping: the first ear of the ring is clipped, again and again. Whether a corner is an ear
  // is kept between steps, since a clip changes it only for the clipped corner's two neighbours
  // (their triangles change) and for the corners it alone kept from being ears (an obstacle gone):
  // each corner remembers the obstacle it was found to have. So each step is one pass over the
  // ring, mostly through what is known, not a test of every corner against every other (cubic in
  // the corner count).
  constexpr index_t unknown = -1, ear = -2, not_ear = -3;  // or the corner in the way
  std::vector<index_t> status(static_cast<std::size_t>(corner_count), unknown);
  std::vector<index_t> ring(corner_count);
  std::iota(ring.begin(), ring.end(), 0);
  while (ring.size() > 3) {
    const std::size_t m = ring.size();
    auto corner = [&](std::size_t k, int offset) { return ring[(k + m + offset) % m]; };
    auto ear_status = [&](std::size_t k) -> index_t {
      const Point2 &a = point[corner(k, -1)], &b = point[corner(k, 0)], &c = point[corner(k, 1)];
      if (!(turn(a, b, c) > 0.0)) return not_ear;
      for (std::size_t j = 0; j < m; ++j) {
        if (j == k || j == (k + 1) % m || j == (k + m - 1) % m) continue;
        const Point2& p = point[ring[j]];
        // A corner at the same place as one of the ear's (a polygon bridged to its hole) is no
        // obstacle; any other corner inside or on the ear is.
        if (same_point(p, a) || same_point(p, b) || same_point(p, c)) continue;
        if (in_triangle(p, a, b, c)) return ring[j];
      }
      return ear;
    };
    auto is_ear = [&](std::size_t k) {
      index_t& known = status[ring[k]];
      if (known == unknown) known = ear_status(k);
      return known == ear;
    };
    std::size_t clip = m;
    for (std::size_t k = 0; k < m && clip == m; ++k) {
      if (is_ear(k)) clip = k;
    }
    // No ear: the rest of the outline crosses itself or is degenerate. Clip the first convex
    // corner, else corner 0, so the polygon still yields its corner_count - 2 triangles.
    for (std::size_t k = 0; k < m && clip == m; ++k) {
      if (turn(point[corner(k, -1)], point[corner(k, 0)], point[corner(k, 1)]) > 0.0) clip = k;
    }
    if (clip == m) clip = 0;
    const index_t clipped = corner(clip, 0);
    triangles.insert(triangles.end(), {corner(clip, -1), clipped, corner(clip, 1)});
    status[corner(clip, -1)] = status[corner(clip, 1)] = unknown;
    for (index_t c : ring)
      if (status[c] == clipped) status[c] = unknown;
    ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(clip));
  }
  triangles.insert(triangles.end(), ring.begin(), ring.end());
}

}  // namespace

std::vector<index_t> triangulate_polygon(const float* corner_pos, index_t corner_count) {
  std::vector<index_t> triangles;
  if (corner_count < 3) return triangles;
  triangles.reserve(3 * static_cast<std::size_t>(corner_count - 2));
  if (corner_count == 3) return {0, 1, 2};

  // Newell's normal: robust for non-planar and partly collinear outlines.
  double normal[3] = {0.0, 0.0, 0.0};
  for (index_t i = 0; i < corner_count; ++i) {
    const float* p = corner_pos + 3 * i;
    const float* q = corner_pos + 3 * ((i + 1) % corner_count);
    normal[0] += (static_cast<double>(p[1]) - q[1]) * (static_cast<double>(p[2]) + q[2]);
    normal[1] += (static_cast<double>(p[2]) - q[2]) * (static_cast<double>(p[0]) + q[0]);
    normal[2] += (static_cast<double>(p[0]) - q[0]) * (static_cast<double>(p[1]) + q[1]);
  }
  int axis = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::fabs(normal[k]) > std::fabs(normal[axis])) axis = k;
  }
  if (!(std::fabs(normal[axis]) > 0.0) || !std::isfinite(normal[axis])) {
    fan(corner_count, triangles);
    return triangles;
  }
  // Project along the dominant axis onto the two others, ordered so that the outline stays
  // counter-clockwise seen from the normal's side.
  int u = (axis + 1) % 3, v = (axis + 2) % 3;
  if (normal[axis] < 0.0) std::swap(u, v);
  std::vector<Point2> point(corner_count);
  for (index_t i = 0; i < corner_count; ++i) point[i] = {corner_pos[3 * i + u], corner_pos[3 * i + v]};

  bool convex = true;
  for (index_t i = 0; i < corner_count && convex; ++i) {
    const index_t prev = (i + corner_count - 1) % corner_count, next = (i + 1) % corner_count;
    convex = turn(point[prev], point[i], point[next]) >= 0.0;
  }
  if (convex || corner_count > ear_clipping_limit) {
    fan(corner_count, triangles);
    return triangles;
  }

  clip_ears(point, triangles);
  return triangles;
}

}  // namespace tear
