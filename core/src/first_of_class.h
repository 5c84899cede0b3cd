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
//  - `group_by_key` and `first_of_class_in_groups`: the same answer as `first_of_class` for
//    items that can only be equal when they share a small integer key (the writer's corners,
//    which share their vertex): each key's items are compared among themselves, so the work
//    stays local to a few items instead of probing a table the size of all of them.

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "deepcut/core/parallel.h"
#include "deepcut/core/types.h"
#include "uninit_vector.h"

namespace deepcut::detail {

constexpr std::size_t kClassGrain = 16384;

/// Index arrays written whole by a parallel loop right after they are sized: left uninitialised
/// (UninitVector), since a std::vector would first be filled on one thread.
using Indices = UninitVector<std::uint32_t>;

/// `hash[i]` must be equal for equal items; `same(a, b)` says whether items a and b are equal.
/// @returns first[i] = the smallest j with same(i, j) (first[i] == i for the first of a class).
template <class Hashes, class Same>
Indices first_of_class(const Hashes& hash, Same&& same) {
  const std::size_t n = hash.size();
  Indices first(n);
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
  Indices where(n);
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
Indices ordered_indices(std::size_t n, Pred&& pred) {
  const std::size_t chunks = (n + kClassGrain - 1) / kClassGrain;
  std::vector<std::size_t> start(chunks + 1, 0);
  parallel_for(n, kClassGrain, [&](std::size_t b, std::size_t e) {
    std::size_t count = 0;
    for (std::size_t i = b; i < e; ++i) count += pred(i) ? 1 : 0;
    start[b / kClassGrain + 1] = count;
  });
  for (std::size_t c = 0; c < chunks; ++c) start[c + 1] += start[c];
  Indices out(start[chunks]);
  parallel_for(n, kClassGrain, [&](std::size_t b, std::size_t e) {
    std::size_t at = start[b / kClassGrain];
    for (std::size_t i = b; i < e; ++i)
      if (pred(i)) out[at++] = static_cast<std::uint32_t>(i);
  });
  return out;
}

/// Items grouped by key: the items of key k are items[start[k] .. start[k + 1]), increasing.
struct Groups {
  UninitVector<std::uint32_t> start;  // keys + 1 offsets
  UninitVector<std::uint32_t> items;
};

/// Groups the items [0, n) by `key_of(i)` (< `keys`), a stable counting sort in parallel passes
/// over fixed cuts (item chunks of 4 * kClassGrain, 256 ranges of keys; neither depends on the
/// thread count): each chunk counts its items per range of keys, a prefix sum over (range, chunk)
/// gives each chunk its place in each range, the chunks scatter their items there, and each range
/// then sorts its own items by key. Every group comes out in increasing order.
template <class KeyOf>
Groups group_by_key(std::size_t n, std::size_t keys, KeyOf&& key_of) {
  constexpr std::size_t kRanges = 256, kGrain = 4 * kClassGrain;
  Groups g;
  g.start.resize(keys + 1);
  g.items.resize(n);
  g.start[keys] = static_cast<std::uint32_t>(n);
  if (keys == 0) return g;
  const std::size_t per_range = (keys + kRanges - 1) / kRanges, ranges = (keys + per_range - 1) / per_range;
  const std::size_t chunks = (n + kGrain - 1) / kGrain;
  std::vector<std::uint32_t> place(chunks * ranges, 0);  // per (chunk, range): a count, then where it writes
  UninitVector<std::uint32_t> key(n), by_range(n);
  parallel_for(n, kGrain, [&](std::size_t b, std::size_t e) {
    std::uint32_t* count = &place[b / kGrain * ranges];
    for (std::size_t i = b; i < e; ++i) {
      key[i] = static_cast<std::uint32_t>(key_of(i));
      ++count[key[i] / per_range];
    }
  });
  std::vector<std::uint32_t> range_start(ranges + 1, 0);
  std::uint32_t at = 0;
  for (std::size_t r = 0; r < ranges; ++r) {
    range_start[r] = at;
    for (std::size_t c = 0; c < chunks; ++c) at += std::exchange(place[c * ranges + r], at);
  }
  range_start[ranges] = at;
  parallel_for(n, kGrain, [&](std::size_t b, std::size_t e) {
    std::uint32_t* to = &place[b / kGrain * ranges];
    for (std::size_t i = b; i < e; ++i) by_range[to[key[i] / per_range]++] = static_cast<std::uint32_t>(i);
  });
  parallel_for(ranges, 1, [&](std::size_t r0, std::size_t r1) {
    std::vector<std::uint32_t> next;
    for (std::size_t r = r0; r < r1; ++r) {
      const std::size_t k0 = r * per_range, k1 = std::min(keys, k0 + per_range);
      next.assign(k1 - k0, 0);
      for (std::uint32_t j = range_start[r]; j < range_start[r + 1]; ++j) ++next[key[by_range[j]] - k0];
      std::uint32_t pos = range_start[r];
      for (std::size_t k = k0; k < k1; ++k) {
        g.start[k] = pos;
        pos += std::exchange(next[k - k0], pos);
      }
      for (std::uint32_t j = range_start[r]; j < range_start[r + 1]; ++j) {
        const std::uint32_t i = by_range[j];
        g.items[next[key[i] - k0]++] = i;
      }
    }
  });
  return g;
}

/// As `first_of_class` for the `n` items of `groups`, when items of different groups are never
/// equal: `same(a, b)` compares two items of one group, `hash(i)` (equal for equal items) sorts
/// the larger groups so that only items of equal hash are compared.
template <class Hash, class Same>
UninitVector<std::uint32_t> first_of_class_in_groups(const Groups& groups, std::size_t n, Hash&& hash, Same&& same) {
  constexpr std::size_t kSmallGroup = 16;
  UninitVector<std::uint32_t> first(n);
  const std::size_t keys = groups.start.empty() ? 0 : groups.start.size() - 1;
  parallel_for(keys, kClassGrain, [&](std::size_t b, std::size_t e) {
    std::vector<std::uint32_t> leaders;  // the first item of each class met so far, increasing
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;
    // Items in increasing order: each joins the first leader equal to it, or leads a new class.
    auto assign = [&](auto begin, auto end, auto item_of) {
      leaders.clear();
      for (auto it = begin; it != end; ++it) {
        const std::uint32_t i = item_of(*it);
        std::uint32_t lead = i;
        for (const std::uint32_t l : leaders)
          if (same(l, i)) {
            lead = l;
            break;
          }
        if (lead == i) leaders.push_back(i);
        first[i] = lead;
      }
    };
    for (std::size_t k = b; k < e; ++k) {
      const auto begin = groups.items.begin() + groups.start[k], end = groups.items.begin() + groups.start[k + 1];
      if (std::size_t(end - begin) <= kSmallGroup) {
        assign(begin, end, [](std::uint32_t i) { return i; });
        continue;
      }
      keyed.clear();
      for (auto it = begin; it != end; ++it) keyed.emplace_back(hash(*it), *it);
      std::sort(keyed.begin(), keyed.end());
      for (auto run = keyed.begin(); run != keyed.end();) {
        auto next = run;
        while (next != keyed.end() && next->first == run->first) ++next;
        assign(run, next, [](const std::pair<std::uint64_t, std::uint32_t>& p) { return p.second; });
        run = next;
      }
    }
  });
  return first;
}

}  // namespace deepcut::detail
