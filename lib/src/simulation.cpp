#include "tear/simulation.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

#include "pd_solver.h"
#include "systems.h"
#include "tear/error.h"

namespace tear {

using nlohmann::json;

namespace {

// ---- the `simulation` block ---------------------------------------------------------------------

std::string describe(const json& value) {
  switch (value.type()) {
    case json::value_t::null:
      return "null";
    case json::value_t::boolean:
      return value.get<bool>() ? "true" : "false";
    case json::value_t::string: {
      const auto& s = value.get_ref<const std::string&>();
      constexpr std::size_t longest = 40;
      const std::string shown = s.size() <= longest ? s : s.substr(0, longest) + "...";
      return json(shown).dump(-1, ' ', false, json::error_handler_t::replace);
    }
    case json::value_t::array:
      if (value.empty()) return "an empty array";
      return "an array of " + std::to_string(value.size()) + (value.size() == 1 ? " element" : " elements");
    case json::value_t::object:
      return value.empty() ? "an empty object" : "an object";
    default:
      if (value.is_number_float() && !std::isfinite(value.get<double>())) return "a non-finite number";
      return value.dump();
  }
}

// Keys that are not plain identifiers are written as ["..."], JSON-escaped, so a message stays on
// one line whatever the key holds.
std::string child(const std::string& path, const std::string& key) {
  const bool plain = !key.empty() && !std::isdigit(static_cast<unsigned char>(key[0])) &&
                     std::all_of(key.begin(), key.end(), [](char c) {
                       return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
                     });
  if (plain) return path + "." + key;
  return path + "[" + json(key).dump(-1, ' ', false, json::error_handler_t::replace) + "]";
}
std::string child(const std::string& path, std::size_t index) { return path + "[" + std::to_string(index) + "]"; }

class Reader {
 public:
  explicit Reader(const std::string& file) : file_(file) {}

  [[noreturn]] void fail(const std::string& path, const std::string& what) const {
    throw input_error(file_, path + ": " + what);
  }

  // Unknown keys are errors: a misspelt "dampning" must not silently leave the default in place.
  void expect_object(const json& value, const std::string& path, const std::vector<std::string>& allowed) const {
    if (!value.is_object()) fail(path, "expected an object, got " + describe(value));
    for (const auto& item : value.items()) {
      if (std::find(allowed.begin(), allowed.end(), item.key()) != allowed.end()) continue;
      std::string list;
      for (std::size_t i = 0; i < allowed.size(); ++i)
        list += (i == 0 ? "" : i + 1 == allowed.size() ? " or " : ", ") + allowed[i];
      fail(child(path, item.key()), "unknown key (expected " + list + ")");
    }
  }

  const json& member(const json& object, const std::string& path, const std::string& key,
                     const std::string& expected) const {
    const auto it = object.find(key);
    if (it == object.end()) fail(child(path, key), "missing (expected " + expected + ")");
    return *it;
  }

  double number(const json& value, const std::string& path) const {
    if (!value.is_number()) fail(path, "expected a number, got " + describe(value));
    const double x = value.get<double>();
    if (!std::isfinite(x)) fail(path, "expected a finite number, got " + describe(value));
    return x;
  }

  // A number with `ok(x)`, else "expected <expected>, got <value>".
  template <class Ok>
  double number(const json& value, const std::string& path, const std::string& expected, Ok ok) const {
    if (!value.is_number() || !std::isfinite(value.get<double>()) || !ok(value.get<double>()))
      fail(path, "expected " + expected + ", got " + describe(value));
    return value.get<double>();
  }

  // JSON does not tell 4 from 4.0: any number with an integral value in [lo, hi] counts.
  long long integer(const json& value, const std::string& path, long long lo, long long hi,
                    const std::string& expected) const {
    bool ok = false;
    long long n = 0;
    if (value.is_number_unsigned()) {
      const unsigned long long u = value.get<unsigned long long>();
      ok = u <= static_cast<unsigned long long>(hi) && static_cast<long long>(u) >= lo;
      n = static_cast<long long>(u);
    } else if (value.is_number_integer()) {
      n = value.get<long long>();
      ok = n >= lo && n <= hi;
    } else if (value.is_number_float()) {
      const double x = value.get<double>();
      ok = std::isfinite(x) && x == std::floor(x) && x >= static_cast<double>(lo) && x <= static_cast<double>(hi);
      if (ok) n = static_cast<long long>(x);
    }
    if (!ok) fail(path, "expected " + expected + ", got " + describe(value));
    return n;
  }

  std::array<double, 3> vector3(const json& value, const std::string& path) const {
    if (!value.is_array() || value.size() != 3) fail(path, "expected an array of 3 numbers, got " + describe(value));
    return {number(value[0], child(path, 0)), number(value[1], child(path, 1)), number(value[2], child(path, 2))};
  }

 private:
  const std::string& file_;
};

Pin parse_pin(const Reader& reader, const json& value, const std::string& path) {
  reader.expect_object(value, path, {"box", "nodes"});
  if (value.size() != 1) reader.fail(path, "expected exactly one of \"box\" or \"nodes\", got " + describe(value));
  Pin pin;
  pin.key_path = path;
  if (value.contains("box")) {
    const std::string box_path = child(path, "box");
    const json& box = value["box"];
    reader.expect_object(box, box_path, {"min", "max"});
    pin.kind = Pin::Kind::box;
    pin.min = reader.vector3(reader.member(box, box_path, "min", "an array of 3 numbers"), child(box_path, "min"));
    pin.max = reader.vector3(reader.member(box, box_path, "max", "an array of 3 numbers"), child(box_path, "max"));
    for (int a = 0; a < 3; ++a)
      if (pin.max[a] < pin.min[a])
        reader.fail(child(child(box_path, "max"), a), "expected a number >= min[" + std::to_string(a) + "] (" +
                                                          json(pin.min[a]).dump() + "), got " +
                                                          json(pin.max[a]).dump());
  } else {
    const std::string nodes_path = child(path, "nodes");
    const json& nodes = value["nodes"];
    if (!nodes.is_array()) reader.fail(nodes_path, "expected an array of node indices, got " + describe(nodes));
    pin.kind = Pin::Kind::nodes;
    for (std::size_t i = 0; i < nodes.size(); ++i)
      pin.nodes.push_back(static_cast<index_t>(reader.integer(
          nodes[i], child(nodes_path, i), 0, std::numeric_limits<index_t>::max(), "a node index (an integer >= 0)")));
  }
  return pin;
}

Collider parse_collider(const Reader& reader, const json& value, const std::string& path) {
  reader.expect_object(value, path, {"plane", "sphere"});
  if (value.size() != 1) reader.fail(path, "expected exactly one of \"plane\" or \"sphere\", got " + describe(value));
  Collider collider;
  if (value.contains("plane")) {
    const std::string plane_path = child(path, "plane");
    const json& plane = value["plane"];
    reader.expect_object(plane, plane_path, {"point", "normal"});
    collider.kind = Collider::Kind::plane;
    collider.point =
        reader.vector3(reader.member(plane, plane_path, "point", "an array of 3 numbers"), child(plane_path, "point"));
    const auto n = reader.vector3(reader.member(plane, plane_path, "normal", "a non-zero [x, y, z] vector"),
                                  child(plane_path, "normal"));
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 0) || !std::isfinite(len))
      reader.fail(child(plane_path, "normal"),
                  "expected a non-zero [x, y, z] vector, got " + describe(plane["normal"]));
    collider.normal = {n[0] / len, n[1] / len, n[2] / len};
  } else {
    const std::string sphere_path = child(path, "sphere");
    const json& sphere = value["sphere"];
    reader.expect_object(sphere, sphere_path, {"center", "radius"});
    collider.kind = Collider::Kind::sphere;
    collider.point = reader.vector3(reader.member(sphere, sphere_path, "center", "an array of 3 numbers"),
                                    child(sphere_path, "center"));
    collider.radius = reader.number(reader.member(sphere, sphere_path, "radius", "a number > 0"),
                                    child(sphere_path, "radius"), "a number > 0", [](double x) { return x > 0; });
  }
  return collider;
}

}  // namespace

SimulationOptions parse_simulation(const json& block, const std::string& script_path) {
  SimulationOptions options;
  options.source = script_path;
  if (block.is_null()) return options;
  const Reader reader(script_path);
  const std::string root = "simulation";
  reader.expect_object(block, root,
                       {"fps", "substeps", "iterations", "gravity", "damping", "density", "stretch_stiffness",
                        "bend_stiffness", "chebyshev", "pins", "colliders"});
  const auto positive = [](double x) { return x > 0; };
  const auto non_negative = [](double x) { return x >= 0; };
  if (block.contains("fps")) options.fps = reader.number(block["fps"], child(root, "fps"), "a number > 0", positive);
  if (block.contains("substeps"))
    options.substeps = static_cast<int>(
        reader.integer(block["substeps"], child(root, "substeps"), 1, 10000, "an integer in 1..10000"));
  if (block.contains("iterations"))
    options.iterations = static_cast<int>(
        reader.integer(block["iterations"], child(root, "iterations"), 1, 100000, "an integer in 1..100000"));
  if (block.contains("gravity")) options.gravity = reader.vector3(block["gravity"], child(root, "gravity"));
  if (block.contains("damping"))
    options.damping = reader.number(block["damping"], child(root, "damping"), "a number in [0, 1]",
                                    [](double x) { return x >= 0 && x <= 1; });
  if (block.contains("density"))
    options.density = reader.number(block["density"], child(root, "density"), "a number > 0", positive);
  if (block.contains("stretch_stiffness"))
    options.stretch_stiffness =
        reader.number(block["stretch_stiffness"], child(root, "stretch_stiffness"), "a number >= 0", non_negative);
  if (block.contains("bend_stiffness"))
    options.bend_stiffness =
        reader.number(block["bend_stiffness"], child(root, "bend_stiffness"), "a number >= 0", non_negative);
  if (block.contains("chebyshev")) {
    const std::string path = child(root, "chebyshev");
    const json& cheb = block["chebyshev"];
    reader.expect_object(cheb, path, {"rho", "gamma", "delay"});
    if (cheb.contains("rho"))
      options.chebyshev.rho =
          reader.number(cheb["rho"], child(path, "rho"), "a number in (0, 1)", [](double x) { return x > 0 && x < 1; });
    if (cheb.contains("gamma"))
      options.chebyshev.gamma = reader.number(cheb["gamma"], child(path, "gamma"), "a number in (0, 1]",
                                              [](double x) { return x > 0 && x <= 1; });
    if (cheb.contains("delay"))
      options.chebyshev.delay =
          static_cast<int>(reader.integer(cheb["delay"], child(path, "delay"), 0, 100000, "an integer in 0..100000"));
  }
  if (block.contains("pins")) {
    const std::string path = child(root, "pins");
    const json& pins = block["pins"];
    if (!pins.is_array()) reader.fail(path, "expected an array of pins, got " + describe(pins));
    for (std::size_t i = 0; i < pins.size(); ++i) options.pins.push_back(parse_pin(reader, pins[i], child(path, i)));
  }
  if (block.contains("colliders")) {
    const std::string path = child(root, "colliders");
    const json& colliders = block["colliders"];
    if (!colliders.is_array()) reader.fail(path, "expected an array of colliders, got " + describe(colliders));
    for (std::size_t i = 0; i < colliders.size(); ++i)
      options.colliders.push_back(parse_collider(reader, colliders[i], child(path, i)));
  }
  return options;
}

std::vector<std::uint8_t> resolve_pins(const SimulationOptions& options, const std::vector<float>& node_rest,
                                       index_t node_count) {
  std::vector<std::uint8_t> node_pinned(static_cast<std::size_t>(std::max<index_t>(node_count, 0)), 0);
  for (const Pin& pin : options.pins) {
    if (pin.kind == Pin::Kind::box) {
      for (index_t n = 0; n < node_count; ++n) {
        bool inside = true;
        for (int a = 0; a < 3; ++a) {
          const double x = node_rest[3 * static_cast<std::size_t>(n) + a];
          inside = inside && x >= pin.min[a] && x <= pin.max[a];
        }
        if (inside) node_pinned[n] = 1;
      }
    } else {
      for (std::size_t i = 0; i < pin.nodes.size(); ++i) {
        const index_t n = pin.nodes[i];
        if (n < 0 || n >= node_count)
          throw input_error(options.source, pin.key_path + ".nodes[" + std::to_string(i) + "]: node " +
                                                std::to_string(n) + " is out of range (the mesh has " +
                                                std::to_string(node_count) + " nodes)");
        node_pinned[n] = 1;
      }
    }
  }
  return node_pinned;
}

// ---- the solver ---------------------------------------------------------------------------------

namespace {
void check_mesh(const std::vector<index_t>& face_nodes, const std::vector<float>& node_rest, index_t node_count) {
  if (node_count < 0 || node_rest.size() != 3 * static_cast<std::size_t>(node_count))
    throw runtime_error("PdSolver: node_rest holds " + std::to_string(node_rest.size()) + " floats, expected 3 × " +
                        std::to_string(node_count));
  if (face_nodes.size() % 3 != 0) throw runtime_error("PdSolver: face_nodes is not a multiple of 3 long");
  for (const index_t n : face_nodes)
    if (n < 0 || n >= node_count)
      throw runtime_error("PdSolver: face_nodes holds node " + std::to_string(n) + ", out of range for " +
                          std::to_string(node_count) + " nodes");
}
}  // namespace

PdSolver::PdSolver(const std::vector<index_t>& face_nodes, const std::vector<float>& node_rest, index_t node_count,
                   const SimulationOptions& options, Device device)
    : PdSolver(face_nodes, node_rest, node_count, options, device,
               (check_mesh(face_nodes, node_rest, node_count), resolve_pins(options, node_rest, node_count))) {}

PdSolver::PdSolver(const std::vector<index_t>& face_nodes, const std::vector<float>& node_rest, index_t node_count,
                   const SimulationOptions& options, Device device, const std::vector<std::uint8_t>& node_pinned) {
  check_mesh(face_nodes, node_rest, node_count);
  if (node_pinned.size() != static_cast<std::size_t>(node_count))
    throw runtime_error("PdSolver: node_pinned holds " + std::to_string(node_pinned.size()) + " flags, expected " +
                        std::to_string(node_count));
  impl_ = backend::dispatch(device, [&](auto system) {
    return backend::make_pd_solver<decltype(system)>(face_nodes, node_rest, node_count, options, node_pinned);
  });
}

PdSolver::~PdSolver() = default;
PdSolver::PdSolver(PdSolver&&) noexcept = default;
PdSolver& PdSolver::operator=(PdSolver&&) noexcept = default;

Device PdSolver::device() const { return impl_->device(); }
index_t PdSolver::node_count() const { return impl_->node_count(); }
index_t PdSolver::constraint_count() const { return impl_->constraint_count(); }
const SimulationOptions& PdSolver::options() const { return impl_->options(); }

void PdSolver::step() { impl_->step(); }

void PdSolver::step(std::vector<float>& node_pos, std::vector<float>& node_vel) {
  set_state(node_pos, node_vel);
  impl_->step();
  node_pos = impl_->node_pos();
  node_vel = impl_->node_vel();
}

void PdSolver::set_state(const std::vector<float>& node_pos, const std::vector<float>& node_vel) {
  const std::size_t size = 3 * static_cast<std::size_t>(impl_->node_count());
  if (node_pos.size() != size || node_vel.size() != size)
    throw runtime_error("PdSolver::set_state: expected " + std::to_string(size) + " floats each, got " +
                        std::to_string(node_pos.size()) + " and " + std::to_string(node_vel.size()));
  impl_->set_state(node_pos, node_vel);
}

std::vector<float> PdSolver::node_pos() const { return impl_->node_pos(); }
std::vector<float> PdSolver::node_vel() const { return impl_->node_vel(); }
float* PdSolver::device_node_pos() { return impl_->device_node_pos(); }
float* PdSolver::device_node_vel() { return impl_->device_node_vel(); }
std::vector<float> PdSolver::node_mass() const { return impl_->node_mass(); }
std::vector<std::uint8_t> PdSolver::node_pinned() const { return impl_->node_pinned(); }

}  // namespace tear
