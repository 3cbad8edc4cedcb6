// The OBJ reader tear had before its own parser: tinyobjloader's callback API, which hands over
// every `v` line in order and every face whole, with its raw (1-based or relative) v/vt/vn
// indices. Kept as the reference the parser must match (test_read_obj.cpp).
#include <tiny_obj_loader.h>

#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "tinyobj_reference.h"

#include "io/mesh/file_mesh.h"
#include "tear/error.h"
#include "tear/triangulate_polygon.h"

namespace tear {
namespace {

/// Everything the callbacks collect, in file order. Corner indices are 0-based (negative or too
/// large when out of range), or `absent` where the corner has no vt/vn, or `invalid` where the
/// file wrote 0 or no number (which OBJ does not allow).
struct ObjData {
  static constexpr std::int64_t invalid = std::numeric_limits<std::int64_t>::min();
  static constexpr std::int64_t absent = invalid + 1;

  std::vector<float> vertex_pos;  ///< [vertex_count * 3]
  std::vector<float> uv;          ///< [uv_count * 2]
  std::vector<float> normal;      ///< [normal_count * 3]
  std::vector<std::int64_t> corner_v, corner_vt, corner_vn;
  std::vector<std::size_t> face_offset = {0};  ///< [face_count + 1] into the corner arrays
  std::vector<std::uint8_t> face_selected;     ///< [face_count] named by --mesh-name (or all)

  std::string mesh_name;
  std::string object, group;  ///< the current `o` name and `g` names joined by spaces
  std::vector<std::string> group_names;
  bool selected = true;
  std::vector<std::string> names;  ///< names of objects and groups that have faces

  void name_changed() {
    if (mesh_name.empty()) return;
    selected = mesh_name == object || mesh_name == group;
    for (const std::string& name : group_names) selected = selected || mesh_name == name;
  }
};

std::int64_t resolve(int raw, std::size_t count) {
  if (raw > 0) return raw - 1;
  if (raw < 0) return static_cast<std::int64_t>(count) + raw;  // relative to the lines read so far
  return ObjData::invalid;
}

void on_vertex(void* user, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t z, tinyobj::real_t) {
  static_cast<ObjData*>(user)->vertex_pos.insert(static_cast<ObjData*>(user)->vertex_pos.end(), {x, y, z});
}

void on_normal(void* user, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t z) {
  static_cast<ObjData*>(user)->normal.insert(static_cast<ObjData*>(user)->normal.end(), {x, y, z});
}

void on_uv(void* user, tinyobj::real_t u, tinyobj::real_t v, tinyobj::real_t) {
  static_cast<ObjData*>(user)->uv.insert(static_cast<ObjData*>(user)->uv.end(), {u, v});
}

void on_face(void* user, tinyobj::index_t* indices, int count) {
  ObjData& data = *static_cast<ObjData*>(user);
  const std::size_t vertex_count = data.vertex_pos.size() / 3;
  for (int k = 0; k < count; ++k) {
    data.corner_v.push_back(resolve(indices[k].vertex_index, vertex_count));
    // The callback passes 0 for a missing vt or vn.
    data.corner_vt.push_back(indices[k].texcoord_index == 0 ? ObjData::absent
                                                            : resolve(indices[k].texcoord_index, data.uv.size() / 2));
    data.corner_vn.push_back(indices[k].normal_index == 0 ? ObjData::absent
                                                          : resolve(indices[k].normal_index, data.normal.size() / 3));
  }
  data.face_offset.push_back(data.corner_v.size());
  data.face_selected.push_back(data.selected);
  append_name(data.names, data.object);
  append_name(data.names, data.group);
  for (const std::string& name : data.group_names) append_name(data.names, name);
}

void on_group(void* user, const char** names, int count) {
  ObjData& data = *static_cast<ObjData*>(user);
  data.group.clear();
  data.group_names.clear();
  for (int k = 0; k < count; ++k) {
    if (!names[k] || !*names[k]) continue;
    data.group_names.push_back(names[k]);
    data.group += (data.group.empty() ? "" : " ") + std::string(names[k]);
  }
  if (data.group_names.size() < 2) data.group_names.clear();
  data.name_changed();
}

void on_object(void* user, const char* name) {
  ObjData& data = *static_cast<ObjData*>(user);
  data.object = name ? name : "";
  const std::size_t first = data.object.find_first_not_of(" \t");
  const std::size_t last = data.object.find_last_not_of(" \t");
  data.object = first == std::string::npos ? std::string() : data.object.substr(first, last + 1 - first);
  data.group.clear();
  data.group_names.clear();
  data.name_changed();
}

bool starts_non_finite(const char* token) {
  if (*token == '+' || *token == '-') ++token;
  return strncasecmp(token, "nan", 3) == 0 || strncasecmp(token, "inf", 3) == 0;
}

/// tinyobjloader reads a coordinate it cannot parse as 0, "nan" and "inf" among them. A NaN or
/// infinite coordinate is bad input that the checks after reading must see, so the `v` lines are
/// scanned here (split into lines and tokens as tinyobjloader splits them) and such coordinates
/// restored.
void restore_non_finite(const std::string& text, std::vector<float>& vertex_pos) {
  std::size_t vertex = 0;
  const char* p = text.data();
  const char* const end = p + text.size();
  while (p < end) {
    const char* line_end = p;
    while (line_end < end && *line_end != '\n' && *line_end != '\r') ++line_end;
    // A line is read as a C string: it stops at the first NUL.
    const char* stop = static_cast<const char*>(std::memchr(p, '\0', static_cast<std::size_t>(line_end - p)));
    if (!stop) stop = line_end;
    const char* token = p;
    p = line_end + (line_end < end && *line_end == '\r' && line_end + 1 < end && line_end[1] == '\n' ? 2 : 1);

    auto skip = [&](const char* set) {
      while (token < stop && std::strchr(set, *token)) ++token;
    };
    skip(" \t");
    if (stop - token < 2 || token[0] != 'v' || (token[1] != ' ' && token[1] != '\t')) continue;
    token += 2;
    for (int k = 0; k < 3; ++k) {
      skip(" \t");
      const char* word = token;
      while (token < stop && *token != ' ' && *token != '\t' && *token != '\r') ++token;
      const std::string value(word, token);
      if (starts_non_finite(value.c_str()) && 3 * vertex + k < vertex_pos.size()) {
        const bool negative = value[0] == '-';
        const bool is_nan = strncasecmp(value.c_str() + (value[0] == '+' || negative), "nan", 3) == 0;
        vertex_pos[3 * vertex + k] = is_nan ? std::numeric_limits<float>::quiet_NaN()
                                            : (negative ? -1.0f : 1.0f) * std::numeric_limits<float>::infinity();
      }
    }
    ++vertex;
  }
}

}  // namespace

FileMesh read_obj_with_tinyobjloader(const std::string& path, std::string text, const std::string& mesh_name) {
  // A UTF-8 byte order mark (Windows editors write one) is no part of the first line.
  if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);
  if (text.compare(0, 2, "\xFE\xFF") == 0 || text.compare(0, 2, "\xFF\xFE") == 0) {
    throw input_error(path, "is UTF-16 text; OBJ files are read as UTF-8 (or ASCII)");
  }

  ObjData data;
  data.mesh_name = mesh_name;
  data.selected = mesh_name.empty();
  tinyobj::callback_t callback;
  callback.vertex_cb = on_vertex;
  callback.normal_cb = on_normal;
  callback.texcoord_cb = on_uv;
  callback.index_cb = on_face;
  callback.group_cb = on_group;
  callback.object_cb = on_object;
  std::istringstream stream(text);
  std::string warning, error;
  // No material reader: materials are of no use to cloth, and no other file is opened.
  if (!tinyobj::LoadObjWithCallback(stream, callback, &data, nullptr, &warning, &error)) {
    throw input_error(path, "cannot read as OBJ");
  }
  restore_non_finite(text, data.vertex_pos);

  const std::size_t vertex_count = data.vertex_pos.size() / 3;
  if (vertex_count > max_index_count || data.corner_v.size() > max_index_count) {
    throw input_error(path, "too large: more than 2^31 vertices or face corners");
  }
  const std::size_t face_count = data.face_offset.size() - 1;
  auto check = [&](std::int64_t index, std::size_t count, std::size_t face, const char* what, const char* keyword) {
    if (index == ObjData::absent) return;
    if (index == ObjData::invalid) {
      throw input_error(path, "face " + std::to_string(face + 1) + " has a " + what +
                                  " index of 0 or no number (OBJ indices start at 1)");
    }
    if (index < 0) {
      throw input_error(path, "face " + std::to_string(face + 1) + " has a relative " + what +
                                  " index that reaches before the first '" + keyword + "' line");
    }
    if (static_cast<std::size_t>(index) >= count) {
      throw input_error(path, "face " + std::to_string(face + 1) + " uses " + what + " " + std::to_string(index + 1) +
                                  ", out of range (the file has " + std::to_string(count) + " '" + keyword +
                                  "' lines)");
    }
  };
  bool any_selected = false, with_uv = false, with_normals = false;
  for (std::size_t face = 0; face < face_count; ++face) {
    for (std::size_t c = data.face_offset[face]; c < data.face_offset[face + 1]; ++c) {
      if (data.corner_v[c] == ObjData::absent) data.corner_v[c] = ObjData::invalid;
      check(data.corner_v[c], vertex_count, face, "vertex", "v");
      check(data.corner_vt[c], data.uv.size() / 2, face, "texture coordinate", "vt");
      check(data.corner_vn[c], data.normal.size() / 3, face, "normal", "vn");
      if (!data.face_selected[face]) continue;
      any_selected = true;
      with_uv = with_uv || data.corner_vt[c] != ObjData::absent;
      with_normals = with_normals || data.corner_vn[c] != ObjData::absent;
    }
  }
  if (!mesh_name.empty() && !any_selected) throw no_mesh_named(path, mesh_name, data.names);

  FileMesh out;
  Mesh& mesh = out.mesh;
  mesh.node_pos = std::move(data.vertex_pos);
  std::vector<float> polygon_pos;
  std::vector<index_t> triangle;
  for (std::size_t face = 0; face < face_count; ++face) {
    const std::size_t first = data.face_offset[face], corner_count = data.face_offset[face + 1] - first;
    if (!data.face_selected[face] || corner_count < 3) continue;
    if (corner_count == 3) {
      triangle = {0, 1, 2};
    } else {
      polygon_pos.clear();
      for (std::size_t k = 0; k < corner_count; ++k) {
        const float* p = &mesh.node_pos[3 * data.corner_v[first + k]];
        polygon_pos.insert(polygon_pos.end(), p, p + 3);
      }
      triangle = triangulate_polygon(polygon_pos.data(), static_cast<index_t>(corner_count));
    }
    for (index_t k : triangle) {
      const std::size_t c = first + static_cast<std::size_t>(k);
      mesh.face_nodes.push_back(static_cast<index_t>(data.corner_v[c]));
      if (with_uv) {
        const std::int64_t t = data.corner_vt[c];
        const bool has = t != ObjData::absent;
        mesh.corner_uv.insert(mesh.corner_uv.end(), {has ? data.uv[2 * t] : 0.0f, has ? data.uv[2 * t + 1] : 0.0f});
      }
      if (with_normals) {
        const std::int64_t n = data.corner_vn[c];
        for (int j = 0; j < 3; ++j) mesh.corner_normal.push_back(n == ObjData::absent ? 0.0f : data.normal[3 * n + j]);
      }
    }
    if (mesh.face_nodes.size() > max_index_count) throw input_error(path, "too large: more than 2^31 face corners");
  }
  return out;
}

}  // namespace tear
