// SPDX-License-Identifier: MIT
#include "ops/cut/caps.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <type_traits>
#include <unordered_set>

#include "deepcut/core/morph.h"
#include "deepcut/core/parallel.h"
#include "geometry/polygon_triangulation.h"
#include "ops/common/crossing_table.h"

namespace deepcut::detail {
namespace {

bool flat(const std::vector<std::int8_t>& sign, const Triangle& t) {
  return sign[t[0].index] == 0 && sign[t[1].index] == 0 && sign[t[2].index] == 0;
}

// Closed rim loops as indices into `verts` (each rim vertex once).
struct RimLoops {
  std::vector<std::vector<std::uint32_t>> loops;
  std::vector<VertexId> verts;
};

// The least and the greatest of some ids (a cut's rim vertices are its newest ones: their ids are
// close), and whether a table over that span is cheap beside m items: fewer than 4 entries per
// item, and 256 more.
struct IdSpan {
  std::uint32_t lo = kInvalidIndex, hi = 0;
  bool few(std::size_t m) const { return hi - lo < 4 * m + 256; }
  std::size_t size() const { return std::size_t(hi - lo) + 1; }
};
template <class Items, class Id>
IdSpan id_span(const Items& items, Id id) {
  IdSpan span;
  for (const auto& item : items) {
    span.lo = std::min(span.lo, id(item));
    span.hi = std::max(span.hi, id(item));
  }
  return span;
}

// Sorts keys (vertex << 32 | halfedge) as numbers when the halfedges are listed in increasing
// order: stably by vertex. When the vertices span few ids (a cut's rim vertices are its newest
// ones) one counting pass over that span does it; otherwise least significant byte first over
// the bytes in which the vertices differ from the smallest one.
void sort_by_vertex(std::vector<std::uint64_t>& keys, std::vector<std::uint64_t>& scratch,
                    std::vector<std::uint32_t>& count) {
  if (keys.size() < 2) return;
  const IdSpan span = id_span(keys, [](std::uint64_t k) { return static_cast<std::uint32_t>(k >> 32); });
  const std::uint32_t lo = span.lo, hi = span.hi;
  scratch.resize(keys.size());
  auto pass = [&](std::uint32_t buckets, auto&& bucket) {
    count.assign(std::size_t(buckets) + 1, 0);
    for (const std::uint64_t k : keys) ++count[bucket(k) + 1];
    for (std::size_t b = 0; b < buckets; ++b) count[b + 1] += count[b];
    for (const std::uint64_t k : keys) scratch[count[bucket(k)]++] = k;
    keys.swap(scratch);
  };
  if (span.few(keys.size())) {
    pass(static_cast<std::uint32_t>(span.size()),
         [lo](std::uint64_t k) { return static_cast<std::uint32_t>(k >> 32) - lo; });
    return;
  }
  for (int shift = 0; shift < 32 && ((hi - lo) >> shift) != 0; shift += 8)
    pass(256, [lo, shift](std::uint64_t k) {
      return ((static_cast<std::uint32_t>(k >> 32) - lo) >> shift) & 0xffu;
    });
}

// The group (index into `from`, the sorted vertices steps leave) of the vertex each halfedge's
// step reaches (its first end), or kInvalidIndex where no step leaves it. When the groups span
// few ids (a cut's rim vertices are its newest ones) a table over that span answers; otherwise
// the reached vertices are sorted and merged with `from`.
void reached_groups(const std::vector<std::pair<VertexId, VertexId>>& halfedges, const std::vector<std::uint32_t>& from,
                    std::vector<std::uint32_t>& reached) {
  const std::size_t m = halfedges.size();
  const auto groups = static_cast<std::uint32_t>(from.size());
  reached.assign(m, kInvalidIndex);
  if (groups == 0) return;
  const IdSpan span{from.front(), from.back()};
  const std::uint32_t lo = span.lo, hi = span.hi;
  if (span.few(m)) {
    std::vector<std::uint32_t> group_of(span.size(), kInvalidIndex);
    for (std::uint32_t r = 0; r < groups; ++r) group_of[from[r] - lo] = r;
    for (std::size_t k = 0; k < m; ++k) {
      const std::uint32_t v = halfedges[k].first.index;
      if (v >= lo && v <= hi) reached[k] = group_of[v - lo];
    }
    return;
  }
  std::vector<std::uint64_t> reaches(m), scratch;
  std::vector<std::uint32_t> count;
  for (std::size_t k = 0; k < m; ++k) reaches[k] = (std::uint64_t(halfedges[k].first.index) << 32) | k;
  sort_by_vertex(reaches, scratch, count);
  for (std::size_t p = 0, r = 0; p < m; ++p) {
    const auto v = static_cast<std::uint32_t>(reaches[p] >> 32);
    while (r < groups && from[r] < v) ++r;
    if (r < groups && from[r] == v) reached[reaches[p] & 0xffffffffu] = static_cast<std::uint32_t>(r);
  }
}

// Appends a closed loop of rim slots to `out`, each slot's vertex (`vertex_of(slot)`) numbered
// locally by its first appearance in a kept loop (`local`, by slot).
template <class VertexOf>
void add_loop(const std::vector<std::uint32_t>& loop, std::vector<std::uint32_t>& local, VertexOf vertex_of,
              RimLoops& out) {
  std::vector<std::uint32_t> l;
  l.reserve(loop.size());
  for (std::uint32_t g : loop) {
    if (local[g] == kInvalidIndex) {
      local[g] = static_cast<std::uint32_t>(out.verts.size());
      out.verts.push_back(vertex_of(g));
    }
    l.push_back(local[g]);
  }
  out.loops.push_back(std::move(l));
}

// trace_loops where no vertex leaves two steps and the vertices steps leave span few ids (a cut's
// rim vertices are its newest ones): the vertex each step reaches by a table over that span of
// the vertices it leaves, walks started in increasing vertex order as trace_loops starts them.
// Returns false, having done nothing, otherwise.
bool trace_single_steps(const std::vector<std::pair<VertexId, VertexId>>& halfedges, RimLoops& out,
                        bool& all_closed) {
  const std::size_t m = halfedges.size();
  if (m == 0) return false;
  const IdSpan ids = id_span(halfedges, [](const auto& h) { return h.second.index; });
  if (!ids.few(m)) return false;
  const std::uint32_t lo = ids.lo;
  const std::size_t span = ids.size();
  std::vector<std::uint32_t> step(span, kInvalidIndex);  // by leaving vertex - lo: the vertex reached
  for (const auto& [a, b] : halfedges) {
    std::uint32_t& s = step[b.index - lo];
    if (s != kInvalidIndex) return false;  // a vertex two steps leave
    s = a.index;
  }
  // Local index of each rim vertex (by vertex - lo), by first appearance in a kept loop.
  std::vector<std::uint32_t> local(span, kInvalidIndex);
  all_closed = true;
  std::vector<std::uint32_t> loop;  // vertices - lo
  loop.reserve(m);
  for (std::uint32_t first = 0; first < span; ++first) {
    if (step[first] == kInvalidIndex) continue;
    loop.assign(1, first);
    std::uint32_t r = first;
    bool closed = false;
    while (true) {
      const std::uint32_t next = step[r] - lo;  // past the span (wrapping below it): no step leaves it
      step[r] = kInvalidIndex;
      r = next;
      if (r == first) {
        closed = true;
        break;
      }
      if (r >= span || step[r] == kInvalidIndex) break;  // an open rim chain (open input): not capped
      loop.push_back(r);
    }
    all_closed = all_closed && closed;
    if (!closed || loop.size() < 3) continue;
    add_loop(loop, local, [lo](std::uint32_t g) { return VertexId(lo + g); }, out);
  }
  return true;
}

// Follows the rim halfedges backwards (the cap runs along the piece's rim edges in the opposite
// direction) into closed loops; returns false if some rim chain is open. Each rim edge is used by
// one rim face, so every reversed halfedge b -> a is listed once. The steps are grouped by the
// vertex they leave (groups in increasing vertex order, steps in halfedge order); loops start at
// each unused step in that order, and a walk takes the first unused step of its vertex. So the
// used steps of a group are always its first ones: a cursor per group is its next unused step.
bool trace_loops(const std::vector<std::pair<VertexId, VertexId>>& halfedges, RimLoops& out) {
  out.loops.clear();
  out.verts.clear();
  out.verts.reserve(halfedges.size());  // each rim vertex once: at most one per step
  bool all_closed = true;
  if (trace_single_steps(halfedges, out, all_closed)) return all_closed;
  const std::size_t m = halfedges.size();
  // The steps sorted by the vertex they leave (ties in halfedge order): (vertex, halfedge) as
  // one key.
  std::vector<std::uint64_t> leaves(m), scratch;
  std::vector<std::uint32_t> count;
  for (std::size_t k = 0; k < m; ++k) leaves[k] = (std::uint64_t(halfedges[k].second.index) << 32) | k;
  sort_by_vertex(leaves, scratch, count);
  // Group r: the steps leaving vertex from[r], which are steps [start[r], start[r + 1]).
  std::vector<std::uint32_t> from, start;
  from.reserve(m);
  start.reserve(m + 1);
  for (std::size_t p = 0; p < m; ++p)
    if (p == 0 || (leaves[p] >> 32) != (leaves[p - 1] >> 32)) {
      from.push_back(static_cast<std::uint32_t>(leaves[p] >> 32));
      start.push_back(static_cast<std::uint32_t>(p));
    }
  const auto groups = static_cast<std::uint32_t>(from.size());
  start.push_back(static_cast<std::uint32_t>(m));
  // The group each step reaches (kInvalidIndex: a vertex no step leaves), by step.
  std::vector<std::uint32_t> reached, to(m);
  reached_groups(halfedges, from, reached);
  for (std::size_t p = 0; p < m; ++p) to[p] = reached[leaves[p] & 0xffffffffu];
  std::vector<std::uint32_t> cursor(start.begin(), start.end() - 1);
  // Local index of each rim vertex (by group), by first appearance in a kept loop.
  std::vector<std::uint32_t> local(groups, kInvalidIndex);
  std::vector<std::uint32_t> loop;  // groups
  loop.reserve(m);
  for (std::uint32_t first = 0; first < groups; ++first)
    while (cursor[first] < start[first + 1]) {
      loop.assign(1, first);
      std::uint32_t r = first;
      bool closed = false;
      while (true) {
        r = to[cursor[r]++];
        if (r == first) {
          closed = true;
          break;
        }
        if (r == kInvalidIndex || cursor[r] == start[r + 1]) break;  // an open rim chain (open input): not capped
        loop.push_back(r);
      }
      all_closed = all_closed && closed;
      if (!closed || loop.size() < 3) continue;
      add_loop(loop, local, [&from](std::uint32_t g) { return VertexId(from[g]); }, out);
    }
  return all_closed;
}

// One piece's cap, planned before any cap is made (plan_cap), so that the caps' polygons can be
// triangulated together (triangulate_caps), then made one piece after another (make_cap).
struct CapPlan {
  RimLoops rim;
  std::vector<FaceId> flat_faces;   // the piece's faces in the plane the cap replaces (sorted)
  std::vector<Triangle> kept_flat;  // those it does not replace: the cap must not repeat them
  glm::dvec3 u{0.0};                // the first axis of the plane's 2D frame
  std::vector<glm::dvec2> pts;      // rim.verts in that frame
  int outer_sign = 1;               // the orientation of the cap's outer loops in that frame
  geometry::LoopPolygons polygons;
  bool holes = false;               // whether a polygon has holes (bridged: points repeat)
  std::vector<std::vector<geometry::LocalTri>> tris;  // by polygon
};

// Faces of the piece lying in the plane (every corner on it) are where the cap goes: capping
// round them would put a second layer on top of them (a duplicate face, or cap triangles sharing
// their edges: non-manifold edges). When the rim closes without them the cap takes their place
// (plan.flat_faces: make_cap removes them); otherwise (open input) they stay and the rim is
// capped as it is (plan.kept_flat: the cap must not repeat them).
void choose_loops(const SurfaceMesh& mesh, const CapInput& in, CapPlan& plan) {
  RimLoops& rim = plan.rim;
  std::vector<FaceId>& flat_faces = plan.flat_faces;
  for (FaceId f : in.rim_faces)
    if (flat(*in.sign, mesh.face(f))) flat_faces.push_back(f);
  std::sort(flat_faces.begin(), flat_faces.end());
  std::vector<Triangle>& kept_flat = plan.kept_flat;
  if (flat_faces.empty() || !trace_loops(rim_halfedges(mesh, in, flat_faces), rim)) {
    for (FaceId f : flat_faces) kept_flat.push_back(mesh.face(f));
    flat_faces.clear();
    const auto found = in.rim ? std::vector<std::pair<VertexId, VertexId>>() : rim_halfedges(mesh, in);
    trace_loops(in.rim ? *in.rim : found, rim);
    // A rim loop that runs along a kept flat face (two of its corners on the loop) would be
    // capped over or beside that face, and cap triangles would share its edges (non-manifold
    // edges on open pieces). The surface there is partly in the plane already, and a cap of the
    // other loops could cover it as a hole, so the piece gets no cap rather than a doubled one.
    if (!kept_flat.empty()) {
      std::unordered_set<std::uint32_t> on_loop;
      for (const auto& loop : rim.loops)
        for (std::uint32_t i : loop) on_loop.insert(rim.verts[i].index);
      const bool runs_along = std::any_of(kept_flat.begin(), kept_flat.end(), [&](const Triangle& t) {
        return on_loop.count(t[0].index) + on_loop.count(t[1].index) + on_loop.count(t[2].index) >= 2;
      });
      if (runs_along) rim.loops.clear();
    }
  }
  if (rim.loops.empty()) flat_faces.clear();  // no cap: they stay
}

// The cap's polygons in the plane's 2D frame (plan.pts, plan.u), with the orientation of its
// largest loop (an outer one) as the cap's.
void plan_polygons(const CapInput& in, CapPlan& plan) {
  const auto& loops = plan.rim.loops;
  const auto& verts = plan.rim.verts;
  const glm::dvec3 n = in.normal;
  const glm::dvec3 u = glm::normalize(std::abs(n.x) < 0.9 ? glm::cross(n, glm::dvec3(1, 0, 0))
                                                          : glm::cross(n, glm::dvec3(0, 1, 0)));
  const glm::dvec3 w = glm::cross(n, u);
  plan.u = u;
  plan.pts.resize(verts.size());
  for (std::size_t i = 0; i < verts.size(); ++i) {
    const glm::dvec3 p = glm::dvec3((*in.posed)(verts[i])) - in.point;
    plan.pts[i] = {glm::dot(p, u), glm::dot(p, w)};
  }
  double largest_area = geometry::signed_area2(plan.pts, loops[0]);
  for (std::size_t i = 1; i < loops.size(); ++i) {
    const double area = geometry::signed_area2(plan.pts, loops[i]);
    if (std::abs(area) > std::abs(largest_area)) largest_area = area;
  }
  plan.outer_sign = largest_area >= 0 ? 1 : -1;
  plan.polygons = geometry::loop_polygons(plan.pts, loops, plan.outer_sign);
  plan.holes = std::any_of(plan.polygons.holes.begin(), plan.polygons.holes.end(),
                           [](const auto& holes) { return !holes.empty(); });
  plan.tris.resize(plan.polygons.outers.size());
}

// Caps with this many polygon corners in all (or more) are triangulated on the pool: below it
// handing the polygons to other threads costs about what it saves, or more on a busy machine (the
// bench's 25k cut, 634 corners, ran faster on one thread in 18 of 23 alternating runs on two
// shared cores; its 1M cut has 4070).
constexpr std::size_t kParallelCapCorners = 2048;

// The points of a cap's polygons by their coordinates, built once per cap pair (O(points)): an
// open-addressing table of point indices probed linearly from a hash of the coordinates' bit
// patterns, -0 taken as +0 (so that a match is where == holds). Of equal points the lowest index
// is kept; a point that is not a number is left out (== matches none).
class PointTable {
 public:
  // The points `pts[i]` with on[i] != kInvalidIndex.
  PointTable(const std::vector<glm::dvec2>& pts, const std::vector<std::uint32_t>& on) : pts_(pts) {
    std::size_t size = 16;
    while (size < 2 * pts.size()) size *= 2;
    slots_.assign(size, kInvalidIndex);
    for (std::uint32_t i = 0; i < pts.size(); ++i) {
      if (on[i] == kInvalidIndex || std::isnan(pts[i].x) || std::isnan(pts[i].y)) continue;
      std::size_t s = slot(pts[i]);
      while (slots_[s] != kInvalidIndex && !(pts_[slots_[s]] == pts[i])) s = (s + 1) & (slots_.size() - 1);
      if (slots_[s] == kInvalidIndex) slots_[s] = i;
    }
  }
  // The lowest index of a point equal to p, or kInvalidIndex.
  std::uint32_t find(const glm::dvec2& p) const {
    if (std::isnan(p.x) || std::isnan(p.y)) return kInvalidIndex;
    for (std::size_t s = slot(p);; s = (s + 1) & (slots_.size() - 1))
      if (slots_[s] == kInvalidIndex || pts_[slots_[s]] == p) return slots_[s];
  }

 private:
  std::size_t slot(const glm::dvec2& p) const {
    auto bits = [](double v) {
      v = v == 0.0 ? 0.0 : v;
      std::uint64_t b;
      std::memcpy(&b, &v, sizeof b);
      return b;
    };
    const std::uint64_t h = (bits(p.x) * 0x9E3779B97F4A7C15ull) ^ (bits(p.y) * 0xC2B2AE3D27D4EB4Full);
    return std::size_t(h ^ (h >> 29)) & (slots_.size() - 1);
  }
  const std::vector<glm::dvec2>& pts_;
  std::vector<std::uint32_t> slots_;
};

// The triangles of polygon k of `to` taken from those of `from`'s polygon that is its mirror
// image, where that one's clip says they are the same (MirrorClip::exact): a plane cut of a
// closed surface caps its two sides over the same rim loops, each loop run the other way by the
// other side, and plan_polygons gives both the same frame, mirrored for one of them (its outer
// loops run the other way). So polygon k's points are exactly those of a polygon of `from` with x
// negated, in reverse order (checked point by point, with the point numbering one-to-one), and its
// clip would make every decision the same. `from_polygon` (by point of `from`: its polygon, or
// kInvalidIndex) and `position` (in that polygon's loop) locate the points, `from_points` finds
// them by coordinates (the points on a polygon); `used` the polygons of
// `from` taken already; `to_from` and `from_to` are scratch (by point, kInvalidIndex between
// calls). Returns false, having taken nothing, where some check fails.
bool mirror_triangles(const CapPlan& from, const std::vector<geometry::MirrorClip>& clips,
                      const std::vector<std::uint32_t>& from_polygon,
                      const std::vector<std::uint32_t>& position, const PointTable& from_points,
                      std::vector<char>& used, std::vector<std::uint32_t>& from_to,
                      std::vector<std::uint32_t>& to_from, CapPlan& to, std::size_t k) {
  const auto& loop = to.rim.loops[to.polygons.outers[k]];
  const std::size_t n = loop.size();
  const auto& pts = to.polygons.pts;
  const auto& from_pts = from.polygons.pts;
  // The first point of `from` (on one of its polygons) that is the loop's first point mirrored
  // (were there several, the check below finds whether this one is where the mirror image starts).
  const glm::dvec2 first = pts[loop[0]];
  const std::uint32_t match = from_points.find({-first.x, first.y});
  if (match == kInvalidIndex) return false;
  const std::uint32_t kf = from_polygon[match];
  const auto& from_loop = from.rim.loops[from.polygons.outers[kf]];
  if (used[kf] || !clips[kf].exact || from_loop.size() != n) return false;
  // Point j of the loop is point position - j (mod n) of from_loop, mirrored.
  bool same = true;
  std::size_t j = 0;
  for (std::size_t f = position[match]; j < n; ++j, f = f == 0 ? n - 1 : f - 1) {
    const std::uint32_t a = from_loop[f], b = loop[j];
    if (!(from_pts[a].x == -pts[b].x && from_pts[a].y == pts[b].y) ||
        (from_to[a] != kInvalidIndex && from_to[a] != b) ||
        (to_from[b] != kInvalidIndex && to_from[b] != a)) {
      same = false;
      break;
    }
    from_to[a] = b;
    to_from[b] = a;
  }
  if (same) {
    const auto& tris = from.tris[kf];
    auto& out = to.tris[k];
    out.resize(tris.size());
    const std::size_t ears = clips[kf].closed ? tris.size() - 1 : tris.size();
    auto to_of = [&](const geometry::LocalTri& t, int a, int b, int c) {
      return geometry::LocalTri{from_to[t[a]], from_to[t[b]], from_to[t[c]]};
    };
    for (std::size_t t = 0; t < ears; ++t) out[t] = to_of(tris[t], 2, 1, 0);
    if (ears < tris.size()) out[ears] = to_of(tris[ears], 1, 0, 2);
    used[kf] = 1;
  }
  // The scratch back to kInvalidIndex.
  for (std::size_t i = 0, f = position[match]; i <= j && i < n; ++i, f = f == 0 ? n - 1 : f - 1) {
    from_to[from_loop[f]] = kInvalidIndex;
    to_from[loop[i]] = kInvalidIndex;
  }
  return same;
}

// Whether the second cap may take its triangles from the first (set_cap_mirroring: tests compare).
std::atomic<bool> cap_mirroring{true};

// Triangulates every planned polygon of every cap (as triangulate_loops would), on the pool
// when they are big enough: each polygon's triangles are its own, so the result is the same
// whatever the thread count. Of two caps without holes (the sides of one closed surface), the
// second takes the triangles of a polygon from the first where they are the same
// (mirror_triangles), and is clipped where they may not be.
void triangulate_caps(std::vector<CapPlan>& plans) {
  cap_mirror_stats() = {};
  const bool pair = cap_mirroring.load(std::memory_order_relaxed) && plans.size() == 2 &&
                    !plans[0].rim.loops.empty() && !plans[1].rim.loops.empty() && !plans[0].holes &&
                    !plans[1].holes && plans[0].polygons.outers.size() == plans[1].polygons.outers.size();
  std::vector<geometry::MirrorClip> clips(pair ? plans[0].polygons.outers.size() : 0);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> jobs;  // (plan, polygon)
  auto triangulate = [&](std::size_t j) {
    CapPlan& plan = plans[jobs[j].first];
    const std::size_t k = jobs[j].second;
    const auto& outer = plan.rim.loops[plan.polygons.outers[k]];
    plan.tris[k].reserve(outer.size());
    geometry::MirrorClip* mirror = pair && jobs[j].first == 0 ? &clips[k] : nullptr;
    auto& holes = plan.polygons.holes[k];
    geometry::triangulate_polygon(plan.polygons.pts, outer, std::move(holes), {}, plan.tris[k], mirror);
  };
  auto run_jobs = [&] {
    std::size_t corners = 0;
    for (const auto& [p, k] : jobs) {
      corners += plans[p].rim.loops[plans[p].polygons.outers[k]].size();
      for (const auto& hole : plans[p].polygons.holes[k]) corners += hole.size();
    }
    if (jobs.size() < 2 || corners < kParallelCapCorners) {
      for (std::size_t j = 0; j < jobs.size(); ++j) triangulate(j);
      return;
    }
    parallel_for(jobs.size(), 1, [&](std::size_t begin, std::size_t end) {
      for (std::size_t j = begin; j < end; ++j) triangulate(j);
    });
  };
  for (std::size_t p = 0; p < plans.size(); ++p)
    if (!pair || p == 0)
      for (std::size_t k = 0; k < plans[p].polygons.outers.size(); ++k)
        jobs.emplace_back(static_cast<std::uint32_t>(p), static_cast<std::uint32_t>(k));
  run_jobs();
  if (!pair) return;
  const CapPlan& from = plans[0];
  CapPlan& to = plans[1];
  const std::size_t from_points = from.polygons.pts.size();
  std::vector<std::uint32_t> from_polygon(from_points, kInvalidIndex), position(from_points);
  for (std::uint32_t k = 0; k < from.polygons.outers.size(); ++k) {
    const auto& loop = from.rim.loops[from.polygons.outers[k]];
    for (std::uint32_t i = 0; i < loop.size(); ++i) {
      from_polygon[loop[i]] = k;
      position[loop[i]] = i;
    }
  }
  const PointTable from_points_by_key(from.polygons.pts, from_polygon);
  std::vector<char> used(from.polygons.outers.size(), 0);
  std::vector<std::uint32_t> from_to(from_points, kInvalidIndex);
  std::vector<std::uint32_t> to_from(to.polygons.pts.size(), kInvalidIndex);
  jobs.clear();
  for (std::uint32_t k = 0; k < to.polygons.outers.size(); ++k)
    if (!mirror_triangles(from, clips, from_polygon, position, from_points_by_key, used, from_to, to_from, to,
                          k))
      jobs.emplace_back(1, k);
  cap_mirror_stats() = {to.polygons.outers.size() - jobs.size(), jobs.size()};
  run_jobs();
}

// The corner arrays a cap sets (null where the mesh has none), found once for all caps: adding
// faces grows them but never replaces them.
struct CapCorners {
  AttributeArray<glm::vec2>* uv = nullptr;
  AttributeArray<glm::vec3>* normal = nullptr;
  AttributeArray<glm::vec4>* tangent = nullptr;
  AttributeArray<glm::vec4>* color = nullptr;
  std::vector<AttributeArray<glm::vec3>*> deltas;  // corner morph deltas
  explicit CapCorners(SurfaceMesh& mesh)
      : uv(mesh.corner_attrs().find<glm::vec2>(attr::kUv0)),
        normal(mesh.corner_attrs().find<glm::vec3>(attr::kNormal)),
        tangent(mesh.corner_attrs().find<glm::vec4>(attr::kTangent)),
        color(mesh.corner_attrs().find<glm::vec4>(attr::kColor0)),
        deltas(corner_morph_deltas(mesh)) {}
};

// The corner attributes of the cap faces first .. first + made.size() - 1 (face k made from
// tris[made[k]], its corners' points in the plane's frame `pts`, first axis `u`): a planar UV
// over the cap's extent, the face normal (`flat_normal`, the plane's oriented as the cap, for a
// degenerate face), the tangent u, white, and zero morph deltas. The faces are consecutive: so
// are their corners. Writes the mesh's corner arrays (through `arrays`).
void set_cap_attributes(SurfaceMesh& mesh, const CapCorners& arrays, std::uint32_t first,
                        const std::vector<std::uint32_t>& made, const std::vector<glm::dvec2>& pts,
                        const std::vector<geometry::LocalTri>& tris, const glm::vec3& flat_normal,
                        const glm::dvec3& u) {
  const std::size_t count = made.size(), corner0 = 3 * std::size_t(first);
  // No faces (each triangle repeats a kept flat face, or the loops gave none): `first` is the
  // face count, no face to read.
  if (count == 0) return;
  // The faces were just added: their corners hold each array's default value (SurfaceMesh::
  // add_face), so a value with the same bits (zero morph deltas, mostly) needs no writing.
  auto fill = [&](auto* attribute, const auto& value) {
    static_assert(
        std::is_same_v<std::decay_t<decltype(attribute->default_value())>, std::decay_t<decltype(value)>>);
    if (!attribute || std::memcmp(&attribute->default_value(), &value, sizeof value) == 0) return;
    std::fill_n(attribute->data().data() + corner0, 3 * count, value);
  };
  if (arrays.uv) {
    double extent = 0.0;
    // std::max({extent, |x|, |y|}) as two std::max: the same comparisons in the same order.
    for (const auto& p : pts) extent = std::max(std::max(extent, std::abs(p.x)), std::abs(p.y));
    if (extent <= 0.0) extent = 1.0;
    // Each point's UV once (a point is a corner of about three faces).
    std::vector<glm::vec2> at(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i)
      at[i] = glm::vec2(0.5 + 0.5 * pts[i].x / extent, 0.5 + 0.5 * pts[i].y / extent);
    glm::vec2* out = arrays.uv->data().data() + corner0;
    for (std::size_t k = 0; k < count; ++k, out += 3) {
      const geometry::LocalTri& t = tris[made[k]];
      out[0] = at[t[0]];
      out[1] = at[t[1]];
      out[2] = at[t[2]];
    }
  }
  if (arrays.normal) {
    const glm::vec3* bind = mesh.positions().data();
    const Triangle* faces = &mesh.face(FaceId(first));
    glm::vec3* out = arrays.normal->data().data() + corner0;
    for (std::size_t k = 0; k < count; ++k, out += 3) {
      const Triangle& t = faces[k];
      glm::vec3 fn = glm::cross(bind[t[1].index] - bind[t[0].index], bind[t[2].index] - bind[t[0].index]);
      const float len = glm::length(fn);
      fn = len > 0.0f ? fn / len : flat_normal;
      out[0] = out[1] = out[2] = fn;
    }
  }
  fill(arrays.tangent, glm::vec4(glm::vec3(u), 1.0f));
  fill(arrays.color, glm::vec4(1.0f));
  for (auto* d : arrays.deltas) fill(d, glm::vec3(0.0f));
}

// Flags the cap faces (from `first` to the end of the mesh) attr::kCutSurface, adding the flags
// when the mesh has none: after the faces, so the array is made at its full size once.
void flag_cap_faces(SurfaceMesh& mesh, std::uint32_t first) {
  auto* flags = mesh.face_attrs().find<std::uint8_t>(attr::kCutSurface);
  if (!flags) flags = &mesh.face_attrs().add<std::uint8_t>(attr::kCutSurface);
  std::fill(flags->data().begin() + first, flags->data().end(), std::uint8_t(1));
}

// Whether each of the cap's polygons is a loop of rim edges (no holes) clipped into all of its
// n - 2 triangles, each with three distinct corners (`distinct`: the caller looked). Clipping a ring of n
// corners one corner at a time is, whatever the geometry, a triangulation of a disk with that ring as its
// boundary: the triangles at one corner of the ring form one fan from the rim edge before it to the rim edge
// after it.
bool whole_fans(const CapPlan& plan, bool distinct) {
  if (plan.holes || !distinct) return false;
  for (std::size_t k = 0; k < plan.tris.size(); ++k)
    if (plan.tris[k].size() + 2 != plan.rim.loops[plan.polygons.outers[k]].size()) return false;
  return true;
}

// Makes the planned cap of a piece: removes the flat faces it replaces, adds its faces (in the
// order of its polygons' triangles) with their attributes. Returns whether the cap's faces are
// whole fans (whole_fans, every triangle made).
bool make_cap(MeshEditor& editor, const CapInput& in, const CapPlan& plan, const CapCorners& arrays,
              std::vector<FaceId>& piece) {
  if (plan.rim.loops.empty()) return true;
  const auto& flat_faces = plan.flat_faces;
  if (!flat_faces.empty()) {
    for (FaceId f : flat_faces) editor.remove_face(f);
    piece.erase(
        std::remove_if(piece.begin(), piece.end(),
                       [&](FaceId f) { return std::binary_search(flat_faces.begin(), flat_faces.end(), f); }),
        piece.end());
  }
  const auto& kept_flat = plan.kept_flat;
  auto repeats_flat = [&](Triangle t) {
    std::sort(t.begin(), t.end());
    return std::any_of(kept_flat.begin(), kept_flat.end(), [&](Triangle g) {
      std::sort(g.begin(), g.end());
      return g == t;
    });
  };
  const auto& verts = plan.rim.verts;
  std::vector<geometry::LocalTri> joined;  // the polygons' triangles in order, where there are several
  if (plan.tris.size() > 1)
    for (const auto& t : plan.tris) joined.insert(joined.end(), t.begin(), t.end());
  const auto& tris = plan.tris.size() == 1 ? plan.tris[0] : joined;
  // The faces, then each attribute in one pass over them.
  std::vector<Triangle> faces;
  std::vector<std::uint32_t> made;  // the triangle of each face made, in order
  faces.reserve(tris.size());
  made.reserve(tris.size());
  bool distinct = true;  // every triangle has three distinct corners
  for (std::size_t i = 0; i < tris.size(); ++i) {
    const auto& tri = tris[i];
    distinct = distinct && tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2];
    const Triangle t = {verts[tri[0]], verts[tri[1]], verts[tri[2]]};
    if (!kept_flat.empty() && repeats_flat(t)) continue;  // that surface is there already
    faces.push_back(t);
    made.push_back(static_cast<std::uint32_t>(i));
  }
  // All in one call: each attribute array grown once.
  const FaceId first_face = editor.add_faces(faces.data(), faces.size());
  const std::size_t listed = piece.size();
  piece.reserve(listed + faces.size());  // exactly (resize alone may double the capacity)
  piece.resize(listed + faces.size());
  for (std::uint32_t k = 0; k < faces.size(); ++k) piece[listed + k] = FaceId(first_face.index + k);
  const glm::vec3 flat_normal = float(plan.outer_sign) * glm::vec3(in.normal);
  set_cap_attributes(editor.mesh(), arrays, first_face.index, made, plan.pts, tris, flat_normal, plan.u);
  return faces.size() == tris.size() && whole_fans(plan, distinct);
}

// rim_halfedges' last step where no vertex is left by two halfedges (nor reached by the one
// leaving it) and the vertices they leave span few ids (a cut's rim vertices are its newest
// ones): then the halfedges of one edge are a -> b and b -> a, found by a table over that span of
// the vertex reached from each vertex. Drops every halfedge whose edge has two, keeping the
// order. Returns false, having changed nothing, otherwise.
bool drop_twins(std::vector<std::pair<VertexId, VertexId>>& halfedges) {
  const std::size_t m = halfedges.size();
  if (m == 0) return true;
  const IdSpan span = id_span(halfedges, [](const auto& h) { return h.first.index; });
  if (!span.few(m)) return false;
  const std::uint32_t lo = span.lo;
  std::vector<std::uint32_t> reached(span.size(), kInvalidIndex);  // by vertex - lo
  for (const auto& [a, b] : halfedges) {
    std::uint32_t& r = reached[a.index - lo];
    if (r != kInvalidIndex || a == b) return false;
    r = b.index;
  }
  std::size_t n = 0;
  for (std::size_t i = 0; i < m; ++i) {
    const auto [a, b] = halfedges[i];
    const std::uint32_t back = b.index - lo;  // past the span (wrapping below it): no halfedge leaves b
    if (back < reached.size() && reached[back] == a.index) continue;
    halfedges[n++] = halfedges[i];
  }
  halfedges.resize(n);
  return true;
}

}  // namespace

CapMirrorStats& cap_mirror_stats() {
  thread_local CapMirrorStats stats;
  return stats;
}
void set_cap_mirroring(bool on) { cap_mirroring.store(on, std::memory_order_relaxed); }

std::vector<std::pair<VertexId, VertexId>> rim_halfedges(const SurfaceMesh& mesh, const CapInput& in,
                                                         const std::vector<FaceId>& skip) {
  // An edge with both ends on the plane belongs only to faces with two corners on it, so
  // counting within the rim faces is exact. The on-plane halfedges in face order, and keys
  // (lower end, halfedge) sorted: the halfedges of one edge share a run of lower ends.
  const auto& sign = *in.sign;
  std::vector<std::pair<VertexId, VertexId>> halfedges;
  // Most rim faces have one edge on the plane: room for one each to start with.
  halfedges.reserve(in.rim_faces.size() + 8);
  for (FaceId f : in.rim_faces) {
    if (!skip.empty() && std::binary_search(skip.begin(), skip.end(), f)) continue;
    const auto& t = mesh.face(f);
    const bool on[3] = {sign[t[0].index] == 0, sign[t[1].index] == 0, sign[t[2].index] == 0};
    for (int k = 0; k < 3; ++k) {
      const int k1 = k == 2 ? 0 : k + 1;
      if (!on[k] || !on[k1]) continue;
      halfedges.emplace_back(t[k], t[k1]);
    }
  }
  if (drop_twins(halfedges)) return halfedges;
  std::vector<std::uint64_t> keys, scratch;
  std::vector<std::uint32_t> count;
  keys.reserve(halfedges.size());
  for (std::size_t i = 0; i < halfedges.size(); ++i) {
    const auto& [a, b] = halfedges[i];
    keys.push_back((std::uint64_t(std::min(a.index, b.index)) << 32) | i);
  }
  sort_by_vertex(keys, scratch, count);
  auto upper = [&](std::uint64_t key) {
    const auto& [a, b] = halfedges[key & 0xffffffffu];
    return std::max(a.index, b.index);
  };
  std::vector<std::uint8_t> once(halfedges.size(), 1);
  for (std::size_t p = 0, q = 0; p < keys.size(); p = q) {
    while (q < keys.size() && (keys[q] >> 32) == (keys[p] >> 32)) ++q;
    // keys[p, q): one lower end; the same upper end is the same edge.
    if (q - p > 16)
      std::sort(keys.begin() + static_cast<std::ptrdiff_t>(p), keys.begin() + static_cast<std::ptrdiff_t>(q),
                [&](std::uint64_t x, std::uint64_t y) { return upper(x) < upper(y); });
    for (std::size_t i = p; i < q; ++i)
      for (std::size_t j = i + 1; j < q && (q - p <= 16 || j == i + 1); ++j)
        if (upper(keys[i]) == upper(keys[j])) once[keys[i] & 0xffffffffu] = once[keys[j] & 0xffffffffu] = 0;
  }
  std::size_t n = 0;
  for (std::size_t i = 0; i < halfedges.size(); ++i)
    if (once[i]) halfedges[n++] = halfedges[i];
  halfedges.resize(n);
  return halfedges;
}

bool make_caps(MeshEditor& editor, const std::vector<CapInput>& in, std::vector<std::vector<FaceId>>& pieces) {
  std::vector<CapPlan> plans(in.size());
  bool capped = false;  // some piece has a cap
  for (std::size_t p = 0; p < in.size(); ++p) {
    choose_loops(editor.mesh(), in[p], plans[p]);
    if (!plans[p].rim.loops.empty()) plan_polygons(in[p], plans[p]);
    capped = capped || !plans[p].rim.loops.empty();
  }
  triangulate_caps(plans);
  if (!capped) return true;
  SurfaceMesh& mesh = editor.mesh();
  const auto first_cap_face = static_cast<std::uint32_t>(mesh.face_slots());
  const CapCorners arrays(mesh);
  bool whole = true;
  for (std::size_t p = 0; p < in.size(); ++p)
    whole = make_cap(editor, in[p], plans[p], arrays, pieces[p]) && whole;
  flag_cap_faces(mesh, first_cap_face);
  return whole;
}

}  // namespace deepcut::detail
