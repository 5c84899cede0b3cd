// SPDX-License-Identifier: MIT
// Slit insertion: one sweep facet's crossing with the mesh, made into mesh edges. The stages:
// candidate faces (the grid's, near the facet's plane) -> chords (where the plane crosses each
// face, clipped to the facet) and in-plane edges -> new vertices (on crossed edges, on in-plane
// edges, inside faces) -> each face re-triangulated along its chord (face refinement) -> needle
// merges -> the sub-faces written and the torn edges recorded.
#include <algorithm>
#include <cmath>

#include "ops/common/face_refinement.h"
#include "ops/tear/stages.h"

namespace deepcut::detail::tear {
namespace {

struct Crossing {  // where the plane crosses a mesh edge
  VertexId lo, hi;
  double t;  // from lo to hi
  glm::dvec3 p;
  HValues h;
  bool in = false, split = false;
  VertexId v;
};
struct ZeroVertex {  // a vertex on the plane
  HValues h;
  bool in = false;
};
struct Classified {  // signed distance to the facet's plane and its snapped sign
  double dist;
  std::int8_t sign;
};

// What one facet sees of the mesh: the signed distances of the vertices of the faces examined
// (the rest of the mesh is never visited), the vertices on its plane and the crossed edges.
class FacetScan {
 public:
  FacetScan(const TearContext& ctx, const SweepFacet& facet)
      : ctx_(ctx), facet_(facet), classified(ctx.arena), zero(ctx.arena) {}

  double dist(VertexId v) const {
    auto it = classified.find(v.index);
    return it == classified.end() ? 0.0 : it->second.dist;
  }
  std::int8_t sign(VertexId v) const {
    auto it = classified.find(v.index);
    return it == classified.end() ? 0 : it->second.sign;
  }
  const ZeroVertex& zero_vertex(VertexId v) {
    auto it = zero.find(v.index);
    if (it != zero.end()) return it->second;
    ZeroVertex z{};
    z.h = hvalues(facet_, facet_.project(glm::dvec3(ctx_.pose.posed(v.index))));
    z.in = inside(facet_, z.h);
    return zero.emplace(v.index, z).first->second;
  }
  Crossing& crossing(VertexId a, VertexId b) {
    const auto [found, added] = crossings.try_emplace(a, b);
    if (!added) return *found;
    Crossing& c = *found;
    c.lo = a < b ? a : b;
    c.hi = a < b ? b : a;
    const double dl = dist(c.lo), dh = dist(c.hi);
    c.t = dl / (dl - dh);
    c.p = glm::mix(glm::dvec3(ctx_.pose.posed(c.lo.index)), glm::dvec3(ctx_.pose.posed(c.hi.index)), c.t);
    c.h = hvalues(facet_, facet_.project(c.p));
    c.in = inside(facet_, c.h);
    c.split = c.in;
    return c;
  }
  // The crossing of the edge with key `key` (one made by crossing()).
  Crossing& at(std::uint64_t key) { return *crossings.find_key(key); }
  const Crossing& at(std::uint64_t key) const { return *crossings.find_key(key); }
  const Crossing* find(VertexId a, VertexId b) const { return crossings.find(a, b); }

 private:
  const TearContext& ctx_;
  const SweepFacet& facet_;

 public:
  Map<std::uint32_t, Classified> classified;
  Map<std::uint32_t, ZeroVertex> zero;
  CrossingTable<Crossing> crossings;
};

struct ChordEnd {
  glm::dvec3 p;
  glm::dvec3 bary;
  const HValues* h;
  VertexId corner;             // valid when the end is a face corner
  std::uint64_t crossing = 0;  // edge key otherwise
};
struct FacePlan {  // a face the plane crosses, its chord and the chord's torn parts
  FaceId f;
  Triangle t;
  ChordEnd a, b;
  std::vector<Interval> torn;
  std::vector<double> interior;        // chord parameters of points strictly inside the face
  std::vector<VertexId> interior_ids;  // their vertices, once made
};
struct ZeroEdge {  // a mesh edge lying in the plane
  VertexId lo, hi;
  std::uint8_t sides = 0;  // bit 1: a face on the positive side, bit 2: negative
  int faces = 0;
  bool coplanar = false;
  std::vector<Interval> torn;
  std::vector<std::pair<double, VertexId>> points;  // split points (parameter from lo)
};

// Chords of the faces the plane crosses, and the edges lying in the plane.
struct Chords {
  explicit Chords(std::pmr::memory_resource* arena) : zero_edges(arena) {}
  std::vector<FacePlan> plans;
  Map<std::uint64_t, ZeroEdge> zero_edges;
};

// The vertices added on edges, by edge key in ascending order (the order they were made).
struct SlitVertices {
  std::vector<std::uint64_t> split_keys;  // crossed edges split
  std::vector<std::uint64_t> zero_keys;   // in-plane edges torn
};

// One face re-triangulated along its chord.
struct Refined {
  FaceId f;
  std::size_t plan;  // index into plans, or plans.size() for a face without a chord
  FaceRefinement local;
  std::vector<std::pair<std::uint32_t, VertexId>> alias;  // inserted vertex -> coincident one
};

// Faces whose posed bounding box meets the facet's (inflated by a few tolerances) and that reach
// the band of the facet's plane (a face with every corner further than that on one side has
// nothing to tear): the grid's faces along the plane plus the faces this tear made.
std::vector<FaceId> candidate_faces(const TearContext& ctx, const SweepFacet& facet) {
  BoundingBox box = facet.box;
  const double band = 4.0 * ctx.tol;
  const glm::vec3 pad(static_cast<float>(band));
  box.add(box.min - pad);
  box.add(box.max + pad);
  auto candidate = [&](const Triangle& t) {
    const glm::vec3 &a = ctx.pose.posed(t[0].index), &b = ctx.pose.posed(t[1].index), &c = ctx.pose.posed(t[2].index);
    const glm::vec3 lo = glm::min(a, glm::min(b, c)), hi = glm::max(a, glm::max(b, c));
    if (lo.x > box.max.x || lo.y > box.max.y || lo.z > box.max.z || hi.x < box.min.x || hi.y < box.min.y ||
        hi.z < box.min.z)
      return false;
    int above = 0, below = 0;
    for (const glm::vec3* p : {&a, &b, &c}) {
      const double d = glm::dot(glm::dvec3(*p) - facet.origin, facet.normal);
      above += d > band;
      below += d < -band;
    }
    return above < 3 && below < 3;
  };
  std::vector<FaceId> faces;
  const float reach = static_cast<float>(band) + 0.01f * ctx.grid.cell_size();
  for (FaceId f : ctx.grid.query_slab(box, glm::vec3(facet.origin), glm::vec3(facet.normal), reach))
    if (f.index < ctx.first_new_face && !ctx.mesh.is_deleted(f) && candidate(ctx.mesh.face(f))) faces.push_back(f);
  for (auto i = ctx.first_new_face; i < ctx.mesh.face_slots(); ++i)
    if (!ctx.mesh.is_deleted(FaceId(i)) && candidate(ctx.mesh.face(FaceId(i)))) faces.push_back(FaceId(i));
  return faces;
}

void classify(FacetScan& scan, const TearContext& ctx, const SweepFacet& facet, const std::vector<FaceId>& faces) {
  scan.classified.reserve(2 * faces.size() + 16);
  scan.crossings.reserve(faces.size() + 16);
  for (FaceId f : faces)
    for (auto v : ctx.mesh.face(f)) {
      auto [it, inserted] = scan.classified.try_emplace(v.index, Classified{0.0, 0});
      if (!inserted) continue;
      const double d = glm::dot(glm::dvec3(ctx.pose.posed(v.index)) - facet.origin, facet.normal);
      it->second = {d, static_cast<std::int8_t>(d > ctx.tol ? 1 : (d < -ctx.tol ? -1 : 0))};
    }
}

// Records a face with two or three corners on the plane among the in-plane edges; returns false
// for any other face.
bool note_zero_edges(const Triangle& t, const std::int8_t s[3], Map<std::uint64_t, ZeroEdge>& zero_edges) {
  const int zeros = (s[0] == 0) + (s[1] == 0) + (s[2] == 0);
  if (zeros == 3) {
    for (int k = 0; k < 3; ++k) {
      auto& ze = zero_edges[edge_key(t[k], t[(k + 1) % 3])];
      ze.lo = t[k] < t[(k + 1) % 3] ? t[k] : t[(k + 1) % 3];
      ze.hi = t[k] < t[(k + 1) % 3] ? t[(k + 1) % 3] : t[k];
      ze.coplanar = true;
      ++ze.faces;
    }
    return true;
  }
  if (zeros == 2) {
    int k = 0;
    while (s[(k + 2) % 3] == 0) ++k;  // the non-zero corner is k + 2
    const VertexId a = t[k], b = t[(k + 1) % 3];
    auto& ze = zero_edges[edge_key(a, b)];
    ze.lo = a < b ? a : b;
    ze.hi = a < b ? b : a;
    ze.sides |= s[(k + 2) % 3] > 0 ? 1 : 2;
    ++ze.faces;
    return true;
  }
  return false;
}

// The chord of face `f` (the plane crosses it: corners on both sides) clipped to the facet, or
// false when no part of it is torn. Marks the crossings at torn chord ends to be split.
bool plan_chord(FacetScan& scan, const TearContext& ctx, const SweepFacet& facet, FaceId f, const Triangle& t,
                const std::int8_t s[3], FacePlan& plan) {
  plan.f = f;
  plan.t = t;
  ChordEnd ends[2];
  int n = 0;
  for (int k = 0; k < 3; ++k) {
    if (s[k] == 0) {
      const ZeroVertex& z = scan.zero_vertex(t[k]);
      glm::dvec3 bary(0.0);
      bary[k] = 1.0;
      ends[n++] = {glm::dvec3(ctx.pose.posed(t[k].index)), bary, &z.h, t[k], 0};
    }
  }
  for (int k = 0; k < 3; ++k) {
    const int k1 = (k + 1) % 3;
    if (s[k] == 0 || s[k1] == 0 || s[k] == s[k1]) continue;
    Crossing& c = scan.crossing(t[k], t[k1]);
    glm::dvec3 bary(0.0);
    const double wk = t[k] == c.lo ? 1.0 - c.t : c.t;
    bary[k] = wk;
    bary[k1] = 1.0 - wk;
    ends[n++] = {c.p, bary, &c.h, VertexId(), edge_key(t[k], t[k1])};
  }
  if (n != 2) return false;
  plan.a = ends[0];
  plan.b = ends[1];
  const double len = glm::length(plan.b.p - plan.a.p);
  const double snap = len > 0.0 ? ctx.tol / len : 1.0;
  plan.torn = clip_segment(facet, *plan.a.h, *plan.b.h, snap);
  if (plan.torn.empty()) return false;
  for (const Interval& iv : plan.torn) {
    for (double s_end : {iv.lo, iv.hi}) {
      if (s_end == 0.0 && plan.a.crossing)
        scan.at(plan.a.crossing).split = true;
      else if (s_end == 1.0 && plan.b.crossing)
        scan.at(plan.b.crossing).split = true;
      else if (s_end > 0.0 && s_end < 1.0)
        plan.interior.push_back(s_end);
    }
  }
  std::sort(plan.interior.begin(), plan.interior.end());
  return true;
}

// Plan: chords of faces crossed by the plane, clipped to the facet, and the in-plane edges.
void plan_chords(FacetScan& scan, const TearContext& ctx, const SweepFacet& facet, const std::vector<FaceId>& faces,
                 Chords& chords) {
  for (FaceId f : faces) {
    const Triangle t = ctx.mesh.face(f);
    const std::int8_t s[3] = {scan.sign(t[0]), scan.sign(t[1]), scan.sign(t[2])};
    if (note_zero_edges(t, s, chords.zero_edges)) continue;
    const bool pos = s[0] > 0 || s[1] > 0 || s[2] > 0, neg = s[0] < 0 || s[1] < 0 || s[2] < 0;
    if (!pos || !neg) continue;  // no chord, or the plane only touches a corner
    FacePlan plan;
    if (plan_chord(scan, ctx, facet, f, t, s, plan)) chords.plans.push_back(std::move(plan));
  }
}

// Edges lying in the plane tear where the surface passes through them (faces on both sides).
// Returns whether any does.
bool tear_in_plane_edges(FacetScan& scan, const TearContext& ctx, const SweepFacet& facet, Chords& chords) {
  bool any_edge_torn = false;
  for (auto& [key, ze] : chords.zero_edges) {
    if (ze.coplanar || ze.faces != 2 || ze.sides != 3) continue;
    const ZeroVertex& za = scan.zero_vertex(ze.lo);
    const ZeroVertex& zb = scan.zero_vertex(ze.hi);
    const double len =
        glm::length(glm::dvec3(ctx.pose.posed(ze.hi.index)) - glm::dvec3(ctx.pose.posed(ze.lo.index)));
    ze.torn = clip_segment(facet, za.h, zb.h, len > 0.0 ? ctx.tol / len : 1.0);
    any_edge_torn |= !ze.torn.empty();
  }
  return any_edge_torn;
}

// Edits. New vertices: on crossed edges, on in-plane edges, inside faces.
SlitVertices add_slit_vertices(FacetScan& scan, TearContext& ctx, Chords& chords, Slits& slits) {
  SlitVertices out;
  for (std::size_t i = 0; i < scan.crossings.size(); ++i)
    if (scan.crossings[i].split) out.split_keys.push_back(scan.crossings.key(i));
  std::sort(out.split_keys.begin(), out.split_keys.end());  // deterministic vertex numbering
  for (std::uint64_t key : out.split_keys) {
    Crossing& c = scan.at(key);
    c.v = ctx.editor.add_vertex_on_edge(c.lo, c.hi, static_cast<float>(c.t));
    const VertexId src[2] = {c.lo, c.hi};
    const double w[2] = {1.0 - c.t, c.t};
    ctx.pose.add(ctx.editor, c.v, c.p, src, w, 2);
    ++slits.intersections;
  }
  for (const auto& [key, ze] : chords.zero_edges)
    if (!ze.torn.empty()) out.zero_keys.push_back(key);
  std::sort(out.zero_keys.begin(), out.zero_keys.end());
  for (std::uint64_t key : out.zero_keys) {
    ZeroEdge& ze = chords.zero_edges.at(key);
    std::vector<double> params;
    for (const Interval& iv : ze.torn)
      for (double s : {iv.lo, iv.hi})
        if (s > 0.0 && s < 1.0) params.push_back(s);
    std::sort(params.begin(), params.end());
    for (double s : params) {
      const VertexId v = ctx.editor.add_vertex_on_edge(ze.lo, ze.hi, static_cast<float>(s));
      const VertexId src[2] = {ze.lo, ze.hi};
      const double w[2] = {1.0 - s, s};
      const glm::dvec3 at = glm::mix(glm::dvec3(ctx.pose.posed(ze.lo.index)), glm::dvec3(ctx.pose.posed(ze.hi.index)), s);
      ctx.pose.add(ctx.editor, v, at, src, w, 2);
      ze.points.emplace_back(s, v);
    }
  }
  for (FacePlan& plan : chords.plans) {
    for (double s : plan.interior) {
      const glm::dvec3 bary = glm::mix(plan.a.bary, plan.b.bary, s);
      const VertexId v = ctx.editor.add_vertex_in_triangle(plan.t, glm::vec3(bary));
      const double w[3] = {bary.x, bary.y, bary.z};
      ctx.pose.add(ctx.editor, v, glm::mix(plan.a.p, plan.b.p, s), plan.t.data(), w, 3);
      plan.interior_ids.push_back(v);
    }
  }
  return out;
}

struct Insert {  // a point to insert into a face, at chord parameter s
  double s;
  VertexId v;
  glm::dvec3 bary;
};

// The points of face `t` to insert, in chord order: its chord's interior points, its split
// crossings and its in-plane edge points. They all lie on the face's chord (a crossing is a
// chord end of every face around its edge).
std::vector<Insert> points_of_face(const FacetScan& scan, const Chords& chords, const Triangle& t,
                                   const FacePlan* plan) {
  std::vector<Insert> list;
  if (plan)
    for (std::size_t i = 0; i < plan->interior.size(); ++i)
      list.push_back({plan->interior[i], plan->interior_ids[i], glm::mix(plan->a.bary, plan->b.bary, plan->interior[i])});
  for (int k = 0; k < 3; ++k) {
    const int k1 = (k + 1) % 3;
    const auto key = edge_key(t[k], t[k1]);
    const Crossing* cit = scan.find(t[k], t[k1]);
    if (cit && cit->split) {
      const Crossing& c = *cit;
      glm::dvec3 bary(0.0);
      const double wk = t[k] == c.lo ? 1.0 - c.t : c.t;
      bary[k] = wk;
      bary[k1] = 1.0 - wk;
      double s = 0.0;
      if (plan) s = plan->b.crossing == key ? 1.0 : 0.0;
      list.push_back({s, c.v, bary});
    }
    auto zit = chords.zero_edges.find(key);
    if (zit != chords.zero_edges.end() && !zit->second.points.empty()) {
      const ZeroEdge& ze = zit->second;
      for (const auto& [param, v] : ze.points) {
        glm::dvec3 bary(0.0);
        const double wk = t[k] == ze.lo ? 1.0 - param : param;
        bary[k] = wk;
        bary[k1] = 1.0 - wk;
        list.push_back({param, v, bary});
      }
    }
  }
  std::sort(list.begin(), list.end(), [](const Insert& x, const Insert& y) { return x.s < y.s; });
  return list;
}

// Re-triangulates every face that got a point: along its chord, in chord order. The sub-faces
// are planned here and written after the needle merges, which are checked against them.
std::vector<Refined> refine_faces(const FacetScan& scan, const TearContext& ctx, const Chords& chords,
                                  const std::vector<FaceId>& faces) {
  Map<std::uint32_t, std::size_t> plan_of(ctx.arena);
  for (std::size_t i = 0; i < chords.plans.size(); ++i) plan_of.emplace(chords.plans[i].f.index, i);
  std::vector<Refined> refined;
  for (FaceId f : faces) {
    const Triangle t = ctx.mesh.face(f);
    auto pit = plan_of.find(f.index);
    const FacePlan* plan = pit == plan_of.end() ? nullptr : &chords.plans[pit->second];
    const std::vector<Insert> list = points_of_face(scan, chords, t, plan);
    if (list.empty()) continue;
    Refined r{f, pit == plan_of.end() ? chords.plans.size() : pit->second, FaceRefinement(t), {}};
    for (const Insert& ins : list) {
      const VertexId got = r.local.insert(ins.v, ins.bary);
      if (got != ins.v) r.alias.emplace_back(ins.v.index, got);
    }
    refined.push_back(std::move(r));
  }
  return refined;
}

// The planned sub-faces as vertex triples (updated as crossings merge), and the ones at each
// vertex.
class PlannedFaces {
 public:
  PlannedFaces(const std::vector<Refined>& refined, std::pmr::memory_resource* arena) : at_(arena) {
    for (const Refined& r : refined) {
      const auto& pts = r.local.points();
      for (const auto& tri : r.local.triangles()) {
        const Triangle nt = {pts[tri[0]].v, pts[tri[1]].v, pts[tri[2]].v};
        for (VertexId v : nt) at_[v.index].push_back(static_cast<std::uint32_t>(faces_.size()));
        faces_.push_back(nt);
      }
    }
  }

  // Merging `hi` into `lo` may only drop the faces between them: every face it changes uses `lo`
  // afterwards, so the faces at the two vertices show any face it would make twice.
  bool merge_keeps_faces_apart(VertexId hi, VertexId lo) {
    std::vector<std::uint32_t> which = at_[lo.index];
    const auto& at_hi = at_[hi.index];
    which.insert(which.end(), at_hi.begin(), at_hi.end());
    std::sort(which.begin(), which.end());
    which.erase(std::unique(which.begin(), which.end()), which.end());
    return clashes(which, hi, lo) <= clashes(which, hi, hi);
  }

  // Merges `hi` into `lo`: records it in `merges` and renames it in the planned faces.
  void merge(VertexId hi, VertexId lo, NeedleMerges& merges) {
    merges.merge(hi, lo);
    auto it = at_.find(hi.index);
    if (it == at_.end()) return;
    for (std::uint32_t i : it->second) {
      for (VertexId& v : faces_[i])
        if (v == hi) v = lo;
      at_[lo.index].push_back(i);
    }
    at_.erase(hi.index);
  }

 private:
  // Faces made twice (in either orientation) and directed edges used twice among the planned
  // faces `which`, with `from` renamed `to` (faces that become degenerate are not made).
  std::size_t clashes(const std::vector<std::uint32_t>& which, VertexId from, VertexId to) const {
    std::vector<std::array<std::uint32_t, 3>> keys;
    std::vector<std::uint64_t> directed;
    for (std::uint32_t i : which) {
      Triangle t = faces_[i];
      for (VertexId& v : t)
        if (v == from) v = to;
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
      std::array<std::uint32_t, 3> k = {t[0].index, t[1].index, t[2].index};
      std::sort(k.begin(), k.end());
      keys.push_back(k);
      for (int j = 0; j < 3; ++j) directed.push_back((std::uint64_t(t[j].index) << 32) | t[(j + 1) % 3].index);
    }
    std::sort(keys.begin(), keys.end());
    std::sort(directed.begin(), directed.end());
    std::size_t n = 0;
    for (std::size_t i = 1; i < keys.size(); ++i) n += keys[i] == keys[i - 1];
    for (std::size_t i = 1; i < directed.size(); ++i) n += directed[i] == directed[i - 1];
    return n;
  }

  std::vector<Triangle> faces_;
  Map<std::uint32_t, std::vector<std::uint32_t>> at_;
};

// A face whose lone corner has two long edges to corners a hair apart (a needle: the lips of a
// narrow tear, a sliver) can have both crossings rounded to one bind position: they become one
// vertex, and the needle's tip (a zero-area triangle) is not made. Same rule as the cut. The
// tear also merges two crossings closer than its tolerance (posed) when the slit crosses the
// face without stopping in it: left apart, they bound a sliver a few float steps wide, which the
// opening (moving both along the blade's normal) would round to zero area. No merge may make a
// face twice (around a spike's tip, a three-face cone whose every edge the slit crosses, its
// other faces would become one triangle twice, reversed), nor may close merges chained through a
// speck of faces a few tolerances across collapse a whole slit into one vertex: such a merge is
// refused.
void merge_needles(const FacetScan& scan, const TearContext& ctx, const Chords& chords,
                   const std::vector<FaceId>& faces, PlannedFaces& planned, Slits& slits) {
  Set<std::uint32_t> stops(ctx.arena);  // faces the slit starts or ends in
  for (const FacePlan& plan : chords.plans)
    if (!plan.interior.empty()) stops.insert(plan.f.index);
  for (FaceId f : faces) {
    const Triangle& t = ctx.mesh.face(f);
    VertexId ends[3];
    glm::dvec3 at[3];
    int n = 0;
    for (int k = 0; k < 3; ++k) {
      const Crossing* cit = scan.find(t[k], t[(k + 1) % 3]);
      if (cit && cit->split) {
        at[n] = cit->p;
        ends[n++] = slits.resolve(cit->v);
      }
    }
    if (n != 2 || ends[0] == ends[1]) continue;
    const VertexId lo = std::min(ends[0], ends[1]), hi = std::max(ends[0], ends[1]);
    if (ctx.mesh.position(ends[0]) != ctx.mesh.position(ends[1]) &&
        (glm::length(at[1] - at[0]) > ctx.tol || stops.count(f.index)))
      continue;
    if (planned.merge_keeps_faces_apart(hi, lo)) planned.merge(hi, lo, slits.merges);
  }
}

// Edges torn by an earlier facet and split by this one stay torn in their parts; the crossings
// take their merged vertex.
void carry_torn_edges(FacetScan& scan, const Chords& chords, const SlitVertices& made, Slits& slits) {
  for (std::uint64_t key : made.split_keys) {
    Crossing& c = scan.at(key);
    c.v = slits.resolve(c.v);
    auto it = slits.torn.find(key);
    if (it != slits.torn.end()) {
      const std::size_t p = it->second;
      slits.torn.erase(it);
      slits.add_torn(c.lo, c.v, p);
      slits.add_torn(c.v, c.hi, p);
    }
  }
  for (std::uint64_t key : made.zero_keys) {
    const ZeroEdge& ze = chords.zero_edges.at(key);
    auto it = slits.torn.find(key);
    if (it != slits.torn.end() && !ze.points.empty()) {
      const std::size_t p = it->second;
      slits.torn.erase(it);
      VertexId prev = ze.lo;
      for (const auto& [s, v] : ze.points) {
        slits.add_torn(prev, v, p);
        prev = v;
      }
      slits.add_torn(prev, ze.hi, p);
    }
  }
}

// Records the torn parts of a chain of points along a chord (parameter, vertex), by `torn`.
void add_torn_chain(const std::vector<std::pair<double, VertexId>>& chain, const std::vector<Interval>& torn,
                    std::size_t facet_index, Slits& slits) {
  for (std::size_t i = 0; i + 1 < chain.size(); ++i)
    if (in_intervals(torn, 0.5 * (chain[i].first + chain[i + 1].first)))
      slits.add_torn(chain[i].second, chain[i + 1].second, facet_index);
}

// The torn pieces of a refined face's chord, from its ends and interior points.
void add_torn_chord(const FacetScan& scan, const FacePlan& plan, const Refined& r, std::size_t facet_index,
                    Slits& slits) {
  std::vector<std::pair<double, VertexId>> chain;
  auto resolve = [&](VertexId v) {
    for (const auto& [from, to] : r.alias)
      if (from == v.index) return slits.resolve(to);
    return slits.resolve(v);
  };
  if (plan.a.corner.valid())
    chain.emplace_back(0.0, plan.a.corner);
  else if (scan.at(plan.a.crossing).split)
    chain.emplace_back(0.0, scan.at(plan.a.crossing).v);
  for (std::size_t i = 0; i < plan.interior.size(); ++i) chain.emplace_back(plan.interior[i], resolve(plan.interior_ids[i]));
  if (plan.b.corner.valid())
    chain.emplace_back(1.0, plan.b.corner);
  else if (scan.at(plan.b.crossing).split)
    chain.emplace_back(1.0, scan.at(plan.b.crossing).v);
  add_torn_chain(chain, plan.torn, facet_index, slits);
}

// Writes the refined faces (without the needle tips whose crossings merged) and records the torn
// edges of the chords and of the in-plane edges.
void write_faces(const FacetScan& scan, TearContext& ctx, const Chords& chords, const SlitVertices& made,
                 const std::vector<Refined>& refined, const std::vector<FaceId>& faces, std::size_t facet_index,
                 Slits& slits) {
  for (const Refined& r : refined) {
    const FaceId f = r.f;
    ctx.editor.remove_face(f);
    const auto& pts = r.local.points();
    for (const auto& tri : r.local.triangles()) {
      const Triangle nt = {slits.resolve(pts[tri[0]].v), slits.resolve(pts[tri[1]].v), slits.resolve(pts[tri[2]].v)};
      if (nt[0] == nt[1] || nt[1] == nt[2] || nt[0] == nt[2]) continue;  // a needle's tip whose crossings merged
      const FaceId nf = ctx.editor.add_face_from(
          nt, f, {glm::vec3(pts[tri[0]].bary), glm::vec3(pts[tri[1]].bary), glm::vec3(pts[tri[2]].bary)});
      slits.region.push_back(nf);
    }
    if (r.plan < chords.plans.size()) add_torn_chord(scan, chords.plans[r.plan], r, facet_index, slits);
  }
  for (FaceId f : faces) slits.region.push_back(f);
  for (std::uint64_t key : made.zero_keys) {
    const ZeroEdge& ze = chords.zero_edges.at(key);
    std::vector<std::pair<double, VertexId>> chain = {{0.0, ze.lo}};
    chain.insert(chain.end(), ze.points.begin(), ze.points.end());
    chain.emplace_back(1.0, ze.hi);
    add_torn_chain(chain, ze.torn, facet_index, slits);
  }
}

}  // namespace

void insert_slit(TearContext& ctx, const SweepFacet& facet, std::size_t facet_index, Slits& slits) {
  FacetScan scan(ctx, facet);
  const std::vector<FaceId> faces = candidate_faces(ctx, facet);
  classify(scan, ctx, facet, faces);
  Chords chords(ctx.arena);
  plan_chords(scan, ctx, facet, faces, chords);
  const bool any_edge_torn = tear_in_plane_edges(scan, ctx, facet, chords);
  if (chords.plans.empty() && !any_edge_torn) return;  // this facet tears nothing: leave the mesh as it is
  const SlitVertices made = add_slit_vertices(scan, ctx, chords, slits);
  const std::vector<Refined> refined = refine_faces(scan, ctx, chords, faces);
  PlannedFaces planned(refined, ctx.arena);
  merge_needles(scan, ctx, chords, faces, planned, slits);
  carry_torn_edges(scan, chords, made, slits);
  write_faces(scan, ctx, chords, made, refined, faces, facet_index, slits);
}

}  // namespace deepcut::detail::tear
