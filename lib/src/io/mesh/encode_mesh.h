// tear: the encoders of write_mesh's formats (obj/write_obj.cpp, ply/write_ply.cpp,
// gltf/write_gltf.cpp) and the little helpers they share.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "io/mesh/parallel_pieces.h"
#include "tear/mesh.h"

namespace tear::encode {

/// The largest node count whose every index a float holds exactly (2^24).
inline constexpr index_t max_float_id = 1 << 24;

inline std::uint32_t float_bits(float value) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

inline void append_u32(std::string& out, std::uint32_t value) {
  const char bytes[4] = {static_cast<char>(value & 0xFFu), static_cast<char>((value >> 8) & 0xFFu),
                         static_cast<char>((value >> 16) & 0xFFu), static_cast<char>((value >> 24) & 0xFFu)};
  out.append(bytes, 4);
}

/// Little endian at `at`, which moves on: binary arrays are written in place, in pieces.
inline void put_u32(char*& at, std::uint32_t value) {
  at[0] = static_cast<char>(value & 0xFFu);
  at[1] = static_cast<char>((value >> 8) & 0xFFu);
  at[2] = static_cast<char>((value >> 16) & 0xFFu);
  at[3] = static_cast<char>((value >> 24) & 0xFFu);
  at += 4;
}

inline void put_f32(char*& at, float value) { put_u32(at, float_bits(value)); }

/// A vertex's UV and normal: its first corner's, or zeros for a node no face uses.
inline float corner_value(const std::vector<float>& corner_values, int width, index_t corner, int k) {
  return corner == none ? 0.0f : corner_values[static_cast<std::size_t>(width) * corner + k];
}

/// Each format's bytes of a mesh that `check_mesh` accepted, encoded in pieces by `team`, in `out`.
void put_obj_text(const Mesh& mesh, const PieceTeam& team, std::string& out);
void put_ply_bytes(const Mesh& mesh, const PieceTeam& team, std::string& out);
void put_gltf_text(const Mesh& mesh, const PieceTeam& team, std::string& out);
void put_glb_bytes(const Mesh& mesh, const PieceTeam& team, std::string& out);

}  // namespace tear::encode
