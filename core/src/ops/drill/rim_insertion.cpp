// SPDX-License-Identifier: MIT
// Conforming insertion of the cylinder's rim: each candidate edge is intersected once with the
// solid cylinder (exact quadratic on the posed positions); crossings closer than the tolerance to
// an end snap to it, grazes are ignored, and every kept crossing becomes one shared vertex (no
// T-junctions). Each affected triangle is handled in its own plane, where the cylinder cuts an
// ellipse (clipped by the end planes): the rim inside the triangle is sampled where the fixed
// rulings (min_rim_edges equal angles around the axis) meet the plane, plus the ellipse's corners
// on the end planes. The kept parts of the triangle (one boundary run and one rim arc each, or
// the triangle with an elliptic hole) are triangulated and flipped to Delaunay in the plane;
// corners get barycentric coordinates of the parent (add_face_from).
#include "ops/drill/rim_insertion.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

#include "deepcut/core/parallel.h"
#include "geometry/predicates.h"
#include "ops/common/vertex_slots.h"
#include "ops/drill/rim_faces.h"
#include "uninit_vector.h"

namespace deepcut::drill {
namespace {

// Steiner points on crossed edges (see cross()) lie at least this many rim spacings outside.
constexpr double kSteinerClear = 0.3;
constexpr double kSteinerParentAngle = 10.0 * geometry::kPi / 180.0;
const double kCosSteinerParent = std::cos(kSteinerParentAngle);  // worked out once
// Fewest crossed candidates planned per parallel chunk (a few dozen crossed faces are worth a thread).
constexpr std::size_t kPlanGrain = 24;
// Fewest candidates judged (deep inside, clear of the cylinder, bad shape), and fewest edges
// crossed, per parallel chunk: a chunk of a few hundred thousand instructions is worth waking a
// thread for, so a hole of a few hundred faces runs them inline and only bigger ones spread.
constexpr std::size_t kJudgeGrain = 2048;
constexpr std::size_t kCrossGrain = 512;

// Runs the insertion: crossings and needle merges first (in candidate order, each edge split
// once), then every candidate's plan (rim_faces.h, in parallel), then the plans carried out in
// candidate order.
class RimInserter {
 public:
  RimInserter(MeshEditor& editor, const CylinderFrame& cyl, PosedOverlay& posed)
      : mesh_(editor.mesh()), editor_(editor), posed_(posed), cyl_(cyl) {
    eps_ = cyl_.eps;
    samples_ = cyl_.samples;
    first_new_ = posed_.first_new();
  }

  RimInsertion run(const std::vector<FaceId>& candidates, const std::vector<std::uint8_t>& deep_corners);

 private:
  void cross(EdgeCut& e, std::uint64_t key) const;
  void cross_edges();
  void make_edge_vertices();
  void merge_crossings(std::size_t c);
  std::size_t judge_faces(const std::vector<FaceId>& candidates,
                          const std::vector<std::uint8_t>& deep_corners);
  bool bad_shape(const glm::dvec3 corner[3]) const;
  void allow_steiner(const std::vector<FaceId>& candidates);
  void angle_corners(const std::vector<FaceId>& candidates);
  void plan_faces(const std::vector<FaceId>& candidates);
  void apply_plan(FaceId f, const FacePlan& plan, std::uint8_t deep_corners);
  unsigned emit_faces(FaceId f, const Triangle& tri, LocalPoint* pts, std::size_t points,
                      const geometry::LocalTri* tris, std::size_t count);
  VertexId vertex_of(const Triangle& tri, LocalPoint& lp);

  SurfaceMesh& mesh_;
  MeshEditor& editor_;
  PosedOverlay& posed_;
  const CylinderFrame& cyl_;
  double eps_ = 0.0;
  int samples_ = 32;
  std::uint32_t first_new_ = 0;
  // Edges met so far, sized for the candidates' edges up front (no allocation per edge).
  detail::CrossingTable<EdgeCut> edges_;
  // Per candidate: kDeep, all three corners deep inside (CylinderFrame::deep_inside), so the face
  // goes whole and none of its edges is crossed: it is removed without looking at its edges;
  // kClear, wholly outside the solid a tolerance clear of it (clear_of_cylinder), so none of its
  // edges is crossed and it is left as it is, without looking at its edges (an edge it shares
  // with a crossed face is filed by that face; its sides matter only to a crossed edge); kCut
  // otherwise, the only candidates with edge records, angles and plans.
  static constexpr std::uint8_t kCut = 0, kDeep = 1, kClear = 2;
  std::vector<std::uint8_t> kind_;
  // The candidates of kind kCut, in candidate order (the later stages walk these, not every
  // candidate: most of a hole's candidates lie deep inside).
  std::vector<std::uint32_t> cut_;
  // Per candidate of kind kCut: of bad shape for Steiner points (allow_steiner).
  std::vector<std::uint8_t> bad_;
  // Per candidate: its edges' records in edges_, looked up once by allow_steiner and read again
  // by merge_crossings and the planning without indexing the table, and its corners' angles
  // (angle_corners); sized without a fill (a candidate deep inside or clear of the cylinder leaves
  // its record unwritten).
  detail::UninitVector<CandidateFace> faces_;
  // Crossings that fell on one bind position (the two long edges of a needle crossed at the same
  // parameter): the later vertex maps to the earlier, so the needle's tip is not a zero-area face.
  detail::NeedleMerges merges_;
  // Per candidate of kind kCut (as cut_) its plan, and the chunks' points and triangles (the
  // calling thread's PlanChunk::reused lists).
  std::vector<FacePlan> plans_;
  std::vector<PlanChunk>* chunks_ = nullptr;
  // The removals and kept parts the plans say, made in one editor batch (candidate order).
  FaceBatch batch_;
  std::size_t crossings_ = 0, removed_ = 0, added_ = 0;
  std::vector<VertexId> bared_;  // RimInsertion::bared
};

// What the solid cylinder does to the edge of record `e` (edge key `key`): its crossings'
// parameters, which sub-segments lie inside, and the parameters of its Steiner points (their
// vertices are made by make_edge_vertices). Reads only old vertices' posed positions and the
// record's sides (final once allow_steiner has run), so every record is worked out in parallel
// (cross_edges).
void RimInserter::cross(EdgeCut& e, std::uint64_t key) const {
  e.lo = VertexId(static_cast<std::uint32_t>(key >> 32));
  e.hi = VertexId(static_cast<std::uint32_t>(key));
  const glm::dvec3 p = posed_(e.lo), q = posed_(e.hi);
  const double len = glm::length(q - p);
  // Parameter interval of the segment inside the closed solid cylinder.
  double t0 = 0.0, t1 = 1.0, tc = 0.5;
  const double sp = cyl_.s(p), ds = cyl_.s(q) - sp;
  if (std::abs(ds) > 0.0) {
    double ta = -sp / ds, tb = (cyl_.len - sp) / ds;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  } else if (sp < 0.0 || sp > cyl_.len) {
    t0 = 1.0;
    t1 = 0.0;
  }
  const glm::dvec3 mp = cyl_.perp(p), dm = cyl_.perp(q) - mp;
  const double aq = glm::dot(dm, dm), bq = glm::dot(mp, dm), cq = glm::dot(mp, mp) - cyl_.r * cyl_.r;
  if (aq > 1e-30 * (cyl_.r * cyl_.r)) {
    const double disc = bq * bq - aq * cq;
    if (disc < 0.0) {
      t0 = 1.0;
      t1 = 0.0;
    } else {
      const double sq = std::sqrt(disc);
      t0 = std::max(t0, (-bq - sq) / aq);
      t1 = std::min(t1, (-bq + sq) / aq);
      tc = -bq / aq;
    }
  } else if (cq > 0.0) {
    t0 = 1.0;
    t1 = 0.0;
  }
  if (!(t0 < t1)) return;
  // A graze (never deeper than the tolerance) does not cut the edge.
  const double tm = 0.5 * (t0 + t1);
  tc = std::clamp(tc, t0, t1);
  const double depth = -std::min(cyl_.sd(glm::mix(p, q, tm)), cyl_.sd(glm::mix(p, q, tc)));
  if (!(depth > eps_)) return;
  int n = 0;
  if (t0 * len > eps_) e.t[n++] = t0;
  if ((1.0 - t1) * len > eps_) e.t[n++] = t1;
  e.n = n;
  double bounds[4] = {0.0, 0.0, 0.0, 0.0};
  for (int i = 0; i < n; ++i) bounds[i + 1] = e.t[i];
  bounds[n + 1] = 1.0;
  for (int i = 0; i <= n; ++i) {
    const double mid = 0.5 * (bounds[i] + bounds[i + 1]);
    e.inside[i] = mid >= t0 && mid <= t1 ? 1 : 0;
  }
  // The kept parts of a crossed edge get points a rim spacing from each crossing, then 2, 4, ...
  // spacings (Ruppert's grading), up to a spacing before the far end: both faces on the edge are
  // processed (it is crossed), so both take them, and their kept parts meet the rim with boundary
  // points at its scale instead of fanning a far corner to close rim points or leaving rim
  // points near a long edge (needles the in-plane refinement cannot mend: its points would fall
  // outside the parent). Only points well outside the cylinder.
  const double spacing = cyl_.spacing;  // 2 r sin(pi / samples)
  const bool steiner = e.takes_steiner();
  for (int i = 0; i < n && steiner; ++i) {
    const double dir = e.inside[i + 1] ? -1.0 : 1.0;  // toward the kept part
    const double room = (dir > 0.0 ? 1.0 - e.t[i] : e.t[i]) * len;
    for (double step = spacing; step + spacing <= room; step *= 2.0) {
      const double t = e.t[i] + dir * step / len;
      if (cyl_.sd(glm::mix(p, q, t)) > kSteinerClear * spacing) e.steiner.emplace_back(t, VertexId());
    }
  }
}

// Every record's crossings worked out (cross), in parallel chunks.
void RimInserter::cross_edges() {
  const std::size_t n = edges_.size();
  parallel_for(n, grain_per_thread(n, kCrossGrain), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) cross(edges_[i], edges_.key(i));
  });
}

// The vertices of the crossed edges' crossings, then of their Steiner points (in the order cross
// found them, then sorted along the edge), edge by edge in the order the candidates ask for them
// (edge k of each candidate of kind kCut), made in one editor batch.
void RimInserter::make_edge_vertices() {
  std::vector<EdgeCut*> order;  // the records making vertices, in that order
  std::vector<std::uint32_t> ends;
  std::vector<float> ts;
  // Room for every record and two points on each (crossings and Steiner points), so the lists
  // of most holes do not grow.
  order.reserve(edges_.size());
  ends.reserve(4 * edges_.size());
  ts.reserve(2 * edges_.size());
  for (const std::uint32_t c : cut_) {
    for (EdgeCut* const ep : faces_[c].edges) {
      EdgeCut& e = *ep;
      if (e.resolved) continue;
      e.resolved = true;
      if (e.n == 0) continue;
      order.push_back(ep);
      auto on_edge = [&](double t) {
        ends.push_back(e.lo.index);
        ends.push_back(e.hi.index);
        ts.push_back(static_cast<float>(t));
      };
      for (int j = 0; j < e.n; ++j) on_edge(e.t[j]);
      for (const auto& st : e.steiner) on_edge(st.first);
    }
  }
  std::uint32_t next = editor_.add_vertices_on_edges(ends.data(), ts.data(), ts.size()).index;
  for (EdgeCut* const ep : order) {
    EdgeCut& e = *ep;
    const glm::dvec3 p = posed_(e.lo), q = posed_(e.hi);
    for (int j = 0; j < e.n; ++j) {
      e.v[j] = VertexId(next++);
      // The exact point on the cylinder; the bind vertex uses the same parameter, corrected
      // through its own (blended) skinning when the pose is not the bind pose.
      posed_.add(glm::mix(p, q, e.t[j]));
      posed_.place(editor_, e.v[j], posed_(e.v[j]));
      ++crossings_;
    }
    for (auto& [t, v] : e.steiner) {
      v = VertexId(next++);
      const glm::dvec3 x = glm::mix(p, q, t);
      posed_.add(x);
      posed_.place(editor_, v, x);
    }
    if (e.steiner.size() > 1)  // most crossed edges have none or one
      std::sort(e.steiner.begin(), e.steiner.end(),
                [](const auto& x, const auto& y) { return x.first < y.first; });
  }
}

// The vertex of a kept part's point: made inside triangle `tri` at its barycentric coordinates
// (and placed at its posed position, PosedOverlay::place) the first time it is asked for.
VertexId RimInserter::vertex_of(const Triangle& tri, LocalPoint& lp) {
  if (lp.v.valid()) return lp.v;
  lp.v = editor_.add_vertex_in_triangle(tri, glm::vec3(lp.bary));
  posed_.add(lp.p);
  posed_.place(editor_, lp.v, lp.p);
  return lp.v;
}

// Merges the crossings of a candidate's edges (made by make_edge_vertices). A face whose corner has
// two long edges to corners a hair apart (a needle: the lips of a narrow tear, a sliver) can have
// crossings of the two edges rounded to one bind position: they become one vertex, and the
// needle's tip, or the kept part at its far end when the circle crosses each edge twice (a
// triangle with two corners at one point), is not made. Same rule as the cut and the tear.
void RimInserter::merge_crossings(std::size_t c) {
  const std::array<EdgeCut*, 3>& es = faces_[c].edges;  // filed by allow_steiner
  for (int k = 0; k < 3; ++k) {
    const EdgeCut& ea = *es[k];            // corner k to corner k + 1
    const EdgeCut& eb = *es[(k + 2) % 3];  // corner k + 2 to corner k
    for (int i = 0; i < ea.n; ++i)
      for (int j = 0; j < eb.n; ++j) merges_.merge_if_coincident(mesh_, ea.v[i], eb.v[j]);
  }
}

// A corner of zero length or an angle under kSteinerParentAngle. The angle's acos is taken only
// where its cosine lies within 1e-9 of the bound's (acos is far more accurate than that margin,
// so the answer is acos's everywhere).
bool RimInserter::bad_shape(const glm::dvec3 corner[3]) const {
  // Side k from corner k to corner k + 1 (c - a is -(a - c) exactly: one length per side).
  double side[3];
  for (int k = 0; k < 3; ++k) side[k] = glm::length(corner[(k + 1) % 3] - corner[k]);
  bool bad = false;
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3 &a = corner[k], &b = corner[(k + 1) % 3], &c3 = corner[(k + 2) % 3];
    const double lb = side[k], lc = side[(k + 2) % 3];
    if (!(lb > 0.0 && lc > 0.0)) {
      bad = true;
      continue;
    }
    const double cosine = std::clamp(glm::dot(b - a, c3 - a) / (lb * lc), -1.0, 1.0);
    if (cosine < kCosSteinerParent - 1e-9) continue;
    if (cosine > kCosSteinerParent + 1e-9 || std::acos(cosine) < kSteinerParentAngle) bad = true;
  }
  return bad;
}

// Every candidate judged on its own (in parallel chunks): its kind (kind_; deep inside when all
// three of its `deep_corners` are) and, for one of kind kCut, whether it is of bad shape (bad_).
// Lists those of kind kCut in cut_ and returns their count.
std::size_t RimInserter::judge_faces(const std::vector<FaceId>& candidates,
                                     const std::vector<std::uint8_t>& deep_corners) {
  const std::size_t n = candidates.size();
  kind_.assign(n, kCut);
  bad_.assign(n, 0);
  parallel_for(n, grain_per_thread(n, kJudgeGrain), [&](std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c) {
      if (deep_corners[c] == 7) {
        kind_[c] = kDeep;
        continue;
      }
      const Triangle& t = mesh_.face(candidates[c]);
      const glm::dvec3 corner[3] = {posed_(t[0]), posed_(t[1]), posed_(t[2])};
      // A face with a corner deep inside is not clear of the cylinder (not tested again).
      if (deep_corners[c] == 0 && clear_of_cylinder(cyl_, corner))
        kind_[c] = kClear;
      else
        bad_[c] = bad_shape(corner) ? 1 : 0;
    }
  });
  cut_.clear();
  for (std::size_t c = 0; c < n; ++c)
    if (kind_[c] == kCut) cut_.push_back(static_cast<std::uint32_t>(c));
  return cut_.size();
}

// Steiner points (see cross()) go only on edges between two candidates of good shape (smallest
// angle 10 degrees or more), one on each side: not on the mesh's border or a non-manifold edge,
// where a point off the cylinder could end up on the hole's boundary, and not on a needle's long
// edges, whose points at one parameter would round to one bind position (zero-area faces).
void RimInserter::allow_steiner(const std::vector<FaceId>& candidates) {
  // Each candidate's half-edges file its edge's record (made here, in the order
  // make_edge_vertices asks for them; the candidate keeps it in faces_): weight 1 for
  // lo -> hi, 16 for hi -> lo, and whether the face is of bad shape. Faces deep inside or clear
  // of the cylinder hold no crossed edge, the only ones asked about.
  for (const std::uint32_t c : cut_) {
    const Triangle& t = mesh_.face(candidates[c]);
    const bool bad = bad_[c] != 0;
    for (int k = 0; k < 3; ++k) {
      const VertexId a = t[k], b = t[(k + 1) % 3];
      EdgeCut* const e = edges_.try_emplace(a, b).first;
      e->file_side(a, b, bad);
      faces_[c].edges[k] = e;
    }
  }
}

// The corners' angles around the axis of every candidate with a piece of an edge inside (those
// sample the rim in their plane), each vertex's worked out once: the faces around a vertex on
// the rim share it.
void RimInserter::angle_corners(const std::vector<FaceId>& candidates) {
  detail::VertexSlots& seen = detail::VertexSlots::scratch();  // vertex -> 3 c + k, its first
  seen.reset(mesh_.vertex_count());
  for (const std::uint32_t c : cut_) {
    CandidateFace& face = faces_[c];
    face.angled = any_piece_inside(face);
    if (!face.angled) continue;
    const Triangle& t = mesh_.face(candidates[c]);
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t first = seen.get(t[k].index);
      if (first != detail::VertexSlots::kNone) {
        face.angle[k] = faces_[first / 3].angle[first % 3];
        continue;
      }
      face.angle[k] = cyl_.window_theta(posed_(t[k]));
      seen.set(t[k].index, 3 * c + static_cast<std::uint32_t>(k));
    }
  }
}

// New vertices for the part's points that have none (in order), then its faces, but a merged
// tip's. Returns which corners of `tri` those faces use (bit k for corner k).
unsigned RimInserter::emit_faces(FaceId f, const Triangle& tri, LocalPoint* pts, std::size_t points,
                                 const geometry::LocalTri* tris, std::size_t count) {
  for (std::size_t i = 0; i < points; ++i) vertex_of(tri, pts[i]);
  unsigned used = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const geometry::LocalTri& t = tris[i];
    if (pts[t[0]].v == pts[t[1]].v || pts[t[1]].v == pts[t[2]].v || pts[t[0]].v == pts[t[2]].v)
      continue;  // merged tip
    batch_.add_from({pts[t[0]].v, pts[t[1]].v, pts[t[2]].v}, f,
                    {glm::vec3(pts[t[0]].bary), glm::vec3(pts[t[1]].bary), glm::vec3(pts[t[2]].bary)});
    ++added_;
    for (int j = 0; j < 3; ++j) {
      const VertexId w = pts[t[j]].v;
      if (w.index < first_new_)
        used |= unsigned(w == tri[0]) | unsigned(w == tri[1]) << 1 | unsigned(w == tri[2]) << 2;
    }
  }
  return used;
}

// Every candidate of kind kCut (neither deep inside nor clear of the cylinder) gets its plan, in
// parallel chunks: a plan reads only the mesh, the posed positions and the crossings made before,
// so it is the same whatever the chunks or the thread count.
void RimInserter::plan_faces(const std::vector<FaceId>& candidates) {
  RimShared shared{mesh_, posed_, cyl_, merges_, faces_.data()};
  shared.eps = eps_;
  shared.samples = samples_;
  shared.sep = 0.3 * 2.0 * cyl_.r * std::sin(geometry::kPi / samples_);
  // A rim sample is kept only inside a triangle or within half a percent of r of it.
  shared.ruling_reach = ruling_reach_angle(cyl_, kWindowReach * cyl_.r + 2.0 * eps_);
  shared.ruling_base.reserve(static_cast<std::size_t>(samples_));
  for (int k = 0; k < samples_; ++k)
    shared.ruling_base.push_back(cyl_.a + cyl_.r * cyl_.ruling(2.0 * geometry::kPi * k / samples_));
  const std::size_t n = cut_.size();
  plans_.assign(n, FacePlan());
  // About four chunks per thread (each chunk's lists grow from empty); where chunks start
  // changes only where plans are stored.
  const std::size_t grain = std::max(kPlanGrain, (n + 4 * thread_count() - 1) / (4 * thread_count()));
  chunks_ = &PlanChunk::reused((n + grain - 1) / grain);
  parallel_for(n, grain, [&](std::size_t begin, std::size_t end) {
    const auto chunk = static_cast<std::uint32_t>(begin / grain);
    FacePlanner planner(shared, (*chunks_)[chunk], chunk);
    for (std::size_t i = begin; i < end; ++i) planner.plan(cut_[i], candidates[cut_[i]], plans_[i]);
  });
}

// Removes the candidate and adds its kept parts, as its plan says; a removed candidate's corners
// that none of its kept parts' faces use are bared (RimInsertion::bared) unless they lie deep
// inside (bit k of `deep_corners` for corner k).
void RimInserter::apply_plan(FaceId f, const FacePlan& plan, std::uint8_t deep_corners) {
  if (!plan.remove) return;  // left as it is (a plan with kept parts removes the candidate)
  batch_.remove(f);
  ++removed_;
  const Triangle tri = mesh_.face(f);
  unsigned kept = 0;  // bit k: a face added for the candidate uses corner k
  PlanChunk& chunk = (*chunks_)[plan.chunk];
  for (std::uint32_t i = plan.first_poly; i < plan.first_poly + plan.polys; ++i) {
    const PolygonPlan& poly = chunk.polys[i];
    kept |= emit_faces(f, tri, chunk.pts.data() + poly.first_pt, poly.pts, chunk.tris.data() + poly.first_tri,
                       poly.tris);
  }
  for (int k = 0; k < 3; ++k)
    if (!((kept | deep_corners) >> k & 1u)) bared_.push_back(tri[k]);
}

RimInsertion RimInserter::run(const std::vector<FaceId>& candidates,
                              const std::vector<std::uint8_t>& deep_corners) {
  const std::size_t shallow = judge_faces(candidates, deep_corners);
  // Every edge looked up is a candidate's of kind kCut: about two per such face (most of their
  // edges are shared by two of them); the table grows when a hole needs more.
  edges_.reserve(2 * shallow + 16);
  faces_.resize(candidates.size());
  allow_steiner(candidates);
  cross_edges();
  angle_corners(candidates);
  make_edge_vertices();
  for (const std::uint32_t c : cut_) merge_crossings(c);
  plan_faces(candidates);
  std::size_t planned_tris = 0;  // every face the plans can add (a merged tip's is not)
  bool gaps = false;
  for (const PlanChunk& chunk : *chunks_) {
    planned_tris += chunk.tris.size();
    gaps = gaps || chunk.gaps;
  }
  batch_.reserve(planned_tris, candidates.size());
  std::size_t next_cut = 0;  // plans_ follows cut_, in candidate order
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    if (kind_[c] == kClear) continue;  // left as it is
    if (kind_[c] == kCut) {
      apply_plan(candidates[c], plans_[next_cut++], deep_corners[c]);
      continue;
    }
    batch_.remove(candidates[c]);  // what the plan of a face inside says
    ++removed_;
  }
  assert(next_cut == plans_.size());  // every plan carried out, each for its own face
  editor_.apply(batch_);
  PlanChunk::give_back_big(*chunks_);  // a big drill's plans do not stay with the thread
  RimInsertion out;
  out.crossings = crossings_;
  out.removed = removed_;
  out.added = added_;
  out.bared = std::move(bared_);
  out.merged = !merges_.empty();
  out.gaps = gaps;
  return out;
}

}  // namespace

RimInsertion insert_rim(MeshEditor& editor, const CylinderFrame& cyl, PosedOverlay& posed,
                        const std::vector<FaceId>& candidates,
                        const std::vector<std::uint8_t>& deep_corners) {
  assert(deep_corners.size() == candidates.size());  // one per candidate, indexed as the candidates
  RimInserter inserter(editor, cyl, posed);
  return inserter.run(candidates, deep_corners);
}

}  // namespace deepcut::drill
