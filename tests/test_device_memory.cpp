// The account of memory (tear/device.h): what a cloth's arrays hold is counted against its backend
// while the cloth lives and given back when it goes.
#include "catch.h"
#include "tear/cloth.h"
#include "tear/device.h"
#include "tear/make_sheet.h"
#include "test_support.h"

TEST_CASE("memory: a cloth's arrays are counted against its backend while it lives", "[device]") {
  const tear::Device device = tear::test::test_device();
  const tear::Device other = device == tear::Device::cuda ? tear::Device::cpu : tear::Device::cuda;
  tear::SheetOptions o;
  o.face_count = 2000;
  const tear::Mesh mesh = tear::make_sheet(o);
  tear::synchronize(device);
  const std::size_t before = tear::memory_in_use(device), other_before = tear::memory_in_use(other);
  tear::reset_memory_peak(device);
  {
    tear::Cloth cloth(mesh, device);
    const std::size_t held = tear::memory_in_use(device) - before;
    // At least the face nodes and the three node arrays (positions, rest positions, velocities).
    CHECK(held >= mesh.face_nodes.size() * 4 + 3 * mesh.node_pos.size() * 4);
    CHECK(tear::memory_peak(device) >= tear::memory_in_use(device));
    CHECK(tear::memory_in_use(other) == other_before);
    tear::CutLine line;
    line.polyline = {{-0.1, 0.5}, {1.1, 0.5}};
    cloth.cut({line});
    CHECK(tear::memory_peak(device) - before > held);  // the cut's working arrays came on top
  }
  CHECK(tear::memory_in_use(device) == before);
  CHECK(tear::memory_peak(device) > before);
}
