// tear: directions scaled to unit length without overflow or underflow, for the directions a
// script gives (blade directions, plane and collider normals): any finite non-zero vector, from
// [0, 0, 1e-320] to [1e308, 1e308, 0], has one.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

namespace tear {

/// The length of `v`, computed on `v` divided by its largest absolute component: finite whenever
/// the length is, and not 0 for a non-zero `v` ([0, 0, 1e-320] has length 1e-320).
inline double vector_length(const std::array<double, 3>& v) {
  const double scale = std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])});
  if (!(scale > 0) || !std::isfinite(scale)) return scale;
  const double x = v[0] / scale, y = v[1] / scale, z = v[2] / scale;
  return scale * std::sqrt(x * x + y * y + z * z);
}

/// `v` divided by its length, computed on `v` divided by its largest absolute component first: the
/// squares then lie in [0, 1] and their sum in [1, 3], so nothing overflows or underflows to 0.
/// Example: [1e308, 1e308, 0] → [0.7071, 0.7071, 0]; [0, 0, 1e-320] → [0, 0, 1]. A zero or
/// non-finite `v` gives [0, 0, 0].
inline std::array<double, 3> unit_vector(const std::array<double, 3>& v) {
  const double scale = std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])});
  if (!(scale > 0) || !std::isfinite(scale)) return {0, 0, 0};
  const std::array<double, 3> w{v[0] / scale, v[1] / scale, v[2] / scale};
  const double length = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  return {w[0] / length, w[1] / length, w[2] / length};
}

/// `b - a` when it is finite, else `b / 2 - a / 2` (same direction, half the length): the
/// difference of two finite points may overflow ([-1e308, 0, 0] to [1e308, 0, 0]).
inline std::array<double, 3> finite_difference(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  std::array<double, 3> d{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  if (std::isfinite(d[0]) && std::isfinite(d[1]) && std::isfinite(d[2])) return d;
  return {b[0] / 2 - a[0] / 2, b[1] / 2 - a[1] / 2, b[2] / 2 - a[2] / 2};
}

}  // namespace tear
