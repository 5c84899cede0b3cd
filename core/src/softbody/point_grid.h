// SPDX-License-Identifier: MIT
#pragma once
// A uniform grid over a set of points (private to core): the clustering's seed sampling and its
// search for a particle near an uncovered vertex.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "csr_fill.h"
#include "deepcut/core/parallel.h"
#include "deepcut/core/surface_mesh.h"
#include "uninit_vector.h"

namespace deepcut::clustering_detail {

/// A uniform grid over a set of points, stored as a counting-sorted list per cell (CSR): each
/// cell lists its points in the order of `ids`.
class PointGrid {
 public:
  /// `ids`: a vector of uint32 point indices (any allocator).
  template <class Ids>
  PointGrid(const std::vector<glm::vec3>& pos, const Ids& ids, float cell) : pos_(pos) {
    // The box in parallel (min / max: the same grid whatever the thread count).
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
    // Each point's cell, then the points packed per cell (their positions in `ids`, in order),
    // then the positions replaced by the ids: every pass over the pool.
    detail::UninitVector<std::size_t> cell_of_id(ids.size());
    parallel_for(ids.size(), kGrain, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) cell_of_id[i] = cell_of(pos[ids[i]]);
    });
    detail::fill_csr(ids.size(), cells, start_, items_,
                     [&](std::size_t i, auto&& visit) { visit(cell_of_id[i]); });
    parallel_for(items_.size(), kGrain, [&](std::size_t b, std::size_t e) {
      for (std::size_t k = b; k < e; ++k) items_[k] = ids[items_[k]];
    });
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

  /// A box of cells: lo[k] .. hi[k] along axis k; its rows run along x, one per (y, z).
  struct CellBox {
    int lo[3], hi[3];
    std::size_t rows() const { return std::size_t(hi[1] - lo[1] + 1) * std::size_t(hi[2] - lo[2] + 1); }
    std::size_t cells() const { return rows() * std::size_t(hi[0] - lo[0] + 1); }
  };

  /// The cells the ball (c, r) overlaps.
  CellBox cells_near(const glm::vec3& c, float r) const {
    CellBox box;
    for (int k = 0; k < 3; ++k) {
      box.lo[k] = clamp_cell(std::floor((double(c[k]) - r - box_.min[k]) / h_), k);
      box.hi[k] = clamp_cell(std::floor((double(c[k]) + r - box_.min[k]) / h_), k);
    }
    return box;
  }

  /// Calls fn(cell) for every non-empty cell of rows [b, e) of `box`, in increasing order.
  template <class F>
  void for_each_cell_in_rows(const CellBox& box, std::size_t b, std::size_t e, F&& fn) const {
    const std::size_t ny = std::size_t(box.hi[1] - box.lo[1] + 1);
    for (std::size_t r = b; r < e; ++r) {
      const std::size_t z = std::size_t(box.lo[2]) + r / ny, y = std::size_t(box.lo[1]) + r % ny;
      const std::size_t row = (z * dims_[1] + y) * dims_[0];
      for (int x = box.lo[0]; x <= box.hi[0]; ++x)
        if (start_[row + x] != start_[row + x + 1]) fn(row + x);
    }
  }

  /// Calls fn(cell) for every non-empty cell the ball (c, r) overlaps.
  template <class F>
  void for_each_cell_near(const glm::vec3& c, float r, F&& fn) const {
    if (items_.empty()) return;
    const CellBox box = cells_near(c, r);
    for_each_cell_in_rows(box, 0, box.rows(), fn);
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
