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
  extent,
  normals,
  st,
  tear_edge,
  count
};
inline constexpr int attribute_count = static_cast<int>(Attribute::count);

/// An attribute's USD type and name, the tag of its temporary file, and whether it is faceVarying.
struct Declaration {
  const char* type_and_name;
  const char* file_tag;  // in the temporary file's name
  bool face_varying;
};

inline constexpr Declaration declarations[attribute_count] = {
    {"int[] faceVertexCounts", "faceVertexCounts", false},
    {"int[] faceVertexIndices", "faceVertexIndices", false},
    {"point3f[] points", "points", false},
    {"vector3f[] velocities", "velocities", false},
    {"float3[] extent", "extent", false},
    {"normal3f[] normals", "normals", true},
    {"texCoord2f[] primvars:st", "st", true},
    {"int[] primvars:tear_edge", "tear_edge", true},
};

inline const Declaration& declaration(Attribute a) { return declarations[static_cast<int>(a)]; }

/// Which attributes a layer holds: normals and UVs only when the mesh has them.
struct AttributeSet {
  bool normals = false, st = false;
  bool has(Attribute a) const { return a == Attribute::normals ? normals : a == Attribute::st ? st : true; }
  static AttributeSet of(const Mesh& mesh) { return {mesh.has_normals(), mesh.has_uv()}; }
};

/// Refuses a mesh whose arrays do not match, so that no sample reads out of range.
void check_arrays(const Mesh& mesh, const std::string& path);

/// Appends the time sample `frame` of attribute `a` of `mesh`: `        <frame>: <value>,\n`.
void put_sample(Text& text, Attribute a, int frame, const Mesh& mesh);

/// The layer's opening: metadata, and the mesh's uniform attributes.
std::string layer_head(int first_frame, int last_frame, const UsdLayerOptions& options);

/// What comes before attribute `a`'s samples, and after them.
std::string attribute_open(Attribute a);
inline const char* const attribute_close = "    }\n";
inline const char* const layer_tail = "}\n";

}  // namespace tear::usda
