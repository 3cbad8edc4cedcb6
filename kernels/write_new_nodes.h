// tear kernels: the new nodes (paper §2.2, write step): each element writes the provenance of its
// copies (up to three old nodes and weights), then every new node gathers its state from them.
#pragma once

#include "cut_info.h"

namespace tear::kernels {

/// Provenance of new nodes: [new_node_count * 3] old node indices (-1 unused) and weights.
struct NodeSources {
  index_t* node_source;
  float* node_source_weight;
  TEAR_HD void write(index_t first, index_t count, index_t a, index_t b, index_t c, float wa, float wb, float wc) const {
    for (index_t i = first; i < first + count; ++i) {
      node_source[3 * i] = a;
      node_source[3 * i + 1] = b;
      node_source[3 * i + 2] = c;
      node_source_weight[3 * i] = wa;
      node_source_weight[3 * i + 1] = wb;
      node_source_weight[3 * i + 2] = wc;
    }
  }
};

struct write_node_sources {
  const index_t* node_new_offset;
  NodeSources out;
  TEAR_HD void operator()(index_t n) const { out.write(node_new_offset[n], (node_new_offset[n + 1] - node_new_offset[n]), n, -1, -1, 1.f, 0.f, 0.f); }
};

/// An edge's copies sit at its cut point, linear between its nodes.
struct write_edge_sources {
  const index_t* edge_nodes;
  const float* edge_point_t;
  const index_t* edge_new_offset;
  NodeSources out;
  TEAR_HD void operator()(index_t e) const {
    const float t = edge_point_t[e];
    out.write(edge_new_offset[e], (edge_new_offset[e + 1] - edge_new_offset[e]), edge_nodes[2 * e], edge_nodes[2 * e + 1], -1, 1.f - t, t, 0.f);
  }
};

/// A face's copies sit at its face point, barycentric over its nodes.
struct write_face_sources {
  const index_t* face_nodes;
  const float* face_point_bary;
  const index_t* face_new_offset;
  NodeSources out;
  TEAR_HD void operator()(index_t f) const {
    out.write(face_new_offset[f], (face_new_offset[f + 1] - face_new_offset[f]), face_nodes[3 * f], face_nodes[3 * f + 1], face_nodes[3 * f + 2],
              face_point_bary[3 * f], face_point_bary[3 * f + 1], face_point_bary[3 * f + 2]);
  }
};

/// New node state by interpolation: a gather over its sources, in a fixed order.
struct interpolate_nodes {
  const index_t* node_source;
  const float* node_source_weight;
  const float* old_value;  ///< [old_node_count * 3]
  float* new_value;        ///< [new_node_count * 3]
  TEAR_HD void operator()(index_t i) const {
    float v[3] = {0, 0, 0};
    for (int s = 0; s < 3; ++s) {
      const index_t n = node_source[3 * i + s];
      if (n < 0) continue;
      const float w = node_source_weight[3 * i + s];
      if (s == 0 && w == 1.f) {  // a copy: bit-exact
        for (int d = 0; d < 3; ++d) v[d] = old_value[3 * n + d];
        break;
      }
      for (int d = 0; d < 3; ++d) v[d] += w * old_value[3 * n + d];
    }
    for (int d = 0; d < 3; ++d) new_value[3 * i + d] = v[d];
  }
};

}  // namespace tear::kernels
