// tear: copies between the host and a backend's memory: `to_host`, `assign_from_host`, and the
// batched copies that do not wait (`ReadBack`, `Upload`).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <new>
#include <stdexcept>
#include <vector>

#include <thrust/copy.h>

#include "backend/traits.h"
#include "backend/vector.h"

namespace tear::backend {

/// Copies between the host and a backend's vectors. Thrust's copy of an empty range still forms a
/// reference to the first element of its destination, which an empty vector does not have (a
/// null reference: undefined behaviour, reported by UBSan for every mesh without UVs and every
/// simulation without colliders); these helpers copy nothing then.
///
/// `v` [n] in `System`'s memory → a host vector of n `T`s.
template <class T, class Vector>
std::vector<T> to_host(const Vector& v) {
  std::vector<T> out(v.size());
  if (!out.empty()) thrust::copy(v.begin(), v.end(), out.begin());
  return out;
}

/// `v` becomes a copy of the host range `host` (any container with begin, end and empty).
template <class Vector, class HostRange>
void assign_from_host(Vector& v, const HostRange& host) {
  if (host.empty())
    v.clear();
  else
    v.assign(host.begin(), host.end());
}

/// Small values read back from the backend together: each `queue` copies values from backend
/// memory behind the stages queued so far, without waiting, and one `wait` then makes them all
/// readable. A cut reads its totals this way, one wait instead of one per value. Offsets, not
/// pointers, name what was queued: the staging memory may move when it grows.
template <class System>
class ReadBack {
 public:
  ReadBack() = default;
  ReadBack(const ReadBack&) = delete;
  ReadBack& operator=(const ReadBack&) = delete;
  ~ReadBack() {
    if (data_) Traits<System>::free_staging(data_, capacity_);
  }

  /// Starts a new batch (what was queued before is forgotten).
  void clear() {
    wait();  // a copy still under way must not land in memory the new batch reuses
    used_ = 0;
  }

  /// Queues a copy of `count` values at backend address `from`; returns the offset `at` takes.
  template <class T>
  std::size_t queue(const T* from, std::size_t count) {
    const std::size_t offset =
        (used_ + alignof(std::max_align_t) - 1) / alignof(std::max_align_t) * alignof(std::max_align_t);
    const std::size_t bytes = count * sizeof(T);
    if (offset + bytes > capacity_) grow(offset + bytes);
    if (bytes > 0) {
      Traits<System>::copy_to_staging(data_ + offset, from, bytes);
      pending_ = true;
    }
    used_ = offset + bytes;
    return offset;
  }

  /// Waits for the copies queued (and everything queued on the backend before them); waits for
  /// nothing when none was queued since the last wait.
  void wait() {
    if (!pending_) return;
    Traits<System>::synchronize();
    pending_ = false;
  }

  /// The values queued at `offset`, after `wait`.
  template <class T>
  const T* at(std::size_t offset) const {
    return reinterpret_cast<const T*>(data_ + offset);
  }

 private:
  void grow(std::size_t bytes) {
    const std::size_t capacity = std::max<std::size_t>(2 * capacity_, std::max<std::size_t>(bytes, 4096));
    char* next = static_cast<char*>(Traits<System>::allocate_staging(capacity));
    if (!next) throw std::bad_alloc();
    if (data_) {
      wait();  // the copies already queued land in the old memory
      std::memcpy(next, data_, used_);
      Traits<System>::free_staging(data_, capacity_);
    }
    data_ = next;
    capacity_ = capacity;
  }

  char* data_ = nullptr;
  std::size_t capacity_ = 0, used_ = 0;
  bool pending_ = false;  // copies queued since the last wait
};

/// Small host arrays sent to the backend together, without waiting: each `send` copies the values
/// into page-locked staging and queues their copy to the backend before the stages queued after it.
/// A batch reuses the staging once the backend has read the batch before (`begin` waits for that
/// point, long passed by then). A cut sends its paths this way: no wait, where a copy from
/// pageable memory waits for the device.
template <class System>
class Upload {
 public:
  Upload() = default;
  Upload(const Upload&) = delete;
  Upload& operator=(const Upload&) = delete;
  ~Upload() {
    sent_.wait();
    if (data_) Traits<System>::free_staging(data_, capacity_);
  }

  /// Starts a batch of `bytes` at most (the sum of the batch's sends, each aligned).
  void begin(std::size_t bytes) {
    sent_.wait();
    used_ = 0;
    if (bytes <= capacity_) return;
    if (data_) Traits<System>::free_staging(data_, capacity_);
    data_ = nullptr;
    capacity_ = 0;
    const std::size_t capacity = std::max<std::size_t>(bytes, 4096);
    data_ = static_cast<char*>(Traits<System>::allocate_staging(capacity));
    if (!data_) throw std::bad_alloc();
    capacity_ = capacity;
  }

  /// The staging a send of `count` values of T takes in a batch.
  template <class T>
  static std::size_t bytes_for(std::size_t count) {
    return (count * sizeof(T) + alignof(std::max_align_t) - 1) / alignof(std::max_align_t) * alignof(std::max_align_t);
  }

  /// `to` resized to `from`'s values, copied there behind the stages queued so far.
  template <class Vector, class T>
  void send(Vector& to, const std::vector<T>& from) {
    resize_for_overwrite(to, from.size());
    const std::size_t bytes = from.size() * sizeof(T);
    if (bytes == 0) return;
    if (used_ + bytes_for<T>(from.size()) > capacity_) throw std::logic_error("Upload: a send beyond its batch");
    std::memcpy(data_ + used_, from.data(), bytes);
    Traits<System>::copy_from_staging(thrust::raw_pointer_cast(to.data()), data_ + used_, bytes);
    used_ += bytes_for<T>(from.size());
    sent_.record();
  }

 private:
  char* data_ = nullptr;
  std::size_t capacity_ = 0, used_ = 0;
  typename Traits<System>::QueuePoint sent_;  // after the last copy sent
};

}  // namespace tear::backend
