// SPDX-License-Identifier: MIT
#pragma once
// Sorting a list of ids and dropping repeats, the way the local edits need it: the lists are a
// few thousand faces gathered from grid cells or edit logs, whose ids fall in a narrow range of
// the mesh. Private to core (the triangle grid's queries, the pinch split's face lists, the
// drill's face sets).

#include <algorithm>
#include <cstdint>
#include <vector>

#include "deepcut/core/types.h"

namespace deepcut::detail {

/// Ids marked in a bitmap (this thread's, all zero between uses) and read back in increasing
/// order, each once: a sorted list without repeats, with no list of repeats to sort. The words
/// that marks make non-zero are recorded, so reading back and clearing cost what was marked, not
/// the span of the ids (after edits a query holds low original ids and high new ones): words
/// spanning no more than a few times their number are scanned in order, sparser ones sorted. The
/// destructor clears whatever take() did not read, so an exception between marking and reading
/// back (an allocation failing) leaves the bitmap clean for the thread's next use. One IdMarks at
/// a time per thread.
class IdMarks {
 public:
  /// Marks for ids in [lo, hi].
  IdMarks(std::uint32_t lo, std::uint32_t hi) : s_(local()), lo_(lo) {
    const std::size_t words = (std::size_t(hi - lo) >> 6) + 1;
    if (s_.bits.size() < words) s_.bits.resize(words, 0);
    bits_ = s_.bits.data();
  }
  IdMarks(const IdMarks&) = delete;
  IdMarks& operator=(const IdMarks&) = delete;
  ~IdMarks() {
    for (const std::uint32_t w : s_.words) bits_[w] = 0;
    s_.words.clear();
  }

  void mark(std::uint32_t id) {
    const std::uint32_t r = id - lo_;
    std::uint64_t& word = bits_[r >> 6];
    const std::uint64_t bit = std::uint64_t(1) << (r & 63);
    if (word == 0) s_.words.push_back(r >> 6);  // before the bit: a throw leaves the word clear
    word |= bit;
  }

  /// The marked ids in increasing order, appended to `out`; the bitmap is left all zero.
  template <class Tag>
  void take(std::vector<Id<Tag>>& out) {
    std::vector<std::uint32_t>& words = s_.words;
    if (words.empty()) return;
    std::uint32_t first = words[0], last = words[0];
    std::size_t count = 0;
    for (const std::uint32_t w : words) {
      first = std::min(first, w);
      last = std::max(last, w);
      count += static_cast<std::size_t>(__builtin_popcountll(bits_[w]));
    }
    out.reserve(out.size() + count);
    if (last - first >= 4 * words.size()) {
      std::sort(words.begin(), words.end());
      for (const std::uint32_t w : words) read(w, out);
    } else {
      for (std::uint32_t w = first; w <= last; ++w)
        if (bits_[w] != 0) read(w, out);
    }
    words.clear();
  }

 private:
  struct State {
    std::vector<std::uint64_t> bits;   // all zero between uses
    std::vector<std::uint32_t> words;  // the words marks made non-zero, in marking order
  };
  static State& local() {
    thread_local State state;
    return state;
  }
  template <class Tag>
  void read(std::uint32_t w, std::vector<Id<Tag>>& out) {
    std::uint64_t b = bits_[w];
    bits_[w] = 0;
    const std::uint32_t base = lo_ + 64 * w;
    for (; b != 0; b &= b - 1) out.push_back(Id<Tag>(base + static_cast<std::uint32_t>(__builtin_ctzll(b))));
  }

  State& s_;
  std::uint64_t* bits_;  // s_.bits
  std::uint32_t lo_;
};

/// `ids` sorted ascending with repeats dropped: the same list `std::sort` then `std::unique` give.
/// Ids spanning a range no wider than a few times the list's length are marked (IdMarks) and read
/// back in order: linear work and no comparison sort; sparser ids are sorted. Never allocates
/// `ids` (the result is no longer).
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
  IdMarks marks(lo, hi);
  for (const Id<Tag> id : ids) marks.mark(id.index);
  ids.clear();
  marks.take(ids);
}

}  // namespace deepcut::detail
