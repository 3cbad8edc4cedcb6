// OBJ by hand, in parallel over line-aligned pieces of the file. The rules are tinyobjloader's
// (its callback API read tear's OBJ files before, and a file must read the same way every time):
// lines end at "\n", "\r\n" or "\r" and stop at a NUL; `v`, `vt`, `vn`, `f`, `o` and `g` lines
// are read, everything else is ignored; a number that does not parse reads as 0, an index as
// `atoi` reads it. Faces are kept whole and every index is checked.
//
// The pieces are read at once, then joined: count, scan, write. Piece k's `v` lines start at the
// sum of the counts of the pieces before it, which is also what a relative (negative) index
// counts from, and its faces' numbers in messages start at the faces before it.
#include <omp.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <system_error>
#include <vector>

#include "io/mesh/file_mesh.h"
#include "io/mesh/parallel_pieces.h"
#include "tear/error.h"
#include "tear/triangulate_polygon.h"

namespace tear {
namespace {

/// Corner indices as a piece stores them: 0-based and final for positive indices; for relative
/// ones, the index within the piece (the lines read so far in it, plus the negative index) plus
/// `relative`, so that joining adds the lines of the pieces before; `absent` where a corner has no
/// vt/vn, `invalid` where the file wrote 0 or no number (which OBJ does not allow).
constexpr std::int64_t invalid = std::numeric_limits<std::int64_t>::min();
constexpr std::int64_t absent = invalid + 1;
constexpr std::int64_t relative = std::int64_t(1) << 40;

/// An `o` or `g` line: what it names, and how many faces of its piece come before it.
struct NameLine {
  std::size_t face = 0;
  bool object = false;
  std::string object_name;               ///< `o`: the rest of the line, trimmed
  std::vector<std::string> group_names;  ///< `g`: its names
};

/// What one piece of the file holds, in its order.
struct ObjPiece {
  std::vector<float> vertex_pos;  ///< [vertex_count * 3]
  std::vector<float> uv;          ///< [uv_count * 2]
  std::vector<float> normal;      ///< [normal_count * 3]
  std::vector<std::int64_t> corner_v, corner_vt, corner_vn;
  std::vector<std::size_t> face_offset = {0};  ///< [face_count + 1] into the corner arrays
  std::vector<NameLine> name_lines;

  std::vector<std::uint8_t> face_selected;  ///< [face_count], filled when joining
  std::size_t face_triangle_corners = 0;    ///< corners of the triangles its selected faces make
};

bool is_space(char c) { return c == ' ' || c == '\t'; }
bool is_digit(char c) { return static_cast<unsigned>(c - '0') < 10u; }

/// One line's content: [p, stop), where `stop` is the line's end or its first NUL.
struct Line {
  const char* p;
  const char* stop;

  char at(const char* q) const { return q < stop ? *q : '\0'; }
  void skip_spaces(const char*& q) const {
    while (q < stop && is_space(*q)) ++q;
  }
  /// strcspn(q, set) on the line: the first of `set` or the line's end.
  template <typename Pred>
  const char* find(const char* q, Pred stops_at) const {
    while (q < stop && !stops_at(*q)) ++q;
    return q;
  }
};

/// tinyobjloader's number arithmetic (its tryParseDouble), for what the fast path does not read:
/// exponents, numbers without digits, numbers a float cannot hold.
double reference_number(const char* s, const char* end, bool& parsed) {
  parsed = false;
  if (s >= end) return 0.0;
  double mantissa = 0.0;
  int exponent = 0;
  char sign = '+', exp_sign = '+';
  const char* curr = s;
  int read = 0;
  bool leading_dot = false;
  if (*curr == '+' || *curr == '-') {
    sign = *curr;
    ++curr;
    if (curr != end && *curr == '.') leading_dot = true;
  } else if (is_digit(*curr)) {
  } else if (*curr == '.') {
    leading_dot = true;
  } else {
    return 0.0;
  }
  bool more = curr != end;
  if (!leading_dot) {
    while (more && is_digit(*curr)) {
      mantissa = mantissa * 10 + static_cast<int>(*curr - '0');
      ++curr;
      ++read;
      more = curr != end;
    }
    if (read == 0) return 0.0;
  }
  if (more) {
    bool exponent_next = false;
    if (*curr == '.') {
      ++curr;
      read = 1;
      more = curr != end;
      static const double pow_lut[] = {1.0, 0.1, 0.01, 0.001, 0.0001, 0.00001, 0.000001, 0.0000001};
      while (more && is_digit(*curr)) {
        mantissa += static_cast<int>(*curr - '0') * (read < 8 ? pow_lut[read] : std::pow(10.0, -read));
        ++read;
        ++curr;
        more = curr != end;
      }
      exponent_next = more;
    } else {
      exponent_next = *curr == 'e' || *curr == 'E';
    }
    if (exponent_next && (*curr == 'e' || *curr == 'E')) {
      ++curr;
      more = curr != end;
      if (more && (*curr == '+' || *curr == '-')) {
        exp_sign = *curr;
        ++curr;
      } else if (!more || !is_digit(*curr)) {
        return 0.0;  // an empty exponent
      }
      read = 0;
      more = curr != end;
      while (more && is_digit(*curr)) {
        // An exponent past the largest int fails the number, as tinyobjloader's check means to
        // (its check lets 2147483648 and 2147483649 through into a signed overflow).
        const int digit = static_cast<int>(*curr - '0');
        if (exponent > (2147483647 - digit) / 10) return 0.0;
        exponent = exponent * 10 + digit;
        ++curr;
        ++read;
        more = curr != end;
      }
      exponent *= exp_sign == '+' ? 1 : -1;
      if (read == 0) return 0.0;
    }
  }
  parsed = true;
  return (sign == '+' ? 1 : -1) * (exponent ? std::ldexp(mantissa * std::pow(5.0, exponent), exponent) : mantissa);
}

/// One number token [s, end): `[+-]digits[.digits]` through `std::from_chars` (correctly rounded,
/// which tinyobjloader's double arithmetic cast to float also is but in contrived cases of 17 and
/// more digits), anything else through tinyobjloader's arithmetic. `parsed` is false where
/// tinyobjloader would use the default.
float parse_number(const char* s, const char* end, bool& parsed) {
  const char* digits = s + (s < end && (*s == '+' || *s == '-') ? 1 : 0);
  const char* q = digits;
  while (q < end && is_digit(*q)) ++q;
  const bool integer_digits = q > digits;
  bool plain = integer_digits;
  if (q < end && *q == '.') {
    const char* fraction = ++q;
    while (q < end && is_digit(*q)) ++q;
    plain = plain || q > fraction;
  }
  // What follows the number is ignored (tinyobjloader stops at it), unless it is an exponent.
  if (plain && (q == end || (*q != 'e' && *q != 'E'))) {
    float value = 0.0f;
    const char* first = *s == '+' ? s + 1 : s;
    const auto result = std::from_chars(first, q, value, std::chars_format::fixed);
    if (result.ec == std::errc() && result.ptr == q) {
      parsed = true;
      return value;
    }
  }
  return static_cast<float>(reference_number(s, end, parsed));
}

/// tinyobjloader's parseReal: the next token of the line, or `fallback` when it is no number.
float next_real(const Line& line, const char*& q, float fallback, bool* parsed = nullptr) {
  line.skip_spaces(q);
  const char* end = line.find(q, [](char c) { return c == ' ' || c == '\t' || c == '\r'; });
  bool ok = false;
  const float value = parse_number(q, end, ok);
  q = end;
  if (parsed) *parsed = ok;
  return ok ? value : fallback;
}

bool starts_with_word(const char* p, const char* stop, const char* word) {
  for (; *word; ++word, ++p) {
    if (p >= stop || std::tolower(static_cast<unsigned char>(*p)) != *word) return false;
  }
  return true;
}

/// A `v` coordinate that does not parse but spells NaN or infinity keeps that value (tinyobjloader
/// reads it as 0), so that the checks after reading see it.
float next_coordinate(const Line& line, const char*& q) {
  line.skip_spaces(q);
  const char* token = q;
  bool parsed = false;
  const float value = next_real(line, q, 0.0f, &parsed);
  if (parsed) return value;
  const bool negative = token < q && *token == '-';
  const char* word = token + (token < q && (*token == '+' || *token == '-') ? 1 : 0);
  if (starts_with_word(word, q, "nan")) return std::numeric_limits<float>::quiet_NaN();
  if (starts_with_word(word, q, "inf")) return (negative ? -1.0f : 1.0f) * std::numeric_limits<float>::infinity();
  return 0.0f;
}

/// `atoi` on the line: spaces, a sign, digits; saturated to a long, then cast to int.
int next_index(const Line& line, const char* q) {
  while (q < line.stop && (*q == ' ' || (*q >= '\t' && *q <= '\r'))) ++q;
  bool negative = false;
  if (q < line.stop && (*q == '+' || *q == '-')) negative = *q++ == '-';
  std::uint64_t magnitude = 0;
  bool overflow = false;
  for (; q < line.stop && is_digit(*q); ++q) {
    if (magnitude > (std::numeric_limits<std::uint64_t>::max() - 9) / 10) overflow = true;
    if (!overflow) magnitude = magnitude * 10 + static_cast<unsigned>(*q - '0');
  }
  constexpr std::uint64_t long_max = static_cast<std::uint64_t>(std::numeric_limits<long>::max());
  long value;
  if (negative) {
    value = overflow || magnitude > long_max + 1 ? std::numeric_limits<long>::min() : static_cast<long>(0 - magnitude);
  } else {
    value = overflow || magnitude > long_max ? std::numeric_limits<long>::max() : static_cast<long>(magnitude);
  }
  return static_cast<int>(static_cast<std::uint32_t>(static_cast<std::uint64_t>(value)));
}

std::int64_t resolve(int raw, std::size_t count_in_piece, std::int64_t zero) {
  if (raw > 0) return raw - 1;
  if (raw < 0) return static_cast<std::int64_t>(count_in_piece) + raw + relative;
  return zero;
}

void read_face(const Line& line, const char* q, ObjPiece& piece) {
  auto field_end = [](char c) { return c == '/' || c == ' ' || c == '\t' || c == '\r'; };
  const std::size_t first_corner = piece.corner_v.size();
  const std::size_t v_count = piece.vertex_pos.size() / 3, vt_count = piece.uv.size() / 2,
                    vn_count = piece.normal.size() / 3;
  line.skip_spaces(q);
  while (q < line.stop) {
    // tinyobjloader's parseRawTriple: v, v/vt, v//vn, v/vt/vn.
    int v = next_index(line, q), vt = 0, vn = 0;
    q = line.find(q, field_end);
    if (line.at(q) == '/') {
      ++q;
      if (line.at(q) == '/') {
        ++q;
        vn = next_index(line, q);
        q = line.find(q, field_end);
      } else {
        vt = next_index(line, q);
        q = line.find(q, field_end);
        if (line.at(q) == '/') {
          ++q;
          vn = next_index(line, q);
          q = line.find(q, field_end);
        }
      }
    }
    piece.corner_v.push_back(resolve(v, v_count, invalid));
    piece.corner_vt.push_back(resolve(vt, vt_count, absent));
    piece.corner_vn.push_back(resolve(vn, vn_count, absent));
    while (q < line.stop && (is_space(*q) || *q == '\r')) ++q;
  }
  if (piece.corner_v.size() > first_corner) piece.face_offset.push_back(piece.corner_v.size());
}

void read_line(const Line& line, ObjPiece& piece) {
  const char* q = line.p;
  line.skip_spaces(q);
  if (q == line.stop || *q == '#') return;
  const char c0 = *q, c1 = line.at(q + 1);
  if (c0 == 'v' && is_space(c1)) {
    q += 2;
    for (int k = 0; k < 3; ++k) piece.vertex_pos.push_back(next_coordinate(line, q));
  } else if (c0 == 'v' && (c1 == 'n' || c1 == 't') && is_space(line.at(q + 2))) {
    q += 3;
    std::vector<float>& values = c1 == 'n' ? piece.normal : piece.uv;
    const float x = next_real(line, q, 0.0f), y = next_real(line, q, 0.0f);
    values.insert(values.end(), {x, y});
    if (c1 == 'n') values.push_back(next_real(line, q, 0.0f));
  } else if (c0 == 'f' && is_space(c1)) {
    read_face(line, q + 2, piece);
  } else if (c0 == 'g' && is_space(c1)) {
    NameLine name;
    name.face = piece.face_offset.size() - 1;
    q += 1;  // tinyobjloader reads the keyword as the first name and passes the others
    while (q < line.stop) {
      line.skip_spaces(q);
      const char* end = line.find(q, [](char c) { return c == ' ' || c == '\t' || c == '\r'; });
      if (end > q) name.group_names.emplace_back(q, end);
      q = end;
    }
    piece.name_lines.push_back(std::move(name));
  } else if (c0 == 'o' && is_space(c1)) {
    NameLine name;
    name.face = piece.face_offset.size() - 1;
    name.object = true;
    const char* first = q + 2;
    const char* last = line.stop;
    while (first < last && is_space(*first)) ++first;
    while (last > first && is_space(last[-1])) --last;
    name.object_name.assign(first, last);
    piece.name_lines.push_back(std::move(name));
  }
}

void read_piece(const char* begin, const char* end, ObjPiece& piece) {
  // Room for what a typical cloth OBJ holds (lines of 20 to 40 bytes), so the arrays rarely grow.
  const std::size_t lines = static_cast<std::size_t>(end - begin) / 32;
  piece.vertex_pos.reserve(lines * 3 / 2);
  piece.corner_v.reserve(lines * 2);
  piece.corner_vt.reserve(lines * 2);
  piece.corner_vn.reserve(lines * 2);
  piece.face_offset.reserve(lines * 2 / 3);
  const char* p = begin;
  while (p < end) {
    const char* line_begin = p;
    const char* nul = nullptr;
    while (p < end && *p != '\n' && *p != '\r') {
      if (*p == '\0' && !nul) nul = p;
      ++p;
    }
    read_line(Line{line_begin, nul ? nul : p}, piece);
    if (p < end) p += (*p == '\r' && p + 1 < end && p[1] == '\n') ? 2 : 1;
  }
}

/// Line-aligned pieces: each ends just after a '\n' (which ends a line however lines end), or at
/// the end of the text.
std::vector<const char*> piece_bounds(const char* begin, const char* end, std::size_t piece_bytes) {
  const std::size_t size = static_cast<std::size_t>(end - begin);
  const std::size_t wanted =
      std::min<std::size_t>(4 * static_cast<std::size_t>(omp_get_max_threads()),
                            std::max<std::size_t>(1, size / std::max<std::size_t>(1, piece_bytes)));
  std::vector<const char*> bounds = {begin};
  for (std::size_t k = 1; k < wanted; ++k) {
    const char* at = begin + size / wanted * k;
    if (at <= bounds.back()) continue;
    const void* newline = std::memchr(at, '\n', static_cast<std::size_t>(end - at));
    if (!newline) break;
    bounds.push_back(static_cast<const char*>(newline) + 1);
  }
  if (bounds.back() != end) bounds.push_back(end);
  return bounds;
}

/// The name state `o` and `g` lines set, followed through the file in order.
struct NameState {
  std::string mesh_name;
  std::string object, group;  ///< the current `o` name and `g` names joined by spaces
  std::vector<std::string> group_names;
  bool selected = true;
  std::vector<std::string> names;  ///< names of objects and groups that have faces

  void apply(const NameLine& line) {
    if (line.object) object = line.object_name;  // a `g` line keeps the object
    group.clear();
    group_names.clear();
    if (!line.object) {
      for (const std::string& name : line.group_names) group += (group.empty() ? "" : " ") + name;
      if (line.group_names.size() >= 2) group_names = line.group_names;
    }
    if (mesh_name.empty()) return;
    selected = mesh_name == object || mesh_name == group;
    for (const std::string& name : group_names) selected = selected || mesh_name == name;
  }

  void faces_follow() {
    append_name(names, object);
    append_name(names, group);
    for (const std::string& name : group_names) append_name(names, name);
  }
};

/// Where each piece's lines and faces start in the file's numbering.
struct PieceOffsets {
  std::size_t v = 0, vt = 0, vn = 0, face = 0, corner = 0, triangle_corner = 0;
};

/// Count and scan: the offsets of every piece, and after the last one the file's totals.
std::vector<PieceOffsets> piece_offsets(const std::string& path, const std::vector<ObjPiece>& pieces) {
  const std::size_t piece_count = pieces.size();
  std::vector<PieceOffsets> piece_offset(piece_count + 1);
  for (std::size_t k = 0; k < piece_count; ++k) {
    const ObjPiece& piece = pieces[k];
    PieceOffsets next = piece_offset[k];
    next.v += piece.vertex_pos.size() / 3;
    next.vt += piece.uv.size() / 2;
    next.vn += piece.normal.size() / 3;
    next.face += piece.face_offset.size() - 1;
    next.corner += piece.corner_v.size();
    piece_offset[k + 1] = next;
  }
  const PieceOffsets& total = piece_offset[piece_count];
  if (total.v > max_index_count || total.corner > max_index_count) {
    throw input_error(path, "too large: more than 2^31 vertices or face corners");
  }
  return piece_offset;
}

/// Which faces --mesh-name selects: the names are followed through the pieces in file order.
/// Returns the names seen, for the error when nothing is selected.
NameState select_faces(std::vector<ObjPiece>& pieces, const std::string& mesh_name) {
  NameState names;
  names.mesh_name = mesh_name;
  names.selected = mesh_name.empty();
  for (ObjPiece& piece : pieces) {
    const std::size_t face_count = piece.face_offset.size() - 1;
    piece.face_selected.assign(face_count, 1);
    if (mesh_name.empty()) continue;
    std::size_t face = 0;
    for (std::size_t n = 0; n <= piece.name_lines.size(); ++n) {
      const std::size_t until = n < piece.name_lines.size() ? piece.name_lines[n].face : face_count;
      if (until > face) names.faces_follow();
      std::fill(piece.face_selected.begin() + face, piece.face_selected.begin() + until, names.selected);
      face = until;
      if (n < piece.name_lines.size()) names.apply(piece.name_lines[n]);
    }
  }
  return names;
}

/// An index of a face's corner checked against the file's count of its lines: empty when it is in
/// range (or absent), else the message.
std::string index_error(std::int64_t index, std::size_t count, std::size_t face_number, const char* what,
                        const char* keyword) {
  if (index == absent || (index >= 0 && static_cast<std::size_t>(index) < count)) return {};
  const std::string number = std::to_string(face_number);
  if (index == invalid)
    return "face " + number + " has a " + what + " index of 0 or no number (OBJ indices start at 1)";
  if (index < 0)
    return "face " + number + " has a relative " + what + " index that reaches before the first '" + keyword + "' line";
  return "face " + number + " uses " + what + " " + std::to_string(index + 1) + ", out of range (the file has " +
         std::to_string(count) + " '" + keyword + "' lines)";
}

/// A piece's relative indices joined to the file's numbering, and every index checked. Returns the
/// message of the piece's first bad face (empty when none), and whether its selected faces have
/// UVs and normals; counts the triangle corners of its selected faces.
std::string join_piece(ObjPiece& piece, const PieceOffsets& at, const PieceOffsets& total, bool& with_uv,
                       bool& with_normals) {
  auto join = [](std::int64_t& index, std::size_t base) {
    if (index >= relative / 2) index = index - relative + static_cast<std::int64_t>(base);
  };
  const std::size_t face_count = piece.face_offset.size() - 1;
  with_uv = with_normals = false;
  for (std::size_t face = 0; face < face_count; ++face) {
    for (std::size_t c = piece.face_offset[face]; c < piece.face_offset[face + 1]; ++c) {
      join(piece.corner_v[c], at.v);
      join(piece.corner_vt[c], at.vt);
      join(piece.corner_vn[c], at.vn);
      const std::size_t number = at.face + face + 1;
      std::string error = index_error(piece.corner_v[c], total.v, number, "vertex", "v");
      if (error.empty()) error = index_error(piece.corner_vt[c], total.vt, number, "texture coordinate", "vt");
      if (error.empty()) error = index_error(piece.corner_vn[c], total.vn, number, "normal", "vn");
      if (!error.empty()) {
        with_uv = with_normals = false;
        return error;
      }
      if (!piece.face_selected[face]) continue;
      with_uv = with_uv || piece.corner_vt[c] != absent;
      with_normals = with_normals || piece.corner_vn[c] != absent;
    }
    const std::size_t corner_count = piece.face_offset[face + 1] - piece.face_offset[face];
    if (piece.face_selected[face] && corner_count >= 3) piece.face_triangle_corners += 3 * (corner_count - 2);
  }
  return {};
}

/// A piece's selected faces, triangulated, written from mesh corner `out_corner` on: nodes, and the
/// corners' UVs and normals from the file's `uv` and `normal` arrays where the mesh has them.
void write_piece_triangles(const ObjPiece& piece, std::size_t out_corner, const std::vector<float>& uv,
                           const std::vector<float>& normal, bool with_uv, bool with_normals, Mesh& mesh) {
  std::vector<float> polygon_pos;
  std::vector<index_t> polygon_triangles;
  static const std::vector<index_t> one_triangle = {0, 1, 2};
  for (std::size_t face = 0; face + 1 < piece.face_offset.size(); ++face) {
    const std::size_t first = piece.face_offset[face], corner_count = piece.face_offset[face + 1] - first;
    if (!piece.face_selected[face] || corner_count < 3) continue;
    const std::vector<index_t>* triangles = &one_triangle;
    if (corner_count > 3) {
      polygon_pos.clear();
      for (std::size_t c = first; c < first + corner_count; ++c) {
        const float* p = &mesh.node_pos[3 * static_cast<std::size_t>(piece.corner_v[c])];
        polygon_pos.insert(polygon_pos.end(), p, p + 3);
      }
      polygon_triangles = triangulate_polygon(polygon_pos.data(), static_cast<index_t>(corner_count));
      triangles = &polygon_triangles;
    }
    for (index_t corner : *triangles) {
      const std::size_t c = first + static_cast<std::size_t>(corner);
      mesh.face_nodes[out_corner] = static_cast<index_t>(piece.corner_v[c]);
      if (with_uv) {
        const std::int64_t t = piece.corner_vt[c];
        mesh.corner_uv[2 * out_corner] = t == absent ? 0.0f : uv[2 * t];
        mesh.corner_uv[2 * out_corner + 1] = t == absent ? 0.0f : uv[2 * t + 1];
      }
      if (with_normals) {
        const std::int64_t n = piece.corner_vn[c];
        for (int j = 0; j < 3; ++j) mesh.corner_normal[3 * out_corner + j] = n == absent ? 0.0f : normal[3 * n + j];
      }
      ++out_corner;
    }
  }
}

/// The mesh of the checked pieces: the vertex arrays joined, then each piece's triangles at its
/// offset.
FileMesh write_pieces(const std::vector<ObjPiece>& pieces, const std::vector<PieceOffsets>& piece_offset, bool with_uv,
                      bool with_normals) {
  const std::size_t piece_count = pieces.size();
  const PieceOffsets& total = piece_offset[piece_count];
  const std::size_t triangle_corner_count = total.triangle_corner;
  FileMesh out;
  Mesh& mesh = out.mesh;
  std::vector<float> uv, normal;
  mesh.node_pos.resize(3 * total.v);
  uv.resize(2 * total.vt);
  normal.resize(3 * total.vn);
  mesh.face_nodes.resize(triangle_corner_count);
  if (with_uv) mesh.corner_uv.resize(2 * triangle_corner_count);
  if (with_normals) mesh.corner_normal.resize(3 * triangle_corner_count);
  for_each_piece(piece_count, [&](std::size_t k) {
    const ObjPiece& piece = pieces[k];
    std::copy(piece.vertex_pos.begin(), piece.vertex_pos.end(), mesh.node_pos.begin() + 3 * piece_offset[k].v);
    std::copy(piece.uv.begin(), piece.uv.end(), uv.begin() + 2 * piece_offset[k].vt);
    std::copy(piece.normal.begin(), piece.normal.end(), normal.begin() + 3 * piece_offset[k].vn);
  });
  for_each_piece(piece_count, [&](std::size_t k) {
    write_piece_triangles(pieces[k], piece_offset[k].triangle_corner, uv, normal, with_uv, with_normals, mesh);
  });
  return out;
}

}  // namespace

FileMesh read_obj_file(const std::string& path, std::string text, const std::string& mesh_name,
                       std::size_t piece_bytes) {
  if (text.compare(0, 2, "\xFE\xFF") == 0 || text.compare(0, 2, "\xFF\xFE") == 0) {
    throw input_error(path, "is UTF-16 text; OBJ files are read as UTF-8 (or ASCII)");
  }
  // A UTF-8 byte order mark (Windows editors write one) is no part of the first line.
  const char* const begin = text.data() + (text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0);
  const std::vector<const char*> bounds = piece_bounds(begin, text.data() + text.size(), piece_bytes);
  const std::size_t piece_count = bounds.size() - 1;
  std::vector<ObjPiece> pieces(piece_count);
  for_each_piece(piece_count, [&](std::size_t k) { read_piece(bounds[k], bounds[k + 1], pieces[k]); });

  std::vector<PieceOffsets> piece_offset = piece_offsets(path, pieces);
  const NameState names = select_faces(pieces, mesh_name);

  // The message is that of the first bad face in the file.
  std::vector<std::string> piece_error(piece_count);
  std::vector<std::uint8_t> piece_uv(piece_count, 0), piece_normals(piece_count, 0);
  bool any_selected = false;
  for (const ObjPiece& piece : pieces) {
    any_selected = any_selected ||
                   std::find(piece.face_selected.begin(), piece.face_selected.end(), 1) != piece.face_selected.end();
  }
  for_each_piece(piece_count, [&](std::size_t k) {
    bool with_uv = false, with_normals = false;
    piece_error[k] = join_piece(pieces[k], piece_offset[k], piece_offset[piece_count], with_uv, with_normals);
    piece_uv[k] = with_uv;
    piece_normals[k] = with_normals;
  });
  for (const std::string& error : piece_error) {
    if (!error.empty()) throw input_error(path, error);
  }
  if (!mesh_name.empty() && !any_selected) throw no_mesh_named(path, mesh_name, names.names);
  const bool with_uv = std::find(piece_uv.begin(), piece_uv.end(), 1) != piece_uv.end();
  const bool with_normals = std::find(piece_normals.begin(), piece_normals.end(), 1) != piece_normals.end();
  for (std::size_t k = 0; k < piece_count; ++k) {
    piece_offset[k + 1].triangle_corner = piece_offset[k].triangle_corner + pieces[k].face_triangle_corners;
  }
  if (piece_offset[piece_count].triangle_corner > max_index_count)
    throw input_error(path, "too large: more than 2^31 face corners");
  return write_pieces(pieces, piece_offset, with_uv, with_normals);
}

}  // namespace tear
