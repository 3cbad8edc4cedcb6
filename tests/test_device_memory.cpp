// The account of GPU memory (tear/device.h): what a cloth holds is counted while it lives and given
// back when it goes; memory of the CPU backend is not counted.
#include "catch.h"
#include "tear/cloth.h"
#include "tear/device.h"
#include "tear/make_sheet.h"

namespace {
tear::Mesh sheet() {
  tear::SheetOptions o;
  o.face_count = 2000;
  return tear::make_sheet(o);
}
}  // namespace

TEST_CASE("device memory: the CPU backend is not counted", "[device]") {
  const std::size_t before = tear::device_memory_in_use();
  {
    tear::Cloth cloth(sheet(), tear::Device::cpu);
    CHECK(tear::device_memory_in_use() == before);
  }
  CHECK(tear::device_memory_in_use() == before);
}

TEST_CASE("device memory: a cloth's GPU arrays are counted while it lives", "[device]") {
  if (!tear::cuda_available()) {
    WARN("no GPU: GPU memory accounting not checked");
    return;
  }
  const tear::Mesh mesh = sheet();
  tear::synchronize(tear::Device::cuda);
  const std::size_t before = tear::device_memory_in_use();
  tear::reset_device_memory_peak();
  {
    tear::Cloth cloth(mesh, tear::Device::cuda);
    const std::size_t held = tear::device_memory_in_use() - before;
    // At least the face nodes and the three node arrays (positions, rest positions, velocities).
    CHECK(held >= mesh.face_nodes.size() * 4 + 3 * mesh.node_pos.size() * 4);
    CHECK(tear::device_memory_peak() >= tear::device_memory_in_use());
  }
  CHECK(tear::device_memory_in_use() == before);
  CHECK(tear::device_memory_peak() > before);
}
