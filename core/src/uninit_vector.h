// SPDX-License-Identifier: MIT
#pragma once
// A std::vector whose new elements are left uninitialised (private to core). For the large arrays
// of import and export that are written whole right after they are sized: a zero fill first would
// touch every page on the calling thread (a serial pass of page faults and writes), while the
// parallel loop that fills them touches each page on the thread that writes it. Only for types
// without invariants (numbers, glm vectors).

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

}  // namespace deepcut::detail
