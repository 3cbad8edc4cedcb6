// tear: a triangle cloth mesh on the host, as structure-of-arrays index buffers.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tear {

/// The one index type of the project. `-1` means "none" wherever an index can be missing.
using index_t = std::int32_t;
inline constexpr index_t none = -1;

/// A triangle mesh on the host.
///
/// Topology is carried by `face_nodes` over welded nodes; UVs and normals are per face corner
/// (corner `c = 3 * face + k`), so UV seams and hard edges survive welding and cutting.
/// In face `f`, local node `k` is opposite local edge `k`; edge `k` joins nodes `k+1` and `k+2`
/// (mod 3).
struct Mesh {
  std::vector<float> node_pos;        ///< [node_count * 3] positions (x, y, z), metres
  std::vector<index_t> face_nodes;    ///< [face_count * 3] node indices, counter-clockwise
  std::vector<float> corner_uv;       ///< [face_count * 3 * 2] or empty when the mesh has no UVs
  std::vector<float> corner_normal;   ///< [face_count * 3 * 3] or empty when it has no normals

  // Identity, carried by the cloth through cuts (docs/identity.md). A node's index is its
  // persistent id: the nodes of the mesh as read keep theirs, a cut appends. Each array is empty
  // when unknown (a mesh as read from a file without them); writers then write 0 / -1.
  std::vector<float> node_vel;            ///< [node_count * 3] velocities, m/s
  std::vector<index_t> node_origin_face;  ///< [node_count] face of the mesh as read the node lies in
  /// [node_count * 2] (u, v): the node's barycentric weights, in the rest shape, of its origin
  /// face's 2nd and 3rd corner (the 1st has 1 - u - v).
  std::vector<float> node_origin_bary;
  /// [torn_edge_count * 2] node pairs: the boundary edges that lie on a cut or tear of this run.
  std::vector<index_t> torn_edge_nodes;
  /// [face_count] the id of the connected piece each face is in, stable through the run (docs/identity.md,
  /// *Pieces*): numbered in order of their lowest face at the start; when a piece splits, the part with
  /// the largest rest area keeps its id and the others take the next unused ids.
  std::vector<index_t> face_piece;
  /// [node_count * 3] or empty: the rest (unstretched, uncut-into) positions, metres; a frame of a
  /// `tear::Cloth` carries them (the USD layer's `primvars:rest`).
  std::vector<float> node_rest;

  index_t node_count() const { return static_cast<index_t>(node_pos.size() / 3); }
  index_t face_count() const { return static_cast<index_t>(face_nodes.size() / 3); }
  bool has_uv() const { return !corner_uv.empty(); }
  bool has_normals() const { return !corner_normal.empty(); }
  bool has_velocities() const { return !node_vel.empty(); }
  bool has_origins() const { return !node_origin_face.empty(); }
  bool has_rest() const { return !node_rest.empty() && node_rest.size() == node_pos.size(); }
  bool has_pieces() const { return !face_piece.empty() && face_piece.size() == face_nodes.size() / 3; }
};

}  // namespace tear
