// tear: a backend's vector, with `resize_for_overwrite` for arrays a stage then writes whole, and
// raw pointers to its elements.
#pragma once

#include <cstddef>
#include <cstring>
#include <type_traits>

#include <thrust/fill.h>
#include <thrust/memory.h>

namespace tear::backend {

/// A backend's vector: Thrust's (whose `resize` writes every new element, a launch of its own on
/// CUDA), with `resize_for_overwrite`, which leaves new elements unwritten for arrays that a stage
/// then writes whole. A cloth grows with every tear, and every stage array with it: through
/// Thrust's resize each would cost a launch per tear for values nobody reads.
template <class Base>
class Vector : public Base {
 public:
  using Base::Base;
  using Base::operator=;
  Vector() = default;

  /// Resizes to `n` elements; those past the old size hold whatever the memory held.
  void resize_for_overwrite(std::size_t n) {
    static_assert(std::is_trivially_copyable<typename Base::value_type>::value &&
                      std::is_trivially_destructible<typename Base::value_type>::value,
                  "only for plain values");
    if (n > this->capacity()) this->reserve(n);
    const std::size_t old = this->size();
    this->m_size = static_cast<typename Base::size_type>(n);
#if TEAR_POISON_GROWN
    // Sanitizer builds: what a stage leaves unwritten is garbage the tests see (a NaN, an index out
    // of range), not the zero that fresh memory often holds.
    using T = typename Base::value_type;
    if (n > old) {
      T poison;
      std::memset(&poison, std::is_floating_point<T>::value ? 0xFF : 0xA5, sizeof poison);
      thrust::fill(this->begin() + static_cast<std::ptrdiff_t>(old), this->end(), poison);
    }
#else
    static_cast<void>(old);
#endif
  }
};

/// Resizes `v` to `n` elements for its stage to write them all: new elements are left unwritten
/// (`Vector::resize_for_overwrite`). When an allocated vector must grow, its capacity becomes n
/// plus an eighth (Thrust's own resize would double it): a cloth grows a little with every cut, and
/// its arrays should neither be reallocated every cut nor hold twice what they need. An empty one
/// gets exactly n.
template <class V>
void resize_for_overwrite(V& v, std::size_t n) {
  if (n > v.capacity()) v.reserve(v.capacity() > 0 ? n + n / 8 : n);
  v.resize_for_overwrite(n);
}

template <class T, class Vector>
T* raw(Vector& v) {
  return thrust::raw_pointer_cast(v.data());
}
template <class T, class Vector>
const T* raw(const Vector& v) {
  return thrust::raw_pointer_cast(v.data());
}

}  // namespace tear::backend
