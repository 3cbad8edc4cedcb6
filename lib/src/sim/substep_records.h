// tear: the records the kernels see of the pins and the plane and sphere colliders during one
// substep, where their keys put them. Shared by the solver and the collision pass.
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include "pd_step.h"
#include "tear/simulation_options.h"

namespace tear::backend {

/// The pins' and colliders' records of substep `s` (0-based) of frame `frame` (1-based), appended:
/// each keyed one where its keys put it at the substep's end, moving by the change of its offset
/// over the substep. The substep spans times (frame − 1 + s/S, frame − 1 + (s+1)/S), in frames.
/// Mesh colliders have none: the collision pass holds them (cloth/collision_job.h).
inline void substep_records(const SimulationOptions& options, int frame, int s, std::vector<kernels::PdPinMotion>& pins,
                            std::vector<kernels::PdCollider>& colliders) {
  const double start = substep_end_time(frame, s - 1, options.substeps);
  const double end = substep_end_time(frame, s, options.substeps);
  const double inv_h = 1.0 / options.step_seconds();
  // The offset at the substep's end; its change over the substep, as a velocity.
  const auto motion = [&](const std::vector<Key>& keys, float* velocity) {
    const std::array<double, 3> a = key_offset(keys, start), b = key_offset(keys, end);
    for (int i = 0; i < 3; ++i) velocity[i] = static_cast<float>((b[i] - a[i]) * inv_h);
    return b;
  };
  for (const Pin& p : options.pins) {
    kernels::PdPinMotion k{};
    k.keyed = p.keys.empty() ? 0 : 1;
    const std::array<double, 3> offset = motion(p.keys, k.velocity);
    for (int a = 0; a < 3; ++a) k.offset[a] = static_cast<float>(offset[a]);
    pins.push_back(k);
  }
  for (const Collider& c : options.colliders) {
    if (c.kind == Collider::Kind::mesh) continue;  // the collision pass's (cloth/collision_job.h)
    kernels::PdCollider k{};
    k.kind = c.kind == Collider::Kind::plane ? 0 : 1;
    const double len = std::sqrt(c.normal[0] * c.normal[0] + c.normal[1] * c.normal[1] + c.normal[2] * c.normal[2]);
    const std::array<double, 3> offset = motion(c.keys, k.velocity);
    for (int a = 0; a < 3; ++a) {
      // Without keys the point as given, not point + 0 (which turns −0 into +0).
      k.point[a] = static_cast<float>(c.keys.empty() ? c.point[a] : c.point[a] + offset[a]);
      k.normal[a] = static_cast<float>(len > 0 ? c.normal[a] / len : 0.0);
    }
    k.radius = static_cast<float>(c.radius);
    colliders.push_back(k);
  }
}

}  // namespace tear::backend
