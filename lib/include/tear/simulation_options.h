// tear: the parameters of a cloth simulation, as a cut script's `simulation` block gives them
// (docs/simulation.md is their reference). Parsed with the script (`tear::read_cut_script`).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "tear/mesh.h"

namespace tear {

/// A translation (and, for a mesh collider, a rotation) at one frame of a keyed motion
/// (`Pin::keys`, `Collider::keys`).
struct Key {
  /// The frame whose end the offset is reached at: frames count as the script's do, from 1; 0 is
  /// the start, before frame 1 is stepped.
  int frame = 0;
  std::array<double, 3> offset{};  ///< metres
  /// A mesh collider's turn about its pivot: a unit axis and an angle in degrees (`rotation`);
  /// none given: no turn at this key.
  std::array<double, 3> axis{0, 1, 0};
  double degrees = 0;
};

/// The offset of `keys` (frames strictly increasing) at `time`, in frames since the start (the end
/// of frame f is time f): linear between keys, the first key's before it, the last's after it;
/// zero without keys. Example: keys {1, [0,0,0]}, {3, [2,0,0]} give [1,0,0] at time 2, [0,0,0] at
/// time 0 and [2,0,0] at time 7.
inline std::array<double, 3> key_offset(const std::vector<Key>& keys, double time) {
  if (keys.empty()) return {0, 0, 0};
  if (!(time > keys.front().frame)) return keys.front().offset;
  if (!(time < keys.back().frame)) return keys.back().offset;
  std::size_t k = 1;
  while (keys[k].frame <= time) ++k;  // keys[k - 1].frame <= time < keys[k].frame
  const Key& a = keys[k - 1];
  const Key& b = keys[k];
  const double w = (time - a.frame) / static_cast<double>(b.frame - a.frame);
  std::array<double, 3> offset{};
  for (int i = 0; i < 3; ++i) offset[i] = a.offset[i] + w * (b.offset[i] - a.offset[i]);
  return offset;
}

/// The time substep `s` (0-based) of `substeps` in frame `frame` (1-based) ends at, in frames since
/// the start: frame − 1 + (s + 1) / substeps; the last substep of frame f ends at exactly f.
inline double substep_end_time(int frame, int s, int substeps) {
  return (frame - 1) + static_cast<double>(s + 1) / substeps;
}

/// Nodes held by a pin: either every node whose rest position lies in a box, or listed nodes. A pin
/// without keys holds its nodes where they are; a pin with keys holds them at their rest position
/// plus the keys' offset (docs/simulation.md).
struct Pin {
  enum class Kind { box, nodes };
  Kind kind = Kind::box;
  std::array<double, 3> min{};  ///< box corner, rest coordinates, metres (kind box)
  std::array<double, 3> max{};  ///< box corner, rest coordinates, metres, max >= min (kind box)
  std::vector<index_t> nodes;   ///< node indices of the mesh the solver is built from (kind nodes)
  std::string key_path;         ///< where the pin is in the script, e.g. "simulation.pins[1]"
  std::vector<Key> keys;        ///< the motion of the pinned nodes; empty: they stay where they are
};

/// The triangles of a mesh collider and its vertices' positions, as read from its file (or, for a
/// sequence, one file per frame, all of one topology).
struct ColliderMesh {
  std::string file;                 ///< the file (or the sequence's pattern) as the script names it
  std::vector<index_t> face_nodes;  ///< [3 * faces], counter-clockwise seen from outside
  /// Positions of the vertices, [3 * vertices] metres, one array per frame of a sequence: frames[i]
  /// is the body at the end of frame `first_frame + i` (time first_frame + i); one array for a
  /// rigid mesh.
  std::vector<std::vector<float>> frames;
  int first_frame = 0;

  index_t vertex_count() const { return frames.empty() ? 0 : static_cast<index_t>(frames[0].size() / 3); }
  index_t face_count() const { return static_cast<index_t>(face_nodes.size() / 3); }
};

/// An obstacle the cloth is kept out of; static, or moved by its keys. Planes and spheres push
/// nodes out after every substep; meshes take part in collision (`CollisionOptions`).
struct Collider {
  enum class Kind { plane, sphere, mesh };
  Kind kind = Kind::plane;
  std::array<double, 3> point{};          ///< a point of the plane, or the sphere's centre, metres
  std::array<double, 3> normal{0, 1, 0};  ///< plane: the free side's normal, unit length (kind plane)
  double radius = 0;                      ///< sphere radius, metres, > 0 (kind sphere)
  std::shared_ptr<const ColliderMesh> mesh;  ///< kind mesh: its triangles and vertices
  std::array<double, 3> pivot{};  ///< kind mesh: the point its keys' rotations turn it about, metres
  std::string key_path;           ///< where the collider is in the script, e.g. "simulation.colliders[0]"
  /// The translation of `point` (of a mesh: of its vertices, after the turn) over time; empty: static.
  std::vector<Key> keys;
};

/// A mesh collider's vertex positions at `time` (frames since the start, as `key_offset`), into
/// `out` [3 * vertices]: the sequence's frames linear between the two around `time` (the first
/// before it, the last after it), turned about the pivot by the keys' rotation (the angle linear
/// between keys of one axis, else the shorter way between their orientations), then moved by the
/// keys' offset.
void collider_positions(const Collider& collider, double time, std::vector<float>& out);

/// Collision of the cloth with itself (its torn pieces included) and with mesh colliders
/// (`simulation.collision`, docs/simulation.md, *Collision*): after the solver's iterations of every
/// substep, node–face and edge–edge pairs closer than `thickness` or crossing over the substep's
/// motion are pushed apart, on the side they started the substep on.
struct CollisionOptions {
  bool self = false;        ///< the cloth against itself
  double thickness = 0.005; ///< metres kept between the cloth and itself or a mesh collider, > 0
  double friction = 0;      ///< Coulomb coefficient of the contacts' tangential motion, >= 0
  int iterations = 8;       ///< passes over the contacts per substep, >= 1
};

/// Chebyshev semi-iteration of the Jacobi global step (Wang 2015).
struct ChebyshevOptions {
  /// Estimated spectral radius of the Jacobi iteration, in (0, 1). Too low wastes the
  /// acceleration, too high overshoots and oscillates; 0.995 measured best on 1 m sheets at the
  /// default stiffness (docs/simulation.md).
  double rho = 0.995;
  double gamma = 0.9;  ///< under-relaxation of each Jacobi update, in (0, 1]
  int delay = 10;      ///< plain (under-relaxed) Jacobi iterations before the acceleration starts, >= 0
};

/// The grain of a woven fabric (`simulation.tearing.weave`): its threads run along the warp
/// direction (in UV space) and across it (the weft).
struct Weave {
  std::array<double, 2> warp{0, 1};  ///< the warp's direction in UV space (normalised when read)
  double weft_strength = 1;          ///< a crack along the weft tears at this times the warp's limit
};

/// A greyscale image in UV space whose value multiplies the tearing limits
/// (`simulation.tearing.strength_map`): white 1, black 0. Read when the script is.
struct StrengthMap {
  std::string file;          ///< the image's path as the script names it, for messages
  int width = 0, height = 0;
  std::vector<float> value;  ///< [height * width] in [0, 1], row 0 the image's top (v = 1)

  /// The value at (u, v), bilinear between texel centres, repeating outside [0, 1] as UVs tile.
  float at(double u, double v) const;
};

/// The cloth tearing by itself where it is stretched too far (`simulation.tearing`): cracks that
/// start where the smoothed stretch passes `start`, run from their tips while the stretch around a
/// tip passes `stretch`, and stop at borders, other cracks or where the stress is gone
/// (docs/simulation.md, *Tearing*).
struct TearingOptions {
  /// The largest principal stretch the fabric bears, measured over a disc of `radius` around a crack
  /// tip in the rest shape; beyond it the tip advances. 0: no tearing; else > 1.
  double stretch = 0;
  /// The smoothed stretch at which a new crack starts; 0: `stretch`.
  double start = 0;
  /// Radius of the disc the stretch is smoothed over, metres (also the distance within which a tip
  /// joins another crack or a border, and no new crack starts near a crack).
  double radius = 0.05;
  /// How far a tip advances per substep, metres (at least one face's width); 0: radius / 2.
  double step = 0;
  /// The smallest piece a crack may cut off, square metres of rest area; < 0 (the default): (2
  /// radius)², or `default_min_piece_share` of the cloth's rest area where that is less.
  double min_piece = -1;
  /// Most crack advances and starts per substep, >= 1.
  int max_faces_per_step = 64;
  /// The most faces tearing may leave the cloth with: a tear past it stops the run with a runtime
  /// `Error` naming `simulation.tearing.max_faces`. 0: the default, `default_tear_face_factor` times
  /// the faces the cloth has when the simulation starts, at least `default_tear_face_floor`.
  std::int64_t max_faces = 0;
  /// Snap tolerance of the tear's cut points: the script's `snap` (as `default_snap` unless given).
  double snap = 0.2;
  bool has_weave = false;
  Weave weave;
  /// Edges where the input's UVs are discontinuous (seams) tear at this times the limit.
  double seam_strength = 1;
  /// Relative amplitude of a seeded noise field (feature size `radius`) on the limits, in [0, 0.9].
  double variation = 0;
  std::uint32_t seed = 0;
  /// A painted strength: the limits times the map's value at the face (null: none).
  std::shared_ptr<const StrengthMap> strength_map;
  /// Strain rate limit, in [0, 1]: no face's altitude may shrink over a substep by more than this
  /// fraction of itself (a tear's recoil spread over substeps instead of turning faces over;
  /// kernels/strain_rate.h). 0: off; not applied while the collision pass runs.
  double strain_rate_limit = 0.1;

  bool enabled() const { return stretch > 0; }
  double start_stretch() const { return start > 0 ? start : stretch; }
  double step_m() const { return step > 0 ? step : radius / 2; }
  /// The smallest piece a crack may cut off from a cloth of `cloth_area` square metres of rest area.
  double min_piece_m2(double cloth_area) const {
    return min_piece >= 0 ? min_piece : std::min(4 * radius * radius, default_min_piece_share * cloth_area);
  }
  /// The default `min_piece` of a small cloth (a ribbon, a label): this share of its rest area.
  static constexpr double default_min_piece_share = 0.02;
  /// `max_faces`, or its default for a cloth of `start_faces` faces when the simulation starts.
  std::int64_t face_budget(std::int64_t start_faces) const;
};

/// How the cloth resists stretch: `springs`, a spring along every edge, or `membrane`, a strain
/// constraint on every face, which responds the same in every direction whatever the faces' shapes
/// (docs/simulation.md, *Stretch models*). `automatic` (the default) is `membrane` for a cloth that
/// tears, whose cracks follow the stretch's direction, and `springs` otherwise.
enum class StretchModel { automatic, springs, membrane };

/// The `simulation` block of a cut script, in physical units. Defaults suit a 1 m cloth.
struct SimulationOptions {
  double fps = 24;       ///< frames per second; one `PdSolver::step` advances 1 / fps seconds
  int substeps = 4;      ///< implicit Euler steps per frame, >= 1
  int iterations = 100;  ///< local/global iterations per substep, >= 1 (fixed: no convergence test)
  std::array<double, 3> gravity{0, -9.81, 0};  ///< m/s²
  /// Fraction of the velocity removed per second, in [0, 1]: each substep of h seconds multiplies
  /// velocities by (1 - damping)^h. 0 adds no damping (implicit Euler still dissipates some).
  double damping = 0.1;
  double density = 0.2;  ///< kg/m² of rest area, > 0
  /// Stiffness against stretch, of the edge springs or the faces' membrane (`stretch_model`), N/m
  /// (energy per rest area per squared strain), >= 0.
  double stretch_stiffness = 1000;
  StretchModel stretch_model = StretchModel::automatic;
  /// Bending rigidity of the edge hinges, N·m (energy per squared dihedral angle, scaled by the
  /// hinge's shape as in discrete shells), >= 0.
  double bend_stiffness = 1e-4;
  ChebyshevOptions chebyshev;
  std::vector<Pin> pins;
  std::vector<Collider> colliders;
  CollisionOptions collision;
  TearingOptions tearing;
  /// The file the options came from, named in errors the solver raises (pins out of range).
  std::string source = "(simulation options)";

  /// The stretch model the solver uses: `stretch_model`, `automatic` resolved.
  StretchModel stretch_model_used() const {
    if (stretch_model != StretchModel::automatic) return stretch_model;
    return tearing.enabled() ? StretchModel::membrane : StretchModel::springs;
  }
  /// Length of one implicit Euler step, seconds.
  double step_seconds() const { return 1.0 / (fps * substeps); }
  /// Whether substeps end in the collision pass: the cloth collides with itself or with a mesh.
  bool collides() const {
    return collision.self || std::any_of(colliders.begin(), colliders.end(),
                                         [](const Collider& c) { return c.kind == Collider::Kind::mesh; });
  }
};

/// Bounds of the `simulation` keys, checked when a script is parsed (an input error naming the key
/// otherwise). Each is far beyond what cloth needs, and together they keep the solver's
/// single-precision state finite: at the extremes (the largest gravity, the longest step, the
/// stiffest and lightest cloth) a 1 m sheet stays finite frame after frame. docs/simulation.md
/// gives the reasons.
namespace simulation_limits {
inline constexpr double min_fps = 0.1;    ///< 1/s: one frame per 10 s
inline constexpr double max_fps = 1e5;    ///< 1/s: a high-speed camera
inline constexpr int max_substeps = 10000;
inline constexpr int max_iterations = 100000;
/// substeps × iterations, the solver iterations of one frame.
inline constexpr long long max_iterations_per_frame = 1000000;
inline constexpr double max_gravity = 1e4;   ///< m/s², the length of `gravity`: about 1000 g
inline constexpr double min_density = 1e-4;  ///< kg/m²: a hundredth of the lightest tissue paper
inline constexpr double max_density = 1e4;   ///< kg/m²: a metre-thick slab of stone
inline constexpr double max_stretch_stiffness = 1e9;  ///< N/m: a centimetre of steel plate
inline constexpr double max_bend_stiffness = 1e3;     ///< N·m: a few millimetres of steel plate
inline constexpr int max_chebyshev_delay = 100000;
/// Metres: the largest coordinate of a collider's point or centre, and its radius.
inline constexpr double max_collider_extent = 1e9;
/// A node's pin is stored in a byte (0 free, p + 1 held by pin p).
inline constexpr int max_pins = 255;
/// `collision.thickness`, metres: beyond it the cloth's pieces stand apart as separate objects.
inline constexpr double max_collision_thickness = 1;
inline constexpr double max_collision_friction = 10;
inline constexpr int max_collision_iterations = 1000;
/// A mesh collider's faces (each file of a sequence), and the files of a sequence.
inline constexpr std::int64_t max_collider_faces = 10000000;
inline constexpr int max_collider_sequence_files = 100001;
/// Metres: the largest coordinate of a key's offset (as of a collider's point).
inline constexpr double max_key_offset = max_collider_extent;
/// The largest frame of a key: the most frames a script has (cut_script.h `max_frames`).
inline constexpr int max_key_frame = 1000000;
/// `tearing.stretch`: a face stretched to 1000 times its rest length has long torn.
inline constexpr double max_tear_stretch = 1000;
/// `tearing.max_faces_per_step`: a cap far above any mesh's faces per substep would be none.
inline constexpr int max_tear_faces_per_step = 100000000;
/// `tearing.max_faces`: the most faces a cloth can have (its face corners are 32-bit indices).
inline constexpr std::int64_t max_tear_faces = 715827882;
/// The default of `tearing.max_faces`: this many times the faces the simulation starts with (a
/// sheet torn to shreds everywhere has about twice its faces), and at least the floor (a small
/// cloth's tears add faces along their paths that a multiple of few faces would not hold).
inline constexpr std::int64_t default_tear_face_factor = 8;
inline constexpr std::int64_t default_tear_face_floor = 100000;
}  // namespace simulation_limits

inline std::int64_t TearingOptions::face_budget(std::int64_t start_faces) const {
  if (max_faces > 0) return max_faces;
  const std::int64_t scaled = simulation_limits::default_tear_face_factor * start_faces;
  return std::min(simulation_limits::max_tear_faces, std::max(simulation_limits::default_tear_face_floor, scaled));
}

}  // namespace tear
