// tear: generated cloth meshes: the paper's square sheet at any exact face count, and a tube.
#pragma once

#include <cstdint>

#include "tear/mesh.h"

namespace tear {

/// Options of `make_sheet`.
struct SheetOptions {
  /// The exact number of faces of the sheet: even, at least 2, and not 6 (see `make_sheet`).
  /// The default is the paper's low resolution (Table 1).
  index_t face_count = 2822;
  /// true: grid nodes jittered, random diagonals, randomly placed centre nodes (seeded);
  /// false: a regular grid with alternating diagonals and evenly spaced centre nodes.
  bool irregular = true;
  /// Seed of the irregular layout; the same options always give the same mesh, bit for bit.
  std::uint64_t seed = 1;
  /// Side of the square, metres.
  double size = 1.0;
};

/// Smallest triangle angle an irregular sheet can have, degrees. The jitter (a disc of a quarter
/// cell) allows 14.2 degrees at worst, reached when a quad's random diagonal is its longer one;
/// the regular sheet's smallest angle is 45 degrees.
inline constexpr double sheet_min_angle_deg = 14.0;

/// A square cloth in the XY plane, [0, size]^2 at z = 0, faces counter-clockwise (normal +z),
/// per-corner UV = (x, y) / size and per-corner normal (0, 0, 1).
///
/// Layout: an n x n grid of quads with n the largest where 2 n^2 <= face_count. Each quad is cut
/// into two triangles by a diagonal, except k = face_count / 2 - n^2 quads that get a centre node
/// and four triangles. Interior grid nodes move by a random offset within a disc of a quarter
/// cell; border nodes slide along their side by up to a quarter cell; corners stay. So the border
/// is exactly the square and the total area exactly size^2.
///
/// Nodes are numbered grid first (row by row from y = 0, x fastest), then the centre nodes in
/// quad order; faces are emitted quad by quad in the same order.
///
/// Odd counts and 6 cannot be tiled this way without a T-junction, so they throw a usage `Error`,
/// as do a non-positive count and a size that is not positive and finite. Linear time and memory.
Mesh make_sheet(const SheetOptions& options = {});

/// Options of `make_tube`.
struct TubeOptions {
  double radius = 0.1;    ///< metres
  double length = 1.0;    ///< metres, along +y from y = 0
  index_t segments = 32;  ///< quads around the tube, at least 3
  index_t rings = 16;     ///< quads along the tube, at least 1
  /// false: the seam is split as exporters write it (the u = 0 and u = 1 columns are distinct
  /// nodes at bit-identical positions), so the mesh must be welded before cutting;
  /// true: one node per position, the faces of the last column wrap to the first.
  bool welded = false;
};

/// An open cylinder around the y axis (no caps), faces counter-clockwise seen from outside.
/// Per-corner UV = (angle / 2 pi, y / length), with u = 1 on the seam side of the last column in
/// both variants (a UV seam), and per-corner smooth (radial) normals.
///
/// Node counts: (segments + 1) (rings + 1) split, segments (rings + 1) welded; 2 segments rings
/// faces. Node (s, r) (s around, r along) is node r (segments + 1) + s, or r segments + s welded.
/// Throws a usage `Error` for fewer than 3 segments, fewer than 1 ring, or a radius or length that
/// is not positive and finite.
Mesh make_tube(const TubeOptions& options = {});

}  // namespace tear
