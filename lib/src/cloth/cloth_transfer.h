// tear: the transfer job of the cloth engine: the cloth record from a mesh (upload), a frame's
// arrays to the host (download), and the record to and from a checkpoint. Each walks the record's
// attribute table (cloth_data/device_cloth.h), so a new attribute needs no code here.
//
// Example: a mesh of 2 faces with UVs and no normals uploads face_nodes [6], node_rest and
// node_pos [nodes * 3], node_vel zeros, corner_uv [12], corner_normal empty, face_origin [0, 1],
// corner_origin the unit weights, input_face_border from the topology; its checkpoint is every
// table array in table order, each as its element count and bytes.
// Only for device code (the .inl files).
#pragma once

#include <cstring>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

#include <thrust/copy.h>
#include <thrust/for_each.h>
#include <thrust/iterator/counting_iterator.h>

#include "backend/backend.h"
#include "cloth_data/device_cloth.h"
#include "node_identity.h"
#include "tear/cut_script.h"  // max_frames: the checkpoint's frame is one of a script's
#include "tear/error.h"
#include "tear/pending_mesh.h"
#include "topology/device_topology.h"

namespace tear::backend {

namespace transfer_detail {
/// Bit j of input face f: its edge j (opposite corner j) is on the border.
struct mark_input_face_border {
  const index_t* face_edges;
  const index_t* edge_faces;
  std::uint8_t* input_face_border;
  TEAR_HD void operator()(index_t f) const {
    std::uint8_t bits = 0;
    for (int j = 0; j < 3; ++j)
      if (edge_faces[2 * face_edges[3 * f + j] + 1] < 0) bits |= std::uint8_t(1u << j);
    input_face_border[f] = bits;
  }
};

/// The unit weights of corner k of its own face: (1,0,0), (0,1,0), (0,0,1).
struct unit_corner_weights {
  float* corner_origin;
  TEAR_HD void operator()(index_t c) const {
    for (int j = 0; j < 3; ++j) corner_origin[3 * c + j] = (c % 3 == j) ? 1.f : 0.f;
  }
};
}  // namespace transfer_detail

/// The cloth record of `mesh` as read: every table attribute with a mesh field from that field
/// (node_rest from the positions; a missing velocity is zero), the mesh as its own origin, its
/// topology built with `scratch`.
template <class System>
void upload_cloth(DeviceCloth<System>& c, const Mesh& mesh, TopologyScratch<System>& scratch,
                  TemporaryAllocator<System>& alloc) {
  using namespace transfer_detail;
  const std::size_t nodes = mesh.node_pos.size() / 3, faces = mesh.face_nodes.size() / 3;
  c.for_each_attribute([&](const auto& a, auto& v) {
    using T = typename std::decay_t<decltype(v)>::value_type;
    const std::size_t size = a.comps * DeviceCloth<System>::element_count(a.element, nodes, faces, faces);
    if (a.mesh && (mesh.*a.mesh).size() == size)
      assign_from_host(v, mesh.*a.mesh);
    else if (!a.optional && a.carry != Carry::written)
      v.assign(size, T(0));
  });
  assign_from_host(c.node_rest, mesh.node_pos);
  build_device_topology(c.topo, c.face_nodes, mesh.node_count(), scratch, alloc);
  const index_t f_count = c.face_count();
  const thrust::counting_iterator<index_t> zero(0);
  const auto policy = Traits<System>::policy();
  thrust::copy(policy, zero, zero + f_count, c.face_origin.begin());
  thrust::for_each(policy, zero, zero + 3 * f_count, unit_corner_weights{raw<float>(c.corner_origin)});
  c.input_face_border.resize(f_count);
  thrust::for_each(policy, zero, zero + f_count,
                   mark_input_face_border{raw<index_t>(c.topo.face_edges), raw<index_t>(c.topo.edge_faces),
                                          raw<std::uint8_t>(c.input_face_border)});
}

/// A frame on its way to the host (`Cloth::mesh_later`): the table's arrays that have a mesh field,
/// and the origins and torn edges derived from the carried ones, in one block of backend memory,
/// copied to the host beside the backend's later work; `take` builds the mesh from the copy.
template <class System>
struct MeshCopy final : PendingMesh::Source {
  /// One array of the block: where it lies, and how it goes into the mesh.
  struct Field {
    std::size_t at, bytes;
    std::function<void(Mesh&, const char*)> into_mesh;
  };
  std::vector<Field> fields;
  std::size_t bytes = 0;  // the block's size
  std::size_t at_origin_bary = 0, at_origin_face = 0, at_torn = 0;
  index_t nodes = 0, faces = 0;
  vector<System, char> frame;  // before `copy`: freed after the copy is waited for
  typename Traits<System>::HostCopy copy;

  std::size_t place(std::size_t size) {
    const std::size_t at = bytes;
    bytes = (bytes + size + 15) / 16 * 16;
    return at;
  }

  Mesh take() override {
    const char* host = static_cast<const char*>(copy.wait());
    const std::size_t n = static_cast<std::size_t>(nodes), f = static_cast<std::size_t>(faces);
    Mesh m;
    // Each array is copied out on a thread of its own (a frame's arrays are a few, of many megabytes).
    const int field_count = static_cast<int>(fields.size());
#pragma omp parallel for schedule(dynamic, 1) if (f >= 16384)
    for (int i = 0; i < field_count; ++i) fields[i].into_mesh(m, host + fields[i].at);
    assign(m.node_origin_bary, host + at_origin_bary, 2 * n);
    assign(m.node_origin_face, host + at_origin_face, n);
    const auto* torn = reinterpret_cast<const std::uint8_t*>(host + at_torn);
    for (std::size_t corner = 0; corner < 3 * f; ++corner)
      if (torn[corner]) {
        const std::size_t face = corner / 3, k = corner % 3;
        m.torn_edge_nodes.push_back(m.face_nodes[3 * face + k]);
        m.torn_edge_nodes.push_back(m.face_nodes[3 * face + (k + 1) % 3]);
      }
    return m;
  }

  /// `count` values of `T` at `from` (placed at a multiple of 16 bytes), copied once (no zeroing).
  template <class T>
  static void assign(std::vector<T>& v, const char* from, std::size_t count) {
    const T* values = reinterpret_cast<const T*>(from);
    v.assign(values, values + count);
  }
};

/// Queues the copy of `c`'s frame to the host (corner normals only with `corner_normals`).
template <class System>
PendingMesh download_cloth_later(const DeviceCloth<System>& c, bool corner_normals) {
  auto copy = std::make_unique<MeshCopy<System>>();
  MeshCopy<System>& m = *copy;
  m.nodes = c.node_count();
  m.faces = c.face_count();
  struct Queued {
    std::size_t at;
    const void* from;
    std::size_t bytes;
  };
  std::vector<Queued> queued;
  c.for_each_attribute([&](const auto& a, const auto& v) {
    using T = typename std::decay_t<decltype(v)>::value_type;
    if (!a.mesh || (a.carry == Carry::unit && !corner_normals) || v.empty()) return;  // normals: on request
    const std::size_t count = v.size(), size = count * sizeof(T);
    const std::size_t at = m.place(size);
    const auto field = a.mesh;
    m.fields.push_back({at, size, [field, count](Mesh& mesh, const char* from) {
                          MeshCopy<System>::assign(mesh.*field, from, count);
                        }});
    queued.push_back({at, raw<T>(v), size});
  });
  const std::size_t n = static_cast<std::size_t>(m.nodes), f = static_cast<std::size_t>(m.faces);
  m.at_origin_bary = m.place(2 * n * sizeof(float));
  m.at_origin_face = m.place(n * sizeof(index_t));
  m.at_torn = m.place(3 * f);
  resize_for_overwrite(m.frame, m.bytes);
  char* base = raw<char>(m.frame);
  // The frame's arrays into one block of backend memory, queued behind its work: the cloth goes on
  // while the block is copied to the host.
  const auto policy = Traits<System>::policy();
  for (const Queued& q : queued) {
    const char* from = static_cast<const char*>(q.from);
    thrust::copy(policy, from, from + q.bytes, base + q.at);
  }
  // Origins and torn edges, derived on the backend from the carried face and corner origins.
  for_each_index<System>(m.nodes, kernels::gather_node_origins{
                                      raw<index_t>(c.face_nodes), raw<index_t>(c.topo.node_face_offset),
                                      raw<index_t>(c.topo.node_faces), raw<index_t>(c.face_origin),
                                      raw<float>(c.corner_origin), reinterpret_cast<index_t*>(base + m.at_origin_face),
                                      reinterpret_cast<float*>(base + m.at_origin_bary)});
  for_each_index<System>(3 * m.faces, kernels::mark_torn_corners{
                                          raw<index_t>(c.topo.face_edges), raw<index_t>(c.topo.edge_faces),
                                          raw<index_t>(c.face_origin), raw<float>(c.corner_origin),
                                          raw<std::uint8_t>(c.input_face_border),
                                          reinterpret_cast<std::uint8_t*>(base + m.at_torn)});
  m.copy.start(base, m.bytes);
  return PendingMesh(std::move(copy));
}

namespace transfer_detail {
/// An array as its element count (8 bytes, little endian as the machine) and its bytes.
template <class T>
void put(std::string& out, const std::vector<T>& host) {
  const std::uint64_t count = host.size();
  out.append(reinterpret_cast<const char*>(&count), sizeof count);
  out.append(reinterpret_cast<const char*>(host.data()), host.size() * sizeof(T));
}
template <class T>
std::vector<T> take(const std::string& in, std::size_t& at, const std::string& source) {
  std::uint64_t count = 0;
  if (in.size() - at < sizeof count) throw input_error(source, "the cloth's arrays are cut short");
  std::memcpy(&count, in.data() + at, sizeof count);
  at += sizeof count;
  if (count > (in.size() - at) / sizeof(T)) throw input_error(source, "the cloth's arrays are cut short");
  std::vector<T> host(count);
  if (count > 0) std::memcpy(host.data(), in.data() + at, count * sizeof(T));
  at += count * sizeof(T);
  return host;
}
}  // namespace transfer_detail

/// The record as bytes: every table array in table order, then `frames_stepped`.
template <class System>
std::string save_cloth(const DeviceCloth<System>& c, int frames_stepped) {
  std::string out;
  c.for_each_attribute([&](const auto&, const auto& v) {
    using T = typename std::decay_t<decltype(v)>::value_type;
    transfer_detail::put(out, to_host<T>(v));
  });
  transfer_detail::put(out, std::vector<std::int64_t>{frames_stepped});
  return out;
}

/// The record of `save_cloth`'s bytes, its topology built; every array's size checked against its
/// element's count, every face's nodes and origin in range. Throws an input `Error` naming `source`.
template <class System>
void load_cloth(DeviceCloth<System>& c, int& frames_stepped, const std::string& state, const std::string& source,
                TopologyScratch<System>& scratch, TemporaryAllocator<System>& alloc) {
  std::size_t at = 0;
  c.for_each_attribute([&](const auto&, auto& v) {
    using T = typename std::decay_t<decltype(v)>::value_type;
    assign_from_host(v, transfer_detail::take<T>(state, at, source));
  });
  const std::vector<std::int64_t> frames = transfer_detail::take<std::int64_t>(state, at, source);
  const std::size_t f = c.face_nodes.size() / 3, n = c.node_rest.size() / 3, input_faces = c.input_face_border.size();
  bool sizes = at == state.size() && frames.size() == 1;
  c.for_each_attribute([&](const auto& a, const auto& v) {
    const std::size_t want = a.comps * DeviceCloth<System>::element_count(a.element, n, f, input_faces);
    sizes = sizes && (v.size() == want || (a.optional && v.empty()));
  });
  if (!sizes) throw input_error(source, "the cloth's arrays do not fit together (a damaged or foreign checkpoint)");
  const std::vector<index_t> nodes = to_host<index_t>(c.face_nodes);
  const std::vector<index_t> origins = to_host<index_t>(c.face_origin);
  const index_t input_face_count = static_cast<index_t>(input_faces);
  if (std::any_of(nodes.begin(), nodes.end(), [&](index_t v) { return v < 0 || v >= index_t(n); }) ||
      std::any_of(origins.begin(), origins.end(), [&](index_t v) { return v < 0 || v >= input_face_count; }))
    throw input_error(source, "a face names a node or an input face out of range (a damaged or foreign checkpoint)");
  if (frames[0] < 0 || frames[0] > max_frames)
    throw input_error(source, "the cloth's frame count is out of range (a damaged or foreign checkpoint)");
  build_device_topology(c.topo, c.face_nodes, static_cast<index_t>(n), scratch, alloc);
  frames_stepped = static_cast<int>(frames[0]);
}

}  // namespace tear::backend
