#include <string>

#include "catch.h"
#include "tear/error.h"
#include "tear/frame_path.h"

using tear::ErrorKind;
using tear::expand_frame_path;
using tear::FramePattern;

namespace {

/// The kind of the `tear::Error` that `f` throws; fails the test when it throws nothing.
template <class F>
ErrorKind error_kind(F f, std::string* message = nullptr) {
  try {
    f();
  } catch (const tear::Error& e) {
    if (message) *message = e.what();
    return e.kind();
  }
  FAIL("no tear::Error thrown");
  return ErrorKind::runtime;
}

}  // namespace

TEST_CASE("frame_path: a run of # is the zero-padded frame number", "[run]") {
  CHECK(expand_frame_path("out/cloth.####.obj", 1) == "out/cloth.0001.obj");
  CHECK(expand_frame_path("out/cloth.####.obj", 42) == "out/cloth.0042.obj");
  CHECK(expand_frame_path("cloth.#.ply", 7) == "cloth.7.ply");
  CHECK(expand_frame_path("cloth_###.glb", 0) == "cloth_000.glb");
}

TEST_CASE("frame_path: a number longer than the run of # is written whole", "[run]") {
  CHECK(expand_frame_path("c.##.obj", 123) == "c.123.obj");
  CHECK(expand_frame_path("c.#.obj", 10000) == "c.10000.obj");
}

TEST_CASE("frame_path: {frame} and {frame:0N} placeholders", "[run]") {
  CHECK(expand_frame_path("out/cloth.{frame}.obj", 7) == "out/cloth.7.obj");
  CHECK(expand_frame_path("out/cloth.{frame:04}.obj", 7) == "out/cloth.0007.obj");
  CHECK(expand_frame_path("out/cloth.{frame:01}.obj", 12) == "out/cloth.12.obj");
  CHECK(expand_frame_path("out/cloth.{frame:09}.obj", 12) == "out/cloth.000000012.obj");
}

TEST_CASE("frame_path: every placeholder gets the number, folders included", "[run]") {
  CHECK(expand_frame_path("f####/cloth.{frame:03}.obj", 5) == "f0005/cloth.005.obj");
  CHECK(FramePattern("f####/cloth.obj").has_frame_number());
}

TEST_CASE("frame_path: other braces are literal", "[run]") {
  CHECK(expand_frame_path("{shot}/cloth.####.obj", 3) == "{shot}/cloth.0003.obj");
  CHECK(expand_frame_path("a{fram}.#.obj", 3) == "a{fram}.3.obj");
  CHECK_FALSE(FramePattern("{shot}/cloth.obj").has_frame_number());
}

TEST_CASE("frame_path: malformed {frame} placeholders are usage errors naming the pattern", "[run]") {
  for (const char* pattern : {"c.{frame:4}.obj", "c.{frame:x}.obj", "c.{frame.obj", "c.{frame:00}.obj",
                              "c.{frame:010}.obj", "c.{frames}.obj", "c.{frame:}.obj"}) {
    INFO(pattern);
    std::string message;
    CHECK(error_kind([&] { FramePattern{pattern}; }, &message) == ErrorKind::usage);
    CHECK(message.find(pattern) != std::string::npos);
  }
}

TEST_CASE("frame_path: an empty pattern is a usage error", "[run]") {
  CHECK(error_kind([] { FramePattern{""}; }) == ErrorKind::usage);
}

TEST_CASE("frame_path: a pattern without frame number is a single frame's file name", "[run]") {
  const FramePattern pattern("out/cloth.obj");
  CHECK_FALSE(pattern.has_frame_number());
  CHECK(pattern.path(1) == "out/cloth.obj");
  CHECK_NOTHROW(pattern.check(1));
  std::string message;
  CHECK(error_kind([&] { pattern.check(2); }, &message) == ErrorKind::usage);
  CHECK(message.find("out/cloth.obj") != std::string::npos);
  CHECK(message.find("2 frames") != std::string::npos);
}

TEST_CASE("frame_path: check refuses an extension write_mesh cannot write", "[run]") {
  CHECK_NOTHROW(FramePattern("out/c.####.obj").check(3));
  CHECK_NOTHROW(FramePattern("out/c.####.PLY").check(3));
  CHECK_NOTHROW(FramePattern("out/c.####.gltf").check(3));
  CHECK_NOTHROW(FramePattern("out/c.####.glb").check(3));
  std::string message;
  CHECK(error_kind([] { FramePattern("out/c.####.stl").check(3); }, &message) == ErrorKind::usage);
  CHECK(message.find(".stl") != std::string::npos);
  CHECK(message.find("'out/c.####.stl'") != std::string::npos);  // the pattern, not frame 1's path
  CHECK(error_kind([] { FramePattern("out/c####").check(3); }) == ErrorKind::usage);
  CHECK(error_kind([] { FramePattern("out/####/").check(3); }) == ErrorKind::usage);
}
