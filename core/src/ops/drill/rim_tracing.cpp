// SPDX-License-Identifier: MIT
// The rims the rim insertion left, traced from the topology of its edits.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <optional>
#include <unordered_map>
#include <vector>

#include "ops/common/crossing_table.h"
#include "ops/common/vertex_slots.h"
#include "ops/drill/rim_insertion.h"

namespace deepcut::drill {
namespace {

// Directed rim edges (from, to): made in discovery order, then grouped by `from` (sorted by
// (from, discovery index), so each vertex's outgoing edges keep that order).
using RimSteps = std::vector<std::pair<std::uint32_t, std::uint32_t>>;
// Half-edges of live faces with both ends on the rim, in the order their faces were filed.
using RimHalfEdgeList = std::vector<std::pair<VertexId, VertexId>>;

// Half-edges between two rim vertices (the only ones rim_steps asks about), each with a bit for
// every kind of face it was filed from (only membership matters).
class RimHalfEdges {
 public:
  static constexpr std::uint8_t kAdded = 1, kRemoved = 2, kUntouched = 4;

  /// Room for `expected` half-edges up front (it grows past them when needed).
  explicit RimHalfEdges(std::size_t expected) { slots_.reserve(expected); }
  /// Files the half-edges of `t` whose two corners are on the rim (`rim`, per corner) as `kind`,
  /// and lists them in `live` unless it is null.
  void file_face(const Triangle& t, const bool rim[3], std::uint8_t kind, RimHalfEdgeList* live) {
    for (int k = 0; k < 3; ++k)
      if (rim[k] && rim[(k + 1) % 3]) {
        const auto [at, made] =
            slots_.find_or_insert(directed_key(t[k], t[(k + 1) % 3]), static_cast<std::uint32_t>(kinds_.size()));
        if (made) kinds_.push_back(kind);
        else kinds_[at] |= kind;
        if (live) live->emplace_back(t[k], t[(k + 1) % 3]);
      }
  }
  /// Whether a -> b was filed as one of `kinds`.
  bool has(VertexId a, VertexId b, std::uint8_t kinds) const {
    const std::uint32_t at = slots_.find(directed_key(a, b));
    return at != detail::EdgeSlots::kNone && (kinds_[at] & kinds) != 0;
  }

 private:
  detail::EdgeSlots slots_;
  std::vector<std::uint8_t> kinds_;  // per filed half-edge
};

// Which corners of `t` lie on the rim (`on_rim`), in `rim`; returns whether an edge of `t` can
// have both ends there. Every edge has corner 0 or 1, so the third is looked at only when one of
// those is on the rim (most faces of the log lie off it).
template <class OnRim>
bool rim_corners(const Triangle& t, const OnRim& on_rim, bool rim[3]) {
  rim[0] = on_rim(t[0]);
  rim[1] = on_rim(t[1]);
  rim[2] = (rim[0] || rim[1]) && on_rim(t[2]);
  return int(rim[0]) + int(rim[1]) + int(rim[2]) >= 2;
}

// The rim half-edges of the added faces and of the untouched candidates (faces the drill left
// alone can border the hole too: an old edge that lies on the cylinder, within the tolerance,
// between a removed face and an untouched one); those of the live faces (the added ones still
// there, then the untouched candidates) are listed in `live` too: the only half-edges that can
// be rim steps. The removed faces' are filed by file_removed_half_edges, only when asked about.
template <class OnRim>
RimHalfEdges file_rim_half_edges(const SurfaceMesh& mesh, const EditLog& log,
                                 const std::vector<FaceId>& candidates, const OnRim& on_rim,
                                 RimHalfEdgeList& live) {
  // Room for an eighth of the edits (the log also holds removed faces, new vertices and moves,
  // and most added faces have no rim half-edge): enough for most holes without growing.
  RimHalfEdges filed(log.edits.size() / 8 + 16);
  bool rim[3];
  for (const Edit& e : log.edits)
    if (const auto* fa = std::get_if<FaceAdded>(&e))
      if (rim_corners(fa->vertices, on_rim, rim))
        filed.file_face(fa->vertices, rim, RimHalfEdges::kAdded, mesh.is_deleted(fa->f) ? nullptr : &live);
  for (FaceId f : candidates)
    if (!mesh.is_deleted(f) && rim_corners(mesh.face(f), on_rim, rim))
      filed.file_face(mesh.face(f), rim, RimHalfEdges::kUntouched, &live);
  return filed;
}

// The rim half-edges of the removed faces, filed into `filed` (only membership matters, so the
// order they are filed in does not).
template <class OldOnRim>
void file_removed_half_edges(const EditLog& log, const OldOnRim& old_on_rim, RimHalfEdges& filed) {
  bool rim[3];
  for (const Edit& e : log.edits)
    if (const auto* fr = std::get_if<FaceRemoved>(&e))
      if (rim_corners(fr->vertices, old_on_rim, rim))
        filed.file_face(fr->vertices, rim, RimHalfEdges::kRemoved, nullptr);
}

// The rim steps among the live half-edges (`live`, in discovery order), unsorted: a live rim
// half-edge is a step unless an added or untouched face holds its reverse, or it joins two old
// vertices (judged by `base`, the original of a pinch copy) whose edge no removed face held. The
// removed faces' half-edges are filed into `filed` only when some live one joins two old
// vertices (most rims have none: their old vertices are the few slid onto the cylinder).
template <class Base, class OldOnRim>
RimSteps steps_from_live(const EditLog& log, const RimHalfEdgeList& live, const Base& base,
                         std::uint32_t first_new, const OldOnRim& old_on_rim, RimHalfEdges& filed) {
  // Whether both ends of a half-edge, judged by their originals, are old vertices (the second
  // looked up only when the first is).
  auto both_old = [&](VertexId a, VertexId b) {
    return base(a).index < first_new && base(b).index < first_new;
  };
  for (const auto& [a, b] : live)
    if (both_old(a, b)) {
      file_removed_half_edges(log, old_on_rim, filed);
      break;
    }
  RimSteps steps;
  for (const auto& [a, b] : live) {
    if (filed.has(b, a, RimHalfEdges::kAdded | RimHalfEdges::kUntouched)) continue;
    if (both_old(a, b) && !filed.has(base(b), base(a), RimHalfEdges::kRemoved)) continue;
    steps.emplace_back(a.index, b.index);
  }
  return steps;
}

// The rim steps, unsorted (steps_from_live), with `base` giving the original of a pinch copy
// (rim_steps).
template <class Base>
RimSteps unsorted_rim_steps(const SurfaceMesh& mesh, const EditLog& log, const CylinderFrame& cyl,
                            const PosedOverlay& posed, const std::vector<FaceId>& candidates,
                            const Base& base) {
  // Each old vertex is judged once (1 on the rim, 0 not).
  detail::VertexSlots& judged = detail::VertexSlots::scratch();
  judged.reset(posed.first_new());
  auto old_on_rim = [&](VertexId v) {
    if (v.index >= posed.first_new()) return false;
    std::uint32_t j = judged.get(v.index);
    if (j == detail::VertexSlots::kNone) {
      j = std::abs(cyl.sd(posed(v))) <= 2.0 * cyl.eps ? 1 : 0;
      judged.set(v.index, j);
    }
    return j == 1;
  };
  auto on_rim = [&](VertexId v) {
    v = base(v);
    return v.index >= posed.first_new() || old_on_rim(v);
  };
  // The live faces' half-edges between two rim vertices, listed while filing, in the order of
  // the added faces' edits and then the candidates.
  RimHalfEdgeList live;
  live.reserve(log.edits.size() / 8 + 16);  // as file_rim_half_edges' table
  RimHalfEdges filed = file_rim_half_edges(mesh, log, candidates, on_rim, live);
  return steps_from_live(log, live, base, posed.first_new(), old_on_rim, filed);
}

// Rim edges are found from the topology the edits left: boundary half-edges of the new faces
// whose ends lie on the cylinder. An edge between two old vertices is an edge of the parent
// triangle; it is a boundary only if the face across it was removed and not replaced there.
RimSteps rim_steps(const SurfaceMesh& mesh, const EditLog& log, const CylinderFrame& cyl,
                   const PosedOverlay& posed, const std::vector<FaceId>& candidates,
                   const std::unordered_map<std::uint32_t, std::uint32_t>& copy_of) {
  RimSteps rim_next;
  if (copy_of.empty()) {  // no pinch split (the usual trace): every vertex is its own original
    rim_next = unsorted_rim_steps(mesh, log, cyl, posed, candidates, [](VertexId v) { return v; });
  } else {
    // A copy the pinch split made of an old vertex is new, but the faces moved onto it keep
    // their old edges: both are judged by the original (an old boundary edge at a split vertex
    // is not rim). The copies are the newest vertices: ids below the lowest copy are looked up
    // nowhere.
    std::uint32_t first_copy = ~std::uint32_t(0);
    for (const auto& [c, v] : copy_of) first_copy = std::min(first_copy, c);
    auto base = [&](VertexId v) {
      if (v.index < first_copy) return v;
      const auto it = copy_of.find(v.index);
      return it == copy_of.end() ? v : VertexId(it->second);
    };
    rim_next = unsorted_rim_steps(mesh, log, cyl, posed, candidates, base);
  }
  // Grouped by `from`, each group in discovery order: sorted by (from, discovery index) as one
  // 64-bit key per step (a plain sort of integers, where a stable sort of the pairs merges).
  assert(rim_next.size() < (std::uint64_t(1) << 32));  // the discovery index fits the key's low half
  std::vector<std::uint64_t> order(rim_next.size());
  for (std::size_t i = 0; i < rim_next.size(); ++i) order[i] = std::uint64_t(rim_next[i].first) << 32 | i;
  std::sort(order.begin(), order.end());
  RimSteps sorted(rim_next.size());
  for (std::size_t i = 0; i < order.size(); ++i) sorted[i] = rim_next[static_cast<std::uint32_t>(order[i])];
  return sorted;
}

// Turns of a closed rim around the axis: the winding number around the axis of the rim's chords
// seen along it (geometry::winding). A chord between two points around the axis turns the short
// way, so this is the sum of the turns from each vertex to the next, each under half a turn,
// without an angle per vertex.
int winding(const CylinderFrame& cyl, const PosedOverlay& posed, const std::vector<VertexId>& rim) {
  std::vector<std::vector<std::uint32_t>> loop(1);
  std::vector<glm::dvec2> xy;
  loop[0].reserve(rim.size());
  xy.reserve(rim.size());
  for (const VertexId v : rim) {
    const glm::dvec3 q = cyl.perp(posed(v));
    loop[0].push_back(static_cast<std::uint32_t>(xy.size()));
    xy.emplace_back(glm::dot(q, cyl.u), glm::dot(q, cyl.w));
  }
  return geometry::winding(xy, loop, glm::dvec2(0.0));
}

// The outgoing rim edges of each vertex, found through the thread's scratch vertex map (each
// vertex with outgoing edges maps to its first one in the sorted steps), and whether a rim edge
// leads to a vertex. Holds the scratch map while it is used.
class OutgoingSteps {
 public:
  OutgoingSteps(const SurfaceMesh& mesh, const RimSteps& rim_next)
      : rim_next_(rim_next), first_out_(detail::VertexSlots::scratch()), led_to_(rim_next.size(), 0) {
    first_out_.reset(mesh.vertex_count());
    for (std::size_t i = rim_next.size(); i-- > 0;)
      first_out_.set(rim_next[i].first, static_cast<std::uint32_t>(i));
    for (const auto& step : rim_next) {
      const std::uint32_t at = first_out_.get(step.second);
      if (at != detail::VertexSlots::kNone) led_to_[at] = 1;
    }
  }
  /// The outgoing rim edges of v: [first, last) in rim_next (empty when none).
  std::pair<std::size_t, std::size_t> of(std::uint32_t v) const {
    const std::uint32_t at = first_out_.get(v);
    if (at == detail::VertexSlots::kNone) return {0, 0};
    std::size_t hi = at;
    while (hi != rim_next_.size() && rim_next_[hi].first == v) ++hi;
    return {at, hi};
  }
  /// Whether v has outgoing rim edges.
  bool has_outgoing(std::uint32_t v) const { return first_out_.get(v) != detail::VertexSlots::kNone; }
  /// Whether a rim edge leads to v, a vertex with outgoing rim edges.
  bool led_to(std::uint32_t v) const {
    const std::uint32_t at = first_out_.get(v);
    return at != detail::VertexSlots::kNone && led_to_[at] != 0;
  }

 private:
  const RimSteps& rim_next_;
  detail::VertexSlots& first_out_;
  std::vector<char> led_to_;  // by a vertex's first outgoing edge
};

// Where several rims meet at one vertex (a vertex on the cylinder whose surface the hole pinches,
// or two holes touching there), each incoming rim edge continues with the outgoing one of its
// own fan: turning around the vertex through the kept faces from the incoming edge's face to
// the next boundary edge. Pairing them otherwise crosses the rims there (they cannot be walled,
// and after the pinch split the rim would jump between the vertex's copies).
class RimFans {
 public:
  // Half-edge a->b of a kept face: its third corner (the last face filed wins), in a hash map.
  // Only half-edges into a vertex with outgoing rim edges are asked about (fan_next's `cur`).
  RimFans(const SurfaceMesh& mesh, const EditLog& log, const std::vector<FaceId>& candidates,
          const RimSteps& rim_next, const OutgoingSteps& steps)
      : rim_next_(rim_next) {
    slots_.reserve(4 * rim_next.size() + 16);
    auto add_face = [&](const Triangle& t) {
      for (int k = 0; k < 3; ++k)
        if (steps.has_outgoing(t[(k + 1) % 3].index)) {
          const auto [at, made] = slots_.find_or_insert(directed_key(t[k], t[(k + 1) % 3]),
                                                        static_cast<std::uint32_t>(third_.size()));
          if (made) third_.push_back(t[(k + 2) % 3].index);
          else third_[at] = t[(k + 2) % 3].index;
        }
    };
    for (const Edit& e : log.edits)
      if (const auto* fa = std::get_if<FaceAdded>(&e))
        if (!mesh.is_deleted(fa->f)) add_face(mesh.face(fa->f));
    for (FaceId f : candidates)
      if (!mesh.is_deleted(f)) add_face(mesh.face(f));
  }

  // The outgoing rim edge of `cur` (those are `out_edges` in rim_next) in the fan of prev->cur
  // (used or not; -1 when the faces around do not say), as an index into rim_next.
  long fan_next(std::uint32_t prev, std::uint32_t cur, std::pair<std::size_t, std::size_t> out_edges,
                const std::vector<char>& used) const {
    std::uint32_t from = prev;  // turn from the face holding prev->cur
    for (std::size_t guard = 0; guard < 256; ++guard) {
      const std::uint32_t at = slots_.find(directed_key(VertexId(from), VertexId(cur)));
      if (at == detail::EdgeSlots::kNone) return -1;
      const std::uint32_t out = third_[at];  // cur->out is the next half-edge of that face
      long found = -1;
      for (std::size_t i = out_edges.first; i < out_edges.second; ++i)
        if (rim_next_[i].second == out && (found < 0 || !used[i])) found = static_cast<long>(i);
      if (found >= 0) return found;
      if (out == prev) return -1;  // went all the way round
      from = out;                  // across cur->out to the face holding out->cur
    }
    return -1;
  }

 private:
  const RimSteps& rim_next_;
  detail::EdgeSlots slots_;  // half-edge -> index into third_
  std::vector<std::uint32_t> third_;
};

// Chains the rim steps into rims: open chains first, then closed loops, each with its winding
// around the axis.
std::vector<Rim> chain_rims(const SurfaceMesh& mesh, const EditLog& log, const CylinderFrame& cyl,
                            const PosedOverlay& posed, const std::vector<FaceId>& candidates,
                            const RimSteps& rim_next) {
  std::vector<Rim> rims;
  std::vector<std::uint32_t> starts;
  for (const auto& step : rim_next)
    if (starts.empty() || starts.back() != step.first) starts.push_back(step.first);
  // A vertex with several outgoing rim edges continues each rim along its own fan (RimFans).
  // Where none has, a walk takes the one unused edge whatever the fans say, and closes at its
  // start (whose only edge is its first) either way: the fans are not looked for.
  bool forks = false;
  for (std::size_t i = 1; i < rim_next.size() && !forks; ++i)
    forks = rim_next[i].first == rim_next[i - 1].first;
  const OutgoingSteps steps(mesh, rim_next);
  std::optional<RimFans> fans;
  if (forks) fans.emplace(mesh, log, candidates, rim_next, steps);
  // Open chains first (from vertices nothing leads to), then closed loops.
  std::stable_partition(starts.begin(), starts.end(), [&](std::uint32_t v) { return !steps.led_to(v); });
  std::vector<char> used(rim_next.size(), 0);  // per outgoing rim edge
  std::vector<VertexId> walk;                  // the rim being walked, copied out whole once
  walk.reserve(rim_next.size() + 1);           // (a rim uses each edge at most once)
  for (std::uint32_t s : starts) {
    const auto from_start = steps.of(s);
    for (std::size_t first = from_start.first; first < from_start.second; ++first) {
      if (used[first]) continue;
      used[first] = 1;
      Rim hole;
      walk.assign(1, VertexId(s));
      std::uint32_t prev = s, cur = rim_next[first].second;
      hole.closed = false;
      while (true) {
        const auto next = steps.of(cur);
        const bool any = next.first < next.second;
        const long fan = any && fans ? fans->fan_next(prev, cur, next, used) : -1;
        if (cur == s && (fan < 0 || fan == static_cast<long>(first))) {  // back through the start's own fan
          hole.closed = true;
          break;
        }
        walk.push_back(VertexId(cur));
        if (!any) break;
        long i = fan >= 0 && !used[static_cast<std::size_t>(fan)] ? fan : -1;
        for (std::size_t j = next.first; j < next.second && i < 0; ++j)
          if (!used[j]) i = static_cast<long>(j);
        if (i < 0) break;
        used[static_cast<std::size_t>(i)] = 1;
        prev = cur;
        cur = rim_next[static_cast<std::size_t>(i)].second;
      }
      hole.vertices.assign(walk.begin(), walk.end());
      if (hole.closed) hole.winding = winding(cyl, posed, hole.vertices);
      rims.push_back(std::move(hole));
    }
  }
  return rims;
}

}  // namespace

std::vector<Rim> trace_rims(const SurfaceMesh& mesh, const EditLog& log, const CylinderFrame& cyl,
                            const PosedOverlay& posed, const std::vector<FaceId>& candidates,
                            const std::unordered_map<std::uint32_t, std::uint32_t>& copy_of) {
  const RimSteps rim_next = rim_steps(mesh, log, cyl, posed, candidates, copy_of);
  return chain_rims(mesh, log, cyl, posed, candidates, rim_next);
}

}  // namespace deepcut::drill
