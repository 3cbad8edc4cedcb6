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
#include "tear/error.h"
#include "tear/triangulate_polygon.h"

namespace tear {
namespace {

enum class PlyType { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

bool type_from_name(const std::string& name, PlyType& type) {
  static const struct {
    const char* name;
    PlyType type;
  } names[] = {{"char", PlyType::int8},      {"int8", PlyType::int8},       {"uchar", PlyType::uint8},
               {"uint8", PlyType::uint8},    {"short", PlyType::int16},     {"int16", PlyType::int16},
               {"ushort", PlyType::uint16},  {"uint16", PlyType::uint16},   {"int", PlyType::int32},
               {"int32", PlyType::int32},    {"uint", PlyType::uint32},     {"uint32", PlyType::uint32},
               {"float", PlyType::float32},  {"float32", PlyType::float32}, {"double", PlyType::float64},
               {"float64", PlyType::float64}};
  for (const auto& entry : names) {
    if (name == entry.name) {
      type = entry.type;
      return true;
    }
  }
  return false;
}

std::size_t size_of(PlyType type) {
  switch (type) {
    case PlyType::int8:
    case PlyType::uint8:
      return 1;
    case PlyType::int16:
    case PlyType::uint16:
      return 2;
    case PlyType::int32:
    case PlyType::uint32:
    case PlyType::float32:
      return 4;
    case PlyType::float64:
      return 8;
  }
  return 1;
}

bool is_integer(PlyType type) { return type != PlyType::float32 && type != PlyType::float64; }

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::float32;  ///< the value type, or a list's item type
  bool list = false;
  PlyType count_type = PlyType::uint8;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;

  int find(const char* property) const {
    for (std::size_t i = 0; i < properties.size(); ++i) {
      if (properties[i].name == property) return static_cast<int>(i);
    }
    return -1;
  }
};

enum class PlyFormat { ascii, binary_little_endian, binary_big_endian };

/// Header text quoted in a message: printable ASCII only, and short.
std::string printable(const std::string& text) {
  std::string out;
  for (char c : text.substr(0, 40)) out += (c >= 0x20 && c < 0x7F) ? c : '?';
  return text.size() > 40 ? out + "..." : out;
}

std::vector<std::string> split_words(const std::string& line) {
  std::vector<std::string> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    std::size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
    if (j > i) words.push_back(line.substr(i, j - i));
    i = j;
  }
  return words;
}

struct PlyHeader {
  PlyFormat format = PlyFormat::ascii;
  std::vector<PlyElement> elements;
  std::size_t data_begin = 0;  ///< offset of the first byte after `end_header`'s line
};

PlyHeader parse_header(const std::string& path, const std::string& bytes) {
  auto fail = [&](std::size_t line, const std::string& what) {
    return input_error(path, "PLY header line " + std::to_string(line) + ": " + what);
  };
  PlyHeader header;
  bool have_format = false;
  std::size_t begin = 0, line_number = 0;
  while (true) {
    const std::size_t end = bytes.find('\n', begin);
    if (end == std::string::npos) throw input_error(path, "PLY header has no 'end_header' line");
    std::string line = bytes.substr(begin, end - begin);
    begin = end + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::vector<std::string> words = split_words(line);
    if (line_number == 1) {
      if (words.size() != 1 || words[0] != "ply")
        throw input_error(path, "not a PLY file (the first line is not 'ply')");
      continue;
    }
    if (words.empty()) continue;
    const std::string& keyword = words[0];
    if (keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "end_header") break;
    if (keyword == "format") {
      if (words.size() != 3 || words[2] != "1.0") throw fail(line_number, "expected 'format <type> 1.0'");
      if (words[1] == "ascii") {
        header.format = PlyFormat::ascii;
      } else if (words[1] == "binary_little_endian") {
        header.format = PlyFormat::binary_little_endian;
      } else if (words[1] == "binary_big_endian") {
        header.format = PlyFormat::binary_big_endian;
      } else {
        throw fail(line_number, "unknown format '" + printable(words[1]) + "'");
      }
      have_format = true;
    } else if (keyword == "element") {
      if (words.size() != 3) throw fail(line_number, "expected 'element <name> <count>'");
      PlyElement element;
      element.name = words[1];
      const char* first = words[2].data();
      const char* last = first + words[2].size();
      const auto parsed = std::from_chars(first, last, element.count);
      if (parsed.ec != std::errc() || parsed.ptr != last) {
        throw fail(line_number,
                   "element '" + printable(words[1]) + "' has no count (got '" + printable(words[2]) + "')");
      }
      header.elements.push_back(element);
    } else if (keyword == "property") {
      if (header.elements.empty()) throw fail(line_number, "a property before any element");
      PlyProperty property;
      if (words.size() == 5 && words[1] == "list") {
        property.list = true;
        if (!type_from_name(words[2], property.count_type) || !is_integer(property.count_type)) {
          throw fail(line_number, "a list count must be of an integer type, got '" + printable(words[2]) + "'");
        }
        if (!type_from_name(words[3], property.type))
          throw fail(line_number, "unknown type '" + printable(words[3]) + "'");
        property.name = words[4];
      } else if (words.size() == 3) {
        if (!type_from_name(words[1], property.type))
          throw fail(line_number, "unknown type '" + printable(words[1]) + "'");
        property.name = words[2];
      } else {
        throw fail(line_number, "expected 'property <type> <name>' or 'property list <type> <type> <name>'");
      }
      header.elements.back().properties.push_back(property);
    }
    // Any other line is taken as a comment, as other readers do (old Blender wrote its
    // "Created by" line without the keyword).
  }
  if (!have_format) throw input_error(path, "PLY header has no 'format' line");
  header.data_begin = begin;
  return header;
}

template <typename T>
double load(const unsigned char* raw) {
  T value;
  std::memcpy(&value, raw, sizeof value);
  return static_cast<double>(value);
}

/// A binary value of `type` at `at`, as a double (exact for every PLY type).
double decode(const char* at, PlyType type, bool big_endian) {
  unsigned char raw[8];
  const std::size_t size = size_of(type);
  std::memcpy(raw, at, size);
  if (big_endian) std::reverse(raw, raw + size);
  // In the order of PlyType.
  static constexpr double (*const loaders[])(const unsigned char*) = {
      load<std::int8_t>,  load<std::uint8_t>,  load<std::int16_t>, load<std::uint16_t>,
      load<std::int32_t>, load<std::uint32_t>, load<float>,        load<double>};
  return loaders[static_cast<int>(type)](raw);
}

/// Reads the values of the data section one by one, binary or ASCII, and fails with the element
/// and instance it was reading when the file ends or a value is malformed.
class PlyReader {
 public:
  PlyReader(const std::string& path, const std::string& bytes, const PlyHeader& header)
      : path_(path), p_(bytes.data() + header.data_begin), end_(bytes.data() + bytes.size()), format_(header.format) {}

  void at(const PlyElement& element, std::uint64_t instance) {
    element_ = &element;
    instance_ = instance;
  }

  std::size_t bytes_left() const { return static_cast<std::size_t>(end_ - p_); }
  bool ascii() const { return format_ == PlyFormat::ascii; }

  /// The next value, of `type`, as a double (exact for every PLY type).
  double next(PlyType type, const std::string& property) {
    return ascii() ? next_text(type, property) : next_binary(type, property);
  }

  /// A list's count: a non-negative integer whose items fit in what is left of the file.
  std::uint64_t next_count(const PlyProperty& property) {
    const double count = next(property.count_type, property.name);
    if (count < 0) throw fail("'" + property.name + "' has a negative count");
    const std::uint64_t items = static_cast<std::uint64_t>(count);
    // Each item needs its bytes, or in ASCII at least one character and a separator.
    const std::uint64_t least = ascii() ? 1 : size_of(property.type);
    if (items > bytes_left() / least + 1)
      throw fail("'" + property.name + "' has " + std::to_string(items) +
                 " items, more than the rest of the file holds");
    return items;
  }

  /// The next `bytes` bytes of a binary file, which the caller has checked are there.
  const char* take(std::size_t bytes) {
    const char* at = p_;
    p_ += bytes;
    return at;
  }
  bool big_endian() const { return format_ == PlyFormat::binary_big_endian; }

  Error fail(const std::string& what) const {
    return input_error(path_, element_->name + " " + std::to_string(instance_) + ": " + what);
  }

 private:
  double next_binary(PlyType type, const std::string& property) {
    const std::size_t size = size_of(type);
    if (bytes_left() < size) throw fail("the file ends in '" + property + "' (truncated)");
    return decode(take(size), type, format_ == PlyFormat::binary_big_endian);
  }

  double next_text(PlyType type, const std::string& property) {
    auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
    while (p_ < end_ && space(*p_)) ++p_;
    const char* first = p_;
    while (p_ < end_ && !space(*p_)) ++p_;
    if (first == p_) throw fail("the file ends before '" + property + "' (truncated)");
    const char* const token = first;
    if (*first == '+') ++first;  // from_chars takes no plus sign
    if (is_integer(type)) {
      std::int64_t value = 0;
      const auto parsed = std::from_chars(first, p_, value);
      if (parsed.ec == std::errc() && parsed.ptr == p_) {
        check_range(type, static_cast<double>(value), property);
        return static_cast<double>(value);
      }
      double wide = 0.0;
      const auto wide_parsed = std::from_chars(first, p_, wide);
      if (wide_parsed.ec != std::errc() || wide_parsed.ptr != p_ || wide != std::floor(wide)) {
        throw fail("'" + property + "' is not an integer: '" + printable(std::string(token, p_)) + "'");
      }
      check_range(type, wide, property);
      return wide;
    }
    // Floats are parsed at their own precision, so a float written with 9 digits reads back exactly.
    if (type == PlyType::float32) {
      float value = 0.0f;
      const auto parsed = std::from_chars(first, p_, value);
      if (parsed.ec == std::errc() && parsed.ptr == p_) return value;
    } else {
      double value = 0.0;
      const auto parsed = std::from_chars(first, p_, value);
      if (parsed.ec == std::errc() && parsed.ptr == p_) return value;
    }
    throw fail("'" + property + "' is not a number: '" + printable(std::string(token, p_)) + "'");
  }

  void check_range(PlyType type, double value, const std::string& property) const {
    double low = 0, high = 0;
    switch (type) {
      case PlyType::int8:
        low = -128;
        high = 127;
        break;
      case PlyType::uint8:
        high = 255;
        break;
      case PlyType::int16:
        low = -32768;
        high = 32767;
        break;
      case PlyType::uint16:
        high = 65535;
        break;
      case PlyType::int32:
        low = -2147483648.0;
        high = 2147483647.0;
        break;
      case PlyType::uint32:
        high = 4294967295.0;
        break;
      default:
        return;
    }
    if (value < low || value > high) throw fail("'" + property + "' is out of the range of its type");
  }

  std::string path_;
  const char* p_;
  const char* end_;
  PlyFormat format_;
  const PlyElement* element_ = nullptr;
  std::uint64_t instance_ = 0;
};

/// Every element's instances need at least this many bytes (binary) or values (ASCII); their sum
/// over the file must fit in the data it has, or the counts are lies and nothing is allocated.
void check_counts(const std::string& path, const PlyHeader& header, std::size_t data_bytes) {
  const bool ascii = header.format == PlyFormat::ascii;
  // In ASCII each value takes at least one character and one separator (the last may have none).
  const std::uint64_t available = ascii ? (static_cast<std::uint64_t>(data_bytes) + 1) / 2 : data_bytes;
  std::uint64_t needed = 0;
  for (const PlyElement& element : header.elements) {
    std::uint64_t least = 0;
    for (const PlyProperty& property : element.properties) {
      least += ascii ? 1 : size_of(property.list ? property.count_type : property.type);
    }
    if (least == 0) continue;
    if (element.count > (available - needed) / least) {
      throw input_error(path, "declares " + std::to_string(element.count) + " " + printable(element.name) +
                                  " elements, more than its " + std::to_string(data_bytes) +
                                  " bytes of data can hold (truncated or corrupt)");
    }
    needed += element.count * least;
  }
}

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
bool is_float_value(double value) { return std::isfinite(value) && std::fabs(value) <= std::numeric_limits<float>::max(); }
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
  for (std::vector<float>* values : {&mesh.node_pos, &vertex_normal, &vertex_uv, &mesh.node_vel, &mesh.node_origin_bary})
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

}  // namespace

FileMesh read_ply_file(const std::string& path, const std::string& bytes, const std::string& mesh_name) {
  const PlyHeader header = parse_header(path, bytes);
  check_counts(path, header, bytes.size() - header.data_begin);
  if (!mesh_name.empty()) throw no_mesh_named(path, mesh_name, {});

  const PlyElement* vertex_element = nullptr;
  for (const PlyElement& element : header.elements) {
    if (element.name == "vertex" && !vertex_element) vertex_element = &element;
  }
  if (!vertex_element) throw input_error(path, "PLY file has no 'vertex' element");
  const Properties props = vertex_properties(*vertex_element);
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
  const std::size_t vertex_count = static_cast<std::size_t>(vertex_element->count);

  FileMesh out;
  Mesh& mesh = out.mesh;
  std::vector<float> vertex_normal, vertex_uv;
  // Polygons as written: corners, and (u, v) per corner from a face `texcoord` list when the face
  // has one of the right length.
  std::vector<index_t> corner_vertex;
  std::vector<float> corner_texcoord;
  std::vector<std::uint8_t> polygon_has_texcoord;
  std::vector<std::size_t> polygon_offset = {0};
  std::vector<index_t> polygon;
  std::vector<float> polygon_texcoord;

  PlyReader reader(path, bytes, header);
  for (const PlyElement& element : header.elements) {
    if (element.properties.empty()) continue;
    const bool is_vertex = &element == vertex_element, is_face = element.name == "face",
               is_edge = element.name == "edge";
    int indices = -1, texcoord = -1, vertex1 = -1, vertex2 = -1;
    if (is_face) {
      indices = element.find("vertex_indices");
      if (indices < 0) indices = element.find("vertex_index");
      if (indices >= 0 && (!element.properties[indices].list || !is_integer(element.properties[indices].type))) {
        throw input_error(path,
                          "PLY face property '" + element.properties[indices].name + "' must be a list of integers");
      }
      texcoord = element.find("texcoord");
      if (texcoord >= 0 && !element.properties[texcoord].list) texcoord = -1;
    }
    if (is_edge) {
      vertex1 = element.find("vertex1"), vertex2 = element.find("vertex2");
      for (int property : {vertex1, vertex2}) {
        if (property >= 0 && (element.properties[property].list || !is_integer(element.properties[property].type))) {
          vertex1 = vertex2 = -1;
        }
      }
    }
    if (is_vertex) {
      mesh.node_pos.reserve(3 * vertex_count);
      if (props.nx >= 0) vertex_normal.reserve(3 * vertex_count);
      if (props.u >= 0) vertex_uv.reserve(2 * vertex_count);
      if (props.id >= 0) out.vertex_id.reserve(vertex_count);
      if (props.vx >= 0) mesh.node_vel.reserve(3 * vertex_count);
      if (props.origin_face >= 0) {
        mesh.node_origin_face.reserve(vertex_count);
        mesh.node_origin_bary.reserve(2 * vertex_count);
      }
    }

    auto vertex_index = [&](double value) {
      if (!is_vertex_value(value, vertex_count)) {
        throw reader.fail("uses vertex " + std::to_string(static_cast<std::int64_t>(value)) +
                          ", out of range (the file has " + std::to_string(vertex_count) + " vertices)");
      }
      return static_cast<index_t>(value);
    };
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
    // Binary vertices and faces as tear writes them: all instances at once, on OpenMP threads.
    if (fixed && is_vertex && element.count > 0 &&
        read_vertices_at_once(element, reader.take(0), stride, reader.big_endian(), props, mesh, out.vertex_id,
                              vertex_normal, vertex_uv)) {
      reader.take(static_cast<std::size_t>(element.count) * stride);
      continue;
    }
    std::size_t face_stride = 0;
    if (is_face && indices == 0 && element.properties.size() == 1 && !reader.ascii() && corner_vertex.empty() &&
        read_faces_at_once(element, reader.take(0), reader.bytes_left(), reader.big_endian(), vertex_count,
                           corner_vertex, face_stride)) {
      reader.take(static_cast<std::size_t>(element.count) * face_stride);
      const std::size_t k = corner_vertex.size() / static_cast<std::size_t>(element.count);
      polygon_offset.resize(static_cast<std::size_t>(element.count) + 1);
      for (std::size_t p = 0; p < polygon_offset.size(); ++p) polygon_offset[p] = p * k;
      polygon_has_texcoord.assign(static_cast<std::size_t>(element.count), 0);
      corner_texcoord.assign(2 * corner_vertex.size(), 0.0f);
      continue;
    }
    for (std::uint64_t instance = 0; instance < element.count; ++instance) {
      reader.at(element, instance);
      polygon.clear();
      polygon_texcoord.clear();
      if (fixed) {
        const char* at = reader.take(stride);
        for (std::size_t i = 0; i < element.properties.size(); ++i) {
          values[i] = decode(at, element.properties[i].type, reader.big_endian());
          at += size_of(element.properties[i].type);
        }
      }
      for (std::size_t i = 0; i < element.properties.size() && !fixed; ++i) {
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
          if (static_cast<int>(i) == indices) {
            polygon.push_back(vertex_index(value));
          } else if (static_cast<int>(i) == texcoord) {
            if (!std::isfinite(value)) throw reader.fail("non-finite value in 'texcoord'");
            polygon_texcoord.push_back(static_cast<float>(value));
          }
        }
      }
      if (is_vertex) {
        auto finite = [&](int property) {
          const double value = values[property];
          if (!is_float_value(value))
            throw reader.fail("non-finite value in '" + element.properties[property].name + "'");
          return static_cast<float>(value);
        };
        mesh.node_pos.insert(mesh.node_pos.end(), {finite(props.x), finite(props.y), finite(props.z)});
        if (props.nx >= 0)
          vertex_normal.insert(vertex_normal.end(), {finite(props.nx), finite(props.ny), finite(props.nz)});
        if (props.u >= 0) vertex_uv.insert(vertex_uv.end(), {finite(props.u), finite(props.v)});
        if (props.vx >= 0)
          mesh.node_vel.insert(mesh.node_vel.end(), {finite(props.vx), finite(props.vy), finite(props.vz)});
        if (props.id >= 0) {
          const double id = values[props.id];
          if (!is_id_value(id)) throw reader.fail("'id' is negative or too large");
          out.vertex_id.push_back(static_cast<index_t>(id));
        }
        if (props.origin_face >= 0) {
          const double face = values[props.origin_face];
          if (!is_origin_face_value(face)) throw reader.fail("'origin_face' is out of range");
          mesh.node_origin_face.push_back(static_cast<index_t>(face));
          mesh.node_origin_bary.insert(mesh.node_origin_bary.end(), {finite(props.origin_u), finite(props.origin_v)});
        }
      } else if (is_face && indices >= 0) {
        // Faces of fewer than 3 corners are no surface; they are dropped like points and lines.
        if (polygon.size() < 3) continue;
        corner_vertex.insert(corner_vertex.end(), polygon.begin(), polygon.end());
        const bool has_texcoord = polygon_texcoord.size() == 2 * polygon.size();
        polygon_has_texcoord.push_back(has_texcoord);
        if (has_texcoord) {
          corner_texcoord.insert(corner_texcoord.end(), polygon_texcoord.begin(), polygon_texcoord.end());
        } else {
          corner_texcoord.insert(corner_texcoord.end(), 2 * polygon.size(), 0.0f);
        }
        polygon_offset.push_back(corner_vertex.size());
        if (corner_vertex.size() > max_index_count) throw input_error(path, "too large: more than 2^31 face corners");
      } else if (is_edge && vertex1 >= 0 && vertex2 >= 0) {
        mesh.torn_edge_nodes.insert(mesh.torn_edge_nodes.end(),
                                    {vertex_index(values[vertex1]), vertex_index(values[vertex2])});
      }
    }
  }

  // Origins that are all unknown (-1) are no origins at all.
  if (std::all_of(mesh.node_origin_face.begin(), mesh.node_origin_face.end(), [](index_t f) { return f == none; })) {
    mesh.node_origin_face.clear();
    mesh.node_origin_bary.clear();
  }

  const bool face_uv =
      std::find(polygon_has_texcoord.begin(), polygon_has_texcoord.end(), 1) != polygon_has_texcoord.end();
  const bool with_uv = face_uv || !vertex_uv.empty();
  const bool with_normals = !vertex_normal.empty();
  const std::size_t triangle_corners = 3 * (corner_vertex.size() - 2 * (polygon_offset.size() - 1));
  if (triangle_corners > max_index_count) throw input_error(path, "too large: more than 2^31 face corners");
  // The UV of the file's corner c, of polygon p: the face's texcoord where it has them, else its
  // vertex's, else 0.
  static const float no_uv[2] = {0.0f, 0.0f};
  const auto uv_of = [&](std::size_t p, std::size_t c) -> const float* {
    if (face_uv && polygon_has_texcoord[p]) return &corner_texcoord[2 * c];
    if (!vertex_uv.empty()) return &vertex_uv[2 * static_cast<std::size_t>(corner_vertex[c])];
    return no_uv;
  };
  const std::int64_t polygons = static_cast<std::int64_t>(polygon_offset.size() - 1);
  if (corner_vertex.size() == 3 * static_cast<std::size_t>(polygons)) {
    // Triangles only (each polygon has 3 corners or more, and they add up to 3 each): corner c of
    // the file is corner c of the mesh, filled on OpenMP threads.
    mesh.face_nodes = corner_vertex;
    if (with_uv) mesh.corner_uv.resize(2 * corner_vertex.size());
    if (with_normals) mesh.corner_normal.resize(3 * corner_vertex.size());
#pragma omp parallel for schedule(static) if (polygons >= parallel_from)
    for (std::int64_t p = 0; p < polygons; ++p) {
      for (std::size_t c = 3 * static_cast<std::size_t>(p); c < 3 * static_cast<std::size_t>(p) + 3; ++c) {
        const std::size_t v = static_cast<std::size_t>(corner_vertex[c]);
        if (with_uv) {
          const float* uv = uv_of(static_cast<std::size_t>(p), c);
          mesh.corner_uv[2 * c] = uv[0];
          mesh.corner_uv[2 * c + 1] = uv[1];
        }
        if (with_normals)
          for (int a = 0; a < 3; ++a) mesh.corner_normal[3 * c + a] = vertex_normal[3 * v + a];
      }
    }
    return out;
  }
  mesh.face_nodes.reserve(triangle_corners);
  if (with_uv) mesh.corner_uv.reserve(2 * triangle_corners);
  if (with_normals) mesh.corner_normal.reserve(3 * triangle_corners);
  std::vector<float> polygon_pos;
  std::vector<index_t> triangle;
  for (std::size_t p = 0; p + 1 < polygon_offset.size(); ++p) {
    const std::size_t first = polygon_offset[p], corner_count = polygon_offset[p + 1] - first;
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
        const float* uv = uv_of(p, c);
        mesh.corner_uv.insert(mesh.corner_uv.end(), uv, uv + 2);
      }
      if (with_normals)
        mesh.corner_normal.insert(mesh.corner_normal.end(), &vertex_normal[3 * v], &vertex_normal[3 * v + 3]);
    }
    if (mesh.face_nodes.size() > max_index_count) throw input_error(path, "too large: more than 2^31 face corners");
  }
  return out;
}

}  // namespace tear
