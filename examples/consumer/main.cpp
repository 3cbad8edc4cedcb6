// Cuts a sheet in two with libtear and checks what the identity guarantees: the sheet's nodes keep
// their indices, the cut appends, and every node knows the input face it came from. Exits 0 when
// all of that holds.
#include <algorithm>
#include <cstdio>
#include <tear/tear.h>

int main() {
  try {
    const tear::Mesh sheet = tear::make_sheet();  // the paper's 2,822-face square, 1 m
    tear::Cloth cloth(sheet, tear::Device::cpu);
    tear::CutLine line;
    line.polyline = {{-0.1, 0.5}, {1.1, 0.5}};  // across the rest shape's xy plane
    const tear::CutStats stats = cloth.cut({line});
    const tear::Mesh cut = cloth.mesh();
    const bool kept = std::equal(sheet.node_pos.begin(), sheet.node_pos.end(), cloth.node_rest().begin());
    std::printf("%d nodes, %d faces -> %d nodes, %d faces; first %d nodes kept: %s; %zu torn edges\n",
                stats.nodes_before, stats.faces_before, stats.nodes_after, stats.faces_after, sheet.node_count(),
                kept ? "yes" : "no", cut.torn_edge_nodes.size() / 2);
    return kept && stats.nodes_after > stats.nodes_before && cut.node_origin_face.size() == std::size_t(cut.node_count()) ? 0 : 1;
  } catch (const tear::Error& e) {
    std::fprintf(stderr, "tear_consumer: %s\n", e.what());
    return 1;
  }
}
