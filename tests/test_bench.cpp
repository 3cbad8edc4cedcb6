// `tear bench` as a smoke test on small sizes: every part runs and reports sane numbers in its JSON.
// No time is asserted.
#include <string>

#include <nlohmann/json.hpp>

#include "catch.h"
#include "cli_support.h"

using tear::test::quoted;
using tear::test::Run;
using tear::test::TempDir;

TEST_CASE("bench: every part runs on small sizes and writes its numbers", "[cli][bench]") {
  TempDir dir;
  const auto json_path = dir / "bench.json";
#if defined(TEAR_SANITIZED)
  // The sanitizers look at the code: the tear and collide parts' scenes (48 frames each, many
  // minutes under them) are left to their own tests ([tearing], [collision]), which run the same
  // passes there.
  const std::string parts = " --only remesh,pd,scene,io";
#else
  const std::string parts;
#endif
  const Run run = dir.tear("bench --device cpu --faces 2822,9022 --repeats 1 --warmup 0 --iterations 10 "
                           "--resolutions low" + parts + " --json " + quoted(json_path));
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  CHECK(run.out.find("remesh:") != std::string::npos);
  CHECK(run.out.find("solver:") != std::string::npos);
  CHECK(run.out.find("scene:") != std::string::npos);
  const nlohmann::json doc = nlohmann::json::parse(tear::test::read_bytes(json_path));
  CHECK(doc.at("iterations") == 10);
  CHECK(doc.at("copy_bandwidth_bytes_per_s").get<double>() > 0);

  const auto& remesh = doc.at("remesh");
  REQUIRE(remesh.size() == 2);
  for (const auto& row : remesh) {
    CHECK(row.at("device") == "cpu");
    CHECK(row.at("remesh_ms").get<double>() > 0);
    CHECK(row.at("faces_after").get<int>() > row.at("faces").get<int>());  // the zigzag split faces
    // The cloth's arrays alone are tens of bytes per face; a cut's working memory stays within a
    // few hundred.
    const double per_face = row.at("peak_bytes").get<double>() / row.at("faces").get<double>();
    CHECK(per_face > 50);
    CHECK(per_face < 1000);
  }

  const auto& pd = doc.at("pd");
  REQUIRE(pd.size() == 2);
  for (const auto& row : pd) {
    INFO(row.dump());
    CHECK(row.at("iterations") == 10);
    const double nodes = row.at("nodes").get<double>();
    CHECK(nodes > row.at("faces").get<double>() / 2);  // a sheet has about half as many nodes as faces
    CHECK(row.at("constraints").get<double>() > 2 * nodes);
    const double step = row.at("step_ms").get<double>();
    CHECK(step > 0);
    CHECK(row.at("iteration_ms").get<double>() == Approx(step / 10));
    CHECK(row.at("node_iterations_per_s").get<double>() == Approx(nodes * 10 / (step * 1e-3)));
    // At least the state and the springs: 4 iterates and 3 edges per node.
    CHECK(row.at("bytes_per_iteration").get<double>() > 100 * nodes);
    CHECK(row.at("floor_ms").get<double>() > 0);
    CHECK(row.at("peak_bytes").get<double>() > 100 * nodes);
  }
  CHECK(pd[1].at("nodes").get<int>() > pd[0].at("nodes").get<int>());

  const auto& scene = doc.at("scene");
  REQUIRE(scene.size() == 1);
  CHECK(scene[0].at("resolution") == "low");
  CHECK(scene[0].at("frames") == 48);
  CHECK(scene[0].at("iterations") == 10);
  CHECK(scene[0].at("faces_end").get<int>() > scene[0].at("faces_start").get<int>());
  CHECK(scene[0].at("frame_ms_max").get<double>() >= scene[0].at("frame_ms_mean").get<double>());
  CHECK(scene[0].at("simulation_ms").get<double>() > 0);
}

TEST_CASE("bench: --only runs the named parts", "[cli][bench]") {
  TempDir dir;
  const auto json_path = dir / "bench.json";
  const Run run = dir.tear("bench --device cpu --faces 2822 --repeats 1 --warmup 0 --iterations 5 --only pd --json " +
                           quoted(json_path));
  REQUIRE(run.exit_code == 0);
  const nlohmann::json doc = nlohmann::json::parse(tear::test::read_bytes(json_path));
  CHECK(doc.contains("pd"));
  CHECK_FALSE(doc.contains("remesh"));
  CHECK_FALSE(doc.contains("scene"));
}

TEST_CASE("bench: bad part and resolution names are usage errors", "[cli][bench]") {
  TempDir dir;
  for (const std::string args : {"bench --device cpu --only everything", "bench --device cpu --resolutions huge",
                                 "bench --device cpu --iterations 0", "bench --device cpu --warmup -1"}) {
    INFO("tear " << args);
    const Run run = dir.tear(args);
    CHECK(run.exit_code == 1);
    CHECK(run.out.empty());
    CHECK(run.err.rfind("tear: ", 0) == 0);
  }
}
