// SPDX-License-Identifier: MIT
#pragma once
// The crossings of a conforming insertion (cut, tear, drill): what the tool does to each mesh
// edge it meets, found by the edge, and the needle merges between the vertices made there.
// Private to core. The operations are described in docs/architecture.md.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

#include "deepcut/core/surface_mesh.h"

namespace deepcut::detail {

/// Key of the undirected edge {a, b}: the lower index in the high word.
inline std::uint64_t edge_key(VertexId a, VertexId b) {
  const auto lo = std::min(a.index, b.index), hi = std::max(a.index, b.index);
  return (std::uint64_t(lo) << 32) | hi;
}

/// Key of the directed edge a -> b.
inline std::uint64_t directed_key(VertexId a, VertexId b) { return (std::uint64_t(a.index) << 32) | b.index; }

/// Open-addressing slots (at most half full) from edge keys to entry numbers. Lookups never
/// depend on the layout, so growing it changes no result.
class EdgeSlots {
 public:
  /// Room for `edges` keys without growing.
  void reserve(std::size_t edges);
  /// Entry number of `key`, or kNone.
  std::uint32_t find(std::uint64_t key) const;
  /// Files `key` (not filed yet) as entry `entry`; grows first when half full.
  void insert(std::uint64_t key, std::uint32_t entry);
  /// Entry number of `key` and false when filed; otherwise files it as `next_entry` (one probe
  /// sequence for both) and returns that and true.
  std::pair<std::uint32_t, bool> find_or_insert(std::uint64_t key, std::uint32_t next_entry);
  void clear();
  static constexpr std::uint32_t kNone = ~std::uint32_t(0);

 private:
  std::size_t slot_of(std::uint64_t key) const {
    return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> shift_);
  }
  void rehash(std::size_t size, int shift);
  static constexpr std::uint64_t kNoKey = ~std::uint64_t(0);  // edge_key of no real edge
  std::vector<std::uint64_t> keys_;
  std::vector<std::uint32_t> entries_;
  std::size_t count_ = 0;
  int shift_ = 64;
};

/// Value-initialised records appended in order that never move: blocks of kBlock records, so
/// finding record i is a shift and a mask (a deque holds only a few large records per block and
/// divides to find one), and a table of a few hundred edges allocates a few blocks, not dozens.
template <class T>
class StableRecords {
 public:
  T& operator[](std::size_t i) { return blocks_[i >> kShift][i & (kBlock - 1)]; }
  const T& operator[](std::size_t i) const { return blocks_[i >> kShift][i & (kBlock - 1)]; }
  std::size_t size() const { return size_; }
  /// Appends a record equal to T(): a new block's are made so, and clear() remakes used ones.
  T& emplace_back() {
    if (size_ == blocks_.size() * kBlock) blocks_.push_back(std::make_unique<T[]>(kBlock));
    return (*this)[size_++];
  }
  /// Forgets every record (the blocks stay, their used records remade as T()).
  void clear() {
    for (std::size_t i = 0; i < size_; ++i) (*this)[i] = T();
    size_ = 0;
  }

  /// Iterates the records in order.
  template <bool Const>
  class Iterator {
   public:
    using List = std::conditional_t<Const, const StableRecords, StableRecords>;
    Iterator(List* list, std::size_t i) : list_(list), i_(i) {}
    auto& operator*() const { return (*list_)[i_]; }
    Iterator& operator++() {
      ++i_;
      return *this;
    }
    bool operator!=(const Iterator& o) const { return i_ != o.i_; }

   private:
    List* list_;
    std::size_t i_;
  };
  Iterator<false> begin() { return {this, 0}; }
  Iterator<false> end() { return {this, size_}; }
  Iterator<true> begin() const { return {this, 0}; }
  Iterator<true> end() const { return {this, size_}; }

 private:
  static constexpr std::size_t kShift = 6, kBlock = std::size_t(1) << kShift;
  std::vector<std::unique_ptr<T[]>> blocks_;
  std::size_t size_ = 0;
};

/// Edge -> crossing record `T` (what the operation keeps per crossed edge: parameters, the
/// vertices made there). Records live in insertion order and never move (references stay valid
/// as edges are added); iteration runs in insertion order. Sized up front with `reserve`.
template <class T>
class CrossingTable {
 public:
  void reserve(std::size_t edges) { slots_.reserve(edges); }
  /// The record of edge {a, b}, or nullptr.
  T* find(VertexId a, VertexId b) { return at_entry(slots_.find(edge_key(a, b))); }
  const T* find(VertexId a, VertexId b) const {
    const std::uint32_t e = slots_.find(edge_key(a, b));
    return e == EdgeSlots::kNone ? nullptr : &records_[e];
  }
  /// The record of the edge with key `key` (edge_key), or nullptr.
  T* find_key(std::uint64_t key) { return at_entry(slots_.find(key)); }
  const T* find_key(std::uint64_t key) const {
    const std::uint32_t e = slots_.find(key);
    return e == EdgeSlots::kNone ? nullptr : &records_[e];
  }
  /// The record of edge {a, b}, default-made when the edge is new (`second` true: fill it in).
  /// A plain find first: most calls find their edge, and this inlines cheaper there than
  /// find_or_insert.
  std::pair<T*, bool> try_emplace(VertexId a, VertexId b) {
    const auto [e, added] = try_emplace_index(a, b);
    return {&records_[e], added};
  }
  /// As try_emplace, with the record's index (operator[]) instead of its address.
  std::pair<std::uint32_t, bool> try_emplace_index(VertexId a, VertexId b) {
    const std::uint64_t key = edge_key(a, b);
    const std::uint32_t e = slots_.find(key);
    if (e != EdgeSlots::kNone) return {e, false};
    const auto added = static_cast<std::uint32_t>(records_.size());
    slots_.insert(key, added);
    keys_.push_back(key);
    records_.emplace_back();
    return {added, true};
  }
  std::size_t size() const { return records_.size(); }
  bool empty() const { return records_.size() == 0; }
  /// Edge key of the i-th record (insertion order).
  std::uint64_t key(std::size_t i) const { return keys_[i]; }
  T& operator[](std::size_t i) { return records_[i]; }
  const T& operator[](std::size_t i) const { return records_[i]; }
  auto begin() { return records_.begin(); }
  auto end() { return records_.end(); }
  auto begin() const { return records_.begin(); }
  auto end() const { return records_.end(); }
  /// Forgets every edge (the slots keep their room).
  void clear() {
    slots_.clear();
    keys_.clear();
    records_.clear();
  }

 private:
  T* at_entry(std::uint32_t e) { return e == EdgeSlots::kNone ? nullptr : &records_[e]; }
  EdgeSlots slots_;
  std::vector<std::uint64_t> keys_;
  StableRecords<T> records_;
};

/// Crossings that fell on one bind position (the two long edges of a needle crossed at the same
/// parameter) become one vertex: the later vertex maps to the earlier, so the needle's tip is
/// not made as a zero-area face. A forest of links to lower vertices; `merged` follows them.
class NeedleMerges {
 public:
  /// The vertex `v` stands for (itself unless merged).
  VertexId merged(VertexId v) const {
    if (to_.empty()) return v;  // the common case: no needle, no hashing
    for (auto it = to_.find(v.index); it != to_.end(); it = to_.find(v.index)) v = it->second;
    return v;
  }
  /// Links `from` to `to` unless `from` is linked already (the first link stays).
  void merge(VertexId from, VertexId to) { to_.emplace(from.index, to); }
  /// The cut's and drill's rule: merged(a) and merged(b), when distinct at one bind position of
  /// `mesh`, become one (the higher links to the lower). True when they were linked.
  bool merge_if_coincident(const SurfaceMesh& mesh, VertexId a, VertexId b);
  /// The cut's rule for the two crossings of one face: as above, and also when their bind
  /// positions are a few float steps apart (at most 4 float epsilons of their largest coordinate).
  /// Crossings that close lie on a sliver: the face between them and the lone corner, or the
  /// needle they would leave behind for a later cut to split, is float noise, and rounds to zero
  /// area. Crossings of any other face are farther apart (the plane snaps corners within 1e-5 of
  /// the model size onto it).
  bool merge_if_near(const SurfaceMesh& mesh, VertexId a, VertexId b);
  bool empty() const { return to_.empty(); }
  std::size_t size() const { return to_.size(); }
  void clear() { to_.clear(); }

 private:
  std::unordered_map<std::uint32_t, VertexId> to_;
};

}  // namespace deepcut::detail
