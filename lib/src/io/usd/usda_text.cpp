// The USDA text of a mesh's attributes, sample by sample, and of a layer's opening.
#include "io/usd/usda_text.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "tear/error.h"

#ifndef TEAR_VERSION
#define TEAR_VERSION "unknown"
#endif

namespace tear::usda {
namespace {

/// 1 for each corner whose edge to the next corner of its face is a torn edge, else 0.
std::vector<char> corner_tear_edge(const Mesh& mesh) {
  std::vector<std::uint64_t> torn;
  torn.reserve(mesh.torn_edge_nodes.size() / 2);
  auto key = [](index_t a, index_t b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
  };
  for (std::size_t e = 0; e + 1 < mesh.torn_edge_nodes.size(); e += 2)
    torn.push_back(key(mesh.torn_edge_nodes[e], mesh.torn_edge_nodes[e + 1]));
  std::sort(torn.begin(), torn.end());
  std::vector<char> marks(mesh.face_nodes.size(), 0);
  if (torn.empty()) return marks;
  for (std::size_t c = 0; c < mesh.face_nodes.size(); ++c) {
    const std::size_t next = c % 3 == 2 ? c - 2 : c + 1;
    marks[c] = std::binary_search(torn.begin(), torn.end(), key(mesh.face_nodes[c], mesh.face_nodes[next]));
  }
  return marks;
}

}  // namespace

/// Refuses a mesh whose arrays do not match, so that no sample reads out of range.
void check_arrays(const Mesh& mesh, const std::string& path) {
  auto fail = [&](const std::string& what) { return runtime_error(path + ": cannot write: " + what); };
  const std::size_t corner_count = mesh.face_nodes.size();
  if (mesh.node_pos.size() % 3 != 0) throw fail("node_pos size is not a multiple of 3");
  if (corner_count % 3 != 0) throw fail("face_nodes size is not a multiple of 3");
  if (mesh.has_uv() && mesh.corner_uv.size() != 2 * corner_count) throw fail("corner_uv has the wrong size");
  if (mesh.has_normals() && mesh.corner_normal.size() != 3 * corner_count)
    throw fail("corner_normal has the wrong size");
  if (mesh.has_velocities() && mesh.node_vel.size() != mesh.node_pos.size()) throw fail("node_vel has the wrong size");
  for (std::size_t c = 0; c < corner_count; ++c)
    if (mesh.face_nodes[c] < 0 || mesh.face_nodes[c] >= mesh.node_count())
      throw fail("face " + std::to_string(c / 3) + " uses node " + std::to_string(mesh.face_nodes[c]) + " of " +
                 std::to_string(mesh.node_count()));
}

IndexedCorners index_corners(const Mesh& mesh, const std::vector<float>& corner_values, int width) {
  IndexedCorners out;
  const std::size_t corners = mesh.face_nodes.size(), bytes = static_cast<std::size_t>(width) * sizeof(float);
  out.corner_value.resize(corners);
  // Each node's values as a chain: node_first[n] the first value of node n, value_next[v] the next.
  std::vector<int> node_first(static_cast<std::size_t>(mesh.node_count()), -1), value_next;
  for (std::size_t c = 0; c < corners; ++c) {
    const float* value = &corner_values[width * c];
    int* link = &node_first[static_cast<std::size_t>(mesh.face_nodes[c])];
    while (*link >= 0 &&
           std::memcmp(&corner_values[width * static_cast<std::size_t>(out.value_corner[*link])], value, bytes) != 0)
      link = &value_next[static_cast<std::size_t>(*link)];
    if (*link < 0) {
      *link = static_cast<int>(out.value_corner.size());
      out.value_corner.push_back(static_cast<index_t>(c));
      value_next.push_back(-1);
    }
    out.corner_value[c] = *link;
  }
  return out;
}

FrameSamples::FrameSamples(const Mesh& m, const std::vector<float>* previous, double rate)
    : mesh(m), previous_vel(previous), per_second(rate) {
  if (m.has_normals()) normals = index_corners(m, m.corner_normal, 3);
  if (m.has_uv()) st = index_corners(m, m.corner_uv, 2);
}

namespace {
void put_indexed_values(Text& text, const std::vector<float>& corner_values, const IndexedCorners& indexed,
                        int width) {
  for (std::size_t v = 0; v < indexed.value_corner.size(); ++v) {
    if (v) text << ", ";
    text.tuple(&corner_values[width * static_cast<std::size_t>(indexed.value_corner[v])], width);
  }
}
void put_ints(Text& text, const std::vector<int>& values) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i) text << ", ";
    text << values[i];
  }
}
}  // namespace

void put_sample_line(Text& text, int frame, const char* value, std::size_t size) {
  text << "        " << frame << ": ";
  text.append(value, size);
  text << ",\n";
}

namespace {

/// The accelerations of a frame: (v - v_before) / dt for the nodes the frame before had; 0 for the
/// others, and without velocities or a frame before.
void put_accelerations(Text& text, const FrameSamples& samples) {
  const Mesh& mesh = samples.mesh;
  const std::size_t node_count = static_cast<std::size_t>(mesh.node_count());
  const std::vector<float>* before = samples.previous_vel;
  const std::size_t known = mesh.has_velocities() && before ? std::min(node_count, before->size() / 3) : 0;
  for (std::size_t n = 0; n < node_count; ++n) {
    if (n) text << ", ";
    float value[3] = {0, 0, 0};
    for (int k = 0; n < known && k < 3; ++k)
      value[k] = static_cast<float>((double(mesh.node_vel[3 * n + k]) - (*before)[3 * n + k]) * samples.per_second);
    text.tuple(value, 3);
  }
}

/// The extent of a frame's points: its two corners (nothing for no points).
void put_extent(Text& text, const Mesh& mesh) {
  const std::size_t node_count = static_cast<std::size_t>(mesh.node_count());
  if (node_count == 0) return;
  float lo[3], hi[3];
  for (int k = 0; k < 3; ++k) lo[k] = hi[k] = mesh.node_pos[k];
  for (std::size_t n = 1; n < node_count; ++n)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], mesh.node_pos[3 * n + k]);
      hi[k] = std::max(hi[k], mesh.node_pos[3 * n + k]);
    }
  text.tuple(lo, 3);
  text << ", ";
  text.tuple(hi, 3);
}

/// Per corner, whether the edge from it is torn: 1 or 0.
void put_tear_edge(Text& text, const Mesh& mesh) {
  const std::vector<char> marks = corner_tear_edge(mesh);
  for (std::size_t c = 0; c < mesh.face_nodes.size(); ++c) {
    if (c) text << ", ";
    text << (marks[c] ? '1' : '0');
  }
}

}  // namespace

/// Appends the value of attribute `a` of a frame: `[...]`.
void put_value(Text& text, Attribute a, const FrameSamples& samples) {
  const Mesh& mesh = samples.mesh;
  text << '[';
  const std::size_t node_count = static_cast<std::size_t>(mesh.node_count());
  const std::size_t corner_count = mesh.face_nodes.size();
  switch (a) {
    case Attribute::face_vertex_counts:
      for (std::size_t f = 0; f < corner_count / 3; ++f) {
        if (f) text << ", ";
        text << '3';
      }
      break;
    case Attribute::face_vertex_indices:
      for (std::size_t c = 0; c < corner_count; ++c) {
        if (c) text << ", ";
        text << static_cast<int>(mesh.face_nodes[c]);
      }
      break;
    case Attribute::points:
      for (std::size_t n = 0; n < node_count; ++n) {
        if (n) text << ", ";
        text.tuple(&mesh.node_pos[3 * n], 3);
      }
      break;
    case Attribute::velocities: {
      const float zero[3] = {0, 0, 0};
      for (std::size_t n = 0; n < node_count; ++n) {
        if (n) text << ", ";
        text.tuple(mesh.has_velocities() ? &mesh.node_vel[3 * n] : zero, 3);
      }
      break;
    }
    case Attribute::accelerations:
      put_accelerations(text, samples);
      break;
    case Attribute::extent:
      put_extent(text, mesh);
      break;
    case Attribute::normals:
      put_indexed_values(text, mesh.corner_normal, samples.normals, 3);
      break;
    case Attribute::normal_indices:
      put_ints(text, samples.normals.corner_value);
      break;
    case Attribute::st:
      put_indexed_values(text, mesh.corner_uv, samples.st, 2);
      break;
    case Attribute::st_indices:
      put_ints(text, samples.st.corner_value);
      break;
    case Attribute::tear_edge:
      put_tear_edge(text, mesh);
      break;
    case Attribute::piece:
      for (std::size_t f = 0; f < corner_count / 3; ++f) {
        if (f) text << ", ";
        text << static_cast<int>(mesh.has_pieces() ? mesh.face_piece[f] : 0);
      }
      break;
    case Attribute::rest:
      for (std::size_t n = 0; mesh.has_rest() && n < node_count; ++n) {
        if (n) text << ", ";
        text.tuple(&mesh.node_rest[3 * n], 3);
      }
      break;
    case Attribute::id:
      for (std::size_t n = 0; n < node_count; ++n) {
        if (n) text << ", ";
        text << static_cast<int>(n);
      }
      break;
    case Attribute::count:
      break;
  }
  text << ']';
}

/// The layer's opening: metadata, and the mesh's uniform attributes.
std::string layer_head(int first_frame, int last_frame, const UsdLayerOptions& options) {
  Text text;
  text << "#usda 1.0\n(\n"
       << "    defaultPrim = \"cloth\"\n"
       << "    doc = \"tear " TEAR_VERSION ": a torn cloth, one time sample per frame\"\n"
       << "    endTimeCode = " << last_frame << "\n"
       << "    framesPerSecond = " << options.frames_per_second << "\n"
       << "    metersPerUnit = " << options.meters_per_unit << "\n"
       << "    startTimeCode = " << first_frame << "\n"
       << "    timeCodesPerSecond = " << options.frames_per_second << "\n"
       << "    upAxis = \"" << std::string(to_string(options.up_axis)) << "\"\n"
       << ")\n\n"
       << "def Mesh \"cloth\"\n{\n"
       // Cloth is seen from both sides; the triangles are the surface (no subdivision), which
       // also keeps the authored normals in use.
       << "    uniform bool doubleSided = 1\n"
       << "    uniform token orientation = \"rightHanded\"\n"
       << "    uniform token subdivisionScheme = \"none\"\n";
  return std::move(text.str());
}

/// What comes before attribute `a`'s samples, and after them.
std::string attribute_open(Attribute a) {
  const Declaration& d = declaration(a);
  std::string text = "    ";
  if (d.interpolation)
    text += std::string(d.type_and_name) + " (\n        interpolation = \"" + d.interpolation + "\"\n    )\n    ";
  return text + d.type_and_name + ".timeSamples = {\n";
}

}  // namespace tear::usda
