// tear kernels: the collision pass's broad phase grid (kernels/collision.h): boxes, the uniform
// grid's cells and keys, and its sorted entries.
#pragma once

#include <cmath>
#include <cstdint>

#include "hd.h"
#include "pd_math.h"

namespace tear::kernels {

TEAR_HD inline float min_of(float a, float b) { return b < a ? b : a; }
TEAR_HD inline float max_of(float a, float b) { return b > a ? b : a; }

/// An axis-aligned box.
struct Box {
  Vec3f lo, hi;
  TEAR_HD void add(Vec3f p) {
    lo = {min_of(lo.x, p.x), min_of(lo.y, p.y), min_of(lo.z, p.z)};
    hi = {max_of(hi.x, p.x), max_of(hi.y, p.y), max_of(hi.z, p.z)};
  }
  TEAR_HD void grow(float r) {
    lo = {lo.x - r, lo.y - r, lo.z - r};
    hi = {hi.x + r, hi.y + r, hi.z + r};
  }
  TEAR_HD bool overlaps(const Box& b) const {
    return lo.x <= b.hi.x && b.lo.x <= hi.x && lo.y <= b.hi.y && b.lo.y <= hi.y && lo.z <= b.hi.z && b.lo.z <= hi.z;
  }
  TEAR_HD static Box of(Vec3f p) { return {p, p}; }
};

/// The uniform grid of the broad phase: cells of side 1 / `inv_cell` from `origin`, at most 2²¹ a
/// side. An item is entered in every cell its box meets, up to `max_entry_cells` of them; a box
/// that meets more is entered once, under `everywhere`, which every query looks at. A pair met in
/// several cells is taken in one: the cell of the lowest corner of the two boxes' overlap.
struct CollisionGrid {
  Vec3f origin;
  float inv_cell;
  static constexpr std::int32_t side = 1 << 21;
  static constexpr std::uint64_t everywhere = ~std::uint64_t(0);

  TEAR_HD std::int32_t coord(float x, float o) const {
    const float c = floorf((x - o) * inv_cell);
    return c < 0.0f ? 0 : c >= static_cast<float>(side - 1) ? side - 1 : static_cast<std::int32_t>(c);
  }
  TEAR_HD void cells(const Box& b, std::int32_t lo[3], std::int32_t hi[3]) const {
    lo[0] = coord(b.lo.x, origin.x), lo[1] = coord(b.lo.y, origin.y), lo[2] = coord(b.lo.z, origin.z);
    hi[0] = coord(b.hi.x, origin.x), hi[1] = coord(b.hi.y, origin.y), hi[2] = coord(b.hi.z, origin.z);
  }
  TEAR_HD static std::uint64_t key(std::int32_t i, std::int32_t j, std::int32_t k) {
    return static_cast<std::uint64_t>(i) | static_cast<std::uint64_t>(j) << 21 | static_cast<std::uint64_t>(k) << 42;
  }
  TEAR_HD std::uint64_t cell_key(const Vec3f& p) const {
    return key(coord(p.x, origin.x), coord(p.y, origin.y), coord(p.z, origin.z));
  }
  static constexpr std::int64_t max_entry_cells = 64;
  /// The cells box `b` meets (`lo`..`hi`), and how many: 0 when it is entered under `everywhere`.
  TEAR_HD std::int64_t entry_cells(const Box& b, std::int32_t lo[3], std::int32_t hi[3]) const {
    // A box that is not finite, or far wider than a cell, is not walked cell by cell.
    const Vec3f extent = b.hi - b.lo;
    if (!(max_of(extent.x, max_of(extent.y, extent.z)) * inv_cell <= static_cast<float>(max_entry_cells))) return 0;
    cells(b, lo, hi);
    const std::int64_t n = static_cast<std::int64_t>(hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
    return n <= max_entry_cells ? n : 0;
  }
};

/// A sorted grid's entries: keys ascending (`everywhere` last), each with its item.
struct GridEntries {
  const std::uint64_t* keys;
  const index_t* items;
  index_t count;
  /// The first entry of `key` (or where it would be) among the first `end` entries.
  TEAR_HD index_t lower_bound(std::uint64_t key, index_t end) const {
    index_t lo = 0, hi = end;
    while (lo < hi) {
      const index_t mid = lo + (hi - lo) / 2;
      if (keys[mid] < key)
        lo = mid + 1;
      else
        hi = mid;
    }
    return lo;
  }
};

}  // namespace tear::kernels
