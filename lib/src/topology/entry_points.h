// tear: the per-system entry points of the topology stages that host code dispatches to (see
// backend/systems.h).
#pragma once

#include "backend/systems.h"
#include "tear/mesh.h"
#include "tear/topology.h"
#include "tear/validate_mesh.h"

namespace tear::backend {

template <class System>
Topology build_topology_on(const Mesh& mesh);

template <class System>
MeshReport check_indices_on(const Mesh& mesh);

template <class System>
MeshReport validate_mesh_on(const Mesh& mesh, const Topology& topology);

/// `validate_mesh_on` with the topology built on the backend: the mesh is uploaded once.
template <class System>
MeshReport validate_mesh_on(const Mesh& mesh);

}  // namespace tear::backend
