// tear: a cloth held on a backend, cut in place by the GPU remesher (paper §2).
#pragma once

#include <array>
#include <csignal>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "tear/cut_script.h"
#include "tear/device.h"
#include "tear/mesh.h"
#include "tear/pending_mesh.h"
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
  /// Check that every writer of the cut writes exactly the slots its scan gave it (the node
  /// provenance, the new faces, the node mapping): each output is filled with a value no writer
  /// writes beforehand and searched for it afterwards; a slot left over throws a runtime `Error`
  /// naming the stage. For tests: it costs a fill and a count per stage.
  bool check_writes = false;
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

/// What tearing did in one `Cloth::step` (docs/simulation.md, "Tearing").
struct TearStats {
  /// Tear events: crack advances and starts laid over the frame's substeps.
  index_t events = 0;
  /// Rest length of the new crack segments, metres (as laid, before the cut points snap).
  double length = 0;
  /// Wall time of the step's parts, milliseconds, each measured after waiting for the backend:
  /// the substeps themselves, deciding where to tear (a pass over the faces and a read-back after
  /// every substep), laying the cracks (the remesher's second half and the box pins applied again),
  /// and rebuilding the solver's model for the torn cloth; `collision_ms`, the collision pass after
  /// the substeps (docs/simulation.md, *Collision*).
  double solver_ms = 0, check_ms = 0, apply_ms = 0, rebuild_ms = 0, collision_ms = 0;
  /// Parts of `check_ms`: the strain rate limit (docs/simulation.md, *Tearing*), and the host's
  /// wait for crack growth's view of the rest mesh after a tear (built beside the next substep on
  /// a GPU, in the check on the CPU).
  double limit_ms = 0, view_ms = 0;
  /// The collision pass: the bytes its arrays hold, and the nodes it has sent back to where they
  /// started a substep (its last resort where contacts still cross) since the simulation started.
  std::size_t collision_bytes = 0;
  std::int64_t held_nodes = 0;
};

struct SimulationOptions;

/// A cloth mesh held on a backend with its state and identity (docs/identity.md): the remesher cuts
/// it in place and the solver steps it in place.
///
/// Identity: node i of the mesh given keeps index i through every cut; a cut appends the nodes it
/// makes (a split node keeps its index for the copy on the side of its lowest-numbered face, see
/// `kernels/walk_sectors.h`), so a node's index is its persistent id. Every node carries its
/// velocity and its origin: the face of the mesh given and the barycentric weights, in the rest
/// shape, of where it lies (`Mesh::node_origin_face`, `node_origin_bary`).
class Cloth {
 public:
  /// Uploads `mesh`: rest shape = current positions, velocities `mesh.node_vel` (0 when empty),
  /// each face its own origin. The mesh must pass `validate_mesh` (the remesher needs an oriented
  /// manifold); callers check first.
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

  /// Simulates the cloth from now on with projective dynamics (docs/simulation.md). Pins: `nodes`
  /// pins name nodes of the cloth as it is now (an input `Error` naming `options.source` when one
  /// is out of range); from then on the copies of a pinned node stay pinned through cuts and a node
  /// a cut makes is free, except that `box` pins also hold every node a cut makes inside a box.
  void simulate(const SimulationOptions& options);
  bool simulated() const;
  /// Advances the state one frame (1 / fps seconds) in place on the backend, the solver's model
  /// rebuilt there after a cut changed the mesh: the frame after the one stepped last (frame 1
  /// after `simulate`; `load_state` restores the count). Queues the work without waiting for it. A
  /// usage `Error` without `simulate`.
  void step();
  /// The same for frame `frame` (>= 1, as a script counts), whose substeps the keys of pins and
  /// colliders are evaluated at; later `step` calls go on from it.
  void step_frame(int frame);
  /// The same, stopping early once `*stop` is non-zero (a signal handler sets it): it is looked at
  /// before every substep, so a stop lands within about a substep however long the frame (work
  /// queued on a GPU is waited for in chunks of substeps that take at least 50 ms, so a stop waits
  /// for at most about twice that and a substep). The substeps are the same work as a whole
  /// frame's, so the bytes are the same. Returns true when the frame was stepped whole; false when
  /// it stopped between substeps, the cloth then part way through the frame, a state of no frame
  /// (a run drops it, and that frame is computed again on resume). `stop` null: `step_frame(frame)`.
  bool step_frame(int frame, const volatile std::sig_atomic_t* stop);
  /// What tearing did in the last step (zeros without `tearing` or before the first step). With
  /// tearing the step checks the cloth after every substep, which waits for the backend there.
  TearStats last_tear() const;
  /// False when a position or velocity is NaN or infinite (waits for the backend).
  bool state_is_finite() const;

  /// The current mesh: positions, faces, per-corner UVs and normals, and the identity arrays
  /// (velocities, origins, the border edges made by cuts).
  Mesh mesh() const;
  /// The same mesh, its copy to the host queued behind the work queued so far; returns without
  /// waiting for it, and the cloth may be cut and stepped meanwhile: `PendingMesh::take` waits for
  /// the copy (on CUDA the frame is copied within the device, then to the host on a stream of its
  /// own, beside the cloth's later work). `corner_normals` false leaves `corner_normal` empty, for a
  /// writer that computes them again.
  PendingMesh mesh_later(bool corner_normals = true) const;
  /// The number of connected pieces of the cloth now (their ids, `Mesh::face_piece`, are 0 .. count - 1;
  /// docs/identity.md, *Pieces*).
  index_t piece_count() const;
  /// Whether the cloth carries per-corner normals (the mesh it was made from had them).
  bool has_corner_normals() const;
  std::vector<index_t> face_nodes() const;  ///< [face_count * 3]
  Topology topology() const;
  std::vector<float> node_pos() const;   ///< [node_count * 3] metres
  std::vector<float> node_rest() const;  ///< [node_count * 3] metres
  std::vector<float> node_vel() const;   ///< [node_count * 3] m/s
  std::vector<std::uint8_t> node_pinned() const;  ///< [node_count] 0 free, p + 1 held by pin p
  /// Replaces the positions and velocities, both [node_count * 3] (a usage `Error` otherwise), from
  /// the host; rest positions stay.
  void set_node_state(const std::vector<float>& node_pos, const std::vector<float>& node_vel);
  /// The positions where the backend keeps them, [node_count * 3] floats (x, y, z per node): GPU
  /// memory of the cloth's GPU on Device::cuda, host memory on Device::cpu; the work queued so far
  /// is waited for first. For reading without a copy (the Python module hands it out through
  /// DLPack); valid until the cloth next changes (a cut, a step, `load_state`, `set_node_state`,
  /// `copy_node_pos_from`) or ends.
  const float* node_pos_data() const;
  /// Replaces the positions with the [node_count * 3] floats at `data`; velocities and rest
  /// positions stay. On Device::cuda `data` may be GPU memory of the cloth's GPU or host memory,
  /// on Device::cpu host memory. Returns once copied (a runtime `Error` where the GPU cannot read
  /// `data`).
  void copy_node_pos_from(const float* data);
  /// Everything the cloth holds that a later run needs to go on bit-exactly (model, state, carried
  /// attributes), as bytes: `load_state` on a cloth made from the same mesh and simulated with the
  /// same options gives back the same cloth, on the same backend the same frames after it.
  std::string save_state() const;
  /// Replaces the cloth with a state `save_state` made; the simulation options (`simulate`) stay.
  /// Throws an input `Error` naming `source` when the bytes are not a consistent cloth.
  void load_state(const std::string& state, const std::string& source);
  /// Provenance of the last cut that split something (empty before the first).
  CutProvenance provenance() const;

  class Engine;  ///< the per-backend implementation

 private:
  std::unique_ptr<Engine> engine_;
};

}  // namespace tear
