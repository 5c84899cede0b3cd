// SPDX-License-Identifier: MIT
#include "ops/common/crossing_table.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace deepcut::detail {

void EdgeSlots::reserve(std::size_t edges) {
  std::size_t size = 16;
  int shift = 60;
  while (size < 2 * edges) {
    size *= 2;
    --shift;
  }
  if (size > keys_.size()) rehash(size, shift);
}

void EdgeSlots::rehash(std::size_t size, int shift) {
  std::vector<std::uint64_t> old_keys(size, kNoKey);
  std::vector<std::uint32_t> old_entries(size, 0);
  old_keys.swap(keys_);
  old_entries.swap(entries_);
  shift_ = shift;
  const std::size_t mask = size - 1;
  for (std::size_t i = 0; i < old_keys.size(); ++i) {
    if (old_keys[i] == kNoKey) continue;
    std::size_t slot = slot_of(old_keys[i]);
    while (keys_[slot] != kNoKey) slot = (slot + 1) & mask;
    keys_[slot] = old_keys[i];
    entries_[slot] = old_entries[i];
  }
}

std::uint32_t EdgeSlots::find(std::uint64_t key) const {
  if (keys_.empty()) return kNone;
  const std::size_t mask = keys_.size() - 1;
  for (std::size_t slot = slot_of(key); keys_[slot] != kNoKey; slot = (slot + 1) & mask)
    if (keys_[slot] == key) return entries_[slot];
  return kNone;
}

void EdgeSlots::insert(std::uint64_t key, std::uint32_t entry) {
  if (2 * (count_ + 1) > keys_.size()) reserve(2 * count_ + 16);
  const std::size_t mask = keys_.size() - 1;
  std::size_t slot = slot_of(key);
  while (keys_[slot] != kNoKey) slot = (slot + 1) & mask;
  keys_[slot] = key;
  entries_[slot] = entry;
  ++count_;
}

std::pair<std::uint32_t, bool> EdgeSlots::find_or_insert(std::uint64_t key, std::uint32_t next_entry) {
  if (!keys_.empty()) {
    const std::size_t mask = keys_.size() - 1;
    std::size_t slot = slot_of(key);
    for (; keys_[slot] != kNoKey; slot = (slot + 1) & mask)
      if (keys_[slot] == key) return {entries_[slot], false};
    if (2 * (count_ + 1) <= keys_.size()) {  // room: file it in the empty slot the probe ended at
      keys_[slot] = key;
      entries_[slot] = next_entry;
      ++count_;
      return {next_entry, true};
    }
  }
  insert(key, next_entry);
  return {next_entry, true};
}

void EdgeSlots::clear() {
  if (count_ == 0) return;
  std::fill(keys_.begin(), keys_.end(), kNoKey);
  count_ = 0;
}

bool NeedleMerges::merge_if_coincident(const SurfaceMesh& mesh, VertexId a, VertexId b) {
  a = merged(a);
  b = merged(b);
  if (a == b || mesh.position(a) != mesh.position(b)) return false;
  to_.emplace(std::max(a, b).index, std::min(a, b));
  return true;
}

bool NeedleMerges::merge_if_near(const SurfaceMesh& mesh, VertexId a, VertexId b) {
  a = merged(a);
  b = merged(b);
  if (a == b) return false;
  const glm::vec3 pa = mesh.position(a), pb = mesh.position(b);
  const float scale = std::max({std::abs(pa.x), std::abs(pa.y), std::abs(pa.z), std::abs(pb.x), std::abs(pb.y),
                                std::abs(pb.z), std::numeric_limits<float>::min()});
  if (pa != pb && glm::distance(pa, pb) > 4.0f * std::numeric_limits<float>::epsilon() * scale) return false;
  to_.emplace(std::max(a, b).index, std::min(a, b));
  return true;
}

}  // namespace deepcut::detail
