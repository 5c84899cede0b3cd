// SPDX-License-Identifier: MIT
#include "geometry/polygon_triangulation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>
#include <tuple>
#include <utility>

namespace deepcut::geometry {
namespace {

// One polygon being clipped: a ring of corners over `poly`, linked by prev/next, that loses one
// corner per clip. The origin is where the fallback scan and the last triangle start: the corner
// before the last clip (kQueued) or the first remaining corner in input order (kExhaustive).
class EarClipper {
 public:
  EarClipper(const std::vector<glm::dvec2>& pts, std::vector<std::uint32_t> poly, EarSearch search)
      : pts_(pts), poly_(std::move(poly)), search_(search) {
    if (search_ == EarSearch::kQueued) {
      poly_.erase(std::unique(poly_.begin(), poly_.end()), poly_.end());
      while (poly_.size() > 1 && poly_.front() == poly_.back()) poly_.pop_back();
    }
    const std::size_t n = poly_.size();
    prev_.resize(n);
    next_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      prev_[i] = (i + n - 1) % n;
      next_[i] = (i + 1) % n;
    }
    alive_.assign(n, 1);
    reflex_.assign(n, 0);
    version_.assign(n, 0);
    remaining_ = n;
    if (search_ == EarSearch::kQueued) make_grid();
  }

  void run(std::vector<LocalTri>& out) {
    const std::size_t n = poly_.size();
    if (n < 3) return;
    for (std::size_t i = 0; i < n; ++i) update_reflex(i);
    if (search_ == EarSearch::kQueued)
      for (std::size_t i = 0; i < n; ++i)
        if (is_ear(i)) ears_.push({quality(i), i, version_[i]});
    while (remaining_ > 3) {
      std::size_t i = search_ == EarSearch::kQueued ? pop_ear() : scan_ears();
      bool emit = true;
      if (i == n) std::tie(i, emit) = most_convex();
      clip(i, emit, out);
    }
    const std::size_t a = origin_, b = next_[a], c = next_[b];
    if (corner_at(a, b, c) > 0.0) out.push_back({poly_[a], poly_[b], poly_[c]});
  }

 private:
  struct Entry {
    double quality;
    std::size_t i;
    std::uint32_t version;
    bool operator<(const Entry& o) const { return quality < o.quality; }
  };

  const glm::dvec2& at(std::size_t i) const { return pts_[poly_[i]]; }
  double corner_at(std::size_t a, std::size_t b, std::size_t c) const { return orient(at(a), at(b), at(c)); }
  double corner(std::size_t i) const { return corner_at(prev_[i], i, next_[i]); }
  double longest(std::size_t i) const {
    const glm::dvec2 &a = at(prev_[i]), &b = at(i), &c = at(next_[i]);
    return std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
  }
  double quality(std::size_t i) const { return corner(i) / std::max(longest(i), 1e-300); }

  void update_reflex(std::size_t i) {
    const bool r = corner(i) <= 0.0;
    if (r && !reflex_[i]) {
      reflex_list_.push_back(i);
      if (!cell_head_.empty()) {
        const std::size_t c = cell_y(at(i).y) * grid_x_ + cell_x(at(i).x);
        cell_link_.push_back({static_cast<std::uint32_t>(i), cell_head_[c]});
        cell_head_[c] = static_cast<std::uint32_t>(cell_link_.size() - 1);
      }
    }
    reflex_[i] = r;
  }

  // A uniform grid over the points (about one cell per corner) filing every corner that became
  // reflex, so an ear test looks at the reflex corners near the ear only. A cell index is a
  // non-decreasing function of the coordinate, so every point of a closed triangle lies in the
  // cells of its bounding box; the scan takes one cell more on each side.
  void make_grid() {
    const std::size_t n = poly_.size();
    if (n < 64) return;
    glm::dvec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (std::uint32_t p : poly_) {
      lo = glm::min(lo, pts_[p]);
      hi = glm::max(hi, pts_[p]);
    }
    const auto side = static_cast<std::size_t>(std::sqrt(double(n)));
    grid_x_ = grid_y_ = side;
    origin_xy_ = lo;
    const glm::dvec2 extent = hi - lo;
    inv_cell_.x = extent.x > 0.0 && std::isfinite(extent.x) ? double(side) / extent.x : 0.0;
    inv_cell_.y = extent.y > 0.0 && std::isfinite(extent.y) ? double(side) / extent.y : 0.0;
    cell_head_.assign(grid_x_ * grid_y_, kNoLink);
  }
  static std::size_t clamp_cell(double c, std::size_t cells) {
    if (!(c > 0.0)) return 0;  // NaN too
    return c >= double(cells - 1) ? cells - 1 : static_cast<std::size_t>(c);
  }
  std::size_t cell_x(double x) const { return clamp_cell((x - origin_xy_.x) * inv_cell_.x, grid_x_); }
  std::size_t cell_y(double y) const { return clamp_cell((y - origin_xy_.y) * inv_cell_.y, grid_y_); }

  // True when some live reflex corner q (`blocks(q)`) lies in the ear (a, b, c): through the grid
  // where its cells are fewer than the reflex corners, else through the list. Same answer.
  template <class Blocks>
  bool reflex_blocker(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c, Blocks&& blocks) const {
    if (!cell_head_.empty()) {
      const std::size_t x0 = cell_x(std::min({a.x, b.x, c.x})), x1 = cell_x(std::max({a.x, b.x, c.x}));
      const std::size_t y0 = cell_y(std::min({a.y, b.y, c.y})), y1 = cell_y(std::max({a.y, b.y, c.y}));
      const std::size_t xa = x0 > 0 ? x0 - 1 : 0, xb = std::min(x1 + 1, grid_x_ - 1);
      const std::size_t ya = y0 > 0 ? y0 - 1 : 0, yb = std::min(y1 + 1, grid_y_ - 1);
      if ((xb - xa + 1) * (yb - ya + 1) < reflex_list_.size()) {
        for (std::size_t y = ya; y <= yb; ++y)
          for (std::size_t x = xa; x <= xb; ++x)
            for (std::uint32_t k = cell_head_[y * grid_x_ + x]; k != kNoLink; k = cell_link_[k].second) {
              const std::size_t q = cell_link_[k].first;
              if (alive_[q] && reflex_[q] && blocks(q)) return true;
            }
        return false;
      }
    }
    for (std::size_t q : reflex_list_)
      if (alive_[q] && reflex_[q] && blocks(q)) return true;
    return false;
  }

  // Positive area beyond the tolerance and no other polygon point in the closed triangle.
  bool is_ear(std::size_t i) const {
    const std::uint32_t ia = poly_[prev_[i]], ib = poly_[i], ic = poly_[next_[i]];
    const glm::dvec2 &a = pts_[ia], &b = pts_[ib], &c = pts_[ic];
    const double tiny = search_ == EarSearch::kExhaustive ? 1e-13 * longest(i) : 0.0;
    if (corner(i) <= tiny) return false;
    auto blocks = [&](std::size_t q) {
      const std::uint32_t iq = poly_[q];
      if (iq == ia || iq == ib || iq == ic) return false;  // the same point (bridges repeat points)
      const glm::dvec2& p = pts_[iq];
      return orient(a, b, p) >= -tiny && orient(b, c, p) >= -tiny && orient(c, a, p) >= -tiny;
    };
    if (search_ == EarSearch::kQueued) {
      // Only a reflex corner can lie inside an ear of a weakly simple polygon.
      return !reflex_blocker(a, b, c, blocks);
    }
    std::size_t q = origin_;
    for (std::size_t k = 0; k < remaining_; ++k, q = next_[q])
      if (blocks(q)) return false;
    return true;
  }

  // The best queued ear still valid, or n.
  std::size_t pop_ear() {
    while (!ears_.empty()) {
      const Entry e = ears_.top();
      ears_.pop();
      if (alive_[e.i] && e.version == version_[e.i]) return e.i;
    }
    return poly_.size();
  }

  // The best ear among all corners (the first one in input order on ties), or n.
  std::size_t scan_ears() const {
    std::size_t best = poly_.size();
    double best_quality = -1.0;
    std::size_t i = origin_;
    for (std::size_t k = 0; k < remaining_; ++k, i = next_[i]) {
      if (!is_ear(i)) continue;
      const double q = quality(i);
      if (q > best_quality) {
        best_quality = q;
        best = i;
      }
    }
    return best;
  }

  // No ear (numerically degenerate input): the most convex corner, and whether it has area.
  std::pair<std::size_t, bool> most_convex() const {
    double best = -std::numeric_limits<double>::max();
    std::size_t i = origin_, j = origin_;
    for (std::size_t k = 0; k < remaining_; ++k, j = next_[j])
      if (corner(j) > best) {
        best = corner(j);
        i = j;
      }
    return {i, best > 0.0};
  }

  void clip(std::size_t i, bool emit, std::vector<LocalTri>& out) {
    const std::size_t a = prev_[i], c = next_[i];
    if (emit) out.push_back({poly_[a], poly_[i], poly_[c]});
    alive_[i] = 0;
    next_[a] = c;
    prev_[c] = a;
    --remaining_;
    if (search_ == EarSearch::kExhaustive) {
      if (origin_ == i) origin_ = c;
      update_reflex(a);
      update_reflex(c);
      return;
    }
    origin_ = a;
    for (std::size_t j : {a, c}) {
      ++version_[j];
      update_reflex(j);
      if (is_ear(j)) ears_.push({quality(j), j, version_[j]});
    }
  }

  const std::vector<glm::dvec2>& pts_;
  std::vector<std::uint32_t> poly_;
  EarSearch search_;
  std::vector<std::size_t> prev_, next_;
  std::vector<char> alive_, reflex_;
  std::vector<std::uint32_t> version_;
  std::vector<std::size_t> reflex_list_;
  // The grid of reflex corners (kQueued, 64 corners and more): per cell the latest filing, each
  // filing (corner, the cell's previous filing).
  static constexpr std::uint32_t kNoLink = ~std::uint32_t(0);
  std::vector<std::uint32_t> cell_head_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> cell_link_;
  std::size_t grid_x_ = 0, grid_y_ = 0;
  glm::dvec2 origin_xy_{0.0}, inv_cell_{0.0};
  std::priority_queue<Entry> ears_;
  std::size_t remaining_ = 0;
  std::size_t origin_ = 0;
};

// The (outer, hole) position pairs a bridge may join, in the order they are tried.
std::vector<std::pair<std::size_t, std::size_t>> bridge_candidates(const std::vector<glm::dvec2>& pts,
                                                                   const std::vector<std::uint32_t>& outer,
                                                                   const std::vector<std::uint32_t>& hole,
                                                                   HoleBridge rule) {
  std::vector<std::pair<std::size_t, std::size_t>> tries;
  tries.reserve(rule == HoleBridge::kRightmost ? outer.size() : outer.size() * hole.size());
  if (rule == HoleBridge::kRightmost) {
    std::size_t hi = 0;
    for (std::size_t i = 1; i < hole.size(); ++i)
      if (pts[hole[i]].x > pts[hole[hi]].x) hi = i;
    const glm::dvec2 h = pts[hole[hi]];
    std::vector<std::size_t> order(outer.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return glm::length(pts[outer[a]] - h) < glm::length(pts[outer[b]] - h);
    });
    for (std::size_t o : order) tries.emplace_back(o, hi);
    return tries;
  }
  std::vector<std::tuple<double, std::size_t, std::size_t>> pairs;
  pairs.reserve(outer.size() * hole.size());
  for (std::size_t o = 0; o < outer.size(); ++o)
    for (std::size_t h = 0; h < hole.size(); ++h) pairs.emplace_back(glm::length(pts[outer[o]] - pts[hole[h]]), o, h);
  std::sort(pairs.begin(), pairs.end());
  for (const auto& [dist, o, h] : pairs) tries.emplace_back(o, h);
  return tries;
}

// `outer` up to position o, the hole once around from position h back to it, then `outer` from o.
std::vector<std::uint32_t> join_at(const std::vector<std::uint32_t>& outer, const std::vector<std::uint32_t>& hole,
                                   std::size_t o, std::size_t h, bool spliced) {
  std::vector<std::uint32_t> merged;
  merged.reserve(outer.size() + hole.size() + 2);
  merged.insert(merged.end(), outer.begin(), outer.begin() + static_cast<std::ptrdiff_t>(o) + 1);
  for (std::size_t k = spliced ? 1 : 0; k <= hole.size(); ++k) merged.push_back(hole[(h + k) % hole.size()]);
  merged.insert(merged.end(), outer.begin() + static_cast<std::ptrdiff_t>(o) + (spliced ? 1 : 0), outer.end());
  return merged;
}

}  // namespace

void clip_ears(const std::vector<glm::dvec2>& pts, std::vector<std::uint32_t> poly, EarSearch search,
               std::vector<LocalTri>& out) {
  EarClipper(pts, std::move(poly), search).run(out);
}

std::vector<std::uint32_t> bridge_hole(const std::vector<glm::dvec2>& pts, const std::vector<std::uint32_t>& outer,
                                       const std::vector<std::uint32_t>& hole,
                                       const std::vector<std::vector<std::uint32_t>>& others, HoleBridge rule) {
  if (outer.empty() || hole.empty()) return outer;
  if (rule == HoleBridge::kNearestPair)
    for (std::size_t o = 0; o < outer.size(); ++o)
      for (std::size_t h = 0; h < hole.size(); ++h)
        if (outer[o] == hole[h]) return join_at(outer, hole, o, h, true);
  const auto tries = bridge_candidates(pts, outer, hole, rule);
  auto [bo, bh] = tries.front();
  for (const auto& [o, h] : tries) {
    const glm::dvec2 &p = pts[outer[o]], &q = pts[hole[h]];
    bool blocked = false;
    auto check = [&](const std::vector<std::uint32_t>& loop) {
      for (std::size_t i = 0; i < loop.size() && !blocked; ++i)
        blocked = segments_cross(p, q, pts[loop[i]], pts[loop[(i + 1) % loop.size()]]);
    };
    check(outer);
    check(hole);
    if (rule == HoleBridge::kNearestPair)
      for (const auto& other : others) check(other);
    if (!blocked) {
      bo = o;
      bh = h;
      break;
    }
  }
  return join_at(outer, hole, bo, bh, false);
}

void triangulate_polygon(const std::vector<glm::dvec2>& pts, const std::vector<std::uint32_t>& outer,
                         std::vector<std::vector<std::uint32_t>> holes, const TriangulationRules& rules,
                         std::vector<LocalTri>& out) {
  // Bridge holes from right to left so earlier bridges do not block later ones.
  auto maxx = [&](const std::vector<std::uint32_t>& l) {
    double m = -std::numeric_limits<double>::max();
    for (auto i : l) m = std::max(m, pts[i].x);
    return m;
  };
  std::sort(holes.begin(), holes.end(), [&](const auto& a, const auto& b) { return maxx(a) > maxx(b); });
  std::vector<std::uint32_t> poly = outer;
  std::vector<std::vector<std::uint32_t>> later;  // the holes still to be bridged (kNearestPair)
  for (std::size_t k = 0; k < holes.size(); ++k) {
    if (rules.holes == HoleBridge::kNearestPair)
      later.assign(holes.begin() + static_cast<std::ptrdiff_t>(k) + 1, holes.end());
    poly = bridge_hole(pts, poly, holes[k], later, rules.holes);
  }
  clip_ears(pts, std::move(poly), rules.ears, out);
}

std::vector<LocalTri> triangulate_loops(const std::vector<glm::dvec2>& points,
                                        const std::vector<std::vector<std::uint32_t>>& loops, int outer_sign,
                                        const TriangulationRules& rules) {
  // Work counter-clockwise: mirror when the outer loops are clockwise, flip the output back.
  std::vector<glm::dvec2> pts = points;
  if (outer_sign < 0)
    for (auto& p : pts) p.x = -p.x;
  std::vector<std::size_t> outers, holes;
  std::vector<double> area(loops.size());
  for (std::size_t i = 0; i < loops.size(); ++i) {
    if (loops[i].size() < 3) continue;
    area[i] = signed_area2(pts, loops[i]);
    if (area[i] > 0) outers.push_back(i);
    else if (area[i] < 0) holes.push_back(i);
  }
  std::vector<std::vector<std::vector<std::uint32_t>>> holes_of(loops.size());
  for (std::size_t h : holes) {
    std::size_t owner = loops.size();
    for (std::size_t o : outers)
      if (point_in_loop(pts, loops[o], pts[loops[h][0]]) && (owner == loops.size() || area[o] < area[owner])) owner = o;
    if (owner != loops.size()) holes_of[owner].push_back(loops[h]);
  }
  std::vector<LocalTri> out;
  for (std::size_t o : outers) triangulate_polygon(pts, loops[o], std::move(holes_of[o]), rules, out);
  // Mirroring reversed orientation once, so `out` already has the outer loops' orientation.
  return out;
}

}  // namespace deepcut::geometry
