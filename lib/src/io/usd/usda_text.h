// tear: the USDA text of a cloth mesh's time samples, for the USD layer writer (usd_layer.cpp).
#pragma once

#include <charconv>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "tear/mesh.h"
#include "tear/usd_layer.h"

namespace tear::usda {

/// Text built with `std::to_chars`: no locale, and for a float the shortest digits that read back
/// to the same float, so the same values always give the same bytes. Numbers are written straight
/// into the buffer (a layer is mostly numbers: 700,000 per frame of the paper's high-resolution
/// scene).
class Text {
 public:
  std::string& str() {
    text_.resize(size_);
    return text_;
  }
  const char* data() const { return text_.data(); }
  std::size_t size() const { return size_; }
  void clear() { size_ = 0; }
  template <std::size_t n>
  Text& operator<<(const char (&literal)[n]) {
    append(literal, n - 1);
    return *this;
  }
  Text& operator<<(const std::string& s) {
    append(s.data(), s.size());
    return *this;
  }
  Text& operator<<(char c) {
    *room(1) = c;
    ++size_;
    return *this;
  }
  Text& operator<<(float value) { return number(value); }
  Text& operator<<(double value) { return number(value); }
  Text& operator<<(int value) { return number(value); }

  /// `(x, y, z)` or `(s, t)`: `width` floats in parentheses.
  void tuple(const float* values, int width) {
    char* out = room(2 + static_cast<std::size_t>(width) * (max_digits + 2));
    char* const start = out;
    *out++ = '(';
    for (int k = 0; k < width; ++k) {
      if (k) *out++ = ',', *out++ = ' ';
      out = std::to_chars(out, out + max_digits, values[k]).ptr;
    }
    *out++ = ')';
    size_ += static_cast<std::size_t>(out - start);
  }

  /// Appends a copy of `[begin, begin + count)` of this text.
  void repeat(std::size_t begin, std::size_t count) {
    char* out = room(count);
    std::memcpy(out, text_.data() + begin, count);
    size_ += count;
  }

  void append(const char* s, std::size_t count) {
    std::memcpy(room(count), s, count);
    size_ += count;
  }

 private:
  static constexpr std::size_t max_digits = 24;  // a float's shortest text is at most 15 chars, a double's 24

  /// Room for `count` more chars at the end; returns where they go.
  char* room(std::size_t count) {
    if (size_ + count > text_.size()) text_.resize(std::max(2 * text_.size(), size_ + count + 4096));
    return text_.data() + size_;
  }
  template <typename T>
  Text& number(T value) {
    char* out = room(max_digits);
    size_ += static_cast<std::size_t>(std::to_chars(out, out + max_digits, value).ptr - out);
    return *this;
  }

  std::string text_;  // [0, size_) is the text; the rest is room
  std::size_t size_ = 0;
};

/// The attributes of the mesh, in the order the layer holds them.
enum class Attribute {
  face_vertex_counts,
  face_vertex_indices,
  points,
  velocities,
  accelerations,
  extent,
  normals,
  normal_indices,
  st,
  st_indices,
  tear_edge,
  piece,
  rest,
  id,
  count
};
inline constexpr int attribute_count = static_cast<int>(Attribute::count);

/// An attribute's USD type and name, the tag of its temporary file, its primvar interpolation (null
/// for an attribute that is not a primvar, or for a primvar's indices), whether it is written at
/// every time code (what moves: points, velocities, accelerations, extent, normals) or only at the
/// time codes where it changes (topology, indices, UVs, tear edges, pieces, rest positions, ids),
/// and whether USD interpolates between its samples (floating-point values: a value held over
/// frames is then written again at the frame before it changes, so the frames between keep it).
struct Declaration {
  const char* type_and_name;
  const char* file_tag;  // in the temporary file's name
  const char* interpolation;
  bool every_frame;
  bool interpolated;
};

inline constexpr Declaration declarations[attribute_count] = {
    {"int[] faceVertexCounts", "faceVertexCounts", nullptr, false, false},
    {"int[] faceVertexIndices", "faceVertexIndices", nullptr, false, false},
    {"point3f[] points", "points", nullptr, true, true},
    {"vector3f[] velocities", "velocities", nullptr, true, true},
    {"vector3f[] accelerations", "accelerations", nullptr, true, true},
    {"float3[] extent", "extent", nullptr, true, true},
    {"normal3f[] primvars:normals", "normals", "faceVarying", true, true},
    {"int[] primvars:normals:indices", "normals_indices", nullptr, false, false},
    {"texCoord2f[] primvars:st", "st", "faceVarying", false, true},
    {"int[] primvars:st:indices", "st_indices", nullptr, false, false},
    {"int[] primvars:tear_edge", "tear_edge", "faceVarying", false, false},
    {"int[] primvars:piece", "piece", "uniform", false, false},
    {"point3f[] primvars:rest", "rest", "vertex", false, true},
    {"int[] primvars:id", "id", "vertex", false, false},
};

inline const Declaration& declaration(Attribute a) { return declarations[static_cast<int>(a)]; }

/// Which attributes a layer holds: normals, UVs, pieces and rest positions only when the mesh has them.
struct AttributeSet {
  bool normals = false, st = false, piece = false, rest = false;
  bool has(Attribute a) const {
    switch (a) {
      case Attribute::normals:
      case Attribute::normal_indices:
        return normals;
      case Attribute::st:
      case Attribute::st_indices:
        return st;
      case Attribute::piece:
        return piece;
      case Attribute::rest:
        return rest;
      default:
        return true;
    }
  }
  bool operator==(const AttributeSet& o) const {
    return normals == o.normals && st == o.st && piece == o.piece && rest == o.rest;
  }
  static AttributeSet of(const Mesh& mesh) {
    return {mesh.has_normals(), mesh.has_uv(), mesh.has_pieces(), mesh.has_rest()};
  }
};

/// Per-corner values as an indexed primvar: the distinct values of each node's corners, in the
/// order of the corners that first use them, and each corner's value index. The corners of a node
/// mostly share a value (a node's UV away from seams, its normal away from hard edges), so the
/// values are about one per node, and the indices change only when the topology (or a seam) does.
struct IndexedCorners {
  std::vector<index_t> value_corner;  ///< [value_count] the corner each value is read from
  std::vector<int> corner_value;      ///< [corner_count] the value index of each corner
};
IndexedCorners index_corners(const Mesh& mesh, const std::vector<float>& corner_values, int width);

/// What one frame's samples are made from: the mesh, its indexed normals and UVs, and the
/// velocities of the frame before (for accelerations; none: 0).
struct FrameSamples {
  const Mesh& mesh;
  IndexedCorners normals, st;
  const std::vector<float>* previous_vel = nullptr;  ///< the frame before's node_vel, or null
  double per_second = 0;                             ///< 1 / the time from the frame before, s
  FrameSamples(const Mesh& m, const std::vector<float>* previous, double rate);
};

/// Refuses a mesh whose arrays do not match, so that no sample reads out of range.
void check_arrays(const Mesh& mesh, const std::string& path);

/// Appends the value of attribute `a` of a frame: `[...]`.
void put_value(Text& text, Attribute a, const FrameSamples& frame);

/// Appends the time sample `frame` of a value: `        <frame>: <value>,\n`.
void put_sample_line(Text& text, int frame, const char* value, std::size_t size);

/// The layer's opening: metadata, and the mesh's uniform attributes.
std::string layer_head(int first_frame, int last_frame, const UsdLayerOptions& options);

/// What comes before attribute `a`'s samples, and after them.
std::string attribute_open(Attribute a);
inline const char* const attribute_close = "    }\n";
inline const char* const layer_tail = "}\n";

}  // namespace tear::usda
