// Generated cloth meshes: the square sheet of the paper's Table 1 and an exporter-style tube.
#include "tear/make_sheet.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "tear/error.h"

namespace tear {
namespace {

Error usage_error(const std::string& what) { return Error(ErrorKind::usage, what); }

// The standard distributions (uniform_real_distribution and friends) are implementation-defined,
// so the same seed gives different meshes with libstdc++ and libc++. mt19937_64's raw output is
// fixed by the standard; the mappings below are ours.
class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}

  /// Uniform in [0, 1), 53 random bits.
  double unit() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }

  /// Uniform in [-1, 1), 53 random bits.
  double symmetric() { return 2.0 * unit() - 1.0; }

  /// Uniform in [0, bound), bound > 0, unbiased (rejects the incomplete top range).
  std::uint64_t below(std::uint64_t bound) {
    const std::uint64_t threshold = (0 - bound) % bound;
    for (;;) {
      const std::uint64_t x = engine_();
      if (x >= threshold) return x % bound;
    }
  }

  bool coin() { return (engine_() >> 63) != 0; }

 private:
  std::mt19937_64 engine_;
};

// Jitter radius in cells. A quarter cell keeps every triangle above sheet_min_angle_deg (the worst
// case is a diagonal triangle with its three nodes pushed towards a line, 14.2 degrees) and the
// quads convex, so either diagonal and the centre node are valid.
constexpr double jitter_cells = 0.25;

// Appends face (a, b, c) of the sheet with its per-corner UVs and normals.
struct SheetWriter {
  Mesh& mesh;
  double size;
  std::size_t face = 0;

  void add(index_t a, index_t b, index_t c) {
    const index_t nodes[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
      const std::size_t corner = 3 * face + k;
      const std::size_t node = static_cast<std::size_t>(nodes[k]);
      mesh.face_nodes[corner] = nodes[k];
      mesh.corner_uv[2 * corner + 0] = static_cast<float>(mesh.node_pos[3 * node + 0] / size);
      mesh.corner_uv[2 * corner + 1] = static_cast<float>(mesh.node_pos[3 * node + 1] / size);
      mesh.corner_normal[3 * corner + 0] = 0.0f;
      mesh.corner_normal[3 * corner + 1] = 0.0f;
      mesh.corner_normal[3 * corner + 2] = 1.0f;
    }
    ++face;
  }
};

/// The (n + 1)² grid nodes of a sheet of n × n cells of side `cell`, jittered (drawing from
/// `random` in node order) when `irregular`. Border coordinates are exactly 0 or `far`, so the
/// outline is the square.
void place_grid_nodes(Mesh& mesh, std::int64_t n, double cell, float far, bool irregular, Random& random) {
  const std::int64_t side = n + 1;
  for (std::int64_t j = 0; j <= n; ++j) {
    for (std::int64_t i = 0; i <= n; ++i) {
      const bool border_x = i == 0 || i == n;
      const bool border_y = j == 0 || j == n;
      double dx = 0.0;
      double dy = 0.0;
      if (irregular) {
        if (!border_x && !border_y) {
          // Uniform in the unit disc by rejection: no trigonometry, so bit-identical everywhere.
          do {
            dx = random.symmetric();
            dy = random.symmetric();
          } while (dx * dx + dy * dy > 1.0);
        } else if (!border_x) {
          dx = random.symmetric();
        } else if (!border_y) {
          dy = random.symmetric();
        }
      }
      float x = static_cast<float>(cell * (static_cast<double>(i) + jitter_cells * dx));
      float y = static_cast<float>(cell * (static_cast<double>(j) + jitter_cells * dy));
      if (i == 0) x = 0.0f;
      if (i == n) x = far;
      if (j == 0) y = 0.0f;
      if (j == n) y = far;
      const std::size_t node = static_cast<std::size_t>(j * side + i);
      mesh.node_pos[3 * node + 0] = x;
      mesh.node_pos[3 * node + 1] = y;
      mesh.node_pos[3 * node + 2] = 0.0f;
    }
  }

}

/// Which of `quad_count` quads get a centre node (`centre_count` of them): uniformly at random
/// (Floyd's sampling) when `irregular`, else evenly spaced.
std::vector<std::uint8_t> pick_centre_quads(std::int64_t quad_count, std::int64_t centre_count, bool irregular,
                                            Random& random) {
  std::vector<std::uint8_t> quad_centre(static_cast<std::size_t>(quad_count), 0);
  if (irregular) {
    // Floyd's sampling: k distinct quads, uniformly, in O(k) draws.
    for (std::int64_t j = quad_count - centre_count; j < quad_count; ++j) {
      const std::int64_t t = static_cast<std::int64_t>(random.below(static_cast<std::uint64_t>(j + 1)));
      quad_centre[static_cast<std::size_t>(quad_centre[static_cast<std::size_t>(t)] ? j : t)] = 1;
    }
  } else {
    // Evenly spaced; quad_count / centre_count >= 1, so the picks are distinct.
    for (std::int64_t t = 0; t < centre_count; ++t) {
      quad_centre[static_cast<std::size_t>((2 * t + 1) * quad_count / (2 * centre_count))] = 1;
    }
  }

  return quad_centre;
}

}  // namespace

Mesh make_sheet(const SheetOptions& options) {
  const std::int64_t face_count = options.face_count;
  const double size = options.size;
  if (!(std::isfinite(size) && size > 0.0)) {
    throw usage_error("make_sheet: size " + std::to_string(size) + " must be positive and finite");
  }
  if (face_count < 2 || face_count % 2 != 0 || face_count == 6) {
    // A quad gives 2 or 4 triangles; 3 would need a node on an edge shared with the neighbour (a
    // T-junction). One quad cannot give 6.
    throw usage_error("make_sheet: face_count " + std::to_string(face_count) +
                      " cannot be tiled; it must be even, at least 2, and not 6");
  }

  // n x n quads, k of them with a centre node: 2 (n^2 - k) + 4 k = face_count. k <= 2n < n^2 for
  // n >= 3, and k <= n^2 for n = 1, 2 except face_count = 6.
  const std::int64_t half = face_count / 2;
  std::int64_t n = static_cast<std::int64_t>(std::sqrt(static_cast<double>(half)));
  while (n * n > half) --n;
  while ((n + 1) * (n + 1) <= half) ++n;
  const std::int64_t quad_count = n * n;
  const std::int64_t centre_count = half - quad_count;
  const std::int64_t side = n + 1;  // grid nodes per row
  const std::int64_t grid_node_count = side * side;

  Random random(options.seed);
  const double cell = size / static_cast<double>(n);
  const float far = static_cast<float>(size);

  Mesh mesh;
  mesh.node_pos.resize(static_cast<std::size_t>(3 * (grid_node_count + centre_count)));
  place_grid_nodes(mesh, n, cell, far, options.irregular, random);
  const std::vector<std::uint8_t> quad_centre = pick_centre_quads(quad_count, centre_count, options.irregular, random);

  mesh.face_nodes.resize(static_cast<std::size_t>(3 * face_count));
  mesh.corner_uv.resize(static_cast<std::size_t>(6 * face_count));
  mesh.corner_normal.resize(static_cast<std::size_t>(9 * face_count));
  SheetWriter writer{mesh, size};
  std::int64_t next_centre = grid_node_count;
  for (std::int64_t j = 0; j < n; ++j) {
    for (std::int64_t i = 0; i < n; ++i) {
      const std::int64_t quad = j * n + i;
      // Counter-clockwise: a (i, j), b (i+1, j), c (i+1, j+1), d (i, j+1).
      const index_t a = static_cast<index_t>(j * side + i);
      const index_t b = a + 1;
      const index_t d = static_cast<index_t>(a + side);
      const index_t c = d + 1;
      if (quad_centre[static_cast<std::size_t>(quad)]) {
        const index_t m = static_cast<index_t>(next_centre++);
        for (int axis = 0; axis < 2; ++axis) {
          double sum = 0.0;
          for (index_t corner : {a, b, c, d}) sum += mesh.node_pos[3 * static_cast<std::size_t>(corner) + axis];
          mesh.node_pos[3 * static_cast<std::size_t>(m) + axis] = static_cast<float>(0.25 * sum);
        }
        mesh.node_pos[3 * static_cast<std::size_t>(m) + 2] = 0.0f;
        writer.add(a, b, m);
        writer.add(b, c, m);
        writer.add(c, d, m);
        writer.add(d, a, m);
      } else {
        const bool diagonal_ac = options.irregular ? random.coin() : (i + j) % 2 == 0;
        if (diagonal_ac) {
          writer.add(a, b, c);
          writer.add(a, c, d);
        } else {
          writer.add(a, b, d);
          writer.add(b, c, d);
        }
      }
    }
  }
  return mesh;
}

Mesh make_tube(const TubeOptions& options) {
  const double radius = options.radius;
  const double length = options.length;
  const std::int64_t segments = options.segments;
  const std::int64_t rings = options.rings;
  if (!(std::isfinite(radius) && radius > 0.0)) {
    throw usage_error("make_tube: radius " + std::to_string(radius) + " must be positive and finite");
  }
  if (!(std::isfinite(length) && length > 0.0)) {
    throw usage_error("make_tube: length " + std::to_string(length) + " must be positive and finite");
  }
  if (segments < 3) throw usage_error("make_tube: segments " + std::to_string(segments) + " must be at least 3");
  if (rings < 1) throw usage_error("make_tube: rings " + std::to_string(rings) + " must be at least 1");

  const std::int64_t columns = options.welded ? segments : segments + 1;
  const double two_pi = 6.283185307179586476925286766559;
  std::vector<float> column_sin(static_cast<std::size_t>(segments));
  std::vector<float> column_cos(static_cast<std::size_t>(segments));
  for (std::int64_t s = 0; s < segments; ++s) {
    const double angle = two_pi * static_cast<double>(s) / static_cast<double>(segments);
    column_sin[static_cast<std::size_t>(s)] = static_cast<float>(std::sin(angle));
    column_cos[static_cast<std::size_t>(s)] = static_cast<float>(std::cos(angle));
  }

  Mesh mesh;
  mesh.node_pos.resize(static_cast<std::size_t>(3 * columns * (rings + 1)));
  for (std::int64_t r = 0; r <= rings; ++r) {
    const float y = static_cast<float>(length * static_cast<double>(r) / static_cast<double>(rings));
    for (std::int64_t s = 0; s < columns; ++s) {
      // The split seam column repeats column 0 from the same floats, so an exact weld joins them.
      const std::size_t around = static_cast<std::size_t>(s % segments);
      const std::size_t node = static_cast<std::size_t>(r * columns + s);
      mesh.node_pos[3 * node + 0] = static_cast<float>(radius * column_sin[around]);
      mesh.node_pos[3 * node + 1] = y;
      mesh.node_pos[3 * node + 2] = static_cast<float>(radius * column_cos[around]);
    }
  }

  const std::int64_t face_count = 2 * segments * rings;
  mesh.face_nodes.resize(static_cast<std::size_t>(3 * face_count));
  mesh.corner_uv.resize(static_cast<std::size_t>(6 * face_count));
  mesh.corner_normal.resize(static_cast<std::size_t>(9 * face_count));
  std::size_t face = 0;
  // Corner (s, r) with s in [0, segments]: s = segments is the seam, u = 1.
  auto add = [&](const std::int64_t(&corners)[3][2]) {
    for (int k = 0; k < 3; ++k) {
      const std::int64_t s = corners[k][0];
      const std::int64_t r = corners[k][1];
      const std::size_t corner = 3 * face + static_cast<std::size_t>(k);
      const std::size_t around = static_cast<std::size_t>(s % segments);
      mesh.face_nodes[corner] = static_cast<index_t>(r * columns + (options.welded ? s % segments : s));
      mesh.corner_uv[2 * corner + 0] = static_cast<float>(static_cast<double>(s) / static_cast<double>(segments));
      mesh.corner_uv[2 * corner + 1] = static_cast<float>(static_cast<double>(r) / static_cast<double>(rings));
      mesh.corner_normal[3 * corner + 0] = column_sin[around];
      mesh.corner_normal[3 * corner + 1] = 0.0f;
      mesh.corner_normal[3 * corner + 2] = column_cos[around];
    }
    ++face;
  };
  for (std::int64_t r = 0; r < rings; ++r) {
    for (std::int64_t s = 0; s < segments; ++s) {
      // Around is +angle (x grows at angle 0), along is +y: (around x along) points outwards.
      add({{s, r}, {s + 1, r}, {s + 1, r + 1}});
      add({{s, r}, {s + 1, r + 1}, {s, r + 1}});
    }
  }
  return mesh;
}

}  // namespace tear
