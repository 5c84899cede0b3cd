// SPDX-License-Identifier: MIT
#pragma once
// Large arrays for the whole-mesh passes of import and export (private to core).
// - UninitVector: a std::vector whose new elements are left uninitialised, for arrays written
//   whole right after they are sized: a zero fill first would touch every page on the calling
//   thread (a serial pass of page faults and writes), while the parallel loop that fills them
//   touches each page on the thread that writes it. Only for types without invariants (numbers,
//   glm vectors).
// - resize_prefaulted: for the arrays that must be std::vectors (a mesh's attributes and faces),
//   whose growth value-initialises every element on the calling thread: their memory is reserved
//   and its pages faulted in over the pool first, so the serial fill writes to present pages.
// Neither asks for huge pages: on the 2-core machine #19 is measured on, a fresh 2 MiB page cost
// more than 512 fresh 4 KiB ones (docs/BENCHMARKS.md, session 19).

#include <algorithm>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

namespace deepcut::detail {

template <class T>
struct UninitAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = UninitAllocator<U>;
  };
  UninitAllocator() = default;
  template <class U>
  UninitAllocator(const UninitAllocator<U>&) noexcept {}
  // Value-initialisation (`resize(n)`, `vector(n)`) leaves the element as it is; explicit
  // values are constructed as usual.
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible<U>::value) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

template <class T>
using UninitVector = std::vector<T, UninitAllocator<T>>;

/// Asks the kernel to fault in the pages of [data, data + bytes) for writing, in parallel parts
/// (MADV_POPULATE_WRITE; nothing happens where the kernel does not offer it). Changes no byte.
void prefault(void* data, std::size_t bytes);

/// Grows the empty `v` to `n` copies of `value`, its pages faulted in over the pool first; its
/// capacity is at least `capacity` (the pages past `n` are left untouched).
template <class T, class A>
void resize_prefaulted(std::vector<T, A>& v, std::size_t n, const T& value = T(), std::size_t capacity = 0) {
  v.reserve(std::max(n, capacity));
  prefault(v.data(), n * sizeof(T));
  v.resize(n, value);
}

}  // namespace deepcut::detail
