// SPDX-License-Identifier: MIT
#pragma once
// Sorting a list of ids and dropping repeats, the way the local edits need it: the lists are a
// few thousand faces gathered from grid cells or edit logs, whose ids fall in a narrow range of
// the mesh. Private to core (the triangle grid's queries, the pinch split's face lists).

#include <algorithm>
#include <cstdint>
#include <vector>

#include "deepcut/core/types.h"

namespace deepcut::detail {

/// `ids` sorted ascending with repeats dropped: the same list `std::sort` then `std::unique` give.
/// Ids spanning a range no wider than a few times the list's length are marked in a bitmap over
/// that range (reused by the thread, left cleared) and read back in order: linear work and no
/// comparison sort; sparser ids are sorted. Never allocates `ids` (the result is no longer).
template <class Tag>
void sort_unique_ids(std::vector<Id<Tag>>& ids) {
  constexpr std::size_t kSmall = 48;  // below: a comparison sort is as quick
  if (ids.size() < kSmall) {
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    return;
  }
  std::uint32_t lo = ids[0].index, hi = ids[0].index;
  for (const Id<Tag> id : ids) {
    lo = std::min(lo, id.index);
    hi = std::max(hi, id.index);
  }
  const std::size_t words = ((hi - lo) >> 6) + 1;
  if (words > 2 * ids.size()) {
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    return;
  }
  thread_local std::vector<std::uint64_t> bits;  // all zero between calls
  if (bits.size() < words) bits.resize(words, 0);
  for (const Id<Tag> id : ids) {
    const std::uint32_t r = id.index - lo;
    bits[r >> 6] |= std::uint64_t(1) << (r & 63);
  }
  ids.clear();
  for (std::size_t w = 0; w < words; ++w) {
    std::uint64_t b = bits[w];
    if (b == 0) continue;
    bits[w] = 0;
    const auto base = static_cast<std::uint32_t>(lo + 64 * w);
    while (b != 0) {
      ids.push_back(Id<Tag>(base + static_cast<std::uint32_t>(__builtin_ctzll(b))));
      b &= b - 1;
    }
  }
}

}  // namespace deepcut::detail
