// SPDX-License-Identifier: MIT
#include "geometry/polygon_triangulation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <set>
#include <thread>

#include "planar_checks.h"

namespace deepcut::geometry {
namespace {

using test::add_loop;
using test::check_tiling;
using test::comb_with_ten_teeth;
using test::Loop;
using test::random_star;
using test::triangulate_exhaustive;
using P = glm::dvec2;
constexpr double kTau = 6.283185307179586;

// The two rule sets in use: cut caps (defaults) and the drill.
const TriangulationRules kCap{};
const TriangulationRules kDrill{EarSearch::kExhaustive, HoleBridge::kNearestPair};

class PolygonTriangulation : public ::testing::TestWithParam<TriangulationRules> {};

std::vector<P> square(P lo, P hi, bool ccw) {
  std::vector<P> r = {lo, P(hi.x, lo.y), hi, P(lo.x, hi.y)};
  if (!ccw) std::reverse(r.begin(), r.end());
  return r;
}

std::vector<P> regular(P c, double radius, int n, bool ccw) {
  std::vector<P> r;
  for (int i = 0; i < n; ++i) {
    const double a = kTau * (ccw ? i : -i) / n;
    r.push_back(c + radius * P(std::cos(a), std::sin(a)));
  }
  return r;
}

std::size_t total_size(const std::vector<Loop>& loops) {
  std::size_t n = 0;
  for (const Loop& l : loops) n += l.size();
  return n;
}

TEST_P(PolygonTriangulation, ConvexPolygon) {
  std::vector<P> pts;
  const std::vector<Loop> loops = {add_loop(pts, regular(P(0, 0), 1.0, 12, true))};
  const auto tris = triangulate_loops(pts, loops, 1, GetParam());
  EXPECT_EQ(check_tiling(pts, loops, tris, 1), "");
  EXPECT_EQ(tris.size(), 10u);
}

TEST_P(PolygonTriangulation, CollinearRunsMakeNoSliverOrTJunction) {
  // A 6 x 3 rectangle with every integer point of its boundary: long collinear runs.
  std::vector<P> ring;
  for (int x = 0; x < 6; ++x) ring.push_back(P(x, 0));
  for (int y = 0; y < 3; ++y) ring.push_back(P(6, y));
  for (int x = 6; x > 0; --x) ring.push_back(P(x, 3));
  for (int y = 3; y > 0; --y) ring.push_back(P(0, y));
  std::vector<P> pts;
  const std::vector<Loop> loops = {add_loop(pts, ring)};
  const auto tris = triangulate_loops(pts, loops, 1, GetParam());
  EXPECT_EQ(check_tiling(pts, loops, tris, 1), "");  // includes: every triangle has positive area
  EXPECT_EQ(tris.size(), ring.size() - 2);
}

TEST_P(PolygonTriangulation, ClockwiseInputGivesClockwiseTriangles) {
  std::vector<P> pts;
  const std::vector<Loop> loops = {add_loop(pts, square(P(0, 0), P(4, 4), false)),
                                   add_loop(pts, square(P(1, 1), P(2, 2), true))};
  const auto tris = triangulate_loops(pts, loops, -1, GetParam());
  EXPECT_EQ(check_tiling(pts, loops, tris, -1), "");
  EXPECT_EQ(tris.size(), total_size(loops) + 2 * 1 - 2);
}

TEST_P(PolygonTriangulation, HolesCountAndArea) {
  // n points and h holes: n + 2h - 2 triangles.
  std::vector<P> pts;
  std::vector<Loop> loops = {add_loop(pts, regular(P(0, 0), 10.0, 40, true))};
  loops.push_back(add_loop(pts, square(P(-5, -1), P(-3, 1), false)));
  loops.push_back(add_loop(pts, regular(P(2, 3), 1.5, 9, false)));
  loops.push_back(add_loop(pts, regular(P(2, -4), 1.0, 5, false)));
  loops.push_back(add_loop(pts, square(P(5, -1), P(6, 1), false)));
  const auto tris = triangulate_loops(pts, loops, 1, GetParam());
  EXPECT_EQ(check_tiling(pts, loops, tris, 1), "");
  EXPECT_EQ(tris.size(), total_size(loops) + 2 * 4 - 2);
}

// Any tiling of a region by its loop points has F = 2V - B - 2 chi triangles, whichever
// diagonals it picks: V points, B loop edges, and chi = 1 - h for h holes (holes that touch at a
// point are still apart: the point belongs to the region). Apart from each other and from the
// outer loop, V = B = n and F = n + 2h - 2; each touching point takes one from V, two from F.
std::size_t euler_count(std::size_t points, std::size_t loop_edges, std::size_t holes) {
  return 2 * points + 2 * holes - loop_edges - 2;
}

TEST_P(PolygonTriangulation, TwoHolesTouchingEachOther) {
  std::vector<P> pts;
  const Loop outer = add_loop(pts, square(P(0, 0), P(12, 12), true));
  const Loop a = add_loop(pts, {P(3, 4), P(3, 8), P(6, 6)});      // clockwise
  const Loop b = {a[2], add_loop(pts, {P(9, 8)})[0], add_loop(pts, {P(9, 4)})[0]};  // (6, 6) shared
  ASSERT_LT(signed_area2(pts, a), 0.0);
  ASSERT_LT(signed_area2(pts, b), 0.0);
  const std::vector<Loop> loops = {outer, a, b};
  const auto tris = triangulate_loops(pts, loops, 1, GetParam());
  EXPECT_EQ(check_tiling(pts, loops, tris, 1), "");
  EXPECT_EQ(tris.size(), euler_count(9, 10, 2));
}

TEST_P(PolygonTriangulation, ZeroAreaAndShortLoopsGiveNothing) {
  std::vector<P> pts;
  const Loop line = add_loop(pts, {P(0, 0), P(1, 1), P(2, 2), P(3, 3)});
  const Loop back_and_forth = {line[0], line[3], line[2]};
  const Loop two = add_loop(pts, {P(5, 5), P(6, 5)});
  EXPECT_TRUE(triangulate_loops(pts, {line}, 1, GetParam()).empty());
  EXPECT_TRUE(triangulate_loops(pts, {back_and_forth}, 1, GetParam()).empty());
  EXPECT_TRUE(triangulate_loops(pts, {two}, 1, GetParam()).empty());
  EXPECT_TRUE(triangulate_loops(pts, {}, 1, GetParam()).empty());
  // A loop of the wrong orientation with no outer loop around it is a hole of nothing.
  const Loop cw = add_loop(pts, square(P(10, 10), P(11, 11), false));
  EXPECT_TRUE(triangulate_loops(pts, {cw}, 1, GetParam()).empty());
}

TEST_P(PolygonTriangulation, RepeatedPoints) {
  std::vector<P> pts;
  const Loop ring = add_loop(pts, regular(P(0, 0), 3.0, 8, true));
  Loop doubled;
  for (std::uint32_t v : ring) {
    doubled.push_back(v);
    if (v % 3 == 0) doubled.push_back(v);  // some points listed twice in a row
  }
  doubled.push_back(ring[0]);  // and the loop closed explicitly
  const auto tris = triangulate_loops(pts, {doubled}, 1, GetParam());
  EXPECT_EQ(check_tiling(pts, {ring}, tris, 1), "");
  std::set<LocalTri> unique(tris.begin(), tris.end());
  EXPECT_EQ(unique.size(), tris.size());
  if (GetParam().ears == EarSearch::kQueued) {
    EXPECT_EQ(tris.size(), ring.size() - 2);  // the repeats are dropped first
  }
}

TEST_P(PolygonTriangulation, NeedleStrip) {
  // A strip 50 long and 1e-6 wide, with points along both long sides: every triangle is a needle.
  std::vector<P> ring;
  for (int i = 0; i <= 50; ++i) ring.push_back(P(i, 0));
  for (int i = 50; i >= 0; --i) ring.push_back(P(i + 0.5, 1e-6));
  std::vector<P> pts;
  const std::vector<Loop> loops = {add_loop(pts, ring)};
  const auto tris = triangulate_loops(pts, loops, 1, GetParam());
  EXPECT_EQ(check_tiling(pts, loops, tris, 1), "");
  EXPECT_EQ(tris.size(), ring.size() - 2);
}

TEST_P(PolygonTriangulation, NestedIslandInAHole) {
  std::vector<P> pts;
  const std::vector<Loop> loops = {add_loop(pts, square(P(0, 0), P(10, 10), true)),
                                   add_loop(pts, square(P(2, 2), P(8, 8), false)),
                                   add_loop(pts, square(P(4, 4), P(6, 6), true)),
                                   add_loop(pts, square(P(20, 0), P(21, 1), true))};
  const auto tris = triangulate_loops(pts, loops, 1, GetParam());
  EXPECT_EQ(check_tiling(pts, loops, tris, 1), "");
  EXPECT_EQ(tris.size(), (8u + 2 - 2) + 2 + 2);  // the frame, the island, the far square
}

TEST_P(PolygonTriangulation, RandomStarsWithAHole) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 400; ++trial) {
    // A star around the origin: radii in [0.6, 1], angles jittered within their sector, so
    // every edge stays farther than 0.42 from the origin and a hole within 0.4 of it fits.
    const std::vector<P> ring = random_star(rng, u, 8, 40, 0.6, 0.4);
    std::vector<P> pts;
    std::vector<Loop> loops = {add_loop(pts, ring)};
    const int holes = trial % 3 == 0 ? 0 : 1;
    if (holes) {
      const double a = kTau * u(rng), r = 0.3 * u(rng);
      std::vector<P> hole = regular(r * P(std::cos(a), std::sin(a)), 0.02 + 0.07 * u(rng), 3 + trial % 12, false);
      loops.push_back(add_loop(pts, hole));
    }
    const double squash = trial % 5 == 0 ? 1e-5 : 1.0;  // some become needles
    const int sign = trial % 2 == 0 ? 1 : -1;           // mirrored: the outer loop is clockwise
    for (auto& p : pts) p = P(sign * p.x, squash * p.y);
    const auto tris = triangulate_loops(pts, loops, sign, GetParam());
    EXPECT_EQ(check_tiling(pts, loops, tris, sign), "") << "trial " << trial;
    EXPECT_EQ(tris.size(), total_size(loops) + 2 * holes - 2) << "trial " << trial;
  }
}

INSTANTIATE_TEST_SUITE_P(Rules, PolygonTriangulation, ::testing::Values(kCap, kDrill),
                         [](const ::testing::TestParamInfo<TriangulationRules>& rules) {
                           return rules.param.ears == EarSearch::kQueued ? std::string("CapRules")
                                                                         : std::string("DrillRules");
                         });

// The drill's rules splice a hole that touches the outer loop; the cap rules bridge it from its
// rightmost point and are not held to this.
TEST(PolygonTriangulationParts, HoleTouchingOuterLoopAtAVertex) {
  std::vector<P> pts;
  const Loop outer = add_loop(pts, {P(0, 0), P(5, 0), P(10, 0), P(10, 10), P(0, 10)});
  Loop hole = add_loop(pts, {P(4, 3), P(6, 3)});
  hole.push_back(outer[1]);  // clockwise: (4, 3), (6, 3), (5, 0), touching the outer loop
  ASSERT_LT(signed_area2(pts, hole), 0.0);
  const std::vector<Loop> loops = {outer, hole};
  const auto tris = triangulate_loops(pts, loops, 1, kDrill);
  EXPECT_EQ(check_tiling(pts, loops, tris, 1), "");
  EXPECT_EQ(tris.size(), euler_count(7, 8, 1));  // 6, not the 8 of a hole apart from the outer loop
}

TEST(PolygonTriangulationParts, BridgeJoinsOnceAroundTheHole) {
  std::vector<P> pts;
  const Loop outer = add_loop(pts, square(P(0, 0), P(10, 10), true));
  const Loop hole = add_loop(pts, regular(P(5, 5), 2.0, 7, false));
  const Loop other = add_loop(pts, square(P(8, 1), P(9, 9), false));
  for (HoleBridge rule : {HoleBridge::kRightmost, HoleBridge::kNearestPair}) {
    const Loop joined = bridge_hole(pts, outer, hole, {other}, rule);
    EXPECT_EQ(joined.size(), outer.size() + hole.size() + 2);
    std::multiset<std::uint32_t> ids(joined.begin(), joined.end());
    for (std::uint32_t v : outer) EXPECT_GE(ids.count(v), 1u);
    for (std::uint32_t v : hole) EXPECT_GE(ids.count(v), 1u);
    // The bridge's two ends appear twice, joined by the bridge walked both ways.
    std::vector<std::uint32_t> twice;
    for (std::uint32_t v : std::set<std::uint32_t>(joined.begin(), joined.end()))
      if (ids.count(v) == 2) twice.push_back(v);
    ASSERT_EQ(twice.size(), 2u);
    // The bridge crosses no edge of the loops it must avoid.
    for (const Loop* l : {&outer, &hole})
      for (std::size_t i = 0; i < l->size(); ++i)
        EXPECT_FALSE(segments_cross(pts[twice[0]], pts[twice[1]], pts[(*l)[i]], pts[(*l)[(i + 1) % l->size()]]));
    if (rule == HoleBridge::kNearestPair) {
      for (std::size_t i = 0; i < other.size(); ++i)
        EXPECT_FALSE(segments_cross(pts[twice[0]], pts[twice[1]], pts[other[i]], pts[other[(i + 1) % other.size()]]));
    }
  }
}

TEST(PolygonTriangulationParts, BridgeSplicesATouchingHole) {
  std::vector<P> pts;
  const Loop outer = add_loop(pts, square(P(0, 0), P(10, 10), true));
  const Loop hole = {add_loop(pts, {P(3, 2)})[0], outer[0], add_loop(pts, {P(2, 3)})[0]};
  ASSERT_LT(signed_area2(pts, hole), 0.0);
  const Loop spliced = bridge_hole(pts, outer, hole, {}, HoleBridge::kNearestPair);
  EXPECT_EQ(spliced.size(), outer.size() + hole.size());
  std::vector<LocalTri> tris;
  clip_ears(pts, spliced, EarSearch::kExhaustive, tris);
  EXPECT_EQ(check_tiling(pts, {outer, hole}, tris, 1), "");
  EXPECT_EQ(tris.size(), spliced.size() - 2);
}

TEST(PolygonTriangulationParts, ClipEarsOnAComb) {
  // A comb with 10 teeth, as both ear searches see it.
  const std::vector<P> ring = comb_with_ten_teeth();
  std::vector<P> pts;
  const Loop poly = add_loop(pts, ring);
  ASSERT_GT(signed_area2(pts, poly), 0.0);
  for (EarSearch search : {EarSearch::kQueued, EarSearch::kExhaustive}) {
    std::vector<LocalTri> tris;
    clip_ears(pts, poly, search, tris);
    EXPECT_EQ(check_tiling(pts, {poly}, tris, 1), "");
    EXPECT_EQ(tris.size(), ring.size() - 2);
  }
}

// A star of `n` corners (radii alternating 1 and 0.7): half of them reflex.
std::vector<P> star(int n) {
  std::vector<P> r;
  for (int i = 0; i < n; ++i) {
    const double a = kTau * i / n, radius = i % 2 == 0 ? 1.0 : 0.7;
    r.push_back(radius * P(std::cos(a), std::sin(a)));
  }
  return r;
}

// The triangles of clipping `poly` on a thread of its own (its first clip: nothing kept before).
std::vector<LocalTri> clip_on_a_fresh_thread(const std::vector<P>& pts, const Loop& poly, EarSearch search) {
  std::vector<LocalTri> tris;
  std::thread([&] { clip_ears(pts, poly, search, tris); }).join();
  return tris;
}

// The corner lists kept on each thread from clip to clip: a clip's triangles do not depend on
// what the thread clipped before (a small polygon, one of more than 4096 corners, the small one
// again, then two that the queued search files in its grid, the larger first), and lists grown
// past the bound give their memory back when the clip ends, among them a kQueued input of many
// repeated points (its corner list is big only until they are dropped).
TEST(PolygonTriangulationParts, ClipListsKeptOnTheThreadChangeNoResult) {
  std::vector<P> pts;
  const Loop small = add_loop(pts, comb_with_ten_teeth());
  const Loop big = add_loop(pts, star(5000));
  const Loop gridded = add_loop(pts, star(1000)), smaller_gridded = add_loop(pts, star(300));  // the grid's lists reused
  Loop repeated;  // a 12-gon, each corner 750 times in a row
  for (std::uint32_t v : add_loop(pts, regular(P(3, 3), 1.0, 12, true))) repeated.insert(repeated.end(), 750, v);
  ASSERT_GT(repeated.size() * sizeof(std::uint32_t), detail::kKeptClipListBytes);
  for (EarSearch search : {EarSearch::kQueued, EarSearch::kExhaustive}) {
    SCOPED_TRACE(search == EarSearch::kQueued ? "kQueued" : "kExhaustive");
    std::vector<Loop> order = {small, big, small, gridded, smaller_gridded};
    if (search == EarSearch::kQueued) order.insert(order.end(), {repeated, small});
    auto run_all = [&] {
      for (const Loop& poly : order) {
        std::vector<LocalTri> tris;
        clip_ears(pts, poly, search, tris);
        EXPECT_EQ(tris, clip_on_a_fresh_thread(pts, poly, search)) << poly.size() << " corners";
        EXPECT_LE(detail::largest_kept_clip_list(), detail::kKeptClipListBytes) << poly.size() << " corners";
      }
    };
    run_all();
    std::thread(run_all).join();
  }
  // A small clip keeps its lists: the next one of that size allocates none.
  std::vector<LocalTri> tris;
  clip_ears(pts, small, EarSearch::kExhaustive, tris);
  const std::size_t kept = detail::largest_kept_clip_list();
  EXPECT_GT(kept, 0u);
  clip_ears(pts, small, EarSearch::kExhaustive, tris);
  EXPECT_EQ(detail::largest_kept_clip_list(), kept);
}

// The queued search's grid (64 corners and more) with the points on the lines between its cells
// (3 units wide and 1 high here) or between them, exactly: long collinear runs, and a V from the
// top whose tip is on the line y = 1, over the bottom run. An ear may only be clipped with no
// point in its closed triangle, so every collinear point on a diagonal, and the tip on the
// diagonals of the bottom run's ears, must be found in the cells the ear reaches.
TEST(PolygonTriangulationParts, GridFindsPointsOnCellLinesAndDiagonals) {
  std::vector<P> ring;
  for (int x = 0; x < 24; ++x) ring.push_back(P(x, 0));
  for (int y = 0; y < 8; ++y) ring.push_back(P(24, y));
  for (int x = 24; x > 12; --x) ring.push_back(P(x, 8));
  for (int y = 8; y > 1; y -= 2) ring.push_back(P(12.0 + (y - 1) / 8.0, y));  // the V down to (12, 1)
  ring.push_back(P(12, 1));
  for (int y = 2; y <= 8; y += 2) ring.push_back(P(12.0 - (y - 1) / 8.0, y));
  for (int x = 11; x > 0; --x) ring.push_back(P(x, 8));
  for (int y = 8; y > 0; --y) ring.push_back(P(0, y));
  ASSERT_GE(ring.size(), 64u);
  std::vector<P> pts;
  const Loop poly = add_loop(pts, ring);
  std::vector<LocalTri> tris;
  clip_ears(pts, poly, EarSearch::kQueued, tris);
  EXPECT_EQ(check_tiling(pts, {poly}, tris, 1), "");  // no T-junction, no overlap, positive areas
  EXPECT_EQ(tris.size(), ring.size() - 2);
}

// Ears of equal quality are clipped in the order the results were made with (the priority
// queue's among equals): every ear of a regular octagon ties with the others, and corners of a
// square with its sides' midpoints tie in pairs. (A queue that takes any of the best ears
// clips the octagon's corner 6 before 7 at the fifth ear.)
TEST(PolygonTriangulationParts, TiedEarsAreClippedInTheRecordedOrder) {
  auto clip = [](const std::vector<P>& pts) {
    Loop poly(pts.size());
    std::iota(poly.begin(), poly.end(), 0u);
    std::vector<LocalTri> tris;
    clip_ears(pts, poly, EarSearch::kQueued, tris);
    EXPECT_EQ(check_tiling(pts, {poly}, tris, 1), "");
    return tris;
  };
  const std::vector<LocalTri> octagon = {{1, 2, 3}, {0, 1, 3}, {7, 0, 3}, {7, 3, 4}, {7, 4, 5}, {7, 5, 6}};
  EXPECT_EQ(clip(regular(P(0, 0), 1.0, 8, true)), octagon);
  const std::vector<LocalTri> midpoints = {{7, 0, 1}, {3, 4, 5}, {5, 6, 7}, {1, 2, 3}, {3, 5, 7}, {3, 7, 1}};
  EXPECT_EQ(clip({P(0, 0), P(1, 0), P(2, 0), P(2, 1), P(2, 2), P(1, 2), P(0, 2), P(0, 1)}), midpoints);
}

// The mirror image of `ring` clipped: point i of the ring is point (n - 1 - i + 5) % n of its
// points, x negated, and its loop runs from a point other than the first. Expects the triangles
// `tris` of the ring's clip so mapped (see MirrorImageClipsTheSame).
void expect_mirror_clips_the_same(const std::vector<P>& ring, const std::vector<LocalTri>& tris,
                                  const MirrorClip& mirror, int trial) {
  const auto n = static_cast<std::uint32_t>(ring.size());
  auto moved = [n](std::uint32_t i) { return (n - 1 - i + 5) % n; };
  std::vector<P> pts(n);
  for (std::uint32_t i = 0; i < n; ++i) pts[moved(i)] = P(-ring[i].x, ring[i].y);
  Loop reversed;
  for (std::uint32_t k = 0; k < n; ++k) reversed.push_back(moved((n + 7 - k) % n));
  std::vector<LocalTri> mirrored;
  clip_ears(pts, reversed, EarSearch::kQueued, mirrored);
  ASSERT_EQ(mirrored.size(), tris.size());
  for (std::size_t t = 0; t < tris.size(); ++t) {
    const LocalTri& a = tris[t];
    const bool closing = mirror.closed && t + 1 == tris.size();
    const LocalTri want = closing ? LocalTri{moved(a[1]), moved(a[0]), moved(a[2])}
                                  : LocalTri{moved(a[2]), moved(a[1]), moved(a[0])};
    EXPECT_EQ(mirrored[t], want) << "trial " << trial << " triangle " << t;
  }
}

// Where a clip says its mirror image clips the same (MirrorClip::exact), clipping the polygon
// with x negated and its corners reversed, numbered another way, gives its triangles so mapped:
// ears (p, q, r) as (r, q, p), the closing one as (q, p, r). Random stars small and big (with the
// grid), shifted far from the origin (rounding at larger scale); a regular octagon's ears tie, so
// its clip is not exact.
TEST(PolygonTriangulationParts, MirrorImageClipsTheSame) {
  std::mt19937 rng(1234);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int exact = 0;
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<P> ring = random_star(rng, u, trial % 2 ? 8 : 64, trial % 2 ? 40 : 300, 0.2, 1.0);
    const P shift = trial % 3 == 0 ? P(1e4, -3e3) : P(0.0);
    for (P& p : ring) p += shift;
    const auto n = static_cast<std::uint32_t>(ring.size());
    Loop poly(n);
    std::iota(poly.begin(), poly.end(), 0u);
    std::vector<LocalTri> tris;
    MirrorClip mirror;
    clip_ears(ring, poly, EarSearch::kQueued, tris, &mirror);
    std::vector<LocalTri> plain;
    clip_ears(ring, poly, EarSearch::kQueued, plain);
    ASSERT_EQ(tris, plain);  // the report changes nothing
    if (!mirror.exact) continue;
    ++exact;
    expect_mirror_clips_the_same(ring, tris, mirror, trial);
  }
  EXPECT_GT(exact, 150);
  std::vector<P> octagon = regular(P(0, 0), 1.0, 8, true);
  Loop poly(8);
  std::iota(poly.begin(), poly.end(), 0u);
  std::vector<LocalTri> tris;
  MirrorClip mirror;
  clip_ears(octagon, poly, EarSearch::kQueued, tris, &mirror);
  EXPECT_FALSE(mirror.exact);
}

// Needle ears (MirrorClip, through the grid): stars of 300 points with points put on their edges
// just off the line (1e-6 to 3e-9 of the edge, either side) make ears whose smallest angle is
// far below what the grid box's padding covers; the clip then tests every live reflex corner too,
// and where it still says exact, the mirror image clips the same.
TEST(PolygonTriangulationParts, MirrorImageOfNeedleEarsClipsTheSame) {
  std::mt19937 rng(4321);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int exact = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const std::vector<P> star = random_star(rng, u, 150, 300, 0.2, 1.0);
    std::vector<P> ring;
    for (std::size_t i = 0; i < star.size(); ++i) {
      const P a = star[i], b = star[(i + 1) % star.size()];
      ring.push_back(a);
      if (i % 3 != 0) continue;
      const double t = 0.02 + 0.96 * u(rng),
                   off = std::pow(10.0, -6.0 - 2.5 * u(rng)) * (u(rng) < 0.5 ? -1 : 1);
      ring.push_back(a + t * (b - a) + off * P(a.y - b.y, b.x - a.x));
    }
    const auto n = static_cast<std::uint32_t>(ring.size());
    Loop poly(n);
    std::iota(poly.begin(), poly.end(), 0u);
    std::vector<LocalTri> tris, plain;
    MirrorClip mirror;
    clip_ears(ring, poly, EarSearch::kQueued, tris, &mirror);
    clip_ears(ring, poly, EarSearch::kQueued, plain);
    ASSERT_EQ(tris, plain);
    if (!mirror.exact) continue;
    ++exact;
    expect_mirror_clips_the_same(ring, tris, mirror, trial);
  }
  EXPECT_GT(exact, 0);
}

// Clips `poly` with each ear tested for blockers when it comes up (EarTests::kWhenTop) and when
// queued: the same triangles. Where both reports on the mirror image are exact they agree (not
// otherwise: a clip that met a tie is made again without a report), and where the deferred one is,
// the mirror image clips the same (counted in `exact`).
void expect_deferred_clips_the_same(const std::vector<P>& ring, const Loop& poly, int trial, int& exact) {
  std::vector<LocalTri> deferred, when_queued;
  MirrorClip deferred_mirror, queued_mirror;
  clip_ears(ring, poly, EarSearch::kQueued, deferred, &deferred_mirror, EarTests::kWhenTop);
  clip_ears(ring, poly, EarSearch::kQueued, when_queued, &queued_mirror, EarTests::kWhenQueued);
  ASSERT_EQ(deferred, when_queued) << "trial " << trial;
  if (deferred_mirror.exact && queued_mirror.exact) {
    EXPECT_EQ(deferred_mirror.closed, queued_mirror.closed) << "trial " << trial;
  }
  if (!deferred_mirror.exact) return;
  ++exact;
  expect_mirror_clips_the_same(ring, deferred, deferred_mirror, trial);
}

// A random star small or big (the grid) swirled into a spiral: each point turned by an angle
// growing with its radius, so that most are self-intersecting.
std::vector<P> random_spiral(std::mt19937& rng, std::uniform_real_distribution<double>& u, int trial) {
  std::vector<P> ring =
      random_star(rng, u, trial % 3 == 0 ? 8 : 64, trial % 3 == 0 ? 40 : 300, 0.1 + 0.3 * u(rng), 1.0);
  const double swirl = trial % 5 == 0 ? 0.0 : 2.0 + 6.0 * u(rng);
  for (P& p : ring) {
    const double r = glm::length(p), a = std::atan2(p.y, p.x) + swirl * r;
    p = r * P(std::cos(a), std::sin(a));
  }
  return ring;
}

Loop in_order(std::size_t n) {
  Loop poly(n);
  std::iota(poly.begin(), poly.end(), 0u);
  return poly;
}

// Ear clipping tests an ear for blockers when it comes up, with the reflex corners live at the
// tick it was queued at, through the grid or the list as testing when queued would (EarQueue in
// polygon_triangulation.cpp): the clips are those of testing each ear when queued. Random
// spirals (random_spiral: most self-intersect, some have negative area), whose ears are blocked
// by reflex corners that turn convex as their own neighbours are clipped, before the ear comes
// up, and where corners turn reflex after the grid is laid out; some with needle ears (the mirror
// report's full scans).
TEST(PolygonTriangulationParts, DeferredEarTestsClipTheSame) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int exact = 0;
  for (int trial = 0; trial < 240; ++trial) {
    std::vector<P> ring = random_spiral(rng, u, trial);
    if (trial % 4 == 1) {  // needle ears: points just off every other edge
      std::vector<P> star;
      star.swap(ring);
      for (std::size_t i = 0; i < star.size(); ++i) {
        ring.push_back(star[i]);
        const P a = star[i], b = star[(i + 1) % star.size()];
        if (i % 2 == 0) ring.push_back(0.5 * (a + b) + 1e-8 * P(a.y - b.y, b.x - a.x));
      }
    }
    expect_deferred_clips_the_same(ring, in_order(ring.size()), trial, exact);
  }
  EXPECT_GT(exact, 30);  // 49 when written
}

// The same on numerically degenerate and self-intersecting input, where corners turn reflex
// again after being clipped around, and filings come late: spirals with points repeated
// (not next to each other), spirals snapped to a grid of 1/64 (repeated and collinear points),
// and random polygons.
TEST(PolygonTriangulationParts, DeferredEarTestsClipTheSameOnDegenerateInput) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int exact = 0;
  for (int trial = 0; trial < 1200; ++trial) {
    std::vector<P> ring = random_spiral(rng, u, trial);
    Loop poly = in_order(ring.size());
    if (trial % 3 == 0) {  // repeated points: some corners visited again further on
      const std::size_t n = poly.size();
      for (std::size_t k = 0; k < n / 4; ++k) {
        const std::size_t at = static_cast<std::size_t>(u(rng) * double(poly.size()));
        const std::size_t from = (at + 2 + static_cast<std::size_t>(u(rng) * double(n - 4))) % n;
        poly.insert(poly.begin() + static_cast<std::ptrdiff_t>(at), static_cast<std::uint32_t>(from));
      }
    } else if (trial % 3 == 1) {  // snapped to a grid of 1/64
      for (P& p : ring) p = glm::round(64.0 * p) / 64.0;
    } else {  // random points in random order
      for (P& p : ring) p = P(u(rng), u(rng));
    }
    expect_deferred_clips_the_same(ring, poly, trial, exact);
  }
}

TEST(PolygonTriangulationParts, TriangulateOneOuterLoopAndOneHole) {
  std::vector<P> pts;
  const std::vector<Loop> loops = {add_loop(pts, regular(P(0, 0), 5.0, 16, true)),
                                   add_loop(pts, regular(P(0.5, 0), 1.0, 6, false))};
  const auto tris = triangulate_exhaustive(pts, loops);
  EXPECT_EQ(check_tiling(pts, loops, tris, 1), "");
  EXPECT_EQ(tris.size(), 16u + 6u);
  const auto alone = triangulate_exhaustive(pts, {loops[0]});
  EXPECT_EQ(check_tiling(pts, {loops[0]}, alone, 1), "");
}

}  // namespace
}  // namespace deepcut::geometry
