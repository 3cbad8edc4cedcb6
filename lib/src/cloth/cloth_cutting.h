// tear: the cut job of the cloth engine: scripted cuts and tears, both through the remesher's
// second half (docs/remesher.md), and the box pins that hold what a cut makes inside them.
// Only for device code (the .inl files).
#pragma once

#include <thrust/for_each.h>
#include <thrust/iterator/counting_iterator.h>

#include "backend/backend.h"
#include "cloth_data/device_cloth.h"
#include "remesh/remesher.h"
#include "tear/cloth.h"
#include "tear/simulation_options.h"

namespace tear::backend {

namespace cutting_detail {
/// Pins every node whose rest position lies in one of the boxes ([box * 7]: min xyz, max xyz, the
/// pin's value p + 1) to the first pin that holds it: a node already held by an earlier pin keeps it.
struct pin_boxes {
  const float* node_rest;
  const double* boxes;
  int box_count;
  std::uint8_t* node_pinned;
  TEAR_HD void operator()(index_t n) const {
    for (int b = 0; b < box_count; ++b) {
      bool inside = true;
      for (int a = 0; a < 3; ++a) {
        const double x = node_rest[3 * n + a];
        inside = inside && x >= boxes[7 * b + a] && x <= boxes[7 * b + 3 + a];
      }
      const auto pin = static_cast<std::uint8_t>(boxes[7 * b + 6]);
      if (inside && (node_pinned[n] == 0 || node_pinned[n] > pin)) node_pinned[n] = pin;
    }
  }
};
}  // namespace cutting_detail

template <class System>
class CutJob {
 public:
  Remesher<System>& remesher() { return remesher_; }
  const Remesher<System>& remesher() const { return remesher_; }

  /// Cuts `cloth` along `cuts`; returns whether the mesh changed.
  CutStats cut(DeviceCloth<System>& cloth, const std::vector<CutLine>& cuts, const CutOptions& options, bool& changed) {
    CutStats stats;
    stats.nodes_before = stats.nodes_after = cloth.node_count();
    stats.faces_before = stats.faces_after = cloth.face_count();
    StageClock clock(options.time_stages, stats.stage_ms.data());
    changed = remesher_.cut_info_from_paths(cloth, cuts, options, clock) &&
              remesher_.apply_cut_info(cloth, options, stats, clock);
    if (changed) reapply_box_pins(cloth);
    Traits<System>::synchronize();
    stats.total_ms = clock.total_ms();
    return stats;
  }

  /// The box pins of a simulation ([box * 7] as `pin_boxes` reads them), applied now and after
  /// every cut and tear.
  void set_pin_boxes(DeviceCloth<System>& cloth, const std::vector<double>& boxes) {
    assign_from_host(pin_boxes_, boxes);
    reapply_box_pins(cloth);
  }

  void reapply_box_pins(DeviceCloth<System>& cloth) {
    if (pin_boxes_.empty()) return;
    const thrust::counting_iterator<index_t> zero(0);
    thrust::for_each(Traits<System>::policy(), zero, zero + cloth.node_count(),
                     cutting_detail::pin_boxes{raw<float>(cloth.node_rest), raw<double>(pin_boxes_),
                                               static_cast<int>(pin_boxes_.size() / 7),
                                               raw<std::uint8_t>(cloth.node_pinned)});
  }

 private:
  Remesher<System> remesher_;
  vector<System, double> pin_boxes_;  // [box * 7] of the simulation's box pins (pin_boxes)
};

}  // namespace tear::backend
