// SPDX-License-Identifier: MIT
// The clustering's seeds: farthest-point sampling over a PointGrid (see clustering_detail.h).
//
// Each new seed lowers the distances of the points closer to it than their current distance.
// A max tree over the grid cells (each leaf: the farthest point of its cell) gives the next seed.
// Per seed, only the cells its ball reaches are considered, and of those only the cells where a
// point could get closer: a cell whose farthest point is nearer than the cell's bounding box is
// to the seed cannot change, so it is skipped unscanned. The cells are tested and rescanned in
// parallel when there are enough of them; while a seed reaches a quarter of the grid or more (the
// first few), the tree is built again over the pool instead of updated per cell. Every cell's rescan reads
// and writes only its own points, and the tree is the max tree of its leaves whatever the order of the
// updates, so the seeds do not depend on the thread count, nor on the skipping (a skipped cell's leaf would
// not have changed).

#include <algorithm>
#include <cmath>
#include <limits>

#include "deepcut/core/parallel.h"
#include "softbody/clustering_detail.h"
#include "softbody/point_grid.h"
#include "uninit_vector.h"

namespace deepcut::clustering_detail {
namespace {

class FarthestPointSampler {
 public:
  // Every array is written whole over the pool (the tree when the first seed has scanned every
  // cell), none filled first on the calling thread.
  FarthestPointSampler(const std::vector<glm::vec3>& rest, const PointGrid& grid) : rest_(rest), grid_(grid) {
    const std::vector<std::uint32_t>& items = grid.items();
    at_.resize(items.size());
    dist2_.resize(items.size());
    parallel_for(items.size(), 1 << 15, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        at_[i] = rest[items[i]];
        dist2_[i] = std::numeric_limits<float>::infinity();
      }
    });
    const std::size_t cells = grid.cell_count();
    lo_.resize(cells);
    hi_.resize(cells);
    parallel_for(cells, 1 << 12, [&](std::size_t b, std::size_t e) {
      for (std::size_t c = b; c < e; ++c) {
        glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
        for (std::size_t i = grid_.slot_begin(c); i < grid_.slot_begin(c + 1); ++i) {
          lo = glm::min(lo, at_[i]);
          hi = glm::max(hi, at_[i]);
        }
        lo_[c] = lo;
        hi_[c] = hi;
      }
    });
    while (leaves_ < cells) leaves_ *= 2;
    tree_.resize(2 * leaves_);
    parallel_for(tree_.size(), 1 << 16, [&](std::size_t b, std::size_t e) {
      for (std::size_t k = b; k < e; ++k) tree_[k] = kNone;
    });
  }

  // Seeds from `first` on until every point lies within `cover` of one.
  std::vector<std::uint32_t> run(std::uint32_t first, float cover) {
    std::vector<std::uint32_t> seeds;
    const float cover2 = cover * cover;
    std::uint32_t seed = first;
    float reach = std::numeric_limits<float>::infinity();
    for (;;) {
      seeds.push_back(seed);
      const glm::vec3 ps = rest_[seed];
      // Early seeds reach most of the grid: every cell is tested over the pool and the tree built
      // again over the pool; later ones only the cells near them, the tree updated per cell.
      const PointGrid::CellBox box = grid_.cells_near(ps, reach);
      if (box.cells() * 4 >= grid_.cell_count())
        visit_all(ps, box);
      else
        visit_near(ps, box);
      const Item top = tree_[1];
      if (top.v == kInvalidIndex || top.d2 <= cover2) break;
      seed = top.v;
      reach = std::sqrt(top.d2);
    }
    return seeds;
  }

 private:
  // Not initialised by itself: the tree's arrays are filled over the pool.
  struct Item {
    float d2;
    std::uint32_t v;
  };
  static constexpr Item kNone{-1.0f, kInvalidIndex};
  // Fewer cells than this near a seed are tested and rescanned on the calling thread.
  static constexpr std::size_t kMinCellsPerChunk = 8;

  // Tests every non-empty cell of `box` (the cells within reach) for a seed at `ps`, rows of
  // cells over the pool, and rescans those that may change, their leaves written in place; then
  // builds the tree's inner nodes again, level after level over the pool (the max tree of its
  // leaves, what the updates of visit_near keep it).
  void visit_all(const glm::vec3& ps, const PointGrid::CellBox& box) {
    parallel_for(box.rows(), 16, [&](std::size_t b, std::size_t e) {
      grid_.for_each_cell_in_rows(box, b, e, [&](std::size_t c) {
        if (!unchanged(c, ps)) tree_[leaves_ + c] = rescan(c, ps);
      });
    });
    for (std::size_t level = leaves_ / 2; level >= 1; level /= 2)
      parallel_for(level, 1 << 14, [&](std::size_t b, std::size_t e) {
        for (std::size_t node = level + b; node < level + e; ++node) {
          const Item& a = tree_[2 * node];
          const Item& x = tree_[2 * node + 1];
          tree_[node] = better(x, a) ? x : a;
        }
      });
  }

  // Tests the cells of `box` (the cells within reach) for a seed at `ps` and rescans those that
  // may change, a few cells per chunk so that the threads stay busy though cells differ in size;
  // then updates the tree from each rescanned cell.
  void visit_near(const glm::vec3& ps, const PointGrid::CellBox& box) {
    cells_.clear();
    grid_.for_each_cell_in_rows(box, 0, box.rows(), [&](std::size_t cell) { cells_.push_back(cell); });
    tops_.resize(cells_.size());
    rescanned_.resize(cells_.size());
    const std::size_t grain = std::max(kMinCellsPerChunk, cells_.size() / (8 * thread_count()));
    parallel_for(cells_.size(), grain, [&](std::size_t b, std::size_t e) {
      for (std::size_t k = b; k < e; ++k) {
        rescanned_[k] = !unchanged(cells_[k], ps);
        if (rescanned_[k]) tops_[k] = rescan(cells_[k], ps);
      }
    });
    for (std::size_t k = 0; k < cells_.size(); ++k)
      if (rescanned_[k]) update(cells_[k], tops_[k]);
  }

  // Farther first; among equals the smaller vertex index.
  static bool better(const Item& a, const Item& b) { return a.d2 > b.d2 || (a.d2 == b.d2 && a.v < b.v); }

  // True when no point of `cell` can get closer to a seed at `ps`: the farthest point of the cell
  // (its leaf) is nearer than the cell's box is to `ps`, with a margin well above the rounding
  // of distance2. Never for a cell not scanned yet.
  bool unchanged(std::size_t cell, const glm::vec3& ps) const {
    const Item& leaf = tree_[leaves_ + cell];
    if (leaf.v == kInvalidIndex) return false;
    double gap2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double g = std::max({double(lo_[cell][k]) - ps[k], double(ps[k]) - hi_[cell][k], 0.0});
      gap2 += g * g;
    }
    return double(leaf.d2) < gap2 * (1.0 - 1e-4);
  }

  // The cell's farthest point after the seed at `ps`; lowers the distances of its points.
  Item rescan(std::size_t cell, const glm::vec3& ps) {
    const std::vector<std::uint32_t>& items = grid_.items();
    Item top = kNone;
    for (std::size_t i = grid_.slot_begin(cell); i < grid_.slot_begin(cell + 1); ++i) {
      const float d2 = std::min(dist2_[i], distance2(at_[i], ps));
      dist2_[i] = d2;
      if (better({d2, items[i]}, top)) top = {d2, items[i]};
    }
    return top;
  }

  void update(std::size_t cell, const Item& top) {
    std::size_t node = leaves_ + cell;
    tree_[node] = top;
    for (node /= 2; node >= 1; node /= 2) {
      const Item& a = tree_[2 * node];
      const Item& b = tree_[2 * node + 1];
      const Item up = better(b, a) ? b : a;
      if (tree_[node].d2 == up.d2 && tree_[node].v == up.v) break;
      tree_[node] = up;
    }
  }

  const std::vector<glm::vec3>& rest_;
  const PointGrid& grid_;
  detail::UninitVector<glm::vec3> at_;       // the points' positions, in grid order
  detail::UninitVector<float> dist2_;        // squared distance to the nearest seed, in grid order
  detail::UninitVector<glm::vec3> lo_, hi_;  // the box of each cell's points
  std::size_t leaves_ = 1;
  detail::UninitVector<Item> tree_;  // a max tree over the cells: leaf c the farthest point of cell c
  // visit_near's cells, the farthest point of each, whether it was rescanned.
  std::vector<std::size_t> cells_;
  std::vector<Item> tops_;
  std::vector<std::uint8_t> rescanned_;
};

}  // namespace

std::vector<std::uint32_t> farthest_point_seeds(const std::vector<glm::vec3>& rest,
                                                const std::vector<std::uint32_t>& ids, const PointGrid& grid,
                                                float cover) {
  if (ids.empty()) return {};
  // The first seed: the point farthest from the bounding-box centre, ties to the smaller index.
  const BoundingBox& box = grid.bounds();
  const glm::vec3 centre = 0.5f * (box.min + box.max);
  struct Far {
    float d2;
    std::uint32_t v;
  };
  auto farther = [](Far a, Far b) { return b.d2 > a.d2 || (b.d2 == a.d2 && b.v < a.v) ? b : a; };
  const Far first = parallel_reduce(
      ids.size(), 1 << 16, Far{-1.0f, ids[0]},
      [&](std::size_t b, std::size_t e) {
        Far best{-1.0f, ids[b]};
        for (std::size_t i = b; i < e; ++i) best = farther(best, {distance2(rest[ids[i]], centre), ids[i]});
        return best;
      },
      farther);
  return FarthestPointSampler(rest, grid).run(first.v, cover);
}

}  // namespace deepcut::clustering_detail
