// SPDX-License-Identifier: MIT
// The pieces of a split as labels of a few bits per element (model_undo_labels.h).
#include "model_undo_labels.h"

#include <algorithm>
#include <atomic>

#include "deepcut/core/errors.h"
#include "deepcut/core/parallel.h"

namespace deepcut::undo {

namespace {

/// Elements per task: a multiple of 64, so that no two tasks write the same word.
constexpr std::size_t kStretch = 65536;

/// The lowest bit of each `bits`-wide field of a word.
std::uint64_t field_lows(unsigned bits) {
  std::uint64_t out = 0;
  for (unsigned b = 0; b < 64; b += bits) out |= std::uint64_t{1} << b;
  return out;
}

/// How many of the first `n` fields of `word` hold the label whose fields `pattern` repeats.
std::size_t count_in(std::uint64_t word, std::uint64_t pattern, unsigned bits, std::uint64_t lows,
                     std::size_t n) {
  std::uint64_t x = word ^ pattern;                    // a field is 0 where it holds the label
  for (unsigned s = 1; s < bits; s *= 2) x |= x >> s;  // each field's lowest bit: any bit set
  std::uint64_t hits = ~x & lows;
  if (n * bits < 64) hits &= (std::uint64_t{1} << (n * bits)) - 1u;
  return static_cast<std::size_t>(__builtin_popcountll(hits));
}

/// Throws unless `list` is increasing and below `count` (the labelling's bisections need it).
void check_list(const std::vector<std::uint32_t>& list, std::size_t count) {
  std::atomic<bool> bad{false};
  parallel_for(list.size(), kStretch, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i)
      if (list[i] >= count || (i > 0 && list[i] <= list[i - 1])) bad.store(true, std::memory_order_relaxed);
  });
  if (bad.load())
    throw Error(ErrorCode::InvalidArgument, "piece labels: a list is not increasing below the count");
}

}  // namespace

PieceLabels::PieceLabels(const std::vector<std::vector<std::uint32_t>>& lists, std::size_t count)
    : count_(count) {
  if (count > UINT32_MAX) throw Error(ErrorCode::InvalidArgument, "piece labels: over 2^32 elements");
  const std::size_t labels = lists.size() + 1;
  while (bits_ < 32 && (std::uint64_t{1} << bits_) < labels) bits_ *= 2;
  sizes_.assign(labels, 0);
  std::size_t listed = 0;
  for (std::size_t k = 0; k < lists.size(); ++k) {
    check_list(lists[k], count);
    sizes_[k] = lists[k].size();
    listed += lists[k].size();
  }
  if (listed > count) throw Error(ErrorCode::InvalidArgument, "piece labels: the lists overlap");
  sizes_.back() = count - listed;
  const std::uint64_t mask = (std::uint64_t{1} << bits_) - 1u;
  const std::uint64_t rest = field_lows(bits_) * lists.size();  // a word of rest labels
  words_.assign((count * bits_ + 63) / 64, rest);
  std::atomic<bool> overlap{false};
  // Each stretch labels its part of every list (found by bisection); an element labelled
  // twice is in two lists.
  parallel_for((count + kStretch - 1) / kStretch, 1, [&](std::size_t first, std::size_t last) {
    for (std::size_t r = first; r < last; ++r) {
      const std::size_t b = r * kStretch, e = std::min(count, b + kStretch);
      for (std::size_t k = 0; k < lists.size(); ++k) {
        const std::uint32_t* const end = lists[k].data() + lists[k].size();
        const std::uint32_t* const lo = std::lower_bound(lists[k].data(), end, b);
        const std::uint32_t* const hi = std::lower_bound(lo, end, e);
        for (const std::uint32_t* p = lo; p != hi; ++p) {
          const std::size_t bit = std::size_t{*p} * bits_;
          std::uint64_t& word = words_[bit / 64];
          if (((word >> (bit % 64)) & mask) != lists.size()) overlap.store(true, std::memory_order_relaxed);
          word = (word & ~(mask << (bit % 64))) | (std::uint64_t{k} << (bit % 64));
        }
      }
    }
  });
  if (overlap.load()) throw Error(ErrorCode::InvalidArgument, "piece labels: the lists overlap");
}

std::vector<std::uint32_t> PieceLabels::stretch_starts(const std::vector<bool>& wanted) const {
  const std::size_t labels = sizes_.size();
  const std::size_t stretches = (count_ + kStretch - 1) / kStretch;
  const std::size_t per_word = 64 / bits_;
  const std::uint64_t lows = field_lows(bits_), mask = (std::uint64_t{1} << bits_) - 1u;
  std::vector<std::uint32_t> out(stretches * labels, 0);
  parallel_for(stretches, 1, [&](std::size_t first, std::size_t last) {  // each stretch counts
    for (std::size_t r = first; r < last; ++r) {
      const std::size_t b = r * kStretch, e = std::min(count_, b + kStretch);
      std::uint32_t* const n = &out[r * labels];
      for (std::size_t w = b / per_word; w * per_word < e; ++w) {
        const std::size_t in_word = std::min(per_word, e - w * per_word);
        if (labels <= 4) {  // a cut's few labels: each wanted one counted over the word at once
          for (std::size_t k = 0; k + 1 < labels; ++k)
            if (wanted[k] || wanted[labels - 1])
              n[k] += static_cast<std::uint32_t>(count_in(words_[w], lows * k, bits_, lows, in_word));
        } else {
          std::uint64_t word = words_[w];
          for (std::size_t i = 0; i < in_word; ++i, word >>= bits_) ++n[word & mask];
        }
      }
      if (labels <= 4) {  // the last label's count: the stretch's others
        n[labels - 1] = static_cast<std::uint32_t>(e - b);
        for (std::size_t k = 0; k + 1 < labels; ++k) n[labels - 1] -= n[k];
      }
    }
  });
  for (std::size_t k = 0; k < labels; ++k) {  // the counts become where each stretch starts
    std::uint32_t at = 0;
    for (std::size_t r = 0; r < stretches; ++r) {
      const std::uint32_t n = out[r * labels + k];
      out[r * labels + k] = at;
      at += n;
    }
  }
  return out;
}

void PieceLabels::decode(const std::vector<std::vector<std::uint32_t>*>& out) const {
  const std::size_t labels = sizes_.size();
  bool all = true;
  for (std::size_t k = 0; k < labels; ++k) {
    if (out[k]) out[k]->resize(sizes_[k]);
    all = all && out[k];
  }
  std::vector<bool> wanted(labels);
  for (std::size_t k = 0; k < labels; ++k) wanted[k] = out[k] != nullptr;
  const std::vector<std::uint32_t> starts = stretch_starts(wanted);
  const std::size_t stretches = starts.size() / std::max<std::size_t>(labels, 1);
  const std::size_t per_word = 64 / bits_;
  const std::uint64_t mask = (std::uint64_t{1} << bits_) - 1u;
  parallel_for(stretches, 1, [&](std::size_t first, std::size_t last) {
    // Where each label's next element goes: its list, or scratch for a list not wanted (each
    // label writes at most a stretch there). Raw pointers, so the writes alias none of them.
    std::vector<std::uint32_t> scratch(all ? 0 : kStretch);
    std::vector<std::uint32_t*> to(labels);
    for (std::size_t r = first; r < last; ++r) {
      for (std::size_t k = 0; k < labels; ++k)
        to[k] = out[k] ? out[k]->data() + starts[r * labels + k] : scratch.data();
      const std::size_t b = r * kStretch, e = std::min(count_, b + kStretch);
      for (std::size_t w = b / per_word; w * per_word < e; ++w) {  // a word of labels at a time
        std::uint64_t word = words_[w];
        const std::size_t end = std::min(e, (w + 1) * per_word);
        for (std::size_t i = w * per_word; i < end; ++i, word >>= bits_)
          *to[static_cast<std::size_t>(word & mask)]++ = static_cast<std::uint32_t>(i);
      }
    }
  });
}

std::vector<std::vector<std::uint32_t>> PieceLabels::lists() const {
  std::vector<std::vector<std::uint32_t>> out(sizes_.size());
  std::vector<std::vector<std::uint32_t>*> to;
  for (auto& list : out) to.push_back(&list);
  decode(to);
  return out;
}

std::vector<std::uint32_t> PieceLabels::list(std::size_t k) const {
  std::vector<std::uint32_t> out;
  std::vector<std::vector<std::uint32_t>*> to(sizes_.size(), nullptr);
  to[k] = &out;
  decode(to);
  return out;
}

std::size_t PieceLabels::bytes() const {
  return words_.capacity() * sizeof(std::uint64_t) + sizes_.capacity() * sizeof(std::size_t);
}

}  // namespace deepcut::undo
