// SPDX-License-Identifier: MIT
#pragma once
// Parallel grouping of equal items (private to core): the weld's vertex classes and the glTF
// writer's vertices. Both number classes by their first item, so the result is a pure function
// of the items, whatever the thread count or the order the threads ran in:
//  - `first_of_class`: for every item, the smallest index of an item equal to it. Items go into a
//    lock-free open-addressing table whose slots only ever change from empty to an index, or
//    from an index to a smaller equal one (atomic min), so each slot ends holding the smallest
//    item of its class.
//  - `ordered_indices`: the indices i in [0, n) where pred(i) holds, in increasing order
//    (counts per chunk, a prefix sum, then each chunk writes its own range).

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "deepcut/core/parallel.h"
#include "deepcut/core/types.h"

namespace deepcut::detail {

constexpr std::size_t kClassGrain = 16384;

/// `hash[i]` must be equal for equal items; `same(a, b)` says whether items a and b are equal.
/// @returns first[i] = the smallest j with same(i, j) (first[i] == i for the first of a class).
template <class Same>
std::vector<std::uint32_t> first_of_class(const std::vector<std::uint64_t>& hash, Same&& same) {
  const std::size_t n = hash.size();
  std::vector<std::uint32_t> first(n);
  if (n == 0) return first;
  std::size_t size = 16;
  while (size < 2 * n) size *= 2;
  const std::size_t mask = size - 1;
  constexpr std::uint32_t kEmpty = kInvalidIndex;
  std::unique_ptr<std::atomic<std::uint32_t>[]> slots(new std::atomic<std::uint32_t>[size]);
  parallel_for(size, 4 * kClassGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) slots[i].store(kEmpty, std::memory_order_relaxed);
  });
  // Claims a slot for item i's class: the first slot of its probe sequence that is empty or
  // holds an equal item. Slots before it hold other classes for good (a slot never empties).
  std::vector<std::uint32_t> where(n);
  parallel_for(n, kClassGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const auto item = static_cast<std::uint32_t>(i);
      std::size_t k = hash[i] & mask;
      for (;; k = (k + 1) & mask) {
        std::uint32_t s = slots[k].load(std::memory_order_acquire);
        if (s == kEmpty && slots[k].compare_exchange_strong(s, item, std::memory_order_acq_rel)) break;
        if (hash[s] == hash[i] && same(s, item)) {
          while (item < s && !slots[k].compare_exchange_weak(s, item, std::memory_order_acq_rel)) {
          }
          break;
        }
      }
      where[i] = static_cast<std::uint32_t>(k);
    }
  });
  parallel_for(n, kClassGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) first[i] = slots[where[i]].load(std::memory_order_relaxed);
  });
  return first;
}

/// The indices i in [0, n) with pred(i), in increasing order.
template <class Pred>
std::vector<std::uint32_t> ordered_indices(std::size_t n, Pred&& pred) {
  const std::size_t chunks = (n + kClassGrain - 1) / kClassGrain;
  std::vector<std::size_t> start(chunks + 1, 0);
  parallel_for(n, kClassGrain, [&](std::size_t b, std::size_t e) {
    std::size_t count = 0;
    for (std::size_t i = b; i < e; ++i) count += pred(i) ? 1 : 0;
    start[b / kClassGrain + 1] = count;
  });
  for (std::size_t c = 0; c < chunks; ++c) start[c + 1] += start[c];
  std::vector<std::uint32_t> out(start[chunks]);
  parallel_for(n, kClassGrain, [&](std::size_t b, std::size_t e) {
    std::size_t at = start[b / kClassGrain];
    for (std::size_t i = b; i < e; ++i)
      if (pred(i)) out[at++] = static_cast<std::uint32_t>(i);
  });
  return out;
}

}  // namespace deepcut::detail
