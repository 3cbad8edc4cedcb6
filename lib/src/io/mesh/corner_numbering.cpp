#include "io/mesh/corner_numbering.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>
#include <vector>

#include "topology/lower_to.h"

namespace tear {
namespace {

/// Equal as numbers: -0 and +0 are one value (Blender writes both in normals), NaN is one value.
bool same_value(float a, float b) { return a == b || (std::isnan(a) && std::isnan(b)); }

/// Finds, for corners met in increasing order, the first corner met with the same value: open
/// addressing on the low bits of the value's hash, at most half full; a slot keeps its corner and
/// the low half of the hash, so that most misses compare no values.
template <int width>
class FirstUse {
 public:
  FirstUse(const float* values, std::size_t expected) : values_(values) {
    while (capacity_ < expected / 2) capacity_ *= 2;
    table_.assign(capacity_, Slot{none, 0});
  }

  /// The first corner met with the value of corner `c` (of hash `hash`): `c` itself the first time.
  index_t first(index_t c, std::uint64_t hash) {
    const std::uint32_t h = static_cast<std::uint32_t>(hash);
    std::size_t s = h & (capacity_ - 1);
    for (; table_[s].corner != none; s = (s + 1) & (capacity_ - 1)) {
      if (table_[s].hash == h && std::memcmp(values_ + width * static_cast<std::size_t>(table_[s].corner),
                                             values_ + width * static_cast<std::size_t>(c), width * sizeof(float)) == 0)
        return table_[s].corner;
    }
    table_[s] = Slot{c, h};
    if (2 * ++used_ > capacity_) grow();
    return c;
  }

 private:
  struct Slot {
    index_t corner;
    std::uint32_t hash;
  };

  void grow() {
    std::vector<Slot> larger(2 * capacity_, Slot{none, 0});
    for (const Slot& slot : table_) {
      if (slot.corner == none) continue;
      std::size_t s = slot.hash & (2 * capacity_ - 1);
      while (larger[s].corner != none) s = (s + 1) & (2 * capacity_ - 1);
      larger[s] = slot;
    }
    table_.swap(larger);
    capacity_ *= 2;
  }

  const float* values_;
  std::size_t capacity_ = 16, used_ = 0;
  std::vector<Slot> table_;
};

/// MurmurHash3's 64-bit finalizer: every bit of `h` moves every bit of the result.
std::uint64_t mix64(std::uint64_t h) {
  h ^= h >> 33;
  h *= 0xFF51AFD7ED558CCDull;
  h ^= h >> 33;
  h *= 0xC4CEB9FE1A85EC53ull;
  return h ^ (h >> 33);
}

/// The hash of the value of corner `c` of `values` [corner_count * width].
template <int width>
std::uint64_t hash_of(const float* values, std::size_t c) {
  std::uint32_t bits[width];
  std::memcpy(bits, values + width * c, sizeof bits);
  const std::uint64_t h = mix64(std::uint64_t(bits[0]) << 32 | bits[1]);
  return width == 3 ? mix64(h ^ bits[width - 1]) : h;
}

/// With `first[c]` the first corner of c's value within c's piece, makes it the first in the whole
/// frame: the local first corners (few: a value is used by several corners) go to buckets by the
/// top bits of their hash, each piece's in order, so that a bucket meets its corners in increasing
/// order, and each bucket has a table of its own.
template <int width>
void join_pieces(const float* values, std::size_t piece_count, const PieceTeam& team, std::vector<index_t>& first) {
  const std::size_t corner_count = first.size();
  // The local first corners, bucket by bucket: counted, then placed.
  const std::size_t bucket_count = 4 * static_cast<std::size_t>(team.threads);
  auto bucket_of = [&](std::uint64_t h) { return static_cast<std::size_t>(((h >> 32) * bucket_count) >> 32); };
  std::vector<std::size_t> next(piece_count * bucket_count, 0);
  team.for_each_range(corner_count, piece_count, [&](std::size_t k, std::size_t begin, std::size_t end) {
    std::size_t* const count = &next[k * bucket_count];
    for (std::size_t c = begin; c < end; ++c) {
      if (first[c] == static_cast<index_t>(c)) ++count[bucket_of(hash_of<width>(values, c))];
    }
  });
  std::vector<std::size_t> bucket_begin(bucket_count + 1);
  std::size_t at = 0;
  for (std::size_t b = 0; b < bucket_count; ++b) {
    bucket_begin[b] = at;
    for (std::size_t k = 0; k < piece_count; ++k) at += std::exchange(next[k * bucket_count + b], at);
  }
  bucket_begin[bucket_count] = at;
  std::vector<index_t> local_firsts(at);
  team.for_each_range(corner_count, piece_count, [&](std::size_t k, std::size_t begin, std::size_t end) {
    std::size_t* const place = &next[k * bucket_count];
    for (std::size_t c = begin; c < end; ++c) {
      if (first[c] == static_cast<index_t>(c))
        local_firsts[place[bucket_of(hash_of<width>(values, c))]++] = static_cast<index_t>(c);
    }
  });
  // A local first corner learns its value's first corner in the frame (writing only its own
  // entry); then every other corner takes that of its local first.
  for_each_piece(
      bucket_count,
      [&](std::size_t b) {
        FirstUse<width> table(values, bucket_begin[b + 1] - bucket_begin[b]);
        for (std::size_t i = bucket_begin[b]; i < bucket_begin[b + 1]; ++i) {
          const index_t c = local_firsts[i];
          first[c] = table.first(c, hash_of<width>(values, c));
        }
      },
      team.threads);
  team.for_each_range(corner_count, piece_count, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c) {
      const index_t local = first[c];
      if (local != static_cast<index_t>(c) && first[local] != local) first[c] = first[local];
    }
  });
}

/// The first corners (`first[c] == c`) numbered in corner order, then every other corner given
/// its first's number.
ValueNumbers number_first_corners(const std::vector<index_t>& first, std::size_t piece_count, const PieceTeam& team) {
  const std::size_t corner_count = first.size();
  ValueNumbers numbers;
  numbers.corner_value.resize(corner_count);
  std::vector<std::size_t> value_start(piece_count, 0);
  team.for_each_range(corner_count, piece_count, [&](std::size_t k, std::size_t begin, std::size_t end) {
    std::size_t count = 0;
    for (std::size_t c = begin; c < end; ++c) count += first[c] == static_cast<index_t>(c);
    value_start[k] = count;
  });
  numbers.first_corner.resize(exclusive_sums(value_start));
  team.for_each_range(corner_count, piece_count, [&](std::size_t k, std::size_t begin, std::size_t end) {
    std::size_t value = value_start[k];
    for (std::size_t c = begin; c < end; ++c) {
      if (first[c] != static_cast<index_t>(c)) continue;
      numbers.corner_value[c] = static_cast<index_t>(value);
      numbers.first_corner[value++] = static_cast<index_t>(c);
    }
  });
  team.for_each_range(corner_count, piece_count, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c) {
      if (first[c] != static_cast<index_t>(c)) numbers.corner_value[c] = numbers.corner_value[first[c]];
    }
  });
  return numbers;
}

/// The numbering depends on the order of use only, not on the tables that find the values. Each
/// piece of corners finds the first corner of each value within the piece, with a table of its
/// own; those local first corners then find their value's first corner in the whole frame
/// (`join_pieces`). The first corners are then numbered in order.
template <int width>
ValueNumbers number_values(const std::vector<float>& corner_values, const PieceTeam& team) {
  const std::size_t corner_count = corner_values.size() / width;
  const float* const values = corner_values.data();
  // first[c]: the first corner with the value of corner c, within c's piece.
  std::vector<index_t> first(corner_count);
  const std::size_t piece_count = team.pieces(corner_count);
  team.for_each_range(corner_count, piece_count, [&](std::size_t, std::size_t begin, std::size_t end) {
    FirstUse<width> table(values, end - begin);
    for (std::size_t c = begin; c < end; ++c)
      first[c] = table.first(static_cast<index_t>(c), hash_of<width>(values, c));
  });
  if (piece_count > 1) join_pieces<width>(values, piece_count, team, first);
  return number_first_corners(first, piece_count, team);
}

/// Whether two corners of a mesh have equal attributes (UVs and normals, those it has) as numbers.
struct SameAttributes {
  const Mesh& mesh;
  bool uv, normals;

  bool operator()(std::size_t a, std::size_t b) const {
    for (int k = 0; uv && k < 2; ++k) {
      if (!same_value(mesh.corner_uv[2 * a + k], mesh.corner_uv[2 * b + k])) return false;
    }
    for (int k = 0; normals && k < 3; ++k) {
      if (!same_value(mesh.corner_normal[3 * a + k], mesh.corner_normal[3 * b + k])) return false;
    }
    return true;
  }
};

constexpr index_t unused = std::numeric_limits<index_t>::max();

/// Each node's first corner (the smallest that uses it; `none` for an unused node) and every
/// corner at its node's vertex; returns the corners whose attributes differ from their node's
/// first corner's (the "misfits"), in corner order.
std::vector<index_t> find_misfits(const Mesh& mesh, const PieceTeam& team, const SameAttributes& same_attributes,
                                  SplitNodes& split) {
  const bool attributes = same_attributes.uv || same_attributes.normals;
  const index_t node_count = mesh.node_count();
  const std::size_t corner_count = mesh.face_nodes.size();
  team.for_each_range(node_count, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v) {
      split.vertex_node[v] = static_cast<index_t>(v);
      split.vertex_corner[v] = unused;
    }
  });
  team.for_each_range(corner_count, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c)
      lower_to(split.vertex_corner[mesh.face_nodes[c]], static_cast<index_t>(c));
  });

  const std::size_t piece_count = team.pieces(corner_count);
  std::vector<std::uint8_t> misfit(attributes ? corner_count : 0);
  std::vector<std::size_t> misfit_start(piece_count, 0);
  team.for_each_range(corner_count, piece_count, [&](std::size_t k, std::size_t begin, std::size_t end) {
    std::size_t count = 0;
    for (std::size_t c = begin; c < end; ++c) {
      const index_t node = mesh.face_nodes[c];
      split.corner_vertex[c] = node;
      if (!attributes) continue;
      const std::size_t first = static_cast<std::size_t>(split.vertex_corner[node]);
      misfit[c] = first != c && !same_attributes(first, c);
      count += misfit[c];
    }
    misfit_start[k] = count;
  });
  team.for_each_range(node_count, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v) {
      if (split.vertex_corner[v] == unused) split.vertex_corner[v] = none;
    }
  });
  const std::size_t misfit_count = exclusive_sums(misfit_start);
  std::vector<index_t> misfits(misfit_count);
  if (misfit_count == 0) return misfits;
  team.for_each_range(corner_count, piece_count, [&](std::size_t k, std::size_t begin, std::size_t end) {
    std::size_t at = misfit_start[k];
    for (std::size_t c = begin; c < end; ++c) {
      if (misfit[c]) misfits[at++] = static_cast<index_t>(c);
    }
  });
  return misfits;
}

/// The class of each misfit: the position (in `misfits`) of the first misfit of its node with
/// equal attributes. Each node's misfits, the nodes one after the other, are counted, then placed
/// in any order and sorted, then compared with the first of every class so far (a node has few).
std::vector<index_t> misfit_classes(const Mesh& mesh, const PieceTeam& team, const SameAttributes& same_attributes,
                                    const std::vector<index_t>& misfits) {
  const index_t node_count = mesh.node_count();
  const std::size_t misfit_count = misfits.size();
  std::vector<index_t> node_misfits_begin(static_cast<std::size_t>(node_count) + 1, 0);
  team.for_each_range(misfit_count, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      __atomic_fetch_add(&node_misfits_begin[mesh.face_nodes[misfits[i]]], 1, __ATOMIC_RELAXED);
    }
  });
  index_t sum = 0;
  for (index_t& count : node_misfits_begin) sum += std::exchange(count, sum);
  std::vector<index_t> next(node_misfits_begin.begin(), node_misfits_begin.end() - 1);
  std::vector<index_t> node_misfits(misfit_count);
  team.for_each_range(misfit_count, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      node_misfits[__atomic_fetch_add(&next[mesh.face_nodes[misfits[i]]], 1, __ATOMIC_RELAXED)] =
          static_cast<index_t>(i);
    }
  });
  std::vector<index_t> class_first(misfit_count);
  team.for_each_range(node_count, [&](std::size_t, std::size_t begin, std::size_t end) {
    std::vector<index_t> firsts;
    for (std::size_t node = begin; node < end; ++node) {
      const auto first = node_misfits.begin() + node_misfits_begin[node];
      const auto last = node_misfits.begin() + node_misfits_begin[node + 1];
      std::sort(first, last);
      firsts.clear();
      for (auto i = first; i != last; ++i) {
        const std::size_t c = static_cast<std::size_t>(misfits[*i]);
        index_t found = *i;
        for (index_t candidate : firsts) {
          if (same_attributes(static_cast<std::size_t>(misfits[candidate]), c)) {
            found = candidate;
            break;
          }
        }
        if (found == *i) firsts.push_back(found);
        class_first[*i] = found;
      }
    }
  });
  return class_first;
}

/// The classes' vertices, after the nodes, in the order of their first corners; each misfit
/// corner at its class's vertex.
void add_class_vertices(const Mesh& mesh, const PieceTeam& team, const std::vector<index_t>& misfits,
                        const std::vector<index_t>& class_first, SplitNodes& split) {
  const index_t node_count = mesh.node_count();
  const std::size_t misfit_count = misfits.size();
  const std::size_t misfit_pieces = team.pieces(misfit_count);
  std::vector<std::size_t> extra_start(misfit_pieces, 0);
  team.for_each_range(misfit_count, misfit_pieces, [&](std::size_t k, std::size_t begin, std::size_t end) {
    std::size_t count = 0;
    for (std::size_t i = begin; i < end; ++i) count += class_first[i] == static_cast<index_t>(i);
    extra_start[k] = count;
  });
  const std::size_t extra_count = exclusive_sums(extra_start);
  split.vertex_node.resize(node_count + extra_count);
  split.vertex_corner.resize(node_count + extra_count);
  team.for_each_range(misfit_count, misfit_pieces, [&](std::size_t k, std::size_t begin, std::size_t end) {
    std::size_t vertex = static_cast<std::size_t>(node_count) + extra_start[k];
    for (std::size_t i = begin; i < end; ++i) {
      if (class_first[i] != static_cast<index_t>(i)) continue;
      const index_t c = misfits[i];
      split.vertex_node[vertex] = mesh.face_nodes[c];
      split.vertex_corner[vertex] = c;
      split.corner_vertex[c] = static_cast<index_t>(vertex++);
    }
  });
  team.for_each_range(misfit_count, misfit_pieces, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      if (class_first[i] != static_cast<index_t>(i))
        split.corner_vertex[misfits[i]] = split.corner_vertex[misfits[class_first[i]]];
    }
  });
}

}  // namespace

/// Equal-as-numbers attributes make classes of a node's corners: the class of the node's first
/// corner is vertex `node`, every other class a vertex of its own, numbered by the class's first
/// corner. Found in steps that each run in pieces: each node's first corner (the smallest that
/// uses it); the corners that differ from it ("misfits", in corner order); each node's misfits,
/// in corner order, put in classes by comparing each with the first of every class so far (a
/// node has few); then the classes numbered in the order of their first corners.
SplitNodes split_nodes(const Mesh& mesh, const PieceTeam& team) {
  const SameAttributes same_attributes{mesh, mesh.has_uv(), mesh.has_normals()};
  const index_t node_count = mesh.node_count();
  SplitNodes split;
  split.vertex_node.resize(node_count);
  split.vertex_corner.resize(node_count);
  split.corner_vertex.resize(mesh.face_nodes.size());
  const std::vector<index_t> misfits = find_misfits(mesh, team, same_attributes, split);
  if (misfits.empty()) return split;
  const std::vector<index_t> class_first = misfit_classes(mesh, team, same_attributes, misfits);
  add_class_vertices(mesh, team, misfits, class_first, split);
  return split;
}

ValueNumbers number_by_value(const std::vector<float>& corner_values, int width, const PieceTeam& team) {
  return width == 2 ? number_values<2>(corner_values, team) : number_values<3>(corner_values, team);
}

}  // namespace tear
