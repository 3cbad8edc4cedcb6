// tear kernels: the new nodes (paper §2.2, write step): each element writes the provenance of its
// copies (up to three old nodes and weights), then every node attribute is carried by a gather
// over that provenance (carry_attributes.h).
//
// Node n keeps index n for its first copy; the rest are appended after the old nodes. Example: 4
// old nodes, node 2 with one extra copy, edge (1, 3) with a point at t = 0.25 and two copies:
//   node_source 0 1 2 3 | 2 | 1 1     node_source (2nd) -1 -1 -1 -1 | -1 | 3 3
//   weights     1 1 1 1 | 1 | .75 .75                   0  0  0  0 |  0 | .25 .25
#pragma once

#include "cut_info.h"

namespace tear::kernels {

/// Provenance of new nodes: [new_node_count * 3] old node indices (-1 unused) and weights.
struct NodeSources {
  index_t* node_source;
  float* node_source_weight;
  TEAR_HD void write(index_t i, index_t a, index_t b, index_t c, float wa, float wb, float wc) const {
    node_source[3 * i] = a;
    node_source[3 * i + 1] = b;
    node_source[3 * i + 2] = c;
    node_source_weight[3 * i] = wa;
    node_source_weight[3 * i + 1] = wb;
    node_source_weight[3 * i + 2] = wc;
  }
  TEAR_HD void write(index_t first, index_t count, index_t a, index_t b, index_t c, float wa, float wb, float wc) const {
    for (index_t i = first; i < first + count; ++i) write(i, a, b, c, wa, wb, wc);
  }
};

/// Node n's first copy is node n itself; its extra copies sit after the old nodes.
struct write_node_sources {
  const index_t* node_extra_offset;
  index_t old_node_count;
  NodeSources out;
  TEAR_HD void operator()(index_t n) const {
    out.write(n, n, -1, -1, 1.f, 0.f, 0.f);
    out.write(old_node_count + node_extra_offset[n], node_extra_offset[n + 1] - node_extra_offset[n], n, -1, -1, 1.f, 0.f, 0.f);
  }
};

/// An edge's copies sit at its cut point, linear between its nodes.
struct write_edge_sources {
  const index_t* edge_nodes;
  const float* edge_point_t;
  const index_t* edge_new_offset;
  index_t old_node_count;
  NodeSources out;
  TEAR_HD void operator()(index_t e) const {
    const float t = edge_point_t[e];
    out.write(old_node_count + edge_new_offset[e], edge_new_offset[e + 1] - edge_new_offset[e], edge_nodes[2 * e],
              edge_nodes[2 * e + 1], -1, 1.f - t, t, 0.f);
  }
};

/// A face's copies sit at its face point, barycentric over its nodes.
struct write_face_sources {
  const index_t* face_nodes;
  const float* face_point_bary;
  const index_t* face_new_offset;
  index_t old_node_count;
  NodeSources out;
  TEAR_HD void operator()(index_t f) const {
    out.write(old_node_count + face_new_offset[f], face_new_offset[f + 1] - face_new_offset[f], face_nodes[3 * f],
              face_nodes[3 * f + 1], face_nodes[3 * f + 2], face_point_bary[3 * f], face_point_bary[3 * f + 1],
              face_point_bary[3 * f + 2]);
  }
};

}  // namespace tear::kernels
