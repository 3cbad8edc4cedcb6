// tear: a cloth held on a backend, cut in place by the GPU remesher (paper §2).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "tear/cut_script.h"
#include "tear/device.h"
#include "tear/mesh.h"
#include "tear/topology.h"

namespace tear {

/// A cut as the remesher takes it: a 2D polyline, and where the mesh's 2D coordinates come from.
/// Script cuts become CutLines through `to_cut_line`.
struct CutLine {
  enum class Source { corner_uv, node_rest, node_pos };
  Source source = Source::node_rest;
  std::array<double, 3> axis_u{1, 0, 0};  ///< 3D sources: a point p projects to (p·axis_u, p·axis_v)
  std::array<double, 3> axis_v{0, 1, 0};
  std::vector<std::array<double, 2>> polyline;  ///< [n >= 2]
  bool unbounded_start = false;  ///< the first segment extends backwards without end
  bool unbounded_end = false;    ///< the last segment extends forwards without end
};

/// The CutLine of a script cut: `uv` reads corner UVs; `rest-*` the rest shape on that plane; a
/// blade projects the current pose along its direction; a plane is a line unbounded both ways in
/// a projection along one of its own directions.
CutLine to_cut_line(const Cut& cut);

/// Options of `Cloth::cut`; mirrored by the script key `snap`.
struct CutOptions {
  double snap = default_snap;  ///< cut points nearer a node than this fraction of their edge move onto it
  /// A face whose split would have an angle sharper than this (degrees, on the rest shape) moves
  /// its cut point nearest a node onto that node, when nearer than `quality_snap` of its edge
  /// (twice, so the face across a moved point is checked again). 0 turns this off, and so does
  /// `snap` 0 (exact cut points). Measured on the paper's scene (docs/remesher.md): without it
  /// six crossing cuts leave angles of 2.5 degrees, with it no angle below 5.
  double quality_angle_deg = 5.0;
  double quality_snap = 0.3;
  /// Measure the time of every stage (`CutStats::stage_ms`); adds a device synchronisation after
  /// each stage, so leave it off outside benchmarks.
  bool time_stages = false;
};

/// The stages of a cut, in order (paper §2.1–2.4), for `CutStats::stage_ms`.
enum class CutStage { intersection, cut_info, counts_and_scans, node_write, face_write, node_mapping, adjacency, count };
const char* to_string(CutStage stage);

/// What one `Cloth::cut` did.
struct CutStats {
  index_t nodes_before = 0, faces_before = 0;
  index_t nodes_after = 0, faces_after = 0;
  index_t edge_points = 0;  ///< edges with a cut point inside them
  index_t face_points = 0;  ///< faces whose cut lines cross
  index_t cut_edges = 0;    ///< edges with a cut line along them (edge cut info != 0)
  /// Milliseconds per stage when `CutOptions::time_stages` is set (zeros otherwise, and for the
  /// stages a cut that splits nothing skips).
  std::array<double, static_cast<int>(CutStage::count)> stage_ms{};
  double total_ms = 0;  ///< wall time of the whole cut, measured always
};

/// Where each node and face of the mesh after a cut came from, in the mesh before it.
struct CutProvenance {
  std::vector<index_t> node_source;        ///< [node_count * 3] old nodes (-1 unused)
  std::vector<float> node_source_weight;   ///< [node_count * 3] interpolation weights (sum 1)
  std::vector<index_t> face_parent;        ///< [face_count] old face each new face lies in
};

/// A cloth mesh and its state (positions, rest positions, velocities) held on a backend.
class Cloth {
 public:
  /// Uploads `mesh` (rest shape = current positions, velocities 0). The mesh must pass
  /// `validate_mesh` (the remesher needs an oriented manifold); callers check first.
  Cloth(const Mesh& mesh, Device device);
  ~Cloth();
  Cloth(Cloth&&) noexcept;
  Cloth& operator=(Cloth&&) noexcept;

  Device device() const;
  index_t node_count() const;
  index_t face_count() const;

  /// Applies `cuts` together (one frame's cuts), remeshing on the device. Cuts that miss the
  /// cloth, or retrace an existing tear, change nothing.
  CutStats cut(const std::vector<CutLine>& cuts, const CutOptions& options = {});

  /// The current mesh: positions, faces, per-corner UVs and normals.
  Mesh mesh() const;
  Topology topology() const;
  std::vector<float> node_pos() const;   ///< [node_count * 3] metres
  std::vector<float> node_rest() const;  ///< [node_count * 3] metres
  std::vector<float> node_vel() const;   ///< [node_count * 3] m/s
  /// Replaces the positions and velocities, both [node_count * 3] (a usage `Error` otherwise), from
  /// the host; rest positions stay. A simulation step hands its result back to the cloth this way.
  void set_node_state(const std::vector<float>& node_pos, const std::vector<float>& node_vel);
  /// Provenance of the last cut (empty before the first).
  CutProvenance provenance() const;

  class Engine;  ///< the per-backend implementation

 private:
  friend class PdSolver;  // steps the cloth's state where it lives (PdSolver::step(Cloth&))
  std::unique_ptr<Engine> engine_;
};

}  // namespace tear
