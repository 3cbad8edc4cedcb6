#include "script/parse_simulation.h"

#include <cmath>
#include <limits>
#include <sstream>

#include <filesystem>

#include "io/image/read_strength_map.h"
#include "script/json_reader.h"
#include "script/unit_vector.h"
#include "tear/error.h"
#include "tear/frame_path.h"
#include "tear/input_file.h"
#include "tear/read_mesh.h"

namespace tear {

namespace {

using namespace json_reading;
using Reader = JsonReader;
namespace limits = simulation_limits;

/// A bound as a message writes it: 100000, 0.1, 1e+09.
std::string shown(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

/// An array of 3 finite numbers each within [-bound, bound].
std::array<double, 3> bounded_point(const Reader& reader, const json& value, const std::string& path, double bound,
                                    const std::string& what) {
  const auto p = reader.point<3>(value, path);
  for (int a = 0; a < 3; ++a)
    if (!(std::abs(p[a]) <= bound))
      reader.fail(child_path(path, a), "expected a number in [-" + shown(bound) + ", " + shown(bound) + "] (" + what +
                                           "), got " + describe(value[a]));
  return p;
}

/// `keys`: a non-empty array of {"frame": F, "offset": [x, y, z]}, frames strictly increasing; with
/// `turns` (a mesh collider's keys) each may also have "rotation": [ax, ay, az, degrees].
std::vector<Key> parse_keys(const Reader& reader, const json& value, const std::string& path, bool turns = false) {
  if (!value.is_array() || value.empty())
    reader.fail(path,
                "expected a non-empty array of keys {\"frame\": F, \"offset\": [x, y, z]}, got " + describe(value));
  const std::string frame_range = "an integer in 0.." + std::to_string(limits::max_key_frame);
  std::vector<Key> keys;
  for (std::size_t i = 0; i < value.size(); ++i) {
    const std::string key_path = child_path(path, i);
    const json& item = value[i];
    if (turns)
      reader.expect_object(item, key_path, {"frame", "offset", "rotation"});
    else
      reader.expect_object(item, key_path, {"frame", "offset"});
    Key key;
    const std::string frame_path = child_path(key_path, "frame");
    key.frame = static_cast<int>(reader.integer(reader.member(item, key_path, "frame", frame_range), frame_path, 0,
                                                limits::max_key_frame, frame_range));
    if (!keys.empty() && key.frame <= keys.back().frame)
      reader.fail(frame_path, "expected a frame after the previous key's (" + std::to_string(keys.back().frame) +
                                  "), got " + std::to_string(key.frame));
    key.offset = bounded_point(reader, reader.member(item, key_path, "offset", "an array of 3 numbers"),
                               child_path(key_path, "offset"), limits::max_key_offset, "metres");
    if (turns && item.contains("rotation")) {
      const std::string rotation_path = child_path(key_path, "rotation");
      const std::string expected = "[ax, ay, az, degrees]: a non-zero axis and an angle in [-1e6, 1e6] degrees";
      const json& r = item["rotation"];
      if (!r.is_array() || r.size() != 4) reader.fail(rotation_path, "expected " + expected + ", got " + describe(r));
      const auto axis = reader.point<3>(json::array({r[0], r[1], r[2]}), rotation_path);
      key.axis = unit_vector(axis);
      if (key.axis == std::array<double, 3>{0, 0, 0})
        reader.fail(rotation_path, "expected " + expected + ", got an axis of length 0");
      key.degrees = reader.number(r[3], child_path(rotation_path, 3), "an angle in [-1e6, 1e6] degrees",
                                  [](double x) { return std::abs(x) <= 1e6; });
    }
    keys.push_back(key);
  }
  return keys;
}

/// The keys of a pin or collider object, if it has any; `value` has one other key, its kind.
std::vector<Key> parse_optional_keys(const Reader& reader, const json& value, const std::string& path,
                                     bool turns = false) {
  if (!value.contains("keys")) return {};
  return parse_keys(reader, value["keys"], child_path(path, "keys"), turns);
}

/// Members of a pin or collider other than `keys` (and a mesh collider's `pivot`).
std::size_t kind_count(const json& value) {
  return value.size() - (value.contains("keys") ? 1 : 0) - (value.contains("pivot") ? 1 : 0);
}

/// A mesh collider's file, or one file per frame where its name has a frame placeholder
/// ("body.####.obj": the body at the end of each frame; `docs/simulation.md`, *Mesh colliders*). A
/// path relative to the script's folder, confined to it as a glTF's files are; read with the mesh
/// reader, every file of a sequence of one topology. `frames`: the script's frames, which a
/// sequence must cover (frame 0, the start, is optional: without it frame 1's file stands there).
std::shared_ptr<const ColliderMesh> read_collider_mesh(const Reader& reader, const json& value, const std::string& path,
                                                       int frames) {
  if (!value.is_string()) reader.fail(path, "expected the path of a mesh file, got " + describe(value));
  const std::string& name = value.get_ref<const std::string&>();
  const std::string folder = std::filesystem::path(reader.file()).parent_path().string();
  const std::string rule = "a relative path to a mesh in the script's folder or below";
  const auto confined = [&](const std::string& file_name) {
    std::string file;
    switch (confine_file(folder, file_name, file)) {
      case Confined::not_relative:
        reader.fail(path, "expected " + rule + ", got \"" + file_name + "\"");
      case Confined::goes_up:
        reader.fail(path, "\"" + file_name + "\" goes up with '..' (expected " + rule + ")");
      case Confined::not_a_file_inside:
        reader.fail(path, "\"" + file_name + "\" is not a regular file in the script's folder or below");
      case Confined::ok:
        break;
    }
    return file;
  };
  const auto read = [&](const std::string& file) {
    try {
      Mesh mesh = read_mesh(file);
      if (mesh.face_count() > limits::max_collider_faces)
        reader.fail(path, file + " has " + std::to_string(mesh.face_count()) + " faces, more than " +
                              std::to_string(limits::max_collider_faces));
      return mesh;
    } catch (const Error& e) {
      if (e.kind() != ErrorKind::input) throw;
      reader.fail(path, std::string("the collider's mesh cannot be read: ") + e.what());
    }
  };
  auto collider = std::make_shared<ColliderMesh>();
  collider->file = name;
  const FramePattern pattern(name);
  if (!pattern.has_frame_number()) {
    Mesh mesh = read(confined(name));
    collider->face_nodes = std::move(mesh.face_nodes);
    collider->frames.push_back(std::move(mesh.node_pos));
    return collider;
  }
  // A sequence: frame 0 if it is there, then every frame the script steps.
  if (frames < 1) frames = 1;
  if (frames + 1 > limits::max_collider_sequence_files)
    reader.fail(path, "a sequence of more than " + std::to_string(limits::max_collider_sequence_files) + " files");
  std::string file;
  const std::string first = pattern.path(0);
  collider->first_frame = confine_file(folder, first, file) == Confined::ok ? 0 : 1;
  for (int f = collider->first_frame; f <= frames; ++f) {
    Mesh mesh = read(confined(pattern.path(f)));
    if (collider->frames.empty()) {
      collider->face_nodes = std::move(mesh.face_nodes);
    } else if (mesh.face_nodes != collider->face_nodes || mesh.node_pos.size() != collider->frames[0].size()) {
      reader.fail(path, pattern.path(f) + " does not have the faces of " + pattern.path(collider->first_frame) +
                            " (a sequence keeps one topology: the same vertices and faces in every file)");
    }
    collider->frames.push_back(std::move(mesh.node_pos));
  }
  return collider;
}

Pin parse_pin(const Reader& reader, const json& value, const std::string& path) {
  reader.expect_object(value, path, {"box", "nodes", "keys"});
  if (kind_count(value) != 1) reader.fail(path, "expected exactly one of \"box\" or \"nodes\", got " + describe(value));
  Pin pin;
  pin.key_path = path;
  if (value.contains("box")) {
    const std::string box_path = child_path(path, "box");
    const json& box = value["box"];
    reader.expect_object(box, box_path, {"min", "max"});
    pin.kind = Pin::Kind::box;
    pin.min =
        reader.point<3>(reader.member(box, box_path, "min", "an array of 3 numbers"), child_path(box_path, "min"));
    pin.max =
        reader.point<3>(reader.member(box, box_path, "max", "an array of 3 numbers"), child_path(box_path, "max"));
    for (int a = 0; a < 3; ++a)
      if (pin.max[a] < pin.min[a])
        reader.fail(child_path(child_path(box_path, "max"), a), "expected a number >= min[" + std::to_string(a) +
                                                                    "] (" + json(pin.min[a]).dump() + "), got " +
                                                                    json(pin.max[a]).dump());
  } else {
    const std::string nodes_path = child_path(path, "nodes");
    const json& nodes = value["nodes"];
    if (!nodes.is_array()) reader.fail(nodes_path, "expected an array of node indices, got " + describe(nodes));
    pin.kind = Pin::Kind::nodes;
    for (std::size_t i = 0; i < nodes.size(); ++i)
      pin.nodes.push_back(
          static_cast<index_t>(reader.integer(nodes[i], child_path(nodes_path, i), 0,
                                              std::numeric_limits<index_t>::max(), "a node index (an integer >= 0)")));
  }
  pin.keys = parse_optional_keys(reader, value, path);
  return pin;
}

Collider parse_collider(const Reader& reader, const json& value, const std::string& path, int frames) {
  reader.expect_object(value, path, {"plane", "sphere", "mesh", "pivot", "keys"});
  if (kind_count(value) != 1)
    reader.fail(path, "expected exactly one of \"plane\", \"sphere\" or \"mesh\", got " + describe(value));
  Collider collider;
  collider.key_path = path;
  const double extent = limits::max_collider_extent;
  if (value.contains("pivot") && !value.contains("mesh"))
    reader.fail(child_path(path, "pivot"), "a pivot is for a mesh collider's rotation only");
  if (value.contains("mesh")) {
    collider.kind = Collider::Kind::mesh;
    collider.mesh = read_collider_mesh(reader, value["mesh"], child_path(path, "mesh"), frames);
    if (value.contains("pivot"))
      collider.pivot = bounded_point(reader, value["pivot"], child_path(path, "pivot"), extent, "metres");
    collider.keys = parse_optional_keys(reader, value, path, true);
    return collider;
  }
  if (value.contains("plane")) {
    const std::string plane_path = child_path(path, "plane");
    const json& plane = value["plane"];
    reader.expect_object(plane, plane_path, {"point", "normal"});
    collider.kind = Collider::Kind::plane;
    collider.point = bounded_point(reader, reader.member(plane, plane_path, "point", "an array of 3 numbers"),
                                   child_path(plane_path, "point"), extent, "metres");
    const auto n = reader.point<3>(reader.member(plane, plane_path, "normal", "a non-zero [x, y, z] vector"),
                                   child_path(plane_path, "normal"));
    collider.normal = unit_vector(n);
    if (collider.normal == std::array<double, 3>{0, 0, 0})
      reader.fail(child_path(plane_path, "normal"), "expected a non-zero [x, y, z] vector, got [0, 0, 0]");
  } else {
    const std::string sphere_path = child_path(path, "sphere");
    const json& sphere = value["sphere"];
    reader.expect_object(sphere, sphere_path, {"center", "radius"});
    collider.kind = Collider::Kind::sphere;
    collider.point = bounded_point(reader, reader.member(sphere, sphere_path, "center", "an array of 3 numbers"),
                                   child_path(sphere_path, "center"), extent, "metres");
    collider.radius =
        reader.number(reader.member(sphere, sphere_path, "radius", "a number in (0, " + shown(extent) + "]"),
                      child_path(sphere_path, "radius"), "a number in (0, " + shown(extent) + "] (metres)",
                      [&](double x) { return x > 0 && x <= extent; });
  }
  collider.keys = parse_optional_keys(reader, value, path);
  return collider;
}

/// A finite number in (lo, hi] with its unit, or the key's default when absent.
double optional_number(const Reader& reader, const json& object, const std::string& path, const std::string& key,
                       double lo, double hi, const std::string& unit, double fallback, bool lo_open = true) {
  if (!object.contains(key)) return fallback;
  const std::string expected =
      std::string("a number in ") + (lo_open ? "(" : "[") + shown(lo) + ", " + shown(hi) + "] (" + unit + ")";
  return reader.number(object[key], child_path(path, key), expected,
                       [&](double x) { return (lo_open ? x > lo : x >= lo) && x <= hi; });
}

/// `tearing.weave`: {"warp": [du, dv], "weft_strength": k}.
Weave parse_weave(const Reader& reader, const json& value, const std::string& path) {
  reader.expect_object(value, path, {"warp", "weft_strength"});
  Weave weave;
  if (value.contains("warp")) {
    const auto w = reader.point<2>(value["warp"], child_path(path, "warp"));
    const double length = std::hypot(w[0], w[1]);
    if (!(length > 1e-9) || !(length < 1e9))
      reader.fail(child_path(path, "warp"),
                  "expected a non-zero direction [du, dv] in UV space, got " + describe(value["warp"]));
    weave.warp = {w[0] / length, w[1] / length};
  }
  weave.weft_strength =
      optional_number(reader, value, path, "weft_strength", 0.01, 100, "times the warp's limit", 1.0, false);
  return weave;
}

/// `tearing.strength_map`: "maps/strength.png", a path relative to the script's folder, confined to
/// it as a glTF's files are to the glTF's (docs/io.md, *Files a file names*).
std::shared_ptr<const StrengthMap> parse_strength_map(const Reader& reader, const json& value,
                                                      const std::string& path) {
  if (!value.is_string()) reader.fail(path, "expected the path of a greyscale image, got " + describe(value));
  const std::string& name = value.get_ref<const std::string&>();
  const std::string folder = std::filesystem::path(reader.file()).parent_path().string();
  const std::string rule = "a relative path to an image in the script's folder or below";
  std::string file;
  switch (confine_file(folder, name, file)) {
    case Confined::not_relative:
      reader.fail(path, "expected " + rule + ", got " + describe(value));
    case Confined::goes_up:
      reader.fail(path, describe(value) + " goes up with '..' (expected " + rule + ")");
    case Confined::not_a_file_inside:
      reader.fail(path, describe(value) + " is not a regular file in the script's folder or below");
    case Confined::ok:
      break;
  }
  return std::make_shared<const StrengthMap>(read_strength_map(file, name, reader.file(), path));
}

/// `tearing`: {"stretch": S, ...}, S required (docs/simulation.md, *Tearing*).
TearingOptions parse_tearing(const Reader& reader, const json& value, const std::string& path) {
  reader.expect_object(value, path,
                       {"stretch", "start", "radius", "step", "min_piece", "max_faces_per_step", "max_faces", "weave",
                        "seam_strength", "variation", "seed", "strength_map", "strain_rate_limit"});
  TearingOptions tearing;
  const std::string stretch_range = "a number in (1, " + shown(limits::max_tear_stretch) + "] (stretch ratio)";
  tearing.stretch = reader.number(reader.member(value, path, "stretch", stretch_range), child_path(path, "stretch"),
                                  stretch_range, [](double x) { return x > 1 && x <= limits::max_tear_stretch; });
  tearing.start = optional_number(reader, value, path, "start", 1, limits::max_tear_stretch, "stretch ratio", 0);
  tearing.radius = optional_number(reader, value, path, "radius", 0, 1e4, "metres", tearing.radius);
  tearing.step = optional_number(reader, value, path, "step", 0, 1e4, "metres", 0);
  tearing.min_piece = optional_number(reader, value, path, "min_piece", 0, 1e8, "square metres", -1, false);
  if (value.contains("max_faces_per_step"))
    tearing.max_faces_per_step = static_cast<int>(reader.integer(
        value["max_faces_per_step"], child_path(path, "max_faces_per_step"), 1, limits::max_tear_faces_per_step,
        "an integer in 1.." + std::to_string(limits::max_tear_faces_per_step) + " (crack advances per substep)"));
  if (value.contains("max_faces"))
    tearing.max_faces =
        reader.integer(value["max_faces"], child_path(path, "max_faces"), 1, limits::max_tear_faces,
                       "an integer in 1.." + std::to_string(limits::max_tear_faces) + " (faces the cloth may tear to)");
  if (value.contains("weave")) {
    tearing.has_weave = true;
    tearing.weave = parse_weave(reader, value["weave"], child_path(path, "weave"));
  }
  tearing.seam_strength =
      optional_number(reader, value, path, "seam_strength", 0.01, 100, "times the limit", 1.0, false);
  tearing.variation = optional_number(reader, value, path, "variation", 0, 0.9, "relative amplitude", 0, false);
  // A limit at or under 1 tears the cloth at rest: each factor must leave the limit above 1.
  const auto above_one = [&](const std::string& key, double factor, const std::string& what) {
    if (!(tearing.stretch * factor > 1))
      reader.fail(child_path(path, key), what + " times stretch (" + shown(tearing.stretch) +
                                             ") must be over 1, or the "
                                             "cloth tears at rest; got " +
                                             shown(tearing.stretch * factor));
  };
  above_one("seam_strength", tearing.seam_strength, "seam_strength (" + shown(tearing.seam_strength) + ")");
  if (tearing.has_weave)
    above_one("weave", tearing.weave.weft_strength, "weave.weft_strength (" + shown(tearing.weave.weft_strength) + ")");
  above_one("variation", 1 - tearing.variation, "1 - variation (" + shown(1 - tearing.variation) + ")");
  if (value.contains("seed"))
    tearing.seed = static_cast<std::uint32_t>(
        reader.integer(value["seed"], child_path(path, "seed"), 0, 4294967295LL, "an integer in 0..4294967295"));
  if (value.contains("strength_map"))
    tearing.strength_map = parse_strength_map(reader, value["strength_map"], child_path(path, "strength_map"));
  tearing.strain_rate_limit = optional_number(reader, value, path, "strain_rate_limit", 0, 1,
                                              "fraction of a face's altitude per substep", tearing.strain_rate_limit, false);
  return tearing;
}

/// `colliders`: an array of colliders (`parse_collider`).
std::vector<Collider> parse_colliders(const Reader& reader, const json& value, const std::string& path, int frames) {
  if (!value.is_array()) reader.fail(path, "expected an array of colliders, got " + describe(value));
  std::vector<Collider> colliders;
  for (std::size_t i = 0; i < value.size(); ++i)
    colliders.push_back(parse_collider(reader, value[i], child_path(path, i), frames));
  return colliders;
}

/// `collision`: {"self": true, "thickness": T, "friction": F, "iterations": N}, each optional
/// (docs/simulation.md, *Collision*).
CollisionOptions parse_collision(const Reader& reader, const json& value, const std::string& path) {
  reader.expect_object(value, path, {"self", "thickness", "friction", "iterations"});
  CollisionOptions collision;
  if (value.contains("self")) {
    if (!value["self"].is_boolean())
      reader.fail(child_path(path, "self"), "expected true or false, got " + describe(value["self"]));
    collision.self = value["self"].get<bool>();
  }
  collision.thickness = optional_number(reader, value, path, "thickness", 0, limits::max_collision_thickness, "metres",
                                        collision.thickness);
  collision.friction = optional_number(reader, value, path, "friction", 0, limits::max_collision_friction,
                                       "Coulomb coefficient", collision.friction, false);
  if (value.contains("iterations"))
    collision.iterations = static_cast<int>(
        reader.integer(value["iterations"], child_path(path, "iterations"), 1, limits::max_collision_iterations,
                       "an integer in 1.." + std::to_string(limits::max_collision_iterations)));
  return collision;
}

/// A number in [lo, hi], "expected a number in [lo, hi] (unit), got ...".
double number_in(const Reader& reader, const json& value, const std::string& path, double lo, double hi,
                 const std::string& unit) {
  return reader.number(value, path, "a number in [" + shown(lo) + ", " + shown(hi) + "] (" + unit + ")",
                       [&](double x) { return x >= lo && x <= hi; });
}

StretchModel stretch_model_of(const Reader& reader, const json& value, const std::string& path) {
  if (value == "automatic") return StretchModel::automatic;
  if (value == "springs") return StretchModel::springs;
  if (value == "membrane") return StretchModel::membrane;
  reader.fail(path, "expected \"automatic\", \"springs\" or \"membrane\", got " + value.dump());
}

}  // namespace

SimulationOptions parse_simulation(const json& block, const std::string& script_path, int frames) {
  SimulationOptions options;
  options.source = script_path;
  if (block.is_null()) return options;
  const Reader reader(script_path);
  const std::string root = "simulation";
  reader.expect_object(block, root,
                       {"fps", "substeps", "iterations", "gravity", "damping", "density", "stretch_stiffness",
                        "stretch_model", "bend_stiffness", "chebyshev", "pins", "colliders", "collision", "tearing"});
  if (block.contains("fps"))
    options.fps =
        number_in(reader, block["fps"], child_path(root, "fps"), limits::min_fps, limits::max_fps, "frames per second");
  const std::string substeps_range = "an integer in 1.." + std::to_string(limits::max_substeps);
  if (block.contains("substeps"))
    options.substeps = static_cast<int>(
        reader.integer(block["substeps"], child_path(root, "substeps"), 1, limits::max_substeps, substeps_range));
  const std::string iterations_range = "an integer in 1.." + std::to_string(limits::max_iterations);
  if (block.contains("iterations"))
    options.iterations = static_cast<int>(reader.integer(block["iterations"], child_path(root, "iterations"), 1,
                                                         limits::max_iterations, iterations_range));
  // Each is allowed alone; together they are the iterations of a frame, which bound its time.
  const long long per_frame = static_cast<long long>(options.substeps) * options.iterations;
  if (per_frame > limits::max_iterations_per_frame)
    reader.fail(child_path(root, block.contains("iterations") ? "iterations" : "substeps"),
                "substeps × iterations is " + std::to_string(per_frame) + " solver iterations per frame, more than " +
                    std::to_string(limits::max_iterations_per_frame) + " (" + std::to_string(options.substeps) + " × " +
                    std::to_string(options.iterations) + ")");
  if (block.contains("gravity")) {
    const std::string path = child_path(root, "gravity");
    options.gravity = reader.point<3>(block["gravity"], path);
    if (!(vector_length(options.gravity) <= limits::max_gravity))
      reader.fail(path, "expected a vector of length at most " + shown(limits::max_gravity) + " (m/s²), got " +
                            block["gravity"].dump());
  }
  if (block.contains("damping"))
    options.damping = number_in(reader, block["damping"], child_path(root, "damping"), 0, 1, "fraction per second");
  if (block.contains("density"))
    options.density = number_in(reader, block["density"], child_path(root, "density"), limits::min_density,
                                limits::max_density, "kg/m²");
  if (block.contains("stretch_stiffness"))
    options.stretch_stiffness = number_in(reader, block["stretch_stiffness"], child_path(root, "stretch_stiffness"), 0,
                                          limits::max_stretch_stiffness, "N/m");
  if (block.contains("stretch_model"))
    options.stretch_model = stretch_model_of(reader, block["stretch_model"], child_path(root, "stretch_model"));
  if (block.contains("bend_stiffness"))
    options.bend_stiffness = number_in(reader, block["bend_stiffness"], child_path(root, "bend_stiffness"), 0,
                                       limits::max_bend_stiffness, "N·m");
  if (block.contains("chebyshev")) {
    const std::string path = child_path(root, "chebyshev");
    const json& cheb = block["chebyshev"];
    reader.expect_object(cheb, path, {"rho", "gamma", "delay"});
    if (cheb.contains("rho"))
      options.chebyshev.rho = reader.number(cheb["rho"], child_path(path, "rho"), "a number in (0, 1)",
                                            [](double x) { return x > 0 && x < 1; });
    if (cheb.contains("gamma"))
      options.chebyshev.gamma = reader.number(cheb["gamma"], child_path(path, "gamma"), "a number in (0, 1]",
                                              [](double x) { return x > 0 && x <= 1; });
    if (cheb.contains("delay"))
      options.chebyshev.delay =
          static_cast<int>(reader.integer(cheb["delay"], child_path(path, "delay"), 0, limits::max_chebyshev_delay,
                                          "an integer in 0.." + std::to_string(limits::max_chebyshev_delay)));
  }
  if (block.contains("pins")) {
    const std::string path = child_path(root, "pins");
    const json& pins = block["pins"];
    if (!pins.is_array()) reader.fail(path, "expected an array of pins, got " + describe(pins));
    if (pins.size() > static_cast<std::size_t>(limits::max_pins))
      reader.fail(path, "expected at most " + std::to_string(limits::max_pins) + " pins, got " + describe(pins));
    for (std::size_t i = 0; i < pins.size(); ++i)
      options.pins.push_back(parse_pin(reader, pins[i], child_path(path, i)));
  }
  if (block.contains("colliders"))
    options.colliders = parse_colliders(reader, block["colliders"], child_path(root, "colliders"), frames);
  if (block.contains("collision"))
    options.collision = parse_collision(reader, block["collision"], child_path(root, "collision"));
  if (block.contains("tearing")) options.tearing = parse_tearing(reader, block["tearing"], child_path(root, "tearing"));
  return options;
}

}  // namespace tear
