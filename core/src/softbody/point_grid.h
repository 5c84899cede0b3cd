// SPDX-License-Identifier: MIT
#pragma once
// A uniform grid over a set of points (private to core): the clustering's seed sampling and its
// search for a particle near an uncovered vertex.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "deepcut/core/parallel.h"
#include "deepcut/core/surface_mesh.h"

namespace deepcut::clustering_detail {

/// A uniform grid over a set of points, stored as a counting-sorted list per cell (CSR).
class PointGrid {
 public:
  PointGrid(const std::vector<glm::vec3>& pos, const std::vector<std::uint32_t>& ids, float cell)
      : pos_(pos) {
    // The box and each point's cell in parallel (min / max and disjoint writes: the same grid
    // whatever the thread count); the counting sort serially.
    constexpr std::size_t kGrain = 1 << 15;
    box_ = parallel_reduce(
        ids.size(), kGrain, BoundingBox{},
        [&](std::size_t b, std::size_t e) {
          BoundingBox part;
          for (std::size_t i = b; i < e; ++i) part.add(pos[ids[i]]);
          return part;
        },
        [](BoundingBox a, const BoundingBox& b) {
          a.add(b);
          return a;
        });
    const glm::vec3 ext = box_.empty() ? glm::vec3(0.0f) : box_.max - box_.min;
    // Cap the cell count (a tiny cell relative to the model would make a huge grid).
    const double max_cells = std::max(4096.0, 2.0 * double(ids.size()));
    h_ = std::max(cell, 1e-30f);
    for (int guard = 0; guard < 64; ++guard) {
      const double n = (std::floor(double(ext.x) / h_) + 1) * (std::floor(double(ext.y) / h_) + 1) *
                       (std::floor(double(ext.z) / h_) + 1);
      if (n <= max_cells) break;
      h_ = static_cast<float>(h_ * std::max(1.01, std::cbrt(n / max_cells)));
    }
    for (int k = 0; k < 3; ++k) dims_[k] = static_cast<int>(std::floor(double(ext[k]) / h_)) + 1;
    const std::size_t cells = std::size_t(dims_[0]) * dims_[1] * dims_[2];
    std::vector<std::size_t> cell_of_id(ids.size());
    parallel_for(ids.size(), kGrain, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) cell_of_id[i] = cell_of(pos[ids[i]]);
    });
    start_.assign(cells + 1, 0);
    for (std::size_t c : cell_of_id) ++start_[c + 1];
    for (std::size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
    items_.resize(ids.size());
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < ids.size(); ++i) items_[fill[cell_of_id[i]]++] = ids[i];
  }

  std::size_t cell_count() const { return start_.size() - 1; }
  /// The points, cell after cell; cell `c` holds slots [slot_begin(c), slot_begin(c + 1)).
  const std::vector<std::uint32_t>& items() const { return items_; }
  std::size_t slot_begin(std::size_t c) const { return start_[c]; }
  /// The bounding box of the points.
  const BoundingBox& bounds() const { return box_; }
  /// The points of cell `c`.
  const std::uint32_t* cell_begin(std::size_t c) const { return items_.data() + start_[c]; }
  const std::uint32_t* cell_end(std::size_t c) const { return items_.data() + start_[c + 1]; }

  /// Calls fn(cell) for every non-empty cell the ball (c, r) overlaps.
  template <class F>
  void for_each_cell_near(const glm::vec3& c, float r, F&& fn) const {
    if (items_.empty()) return;
    int lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
      lo[k] = clamp_cell(std::floor((double(c[k]) - r - box_.min[k]) / h_), k);
      hi[k] = clamp_cell(std::floor((double(c[k]) + r - box_.min[k]) / h_), k);
    }
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y) {
        const std::size_t row = (std::size_t(z) * dims_[1] + y) * dims_[0];
        for (int x = lo[0]; x <= hi[0]; ++x)
          if (start_[row + x] != start_[row + x + 1]) fn(row + x);
      }
  }

  /// Calls fn(v) for every point in the cells the ball (c, r) overlaps (a superset of the ball).
  template <class F>
  void for_each_near(const glm::vec3& c, float r, F&& fn) const {
    for_each_cell_near(c, r, [&](std::size_t cell) {
      for (const std::uint32_t* v = cell_begin(cell); v != cell_end(cell); ++v) fn(*v);
    });
  }

 private:
  int clamp_cell(double x, int k) const {
    return static_cast<int>(std::min(std::max(x, 0.0), double(dims_[k] - 1)));
  }
  std::size_t cell_of(const glm::vec3& p) const {
    std::size_t idx[3];
    for (int k = 0; k < 3; ++k)
      idx[k] = std::size_t(clamp_cell(std::floor(double(p[k] - box_.min[k]) / h_), k));
    return (idx[2] * dims_[1] + idx[1]) * dims_[0] + idx[0];
  }

  const std::vector<glm::vec3>& pos_;
  BoundingBox box_;
  float h_ = 1.0f;
  int dims_[3] = {1, 1, 1};
  std::vector<std::uint32_t> start_, items_;
};

}  // namespace deepcut::clustering_detail
