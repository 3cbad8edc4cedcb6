#include "tear/topology.h"

#include "topology/entry_points.h"

namespace tear {

Topology build_topology(const Mesh& mesh, Device device) {
  return backend::dispatch(device, [&](auto system) { return backend::build_topology_on<decltype(system)>(mesh); });
}

}  // namespace tear
