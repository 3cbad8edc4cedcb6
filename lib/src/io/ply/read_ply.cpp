// PLY by hand: assimp's PLY importer crashes on some malformed headers and trusts declared
// counts, and Debian has no other PLY library. Every count is checked against the bytes the file
// actually has before anything is allocated for it.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

#include "io/mesh/file_mesh.h"
#include "io/ply/ply_format.h"
#include "tear/error.h"
#include "tear/triangulate_polygon.h"

namespace tear {
namespace {

using namespace ply;

struct Properties {
  int x = -1, y = -1, z = -1, nx = -1, ny = -1, nz = -1, u = -1, v = -1;
  int id = -1, vx = -1, vy = -1, vz = -1, origin_face = -1, origin_u = -1, origin_v = -1;
};

Properties vertex_properties(const PlyElement& vertex) {
  Properties p;
  p.x = vertex.find("x"), p.y = vertex.find("y"), p.z = vertex.find("z");
  p.nx = vertex.find("nx"), p.ny = vertex.find("ny"), p.nz = vertex.find("nz");
  if (p.nx < 0 || p.ny < 0 || p.nz < 0) p.nx = p.ny = p.nz = -1;
  static const char* const uv_names[][2] = {
      {"s", "t"}, {"u", "v"}, {"texture_u", "texture_v"}, {"texture_s", "texture_t"}};
  for (const auto& names : uv_names) {
    if (p.u >= 0) break;
    p.u = vertex.find(names[0]), p.v = vertex.find(names[1]);
    if (p.u < 0 || p.v < 0) p.u = p.v = -1;
  }
  p.id = vertex.find("id");
  p.vx = vertex.find("vx"), p.vy = vertex.find("vy"), p.vz = vertex.find("vz");
  if (p.vx < 0 || p.vy < 0 || p.vz < 0) p.vx = p.vy = p.vz = -1;
  p.origin_face = vertex.find("origin_face"), p.origin_u = vertex.find("origin_u"),
  p.origin_v = vertex.find("origin_v");
  if (p.origin_face < 0 || p.origin_u < 0 || p.origin_v < 0) p.origin_face = p.origin_u = p.origin_v = -1;
  return p;
}

/// What a vertex value must be, in the fast paths and the one-by-one loop alike: a coordinate a
/// float holds, an `id` that is a node index, an `origin_face` that is one or -1 (unknown), a
/// corner that names one of the file's vertices.
bool is_float_value(double value) {
  return std::isfinite(value) && std::fabs(value) <= std::numeric_limits<float>::max();
}
bool is_id_value(double value) { return value >= 0 && value <= static_cast<double>(max_index_count); }
bool is_origin_face_value(double value) { return value >= -1 && value <= static_cast<double>(max_index_count); }
bool is_vertex_value(double value, std::size_t vertex_count) {
  return value >= 0 && value < static_cast<double>(vertex_count);
}

/// Below this many instances an element's fast path runs on the calling thread alone.
constexpr std::int64_t parallel_from = 4096;

/// The vertex element of a binary file whose instances all have one layout (no lists), on OpenMP
/// threads: each instance's values written at its own index, converted as the one-by-one loop
/// converts them. False, with nothing written, where a value is one that loop refuses (it then
/// reads the element and fails with its message).
bool read_vertices_at_once(const PlyElement& element, const char* data, std::size_t stride, bool big_endian,
                           const Properties& props, Mesh& mesh, std::vector<index_t>& vertex_id,
                           std::vector<float>& vertex_normal, std::vector<float>& vertex_uv) {
  const std::int64_t count = static_cast<std::int64_t>(element.count);
  std::vector<std::size_t> offset(element.properties.size());
  for (std::size_t i = 1; i < offset.size(); ++i) offset[i] = offset[i - 1] + size_of(element.properties[i - 1].type);
  const std::size_t n = static_cast<std::size_t>(count);
  mesh.node_pos.resize(3 * n);
  if (props.nx >= 0) vertex_normal.resize(3 * n);
  if (props.u >= 0) vertex_uv.resize(2 * n);
  if (props.vx >= 0) mesh.node_vel.resize(3 * n);
  if (props.id >= 0) vertex_id.resize(n);
  if (props.origin_face >= 0) {
    mesh.node_origin_face.resize(n);
    mesh.node_origin_bary.resize(2 * n);
  }
  bool refused = false;
#pragma omp parallel for schedule(static) reduction(|| : refused) if (count >= parallel_from)
  for (std::int64_t instance = 0; instance < count; ++instance) {
    const char* at = data + static_cast<std::size_t>(instance) * stride;
    const std::size_t v = static_cast<std::size_t>(instance);
    const auto value = [&](int property) {
      return decode(at + offset[static_cast<std::size_t>(property)], element.properties[property].type, big_endian);
    };
    // As the one-by-one loop's `finite`: a refused value marks the element, and reads as 0.
    const auto finite = [&](int property) {
      const double x = value(property);
      if (!is_float_value(x)) {
        refused = true;
        return 0.0f;
      }
      return static_cast<float>(x);
    };
    const auto put = [&](std::vector<float>& into, std::size_t width, std::initializer_list<int> properties) {
      std::size_t k = 0;
      for (int property : properties) into[width * v + k++] = finite(property);
    };
    put(mesh.node_pos, 3, {props.x, props.y, props.z});
    if (props.nx >= 0) put(vertex_normal, 3, {props.nx, props.ny, props.nz});
    if (props.u >= 0) put(vertex_uv, 2, {props.u, props.v});
    if (props.vx >= 0) put(mesh.node_vel, 3, {props.vx, props.vy, props.vz});
    if (props.id >= 0) {
      const double id = value(props.id);
      if (!is_id_value(id)) refused = true;
      vertex_id[v] = refused ? 0 : static_cast<index_t>(id);
    }
    if (props.origin_face >= 0) {
      const double face = value(props.origin_face);
      if (!is_origin_face_value(face)) refused = true;
      mesh.node_origin_face[v] = refused ? 0 : static_cast<index_t>(face);
      put(mesh.node_origin_bary, 2, {props.origin_u, props.origin_v});
    }
  }
  if (!refused) return true;
  for (std::vector<float>* values :
       {&mesh.node_pos, &vertex_normal, &vertex_uv, &mesh.node_vel, &mesh.node_origin_bary})
    values->clear();
  vertex_id.clear();
  mesh.node_origin_face.clear();
  return false;
}

/// A binary face element of one property, its corner list, whose instances all have the first
/// one's corner count k >= 3 (tear's own faces: k = 3), on OpenMP threads: the corners of instance
/// i at i * k. Every instance's count is checked where that layout puts it, so the layout is the
/// file's. False, with nothing written, for any other file, or where a corner is out of range: the
/// one-by-one loop then reads the element (and fails with its message).
bool read_faces_at_once(const PlyElement& element, const char* data, std::size_t bytes_left, bool big_endian,
                        std::size_t vertex_count, std::vector<index_t>& corner_vertex, std::size_t& stride) {
  const PlyProperty& list = element.properties[0];
  const std::int64_t count = static_cast<std::int64_t>(element.count);
  const std::size_t count_size = size_of(list.count_type), item_size = size_of(list.type);
  if (count == 0 || bytes_left < count_size) return false;
  const double first = decode(data, list.count_type, big_endian);
  if (!(first >= 3 && first <= 255)) return false;
  const std::size_t k = static_cast<std::size_t>(first);
  stride = count_size + k * item_size;
  if (element.count > bytes_left / stride || element.count * k > max_index_count) return false;
  corner_vertex.resize(static_cast<std::size_t>(count) * k);
  bool refused = false;
#pragma omp parallel for schedule(static) reduction(|| : refused) if (count >= parallel_from)
  for (std::int64_t instance = 0; instance < count; ++instance) {
    const char* at = data + static_cast<std::size_t>(instance) * stride;
    if (decode(at, list.count_type, big_endian) != first) {
      refused = true;
      continue;
    }
    for (std::size_t c = 0; c < k; ++c) {
      const double value = decode(at + count_size + c * item_size, list.type, big_endian);
      const bool in_range = is_vertex_value(value, vertex_count);
      refused = refused || !in_range;
      corner_vertex[static_cast<std::size_t>(instance) * k + c] = in_range ? static_cast<index_t>(value) : 0;
    }
  }
  if (!refused) return true;
  corner_vertex.clear();
  return false;
}

/// What the reader gathers from the file's elements before the faces are made.
struct PlyContent {
  FileMesh out;
  std::vector<float> vertex_normal, vertex_uv;
  // Polygons as written: corners, and (u, v) per corner from a face `texcoord` list when the face
  // has one of the right length.
  std::vector<index_t> corner_vertex;
  std::vector<float> corner_texcoord;
  std::vector<std::uint8_t> polygon_has_texcoord;
  std::vector<std::size_t> polygon_offset = {0};
};

/// The file's first `vertex` element, whose properties must be usable: x, y and z, none a list,
/// `id` and `origin_face` of integer types, and at most 2^31 instances.
const PlyElement& vertex_element_of(const std::string& path, const PlyHeader& header, Properties& props) {
  const PlyElement* vertex_element = nullptr;
  for (const PlyElement& element : header.elements) {
    if (element.name == "vertex" && !vertex_element) vertex_element = &element;
  }
  if (!vertex_element) throw input_error(path, "PLY file has no 'vertex' element");
  props = vertex_properties(*vertex_element);
  if (props.x < 0 || props.y < 0 || props.z < 0) throw input_error(path, "PLY vertices have no x, y and z");
  if (vertex_element->count > max_index_count) throw input_error(path, "too large: more than 2^31 vertices");
  for (int property : {props.x, props.y, props.z, props.nx, props.ny, props.nz, props.u, props.v, props.id, props.vx,
                       props.vy, props.vz, props.origin_face, props.origin_u, props.origin_v}) {
    if (property >= 0 && vertex_element->properties[property].list) {
      throw input_error(path, "PLY vertex property '" + vertex_element->properties[property].name + "' is a list");
    }
  }
  for (int property : {props.id, props.origin_face}) {
    if (property >= 0 && !is_integer(vertex_element->properties[property].type)) {
      throw input_error(
          path, "PLY vertex property '" + vertex_element->properties[property].name + "' must be of an integer type");
    }
  }
  return *vertex_element;
}

/// The properties of a face element (its corner list and `texcoord`) or of an edge element (its two
/// vertices) that the reader takes; -1 for those it has not, or cannot take.
struct ElementColumns {
  int indices = -1, texcoord = -1, vertex1 = -1, vertex2 = -1;
};

ElementColumns element_columns(const std::string& path, const PlyElement& element, bool is_face, bool is_edge) {
  ElementColumns columns;
  if (is_face) {
    int& indices = columns.indices;
    indices = element.find("vertex_indices");
    if (indices < 0) indices = element.find("vertex_index");
    if (indices >= 0 && (!element.properties[indices].list || !is_integer(element.properties[indices].type))) {
      throw input_error(path,
                        "PLY face property '" + element.properties[indices].name + "' must be a list of integers");
    }
    columns.texcoord = element.find("texcoord");
    if (columns.texcoord >= 0 && !element.properties[columns.texcoord].list) columns.texcoord = -1;
  }
  if (is_edge) {
    columns.vertex1 = element.find("vertex1"), columns.vertex2 = element.find("vertex2");
    for (int property : {columns.vertex1, columns.vertex2}) {
      if (property >= 0 && (element.properties[property].list || !is_integer(element.properties[property].type))) {
        columns.vertex1 = columns.vertex2 = -1;
      }
    }
  }
  return columns;
}

void reserve_vertices(const Properties& props, std::size_t vertex_count, PlyContent& content) {
  Mesh& mesh = content.out.mesh;
  mesh.node_pos.reserve(3 * vertex_count);
  if (props.nx >= 0) content.vertex_normal.reserve(3 * vertex_count);
  if (props.u >= 0) content.vertex_uv.reserve(2 * vertex_count);
  if (props.id >= 0) content.out.vertex_id.reserve(vertex_count);
  if (props.vx >= 0) mesh.node_vel.reserve(3 * vertex_count);
  if (props.origin_face >= 0) {
    mesh.node_origin_face.reserve(vertex_count);
    mesh.node_origin_bary.reserve(2 * vertex_count);
  }
}

/// A corner's vertex, which must be one of the file's.
index_t vertex_index(const PlyReader& reader, double value, std::size_t vertex_count) {
  if (!is_vertex_value(value, vertex_count)) {
    throw reader.fail("uses vertex " + std::to_string(static_cast<std::int64_t>(value)) +
                      ", out of range (the file has " + std::to_string(vertex_count) + " vertices)");
  }
  return static_cast<index_t>(value);
}

/// One instance's values, in `values` (lists left out), and the items of its corner list and its
/// texcoord list in `polygon` and `polygon_texcoord`. `fixed`: the element has no list and the file
/// holds all of it, so the values are at `stride` bytes per instance.
void read_instance(PlyReader& reader, const PlyElement& element, const ElementColumns& columns, bool fixed,
                   std::size_t stride, std::size_t vertex_count, std::vector<double>& values,
                   std::vector<index_t>& polygon, std::vector<float>& polygon_texcoord) {
  if (fixed) {
    const char* at = reader.take(stride);
    for (std::size_t i = 0; i < element.properties.size(); ++i) {
      values[i] = decode(at, element.properties[i].type, reader.big_endian());
      at += size_of(element.properties[i].type);
    }
    return;
  }
  for (std::size_t i = 0; i < element.properties.size(); ++i) {
    const PlyProperty& property = element.properties[i];
    if (!property.list) {
      values[i] = reader.next(property.type, property.name);
      continue;
    }
    const std::uint64_t items = reader.next_count(property);
    // A binary list whose items are all there is read without checking each item's bytes.
    const std::size_t item_size = size_of(property.type);
    const char* list_at = !reader.ascii() && items <= reader.bytes_left() / item_size
                              ? reader.take(static_cast<std::size_t>(items) * item_size)
                              : nullptr;
    for (std::uint64_t item = 0; item < items; ++item) {
      const double value = list_at ? decode(list_at + item * item_size, property.type, reader.big_endian())
                                   : reader.next(property.type, property.name);
      if (static_cast<int>(i) == columns.indices) {
        polygon.push_back(vertex_index(reader, value, vertex_count));
      } else if (static_cast<int>(i) == columns.texcoord) {
        if (!std::isfinite(value)) throw reader.fail("non-finite value in 'texcoord'");
        polygon_texcoord.push_back(static_cast<float>(value));
      }
    }
  }
}

/// A vertex instance's values appended to the arrays its properties fill.
void store_vertex(const PlyReader& reader, const PlyElement& element, const Properties& props,
                  const std::vector<double>& values, PlyContent& content) {
  Mesh& mesh = content.out.mesh;
  auto finite = [&](int property) {
    const double value = values[property];
    if (!is_float_value(value)) throw reader.fail("non-finite value in '" + element.properties[property].name + "'");
    return static_cast<float>(value);
  };
  mesh.node_pos.insert(mesh.node_pos.end(), {finite(props.x), finite(props.y), finite(props.z)});
  if (props.nx >= 0)
    content.vertex_normal.insert(content.vertex_normal.end(), {finite(props.nx), finite(props.ny), finite(props.nz)});
  if (props.u >= 0) content.vertex_uv.insert(content.vertex_uv.end(), {finite(props.u), finite(props.v)});
  if (props.vx >= 0) mesh.node_vel.insert(mesh.node_vel.end(), {finite(props.vx), finite(props.vy), finite(props.vz)});
  if (props.id >= 0) {
    const double id = values[props.id];
    if (!is_id_value(id)) throw reader.fail("'id' is negative or too large");
    content.out.vertex_id.push_back(static_cast<index_t>(id));
  }
  if (props.origin_face >= 0) {
    const double face = values[props.origin_face];
    if (!is_origin_face_value(face)) throw reader.fail("'origin_face' is out of range");
    mesh.node_origin_face.push_back(static_cast<index_t>(face));
    mesh.node_origin_bary.insert(mesh.node_origin_bary.end(), {finite(props.origin_u), finite(props.origin_v)});
  }
}

/// A face instance's polygon appended, with its texcoords when it has one per corner.
void store_polygon(const std::string& path, const std::vector<index_t>& polygon,
                   const std::vector<float>& polygon_texcoord, PlyContent& content) {
  // Faces of fewer than 3 corners are no surface; they are dropped like points and lines.
  if (polygon.size() < 3) return;
  content.corner_vertex.insert(content.corner_vertex.end(), polygon.begin(), polygon.end());
  const bool has_texcoord = polygon_texcoord.size() == 2 * polygon.size();
  content.polygon_has_texcoord.push_back(has_texcoord);
  if (has_texcoord) {
    content.corner_texcoord.insert(content.corner_texcoord.end(), polygon_texcoord.begin(), polygon_texcoord.end());
  } else {
    content.corner_texcoord.insert(content.corner_texcoord.end(), 2 * polygon.size(), 0.0f);
  }
  content.polygon_offset.push_back(content.corner_vertex.size());
  if (content.corner_vertex.size() > max_index_count) throw input_error(path, "too large: more than 2^31 face corners");
}

/// Binary vertices and faces as tear writes them: all instances at once, on OpenMP threads. True
/// when the element was read so (the reader then stands after it).
bool read_element_at_once(PlyReader& reader, const PlyElement& element, bool is_vertex, bool is_face,
                          const ElementColumns& columns, bool fixed, std::size_t stride, const Properties& props,
                          std::size_t vertex_count, PlyContent& content) {
  if (fixed && is_vertex && element.count > 0 &&
      read_vertices_at_once(element, reader.take(0), stride, reader.big_endian(), props, content.out.mesh,
                            content.out.vertex_id, content.vertex_normal, content.vertex_uv)) {
    reader.take(static_cast<std::size_t>(element.count) * stride);
    return true;
  }
  std::size_t face_stride = 0;
  if (is_face && columns.indices == 0 && element.properties.size() == 1 && !reader.ascii() &&
      content.corner_vertex.empty() &&
      read_faces_at_once(element, reader.take(0), reader.bytes_left(), reader.big_endian(), vertex_count,
                         content.corner_vertex, face_stride)) {
    reader.take(static_cast<std::size_t>(element.count) * face_stride);
    const std::size_t k = content.corner_vertex.size() / static_cast<std::size_t>(element.count);
    content.polygon_offset.resize(static_cast<std::size_t>(element.count) + 1);
    for (std::size_t p = 0; p < content.polygon_offset.size(); ++p) content.polygon_offset[p] = p * k;
    content.polygon_has_texcoord.assign(static_cast<std::size_t>(element.count), 0);
    content.corner_texcoord.assign(2 * content.corner_vertex.size(), 0.0f);
    return true;
  }
  return false;
}

/// One element's instances: vertices, faces and edges kept, any other element read past.
void read_element(const std::string& path, PlyReader& reader, const PlyElement& element, bool is_vertex,
                  const Properties& props, std::size_t vertex_count, PlyContent& content) {
  const bool is_face = element.name == "face", is_edge = element.name == "edge";
  const ElementColumns columns = element_columns(path, element, is_face, is_edge);
  if (is_vertex) reserve_vertices(props, vertex_count, content);
  std::vector<double> values(element.properties.size());
  // A binary element without lists has one layout for every instance: when the file holds all
  // of them, their values are taken at fixed offsets, without checking each value's bytes.
  std::size_t stride = 0;
  bool fixed = !reader.ascii();
  for (const PlyProperty& property : element.properties) {
    fixed = fixed && !property.list;
    stride += size_of(property.type);
  }
  fixed = fixed && element.count <= reader.bytes_left() / stride;
  if (read_element_at_once(reader, element, is_vertex, is_face, columns, fixed, stride, props, vertex_count, content))
    return;
  std::vector<index_t> polygon;
  std::vector<float> polygon_texcoord;
  for (std::uint64_t instance = 0; instance < element.count; ++instance) {
    reader.at(element, instance);
    polygon.clear();
    polygon_texcoord.clear();
    read_instance(reader, element, columns, fixed, stride, vertex_count, values, polygon, polygon_texcoord);
    if (is_vertex) {
      store_vertex(reader, element, props, values, content);
    } else if (is_face && columns.indices >= 0) {
      store_polygon(path, polygon, polygon_texcoord, content);
    } else if (is_edge && columns.vertex1 >= 0 && columns.vertex2 >= 0) {
      content.out.mesh.torn_edge_nodes.insert(content.out.mesh.torn_edge_nodes.end(),
                                              {vertex_index(reader, values[columns.vertex1], vertex_count),
                                               vertex_index(reader, values[columns.vertex2], vertex_count)});
    }
  }
}

/// The UV of the file's corner c, of polygon p: the face's texcoord where it has them, else its
/// vertex's, else 0.
const float* uv_of(const PlyContent& content, bool face_uv, std::size_t p, std::size_t c) {
  static const float no_uv[2] = {0.0f, 0.0f};
  if (face_uv && content.polygon_has_texcoord[p]) return &content.corner_texcoord[2 * c];
  if (!content.vertex_uv.empty()) return &content.vertex_uv[2 * static_cast<std::size_t>(content.corner_vertex[c])];
  return no_uv;
}

/// Triangles only (each polygon has 3 corners or more, and they add up to 3 each): corner c of the
/// file is corner c of the mesh, filled on OpenMP threads.
void fill_triangles(PlyContent& content, bool face_uv, bool with_uv, bool with_normals) {
  Mesh& mesh = content.out.mesh;
  const std::vector<index_t>& corner_vertex = content.corner_vertex;
  const std::int64_t polygons = static_cast<std::int64_t>(content.polygon_offset.size() - 1);
  mesh.face_nodes = corner_vertex;
  if (with_uv) mesh.corner_uv.resize(2 * corner_vertex.size());
  if (with_normals) mesh.corner_normal.resize(3 * corner_vertex.size());
#pragma omp parallel for schedule(static) if (polygons >= parallel_from)
  for (std::int64_t p = 0; p < polygons; ++p) {
    for (std::size_t c = 3 * static_cast<std::size_t>(p); c < 3 * static_cast<std::size_t>(p) + 3; ++c) {
      const std::size_t v = static_cast<std::size_t>(corner_vertex[c]);
      if (with_uv) {
        const float* uv = uv_of(content, face_uv, static_cast<std::size_t>(p), c);
        mesh.corner_uv[2 * c] = uv[0];
        mesh.corner_uv[2 * c + 1] = uv[1];
      }
      if (with_normals)
        for (int a = 0; a < 3; ++a) mesh.corner_normal[3 * c + a] = content.vertex_normal[3 * v + a];
    }
  }
}

/// Polygons of any corner count, each triangulated (`triangulate_polygon`) in file order.
void triangulate_polygons(const std::string& path, PlyContent& content, bool face_uv, bool with_uv, bool with_normals,
                          std::size_t triangle_corners) {
  Mesh& mesh = content.out.mesh;
  const std::vector<index_t>& corner_vertex = content.corner_vertex;
  const std::vector<float>& vertex_normal = content.vertex_normal;
  mesh.face_nodes.reserve(triangle_corners);
  if (with_uv) mesh.corner_uv.reserve(2 * triangle_corners);
  if (with_normals) mesh.corner_normal.reserve(3 * triangle_corners);
  std::vector<float> polygon_pos;
  std::vector<index_t> triangle;
  for (std::size_t p = 0; p + 1 < content.polygon_offset.size(); ++p) {
    const std::size_t first = content.polygon_offset[p], corner_count = content.polygon_offset[p + 1] - first;
    if (corner_count == 3) {
      triangle = {0, 1, 2};
    } else {
      polygon_pos.clear();
      for (std::size_t k = 0; k < corner_count; ++k) {
        const float* position = &mesh.node_pos[3 * static_cast<std::size_t>(corner_vertex[first + k])];
        polygon_pos.insert(polygon_pos.end(), position, position + 3);
      }
      triangle = triangulate_polygon(polygon_pos.data(), static_cast<index_t>(corner_count));
    }
    for (index_t k : triangle) {
      const std::size_t c = first + static_cast<std::size_t>(k);
      const std::size_t v = static_cast<std::size_t>(corner_vertex[c]);
      mesh.face_nodes.push_back(corner_vertex[c]);
      if (with_uv) {
        const float* uv = uv_of(content, face_uv, p, c);
        mesh.corner_uv.insert(mesh.corner_uv.end(), uv, uv + 2);
      }
      if (with_normals)
        mesh.corner_normal.insert(mesh.corner_normal.end(), &vertex_normal[3 * v], &vertex_normal[3 * v + 3]);
    }
    if (mesh.face_nodes.size() > max_index_count) throw input_error(path, "too large: more than 2^31 face corners");
  }
}

/// The mesh's faces from the file's polygons, with UVs and normals per corner.
void make_faces(const std::string& path, PlyContent& content) {
  const bool face_uv = std::find(content.polygon_has_texcoord.begin(), content.polygon_has_texcoord.end(), 1) !=
                       content.polygon_has_texcoord.end();
  const bool with_uv = face_uv || !content.vertex_uv.empty();
  const bool with_normals = !content.vertex_normal.empty();
  const std::size_t triangle_corners = 3 * (content.corner_vertex.size() - 2 * (content.polygon_offset.size() - 1));
  if (triangle_corners > max_index_count) throw input_error(path, "too large: more than 2^31 face corners");
  const std::int64_t polygons = static_cast<std::int64_t>(content.polygon_offset.size() - 1);
  if (content.corner_vertex.size() == 3 * static_cast<std::size_t>(polygons)) {
    fill_triangles(content, face_uv, with_uv, with_normals);
  } else {
    triangulate_polygons(path, content, face_uv, with_uv, with_normals, triangle_corners);
  }
}

}  // namespace

FileMesh read_ply_file(const std::string& path, const std::string& bytes, const std::string& mesh_name) {
  const PlyHeader header = parse_header(path, bytes);
  check_counts(path, header, bytes.size() - header.data_begin);
  if (!mesh_name.empty()) throw no_mesh_named(path, mesh_name, {});

  Properties props;
  const PlyElement& vertex_element = vertex_element_of(path, header, props);
  const std::size_t vertex_count = static_cast<std::size_t>(vertex_element.count);
  PlyContent content;
  PlyReader reader(path, bytes, header);
  for (const PlyElement& element : header.elements) {
    if (element.properties.empty()) continue;
    read_element(path, reader, element, &element == &vertex_element, props, vertex_count, content);
  }

  // Origins that are all unknown (-1) are no origins at all.
  Mesh& mesh = content.out.mesh;
  if (std::all_of(mesh.node_origin_face.begin(), mesh.node_origin_face.end(), [](index_t f) { return f == none; })) {
    mesh.node_origin_face.clear();
    mesh.node_origin_bary.clear();
  }
  make_faces(path, content);
  return std::move(content.out);
}

}  // namespace tear
