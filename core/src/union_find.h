// SPDX-License-Identifier: MIT
#pragma once
// Union-find over indices: the root of an element's set, halving the path on the way. Private to
// core (the adjacency's vertex groups, the drill's shells).

#include <cstdint>
#include <vector>

namespace deepcut::detail {

/// The root of `x` in the forest `parent` (a root is its own parent); every node on the way gets
/// its grandparent as parent.
inline std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}

}  // namespace deepcut::detail
