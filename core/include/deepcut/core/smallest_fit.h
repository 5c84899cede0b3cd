// SPDX-License-Identifier: MIT
#pragma once
/// @file smallest_fit.h
/// Choosing which of the buffers a step sets aside (spares) a new buffer reuses: the smallest
/// that holds what is needed, so large spares stay for large needs, and none far larger than
/// needed, so a small piece does not keep a large allocation alive (its unused room would
/// outlive the step; the spare is better freed).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <set>
#include <utility>
#include <vector>

namespace deepcut {

/// Of `spare`, the element with the least room (`room(element)`, in the units of `n`) that
/// holds `n` and at most `most`, taken out of `spare`; else a default T (nothing reused). The
/// first of equal rooms is taken, so the choice depends only on the order of `spare`. `most` is
/// twice the room a new buffer for `n` would be given (a buffer given fixed room to grow past
/// `n` still fits a piece of its own size).
template <class T, class Room>
T take_smallest_fit(std::vector<T>& spare, std::size_t n, std::size_t most, const Room& room) {
  auto best = spare.end();
  std::size_t best_room = 0;
  for (auto it = spare.begin(); it != spare.end(); ++it) {
    const std::size_t r = room(*it);
    if (r >= n && r <= most && (best == spare.end() || r < best_room)) {
      best = it;
      best_room = r;
    }
  }
  if (best == spare.end()) return T();
  T out = std::move(*best);
  spare.erase(best);
  return out;
}

/// take_smallest_fit for buffers made with no room past `n`: at most twice `n`.
template <class T, class Room>
T take_smallest_fit(std::vector<T>& spare, std::size_t n, const Room& room) {
  return take_smallest_fit(spare, n, 2 * n + 1, room);
}

/// Orders `items` by `size(item)`, largest first (equal sizes keep their order): the order in
/// which buffers take spares, so each takes the smallest that holds it and a piece that grew a
/// little past the spare of the one it was does not take the spare a larger piece needs.
template <class T, class Size>
void largest_first(std::vector<T>& items, const Size& size) {
  std::stable_sort(items.begin(), items.end(), [&](const T& a, const T& b) { return size(a) > size(b); });
}

/// Moves out of `stash` (a map keyed by (content tag, index)) the values whose tag is not in
/// `claimed`, in key order: the spares a step's new buffers may reuse (take_smallest_fit).
template <class Map>
std::vector<typename Map::mapped_type> take_unclaimed(Map& stash, const std::set<std::uint64_t>& claimed) {
  std::vector<typename Map::mapped_type> spare;
  for (auto it = stash.begin(); it != stash.end();) {
    if (claimed.count(it->first.first)) {
      ++it;
      continue;
    }
    spare.push_back(std::move(it->second));
    it = stash.erase(it);
  }
  return spare;
}

}  // namespace deepcut
