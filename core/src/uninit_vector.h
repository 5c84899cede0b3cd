// SPDX-License-Identifier: MIT
#pragma once
// Large arrays for the whole-mesh passes of import and export (private to core).
// - UninitVector (deepcut/core/uninit_vector.h): a std::vector whose new elements are left
//   uninitialised, for arrays written whole by a parallel loop right after they are sized.
// - reserve_prefaulted: reserves an array and faults in the pages its next sizing writes.
// - resize_prefaulted: for the arrays that must be std::vectors (a mesh's attributes and faces),
//   whose growth value-initialises every element on the calling thread: their memory is reserved
//   and its pages faulted in over the pool first, so the serial fill writes to present pages.
// None asks for huge pages: on the 2-core machine #19 is measured on, a fresh 2 MiB page cost
// more than 512 fresh 4 KiB ones (docs/BENCHMARKS.md, session 19).

#include <algorithm>
#include <cstddef>
#include <vector>

#include "deepcut/core/uninit_vector.h"

namespace deepcut::detail {

using deepcut::UninitAllocator;
using deepcut::UninitVector;

/// Asks the kernel to fault in the pages of [data, data + bytes) for writing, in parallel parts
/// (MADV_POPULATE_WRITE; nothing happens where the kernel does not offer it). Changes no byte.
/// Called inside a pool task (parallel_invoke) its parts run serially on that task's thread, as
/// every nested pool call does: fault large arrays in from the calling thread, outside tasks.
void prefault(void* data, std::size_t bytes);

/// Reserves the empty `v` for at least `n` elements and `room` (the most it is expected to grow
/// to without moving), and faults in the pages of its first `n` over the pool; the pages past
/// `n` are left untouched (address space only). Its size stays 0: the caller sizes it next.
template <class T, class A>
void reserve_prefaulted(std::vector<T, A>& v, std::size_t n, std::size_t room) {
  v.reserve(std::max(n, room));
  prefault(v.data(), n * sizeof(T));
}

/// Grows the empty `v` to `n` copies of `value`, its pages faulted in over the pool first; its
/// capacity is at least `capacity` (the pages past `n` are left untouched).
template <class T, class A>
void resize_prefaulted(std::vector<T, A>& v, std::size_t n, const T& value = T(), std::size_t capacity = 0) {
  reserve_prefaulted(v, n, capacity);
  v.resize(n, value);
}

}  // namespace deepcut::detail
