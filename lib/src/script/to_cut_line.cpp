// tear: a script's cut as the remesher takes it (`to_cut_line`, declared in tear/cloth.h): the
// script layer turns its cuts into CutLines, so the cloth below it knows nothing of scripts.
#include <array>
#include <cmath>

#include "script/unit_vector.h"
#include "tear/cloth.h"
#include "tear/cut_script.h"

namespace tear {

namespace {
using Vec3 = std::array<double, 3>;
// Scaled by the largest component first: a direction such as [1e308, 1e308, 0] or [0, 0, 1e-320]
// would overflow or underflow its squared length.
Vec3 normalized(const Vec3& v) { return unit_vector(v); }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
/// A unit vector perpendicular to unit `d`, from the coordinate axis least aligned with it.
Vec3 perpendicular(const Vec3& d) {
  int axis = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(d[i]) < std::abs(d[axis])) axis = i;
  Vec3 e{0, 0, 0};
  e[axis] = 1;
  return normalized(cross(d, e));
}
}  // namespace

CutLine to_cut_line(const Cut& cut) {
  CutLine line;
  switch (cut.kind) {
    case CutKind::polyline:
      line.polyline = cut.polyline2;
      if (cut.space == CutSpace::uv) {
        line.source = CutLine::Source::corner_uv;
      } else {
        line.source = CutLine::Source::node_rest;
        const auto axes = rest_plane_axes(cut.space);
        line.axis_u = {0, 0, 0};
        line.axis_v = {0, 0, 0};
        line.axis_u[axes[0]] = 1;
        line.axis_v[axes[1]] = 1;
      }
      break;
    case CutKind::blade: {
      // Projecting along the sweep direction turns the swept surface into the polyline itself.
      const Vec3 d = normalized(cut.direction);
      line.source = CutLine::Source::node_pos;
      line.axis_u = perpendicular(d);
      line.axis_v = cross(d, line.axis_u);
      for (const auto& p : cut.polyline3) line.polyline.push_back({dot(p, line.axis_u), dot(p, line.axis_v)});
      break;
    }
    case CutKind::plane: {
      // Along a direction d inside the plane, the plane projects to the line u = point·normal.
      const Vec3 n = normalized(cut.normal);
      const Vec3 d = perpendicular(n);
      line.source = CutLine::Source::node_pos;
      line.axis_u = n;
      line.axis_v = cross(n, d);
      const double u = dot(cut.point, n), v = dot(cut.point, line.axis_v);
      line.polyline = {{u, v - 1.0}, {u, v + 1.0}};
      line.unbounded_start = line.unbounded_end = true;
      break;
    }
  }
  return line;
}

}  // namespace tear
