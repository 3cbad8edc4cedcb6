// The thread of the host's that builds crack growth's view beside the device's next substep
// (lib/src/backend/host_worker.h): tasks in turn on a thread of its own, results and errors in their
// futures, the task under way finished at the end; a view built there the same as one built here,
// and a view built in the memory of the one before the same as one built anew.
#include <future>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "backend/host_worker.h"
#include "catch.h"
#include "cloth/crack_growth.h"
#include "tear/cloth.h"
#include "tear/cut_script.h"
#include "test_support.h"
#include "torn_pulls.h"

using tear::backend::HostWorker;
using namespace tear::test::pulls;

TEST_CASE("host worker: tasks run in turn on one thread of its own, their results and errors in their futures",
          "[tearing]") {
  HostWorker<int> worker;
  std::vector<int> order;  // written by the worker's thread only, read after the last future
  std::vector<std::future<int>> results;
  std::thread::id ran_on[2];
  for (int i = 0; i < 20; ++i) {
    std::packaged_task<int()> task([i, &order, &ran_on] {
      if (i < 2) ran_on[i] = std::this_thread::get_id();
      if (i == 7) throw std::runtime_error("task 7 failed");
      order.push_back(i);
      return i * i;
    });
    results.push_back(task.get_future());
    worker.run(std::move(task));
  }
  for (int i = 0; i < 20; ++i) {
    if (i == 7) {
      CHECK_THROWS_WITH(results[i].get(), "task 7 failed");
      continue;
    }
    CHECK(results[i].get() == i * i);
  }
  std::vector<int> expected;
  for (int i = 0; i < 20; ++i)
    if (i != 7) expected.push_back(i);
  CHECK(order == expected);
  CHECK(ran_on[0] == ran_on[1]);
  CHECK(ran_on[0] != std::this_thread::get_id());
}

TEST_CASE("host worker: its end waits for the task under way, and a task queued behind it runs or is dropped",
          "[tearing]") {
  std::promise<void> started, release;
  std::shared_future<void> go = release.get_future().share();
  std::future<int> first, second;
  std::thread releaser;  // lets the first task end while the worker's end waits for it
  {
    HostWorker<int> worker;
    std::packaged_task<int()> one([&started, go] {
      started.set_value();
      go.wait();
      return 1;
    });
    std::packaged_task<int()> two([] { return 2; });
    first = one.get_future();
    second = two.get_future();
    worker.run(std::move(one));
    worker.run(std::move(two));
    started.get_future().wait();  // the first is under way, the second queued
    releaser = std::thread([&release] { release.set_value(); });
  }
  releaser.join();
  CHECK(first.get() == 1);
  // Released before or after the end began: either it ran, or its promise was broken.
  bool ran = false, dropped = false;
  try {
    ran = second.get() == 2;
  } catch (const std::future_error& e) {
    dropped = e.code() == std::future_errc::broken_promise;
  }
  CHECK((ran || dropped));
}

TEST_CASE("host worker: crack growth's view built on it is the one built on the calling thread", "[tearing]") {
  tear::Cloth cloth(sheet(2000, true), tear::test::test_device());
  tear::CutLine line;
  line.polyline = {{0.5, -0.1}, {0.5, 0.4}};
  cloth.cut({line}, tear::CutOptions{});
  const tear::CrackMesh mesh = crack_mesh_of(cloth);
  tear::TearingOptions options;
  options.stretch = 1.3;
  options.radius = 0.05;
  const tear::CrackField here(mesh, options);
  HostWorker<tear::CrackProbes> worker;
  std::packaged_task<tear::CrackProbes()> task([mesh, options] { return tear::CrackField(mesh, options).probes(); });
  std::future<tear::CrackProbes> built = task.get_future();
  worker.run(std::move(task));
  const tear::CrackProbes there = built.get(), own = here.probes();
  REQUIRE(!here.tips().empty());
  CHECK(there.count() == own.count());
  CHECK(there.offsets == own.offsets);
  CHECK(there.faces == own.faces);
  CHECK(there.normal == own.normal);
  CHECK(there.limit == own.limit);
  CHECK(there.gain == own.gain);
  CHECK(there.may_start == own.may_start);
  CHECK(there.cell_key == own.cell_key);
  CHECK(there.cell_face == own.cell_face);
  CHECK(there.cell == own.cell);
  CHECK(there.radius == own.radius);
}

TEST_CASE("crack growth: a view built in the memory of the one before is the view built anew", "[tearing]") {
  // The view before: of a sheet with a short slit; the view after: of the same sheet cut further
  // and across (more faces, nodes and border), and of the sheet before the slit (fewer).
  tear::TearingOptions options;
  options.stretch = 1.3;
  options.radius = 0.05;
  tear::Cloth small(sheet(2000, true), tear::test::test_device());
  const tear::CrackMesh before_cut = crack_mesh_of(small);
  tear::CutLine slit;
  slit.polyline = {{0.5, -0.1}, {0.5, 0.3}};
  small.cut({slit}, tear::CutOptions{});
  const tear::CrackMesh slit_mesh = crack_mesh_of(small);
  tear::CutLine across;
  across.polyline = {{-0.1, 0.7}, {0.6, 0.65}};
  small.cut({across}, tear::CutOptions{});
  const tear::CrackMesh cut_mesh = crack_mesh_of(small);
  for (const tear::CrackMesh* next : {&cut_mesh, &before_cut}) {
    tear::CrackField old(slit_mesh, options);
    tear::CrackMesh reused = old.release_mesh();
    reused.node_rest = next->node_rest;
    reused.face_nodes = next->face_nodes;
    reused.topo = next->topo;
    const tear::CrackField recycled(std::move(reused), options, &old), fresh(*next, options);
    const tear::CrackProbes a = recycled.probes(), b = fresh.probes();
    INFO((next == &cut_mesh ? "cut further" : "uncut"));
    CHECK(recycled.tips() == fresh.tips());
    CHECK(recycled.node_pieces() == fresh.node_pieces());
    CHECK(a.offsets == b.offsets);
    CHECK(a.faces == b.faces);
    CHECK(a.normal == b.normal);
    CHECK(a.limit == b.limit);
    CHECK(a.may_start == b.may_start);
    CHECK(a.cell_key == b.cell_key);
    CHECK(a.cell_face == b.cell_face);
    std::vector<float> pos = next->node_rest;
    for (std::size_t i = 0; i < pos.size(); i += 3) pos[i] *= 1.4f;  // pulled along x: some tip may cut
    const tear::CrackPlan pa = recycled.plan(pos), pb = fresh.plan(pos);
    CHECK(pa.events > 0);  // stretched past the limit everywhere: a tip runs or a crack starts
    CHECK(pa.events == pb.events);
    CHECK(pa.length == pb.length);
    REQUIRE(pa.cuts.size() == pb.cuts.size());
    for (std::size_t c = 0; c < pa.cuts.size(); ++c) CHECK(pa.cuts[c].polyline == pb.cuts[c].polyline);
  }
}
