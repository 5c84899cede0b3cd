// SPDX-License-Identifier: MIT
// The clustering's seeds: farthest-point sampling over a PointGrid (see clustering_detail.h).
//
// Each new seed lowers the distances of the points closer to it than their current distance.
// A max tree over the grid cells (each leaf: the farthest point of its cell) gives the next seed.
// Per seed, only the cells its ball reaches are considered, and of those only the cells where a
// point could get closer: a cell whose farthest point is nearer than the cell's bounding box is
// to the seed cannot change, so it is skipped unscanned. The cells to rescan are cut into pieces
// of at most kPiece points, rescanned over the pool (a cell holds thousands of points when the
// radius is large against the model, and a seed reaches a few cells: cells alone would keep one
// or two threads busy); each cell's farthest point is then the best of its pieces'. While a seed
// reaches a quarter of the grid or more (the first few), the tree is built again over the pool
// instead of updated per cell. Every piece reads and writes only its own points, the best of a
// cell's points does not depend on how they are cut, and the tree is the max tree of its leaves
// whatever the order of the updates, so the seeds do not depend on the thread count, nor on the
// skipping (a skipped cell's leaf would not have changed).

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
    // About kPiece points per chunk: a coarse grid's cells hold thousands of points each (a fixed
    // grain of cells put them all in one chunk, a whole pass over the points on this thread).
    const std::size_t cell_grain =
        std::max<std::size_t>(1, cells * kPiece / std::max<std::size_t>(1, items.size()));
    parallel_for(cells, cell_grain, [&](std::size_t b, std::size_t e) {
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
      const bool rebuild = box.cells() * 4 >= grid_.cell_count();
      if (rebuild && box.cells() > kMaxListedCells)
        visit_all(ps, box);
      else
        visit_listed(ps, box, rebuild);
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
  // A seed reaching more cells than this while the tree is built again (a fine grid) has its
  // cells tested and rescanned per row of cells over the pool (visit_all), not listed first.
  static constexpr std::size_t kMaxListedCells = std::size_t(1) << 16;
  // The most points of one piece of a cell's rescan, and the fewest points per pool chunk (small
  // cells' pieces are rescanned together). Small: a later seed rescans a few thousand points, and
  // a rescan runs inline when the pieces before the last total under kPiece points.
  static constexpr std::size_t kPiece = 1024;

  // Tests every non-empty cell of `box` (the cells within reach) for a seed at `ps`, rows of
  // cells over the pool, and rescans those that may change, their leaves written in place; then
  // builds the tree's inner nodes again, level after level over the pool (the max tree of its
  // leaves, what the updates of visit_listed keep it).
  void visit_all(const glm::vec3& ps, const PointGrid::CellBox& box) {
    parallel_for(box.rows(), 16, [&](std::size_t b, std::size_t e) {
      grid_.for_each_cell_in_rows(box, b, e, [&](std::size_t c) {
        if (!unchanged(c, ps)) tree_[leaves_ + c] = rescan(grid_.slot_begin(c), grid_.slot_begin(c + 1), ps);
      });
    });
    build_tree();
  }

  // The tree's inner nodes from its leaves, level after level over the pool.
  void build_tree() {
    for (std::size_t level = leaves_ / 2; level >= 1; level /= 2)
      parallel_for(level, 1 << 14, [&](std::size_t b, std::size_t e) {
        for (std::size_t node = level + b; node < level + e; ++node) {
          const Item& a = tree_[2 * node];
          const Item& x = tree_[2 * node + 1];
          tree_[node] = better(x, a) ? x : a;
        }
      });
  }

  // Tests the non-empty cells of `box` (the cells within reach) for a seed at `ps`, listed on
  // the calling thread, and rescans those that may change in pieces over the pool; then writes
  // their leaves and builds the tree again over the pool (`rebuild`), or updates the tree from
  // each rescanned cell.
  void visit_listed(const glm::vec3& ps, const PointGrid::CellBox& box, bool rebuild) {
    cells_.clear();
    grid_.for_each_cell_in_rows(box, 0, box.rows(), [&](std::size_t cell) { cells_.push_back(cell); });
    rescanned_.resize(cells_.size());
    parallel_for(cells_.size(), 1024, [&](std::size_t b, std::size_t e) {
      for (std::size_t k = b; k < e; ++k) rescanned_[k] = !unchanged(cells_[k], ps);
    });
    // The pieces, cell after cell; the pool's chunks: runs of pieces of kPiece points or more.
    pieces_.clear();
    chunk_start_.clear();
    std::size_t points = kPiece;  // in the chunk being filled
    for (std::size_t k = 0; k < cells_.size(); ++k) {
      if (!rescanned_[k]) continue;
      const std::size_t end = grid_.slot_begin(cells_[k] + 1);
      for (std::size_t b = grid_.slot_begin(cells_[k]); b < end; b += kPiece) {
        if (points >= kPiece) {
          chunk_start_.push_back(pieces_.size());
          points = 0;
        }
        const std::size_t e = std::min(end, b + kPiece);
        pieces_.push_back({k, b, e});
        points += e - b;
      }
    }
    chunk_start_.push_back(pieces_.size());
    tops_.resize(pieces_.size());
    parallel_for(chunk_start_.size() - 1, 1, [&](std::size_t c, std::size_t) {
      for (std::size_t i = chunk_start_[c]; i < chunk_start_[c + 1]; ++i)
        tops_[i] = rescan(pieces_[i].begin, pieces_[i].end, ps);
    });
    // Each rescanned cell's farthest point: the best of its pieces' (in order, one cell at a time).
    for (std::size_t i = 0; i < pieces_.size();) {
      const std::size_t k = pieces_[i].cell;
      Item top = tops_[i];
      for (++i; i < pieces_.size() && pieces_[i].cell == k; ++i)
        if (better(tops_[i], top)) top = tops_[i];
      if (rebuild)
        tree_[leaves_ + cells_[k]] = top;
      else
        update(cells_[k], top);
    }
    if (rebuild) build_tree();
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

  // The farthest of the points in slots [begin, end) after the seed at `ps`; lowers their
  // distances.
  Item rescan(std::size_t begin, std::size_t end, const glm::vec3& ps) {
    const std::vector<std::uint32_t>& items = grid_.items();
    Item top = kNone;
    for (std::size_t i = begin; i < end; ++i) {
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
  // visit_listed's cells, whether each is rescanned, the pieces (the cell's index in cells_ and
  // a range of slots), the first piece of each pool chunk, the farthest point of each piece.
  struct Piece {
    std::size_t cell, begin, end;
  };
  std::vector<std::size_t> cells_;
  std::vector<std::uint8_t> rescanned_;
  std::vector<Piece> pieces_;
  std::vector<std::size_t> chunk_start_;
  std::vector<Item> tops_;
};

}  // namespace

std::vector<std::uint32_t> farthest_point_seeds(const std::vector<glm::vec3>& rest, const std::uint32_t* ids,
                                                std::size_t count, const PointGrid& grid, float cover) {
  if (count == 0) return {};
  // The first seed: the point farthest from the bounding-box centre, ties to the smaller index.
  const BoundingBox& box = grid.bounds();
  const glm::vec3 centre = 0.5f * (box.min + box.max);
  struct Far {
    float d2;
    std::uint32_t v;
  };
  auto farther = [](Far a, Far b) { return b.d2 > a.d2 || (b.d2 == a.d2 && b.v < a.v) ? b : a; };
  const Far first = parallel_reduce(
      count, 1 << 16, Far{-1.0f, ids[0]},
      [&](std::size_t b, std::size_t e) {
        Far best{-1.0f, ids[b]};
        for (std::size_t i = b; i < e; ++i) best = farther(best, {distance2(rest[ids[i]], centre), ids[i]});
        return best;
      },
      farther);
  return FarthestPointSampler(rest, grid).run(first.v, cover);
}

}  // namespace deepcut::clustering_detail
