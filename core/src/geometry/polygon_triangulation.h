// SPDX-License-Identifier: MIT
#pragma once
// Triangulation of planar polygons with holes: holes are bridged (or spliced) into their outer
// loop, then the weakly simple polygon is ear-clipped, best-shaped ear first. Private to core:
// used by cut caps and by the drill's rim faces and walls. Two rules tune it (see
// TriangulationRules); each caller keeps the rule its output was made with.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "geometry/predicates.h"

namespace deepcut::geometry {

/// How ears are found. Both clip the best-shaped ear first (largest area over squared longest
/// edge); an ear has positive area and no other polygon point in its closed triangle (points
/// repeated by bridges excepted), so points on a diagonal never make T-junctions. When no ear is
/// left (numerically degenerate input) the most convex corner is cut off, and emitted only if it
/// has positive area.
enum class EarSearch {
  /// Ears wait in a priority queue; a clip re-examines its two neighbours only, and only reflex
  /// corners are tested as blockers, exactly. Consecutive repeated points are dropped first.
  /// O(n log n + n r) for r reflex corners.
  kQueued,
  /// Every corner is re-examined after each clip against every polygon point, with a tolerance of
  /// 1e-13 times the ear's squared longest edge (for planes spanning many scales). O(n^3).
  kExhaustive,
};

/// How a hole is joined to its outer loop.
enum class HoleBridge {
  /// From the hole's rightmost point to the nearest outer point whose segment crosses no edge of
  /// the outer loop or the hole.
  kRightmost,
  /// A hole sharing a point with the outer loop is spliced in there; otherwise the shortest
  /// outer-hole segment that crosses no edge of the outer loop, the hole, or the holes still to
  /// be bridged.
  kNearestPair,
};

struct TriangulationRules {
  EarSearch ears = EarSearch::kQueued;
  HoleBridge holes = HoleBridge::kRightmost;
};

/// What a clip (kQueued) found out about the clip of its mirror image: the same polygon with x
/// negated (exactly) and its corners in reverse order, its points numbered by any one-to-one map.
/// Where `exact` is true every decision of the clip (each corner's convexity, each blocker test,
/// each ear chosen over the next best, the closing triangle) held with a margin wider than the
/// rounding of both clips' arithmetic: so the mirror image's clip makes the same decisions and
/// gives the same triangles in the same order, each ear (p, q, r) as (r, q, p), and the closing
/// triangle (the last one, where `closed`) (p, q, r) as (q, p, r).
struct MirrorClip {
  bool exact = false;
  bool closed = false;  ///< the clip ended with its closing triangle (else it had no area); read where exact
};

/// When kQueued tests an ear for blockers: when its corner is queued, or when it comes to the top
/// of the queue (fewer tests). The clips are the same (the argument at EarQueue in
/// polygon_triangulation.cpp); kWhenQueued is there for the tests that compare the two.
enum class EarTests { kWhenQueued, kWhenTop };

/// Ear clipping of one counter-clockwise, weakly simple polygon (indices into `pts`; a bridged
/// hole repeats two points), appending counter-clockwise triangles to `out`.
///
/// The polygon's corner lists are kept on the calling thread from clip to clip, so small
/// polygons clip without allocating them: one clip at a time per thread (a clip never starts
/// another; checked by an assert in debug builds). Each list keeps at most
/// detail::kKeptClipListBytes (32 KB) between clips: 23 lists, 736 KB at most per thread; a
/// bigger one gives its memory back when its clip ends. The result does not depend on what the
/// lists held before.
/// With `mirror`, also what the clip tells of its mirror image's (MirrorClip; never exact for
/// kExhaustive, for fewer than four corners, or for a polygon with repeated consecutive points).
/// `tests`: see EarTests (kQueued only).
void clip_ears(const std::vector<glm::dvec2>& pts, const std::vector<std::uint32_t>& poly, EarSearch search,
               std::vector<LocalTri>& out, MirrorClip* mirror = nullptr, EarTests tests = EarTests::kWhenTop);

/// Joins a clockwise `hole` lying inside the counter-clockwise `outer` into one weakly simple
/// polygon (the bridge is walked both ways, so its two ends appear twice). `others` are further
/// holes the bridge must not cross (HoleBridge::kNearestPair only looks at them).
std::vector<std::uint32_t> bridge_hole(const std::vector<glm::dvec2>& pts, const std::vector<std::uint32_t>& outer,
                                       const std::vector<std::uint32_t>& hole,
                                       const std::vector<std::vector<std::uint32_t>>& others, HoleBridge rule);

/// Triangulates the counter-clockwise `outer` with clockwise `holes` inside it: holes are bridged
/// from right to left (by their largest x), then the polygon is clipped (clip_ears: the same
/// per-thread lists). Appends to `out`. With `mirror`, as clip_ears tells it (never exact with
/// holes).
void triangulate_polygon(const std::vector<glm::dvec2>& pts, const std::vector<std::uint32_t>& outer,
                         std::vector<std::vector<std::uint32_t>> holes, const TriangulationRules& rules,
                         std::vector<LocalTri>& out, MirrorClip* mirror = nullptr);

/// The polygons triangulate_loops clips, so that they can be clipped apart (e.g. on several
/// threads): triangulate_polygon(pts, loops[outers[k]], holes[k], rules, out) for k in order
/// appends what triangulate_loops returns.
struct LoopPolygons {
  /// The points in a frame where the outer loops run counter-clockwise (x mirrored when
  /// `outer_sign` < 0; the triangles then have the outer loops' orientation in the input).
  std::vector<glm::dvec2> pts;
  std::vector<std::size_t> outers;  ///< indices into the loops, in loop order
  std::vector<std::vector<std::vector<std::uint32_t>>> holes;  ///< holes[k]: those of outers[k]
};

/// The outer loops and holes of `loops`, as triangulate_loops assigns them.
LoopPolygons loop_polygons(const std::vector<glm::dvec2>& points, const std::vector<std::vector<std::uint32_t>>& loops,
                           int outer_sign);

/// Triangulates the region bounded by `loops` (2D points, each loop a closed polygon given by
/// indices into `points`). Loops whose signed area has the sign of `outer_sign` (+1: counter-
/// clockwise) are outer boundaries; the others are holes, assigned to the smallest outer loop
/// containing them. Output triangles have the orientation of the outer loops and index `points`.
/// Degenerate input (zero-area loops, self-touching loops) is handled best-effort: no triangle
/// is emitted twice and the output never references a point outside the loops.
std::vector<LocalTri> triangulate_loops(const std::vector<glm::dvec2>& points,
                                        const std::vector<std::vector<std::uint32_t>>& loops, int outer_sign,
                                        const TriangulationRules& rules = {});

}  // namespace deepcut::geometry

namespace deepcut::detail {
/// A corner list of ear clipping (see clip_ears) holding more bytes than this gives its memory
/// back when its clip ends: 4096 corners of the widest list (doubles).
inline constexpr std::size_t kKeptClipListBytes = std::size_t(4096) * sizeof(double);
/// The bytes held by the largest of the calling thread's kept corner lists (for tests).
std::size_t largest_kept_clip_list();
}  // namespace deepcut::detail
