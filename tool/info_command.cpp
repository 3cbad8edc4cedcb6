// `tear info MESH`: what a mesh is made of and what is wrong with it, for people and for scripts.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "tear/error.h"
#include "tear/mesh_info.h"
#include "tear/topology.h"
#include "tear/validate_mesh.h"

namespace tear::cli {

namespace {

struct InfoOptions {
  std::string mesh_path;
  bool json = false;
  std::string device = "auto";
  ReadOptions read;
  bool strict = false;
};

std::string format_number(double x) {
  if (std::isnan(x)) return "n/a";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", x);
  return buffer;
}

std::string format_point(const std::array<double, 3>& p) {
  if (std::isnan(p[0])) return "n/a";
  return format_number(p[0]) + " " + format_number(p[1]) + " " + format_number(p[2]);
}

std::string yes_no(bool b) { return b ? "yes" : "no"; }

/// A defect count, with what the defect is when there is one.
std::string count_why(std::int64_t count, const char* why) {
  return count ? std::to_string(count) + " (" + why + ")" : "0";
}

void print_human(std::ostream& out, const std::string& path, Device device, const MeshInfo& info,
                 const MeshReport& report) {
  const std::vector<std::pair<std::string, std::string>> rows = {
      {"file", path},
      {"backend", std::string(to_string(device)) + ", " + device_name(device)},
      {"nodes", std::to_string(info.nodes)},
      {"faces", std::to_string(info.faces)},
      {"edges", std::to_string(info.edges)},
      {"boundary edges", std::to_string(info.boundary_edges)},
      {"boundary loops", std::to_string(info.boundary_loops)},
      {"components", std::to_string(info.components)},
      {"pieces", std::to_string(info.pieces)},
      {"euler characteristic", std::to_string(info.euler_characteristic)},
      {"non-manifold edges", count_why(info.non_manifold_edges, "more than two faces on one edge")},
      {"bow-tie nodes", count_why(info.non_manifold_nodes, "faces around the node form several fans")},
      {"degenerate faces", count_why(info.degenerate_faces, "repeated node or zero area")},
      {"inconsistent edges", count_why(info.inconsistent_edges, "neighbouring faces of opposite orientation")},
      {"duplicate faces", count_why(info.duplicate_faces, "on the same three nodes as another face")},
      {"thin faces", count_why(info.thin_faces, "too thin to cut: height under 1e-7 of the longest edge")},
      {"imprecise faces", count_why(info.imprecise_faces, "too thin to cut at their coordinates: height under 8 float32 steps there")},
      {"area", format_number(info.area)},
      {"min angle", info.faces ? format_number(info.min_angle_deg) + " deg" : "n/a"},
      {"sliver faces", info.sliver_faces ? std::to_string(info.sliver_faces) + " (an angle under " +
                                               format_number(sliver_angle_deg) +
                                               " deg: cuts near them make thinner slivers still)"
                                         : "0"},
      {"uvs", yes_no(info.has_uv)},
      {"normals", yes_no(info.has_normals)},
      {"bbox min", format_point(info.bbox_min)},
      {"bbox max", format_point(info.bbox_max)},
      {"cuttable", !report.cuttable()    ? "no: " + report.describe()
                   : info.sliver_faces ? "yes, with " + std::to_string(info.sliver_faces) +
                                             (info.sliver_faces == 1 ? " sliver face" : " sliver faces") +
                                             " (warning: see above)"
                                       : "yes"},
  };
  std::size_t width = 0;
  for (const auto& row : rows) width = std::max(width, row.first.size());
  for (const auto& row : rows)
    out << row.first << ':' << std::string(width + 1 - row.first.size(), ' ') << row.second << '\n';
}

void run_info(const InfoOptions& options) {
  const Device device = select_device(options.device);
  // The GPU's context is made while the input is read.
  const DeviceWarmUp warm_up(device);
  const Mesh mesh = read_checked_mesh(options.mesh_path, options.read, device, options.strict);
  const Topology topology = build_topology(mesh, device);
  const MeshReport report = validate_mesh(mesh, topology, device);
  const MeshInfo info = compute_mesh_info(mesh, topology, report);

  if (options.json) {
    nlohmann::json j = nlohmann::json::parse(to_json(info));
    j["file"] = options.mesh_path;
    j["device"] = to_string(device);
    j["device_name"] = device_name(device);
    // A file name need not be UTF-8; replace bad bytes rather than fail on them.
    std::cout << j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) << '\n';
  } else {
    print_human(std::cout, options.mesh_path, device, info, report);
  }
  std::cout.flush();
  if (!std::cout) throw runtime_error("cannot write to standard output");
}

}  // namespace

void add_info_command(CLI::App& app) {
  auto options = std::make_shared<InfoOptions>();
  CLI::App* command = app.add_subcommand("info", "Print the counts, boundary loops, components and defects of a mesh");
  command->footer(
      "Defects (non-manifold edges, bow-tie nodes, degenerate faces, inconsistent orientation, duplicate faces) are "
      "reported, not refused. A face index out of range or a non-finite coordinate is bad input (exit 2). Exit "
      "codes: 0 ok, 1 usage error, 2 bad input, 3 runtime failure.");
  command->add_option("MESH", options->mesh_path, "Mesh file: OBJ, glTF, GLB, PLY or any format assimp reads")
      ->required()
      ->type_name("");
  command->add_flag("--json", options->json,
                    "Print one JSON object on one line instead of the table (keys: see docs/cli.md)");
  add_device_option(*command, options->device);
  add_read_options(*command, options->read);
  add_strict_option(*command, options->strict);
  command->callback([options] { run_info(*options); });
}

}  // namespace tear::cli
