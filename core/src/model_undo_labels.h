// SPDX-License-Identifier: MIT
#pragma once
// Which piece of a split each element of the primitive went to (model_undo_parts.h, SplitPart),
// kept as a label of a few bits per element instead of the pieces' index lists (4 bytes per
// element): a cut into two pieces keeps 2 bits per element, a sixteenth of the lists' bytes (a
// quarter of a byte per element), and the lists are made again, over the pool, when undo or
// redo need them.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace deepcut::undo {

class PieceLabels {
 public:
  PieceLabels() = default;
  /// The elements below `count` that the (increasing, disjoint) `lists` hold: element i of list
  /// k is labelled k, the elements no list holds `lists.size()` (the rest).
  /// @throws Error{InvalidArgument} when `count` is over 2^32 - 1 or the lists are not
  /// increasing, below `count` and disjoint.
  PieceLabels(const std::vector<std::vector<std::uint32_t>>& lists, std::size_t count);

  /// Number of pieces (lists) and of elements labelled.
  std::size_t pieces() const { return sizes_.empty() ? 0 : sizes_.size() - 1; }
  std::size_t count() const { return count_; }
  /// Elements of piece `k` (`pieces()`: the rest).
  std::size_t size(std::size_t k) const { return sizes_[k]; }
  /// Bits a label takes: the fewest of 1, 2, 4, 8, 16 and 32 that number the pieces and the rest.
  unsigned bits() const { return bits_; }

  /// The lists again, increasing, one per piece, the rest last.
  std::vector<std::vector<std::uint32_t>> lists() const;
  /// The elements of piece `k` (`pieces()`: the rest), increasing.
  std::vector<std::uint32_t> list(std::size_t k) const;

  /// Bytes held, capacity included.
  std::size_t bytes() const;

 private:
  /// Writes the lists named in `out` (nullptr: not wanted) from the labels.
  void decode(const std::vector<std::vector<std::uint32_t>*>& out) const;
  /// Per stretch of elements, per label: how many of its elements come before the stretch
  /// (counted a word at a time when decoding, not kept). Only the `wanted` labels' are right
  /// (the others' may be left out).
  std::vector<std::uint32_t> stretch_starts(const std::vector<bool>& wanted) const;

  unsigned bits_ = 1;
  std::size_t count_ = 0;
  std::vector<std::uint64_t> words_;  // the labels, packed from the low bits up
  std::vector<std::size_t> sizes_;    // per label: its elements
};

}  // namespace deepcut::undo
