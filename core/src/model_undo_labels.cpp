// SPDX-License-Identifier: MIT
// The pieces of a split as labels of a few bits per element (model_undo_labels.h).
#include "model_undo_labels.h"

#include <algorithm>

#include "deepcut/core/parallel.h"

namespace deepcut::undo {

namespace {

/// Elements per task: a multiple of 64, so that no two tasks write the same word.
constexpr std::size_t kStretch = 65536;

}  // namespace

PieceLabels::PieceLabels(const std::vector<std::vector<std::uint32_t>>& lists, std::size_t count)
    : count_(count) {
  const std::size_t labels = lists.size() + 1;
  while (bits_ < 32 && (std::uint64_t{1} << bits_) < labels) bits_ *= 2;
  const std::uint64_t mask = (std::uint64_t{1} << bits_) - 1u;
  std::uint64_t rest = 0;  // a word of rest labels
  for (unsigned b = 0; b < 64; b += bits_) rest |= std::uint64_t{lists.size()} << b;
  words_.assign((count * bits_ + 63) / 64, rest);
  const std::size_t stretches = (count + kStretch - 1) / kStretch;
  starts_.assign(stretches * labels, 0);
  // Each stretch labels its part of every list (found by bisection) and counts it.
  parallel_for(stretches, 1, [&](std::size_t first, std::size_t last) {
    for (std::size_t r = first; r < last; ++r) {
      const std::size_t b = r * kStretch, e = std::min(count, b + kStretch);
      std::size_t listed = 0;
      for (std::size_t k = 0; k < lists.size(); ++k) {
        const std::uint32_t* const end = lists[k].data() + lists[k].size();
        const std::uint32_t* const lo = std::lower_bound(lists[k].data(), end, b);
        const std::uint32_t* const hi = std::lower_bound(lo, end, e);
        for (const std::uint32_t* p = lo; p != hi; ++p) {
          const std::size_t bit = std::size_t{*p} * bits_;
          std::uint64_t& word = words_[bit / 64];
          word = (word & ~(mask << (bit % 64))) | (std::uint64_t{k} << (bit % 64));
        }
        starts_[r * labels + k] = static_cast<std::uint32_t>(hi - lo);
        listed += static_cast<std::size_t>(hi - lo);
      }
      starts_[r * labels + lists.size()] = static_cast<std::uint32_t>(e - b - listed);
    }
  });
  sizes_.assign(labels, 0);  // the counts become where each stretch starts in each list
  for (std::size_t r = 0; r < stretches; ++r)
    for (std::size_t k = 0; k < labels; ++k) {
      const std::uint32_t n = starts_[r * labels + k];
      starts_[r * labels + k] = static_cast<std::uint32_t>(sizes_[k]);
      sizes_[k] += n;
    }
}

void PieceLabels::decode(const std::vector<std::vector<std::uint32_t>*>& out) const {
  const std::size_t labels = sizes_.size();
  bool all = true;
  for (std::size_t k = 0; k < labels; ++k) {
    if (out[k]) out[k]->resize(sizes_[k]);
    all = all && out[k];
  }
  const std::size_t stretches = starts_.size() / std::max<std::size_t>(labels, 1);
  const std::size_t per_word = 64 / bits_;
  const std::uint64_t mask = (std::uint64_t{1} << bits_) - 1u;
  parallel_for(stretches, 1, [&](std::size_t first, std::size_t last) {
    // Where each label's next element goes: its list, or scratch for a list not wanted (each
    // label writes at most a stretch there). Raw pointers, so the writes alias none of them.
    std::vector<std::uint32_t> scratch(all ? 0 : kStretch);
    std::vector<std::uint32_t*> to(labels);
    for (std::size_t r = first; r < last; ++r) {
      for (std::size_t k = 0; k < labels; ++k)
        to[k] = out[k] ? out[k]->data() + starts_[r * labels + k] : scratch.data();
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
  return words_.capacity() * sizeof(std::uint64_t) + starts_.capacity() * sizeof(std::uint32_t) +
         sizes_.capacity() * sizeof(std::size_t);
}

}  // namespace deepcut::undo
