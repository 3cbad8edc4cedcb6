// tear: the one record of a cloth on a backend, which the remesher and the solver both work on in
// place (docs/identity.md, docs/architecture.md). It sits below both pipelines: `remesh/` and
// `sim/` include it, it includes only the backend and the topology.
//
// One table, `DeviceCloth::for_each_attribute`, declares every array of the record once: its
// element, components, how a cut carries it, its role, and the field of `tear::Mesh` it comes from
// and goes to. Upload (the engine's constructor), download (a frame's copy to the host), the cut's
// carry (the remesher) and the checkpoint iterate that table, so a new attribute is one line there
// (and, if it is written out, its writer's field).
//
//   model   face_nodes, node_rest, corner UVs and normals (the topology is derived from face_nodes)
//   state   node_pos, node_vel
//   carried node_pinned, face_origin, corner_origin, face_strength, face_piece (every array a cut carries)
//
// Example: a sheet of 2 faces read from a file: face_origin = [0, 1], corner_origin = the unit
// weights (1,0,0 | 0,1,0 | 0,0,1) of each face's corners; after a cut through face 1, the new
// faces all have face_origin 1 and their corners the weights of where they lie in face 1.
#pragma once

#include <cstdint>
#include <vector>

#include "backend/backend.h"
#include "tear/mesh.h"
#include "topology/device_topology.h"

namespace tear::backend {

/// The element an attribute has one value (of `comps` components) per.
enum class Element : std::uint8_t { node, corner, face, input_face };

/// How a cut carries an attribute onto the mesh it makes (docs/remesher.md, *carried attributes*).
enum class Carry : std::uint8_t {
  written,      ///< the cut writes it itself (face_nodes), or the mesh as read fixes it (input_face)
  interpolate,  ///< node values over the new node's sources, corner values inside the parent face
  unit,         ///< as `interpolate`, renormalised (normals)
  copy,         ///< node flags: kept by a node's copies, 0 on nodes made inside an edge or a face
  parent,       ///< face values: each new face takes its parent's
};

/// Newton's tags: model data the solver derives its model from, state it steps, data carried along.
enum class Role : std::uint8_t { model, state, carried };

/// A field of `tear::Mesh` holding an array of `T`.
template <class T>
using MeshField = std::vector<T> Mesh::*;

/// One line of the table. `T` is the array's element type.
template <class T>
struct Attribute {
  const char* name;
  Element element;
  int comps;
  Carry carry;
  Role role;
  bool optional;                ///< may be empty (a mesh without UVs): skipped by the carry
  MeshField<T> mesh;  ///< the field of `tear::Mesh` it is read from and written to, or null
};

template <class System>
struct DeviceCloth {
  template <class T>
  using vec = vector<System, T>;

  // Model.
  vec<index_t> face_nodes;   ///< [face_count * 3]
  vec<float> node_rest;      ///< [node_count * 3] metres
  vec<float> corner_uv;      ///< [face_count * 3 * 2] or empty
  vec<float> corner_normal;  ///< [face_count * 3 * 3] or empty
  DeviceTopology<System> topo;
  // State.
  vec<float> node_pos;  ///< [node_count * 3] metres
  vec<float> node_vel;  ///< [node_count * 3] m/s
  // Carried attributes besides the model and state.
  vec<std::uint8_t> node_pinned;  ///< [node_count] 0 free, p + 1 held by pin p
  vec<index_t> face_origin;       ///< [face_count] the face of the mesh as read this face lies in
  vec<float> corner_origin;       ///< [face_count * 3 * 3] the corner's weights in its origin face
  /// [face_count] or empty: the factor on the tearing limits of the fabric in this face (strength
  /// map, variation; docs/simulation.md, *Tearing*), set when a simulation with tearing starts.
  vec<float> face_strength;
  /// [face_count] the connected piece of the face (docs/identity.md, *Pieces*): carried from the
  /// parent through a cut, then renumbered by the engine (cloth/face_pieces.h).
  vec<index_t> face_piece;
  // Of the mesh as read, not carried: bit j of face F = F's edge j was on the border.
  vec<std::uint8_t> input_face_border;

  index_t node_count() const { return topo.node_count; }
  index_t face_count() const { return topo.face_count; }

  /// The table: `f(attribute, array)` for every array of the record, in a fixed order (the
  /// checkpoint's). A new attribute is a new line here.
  template <class F>
  void for_each_attribute(F&& f) {
    visit(*this, f);
  }
  template <class F>
  void for_each_attribute(F&& f) const {
    visit(*this, f);
  }

  /// The number of values an attribute of `element` has in a cloth of these counts.
  static std::size_t element_count(Element e, std::size_t nodes, std::size_t faces, std::size_t input_faces) {
    switch (e) {
      case Element::node:
        return nodes;
      case Element::corner:
        return 3 * faces;
      case Element::face:
        return faces;
      case Element::input_face:
        return input_faces;
    }
    return 0;
  }

 private:
  template <class Self, class F>
  static void visit(Self& c, F& f) {
    using E = Element;
    using C = Carry;
    using R = Role;
    // clang-format off
    f(Attribute<index_t>{"face_nodes", E::face, 3, C::written, R::model, false, &Mesh::face_nodes}, c.face_nodes);
    f(Attribute<float>{"node_rest", E::node, 3, C::interpolate, R::model, false, &Mesh::node_rest}, c.node_rest);
    f(Attribute<float>{"corner_uv", E::corner, 2, C::interpolate, R::model, true, &Mesh::corner_uv}, c.corner_uv);
    f(Attribute<float>{"corner_normal", E::corner, 3, C::unit, R::model, true, &Mesh::corner_normal}, c.corner_normal);
    f(Attribute<float>{"node_pos", E::node, 3, C::interpolate, R::state, false, &Mesh::node_pos}, c.node_pos);
    f(Attribute<float>{"node_vel", E::node, 3, C::interpolate, R::state, false, &Mesh::node_vel}, c.node_vel);
    f(Attribute<std::uint8_t>{"node_pinned", E::node, 1, C::copy, R::carried, false, nullptr}, c.node_pinned);
    f(Attribute<index_t>{"face_origin", E::face, 1, C::parent, R::carried, false, nullptr}, c.face_origin);
    f(Attribute<float>{"corner_origin", E::corner, 3, C::interpolate, R::carried, false, nullptr}, c.corner_origin);
    f(Attribute<std::uint8_t>{"input_face_border", E::input_face, 1, C::written, R::model, false, nullptr}, c.input_face_border);
    f(Attribute<float>{"face_strength", E::face, 1, C::parent, R::carried, true, nullptr}, c.face_strength);
    f(Attribute<index_t>{"face_piece", E::face, 1, C::parent, R::carried, false, &Mesh::face_piece}, c.face_piece);
    // clang-format on
  }
};

}  // namespace tear::backend
