// tear: union-find over element indices, shared by host code that groups nodes or faces.
#pragma once

#include <numeric>
#include <vector>

#include "tear/mesh.h"

namespace tear {

/// Union-find with path halving. The root of a set is always its lowest index, so the result does
/// not depend on the order in which pairs are united.
class DisjointSets {
 public:
  explicit DisjointSets(index_t count) : parent_(static_cast<std::size_t>(count)) {
    std::iota(parent_.begin(), parent_.end(), index_t(0));
  }
  index_t find(index_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void unite(index_t a, index_t b) {
    a = find(a);
    b = find(b);
    if (a < b) parent_[b] = a;
    if (b < a) parent_[a] = b;
  }

 private:
  std::vector<index_t> parent_;
};

}  // namespace tear
