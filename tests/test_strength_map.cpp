// A painted strength (`simulation.tearing.strength_map`, docs/simulation.md, *Tearing*): the map
// sampled in UV space, read from image files, every bad path or file refused naming the key, and a
// strip pulled at its ends tearing where the map makes it weak.
#include <stb_image_write.h>

#include <cmath>
#include <string>
#include <vector>

#include "catch.h"
#include "cli_support.h"
#include "cloth/crack_growth.h"
#include "tear/cut_script.h"
#include "tear/error.h"
#include "torn_pulls.h"

using namespace tear::test::pulls;
namespace fs = std::filesystem;

namespace {

/// A greyscale PNG of `width` × `height` from `value(i, j)` in [0, 1] (i the column, j the row from
/// the top), at `path`.
template <class F>
void write_png(const std::string& path, int width, int height, F&& value) {
  std::vector<unsigned char> texels(static_cast<std::size_t>(width) * height);
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i)
      texels[static_cast<std::size_t>(j) * width + i] = static_cast<unsigned char>(std::lround(255 * value(i, j)));
  REQUIRE(stbi_write_png(path.c_str(), width, height, 1, texels.data(), width) != 0);
}

std::string pull_script(const std::string& tearing) {
  return R"({"version": 1, "frames": 24, "simulation": {"gravity": [0, 0, 0], "substeps": 4,
    "iterations": 200, "pins": [
      {"box": {"min": [-1, -1, -1], "max": [0.04, 2, 1]}, "keys": [{"frame": 0, "offset": [0, 0, 0]}, {"frame": 24, "offset": [-0.25, 0, 0]}]},
      {"box": {"min": [0.96, -1, -1], "max": [2, 2, 1]}, "keys": [{"frame": 0, "offset": [0, 0, 0]}, {"frame": 24, "offset": [0.25, 0, 0]}]}],
    "tearing": {)" + tearing + "}}}";
}

/// The message of the input error parsing `script_text` as `script_path` throws.
std::string parse_error(const std::string& script_text, const std::string& script_path) {
  try {
    tear::parse_cut_script(script_text, script_path);
  } catch (const tear::Error& e) {
    CHECK(e.kind() == tear::ErrorKind::input);
    return e.what();
  }
  FAIL("no error");
  return {};
}

}  // namespace

TEST_CASE("strength map: bilinear between texel centres in UV space, v up, repeating", "[tearing][strength_map]") {
  tear::StrengthMap map;
  map.width = 2;
  map.height = 2;
  map.value = {0.f, 1.f,    // top row: v near 1
               0.5f, 0.25f};  // bottom row
  CHECK(map.at(0.25, 0.75) == Approx(0.0));   // the top-left texel's centre
  CHECK(map.at(0.75, 0.75) == Approx(1.0));
  CHECK(map.at(0.25, 0.25) == Approx(0.5));   // bottom-left
  CHECK(map.at(0.5, 0.75) == Approx(0.5));    // between the top two
  CHECK(map.at(0.5, 0.5) == Approx((0 + 1 + 0.5 + 0.25) / 4.0));
  CHECK(map.at(1.25, -0.25) == Approx(map.at(0.25, 0.75)));  // UVs tile
  CHECK(map.at(0.0, 0.75) == Approx(0.5));    // the seam of the tile blends its two edges
}

TEST_CASE("strength map: read from a file beside the script, every bad one refused naming the key",
          "[tearing][strength_map]") {
  tear::test::TempDir dir;
  const std::string script = (dir / "shot.json").string();
  fs::create_directories(dir / "maps");
  // 4 × 2: columns 0..3 at 0, 1/3, 2/3, 1 on the top row, the bottom row the reverse.
  write_png((dir / "maps" / "ramp.png").string(), 4, 2, [](int i, int j) { return (j == 0 ? i : 3 - i) / 3.0; });
  const auto with_map = [](const std::string& value) {
    return pull_script(R"("stretch": 1.3, "strength_map": )" + value);
  };
  const tear::CutScript parsed = tear::parse_cut_script(with_map(R"("maps/ramp.png")"), script);
  const auto& map = parsed.simulation->tearing.strength_map;
  REQUIRE(map);
  CHECK(map->width == 4);
  CHECK(map->height == 2);
  CHECK(map->file == "maps/ramp.png");
  CHECK(map->value[1] == Approx(1 / 3.0).margin(0.5 / 255));
  CHECK(map->value[4] == Approx(1.0));
  CHECK(map->at(0.125, 0.75) == Approx(0.0));   // top-left texel: v = 1 is the image's top row

  const std::string key = "simulation.tearing.strength_map";
  const auto refused = [&](const std::string& value, const std::string& why) {
    const std::string message = parse_error(with_map(value), script);
    INFO(message);
    CHECK(message.find(script) != std::string::npos);
    CHECK(message.find(key) != std::string::npos);
    CHECK(message.find(why) != std::string::npos);
    CHECK(message.find('\n') == std::string::npos);
  };
  refused("0.5", "expected the path of a greyscale image");
  refused(R"("/etc/passwd")", "relative path");
  refused(R"("file:maps/ramp.png")", "relative path");
  refused(R"("../ramp.png")", "goes up");
  refused(R"("maps/../maps/ramp.png")", "goes up");
  refused(R"("maps/none.png")", "not a regular file");
  refused(R"("maps")", "not a regular file");
  fs::create_symlink("/etc/hostname", dir / "maps" / "outside.png");
  refused(R"("maps/outside.png")", "not a regular file in the script's folder");
  dir.file("maps/text.png", "this is not an image\n");
  refused(R"("maps/text.png")", "not an image");
  // A PNG header declaring 10000 × 10000 texels (no data), refused from the header before decoding.
  std::string header("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR\0\0\x27\x10\0\0\x27\x10\x08\x00\0\0\0", 29);
  header += std::string(4, '\0');
  dir.file("maps/huge.png", header);
  refused(R"("maps/huge.png")", "over the limit");
}

TEST_CASE("strength map: a mesh without UVs, or a map that makes a limit 1 or less, is refused naming the key",
          "[tearing][strength_map]") {
  tear::test::TempDir dir;
  const std::string script_path = (dir / "shot.json").string();
  write_png((dir / "grey.png").string(), 2, 2, [](int, int) { return 0.7; });
  write_png((dir / "light.png").string(), 2, 2, [](int, int) { return 0.9; });
  const tear::Mesh no_uvs = strip_mesh(false, false), with_uvs = strip_mesh(false, true);
  for (const std::string& tearing : {std::string(R"("stretch": 1.3, "strength_map": "light.png")"),
                                     std::string(R"("stretch": 1.3, "weave": {"warp": [0, 1]})")}) {
    const tear::CutScript script = tear::parse_cut_script(pull_script(tearing), script_path);
    INFO(tearing);
    try {
      tear::check_script_against_mesh(script, no_uvs, "strip.obj");
      FAIL("a mesh without UVs was accepted");
    } catch (const tear::Error& e) {
      const std::string message = e.what();
      INFO(message);
      CHECK(message.find("simulation.tearing.") != std::string::npos);
      CHECK(message.find("strip.obj has none") != std::string::npos);
    }
    CHECK_NOTHROW(tear::check_script_against_mesh(script, with_uvs, "strip.obj"));
  }
  // 0.7 × 1.3 = 0.91: every face would tear at rest.
  const tear::CutScript dark =
      tear::parse_cut_script(pull_script(R"("stretch": 1.3, "strength_map": "grey.png")"), script_path);
  try {
    tear::check_script_against_mesh(dark, with_uvs, "strip.obj");
    FAIL("a map that tears the cloth at rest was accepted");
  } catch (const tear::Error& e) {
    const std::string message = e.what();
    INFO(message);
    CHECK(message.find("simulation.tearing.strength_map: grey.png") != std::string::npos);
    CHECK(message.find("tear at rest") != std::string::npos);
  }
}

TEST_CASE("strength map: a strip pulled at its ends tears once, where the map paints it weak",
          "[tearing][strength_map][quality]") {
  // A uniform strip (u = x) whose map is 1 but for a soft band at 0.85 around u = `band`: the one
  // crack runs across the strip inside the band, wherever the band is.
  tear::test::TempDir dir;
  for (double band : {0.3, 0.7}) {
    INFO("band at u = " << band);
    const std::string name = "band" + std::to_string(int(band * 10)) + ".png";
    write_png((dir / name).string(), 200, 4, [&](int i, int) {
      const double u = (i + 0.5) / 200;
      return 1 - 0.15 * std::exp(-std::pow((u - band) / 0.04, 2));
    });
    const tear::Mesh input = strip_mesh(false, true);
    const Torn t = run(input, pull_script(R"("stretch": 1.3, "strength_map": ")" + name + "\""), pull_frames, 2,
                       (dir / "pull.json").string());
    CHECK(t.pieces == 2);
    check_clean(t, input);
    REQUIRE_FALSE(t.boundary.empty());
    double lo_x = 1e9, hi_x = -1e9;
    for (const auto& p : t.boundary) {
      lo_x = std::min(lo_x, p[0]);
      hi_x = std::max(hi_x, p[0]);
    }
    INFO("the crack spans x in [" << lo_x << ", " << hi_x << "]");
    CHECK(std::abs(0.5 * (lo_x + hi_x) - band) <= 0.05);
  }
}
