// OBJ frames: text written in pieces side by side, numbers without the locale.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "io/mesh/corner_numbering.h"
#include "io/mesh/encode_mesh.h"
#include "io/mesh/parallel_pieces.h"
#include "tear/error.h"

namespace tear::encode {
namespace {

/// Appends `%.9g` of `value` without the locale: 9 significant digits always read back to the
/// same float. Small magnitudes go to fixed notation where that is exact too, because fast OBJ
/// parsers (assimp's among them) scale by the exponent in float arithmetic and miss by one ulp on
/// a few percent of such numbers. The digits go through a buffer on the stack, so a frame of
/// hundreds of thousands of numbers allocates nothing per number.
void append_float(std::string& out, float value) {
  char text[64];
  const double wide = value;
  if (std::isfinite(value) && value != 0.0f && std::fabs(value) < 1e-4f) {
    const auto fixed = std::to_chars(text, text + sizeof text, wide, std::chars_format::fixed, 15);
    float back = 0.0f;
    const auto parsed = std::from_chars(text, fixed.ptr, back);
    if (parsed.ec == std::errc() && back == value) {
      out.append(text, fixed.ptr);
      return;
    }
  }
  const auto general = std::to_chars(text, text + sizeof text, wide, std::chars_format::general, 9);
  out.append(text, general.ptr);
}

/// The digits of `value` in decimal.
std::size_t decimal_digits(std::uint32_t value) {
  std::size_t digits = 1;
  for (; value >= 10; value /= 10) ++digits;
  return digits;
}

/// Text written in pieces side by side, then joined in order. Pieces are added loop by loop; a
/// loop of one piece appends to the last piece instead, so that on one thread all the text goes
/// straight into the first piece, which is the output's own buffer.
class TextPieces {
 public:
  TextPieces(const PieceTeam& team, std::string& out) : team_(team), out_(out) {
    pieces_.emplace_back();
    pieces_[0].swap(out);
    pieces_[0].clear();
  }

  std::string& first() { return pieces_[0]; }

  /// Runs `write(text, i)` for each i in [0, count), in pieces; `bytes_each` is a guess of the
  /// bytes each writes, to reserve.
  template <typename Write>
  void add(std::size_t count, std::size_t bytes_each, Write write) {
    const std::size_t piece_count = team_.pieces(count);
    const std::size_t first = piece_count == 1 ? pieces_.size() - 1 : pieces_.size();
    pieces_.resize(first + piece_count);
    team_.for_each_range(count, piece_count, [&](std::size_t k, std::size_t begin, std::size_t end) {
      std::string& text = pieces_[first + k];
      const std::size_t wanted = text.size() + (end - begin) * bytes_each;
      if (text.capacity() < wanted) text.reserve(wanted);
      for (std::size_t i = begin; i < end; ++i) write(text, i);
    });
  }

  /// Puts the text together in the output, followed by `more` bytes to be written; returns where
  /// they go.
  char* join(std::size_t more) {
    std::vector<std::size_t> at(pieces_.size() + 1);
    for (std::size_t k = 0; k < pieces_.size(); ++k) at[k + 1] = at[k] + pieces_[k].size();
    out_.swap(pieces_[0]);
    out_.resize(at.back() + more);
    for_each_piece(
        pieces_.size() - 1,
        [&](std::size_t k) { std::memcpy(&out_[at[k + 1]], pieces_[k + 1].data(), pieces_[k + 1].size()); },
        team_.threads);
    return out_.data() + at.back();
  }

 private:
  const PieceTeam& team_;
  std::string& out_;
  std::vector<std::string> pieces_;
};

/// Appends a line of `keyword` and `width` floats.
void append_line(std::string& out, const char* keyword, const float* values, int width) {
  out += keyword;
  for (int k = 0; k < width; ++k) {
    out += ' ';
    append_float(out, values[k]);
  }
  out += '\n';
}

}  // namespace

void put_obj_text(const Mesh& mesh, const PieceTeam& team, std::string& out) {
  TextPieces text(team, out);
  text.first() = "# tear\n";
  text.add(static_cast<std::size_t>(mesh.node_count()), 32,
           [&](std::string& line, std::size_t node) { append_line(line, "v", &mesh.node_pos[3 * node], 3); });
  ValueNumbers uv, normal;
  if (mesh.has_uv()) {
    uv = number_by_value(mesh.corner_uv, 2, team);
    text.add(uv.first_corner.size(), 24, [&](std::string& line, std::size_t i) {
      append_line(line, "vt", &mesh.corner_uv[2 * static_cast<std::size_t>(uv.first_corner[i])], 2);
    });
  }
  if (mesh.has_normals()) {
    normal = number_by_value(mesh.corner_normal, 3, team);
    text.add(normal.first_corner.size(), 32, [&](std::string& line, std::size_t i) {
      append_line(line, "vn", &mesh.corner_normal[3 * static_cast<std::size_t>(normal.first_corner[i])], 3);
    });
  }
  // `f` lines: their lengths are cheap to count, so they are counted, then written in place.
  const bool with_uv = mesh.has_uv(), with_normals = mesh.has_normals();
  auto corner_bytes = [&](std::size_t c) {
    return 1 + decimal_digits(mesh.face_nodes[c] + 1u) + (with_uv || with_normals) +
           (with_uv ? decimal_digits(uv.corner_value[c] + 1u) : 0) +
           (with_normals ? 1 + decimal_digits(normal.corner_value[c] + 1u) : 0);
  };
  const std::size_t face_count = static_cast<std::size_t>(mesh.face_count());
  const std::size_t piece_count = team.pieces(face_count);
  std::vector<std::size_t> face_start(piece_count);
  team.for_each_range(face_count, piece_count, [&](std::size_t k, std::size_t begin, std::size_t end) {
    std::size_t bytes = 0;
    for (std::size_t c = 3 * begin; c < 3 * end; ++c) bytes += corner_bytes(c);
    face_start[k] = bytes + 2 * (end - begin);
  });
  const std::size_t face_bytes = exclusive_sums(face_start);
  char* const faces = text.join(face_bytes);
  team.for_each_range(face_count, piece_count, [&](std::size_t k, std::size_t begin, std::size_t end) {
    char* at = faces + face_start[k];
    auto put = [&](std::uint32_t value) { at = std::to_chars(at, at + 10, value).ptr; };
    for (std::size_t c = 3 * begin; c < 3 * end; ++c) {
      if (c % 3 == 0) *at++ = 'f';
      *at++ = ' ';
      put(mesh.face_nodes[c] + 1u);
      if (with_uv || with_normals) *at++ = '/';
      if (with_uv) put(uv.corner_value[c] + 1u);
      if (with_normals) {
        *at++ = '/';
        put(normal.corner_value[c] + 1u);
      }
      if (c % 3 == 2) *at++ = '\n';
    }
  });
}

}  // namespace tear::encode
