// tear: a caching allocator for Thrust's temporary storage (the buffers of sort, scan, reduce),
// so that once a cloth's cuts reach their largest size no stage allocates device memory again.
#pragma once

#include <cstddef>
#include <map>
#include <new>

#include "backend/backend.h"

namespace tear::backend {

/// Keeps every block it handed out; a request takes the smallest free block that fits. Blocks are
/// freed when the allocator is destroyed. Not thread-safe: one per cloth, used by the GPU backend
/// (whose Thrust calls come from one host thread).
template <class System>
class TemporaryAllocator {
 public:
  using value_type = char;

  TemporaryAllocator() = default;
  TemporaryAllocator(const TemporaryAllocator&) = delete;
  TemporaryAllocator& operator=(const TemporaryAllocator&) = delete;
  ~TemporaryAllocator() {
    for (auto& [size, p] : free_) Traits<System>::free_bytes(p, size);
    for (auto& [p, size] : used_) Traits<System>::free_bytes(p, size);
  }

  char* allocate(std::ptrdiff_t bytes) {
    const std::size_t n = static_cast<std::size_t>(bytes);
    auto it = free_.lower_bound(n);
    char* p;
    std::size_t size;
    if (it != free_.end()) {
      size = it->first;
      p = it->second;
      free_.erase(it);
    } else {
      size = n;
      p = static_cast<char*>(Traits<System>::allocate_bytes(n));
      if (!p) throw std::bad_alloc();
    }
    used_.emplace(p, size);
    return p;
  }

  void deallocate(char* p, std::size_t) {
    auto it = used_.find(p);
    if (it == used_.end()) return;
    free_.emplace(it->second, p);
    used_.erase(it);
  }

 private:
  std::multimap<std::size_t, char*> free_;
  std::map<char*, std::size_t> used_;
};

}  // namespace tear::backend
