// SPDX-License-Identifier: MIT
#pragma once
// A map from vertex ids to small numbers for the few vertices an edit touched, cleared in O(1):
// each entry carries the generation that wrote it, and starting over bumps the generation. Its
// memory (one entry per vertex of the largest mesh seen) is reused from call to call on each
// thread (scratch()), so a local edit pays for what it touches, not for the mesh (no per-call
// array as long as the mesh, no hashing in the hot loops). Private to core's operations.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace deepcut::detail {

class VertexSlots {
 public:
  static constexpr std::uint32_t kNone = 0xffffffffu;

  /// Forgets every entry and makes room for vertex ids below `vertex_count`.
  void reset(std::size_t vertex_count) {
    if (entries_.size() < vertex_count) entries_.resize(vertex_count, Entry{0, kNone});
    if (++generation_ == 0) {  // wrapped: old entries could look current
      for (Entry& e : entries_) e = Entry{0, kNone};
      generation_ = 1;
    }
  }
  /// Sets vertex `v`'s value (v below the count given to reset).
  void set(std::uint32_t v, std::uint32_t value) { entries_[v] = Entry{generation_, value}; }
  /// Vertex `v`'s value, kNone when unset (any id: ones beyond the count are unset).
  std::uint32_t get(std::uint32_t v) const {
    if (v >= entries_.size()) return kNone;
    const Entry& e = entries_[v];
    return e.generation == generation_ ? e.value : kNone;
  }
  bool has(std::uint32_t v) const { return get(v) != kNone; }

  /// This thread's scratch map: one user at a time (each resets it and is done with it before
  /// the next starts; none of them nests another).
  static VertexSlots& scratch() {
    thread_local VertexSlots map;
    return map;
  }

 private:
  struct Entry {
    std::uint32_t generation, value;
  };
  std::vector<Entry> entries_;
  std::uint32_t generation_ = 0;
};

}  // namespace deepcut::detail
