// SPDX-License-Identifier: MIT
// Soft-body clusters: the storage helpers of Clusters (rows in the pool, renormalised weights,
// new particles and their rest centres), shared by the build, the split and the apply.
#include <algorithm>

#include "deepcut/core/softbody/clustering.h"

namespace deepcut {

void Clusters::set_row(std::uint32_t v, const Influence* first, std::size_t count) {
  Row& r = rows_[v];
  if (count > r.capacity) {
    pool_garbage_ += r.capacity;
    r.begin = static_cast<std::uint32_t>(pool_.size());
    r.capacity = static_cast<std::uint32_t>(count);
    pool_.resize(pool_.size() + count);
  }
  std::copy(first, first + count, pool_.begin() + r.begin);
  r.size = static_cast<std::uint32_t>(count);
  sort_row(v);
}

void Clusters::sort_row(std::uint32_t v) {
  const Row& r = rows_[v];
  Influence* row = pool_.data() + r.begin;
  // Rows are short: insertion sort.
  for (std::uint32_t i = 1; i < r.size; ++i)
    for (std::uint32_t j = i; j > 0 && row[j].particle < row[j - 1].particle; --j)
      std::swap(row[j], row[j - 1]);
}

void Clusters::compact_pool() {
  decltype(pool_) pool;
  pool.reserve(pool_.size() - pool_garbage_);
  for (Row& r : rows_) {
    const auto b = static_cast<std::uint32_t>(pool.size());
    pool.insert(pool.end(), pool_.begin() + r.begin, pool_.begin() + r.begin + r.size);
    r.begin = b;
    r.capacity = r.size;
  }
  pool_.swap(pool);
  pool_garbage_ = 0;
}

void Clusters::renormalise(std::uint32_t v) {
  const Row& r = rows_[v];
  double sum = 0.0;
  for (std::uint32_t i = 0; i < r.size; ++i) sum += pool_[r.begin + i].weight;
  for (std::uint32_t i = 0; i < r.size; ++i) {
    Influence& e = pool_[r.begin + i];
    e.weight = sum > 0.0 ? static_cast<float>(e.weight / sum) : 1.0f / float(r.size);
  }
}

void Clusters::recompute_centre(std::uint32_t p, const std::vector<glm::vec3>& rest) {
  const auto& m = members_[p];
  if (m.empty()) {
    centres_[p] = seeds_[p];
    return;
  }
  glm::dvec3 sum(0.0);
  for (std::uint32_t v : m) sum += glm::dvec3(rest[v]);
  centres_[p] = glm::vec3(sum / double(m.size()));
}

std::uint32_t Clusters::new_particle(const glm::vec3& seed_ref) {
  // Copy first: callers pass seeds_[i], which seeds_.push_back may reallocate (ASan found the
  // read of the freed seed in centres_.push_back).
  const glm::vec3 seed = seed_ref;
  const auto p = static_cast<std::uint32_t>(seeds_.size());
  seeds_.push_back(seed);
  centres_.push_back(seed);
  members_.emplace_back();
  return p;
}

std::size_t Clusters::particle_count() const {
  std::size_t n = 0;
  for (const auto& m : members_) n += m.empty() ? 0 : 1;
  return n;
}

}  // namespace deepcut
