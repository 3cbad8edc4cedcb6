#include "tear/demo_scene.h"
#include <cmath>

#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tear/error.h"
#include "tear/make_sheet.h"

namespace tear {

const char* to_string(DemoResolution resolution) {
  switch (resolution) {
    case DemoResolution::low:
      return "low";
    case DemoResolution::medium:
      return "medium";
    case DemoResolution::high:
      return "high";
  }
  return "?";
}

DemoResolution parse_demo_resolution(const std::string& text) {
  for (DemoResolution r : {DemoResolution::low, DemoResolution::medium, DemoResolution::high})
    if (text == to_string(r)) return r;
  throw Error(ErrorKind::usage, "--resolution: expected low, medium or high, got '" + text + "'");
}

index_t demo_face_count(DemoResolution resolution) {
  switch (resolution) {
    case DemoResolution::low:
      return 2822;
    case DemoResolution::medium:
      return 9022;
    case DemoResolution::high:
      return 38298;
  }
  return 2822;
}

Mesh make_demo_sheet(DemoResolution resolution) {
  SheetOptions options;
  options.face_count = demo_face_count(resolution);
  options.seed = 1;
  return make_sheet(options);
}

CutScript demo_script() {
  // The cuts of examples/paper_scene.json: six chords through the centre, 15 degrees apart.
  const std::array<std::array<std::array<double, 2>, 2>, 6> chords = {{
      {{{0.1619, 0.4594}, {0.8381, 0.6406}}},
      {{{0.2525, 0.3025}, {0.7475, 0.7975}}},
      {{{0.4094, 0.2119}, {0.5906, 0.8881}}},
      {{{0.5906, 0.2119}, {0.4094, 0.8881}}},
      {{{0.7475, 0.3025}, {0.2525, 0.7975}}},
      {{{0.8381, 0.4594}, {0.1619, 0.6406}}},
  }};
  nlohmann::json cuts = nlohmann::json::array();
  for (std::size_t i = 0; i < chords.size(); ++i)
    cuts.push_back({{"frame", demo_first_cut_frame + demo_cut_interval * static_cast<int>(i)},
                    {"space", "rest-xy"},
                    {"polyline", {{chords[i][0][0], chords[i][0][1]}, {chords[i][1][0], chords[i][1][1]}}}});
  // The sheet's top row lies exactly on y = 1 (border nodes slide only along their side); the next
  // row is a cell (less a quarter-cell jitter) below: more than 5 mm at the high resolution, far outside
  // this box.
  const nlohmann::json top_edge = {{"box", {{"min", {-1.0, 0.999, -1.0}}, {"max", {2.0, 1.001, 1.0}}}}};
  const nlohmann::json script = {
      {"version", 1},
      {"frames", demo_frames},
      {"cuts", cuts},
      {"simulation", {{"fps", demo_fps}, {"gravity", {0.0, -9.81, 0.0}}, {"pins", nlohmann::json::array({top_edge})}}}};
  // Parsed like a file, so the demo's script passes every check a user's would.
  return parse_cut_script(script.dump(), "(demo scene)");
}

const char* to_string(DemoScene scene) {
  switch (scene) {
    case DemoScene::paper:
      return "paper";
    case DemoScene::pull:
      return "pull";
    case DemoScene::punch:
      return "punch";
    case DemoScene::grain:
      return "grain";
    case DemoScene::drape:
      return "drape";
  }
  return "?";
}

DemoScene parse_demo_scene(const std::string& text) {
  for (DemoScene s : {DemoScene::paper, DemoScene::pull, DemoScene::punch, DemoScene::grain, DemoScene::drape})
    if (text == to_string(s)) return s;
  throw Error(ErrorKind::usage, "--scene: expected paper, pull, punch, grain or drape, got '" + text + "'");
}

Mesh make_demo_mesh(DemoScene scene, DemoResolution resolution) {
  Mesh sheet = make_demo_sheet(resolution);
  if (scene == DemoScene::grain) {
    // A seam as a garment's: the UVs of the faces right of it moved by half a tile, so the faces
    // either side of it give its nodes different UVs.
    for (index_t f = 0; f < sheet.face_count(); ++f) {
      double x = 0;
      for (int k = 0; k < 3; ++k) x += sheet.node_pos[3 * sheet.face_nodes[3 * f + k]] / 3.0;
      if (x > demo_grain_seam_x)
        for (int k = 0; k < 3; ++k) sheet.corner_uv[6 * f + 2 * k] += 0.5f;
    }
    return sheet;
  }
  if (scene != DemoScene::punch && scene != DemoScene::drape) return sheet;
  // Turned about x so that the normal +z becomes +y: (x, y, z) -> (x, z, 1 - y) (a rotation, so
  // the faces keep their orientation). The sheet's z is 0, so its nodes land on y = 0 and its
  // border rows on z = 0 and z = 1 exactly.
  for (std::size_t i = 0; i < sheet.node_pos.size(); i += 3) {
    const float y = sheet.node_pos[i + 1], z = sheet.node_pos[i + 2];
    sheet.node_pos[i + 1] = scene == DemoScene::drape ? z + static_cast<float>(demo_drape_height) : z;
    sheet.node_pos[i + 2] = 1.0f - y;
  }
  for (std::size_t i = 0; i < sheet.corner_normal.size(); i += 3) {
    const float y = sheet.corner_normal[i + 1], z = sheet.corner_normal[i + 2];
    sheet.corner_normal[i + 1] = z;
    sheet.corner_normal[i + 2] = -y;
  }
  return sheet;
}

namespace {

nlohmann::json box(std::array<double, 3> min, std::array<double, 3> max) {
  return {{"box", {{"min", min}, {"max", max}}}};
}

/// Keys moving from no offset at the start to `offset` at the end of the last frame.
nlohmann::json linear_keys(std::array<double, 3> offset) {
  return nlohmann::json::array(
      {{{"frame", 0}, {"offset", {0.0, 0.0, 0.0}}}, {{"frame", demo_frames}, {"offset", offset}}});
}

}  // namespace

ColliderMesh make_box_collider(std::array<double, 3> centre, double half, int n) {
  ColliderMesh box;
  box.file = "(demo box)";
  std::vector<float> v;
  // Each side: a grid of (n + 1)² vertices on the face whose outward normal is ±axis `a`.
  for (int a = 0; a < 3; ++a)
    for (int sign = -1; sign <= 1; sign += 2) {
      const int u = (a + 1) % 3, w = (a + 2) % 3;
      const index_t first = static_cast<index_t>(v.size() / 3);
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
          std::array<double, 3> p{};
          p[a] = centre[a] + sign * half;
          p[u] = centre[u] + half * (2.0 * i / n - 1);
          p[w] = centre[w] + half * (2.0 * j / n - 1);
          for (double c : p) v.push_back(static_cast<float>(c));
        }
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const index_t p00 = first + j * (n + 1) + i, p10 = p00 + 1, p01 = p00 + n + 1, p11 = p01 + 1;
          // (u, w, a) is right-handed: counter-clockwise about +a is u then w.
          if (sign > 0)
            box.face_nodes.insert(box.face_nodes.end(), {p00, p10, p11, p00, p11, p01});
          else
            box.face_nodes.insert(box.face_nodes.end(), {p00, p11, p10, p00, p01, p11});
        }
    }
  box.frames.push_back(std::move(v));
  return box;
}

CutScript demo_script(DemoScene scene) {
  if (scene == DemoScene::paper) return demo_script();
  const nlohmann::json tearing = {{"stretch", demo_tear_stretch}};
  nlohmann::json script = {{"version", 1}, {"frames", demo_frames}};
  if (scene == DemoScene::pull) {
    // The notch: from below the bottom border up to a quarter of the sheet, so the tear starts
    // at its tip and runs up across the middle.
    script["cuts"] =
        nlohmann::json::array({{{"frame", 1}, {"space", "rest-xy"}, {"polyline", {{0.5, -0.1}, {0.5, 0.25}}}}});
    nlohmann::json left = box({-1.0, -1.0, -1.0}, {0.04, 2.0, 1.0});
    left["keys"] = linear_keys({-demo_pull_distance, 0.0, 0.0});
    nlohmann::json right = box({0.96, -1.0, -1.0}, {2.0, 2.0, 1.0});
    right["keys"] = linear_keys({demo_pull_distance, 0.0, 0.0});
    script["simulation"] = {{"fps", demo_fps},
                            {"gravity", {0.0, 0.0, 0.0}},
                            {"pins", nlohmann::json::array({left, right})},
                            {"tearing", tearing}};
  } else if (scene == DemoScene::grain) {
    const double d = demo_pull_distance / std::sqrt(2.0);
    nlohmann::json left = box({-1.0, -1.0, -1.0}, {0.04, 2.0, 1.0});
    left["keys"] = linear_keys({-d, -d, 0.0});
    nlohmann::json right = box({0.96, -1.0, -1.0}, {2.0, 2.0, 1.0});
    right["keys"] = linear_keys({d, d, 0.0});
    nlohmann::json woven = tearing;
    woven["weave"] = {{"warp", {0.0, 1.0}}, {"weft_strength", demo_grain_weft_strength}};
    woven["seam_strength"] = demo_grain_seam_strength;
    script["simulation"] = {{"fps", demo_fps},
                            {"gravity", {0.0, 0.0, 0.0}},
                            {"pins", nlohmann::json::array({left, right})},
                            {"tearing", woven}};
  } else if (scene == DemoScene::punch) {
    // The four border rows of the horizontal sheet lie exactly on x = 0, x = 1, z = 0 and z = 1;
    // the next rows are more than 5 mm inside at the high resolution.
    const nlohmann::json pins = nlohmann::json::array({
        box({-1.0, -1.0, -1.0}, {0.001, 1.0, 2.0}),
        box({0.999, -1.0, -1.0}, {2.0, 1.0, 2.0}),
        box({-1.0, -1.0, -1.0}, {2.0, 1.0, 0.001}),
        box({-1.0, -1.0, 0.999}, {2.0, 1.0, 2.0}),
    });
    nlohmann::json sphere = {{"sphere", {{"center", {0.5, demo_punch_start_y, 0.5}}, {"radius", demo_punch_radius}}}};
    sphere["keys"] = linear_keys({0.0, demo_punch_rise, 0.0});
    script["simulation"] = {{"fps", demo_fps},
                            {"gravity", {0.0, -9.81, 0.0}},
                            {"pins", pins},
                            {"colliders", nlohmann::json::array({sphere})},
                            {"collision", {{"self", true}, {"thickness", demo_collision_thickness}}},
                            {"tearing", tearing}};
  } else {
    // drape: the corner caught, a floor under the box; the box is added below (it is no file).
    const nlohmann::json floor = {{"plane", {{"point", {0.0, -0.3, 0.0}}, {"normal", {0.0, 1.0, 0.0}}}}};
    script["simulation"] = {{"fps", demo_fps},
                            {"gravity", {0.0, -9.81, 0.0}},
                            {"pins", nlohmann::json::array({box({-1.0, -1.0, -1.0}, {0.04, 2.0, 0.04})})},
                            {"colliders", nlohmann::json::array({floor})},
                            {"collision", {{"self", true}, {"thickness", demo_collision_thickness}, {"friction", 0.3}}},
                            {"tearing", tearing}};
  }
  CutScript parsed = parse_cut_script(script.dump(), std::string("(demo scene: ") + to_string(scene) + ")");
  if (scene == DemoScene::drape) {
    Collider body;
    body.kind = Collider::Kind::mesh;
    body.mesh = std::make_shared<const ColliderMesh>(make_box_collider({0.5, 0.0, 0.5}, demo_drape_box_half, 8));
    body.pivot = {0.5, 0.0, 0.5};
    body.key_path = "simulation.colliders[1]";
    Key start, end;
    end.frame = demo_frames;
    end.degrees = demo_drape_turn;
    body.keys = {start, end};
    parsed.simulation->colliders.push_back(std::move(body));
  }
  return parsed;
}

}  // namespace tear
