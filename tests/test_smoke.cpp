#include "catch.h"
#include "tear/topology.h"
#include "test_support.h"
TEST_CASE("topology: single triangle") {
  tear::Mesh m;
  m.node_pos = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  m.face_nodes = {0, 1, 2};
  auto t = tear::build_topology(m, tear::test::test_device());
  CHECK(t.edge_count == 3);
}
