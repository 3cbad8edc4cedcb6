#include "tear/cut_script.h"

#include "cloth/crack_growth.h"
#include "script/json_reader.h"
#include "script/parse_simulation.h"
#include "script/unit_vector.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include "tear/error.h"
#include "tear/input_file.h"

namespace tear {

using nlohmann::json;

const char* to_string(CutSpace space) {
  switch (space) {
    case CutSpace::uv:
      return "uv";
    case CutSpace::rest_xy:
      return "rest-xy";
    case CutSpace::rest_xz:
      return "rest-xz";
    case CutSpace::rest_yz:
      return "rest-yz";
    case CutSpace::world:
      return "world";
  }
  return "?";
}

const char* to_string(CutKind kind) {
  switch (kind) {
    case CutKind::polyline:
      return "polyline";
    case CutKind::blade:
      return "blade";
    case CutKind::plane:
      return "plane";
  }
  return "?";
}

std::array<int, 2> rest_plane_axes(CutSpace space) {
  switch (space) {
    case CutSpace::rest_xz:
      return {0, 2};
    case CutSpace::rest_yz:
      return {1, 2};
    default:
      return {0, 1};
  }
}

std::vector<const Cut*> CutScript::cuts_of_frame(int frame) const {
  std::vector<const Cut*> out;
  for (const Cut& cut : cuts)
    if (cut.frame == frame) out.push_back(&cut);
  return out;
}

namespace {

using namespace json_reading;

// ---- syntax --------------------------------------------------------------------------------------

// Line and column (1-based; the column counts UTF-8 characters) of byte `offset` (0-based).
std::pair<std::size_t, std::size_t> line_and_column(const std::string& text, std::size_t offset) {
  offset = std::min(offset, text.size());
  std::size_t line = 1, line_start = 0;
  for (std::size_t i = 0; i < offset; ++i)
    if (text[i] == '\n') ++line, line_start = i + 1;
  std::size_t column = 1;
  for (std::size_t i = line_start; i < offset; ++i)
    if ((static_cast<unsigned char>(text[i]) & 0xC0) != 0x80) ++column;
  // An editor does not show the byte order mark nlohmann skips.
  if (line == 1 && text.compare(0, 3, "\xEF\xBB\xBF") == 0 && offset >= 3) --column;
  return {line, column};
}

// nlohmann says "[json.exception.parse_error.101] parse error at line 3, column 4: syntax error
// while parsing object - unexpected '}'; expected string literal". Keep what comes after the
// position, reworded as "syntax error: <detail> (while parsing <what>)".
std::string syntax_detail(const std::string& message) {
  std::string rest = message;
  const std::size_t column_at = rest.find(", column ");
  if (column_at != std::string::npos) {
    const std::size_t colon = rest.find(": ", column_at);
    if (colon != std::string::npos) rest = rest.substr(colon + 2);
  }
  const std::string head = "syntax error ";
  if (rest.compare(0, head.size(), head) == 0) {
    rest = rest.substr(head.size());
    const std::size_t dash = rest.find(" - ");
    if (dash != std::string::npos) return "syntax error: " + rest.substr(dash + 3) + " (" + rest.substr(0, dash) + ")";
  }
  return "syntax error: " + rest;
}

// Builds the document as nlohmann's own parser does and follows the key path meanwhile, so that
// errors the parser raises without a position (duplicate keys, numbers that overflow a double) can
// name the key path instead. A SAX handler, not nlohmann's parse callback: with a callback,
// nlohmann (3.11) scans the whole enclosing array for discarded values after each object in it,
// so a script of 100,000 cuts took seconds to parse (quadratic in the cuts).
class PathTracker {
 public:
  PathTracker(const std::string& file, json& result) : file_(file), dom_(result) {}

  bool null() { return value(dom_.null()); }
  bool boolean(bool v) { return value(dom_.boolean(v)); }
  bool number_integer(json::number_integer_t v) { return value(dom_.number_integer(v)); }
  bool number_unsigned(json::number_unsigned_t v) { return value(dom_.number_unsigned(v)); }
  bool number_float(json::number_float_t v, const json::string_t& text) { return value(dom_.number_float(v, text)); }
  bool string(json::string_t& v) { return value(dom_.string(v)); }
  bool binary(json::binary_t& v) { return value(dom_.binary(v)); }
  bool start_object(std::size_t size) {
    levels_.push_back(Level{false, {}, 0, {}});
    return dom_.start_object(size);
  }
  bool key(json::string_t& key) {
    Level& top = levels_.back();
    top.key = key;
    if (!top.keys.insert(top.key).second)
      throw input_error(file_, next_value_path() + ": duplicate key (each key may appear once)");
    return dom_.key(key);
  }
  bool end_object() {
    levels_.pop_back();
    element_done();
    return dom_.end_object();
  }
  bool start_array(std::size_t size) {
    levels_.push_back(Level{true, {}, 0, {}});
    return dom_.start_array(size);
  }
  bool end_array() {
    levels_.pop_back();
    element_done();
    return dom_.end_array();
  }
  template <class Exception>
  bool parse_error(std::size_t position, const std::string& last_token, const Exception& e) {
    return dom_.parse_error(position, last_token, e);  // throws it
  }

  // The key path of the value being parsed now.
  std::string next_value_path() const {
    std::string path;
    for (const Level& level : levels_)
      path = level.is_array ? child_path(path, level.index) : child_path(path, level.key);
    return path;
  }

 private:
  struct Level {
    bool is_array;
    std::string key;    // objects: the key of the member being parsed
    std::size_t index;  // arrays: the index of the element being parsed
    std::set<std::string> keys;
  };
  bool value(bool kept) {
    element_done();
    return kept;
  }
  void element_done() {
    if (!levels_.empty() && levels_.back().is_array) ++levels_.back().index;
  }

  const std::string& file_;
  nlohmann::detail::json_sax_dom_parser<json> dom_;
  std::vector<Level> levels_;
};


json parse_json(const std::string& text, const std::string& file) {
  if (text.size() > max_script_bytes)
    throw input_error(file, "the cut script has " + std::to_string(text.size()) + " bytes, more than the limit of " +
                                std::to_string(max_script_bytes));
  if (json_nesting_depth(text.data(), text.size()) > max_script_depth)
    throw input_error(file, "the cut script nests arrays and objects deeper than " + std::to_string(max_script_depth) +
                                " levels");
  json result;
  PathTracker tracker(file, result);
  try {
    json::sax_parse(text, &tracker);
    return result;
  } catch (const json::parse_error& e) {
    const auto [line, column] = line_and_column(text, e.byte > 0 ? e.byte - 1 : 0);
    throw input_error(file + ":" + std::to_string(line) + ":" + std::to_string(column), syntax_detail(e.what()));
  } catch (const json::out_of_range& e) {
    // 406: a number too large for a double (1e999). JSON has no NaN or infinity; neither has a script.
    std::string token;
    const std::string message = e.what();
    const std::size_t open = message.find('\''), close = message.rfind('\'');
    if (open != std::string::npos && close > open) token = " " + message.substr(open + 1, close - open - 1);
    throw input_error(file, shown_path(tracker.next_value_path()) + ": expected a finite number, got" + token +
                                " (beyond the range of a double)");
  } catch (const json::exception& e) {
    throw input_error(file, std::string("cannot parse: ") + e.what());
  }
}

// ---- schema --------------------------------------------------------------------------------------

class ScriptReader : public JsonReader {
 public:
  using JsonReader::JsonReader;

  int integer(const json& value, const std::string& path, long long lo, long long hi, const std::string& expected) const {
    return static_cast<int>(JsonReader::integer(value, path, lo, hi, expected));
  }

  template <std::size_t N>
  std::vector<std::array<double, N>> polyline(const json& value, const std::string& path) const {
    const std::string shape = N == 2 ? "[u, v]" : "[x, y, z]";
    if (!value.is_array()) fail(path, "expected an array of " + shape + " points, got " + describe(value));
    if (value.size() < 2) fail(path, "expected at least 2 points, got " + std::to_string(value.size()));
    std::vector<std::array<double, N>> points;
    for (std::size_t i = 0; i < value.size(); ++i) points.push_back(point<N>(value[i], child_path(path, i)));
    return points;
  }

  std::array<double, 3> nonzero_vector(const json& value, const std::string& path) const {
    const auto v = point<3>(value, path);
    if (v[0] == 0 && v[1] == 0 && v[2] == 0) fail(path, "expected a non-zero vector, got [0, 0, 0]");
    return v;
  }
};

std::array<double, 3> cross(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

CutSpace parse_space(const ScriptReader& reader, const json& value, const std::string& path) {
  static const std::pair<const char*, CutSpace> spaces[] = {{"uv", CutSpace::uv},
                                                            {"rest-xy", CutSpace::rest_xy},
                                                            {"rest-xz", CutSpace::rest_xz},
                                                            {"rest-yz", CutSpace::rest_yz}};
  const std::string expected = "\"uv\", \"rest-xy\", \"rest-xz\" or \"rest-yz\"";
  if (!value.is_string()) reader.fail(path, "expected one of " + expected + ", got " + describe(value));
  for (const auto& [name, space] : spaces)
    if (value.get_ref<const std::string&>() == name) return space;
  reader.fail(path, "unknown space " + describe(value) + " (expected " + expected + ")");
}

Cut parse_cut(const ScriptReader& reader, const json& value, const std::string& path, int frames) {
  reader.expect_object(value, path, {"frame", "space", "polyline", "blade", "plane"});
  Cut cut;
  cut.key_path = path;
  const std::string frame_range = "an integer in 1.." + std::to_string(frames);
  cut.frame = reader.integer(reader.member(value, path, "frame", frame_range), child_path(path, "frame"), 1, frames,
                             frame_range + " (1..frames)");

  std::vector<std::string> given;
  if (value.contains("space") || value.contains("polyline")) given.push_back("\"polyline\"");
  if (value.contains("blade")) given.push_back("\"blade\"");
  if (value.contains("plane")) given.push_back("\"plane\"");
  if (given.empty())
    reader.fail(path, "expected one of \"polyline\" (with \"space\"), \"blade\" or \"plane\", got none");
  if (given.size() > 1) {
    std::string list = given[0];
    for (std::size_t i = 1; i < given.size(); ++i) list += (i + 1 == given.size() ? " and " : ", ") + given[i];
    reader.fail(path, "expected exactly one of \"polyline\", \"blade\" or \"plane\", got " + list);
  }

  if (value.contains("blade")) {
    const std::string blade_path = child_path(path, "blade");
    const json& blade = value["blade"];
    reader.expect_object(blade, blade_path, {"polyline", "direction"});
    cut.kind = CutKind::blade;
    cut.space = CutSpace::world;
    cut.polyline3 = reader.polyline<3>(reader.member(blade, blade_path, "polyline", "an array of [x, y, z] points"),
                                       child_path(blade_path, "polyline"));
    cut.direction = reader.nonzero_vector(reader.member(blade, blade_path, "direction", "a non-zero [x, y, z] vector"),
                                          child_path(blade_path, "direction"));
    // A segment parallel to the direction sweeps a line, which the neighbouring segments' surfaces
    // already contain: harmless. A blade made only of such segments cuts nothing, which is a mistake.
    // The sine is that of unit vectors, which any finite non-zero vector has (no 1e-320 squared to 0).
    const std::array<double, 3> direction = unit_vector(cut.direction);
    bool sweeps_area = false;
    for (std::size_t i = 0; i + 1 < cut.polyline3.size() && !sweeps_area; ++i) {
      const std::array<double, 3> segment = unit_vector(finite_difference(cut.polyline3[i], cut.polyline3[i + 1]));
      sweeps_area = vector_length(cross(segment, direction)) > blade_parallel_sine;
    }
    if (!sweeps_area)
      reader.fail(blade_path, "every segment of the polyline is parallel to the direction, so the blade has no area");
  } else if (value.contains("plane")) {
    const std::string plane_path = child_path(path, "plane");
    const json& plane = value["plane"];
    reader.expect_object(plane, plane_path, {"point", "normal"});
    cut.kind = CutKind::plane;
    cut.space = CutSpace::world;
    cut.point = reader.point<3>(reader.member(plane, plane_path, "point", "an array of 3 numbers"),
                                child_path(plane_path, "point"));
    cut.normal = reader.nonzero_vector(reader.member(plane, plane_path, "normal", "a non-zero [x, y, z] vector"),
                                       child_path(plane_path, "normal"));
  } else {
    cut.kind = CutKind::polyline;
    cut.space =
        parse_space(reader, reader.member(value, path, "space", "\"uv\", \"rest-xy\", \"rest-xz\" or \"rest-yz\""),
                    child_path(path, "space"));
    const std::string polyline_path = child_path(path, "polyline");
    cut.polyline2 =
        reader.polyline<2>(reader.member(value, path, "polyline", "an array of [u, v] points"), polyline_path);
    const auto& p = cut.polyline2;
    if (std::all_of(p.begin(), p.end(), [&](const std::array<double, 2>& q) { return q == p.front(); }))
      reader.fail(polyline_path, "all points are equal, so the cut has no length");
  }
  return cut;
}

}  // namespace

CutScript parse_cut_script(const std::string& text, const std::string& path_for_messages) {
  const std::string& file = path_for_messages;
  json root = parse_json(text, file);
  const ScriptReader reader(file);
  if (!root.is_object()) reader.fail("", "expected an object, got " + describe(root));

  CutScript script;
  script.path = file;
  // The version comes first: keys a later version adds should be reported as a version mismatch.
  script.version = reader.integer(reader.member(root, "", "version", "1"), "version", 1, 1, "1");
  reader.expect_object(root, "", {"version", "frames", "snap", "cuts", "simulation"});

  const std::string frames_expected = "an integer in 1.." + std::to_string(max_frames);
  script.frames =
      reader.integer(reader.member(root, "", "frames", frames_expected), "frames", 1, max_frames, frames_expected);

  if (root.contains("snap")) {
    script.snap = reader.number(root["snap"], "snap");
    if (!(script.snap >= 0 && script.snap < 0.5))
      reader.fail("snap", "expected a number in [0, 0.5), got " + describe(root["snap"]));
  }

  if (root.contains("cuts")) {
    const json& cuts = root["cuts"];
    if (!cuts.is_array()) reader.fail("cuts", "expected an array of cuts, got " + describe(cuts));
    for (std::size_t i = 0; i < cuts.size(); ++i)
      script.cuts.push_back(parse_cut(reader, cuts[i], child_path("cuts", i), script.frames));
  }

  if (root.contains("simulation")) {
    if (!root["simulation"].is_object())
      reader.fail("simulation", "expected an object, got " + describe(root["simulation"]));
    script.simulation = parse_simulation(root["simulation"], file, script.frames);
    script.simulation->tearing.snap = script.snap;  // a tear's cut points snap as the script's cuts do
  }
  return script;
}

CutScript read_cut_script(const std::string& path) {
  // A regular file within the script's own limit, read at once: a FIFO or /dev/urandom as the
  // script is refused instead of blocking or growing without end.
  return parse_cut_script(read_input_file(path, "the cut script", std::min(max_input_bytes(), max_script_bytes)),
                          path);
}

void check_script_against_mesh(const CutScript& script, const Mesh& mesh, const std::string& mesh_path) {
  // Rest-shape bounding box, for the projection check below.
  std::array<double, 3> lo{}, hi{};
  const index_t node_count = mesh.node_count();
  for (index_t n = 0; n < node_count; ++n)
    for (int a = 0; a < 3; ++a) {
      const double x = mesh.node_pos[3 * n + a];
      lo[a] = n == 0 ? x : std::min(lo[a], x);
      hi[a] = n == 0 ? x : std::max(hi[a], x);
    }
  const std::array<double, 3> extent{hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
  const double diagonal = vector_length(extent);
  // Relative, so that the check means the same in millimetres and in metres.
  constexpr double flat_fraction = 1e-9;

  if (script.simulation && script.simulation->tearing.enabled()) {
    // The grain and the painted strength are laid out in UV space.
    const TearingOptions& tearing = script.simulation->tearing;
    for (const char* key : {"weave", "strength_map"}) {
      const bool given = std::string(key) == "weave" ? tearing.has_weave : tearing.strength_map != nullptr;
      if (given && !mesh.has_uv())
        throw input_error(script.path, std::string("simulation.tearing.") + key +
                                           ": needs a mesh with UVs (it is laid out in UV space), and " + mesh_path +
                                           " has none");
    }
    // Every face's limit over 1 (the map's value times the rest), or the cloth tears at rest.
    if (tearing.strength_map)
      face_strength_field(mesh.node_rest.empty() ? mesh.node_pos : mesh.node_rest, mesh.face_nodes, mesh.corner_uv,
                          tearing, script.path);
  }

  for (const Cut& cut : script.cuts) {
    if (cut.kind != CutKind::polyline) continue;
    if (cut.space == CutSpace::uv) {
      if (!mesh.has_uv())
        throw input_error(script.path, cut.key_path + ": a \"uv\" cut needs a mesh with UVs, and " + mesh_path +
                                           " has none (use a \"rest-xy\", \"rest-xz\" or \"rest-yz\" space)");
      continue;
    }
    if (node_count == 0) continue;
    for (int axis : rest_plane_axes(cut.space)) {
      if (extent[axis] > flat_fraction * diagonal) continue;
      throw input_error(script.path, cut.key_path + ": \"" + to_string(cut.space) + "\" projects the rest shape of " +
                                         mesh_path + " onto a line or a point (it has no extent along " + "xyz"[axis] +
                                         "); use the plane the cloth lies in");
    }
  }
}

}  // namespace tear
