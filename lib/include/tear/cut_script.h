// tear: the cut script, a versioned JSON file of timed cuts (docs/cut-script.md is its reference).
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "tear/mesh.h"
#include "tear/simulation_options.h"

namespace tear {

/// The space a cut's geometry is given in.
enum class CutSpace {
  uv,       ///< the mesh's UV space (per-corner UVs); the cut follows the fabric whatever the pose
  rest_xy,  ///< the rest shape projected on the xy plane: 2D point (u, v) is (x, y), metres
  rest_xz,  ///< the rest shape projected on the xz plane: 2D point (u, v) is (x, z), metres
  rest_yz,  ///< the rest shape projected on the yz plane: 2D point (u, v) is (y, z), metres
  world,    ///< world space, against the current pose (blades and planes)
};

/// What a cut is.
enum class CutKind {
  polyline,  ///< a 2D polyline in `uv` or a `rest_*` space
  blade,     ///< a world-space 3D polyline swept both ways along a direction, without bound
  plane,     ///< an infinite world-space plane
};

/// The spelling of a space in a script ("uv", "rest-xy", ...; "world" for blades and planes).
const char* to_string(CutSpace space);
/// "polyline", "blade" or "plane".
const char* to_string(CutKind kind);

/// The two rest-position axes (0 = x, 1 = y, 2 = z) that a `rest_*` space keeps, in (u, v) order.
/// Only meaningful for `rest_xy`, `rest_xz` and `rest_yz`.
std::array<int, 2> rest_plane_axes(CutSpace space);

/// Default of `CutScript::snap`. A cut point that snaps leaves no edge piece shorter than this
/// fraction of its edge, which bounds how thin a split triangle can get (docs/cut-script.md).
inline constexpr double default_snap = 0.2;

/// The most frames a script may have: 11.5 hours at 24 fps, one file each. More is taken for a
/// mistake (a run that would not end) and refused when the script is read.
inline constexpr int max_frames = 1000000;
static_assert(simulation_limits::max_key_frame == max_frames, "a key may name any frame of a script");

/// A blade segment counts as parallel to the blade direction when the sine of the angle between
/// them is at most this (zero-length segments count as parallel). Such segments sweep no area.
inline constexpr double blade_parallel_sine = 1e-9;

/// One cut of a script. Which fields are set depends on `kind`; the others are empty or zero.
struct Cut {
  int frame = 1;  ///< frame the cut is applied at, in 1..frames
  CutKind kind = CutKind::polyline;
  CutSpace space = CutSpace::world;              ///< uv / rest_* for polylines, world for blades and planes
  std::vector<std::array<double, 2>> polyline2;  ///< [n >= 2] polyline points (u, v), kind polyline
  std::vector<std::array<double, 3>> polyline3;  ///< [n >= 2] blade points (x, y, z), metres, kind blade
  std::array<double, 3> direction{};             ///< blade sweep direction, non-zero, length ignored
  std::array<double, 3> point{};                 ///< a point of the plane, metres, kind plane
  std::array<double, 3> normal{};                ///< plane normal, non-zero, length ignored
  std::string key_path;                          ///< where the cut is in the script, e.g. "cuts[2]"
};

/// A parsed, validated cut script.
struct CutScript {
  int version = 1;
  int frames = 1;              ///< number of frames of the run, in 1..max_frames
  double snap = default_snap;  ///< snap tolerance, fraction of an edge's length, in [0, 0.5)
  std::vector<Cut> cuts;       ///< in script order
  /// The `simulation` block, parsed and checked (every key within `simulation_limits`); empty when
  /// the script has none (the cloth then does not move).
  std::optional<SimulationOptions> simulation;
  std::string path;            ///< the file name used in messages

  /// The cuts applied at `frame`, in script order; they are applied together. The pointers are
  /// into `cuts` and stay valid while `cuts` is not modified.
  std::vector<const Cut*> cuts_of_frame(int frame) const;
};

/// The largest cut script read or parsed, in bytes (4 MiB; also within --max-input-bytes when read
/// from a file), and the deepest nesting of its arrays and objects: both checked before parsing,
/// which takes memory a few hundred times the text's size.
constexpr std::size_t max_script_bytes = std::size_t(4) << 20;
constexpr std::size_t max_script_depth = 32;

/// Parses and validates a script held in memory, its `simulation` block included.
/// `path_for_messages` names it in errors (and becomes `SimulationOptions::source`).
/// Throws `tear::Error` of kind input, with a one-line message
/// `<path>: <key path>: <what was expected>` or, for JSON syntax, `<path>:<line>:<column>: syntax error: ...`.
CutScript parse_cut_script(const std::string& text, const std::string& path_for_messages);

/// Reads and parses a script file. A file that cannot be read is an input error naming it.
CutScript read_cut_script(const std::string& path);

/// Checks that the script can be applied to a mesh: `uv` cuts need UVs; a `rest_*` cut needs the
/// rest shape to have some extent along both axes of its plane (else the projection is a line).
/// Throws an input error naming the script, the cut's key path and `mesh_path`.
void check_script_against_mesh(const CutScript& script, const Mesh& mesh, const std::string& mesh_path);

}  // namespace tear
