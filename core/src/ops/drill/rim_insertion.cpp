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
#include <cmath>

#include "geometry/delaunay_flip.h"
#include "geometry/polygon_triangulation.h"
#include "geometry/predicates.h"
#include "ops/common/vertex_slots.h"

namespace deepcut::drill {
namespace {

// Steiner points on crossed edges (see edge()) lie at least this many rim spacings outside.
constexpr double kSteinerClear = 0.3;
constexpr double kSteinerParentAngle = 10.0 * geometry::kPi / 180.0;

// What the solid cylinder does to one mesh edge, from `lo` to `hi` (lo < hi).
struct EdgeCut {
  VertexId lo, hi;
  int n = 0;                           // kept crossings
  double t[2] = {0.0, 0.0};            // their parameters, increasing
  VertexId v[2];                       // their vertices
  std::uint8_t inside[3] = {0, 0, 0};  // sub-segments between 0, t[0..n-1], 1
  // Points on the kept parts of a crossed edge, graded away from the crossings (see edge()):
  // parameters, increasing, and their vertices.
  std::vector<std::pair<double, VertexId>> steiner;
};

// A point on the boundary of a triangle's kept region, or on its rim.
struct LocalPoint {
  VertexId v;           // invalid until a rim sample is created
  glm::dvec3 p;         // posed
  glm::dvec3 bary;      // w.r.t. the parent triangle's corners
  glm::dvec2 q;         // in the triangle's plane frame
  double phi = 0.0;     // rim samples: angle around the ellipse centre (normalised frame)
  bool on_rim = false;  // lies on the cylinder's boundary
};

// The triangle being processed, in its plane: the cylinder's cut there, the corners, and
// barycentric coordinates and distances from the edges of plane points.
struct FacePlane {
  PlaneCut pc;
  glm::dvec3 corner[3];  // posed
  glm::dvec2 tq[3];
  double area2 = 1.0;
  double height[3] = {0.0, 0.0, 0.0};  // distance of a plane point from edge k = bary[k] * height[k]

  glm::dvec3 bary_of(const glm::dvec2& q) const {
    return glm::dvec3(geometry::orient(q, tq[1], tq[2]), geometry::orient(tq[0], q, tq[2]),
                      geometry::orient(tq[0], tq[1], q)) /
           area2;
  }
  // Distance of a plane point inside the triangle from its nearest edge (negative outside).
  double clearance(const glm::dvec2& q) const {
    const glm::dvec3 b = bary_of(q);
    return std::min({b.x * height[0], b.y * height[1], b.z * height[2]});
  }
};

class RimInserter {
 public:
  RimInserter(MeshEditor& editor, const CylinderFrame& cyl, PosedOverlay& posed)
      : mesh_(editor.mesh()), editor_(editor), posed_(posed), cyl_(cyl) {
    eps_ = cyl_.eps;
    samples_ = cyl_.samples;
    sep_ = 0.3 * 2.0 * cyl_.r * std::sin(geometry::kPi / samples_);
    // consider() keeps only points inside a triangle or within half a percent of r of it.
    ruling_reach_ = ruling_reach_angle(cyl_, 0.02 * cyl_.r + 2.0 * eps_);
    first_new_ = posed_.first_new();
    for (int k = 0; k < samples_; ++k)
      ruling_base_.push_back(cyl_.a + cyl_.r * cyl_.ruling(2.0 * geometry::kPi * k / samples_));
  }

  RimInsertion run(const std::vector<FaceId>& candidates);

 private:
  const EdgeCut& edge(VertexId a, VertexId b);
  void merge_crossings(std::size_t c, FaceId f);
  void allow_steiner(const std::vector<FaceId>& candidates);
  bool deep(const Triangle& t, detail::VertexSlots& judged) const;
  VertexId merged(VertexId v) const { return merges_.merged(v); }
  void process_face(std::size_t c, FaceId f);
  void face_boundary(const Triangle& tri, const glm::dvec3 corner[3]);
  void sample_rim();
  void consider(const glm::dvec3& x, bool corner_point);
  void end_corner(double a_cap, double hh, double sign);
  void emit_kept_parts(FaceId f, const Triangle& tri);
  void emit_polygon(FaceId f, const Triangle& tri, std::vector<LocalPoint>& pts,
                    const std::vector<std::uint32_t>& outer, const std::vector<std::vector<std::uint32_t>>& holes);
  void emit_faces(FaceId f, const Triangle& tri, std::vector<LocalPoint>& pts,
                  const std::vector<geometry::LocalTri>& tris);
  VertexId vertex_of(const Triangle& tri, LocalPoint& lp);
  void refine(geometry::FlipTriangulation& ft, std::vector<glm::dvec2>& q, std::vector<LocalPoint>& pts,
              const std::vector<std::uint32_t>& outer, const std::vector<std::vector<std::uint32_t>>& holes);

  SurfaceMesh& mesh_;
  MeshEditor& editor_;
  PosedOverlay& posed_;
  const CylinderFrame& cyl_;
  double eps_ = 0.0, sep_ = 0.0, ruling_reach_ = -1.0;
  int samples_ = 32;
  std::uint32_t first_new_ = 0;
  std::vector<glm::dvec3> ruling_base_;  // where each sampled ruling starts (s = 0)
  // Edges met so far, sized for the candidates' edges up front (no allocation per edge).
  detail::CrossingTable<EdgeCut> edges_;
  std::vector<std::uint64_t> steiner_edges_;  // edge keys that may take Steiner points, sorted (allow_steiner)
  // Per candidate: all three corners deep inside (CylinderFrame::deep_inside), so the face goes
  // whole and none of its edges is crossed: it is removed without looking at its edges.
  std::vector<std::uint8_t> deep_;
  // Per candidate: its edges' records (edge k from corner k to corner k + 1), looked up once by
  // merge_crossings and read again by process_face (CrossingTable records never move).
  std::vector<std::array<const EdgeCut*, 3>> face_edges_;
  const std::array<const EdgeCut*, 3>* cur_edges_ = nullptr;  // the face being processed
  // Crossings that fell on one bind position (the two long edges of a needle crossed at the same
  // parameter): the later vertex maps to the earlier, so the needle's tip is not a zero-area face.
  detail::NeedleMerges merges_;
  std::size_t crossings_ = 0, removed_ = 0, added_ = 0;
  FacePlane face_;  // the triangle being processed
  // process_face's working lists, kept between faces so their memory is reused: the triangle's
  // boundary (corners and crossings in order, with the state of each segment) and its rim samples.
  std::vector<LocalPoint> pts_, rim_, all_scratch_, poly_scratch_;
  std::vector<std::uint8_t> seg_inside_, used_scratch_;
  // emit_kept_parts' and emit_polygon's working lists, reused the same way.
  std::vector<std::pair<double, std::size_t>> arc_scratch_;
  std::vector<std::uint32_t> loop_scratch_;
  const std::vector<std::vector<std::uint32_t>> no_holes_;
  std::vector<glm::dvec2> q_scratch_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> segments_scratch_;
  std::vector<geometry::LocalTri> clipped_scratch_, failed_scratch_;
  geometry::FlipTriangulation flips_;
};

const EdgeCut& RimInserter::edge(VertexId a, VertexId b) {
  const auto key = edge_key(a, b);
  const auto [record, made] = edges_.try_emplace(a, b);
  if (!made) return *record;
  EdgeCut& e = *record;
  e.lo = a < b ? a : b;
  e.hi = a < b ? b : a;
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
  if (t0 < t1) {
    // A graze (never deeper than the tolerance) does not cut the edge.
    const double tm = 0.5 * (t0 + t1);
    tc = std::clamp(tc, t0, t1);
    const double depth = -std::min(cyl_.sd(glm::mix(p, q, tm)), cyl_.sd(glm::mix(p, q, tc)));
    if (depth > eps_) {
      double cuts[2];
      int n = 0;
      if (t0 * len > eps_) cuts[n++] = t0;
      if ((1.0 - t1) * len > eps_) cuts[n++] = t1;
      e.n = n;
      double bounds[4] = {0.0, 0.0, 0.0, 0.0};
      for (int i = 0; i < n; ++i) bounds[i + 1] = cuts[i];
      bounds[n + 1] = 1.0;
      for (int i = 0; i <= n; ++i) {
        const double mid = 0.5 * (bounds[i] + bounds[i + 1]);
        e.inside[i] = mid >= t0 && mid <= t1 ? 1 : 0;
      }
      for (int i = 0; i < n; ++i) {
        e.t[i] = cuts[i];
        e.v[i] = editor_.add_vertex_on_edge(e.lo, e.hi, static_cast<float>(cuts[i]));
        // The exact point on the cylinder; the bind vertex uses the same parameter, corrected
        // through its own (blended) skinning when the pose is not the bind pose.
        posed_.add(glm::mix(p, q, cuts[i]));
        posed_.place(editor_, e.v[i], posed_(e.v[i]));
        ++crossings_;
      }
      // The kept parts of a crossed edge get points a rim spacing from each crossing, then 2,
      // 4, ... spacings (Ruppert's grading), up to a spacing before the far end: both faces on
      // the edge are processed (it is crossed), so both take them, and their kept parts meet
      // the rim with boundary points at its scale instead of fanning a far corner to close rim
      // points or leaving rim points near a long edge (needles the in-plane refinement cannot
      // mend: its points would fall outside the parent). Only points well outside the cylinder.
      const double spacing = 2.0 * cyl_.r * std::sin(geometry::kPi / samples_);
      const bool steiner = std::binary_search(steiner_edges_.begin(), steiner_edges_.end(), key);
      for (int i = 0; i < n && steiner; ++i) {
        const double dir = e.inside[i + 1] ? -1.0 : 1.0;  // toward the kept part
        const double room = (dir > 0.0 ? 1.0 - cuts[i] : cuts[i]) * len;
        for (double step = spacing; step + spacing <= room; step *= 2.0) {
          const double t = cuts[i] + dir * step / len;
          const glm::dvec3 x = glm::mix(p, q, t);
          if (!(cyl_.sd(x) > kSteinerClear * spacing)) continue;
          const VertexId v = editor_.add_vertex_on_edge(e.lo, e.hi, static_cast<float>(t));
          posed_.add(x);
          posed_.place(editor_, v, x);
          e.steiner.emplace_back(t, v);
        }
      }
      std::sort(e.steiner.begin(), e.steiner.end(),
                [](const auto& x, const auto& y) { return x.first < y.first; });
    }
  }
  return e;
}

// Skinning is not linear in the blended weights, so a new vertex interpolated in bind space
VertexId RimInserter::vertex_of(const Triangle& tri, LocalPoint& lp) {
  if (lp.v.valid()) return lp.v;
  lp.v = editor_.add_vertex_in_triangle(tri, glm::vec3(lp.bary));
  posed_.add(lp.p);
  posed_.place(editor_, lp.v, lp.p);
  return lp.v;
}

// Crosses a candidate's edges (in the order process_face asks for them). A face whose corner has
// two long edges to corners a hair apart (a needle: the lips of a narrow tear, a sliver) can have
// crossings of the two edges rounded to one bind position: they become one vertex, and the
// needle's tip, or the kept part at its far end when the circle crosses each edge twice (a
// triangle with two corners at one point), is not made. Same rule as the cut and the tear.
void RimInserter::merge_crossings(std::size_t c, FaceId f) {
  const Triangle tri = mesh_.face(f);
  std::array<const EdgeCut*, 3>& es = face_edges_[c];
  for (int k = 0; k < 3; ++k) es[k] = &edge(tri[k], tri[(k + 1) % 3]);  // records never move
  for (int k = 0; k < 3; ++k) {
    const EdgeCut& ea = *es[k];            // corner k to corner k + 1
    const EdgeCut& eb = *es[(k + 2) % 3];  // corner k + 2 to corner k
    for (int i = 0; i < ea.n; ++i)
      for (int j = 0; j < eb.n; ++j) merges_.merge_if_coincident(mesh_, ea.v[i], eb.v[j]);
  }
}

// Steiner points (see edge()) go only on edges between two candidates of good shape (smallest
// angle 10 degrees or more), one on each side: not on the mesh's border or a non-manifold edge,
// where a point off the cylinder could end up on the hole's boundary, and not on a needle's long
// edges, whose points at one parameter would round to one bind position (zero-area faces).
void RimInserter::allow_steiner(const std::vector<FaceId>& candidates) {
  steiner_edges_.clear();
  // The candidates' half-edges by edge: weight 1 for lo -> hi, 16 for hi -> lo, and whether the
  // face is of bad shape. Faces deep inside hold no crossed edge, the only ones asked about.
  struct HalfEdge {
    std::uint64_t key;
    std::uint8_t weight, bad;
    bool operator<(const HalfEdge& o) const { return key < o.key; }
  };
  std::vector<HalfEdge> halves;
  halves.reserve(3 * candidates.size());
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    if (deep_[c]) continue;
    const Triangle& t = mesh_.face(candidates[c]);
    double smallest = kInf;
    const glm::dvec3 corner[3] = {posed_(t[0]), posed_(t[1]), posed_(t[2])};
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 &a = corner[k], &b = corner[(k + 1) % 3], &c3 = corner[(k + 2) % 3];
      const double lb = glm::length(b - a), lc = glm::length(c3 - a);
      smallest =
          lb > 0.0 && lc > 0.0
              ? std::min(smallest, std::acos(std::clamp(glm::dot(b - a, c3 - a) / (lb * lc), -1.0, 1.0)))
              : 0.0;
    }
    const std::uint8_t bad = smallest >= kSteinerParentAngle ? 0 : 1;
    for (int k = 0; k < 3; ++k) {
      const VertexId a = t[k], b = t[(k + 1) % 3];
      halves.push_back({edge_key(a, b), static_cast<std::uint8_t>(a < b ? 1 : 16), bad});
    }
  }
  std::sort(halves.begin(), halves.end());
  // One face on each side (1 + 16), neither of bad shape.
  for (std::size_t i = 0, j = 0; i < halves.size(); i = j) {
    int count = 0;
    bool bad = false;
    for (j = i; j < halves.size() && halves[j].key == halves[i].key; ++j) {
      count += halves[j].weight;
      bad |= halves[j].bad != 0;
    }
    if (count == 17 && !bad) steiner_edges_.push_back(halves[i].key);
  }
}

void RimInserter::process_face(std::size_t c, FaceId f) {
  const Triangle tri = mesh_.face(f);
  cur_edges_ = &face_edges_[c];
  const glm::dvec3 corner[3] = {posed_(tri[0]), posed_(tri[1]), posed_(tri[2])};
  face_boundary(tri, corner);
  std::vector<LocalPoint>& pts = pts_;
  const std::vector<std::uint8_t>& seg_inside = seg_inside_;
  const std::size_t m = pts.size();
  bool any_inside = false, all_inside = true;
  for (auto s : seg_inside) {
    any_inside |= s != 0;
    all_inside &= s != 0;
  }
  for (std::size_t i = 0; i < m; ++i)
    if (seg_inside[i] || seg_inside[(i + m - 1) % m] || std::abs(cyl_.sd(pts[i].p)) <= eps_)
      pts[i].on_rim = true;
  if (all_inside) {
    editor_.remove_face(f);
    ++removed_;
    return;
  }
  const PlaneCut pc = plane_cut(cyl_, corner);
  if (pc.empty) {
    if (any_inside) {  // a degenerate triangle or a plane the cylinder only touches
      editor_.remove_face(f);
      ++removed_;
    }
    return;
  }
  glm::dvec2 tq[3];
  for (int k = 0; k < 3; ++k) tq[k] = pc.coords(corner[k]);
  const double area2 = geometry::orient(tq[0], tq[1], tq[2]);
  if (!(area2 > 0.0)) {
    if (any_inside) {
      editor_.remove_face(f);
      ++removed_;
    }
    return;
  }
  face_.pc = pc;
  for (int k = 0; k < 3; ++k) face_.tq[k] = tq[k], face_.corner[k] = corner[k];
  face_.area2 = area2;
  if (!any_inside) {
    // Only a hole wholly inside the triangle can be left: its centre must lie inside.
    const glm::dvec3 cb = face_.bary_of({pc.ac, pc.b0});
    if (cb.x <= 0.0 || cb.y <= 0.0 || cb.z <= 0.0) return;
  }
  for (auto& lp : pts) lp.q = pc.coords(lp.p);
  // Distance of a plane point from each edge is its barycentric coordinate times the height.
  for (int k = 0; k < 3; ++k)
    face_.height[k] = area2 / std::max(glm::length(tq[(k + 2) % 3] - tq[(k + 1) % 3]), 1e-300);
  sample_rim();
  std::vector<LocalPoint>& rim = rim_;
  if (!any_inside) {
    if (rim.size() < 3) return;
    // Triangle with an elliptic hole: the hole runs clockwise (decreasing phi).
    std::sort(rim.begin(), rim.end(), [](const LocalPoint& x, const LocalPoint& y) { return x.phi > y.phi; });
    std::vector<LocalPoint>& all = all_scratch_;
    all.assign(pts.begin(), pts.begin() + 3);
    std::vector<std::uint32_t> outer = {0, 1, 2}, hole;
    for (auto& lp : rim) {
      hole.push_back(static_cast<std::uint32_t>(all.size()));
      all.push_back(lp);
    }
    editor_.remove_face(f);
    ++removed_;
    emit_polygon(f, tri, all, outer, {hole});
    return;
  }
  emit_kept_parts(f, tri);
}

// The triangle's boundary: corners, crossings and Steiner points in order (pts_), with the
// state of each segment (seg_inside_).
void RimInserter::face_boundary(const Triangle& tri, const glm::dvec3 corner[3]) {
  std::vector<LocalPoint>& pts = pts_;
  std::vector<std::uint8_t>& seg_inside = seg_inside_;
  pts.clear();
  seg_inside.clear();
  for (int k = 0; k < 3; ++k) {
    const int k1 = (k + 1) % 3;
    const EdgeCut& e = *(*cur_edges_)[k];
    LocalPoint c;
    c.v = tri[k];
    c.p = corner[k];
    c.bary = glm::dvec3(0.0);
    c.bary[k] = 1.0;
    pts.push_back(c);
    const bool forward = tri[k] == e.lo;
    seg_inside.push_back(e.inside[forward ? 0 : e.n]);
    // Crossings and Steiner points in order from corner k to corner k1 (parameters from lo).
    std::size_t si = 0;
    const std::size_t ns = e.steiner.size();
    for (int i = 0; i < e.n;) {
      const int j = forward ? i : e.n - 1 - i;
      const double tc = e.t[j];
      const bool steiner_first =
          si < ns && (forward ? e.steiner[si].first < tc : e.steiner[ns - 1 - si].first > tc);
      const double tl = steiner_first ? e.steiner[forward ? si : ns - 1 - si].first : tc;
      const double t = forward ? tl : 1.0 - tl;  // from corner k to corner k1
      const VertexId sv = steiner_first ? e.steiner[forward ? si : ns - 1 - si].second : e.v[j];
      LocalPoint x;
      x.v = steiner_first ? sv : merged(sv);
      x.p = posed_(sv);
      x.bary = glm::dvec3(0.0);
      x.bary[k] = 1.0 - t;
      x.bary[k1] = t;
      x.on_rim = !steiner_first;
      pts.push_back(x);
      if (steiner_first) {
        seg_inside.push_back(seg_inside.back());
        ++si;
      } else {
        seg_inside.push_back(e.inside[forward ? i + 1 : e.n - 1 - i]);
        ++i;
      }
    }
    for (; si < ns; ++si) {
      const auto& [tl, sv] = e.steiner[forward ? si : ns - 1 - si];
      const double t = forward ? tl : 1.0 - tl;
      LocalPoint x;
      x.v = sv;
      x.p = posed_(sv);
      x.bary = glm::dvec3(0.0);
      x.bary[k] = 1.0 - t;
      x.bary[k1] = t;
      pts.push_back(x);
      seg_inside.push_back(seg_inside.back());
    }
  }
}

// A rim sample at `x` (a ruling's point in the triangle's plane, or a corner of the rim on an
// end plane) joins rim_ unless it falls outside the triangle or next to a boundary or rim point.
void RimInserter::consider(const glm::dvec3& x, bool corner_point) {
  LocalPoint lp;
  lp.p = x;
  lp.q = face_.pc.coords(x);
  lp.bary = face_.bary_of(lp.q);
  int low = -1, lows = 0;
  for (int k = 0; k < 3; ++k)
    if (lp.bary[k] < 1e-7) low = k, ++lows;
  if (lows > 0) {
    // A ruling's point just beyond an edge the cylinder only grazes (too shallowly to be cut):
    // the rim bulges over that edge by about the tolerance, and no neighbour takes the point
    // (at a crease the ruling meets its plane beyond the edge too, and no rim crosses an uncut
    // edge). Dropped, the hole would lose a rim edge (31 of 32 around the axis); it is
    // moved inside, a tolerance from the edge, when that moves it and keeps it within half a
    // percent of r (not on holes smaller than the absolute tolerance: the move would round
    // away in float and leave zero-area faces).
    if (corner_point || lows > 1) return;
    const int k1 = (low + 1) % 3, k2 = (low + 2) % 3;
    const double shift = eps_ - lp.bary[low] * face_.height[low], bound = 0.005 * cyl_.r;
    if (shift > bound || (*cur_edges_)[k1]->n != 0) return;
    const glm::dvec2 along = glm::normalize(face_.tq[k2] - face_.tq[k1]);
    lp.q += shift * glm::dvec2(-along.y, along.x);  // inside is on the left
    lp.bary = face_.bary_of(lp.q);
    lp.p = face_.pc.point(lp.q.x, lp.q.y);
    for (int k = 0; k < 3; ++k)
      if (lp.bary[k] < 1e-7) return;
    if (std::abs(cyl_.sd(lp.p)) > bound) return;
  }
  // An end-plane corner gives way only to a rim point a hair away: without it the chord from
  // the end-plane part to the side part of a D-shaped rim cuts the corner off, as deep as
  // the gap (a triangle of kept surface with its centroid inside the cylinder).
  const double gap = corner_point ? 2.0 * eps_ : sep_;
  for (const auto& b : pts_)
    if (b.on_rim && glm::length(b.p - lp.p) < gap) return;
  if (!corner_point)
    for (const auto& other : rim_)
      if (glm::length(other.p - lp.p) < sep_) return;
  lp.phi = face_.pc.phi(lp.q);
  lp.on_rim = true;
  rim_.push_back(lp);
}

// The corner where the rim's straight part (on an end plane) meets its arc. One lying just
// outside the triangle (within a rim spacing: an edge grazes the hole there, too shallowly to
// be cut, or cuts off the corner alone) still bends the rim inside: the rim then gets the
// first points of both parts 2 tolerances inside, or the chord between the two parts'
// crossings cuts the corner off (kept surface up to a few % of r inside the cylinder).
void RimInserter::end_corner(double a_cap, double hh, double sign) {
  const PlaneCut& pc = face_.pc;
  const glm::dvec2 qc(a_cap, pc.b0 + sign * hh);
  const double out = -face_.clearance(qc);
  if (out <= 0.0 || out > sep_) {
    consider(pc.point(qc.x, qc.y), true);
    return;
  }
  const double margin = 2.0 * eps_, toward = pc.ac > a_cap ? 1.0 : -1.0;
  for (int part = 0; part < 2; ++part)
    for (double t = margin; t < hh; t *= 2.0) {
      glm::dvec2 q(a_cap, pc.b0 + sign * (hh - t));  // along the end plane's line
      if (part == 1) {                               // along the arc
        q.x = a_cap + toward * t;
        const double e = pc.parallel ? 0.0 : (q.x - pc.a0) / pc.ra;
        if (std::abs(e) >= 1.0) break;
        q.y = pc.b0 + sign * pc.rb * std::sqrt(1.0 - e * e);
      }
      if (face_.clearance(q) >= margin) {
        consider(pc.point(q.x, q.y), true);
        break;
      }
    }
}

// Rim samples (rim_): the fixed rulings' points in this plane, and the ellipse's end-plane
// corners.
void RimInserter::sample_rim() {
  const PlaneCut& pc = face_.pc;
  rim_.clear();
  std::array<std::pair<double, double>, 2> chords{};  // (a, half length) on each end plane
  if (pc.c1 > 0.0) {  // end-plane corners first, so rulings next to them give way
    for (double s_cap : {0.0, cyl_.len}) {
      const double a_cap = (s_cap - pc.so) / pc.c1;
      double hh = 0.0;
      if (pc.parallel)
        hh = pc.rb;
      else if (std::abs(a_cap - pc.a0) < pc.ra)
        hh = pc.rb * std::sqrt(1.0 - std::pow((a_cap - pc.a0) / pc.ra, 2.0));
      if (hh > 0.0)
        for (const double sign : {1.0, -1.0}) end_corner(a_cap, hh, sign);
      chords[s_cap > 0.0 ? 1 : 0] = {a_cap, hh};
    }
  }
  int arc_rulings = 0;  // rulings whose point in this plane lies between the end planes
  const std::size_t before_rulings = rim_.size();
  if (!pc.parallel) {
    // Rulings in increasing order (an earlier point wins over a later one too close to it); only
    // those in the window, unless a chord needs the count of all of them.
    const RulingWindow w = ruling_window(cyl_, face_.corner, ruling_reach_);
    const bool count_all = chords[0].second > 0.0 || chords[1].second > 0.0;
    const int wrapped = std::max(0, w.first + w.count - samples_);  // the window's part from 0
    for (int k = 0; k < samples_; ++k) {
      const bool in_window = k < wrapped || (k >= w.first && k < w.first + w.count);
      if (!in_window && !count_all) {
        if (k >= wrapped && k < w.first) k = w.first - 1;  // on to the window's main part
        else if (k >= w.first + w.count) break;
        continue;
      }
      const glm::dvec3& base = ruling_base_[static_cast<std::size_t>(k)];
      const double sv = glm::dot(pc.o - base, pc.n) / pc.dn;
      if (sv < 0.0 || sv > cyl_.len) continue;
      ++arc_rulings;
      if (in_window) consider(base + sv * cyl_.d, false);
    }
  }
  const bool arc_sampled = rim_.size() > before_rulings;
  // A layer that only clips the cylinder's rim edge (one end plane, no ruling point kept between
  // the end planes here) cuts a thin lens: without a point on its arc (the ellipse's apex, taken before
  // the straight part's points, which give way to it) the chord between the corners would run
  // along the straight part, a hole of zero area (a slit no wall can close).
  if (!pc.parallel && !arc_sampled && (chords[0].second > 0.0) != (chords[1].second > 0.0)) {
    const double a_cap = chords[0].second > 0.0 ? chords[0].first : chords[1].first;
    consider(pc.point(a_cap < pc.ac ? pc.a0 + pc.ra : pc.a0 - pc.ra, pc.b0), false);
  }
  // A layer that crosses an end disk gets a D-shaped rim: its straight part on the end plane is
  // sampled at the rim spacing, and densely enough (down to half of it) that the whole D has
  // min_rim_edges edges when the axis crosses the layer (its arc is then at least half a turn).
  for (const auto& [a_cap, hh] : chords) {
    if (!(hh > 0.0)) continue;
    const double spacing = 2.0 * cyl_.r * std::sin(geometry::kPi / samples_);
    const int by_spacing = static_cast<int>(std::ceil(2.0 * hh / spacing));
    const int by_count =
        std::min(samples_ - arc_rulings + 1, static_cast<int>(std::floor(4.0 * hh / spacing)));
    const int pieces = std::min(std::max(by_spacing, by_count), 4 * samples_);
    for (int j = 1; j < pieces; ++j)
      consider(pc.point(a_cap, pc.b0 - hh + 2.0 * hh * j / pieces), false);
  }
}

// Runs of outside segments; each closes with the rim arc from its end back to its start.
void RimInserter::emit_kept_parts(FaceId f, const Triangle& tri) {
  const std::vector<LocalPoint>& pts = pts_;
  const std::vector<std::uint8_t>& seg_inside = seg_inside_;
  const std::vector<LocalPoint>& rim = rim_;
  const std::size_t m = pts.size();
  std::size_t start = m;
  for (std::size_t i = 0; i < m; ++i)
    if (seg_inside[(i + m - 1) % m] && !seg_inside[i]) {
      start = i;
      break;
    }
  editor_.remove_face(f);
  ++removed_;
  if (start == m) return;
  std::vector<std::uint8_t>& used = used_scratch_;
  used.assign(rim.size(), 0);
  for (std::size_t step = 0; step < m; ++step) {
    const std::size_t j = (start + step) % m;
    if (!(seg_inside[(j + m - 1) % m] && !seg_inside[j])) continue;
    std::vector<LocalPoint>& poly = poly_scratch_;
    poly.clear();
    std::size_t k = j;
    poly.push_back(pts[k]);
    while (!seg_inside[k]) {
      k = (k + 1) % m;
      poly.push_back(pts[k]);
      if (k == j) break;
    }
    const double phi_end = face_.pc.phi(pts[k].q);
    const double span = geometry::wrap_2pi(phi_end - face_.pc.phi(pts[j].q));
    std::vector<std::pair<double, std::size_t>>& arc = arc_scratch_;
    arc.clear();
    for (std::size_t i = 0; i < rim.size(); ++i) {
      if (used[i]) continue;
      const double delta = geometry::wrap_2pi(phi_end - rim[i].phi);
      if (delta > 0.0 && delta < span) arc.emplace_back(delta, i);
    }
    std::sort(arc.begin(), arc.end());
    for (const auto& [delta, i] : arc) {
      used[i] = 1;
      poly.push_back(rim[i]);
    }
    std::vector<std::uint32_t>& loop = loop_scratch_;
    loop.resize(poly.size());
    for (std::size_t i = 0; i < poly.size(); ++i) loop[i] = static_cast<std::uint32_t>(i);
    emit_polygon(f, tri, poly, loop, no_holes_);
  }
}

// Chew-style refinement of one kept part: points at the circumcentres of skinny triangles that
// are larger than the rim spacing (needles from a far corner to a small hole), kept away from
// the part's boundary so no edge of the parent triangle is split (its neighbour shares it).
void RimInserter::refine(geometry::FlipTriangulation& ft, std::vector<glm::dvec2>& q,
                         std::vector<LocalPoint>& pts, const std::vector<std::uint32_t>& outer,
                         const std::vector<std::vector<std::uint32_t>>& holes) {
  const double spacing = 2.0 * cyl_.r * std::sin(geometry::kPi / samples_);
  const std::size_t boundary = pts.size();
  std::vector<std::pair<std::uint32_t, std::uint32_t>>& segments = segments_scratch_;
  segments.clear();
  const auto add_segments = [&segments](const std::vector<std::uint32_t>& l) {
    for (std::size_t i = 0; i < l.size(); ++i) segments.emplace_back(l[i], l[(i + 1) % l.size()]);
  };
  add_segments(outer);
  for (const auto& l : holes) add_segments(l);
  std::vector<geometry::LocalTri>& failed = failed_scratch_;  // by sorted_corners
  failed.clear();
  auto has_failed = [&failed](const geometry::LocalTri& t) {
    return std::find(failed.begin(), failed.end(), t) != failed.end();
  };
  const std::size_t budget = 4 * boundary + 8;
  for (std::size_t added = 0; added < budget;) {
    const geometry::LocalTri* worst = nullptr;
    double worst_ratio = 0.684;  // shortest edge / circumradius = 2 sin(min angle): 20 degrees
    for (const auto& t : ft.triangles()) {
      const glm::dvec2 &a = q[t[0]], &b = q[t[1]], &c = q[t[2]];
      const double la = glm::length(b - c), lb = glm::length(c - a), lc = glm::length(a - b);
      const double area2 = std::abs(geometry::orient(a, b, c));
      if (!(area2 > 0.0) || std::max({la, lb, lc}) < 2.0 * spacing) continue;
      const double circumradius = la * lb * lc / (2.0 * area2);
      const double ratio = std::min({la, lb, lc}) / circumradius;
      if (ratio < worst_ratio && !has_failed(geometry::sorted_corners(t))) {
        worst_ratio = ratio;
        worst = &t;
      }
    }
    if (!worst) return;
    const geometry::LocalTri t = *worst;
    const glm::dvec2 centre = geometry::circumcentre(q[t[0]], q[t[1]], q[t[2]]);
    bool ok = std::isfinite(centre.x) && std::isfinite(centre.y);
    const glm::dvec3 bary = ok ? face_.bary_of(centre) : glm::dvec3(-1.0);
    ok = ok && bary.x > 1e-6 && bary.y > 1e-6 && bary.z > 1e-6;
    for (std::size_t i = 0; i < boundary && ok; ++i) ok = glm::length(q[i] - centre) > 0.5 * spacing;
    for (const auto& [u, v] : segments) {
      if (!ok) break;
      ok = std::sqrt(geometry::segment_distance2(centre, q[u], q[v])) > 0.35 * spacing;
    }
    if (!ok || !ft.insert(centre)) {
      if (!has_failed(geometry::sorted_corners(t))) failed.push_back(geometry::sorted_corners(t));
      continue;
    }
    LocalPoint lp;
    lp.q = centre;
    lp.p = face_.pc.point(centre.x, centre.y);
    lp.bary = bary;
    pts.push_back(lp);
    ++added;
  }
}

// A kept part that is a triangle is emitted as it is; any other is triangulated, flipped to
// Delaunay and refined in the plane.
void RimInserter::emit_polygon(FaceId f, const Triangle& tri, std::vector<LocalPoint>& pts,
                               const std::vector<std::uint32_t>& outer,
                               const std::vector<std::vector<std::uint32_t>>& holes) {
  if (holes.empty() && outer.size() == 3) {
    emit_faces(f, tri, pts, {{outer[0], outer[1], outer[2]}});
    return;
  }
  std::vector<glm::dvec2>& q = q_scratch_;
  q.resize(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) q[i] = pts[i].q;
  std::vector<geometry::LocalTri>& clipped = clipped_scratch_;
  clipped.clear();
  geometry::triangulate_polygon(q, outer, holes, kRimTriangulation, clipped);
  geometry::FlipTriangulation& ft = flips_;
  ft.reset(q, clipped);
  ft.make_delaunay();
  refine(ft, q, pts, outer, holes);
  emit_faces(f, tri, pts, ft.triangles());
}

// New vertices for the part's points that have none (in order), then its faces, but a merged
// tip's.
void RimInserter::emit_faces(FaceId f, const Triangle& tri, std::vector<LocalPoint>& pts,
                             const std::vector<geometry::LocalTri>& tris) {
  for (auto& lp : pts) vertex_of(tri, lp);
  for (const auto& t : tris) {
    if (pts[t[0]].v == pts[t[1]].v || pts[t[1]].v == pts[t[2]].v || pts[t[0]].v == pts[t[2]].v)
      continue;  // merged tip
    editor_.add_face_from({pts[t[0]].v, pts[t[1]].v, pts[t[2]].v}, f,
                          {glm::vec3(pts[t[0]].bary), glm::vec3(pts[t[1]].bary), glm::vec3(pts[t[2]].bary)});
    ++added_;
  }
}

// Rim edges are found from the topology the edits left: boundary half-edges of the new faces
// whose ends lie on the cylinder. An edge between two old vertices is an edge of the parent
// All three corners deep inside; `judged` keeps each vertex's answer (1 deep, 0 not).
bool RimInserter::deep(const Triangle& t, detail::VertexSlots& judged) const {
  for (const VertexId v : t) {
    std::uint32_t j = judged.get(v.index);
    if (j == detail::VertexSlots::kNone) judged.set(v.index, j = deep_vertex(cyl_, posed_, v) ? 1 : 0);
    if (j == 0) return false;
  }
  return true;
}

RimInsertion RimInserter::run(const std::vector<FaceId>& candidates) {
  deep_.resize(candidates.size());
  std::size_t shallow = 0;
  detail::VertexSlots& judged = detail::VertexSlots::scratch();
  judged.reset(mesh_.vertex_count());
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    deep_[c] = deep(mesh_.face(candidates[c]), judged) ? 1 : 0;
    shallow += !deep_[c];
  }
  edges_.reserve(3 * shallow + 3);  // every edge looked up is a shallow candidate's
  face_edges_.resize(candidates.size());
  allow_steiner(candidates);
  for (std::size_t c = 0; c < candidates.size(); ++c)
    if (!deep_[c]) merge_crossings(c, candidates[c]);
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    if (!deep_[c]) {
      process_face(c, candidates[c]);
      continue;
    }
    editor_.remove_face(candidates[c]);  // what process_face does with a face inside
    ++removed_;
  }
  RimInsertion out;
  out.crossings = crossings_;
  out.removed = removed_;
  out.added = added_;
  return out;
}

}  // namespace

RimInsertion insert_rim(MeshEditor& editor, const CylinderFrame& cyl, PosedOverlay& posed,
                        const std::vector<FaceId>& candidates) {
  RimInserter inserter(editor, cyl, posed);
  return inserter.run(candidates);
}

}  // namespace deepcut::drill
