#include "tear/demo_scene.h"

#include <array>
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

}  // namespace tear
