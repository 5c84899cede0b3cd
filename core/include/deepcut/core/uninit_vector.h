// SPDX-License-Identifier: MIT
#pragma once
// UninitVector: a std::vector whose new elements are left uninitialised, for large arrays written
// whole right after they are sized (PosedMesh::linear, core's whole-mesh passes): a fill first
// would write every element on the calling thread (a serial pass, and the one that faults the
// pages in), while the parallel loop that writes them touches each page on the thread that
// writes it. Only for types without invariants (numbers, glm vectors and matrices, plain structs
// of them): the allocator asserts that the type is trivially copyable and destructible. Growing
// it by `resize(n)` default-initialises the new elements: a type with default member values gets
// them, any other keeps whatever bytes the storage held, and the code that grows it writes them.
// UnfilledVector goes one step further for plain structs with default member values: growing it
// writes nothing at all (explicit values, as in `resize(n, value)`, are written as usual), so a
// pass that writes every new element itself is not preceded by a serial one writing the defaults.

#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

namespace deepcut {

template <class T, bool kDefaults = true>
struct UninitAllocator : std::allocator<T> {
  // Bytes left unwritten are only harmless in a type that any bytes make a value of and that
  // needs no clean-up: one with invariants (an owning pointer, a container) would be broken.
  static_assert(std::is_trivially_copyable<T>::value && std::is_trivially_destructible<T>::value,
                "UninitVector holds only types without invariants");
  template <class U>
  struct rebind {
    using other = UninitAllocator<U, kDefaults>;
  };
  UninitAllocator() = default;
  template <class U>
  UninitAllocator(const UninitAllocator<U, kDefaults>&) noexcept {}
  // Value-initialisation (`resize(n)`, `vector(n)`) default-initialises the element (kDefaults)
  // or writes nothing; explicit values are constructed as usual.
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible<U>::value) {
    if constexpr (kDefaults) ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

template <class T>
using UninitVector = std::vector<T, UninitAllocator<T>>;
template <class T>
using UnfilledVector = std::vector<T, UninitAllocator<T, false>>;

}  // namespace deepcut
