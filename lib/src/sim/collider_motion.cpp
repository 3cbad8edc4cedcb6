// tear: where a mesh collider's vertices are at a time: its sequence's frames, its keys' turn about
// the pivot and their offset (docs/simulation.md, *Mesh colliders*).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "tear/simulation_options.h"

namespace tear {
namespace {

using Quat = std::array<double, 4>;  // w, x, y, z

constexpr double degrees_to_radians = 3.14159265358979323846 / 180.0;

Quat axis_angle(const std::array<double, 3>& axis, double degrees) {
  const double half = 0.5 * degrees * degrees_to_radians;
  const double s = std::sin(half);
  return {std::cos(half), s * axis[0], s * axis[1], s * axis[2]};
}

/// The orientation between two keys' at weight `w`: where both turn about one axis, the angle
/// linear between them (so keys 0° and 360° make a whole turn); else the shorter way between the
/// two orientations (spherical linear interpolation).
Quat between(const Key& a, const Key& b, double w) {
  if (a.axis == b.axis || a.degrees == 0 || b.degrees == 0) {
    // One axis (a key without a turn has no angle about any): the angle, linear.
    return axis_angle(a.degrees != 0 ? a.axis : b.axis, a.degrees + w * (b.degrees - a.degrees));
  }
  Quat qa = axis_angle(a.axis, a.degrees), qb = axis_angle(b.axis, b.degrees);
  double cosine = qa[0] * qb[0] + qa[1] * qb[1] + qa[2] * qb[2] + qa[3] * qb[3];
  if (cosine < 0) {
    for (double& c : qb) c = -c;
    cosine = -cosine;
  }
  double wa = 1 - w, wb = w;
  if (cosine < 0.9999) {
    const double angle = std::acos(cosine), s = std::sin(angle);
    wa = std::sin((1 - w) * angle) / s;
    wb = std::sin(w * angle) / s;
  }
  Quat q{};
  double length = 0;
  for (int i = 0; i < 4; ++i) {
    q[i] = wa * qa[i] + wb * qb[i];
    length += q[i] * q[i];
  }
  length = std::sqrt(length);
  for (double& c : q) c /= length;
  return q;
}

/// The keys' orientation at `time`, as `key_offset` places the offset: the first key's before it,
/// the last's after it.
Quat key_rotation(const std::vector<Key>& keys, double time) {
  if (keys.empty()) return {1, 0, 0, 0};
  if (!(time > keys.front().frame)) return axis_angle(keys.front().axis, keys.front().degrees);
  if (!(time < keys.back().frame)) return axis_angle(keys.back().axis, keys.back().degrees);
  std::size_t k = 1;
  while (keys[k].frame <= time) ++k;
  const Key& a = keys[k - 1];
  const Key& b = keys[k];
  return between(a, b, (time - a.frame) / static_cast<double>(b.frame - a.frame));
}

std::array<double, 3> rotate(const Quat& q, const std::array<double, 3>& v) {
  // v + 2 w (u × v) + 2 u × (u × v), u the vector part.
  const std::array<double, 3> u{q[1], q[2], q[3]};
  const std::array<double, 3> t{2 * (u[1] * v[2] - u[2] * v[1]), 2 * (u[2] * v[0] - u[0] * v[2]),
                                2 * (u[0] * v[1] - u[1] * v[0])};
  return {v[0] + q[0] * t[0] + (u[1] * t[2] - u[2] * t[1]), v[1] + q[0] * t[1] + (u[2] * t[0] - u[0] * t[2]),
          v[2] + q[0] * t[2] + (u[0] * t[1] - u[1] * t[0])};
}

}  // namespace

void collider_positions(const Collider& collider, double time, std::vector<float>& out) {
  const ColliderMesh& mesh = *collider.mesh;
  const std::size_t n = mesh.frames.front().size();
  out.resize(n);
  // The sequence's frames around `time`.
  const int last = mesh.first_frame + static_cast<int>(mesh.frames.size()) - 1;
  const double t = std::min<double>(std::max<double>(time, mesh.first_frame), last);
  const int i = std::min(static_cast<int>(std::floor(t)), last) - mesh.first_frame;
  const int j = std::min(i + 1, static_cast<int>(mesh.frames.size()) - 1);
  const double w = t - (mesh.first_frame + i);
  const std::vector<float>& a = mesh.frames[static_cast<std::size_t>(i)];
  const std::vector<float>& b = mesh.frames[static_cast<std::size_t>(j)];
  const bool turns =
      std::any_of(collider.keys.begin(), collider.keys.end(), [](const Key& k) { return k.degrees != 0; });
  const Quat q = key_rotation(collider.keys, time);
  const std::array<double, 3> offset = key_offset(collider.keys, time);
  for (std::size_t v = 0; v < n; v += 3) {
    std::array<double, 3> p{};
    for (int c = 0; c < 3; ++c) p[c] = a[v + c] + w * (static_cast<double>(b[v + c]) - a[v + c]);
    if (turns) {
      for (int c = 0; c < 3; ++c) p[c] -= collider.pivot[c];
      p = rotate(q, p);
      for (int c = 0; c < 3; ++c) p[c] += collider.pivot[c];
    }
    for (int c = 0; c < 3; ++c) out[v + c] = static_cast<float>(p[c] + offset[c]);
  }
}

}  // namespace tear
