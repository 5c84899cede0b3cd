// SPDX-License-Identifier: MIT
#include "geometry/polygon_triangulation.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <queue>
#include <tuple>
#include <utility>

#include "kept_lists.h"

namespace deepcut::geometry {
namespace {

// An ear queued by kQueued: kLazy's `version` is its corner's version when queued, kIndexed's the
// tick it was queued at (its deferred test looks at the reflex corners live then); the same
// comparison (quality only) keeps the same order among equals.
struct Entry {
  double quality;
  std::uint32_t i;
  std::uint32_t version;
  bool operator<(const Entry& o) const { return quality < o.quality; }
};
// A filed reflex corner with its point, so a blocker test reads one record.
struct Filed {
  glm::dvec2 p;
  std::uint32_t corner, point;
};
// A cell of kQueued's grid (make_grid).
struct Cell {
  std::uint32_t x, y;
};
// The cells a corner reaches (make_grid): [x0, x1] by [y0, y1].
struct Reach {
  std::uint32_t x0, x1, y0, y1;
};
// A corner filed after the grid was laid out (self-intersecting or numerically degenerate input),
// with its cell.
struct LateFiled {
  Filed f;
  Cell cell;
};

// The corners and per-corner lists of one polygon being clipped, kept on each thread from polygon
// to polygon (the drill clips about a hundred small ones per call, a cut's cap a few: they then
// allocate nothing per polygon but kLazy's queue). Every list is written for the polygon's
// corners (or emptied) before it is read, so what an earlier polygon left does not matter. One clip at a time
// uses them (EarClipper takes them in its constructor and hands them back in its destructor; no
// clip runs inside another); when it ends, a list above detail::kKeptClipListBytes gives its
// memory back (each list judged on its own: the small ones keep theirs).
struct RingLists {
  std::vector<std::uint32_t> poly, prev, next, version, slot, ear_state;
  // kIndexed, deferred ear tests: the tick each corner was filed reflex at, and the tick it
  // stopped being reflex at (kNever where it has not).
  std::vector<std::uint32_t> since, until;
  std::vector<glm::dvec2> xy;  // the point of each corner
  std::vector<char> alive, reflex;
  std::vector<double> ear_quality, corners;
  std::vector<double> edge2;  // the squared length of the edge from each corner to the next
  // kQueued's filings and grid (EarClipper's members of these names), file_grid's working lists,
  // and kIndexed's heap.
  std::vector<Filed> reflex_list, filed;
  std::vector<LateFiled> late;
  std::vector<Cell> cell;
  std::vector<Reach> reach;
  std::vector<std::uint32_t> cell_start, cell_of, fill;
  std::vector<Entry> heap;
  bool in_use = false;

  static RingLists& local() {
    thread_local RingLists lists;
    return lists;
  }
  // Takes this thread's lists for one clip.
  static RingLists& take() {
    RingLists& lists = local();
    assert(!lists.in_use && "one ear clip at a time on a thread");
    lists.in_use = true;
    return lists;
  }
  // Ends the clip: gives back the memory of the lists above the bound.
  void hand_back() {
    constexpr std::size_t kept = detail::kKeptClipListBytes;
    for (auto* list :
         {&poly, &prev, &next, &version, &slot, &ear_state, &since, &until, &cell_start, &cell_of, &fill})
      detail::give_back_if_big(*list, kept);
    detail::give_back_if_big(reflex_list, kept);
    detail::give_back_if_big(filed, kept);
    detail::give_back_if_big(late, kept);
    detail::give_back_if_big(cell, kept);
    detail::give_back_if_big(reach, kept);
    detail::give_back_if_big(heap, kept);
    detail::give_back_if_big(xy, kept);
    detail::give_back_if_big(alive, kept);
    detail::give_back_if_big(reflex, kept);
    detail::give_back_if_big(ear_quality, kept);
    detail::give_back_if_big(corners, kept);
    detail::give_back_if_big(edge2, kept);
    in_use = false;
  }
};

// How kQueued keeps its ears. The order of clipping is the priority queue's: std::priority_queue
// over every ear found, stale ones dropped when they come up (kLazy). Where no two ears tie for
// the best, any queue that gives the best ear clips the same ears: kIndexed keeps one entry per
// corner (a binary heap whose entries move when their corner changes, so it pops clips only) and
// stops when the best ear ties with another one, or a quality is not a number; the polygon is
// then clipped again through kLazy, whose order among equals is the one the results were made
// with.
//
// kIndexed defers each ear's blocker test (reflex_blocker) from when its corner is queued to when
// it comes to the top of the heap: most corners are queued again (a neighbour clipped) before
// they come up, so the test is made about once per ear clipped instead of once per corner queued.
// The clip is the same as testing when queued (as kLazy does, and kIndexed with
// EarTests::kWhenQueued: DeferredEarTestsClipTheSame in polygon_triangulation_test.cpp compares
// the two on spirals whose blockers turn convex first, and on self-intersecting and numerically
// degenerate polygons):
// - The deferred test is the same test. The ear's corners are those it was queued with (a
//   neighbour clipped queues it again, at a new tick), and it looks at the reflex corners live at
//   the tick it was queued at: filed at or before it, and not unfiled by it (lists_.since,
//   lists_.until; ticks count the changes of reflex corners, in the order testing when queued
//   sees them). Filings stale now stay in the lists for that. It goes through the grid or the
//   list as testing when queued would: by the filings made up to that tick (filings_ less the
//   late filings after it: late_ is in tick order, and never pruned when deferring), since grid
//   and list may disagree on a needle ear. A corner filed twice (reflex, convex, reflex again:
//   self-intersecting or numerically degenerate input) would need two spans: the clip stops as at
//   a tie, and is made again through kLazy.
// - So the heap holds every ear testing when queued holds, and corners found blocked when they
//   come up (taken out then; a neighbour clipped queues them again, as it would). The first entry
//   that comes up unblocked is the best ear testing when queued has. A tie of two such ears shows
//   as before: an entry equal to the root has an equal parent, up to a child of the root. A tie
//   with an entry not tested yet stops the clip too (the same clip, made through kLazy).
// - MirrorClip: the mirror image's clip (deferring too) makes the same decisions. Each corner's
//   convexity is checked when it changes, each ear test made here is checked (reflex_blocker
//   <true>), and each ear clipped beats every entry left in the heap by the margin (pop_ear), those
//   not tested yet too. The mirror image's heap holds the same entries but for ones found blocked
//   here and taken out while the mirror image still holds them (it may order them within rounding
//   after the ear clipped next): when they come up there they are found blocked too (the same
//   test, checked here), unless a clip queued them again first, as it does here. So the ear it
//   clips next is the one clipped here, every time; and where one of those ties with it there,
//   the mirror image is clipped again through kLazy, which tests when queued and never holds
//   them: the same clip again.
enum class EarQueue { kIndexed, kLazy };

// One polygon being clipped: a ring of corners over `poly`, linked by prev/next, that loses one
// corner per clip. The origin is where the fallback scan and the last triangle start: the corner
// before the last clip (kQueued) or the first remaining corner in input order (kExhaustive).
class EarClipper {
 public:
  EarClipper(const std::vector<glm::dvec2>& pts, const std::vector<std::uint32_t>& poly, EarSearch search,
             EarQueue queue = EarQueue::kLazy, MirrorClip* mirror = nullptr,
             EarTests tests = EarTests::kWhenQueued)
      : pts_(pts),
        lists_(RingLists::take()),
        search_(search),
        indexed_(queue == EarQueue::kIndexed),
        deferred_(search == EarSearch::kQueued && indexed_ && tests == EarTests::kWhenTop),
        mirror_(search == EarSearch::kQueued && indexed_ ? mirror : nullptr) {
    lists_.poly.assign(poly.begin(), poly.end());
    if (search_ == EarSearch::kQueued) {
      lists_.poly.erase(std::unique(lists_.poly.begin(), lists_.poly.end()), lists_.poly.end());
      while (lists_.poly.size() > 1 && lists_.poly.front() == lists_.poly.back()) lists_.poly.pop_back();
    }
    const auto n = static_cast<std::uint32_t>(lists_.poly.size());
    lists_.xy.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) lists_.xy[i] = pts_[lists_.poly[i]];
    if (mirror_) set_margin(poly.size());
    lists_.prev.resize(n);
    lists_.next.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) {
      lists_.prev[i] = i - 1;
      lists_.next[i] = i + 1;
    }
    if (n > 0) {
      lists_.prev[0] = n - 1;
      lists_.next[n - 1] = 0;
    }
    lists_.edge2.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) lists_.edge2[i] = edge_length2(i, lists_.next[i]);
    lists_.alive.assign(n, 1);
    lists_.reflex.assign(n, 0);
    if (indexed_)
      lists_.slot.assign(n, kNoSlot);
    else
      lists_.version.assign(n, 0);
    if (deferred_) {
      lists_.since.assign(n, kNever);
      lists_.until.assign(n, kNever);
    }
    remaining_ = n;
    reflex_list_.clear();
    late_.clear();
    if (search_ == EarSearch::kQueued) make_grid();
    if (search_ == EarSearch::kExhaustive) {
      lists_.ear_state.assign(n, kUnknown);
      lists_.ear_quality.assign(n, 0.0);
    }
  }
  EarClipper(const EarClipper&) = delete;
  EarClipper& operator=(const EarClipper&) = delete;
  ~EarClipper() {
    if (mirror_) mirror_->exact = exact_ && !tied_;
    lists_.hand_back();
  }

  // Returns false, having stopped part way, where kIndexed met a tie (see EarQueue).
  bool run(std::vector<LocalTri>& out) {
    const std::size_t n = lists_.poly.size();
    if (n <= 3) exact_ = false;  // no clip: the closing triangle starts where the ring does
    if (n < 3) return true;
    std::vector<double>& corners = lists_.corners;
    corners.resize(n);
    for (std::size_t i = 0; i < n; ++i) corners[i] = update_reflex(i);
    if (search_ == EarSearch::kQueued) {
      file_grid();
      heap_.clear();
      if (!indexed_) {
        std::vector<Entry> room;
        room.reserve(3 * n);  // every corner once, then at most two per clip
        ears_ = std::priority_queue<Entry>(std::less<Entry>(), std::move(room));
      }
      for (std::size_t i = 0; i < n; ++i)
        queue_if_ear(i, corners[i]);
    }
    while (remaining_ > 3) {
      std::size_t i = search_ == EarSearch::kQueued ? pop_ear() : scan_ears();
      if (tied_) return false;
      bool emit = true;
      if (i == n) {
        exact_ = false;
        std::tie(i, emit) = most_convex();
      }
      clip(i, emit, out);
    }
    const std::size_t a = origin_, b = lists_.next[a], c = lists_.next[b];
    const double last = corner_at(a, b, c);
    if (mirror_) {
      check_margin(last);
      mirror_->closed = last > 0.0;
    }
    if (last > 0.0) out.push_back({lists_.poly[a], lists_.poly[b], lists_.poly[c]});
    return true;
  }

 private:
  const glm::dvec2& at(std::size_t i) const { return lists_.xy[i]; }
  double corner_at(std::size_t a, std::size_t b, std::size_t c) const { return orient(at(a), at(b), at(c)); }
  double corner(std::size_t i) const { return corner_at(lists_.prev[i], i, lists_.next[i]); }
  // The squared length of the edge from corner a to corner b: glm::dot(b - a, b - a), the value
  // longest_edge2 takes (the same from b to a: negation is exact).
  double edge_length2(std::size_t a, std::size_t b) const {
    const glm::dvec2 d = at(b) - at(a);
    return glm::dot(d, d);
  }
  // longest_edge2 of corner i's triangle: its two edges kept (lists_.edge2), the diagonal made.
  double longest(std::size_t i) const {
    const std::size_t a = lists_.prev[i], c = lists_.next[i];
    return std::max({lists_.edge2[a], lists_.edge2[i], edge_length2(c, a)});
  }
  double quality(std::size_t i) const { return ear_quality(corner(i), longest(i)); }

  // MirrorClip: the margin a decision on an orient()-like value v (a difference of two products
  // of coordinate differences of polygon points) needs, and the check of one. Every such
  // difference is at most the points' extent D in magnitude (rounding is monotone), so each
  // product at most D^2 (1 + u) (u = 2^-53 ~ 1.11e-16, the unit roundoff), and the value of either
  // clip (the mirror image's takes other differences of the same points, with the same
  // magnitudes) is within about 4u (two differences, a product, the final difference) of each of
  // the two products, 8u D^2 ~ 8.9e-16 D^2 in all, of the exact value: the two clips' values
  // differ by up to 16u D^2 ~ 1.8e-15 D^2. The margin, 4e-15 D^2, is more than twice that: a value
  // beyond it in one clip has the same sign, beyond 2.2e-15 D^2, in the other. Not exact where D^2
  // is out of [1e-200, 1e200] (underflow, overflow) or not a number, or where repeated points were
  // dropped (fewer corners than `given`).
  void set_margin(std::size_t given) {
    if (lists_.poly.size() != given) exact_ = false;
    glm::dvec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const glm::dvec2& p : lists_.xy) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    const double d = std::max(hi.x - lo.x, hi.y - lo.y), d2 = d * d;
    if (!(d2 >= 1e-200 && d2 <= 1e200)) exact_ = false;
    margin_ = 4e-15 * d2;
  }
  void check_margin(double v) {
    if (!(std::abs(v) > margin_)) exact_ = false;
  }
  // MirrorClip, an ear (a, b, c) found free through the grid: the mirror image's test may look
  // at points this one did not (its grid is another), and is the same only if none of those
  // passes its rounded tests. A test of p against the side through v, w, taken as
  // (w - v) x (p - x) with x = v or w (with or without a fused multiply-add), is non-negative
  // only where the exact value is at least -3.01u (|(w - v).x (p - x).y| + |(w - v).y (p - x).x|)
  // >= -3.01u |w - v| |p - x| (u = 2^-53; rounding keeps the sign of the last difference;
  // Cauchy-Schwarz): so p lies at most g |p - x| outside that side's line, g = 3.01u. Were s the
  // distance of p from the triangle (longest edge L, perimeter P, turn = 2 x area, inradius
  // rho = turn / P), |p - x| <= s + L: every side moved out by t = g (s + L) holds p, that is the
  // triangle scaled about its incentre by 1 + t / rho, whose points lie within t L / rho of it.
  // So s <= K (s + L), K = g L P / turn, and where K <= 1/100, s <= 1.0102 K L. With K that
  // small the rounding of turn is within 3u L^2 / turn <= K / 2 (P >= 2L) of it: the bound is
  // taken as 4e-16 L^2 P / turn with P as 3L (no square roots but one), and K as that over L. make_grid's box
  // holds every point within box_reach_ of the bounding box of the ear's corners: where the bound is within
  // it, every point the mirror image's test finds was tested here, with the margin. Else (a needle: the sine
  // of its smallest angle, about turn / L^2, below about 1.2e-15 L / box_reach_, 1e-7 and less in the caps
  // clipped; the bound is tight at such a tip, whose sides both round by up to g L) reflex_blocker tests
  // every live reflex corner too, with the margin, and the clip is not exact where one of them blocks. An ear
  // found blocked needs no check: its blocker is inside the triangle by more than the rounding, in every box
  // of it.
  // `turn` and `l2` are orient(a, b, c) and longest_edge2(a, b, c) of the ear (a, b, c).
  bool within_box(double turn, double l2) const {
    const double l = std::sqrt(l2);
    const double bound = 1.2e-15 * l2 * l;  // times 1 / turn; P <= 3L
    return bound <= 0.01 * l * turn && bound <= box_reach_ * turn;
  }
  // kQueued: queues corner i (its corner() `turn`, its quality) when it is an ear: positive area
  // and no other polygon point in the closed triangle (only a reflex corner can lie inside an ear
  // of a weakly simple polygon). kIndexed moves its entry, or drops it when it is no ear.
  void queue_if_ear(std::size_t i, double turn) {
    const auto corner = static_cast<std::uint32_t>(i);
    if (turn <= 0.0) {
      if (indexed_) heap_remove(corner);
      return;
    }
    const double l2 = longest(i);
    if (!deferred_ && blocked(i, turn, l2, ticks_)) {
      if (indexed_) heap_remove(corner);
      return;
    }
    const double quality = ear_quality(turn, l2);
    if (!indexed_) {
      ears_.push({quality, corner, lists_.version[i]});
      return;
    }
    tied_ = tied_ || std::isnan(quality);
    std::uint32_t s = lists_.slot[i];
    if (s == kNoSlot) {
      s = static_cast<std::uint32_t>(heap_.size());
      heap_.emplace_back();
    }
    heap_place(s, {quality, corner, ticks_});  // deferred: the tick its test is made at
  }
  // `tick`: the tick the ear was queued at (deferred).
  bool blocked(std::size_t i, double turn, double l2, std::uint32_t tick) {
    return mirror_ ? reflex_blocker<true>(i, turn, l2, tick) : reflex_blocker<false>(i, turn, l2, tick);
  }
  // Deferred ear tests: corner i was filed reflex (r) or stopped being reflex, at a new tick. A
  // second filing of a corner (self-intersecting or numerically degenerate input) stops the clip
  // as a tie does.
  void tick(std::size_t i, bool r) {
    ++ticks_;
    if (!r) {
      lists_.until[i] = ticks_;
      return;
    }
    tied_ = tied_ || lists_.since[i] != kNever;
    lists_.since[i] = ticks_;
  }
  // Whether the filing of `corner` is live for the test being made: reflex now, or (deferred) at
  // `tick`, the tick the ear was queued at.
  bool live(std::uint32_t corner, std::uint32_t tick) const {
    if (!deferred_) return lists_.reflex[corner];
    return lists_.since[corner] <= tick && tick < lists_.until[corner];
  }
  // The filings made up to `tick` (deferred; else all of them): the count testing when queued
  // goes by. Late filings after it are the last ones of late_ (tick order, never pruned).
  std::size_t filings_at(std::uint32_t tick) const {
    std::size_t n = filings_;
    if (!deferred_) return n;
    for (std::size_t k = late_.size(); k > 0 && lists_.since[late_[k - 1].f.corner] > tick; --k) --n;
    return n;
  }

  // kIndexed: puts `e` at slot s of the heap and moves it up or down to where every entry's
  // quality is at most its parent's (lists_.slot follows the entries).
  void heap_place(std::size_t s, Entry e) {
    auto put = [&](std::size_t at, const Entry& x) {
      heap_[at] = x;
      lists_.slot[x.i] = static_cast<std::uint32_t>(at);
    };
    for (; s > 0 && heap_[(s - 1) / 2] < e; s = (s - 1) / 2) put(s, heap_[(s - 1) / 2]);
    const std::size_t size = heap_.size();
    for (std::size_t c = 2 * s + 1; c < size; s = c, c = 2 * s + 1) {
      if (c + 1 < size && heap_[c] < heap_[c + 1]) ++c;
      if (!(e < heap_[c])) break;
      put(s, heap_[c]);
    }
    put(s, e);
  }
  // kIndexed: takes corner i's entry out of the heap, if it has one.
  void heap_remove(std::uint32_t i) {
    const std::uint32_t s = lists_.slot[i];
    if (s == kNoSlot) return;
    lists_.slot[i] = kNoSlot;
    const Entry last = heap_.back();
    heap_.pop_back();
    if (s < heap_.size()) heap_place(s, last);
  }
  Filed filing(std::size_t i) const { return {at(i), static_cast<std::uint32_t>(i), lists_.poly[i]}; }

  // Whether corner i is reflex (returns its corner()); one that became reflex is filed (kQueued):
  // in the list, and once the grid is laid out, in its late filings. A dead corner is never
  // reflex. A filing whose corner is no longer reflex is stale (were the corner reflex again, it
  // would be filed again): the scans drop those.
  double update_reflex(std::size_t i) {
    const double turn = corner(i);
    if (mirror_) check_margin(turn);
    const bool r = turn <= 0.0;
    if (deferred_ && r != bool(lists_.reflex[i])) tick(i, r);
    if (r && !lists_.reflex[i] && search_ == EarSearch::kQueued) {
      ++filings_;
      reflex_list_.push_back(filing(i));
      if (grid_filed_ && grid_x_ > 0) late_.push_back({filing(i), cell_[i]});
    }
    lists_.reflex[i] = r;
    return turn;
  }

  // A uniform grid over the points (about one cell per corner) of the reflex corners, so an ear
  // test looks at the reflex corners near the ear only: in the box of the cells its corners
  // reach. A corner reaches the cells of its coordinates moved by `pad` (kBoxPad times the
  // points' largest coordinate and extent), at most one cell on from its own. A point the rounded
  // tests of reflex_blocker find in a closed triangle lies within about 1e-15 times that scale of
  // it, and a cell index is a non-decreasing function of the coordinate: so the box holds every
  // point the test can find. One cell on is where the box always reached before (and where a pad
  // that is not finite ends): within it the test finds the same points as then, from mostly one
  // or two cells a side instead of three or four.
  void make_grid() {
    const std::size_t n = lists_.poly.size();
    if (n < 64) return;
    glm::dvec2 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (std::uint32_t p : lists_.poly) {
      lo = glm::min(lo, pts_[p]);
      hi = glm::max(hi, pts_[p]);
    }
    const auto side = static_cast<std::size_t>(std::sqrt(double(n)));
    grid_x_ = grid_y_ = side;
    origin_xy_ = lo;
    const glm::dvec2 extent = hi - lo;
    inv_cell_.x = extent.x > 0.0 && std::isfinite(extent.x) ? double(side) / extent.x : 0.0;
    inv_cell_.y = extent.y > 0.0 && std::isfinite(extent.y) ? double(side) / extent.y : 0.0;
    constexpr double kBoxPad = 1e-9;
    const double pad = kBoxPad * (std::max({std::abs(lo.x), std::abs(lo.y), std::abs(hi.x), std::abs(hi.y)}) +
                                  extent.x + extent.y);
    // MirrorClip (within_box): a point within pad (1 - 1e-6) and half a cell, on each axis, of
    // the bounding box of an ear's corners is in its box: p.x >= v - pad (1 - 1e-6) is at least
    // v - pad rounded (|v| is at most 1e9 pad), so its cell is at least that of v - pad, and
    // p.x >= v - (cell width) / 2 has (p.x - origin) x inv_cell at least own - 1/2 before a
    // rounding of a few u times the cell count: its cell is at least own - 1. A coordinate of one
    // cell (no extent, or not finite) reaches every point. Not a number: never within it.
    if (mirror_) {
      auto width = [&](double e, double inv) {
        return inv > 0.0 ? e / double(side) : std::numeric_limits<double>::infinity();
      };
      box_reach_ = std::min(
          {pad * (1.0 - 1e-6), 0.5 * width(extent.x, inv_cell_.x), 0.5 * width(extent.y, inv_cell_.y)});
    }
    cell_.resize(n);
    reach_.resize(n);
    auto cell = [](std::size_t c) { return static_cast<std::uint32_t>(c); };
    for (std::size_t i = 0; i < n; ++i) {
      const glm::dvec2& p = at(i);
      const Cell own = {cell(cell_x(p.x)), cell(cell_y(p.y))};
      cell_[i] = own;
      const auto [x0, x1] = reach(p.x, pad, origin_xy_.x, inv_cell_.x, grid_x_, own.x);
      const auto [y0, y1] = reach(p.y, pad, origin_xy_.y, inv_cell_.y, grid_y_, own.y);
      reach_[i] = {x0, x1, y0, y1};
    }
  }
  // The cells [lo, hi] coordinate v of a corner in cell `own` reaches on one axis (make_grid):
  // lo = own > 0 ? max(cell(v - pad), own - 1) : 0 and hi = min(cell(v + pad), own + 1), cell
  // being clamp_cell of the same arithmetic, without its conversions. The rounded arithmetic is
  // monotone and pad is 0 or more (or not a number), so cell(v - pad) <= own <= cell(v + pad)
  // where pad is a number: lo is own just when cell(v - pad) >= own > 0, that is when
  // (v - pad - origin) * inv >= own (false for a NaN, whose cell is 0); hi is own + 1 just when
  // own + 1 is a cell and (v + pad - origin) * inv >= own + 1, else own, and 0 where that is not
  // above 0 (it is then not a number: cell 0).
  static std::pair<std::uint32_t, std::uint32_t> reach(double v, double pad, double origin, double inv,
                                                       std::size_t cells, std::uint32_t own) {
    const double lo = (v - pad - origin) * inv, hi = (v + pad - origin) * inv;
    return {own > 0 && !(lo >= double(own)) ? own - 1 : own,
            !(hi > 0.0) ? 0 : (own + 1 < cells && hi >= double(own + 1) ? own + 1 : own)};
  }
  static std::size_t clamp_cell(double c, std::size_t cells) {
    if (!(c > 0.0)) return 0;  // NaN too
    // Through a signed integer (c is below the cell count): the same value, a cheaper conversion.
    return c >= double(cells - 1) ? cells - 1 : static_cast<std::size_t>(static_cast<std::int64_t>(c));
  }
  std::size_t cell_x(double x) const { return clamp_cell((x - origin_xy_.x) * inv_cell_.x, grid_x_); }
  std::size_t cell_y(double y) const { return clamp_cell((y - origin_xy_.y) * inv_cell_.y, grid_y_); }

  // Lays the reflex corners filed so far out by cell (row-major, so the cells of one row of a box
  // are one run); later filings go to `late_`.
  void file_grid() {
    grid_filed_ = true;
    if (grid_x_ == 0) return;
    std::vector<std::uint32_t>& cell = lists_.cell_of;
    cell.resize(reflex_list_.size());
    cell_start_.assign(grid_x_ * grid_y_ + 1, 0);
    for (std::size_t k = 0; k < reflex_list_.size(); ++k) {
      const Cell xy = cell_[reflex_list_[k].corner];
      cell[k] = static_cast<std::uint32_t>(xy.y * grid_x_ + xy.x);
      ++cell_start_[cell[k] + 1];
    }
    for (std::size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
    filed_.resize(reflex_list_.size());
    std::vector<std::uint32_t>& fill = lists_.fill;
    fill.assign(cell_start_.begin(), cell_start_.end() - 1);
    for (std::size_t k = 0; k < reflex_list_.size(); ++k) filed_[fill[cell[k]]++] = reflex_list_[k];
  }

  // True when some live reflex corner other than the ear's points lies in the closed ear of
  // corner i: through the grid where the cells its corners reach (make_grid) are fewer than the
  // filings made up to the ear's queueing (filings_at), else through the list (a point that is
  // not a number makes every test false).
  // Checked: each value tested is checked against the margin (MirrorClip).
  // `turn` and `l2`: corner(i) and longest(i); `tick`: see blocked().
  template <bool Checked>
  bool reflex_blocker(std::size_t i, double turn, double l2, std::uint32_t tick) {
    const std::size_t pa = lists_.prev[i], pc = lists_.next[i];
    const std::uint32_t ia = lists_.poly[pa], ib = lists_.poly[i], ic = lists_.poly[pc];
    const glm::dvec2 &a = at(pa), &b = at(i), &c = at(pc);
    // orient(c, a, p) >= 0 && orient(a, b, p) >= 0 && orient(b, c, p) >= 0, the edges' terms taken
    // out of the loop (the same operations in the same order: the same values). The diagonal c-a
    // first: the other two sides are polygon edges, with most of the polygon on their inner side.
    // The ear's own neighbours (often reflex themselves) are its points a and c: skipped before
    // the arithmetic.
    const glm::dvec2 ab = b - a, bc = c - b, ca = a - c;
    const auto prev_corner = static_cast<std::uint32_t>(pa), next_corner = static_cast<std::uint32_t>(pc);
    auto blocks = [&](const Filed& f) {
      if (f.corner == prev_corner || f.corner == next_corner) return false;
      const glm::dvec2 p = f.p;
      if constexpr (Checked) {  // the same tests in the same order, each value checked
        const double d = ca.x * (p.y - c.y) - ca.y * (p.x - c.x);
        check_margin(d);
        if (!(d >= 0.0)) return false;
        const double e = ab.x * (p.y - a.y) - ab.y * (p.x - a.x);
        check_margin(e);
        if (!(e >= 0.0)) return false;
        const double g = bc.x * (p.y - b.y) - bc.y * (p.x - b.x);
        check_margin(g);
        return g >= 0.0 && f.point != ia && f.point != ib && f.point != ic;
      }
      return ca.x * (p.y - c.y) - ca.y * (p.x - c.x) >= 0.0 && ab.x * (p.y - a.y) - ab.y * (p.x - a.x) >= 0.0 &&
             bc.x * (p.y - b.y) - bc.y * (p.x - b.x) >= 0.0 &&
             f.point != ia && f.point != ib && f.point != ic;  // not the same point (bridges repeat points)
    };
    const std::size_t filings = grid_x_ > 0 ? filings_at(tick) : 0;
    if (filings > 1) {  // a box has a cell at least: one filing goes through the list
      const Reach &u = reach_[pa], &v = reach_[i], &w = reach_[pc];
      const std::size_t xa = std::min(u.x0, std::min(v.x0, w.x0)), xb = std::max(u.x1, std::max(v.x1, w.x1));
      const std::size_t ya = std::min(u.y0, std::min(v.y0, w.y0)), yb = std::max(u.y1, std::max(v.y1, w.y1));
      if ((xb - xa + 1) * (yb - ya + 1) < filings) {
        for (std::size_t y = ya; y <= yb; ++y) {
          const Filed* f = filed_.data() + cell_start_[y * grid_x_ + xa];
          const Filed* end = filed_.data() + cell_start_[y * grid_x_ + xb + 1];
          for (; f != end; ++f)
            if (live(f->corner, tick) && blocks(*f)) return true;
        }
        auto in_box = [&](const LateFiled& l) {
          return l.cell.x >= xa && l.cell.x <= xb && l.cell.y >= ya && l.cell.y <= yb && blocks(l.f);
        };
        const bool found = live_filing(
            late_, tick, [](const LateFiled& l) { return l.f.corner; }, in_box);
        if constexpr (Checked)  // a needle (within_box): every live reflex corner tested, with the margin
          if (!found && !within_box(turn, l2))
            for (const Filed& f : reflex_list_)
              if (live(f.corner, tick) && blocks(f)) {
                exact_ = false;  // the rounded tests find a point outside the box
                break;
              }
        return found;
      }
    }
    return live_filing(
        reflex_list_, tick, [](const Filed& f) { return f.corner; }, blocks);
  }

  // Whether `test` holds for a live filing in `v` (live()); stale filings met on the way are
  // dropped (the order of `v` does not matter), but where tests are deferred (an ear queued
  // earlier may need a filing stale now).
  template <class Filing, class CornerOf, class Test>
  bool live_filing(std::vector<Filing>& v, std::uint32_t tick, CornerOf&& corner_of, Test&& test) const {
    for (std::size_t k = 0; k < v.size();) {
      if (live(corner_of(v[k]), tick)) {
        if (test(v[k])) return true;
        ++k;
      } else if (deferred_) {
        ++k;
      } else {
        v[k] = v.back();
        v.pop_back();
      }
    }
    return false;
  }

  // kExhaustive: kEar for an ear (positive area beyond the tolerance and no other polygon point
  // in the closed triangle), else kFlat, or the first live corner met in its closed triangle.
  std::uint32_t find_blocker(std::size_t i) const {
    const std::uint32_t ia = lists_.poly[lists_.prev[i]], ib = lists_.poly[i], ic = lists_.poly[lists_.next[i]];
    const glm::dvec2 &a = pts_[ia], &b = pts_[ib], &c = pts_[ic];
    const double tiny = ear_tolerance(longest(i));
    if (corner(i) <= tiny) return kFlat;
    std::size_t q = origin_;
    for (std::size_t k = 0; k < remaining_; ++k, q = lists_.next[q]) {
      const std::uint32_t iq = lists_.poly[q];
      if (iq == ia || iq == ib || iq == ic) continue;  // the same point (bridges repeat points)
      const glm::dvec2& p = at(q);
      if (blocks_ear(a, b, c, p, tiny)) return static_cast<std::uint32_t>(q);
    }
    return kEar;
  }

  // The best queued ear still valid, or n. kIndexed: every entry is valid, and one of equal
  // quality to the best is a child of it (no entry is above its parent): then it stops (tied_).
  std::size_t pop_ear() {
    if (indexed_) {
      // Deferred: entries found blocked when they come up are taken out (see EarQueue).
      while (deferred_ && !heap_.empty() && top_blocked()) heap_remove(heap_[0].i);
      if (heap_.empty()) return lists_.poly.size();
      const std::uint32_t best = heap_[0].i;
      const double quality = heap_[0].quality;
      tied_ = tied_ || (heap_.size() > 1 && heap_[1].quality == quality) ||
              (heap_.size() > 2 && heap_[2].quality == quality);
      if (mirror_) {
        // The mirror image's qualities: its turn differs by up to 16u ~ 1.8e-15 times the ear's
        // squared longest edge (the bound of set_margin with the ear's own edges; the longest
        // edge is the same value, and above the margin: no underflow), so its quality (at most 1)
        // by up to 1.8e-15 + 2u |q| < 2.1e-15. The best ear leads the next by more than twice
        // that (8e-15), with room.
        const double next =
            std::max(heap_.size() > 1 ? heap_[1].quality : -1.0, heap_.size() > 2 ? heap_[2].quality : -1.0);
        if (!(quality - next > 8e-15)) exact_ = false;
      }
      heap_remove(best);
      return best;
    }
    while (!ears_.empty()) {
      const Entry e = ears_.top();
      ears_.pop();
      if (lists_.alive[e.i] && e.version == lists_.version[e.i]) return e.i;
    }
    return lists_.poly.size();
  }

  // Deferred: whether the ear at the top of the heap is blocked, tested with the reflex corners
  // live at the tick it was queued at (its corners have not changed since).
  bool top_blocked() {
    const std::uint32_t i = heap_[0].i;
    return blocked(i, corner(i), longest(i), heap_[0].version);
  }

  // kExhaustive: the best ear among all corners (the first one in input order on ties), or n. A
  // corner's triangle changes only when a neighbour is clipped (which forgets what is known of
  // it), and corners only leave: an ear stays one, and a blocked corner stays blocked while its
  // blocker lives. So a corner is looked at again only then.
  std::size_t scan_ears() {
    std::size_t best = lists_.poly.size();
    double best_quality = -1.0;
    std::size_t i = origin_;
    for (std::size_t k = 0; k < remaining_; ++k, i = lists_.next[i]) {
      std::uint32_t& state = lists_.ear_state[i];
      if (state == kUnknown || (state < kFlat && !lists_.alive[state])) {
        state = find_blocker(i);
        if (state == kEar) lists_.ear_quality[i] = quality(i);
      }
      if (state != kEar) continue;
      const double q = lists_.ear_quality[i];
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
    for (std::size_t k = 0; k < remaining_; ++k, j = lists_.next[j])
      if (corner(j) > best) {
        best = corner(j);
        i = j;
      }
    return {i, best > 0.0};
  }

  void clip(std::size_t i, bool emit, std::vector<LocalTri>& out) {
    const std::uint32_t a = lists_.prev[i], c = lists_.next[i];
    if (emit) out.push_back({lists_.poly[a], lists_.poly[i], lists_.poly[c]});
    lists_.alive[i] = 0;
    if (deferred_ && lists_.reflex[i]) tick(i, false);
    lists_.reflex[i] = 0;
    lists_.next[a] = c;
    lists_.prev[c] = a;
    lists_.edge2[a] = edge_length2(a, c);
    --remaining_;
    if (search_ == EarSearch::kExhaustive) {
      lists_.ear_state[a] = lists_.ear_state[c] = kUnknown;
      if (origin_ == i) origin_ = c;
      update_reflex(a);
      update_reflex(c);
      return;
    }
    origin_ = a;
    for (std::uint32_t j : {a, c}) {
      if (!indexed_) ++lists_.version[j];
      queue_if_ear(j, update_reflex(j));
    }
  }

  const std::vector<glm::dvec2>& pts_;
  RingLists& lists_;  // poly, prev/next, alive, reflex, version or slot; ear_state, ear_quality (kExhaustive)
  EarSearch search_;
  bool indexed_;       // kQueued: the queue is kIndexed, else kLazy
  bool deferred_;      // kIndexed: ear tests made when an ear comes up (see EarQueue)
  std::uint32_t ticks_ = 0;  // deferred: changes of reflex corners so far
  bool tied_ = false;  // kIndexed met a tie: run stops
  MirrorClip* mirror_;      // kIndexed: the report on the mirror image, or null
  bool exact_ = true;       // MirrorClip::exact so far
  double margin_ = 0.0;     // MirrorClip: the margin (set_margin)
  double box_reach_ = 0.0;  // MirrorClip: how far past an ear's corners its grid box reaches (make_grid)
  // The filings of corners that became reflex (kQueued), less stale ones dropped by scans, and
  // how many filings there were: the threshold between the grid and the list.
  std::vector<Filed>& reflex_list_ = lists_.reflex_list;
  std::size_t filings_ = 0;
  // The grid (kQueued, 64 corners and more): the filings up to the first ear test by cell
  // (cell c holds filed_[cell_start_[c], cell_start_[c + 1]), stale ones too), the later ones in
  // late_.
  std::vector<std::uint32_t>& cell_start_ = lists_.cell_start;
  std::vector<Filed>& filed_ = lists_.filed;
  std::vector<LateFiled>& late_ = lists_.late;
  std::vector<Cell>& cell_ = lists_.cell;     // the cell of every corner
  std::vector<Reach>& reach_ = lists_.reach;  // the cells every corner reaches
  bool grid_filed_ = false;
  std::size_t grid_x_ = 0, grid_y_ = 0;
  glm::dvec2 origin_xy_{0.0}, inv_cell_{0.0};
  std::priority_queue<Entry> ears_;  // kLazy
  // kIndexed: a binary max-heap, heap_[(s - 1) / 2] the parent of heap_[s].
  std::vector<Entry>& heap_ = lists_.heap;
  static constexpr std::uint32_t kNoSlot = ~std::uint32_t(0);  // lists_.slot of a corner without an entry
  static constexpr std::uint32_t kNever = ~std::uint32_t(0);   // lists_.since, lists_.until: no such tick
  // kExhaustive: what is known of each corner's ear (lists_.ear_state: find_blocker, or
  // kUnknown), and the quality of each known ear (lists_.ear_quality).
  static constexpr std::uint32_t kUnknown = ~std::uint32_t(0), kEar = kUnknown - 1, kFlat = kUnknown - 2;
  std::size_t remaining_ = 0;
  std::size_t origin_ = 0;
};
// Clips one polygon (kQueued: through kIndexed, and again through kLazy where that meets a tie).
void clip_polygon(const std::vector<glm::dvec2>& pts, const std::vector<std::uint32_t>& poly,
                  EarSearch search, std::vector<LocalTri>& out, MirrorClip* mirror = nullptr,
                  EarTests tests = EarTests::kWhenTop) {
  const std::size_t before = out.size();
  if (mirror) *mirror = {};
  if (search == EarSearch::kQueued &&
      EarClipper(pts, poly, search, EarQueue::kIndexed, mirror, tests).run(out))
    return;
  if (mirror) *mirror = {};
  out.resize(before);
  EarClipper(pts, poly, search, EarQueue::kLazy).run(out);
}

}  // namespace

void clip_ears(const std::vector<glm::dvec2>& pts, const std::vector<std::uint32_t>& poly, EarSearch search,
               std::vector<LocalTri>& out, MirrorClip* mirror, EarTests tests) {
  clip_polygon(pts, poly, search, out, mirror, tests);
}

void triangulate_polygon(const std::vector<glm::dvec2>& pts, const std::vector<std::uint32_t>& outer,
                         std::vector<std::vector<std::uint32_t>> holes, const TriangulationRules& rules,
                         std::vector<LocalTri>& out, MirrorClip* mirror) {
  if (holes.empty()) {  // clipped as it is (no bridged copy of the loop to allocate)
    clip_polygon(pts, outer, rules.ears, out, mirror);
    return;
  }
  if (mirror) *mirror = {};
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
  clip_polygon(pts, poly, rules.ears, out);
}

std::vector<LocalTri> triangulate_loops(const std::vector<glm::dvec2>& points,
                                        const std::vector<std::vector<std::uint32_t>>& loops, int outer_sign,
                                        const TriangulationRules& rules) {
  LoopPolygons polygons = loop_polygons(points, loops, outer_sign);
  std::vector<LocalTri> out;
  std::size_t corners = 0;  // a polygon of n corners (holes bridged in) makes n - 2 triangles at most
  for (const auto& loop : loops) corners += loop.size() + 2;
  out.reserve(corners);
  for (std::size_t k = 0; k < polygons.outers.size(); ++k)
    triangulate_polygon(polygons.pts, loops[polygons.outers[k]], std::move(polygons.holes[k]), rules, out);
  return out;
}

}  // namespace deepcut::geometry

namespace deepcut::detail {

std::size_t largest_kept_clip_list() {
  using geometry::RingLists;
  const RingLists& l = RingLists::local();
  return std::max({l.poly.capacity() * sizeof(std::uint32_t),
                   l.prev.capacity() * sizeof(std::uint32_t),
                   l.next.capacity() * sizeof(std::uint32_t),
                   l.version.capacity() * sizeof(std::uint32_t),
                   l.slot.capacity() * sizeof(std::uint32_t),
                   l.cell_start.capacity() * sizeof(std::uint32_t),
                   l.cell_of.capacity() * sizeof(std::uint32_t),
                   l.fill.capacity() * sizeof(std::uint32_t),
                   l.reflex_list.capacity() * sizeof(geometry::Filed),
                   l.filed.capacity() * sizeof(geometry::Filed),
                   l.late.capacity() * sizeof(geometry::LateFiled),
                   l.cell.capacity() * sizeof(geometry::Cell),
                   l.reach.capacity() * sizeof(geometry::Reach),
                   l.heap.capacity() * sizeof(geometry::Entry),
                   l.ear_state.capacity() * sizeof(std::uint32_t),
                   l.since.capacity() * sizeof(std::uint32_t),
                   l.until.capacity() * sizeof(std::uint32_t),
                   l.alive.capacity(),
                   l.reflex.capacity(),
                   l.ear_quality.capacity() * sizeof(double),
                   l.corners.capacity() * sizeof(double),
                   l.edge2.capacity() * sizeof(double),
                   l.xy.capacity() * sizeof(glm::dvec2)});
}

}  // namespace deepcut::detail
