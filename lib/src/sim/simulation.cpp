#include "tear/simulation.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

#include "script/json_reader.h"
#include "sim/pd_solver.h"
#include "backend/systems.h"
#include "tear/error.h"

namespace tear {

using nlohmann::json;

namespace {

// ---- the `simulation` block ---------------------------------------------------------------------

using namespace json_reading;
using Reader = JsonReader;

Pin parse_pin(const Reader& reader, const json& value, const std::string& path) {
  reader.expect_object(value, path, {"box", "nodes"});
  if (value.size() != 1) reader.fail(path, "expected exactly one of \"box\" or \"nodes\", got " + describe(value));
  Pin pin;
  pin.key_path = path;
  if (value.contains("box")) {
    const std::string box_path = child_path(path, "box");
    const json& box = value["box"];
    reader.expect_object(box, box_path, {"min", "max"});
    pin.kind = Pin::Kind::box;
    pin.min = reader.point<3>(reader.member(box, box_path, "min", "an array of 3 numbers"), child_path(box_path, "min"));
    pin.max = reader.point<3>(reader.member(box, box_path, "max", "an array of 3 numbers"), child_path(box_path, "max"));
    for (int a = 0; a < 3; ++a)
      if (pin.max[a] < pin.min[a])
        reader.fail(child_path(child_path(box_path, "max"), a), "expected a number >= min[" + std::to_string(a) + "] (" +
                                                          json(pin.min[a]).dump() + "), got " +
                                                          json(pin.max[a]).dump());
  } else {
    const std::string nodes_path = child_path(path, "nodes");
    const json& nodes = value["nodes"];
    if (!nodes.is_array()) reader.fail(nodes_path, "expected an array of node indices, got " + describe(nodes));
    pin.kind = Pin::Kind::nodes;
    for (std::size_t i = 0; i < nodes.size(); ++i)
      pin.nodes.push_back(static_cast<index_t>(reader.integer(
          nodes[i], child_path(nodes_path, i), 0, std::numeric_limits<index_t>::max(), "a node index (an integer >= 0)")));
  }
  return pin;
}

Collider parse_collider(const Reader& reader, const json& value, const std::string& path) {
  reader.expect_object(value, path, {"plane", "sphere"});
  if (value.size() != 1) reader.fail(path, "expected exactly one of \"plane\" or \"sphere\", got " + describe(value));
  Collider collider;
  if (value.contains("plane")) {
    const std::string plane_path = child_path(path, "plane");
    const json& plane = value["plane"];
    reader.expect_object(plane, plane_path, {"point", "normal"});
    collider.kind = Collider::Kind::plane;
    collider.point =
        reader.point<3>(reader.member(plane, plane_path, "point", "an array of 3 numbers"), child_path(plane_path, "point"));
    const auto n = reader.point<3>(reader.member(plane, plane_path, "normal", "a non-zero [x, y, z] vector"),
                                  child_path(plane_path, "normal"));
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 0) || !std::isfinite(len))
      reader.fail(child_path(plane_path, "normal"),
                  "expected a non-zero [x, y, z] vector, got " + describe(plane["normal"]));
    collider.normal = {n[0] / len, n[1] / len, n[2] / len};
  } else {
    const std::string sphere_path = child_path(path, "sphere");
    const json& sphere = value["sphere"];
    reader.expect_object(sphere, sphere_path, {"center", "radius"});
    collider.kind = Collider::Kind::sphere;
    collider.point = reader.point<3>(reader.member(sphere, sphere_path, "center", "an array of 3 numbers"),
                                    child_path(sphere_path, "center"));
    collider.radius = reader.number(reader.member(sphere, sphere_path, "radius", "a number > 0"),
                                    child_path(sphere_path, "radius"), "a number > 0", [](double x) { return x > 0; });
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
  if (block.contains("fps")) options.fps = reader.number(block["fps"], child_path(root, "fps"), "a number > 0", positive);
  if (block.contains("substeps"))
    options.substeps = static_cast<int>(
        reader.integer(block["substeps"], child_path(root, "substeps"), 1, 10000, "an integer in 1..10000"));
  if (block.contains("iterations"))
    options.iterations = static_cast<int>(
        reader.integer(block["iterations"], child_path(root, "iterations"), 1, 100000, "an integer in 1..100000"));
  if (block.contains("gravity")) options.gravity = reader.point<3>(block["gravity"], child_path(root, "gravity"));
  if (block.contains("damping"))
    options.damping = reader.number(block["damping"], child_path(root, "damping"), "a number in [0, 1]",
                                    [](double x) { return x >= 0 && x <= 1; });
  if (block.contains("density"))
    options.density = reader.number(block["density"], child_path(root, "density"), "a number > 0", positive);
  if (block.contains("stretch_stiffness"))
    options.stretch_stiffness =
        reader.number(block["stretch_stiffness"], child_path(root, "stretch_stiffness"), "a number >= 0", non_negative);
  if (block.contains("bend_stiffness"))
    options.bend_stiffness =
        reader.number(block["bend_stiffness"], child_path(root, "bend_stiffness"), "a number >= 0", non_negative);
  if (block.contains("chebyshev")) {
    const std::string path = child_path(root, "chebyshev");
    const json& cheb = block["chebyshev"];
    reader.expect_object(cheb, path, {"rho", "gamma", "delay"});
    if (cheb.contains("rho"))
      options.chebyshev.rho =
          reader.number(cheb["rho"], child_path(path, "rho"), "a number in (0, 1)", [](double x) { return x > 0 && x < 1; });
    if (cheb.contains("gamma"))
      options.chebyshev.gamma = reader.number(cheb["gamma"], child_path(path, "gamma"), "a number in (0, 1]",
                                              [](double x) { return x > 0 && x <= 1; });
    if (cheb.contains("delay"))
      options.chebyshev.delay =
          static_cast<int>(reader.integer(cheb["delay"], child_path(path, "delay"), 0, 100000, "an integer in 0..100000"));
  }
  if (block.contains("pins")) {
    const std::string path = child_path(root, "pins");
    const json& pins = block["pins"];
    if (!pins.is_array()) reader.fail(path, "expected an array of pins, got " + describe(pins));
    for (std::size_t i = 0; i < pins.size(); ++i) options.pins.push_back(parse_pin(reader, pins[i], child_path(path, i)));
  }
  if (block.contains("colliders")) {
    const std::string path = child_path(root, "colliders");
    const json& colliders = block["colliders"];
    if (!colliders.is_array()) reader.fail(path, "expected an array of colliders, got " + describe(colliders));
    for (std::size_t i = 0; i < colliders.size(); ++i)
      options.colliders.push_back(parse_collider(reader, colliders[i], child_path(path, i)));
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
std::size_t PdSolver::bytes_per_iteration() const { return impl_->bytes_per_iteration(); }
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
