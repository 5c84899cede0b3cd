// SPDX-License-Identifier: MIT
#pragma once
// Posed positions while an operation edits a mesh: the caller's positions of the input vertices,
// the operation's own for the vertices it adds, and for input vertices it moves. Private to core.
// The operations predicate on posed positions and edit the bind ones (docs/architecture.md).

#include <algorithm>
#include <cstdint>
#include <glm/glm.hpp>
#include <utility>
#include <vector>

#include "deepcut/core/surface_mesh.h"

namespace deepcut::detail {

/// `Vec` is the precision the operation computes in (glm::vec3 for the cut and the tear,
/// glm::dvec3 for the drill); the input positions are float and are read as `Vec`.
template <class Vec>
class PosedOverlay {
 public:
  /// `input`: one posed position per vertex of the mesh as the operation starts (kept by
  /// reference: it must outlive the overlay and not change while it is used).
  explicit PosedOverlay(const std::vector<glm::vec3>& input)
      : input_(input), first_new_(static_cast<std::uint32_t>(input.size())) {}

  /// Posed position of vertex `v`: added, moved, or the input's.
  Vec operator()(std::uint32_t v) const {
    if (v >= first_new_) return added_[v - first_new_];
    if (might_be_moved(v)) {
      const auto it = find_moved(v);
      if (it != moved_.end() && it->first == v) return it->second;
    }
    return Vec(input_[v]);
  }
  Vec operator()(VertexId v) const { return (*this)(v.index); }
  /// Whether input vertex `v` was moved (added vertices never are).
  bool is_moved(VertexId v) const {
    if (!might_be_moved(v.index)) return false;
    const auto it = find_moved(v.index);
    return it != moved_.end() && it->first == v.index;
  }

  /// Posed position of the vertex just added (vertices are added in id order).
  void add(const Vec& p) { added_.push_back(p); }
  /// Posed position of added vertex `v`, in any order (slots between stay value-initialised
  /// until set).
  void set_added(VertexId v, const Vec& p) {
    const std::size_t i = v.index - first_new_;
    if (added_.size() <= i) added_.resize(i + 1);
    added_[i] = p;
  }
  /// New posed position of input vertex `v` (below first_new()).
  void move(VertexId v, const Vec& p) {
    const auto it = moved_.begin() + (find_moved(v.index) - moved_.cbegin());
    if (it != moved_.end() && it->first == v.index) {
      it->second = p;
    } else {
      moved_.insert(it, {v.index, p});
      moved_bits_[(v.index >> 6) & (kMovedWords - 1)] |= std::uint64_t(1) << (v.index & 63);
    }
  }

  /// First vertex the operation added (the input's vertex count).
  std::uint32_t first_new() const { return first_new_; }
  const std::vector<glm::vec3>& input() const { return input_; }
  /// Positions of the added vertices, by id from first_new().
  const std::vector<Vec>& added() const { return added_; }
  /// Moved input vertices with their new positions, by vertex id.
  const std::vector<std::pair<std::uint32_t, Vec>>& moved() const { return moved_; }

 private:
  // A filter over the moved vertices (bit v mod kMovedWords * 64 set for each): most lookups are
  // of vertices never moved, answered here without searching moved_.
  static constexpr std::uint32_t kMovedWords = 16;
  bool might_be_moved(std::uint32_t v) const {
    return (moved_bits_[(v >> 6) & (kMovedWords - 1)] >> (v & 63)) & 1;
  }
  // The first entry of moved_ not below vertex `v`.
  typename std::vector<std::pair<std::uint32_t, Vec>>::const_iterator find_moved(std::uint32_t v) const {
    return std::lower_bound(
        moved_.begin(), moved_.end(), v,
        [](const std::pair<std::uint32_t, Vec>& x, std::uint32_t i) { return x.first < i; });
  }

  const std::vector<glm::vec3>& input_;
  std::uint32_t first_new_;
  std::vector<Vec> added_;
  std::vector<std::pair<std::uint32_t, Vec>> moved_;
  std::uint64_t moved_bits_[kMovedWords] = {};
};

}  // namespace deepcut::detail
