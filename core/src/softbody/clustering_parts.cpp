// SPDX-License-Identifier: MIT
// The connected parts of one particle's members from their union-find roots (parts_by_group of
// clustering_detail.h), for Clusters::split_disconnected (clustering_split.cpp): the members are
// numbered by part, the parts given their places (the main one, then the minors in root order),
// and each member filed under its part.

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "clustering_detail.h"

namespace deepcut::clustering_detail {
namespace {

// Up to this many parts, numbered by a linear search on the stack; past it, by a binary search.
constexpr std::size_t kLinearRoots = 16;

// The parts numbered by the linear search: their roots in the order met, sizes and places.
struct LinearParts {
  std::uint32_t roots[kLinearRoots];
  std::uint32_t sizes[kLinearRoots];
  std::uint32_t slot[kLinearRoots];  // per part: kInvalidIndex (main) or its minor's index
  std::size_t count = 0;
};

// Numbers the members' parts in the order their roots are met (`group[i]`, that of m[i]), the
// last root met tried first. Returns false (and stops) on meeting more than kLinearRoots roots.
bool number_by_linear_search(const std::vector<std::uint32_t>& m, const std::vector<std::uint32_t>& root,
                             std::vector<std::uint32_t>& group, LinearParts& parts) {
  std::size_t last = 0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    assert((i == 0 || m[i - 1] < m[i]) && "parts_by_group: members not strictly ascending");
    if (parts.count == 0 || parts.roots[last] != root[i]) {
      last = 0;
      while (last < parts.count && parts.roots[last] != root[i]) ++last;
      if (last == parts.count) {
        if (parts.count == kLinearRoots) return false;
        parts.roots[parts.count] = root[i];
        parts.sizes[parts.count++] = 0;
      }
    }
    ++parts.sizes[last];
    group[i] = static_cast<std::uint32_t>(last);
  }
  return true;
}

// The places of the linearly numbered parts: in root order, the largest (the first on ties) the
// main one, the others the minors.
void place_linear_parts(LinearParts& parts) {
  std::uint32_t order[kLinearRoots];
  const auto count = static_cast<std::uint32_t>(parts.count);
  for (std::uint32_t g = 0; g < count; ++g) order[g] = g;
  std::sort(order, order + count,
            [&](std::uint32_t a, std::uint32_t b) { return parts.roots[a] < parts.roots[b]; });
  std::uint32_t best = order[0];
  for (std::uint32_t k = 1; k < count; ++k)
    if (parts.sizes[order[k]] > parts.sizes[best]) best = order[k];
  for (std::uint32_t k = 0, minor = 0; k < count; ++k)
    parts.slot[order[k]] = order[k] == best ? kInvalidIndex : minor++;
}

// Numbers the members' parts by their roots' places in the sorted unique list of all the roots
// (already in root order), into scratch.group and scratch.sizes. Returns the number of parts.
std::size_t number_by_sorted_roots(const std::vector<std::uint32_t>& m,
                                   const std::vector<std::uint32_t>& root, PartsScratch& scratch) {
  std::vector<std::uint32_t>& distinct = scratch.distinct;
  distinct.assign(root.begin(), root.begin() + static_cast<std::ptrdiff_t>(m.size()));
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  scratch.sizes.assign(distinct.size(), 0);
  for (std::size_t i = 0; i < m.size(); ++i) {
    scratch.group[i] = static_cast<std::uint32_t>(
        std::lower_bound(distinct.begin(), distinct.end(), root[i]) - distinct.begin());
    ++scratch.sizes[scratch.group[i]];
  }
  return distinct.size();
}

// The places of the parts numbered in root order, into scratch.slot: the largest (the first on
// ties) the main one, the others the minors.
void place_sorted_parts(std::size_t count, PartsScratch& scratch) {
  const std::vector<std::uint32_t>& sizes = scratch.sizes;
  std::uint32_t best = 0;
  for (std::uint32_t g = 1; g < count; ++g)
    if (sizes[g] > sizes[best]) best = g;
  scratch.slot.resize(count);
  for (std::uint32_t g = 0, minor = 0; g < count; ++g) scratch.slot[g] = g == best ? kInvalidIndex : minor++;
}

// Each member m[i] filed, in order, under its part `group[i]` of `count`, at the part's place.
Parts file_members(const std::vector<std::uint32_t>& m, const std::vector<std::uint32_t>& group,
                   const std::uint32_t* sizes, const std::uint32_t* slot, std::size_t count) {
  Parts parts;
  parts.minors.resize(count - 1);
  auto out = [&](std::uint32_t g) -> std::vector<std::uint32_t>& {
    return slot[g] == kInvalidIndex ? parts.main : parts.minors[slot[g]];
  };
  for (std::uint32_t g = 0; g < count; ++g) out(g).reserve(sizes[g]);
  for (std::size_t i = 0; i < m.size(); ++i) out(group[i]).push_back(m[i]);
  return parts;
}

}  // namespace

Parts parts_by_group(const std::vector<std::uint32_t>& m, const std::vector<std::uint32_t>& root,
                     PartsScratch& scratch) {
  if (m.empty()) return Parts{};
  scratch.group.resize(m.size());
  LinearParts linear;  // up to kLinearRoots parts: on the stack, no search through a sorted list
  if (number_by_linear_search(m, root, scratch.group, linear)) {
    place_linear_parts(linear);
    return file_members(m, scratch.group, linear.sizes, linear.slot, linear.count);
  }
  const std::size_t count = number_by_sorted_roots(m, root, scratch);
  place_sorted_parts(count, scratch);
  return file_members(m, scratch.group, scratch.sizes.data(), scratch.slot.data(), count);
}

}  // namespace deepcut::clustering_detail
