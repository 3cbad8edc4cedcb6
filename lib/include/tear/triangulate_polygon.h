// tear: one polygon of a mesh file split into triangles, the way readers of OBJ and PLY do it.
//
// Example: the L-shaped hexagon (0,0) (2,0) (2,1) (1,1) (1,2) (0,2), concave at corner 3:
//   corner_pos     = {0,0,0, 2,0,0, 2,1,0, 1,1,0, 1,2,0, 0,2,0}, corner_count = 6
//   a fan from corner 0 would cover the notch, so ears are clipped instead:
//   triangles      = {1,2,3, 0,1,3, 3,4,5, 0,3,5}   (4 triangles, counter-clockwise like the polygon)
// A convex quad (0,1,2,3) gives the fan {0,1,2, 0,2,3}.
#pragma once

#include <vector>

#include "tear/mesh.h"

namespace tear {

/// Splits a polygon of `corner_count` corners into `corner_count - 2` triangles.
///
/// - `corner_pos`: [corner_count * 3] the corners' positions, in the polygon's order.
/// - Returns [(corner_count - 2) * 3] corner numbers (0 .. corner_count - 1), each triangle in the
///   polygon's own orientation.
/// - A triangle is returned as it is. A convex polygon (every turn of its outline, seen along its
///   Newell normal, to the same side or straight) becomes a fan from corner 0, as assimp and most
///   exporters do. A concave one is cut by ear clipping in its plane (the outline projected along
///   the dominant axis of its normal), always clipping the first ear in the outline's order, so
///   the result is deterministic. Where no ear is left (a self-intersecting or degenerate
///   outline) the first convex corner, or else corner 0 of what is left, is clipped, so any input
///   gives `corner_count - 2` triangles. Polygons of fewer than 3 corners give none.
std::vector<index_t> triangulate_polygon(const float* corner_pos, index_t corner_count);

}  // namespace tear
