// SPDX-License-Identifier: MIT
// Drill: conforming insertion of a finite cylinder's rim into each crossed triangle.
//
// 1. Candidate faces come from the spatial index (or a bounding-sphere scan).
// 2. Each candidate edge is intersected once with the solid cylinder (exact quadratic on the
//    posed positions); crossings closer than the tolerance to an end snap to it, grazes are
//    ignored, and every kept crossing becomes one shared vertex (no T-junctions).
// 3. Each affected triangle is handled in its own plane, where the cylinder cuts an ellipse
//    (clipped by the end planes): the rim inside the triangle is sampled where the fixed
//    rulings (min_rim_edges equal angles around the axis) meet the plane, plus the ellipse's
//    corners on the end planes. The kept parts of the triangle (one boundary run and one rim
//    arc each, or the triangle with an elliptic hole) are triangulated and flipped to Delaunay
//    in the plane; corners get barycentric coordinates of the parent (add_face_from).
// 4. Rims are chained; with `wall`, each connected shell gets the part of the cylinder's surface
//    (side and end disks) inside it, triangulated in one plane the surface is mapped to
//    conformally (log-polar on the side, the end disks continuing it), where the shell's rims
//    are nested loops (see wall_shell).
#include "deepcut/core/ops/drill.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <deque>
#include <iterator>
#include <limits>
#include <map>
#include <string>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/core/skinning.h"
#include "geometry/delaunay_flip.h"
#include "geometry/polygon_triangulation.h"
#include "geometry/predicates.h"
#include "ops/common/model_surgery.h"
#include "ops/common/pinches.h"

namespace deepcut {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();
// The wall plane map spans at most exp(kWallSpan) in scale: exact orientation tests stay
// reliable, and longer walls are compressed along the axis (kappa).
constexpr double kWallSpan = 8.0;
// Wall Steiner rows (see wall_shell): away from the rims a ring keeps at least kWallSides points
// (an inscribed 24-gon holds 98.9% of the circle's area), rows are at most kWallAspect of its
// spacing apart (triangles of about 8 degrees at the narrowest), and where the rims' skin
// weights differ, rows at most kWallBend of weight change apart let the wall bend with them. At
// most kWallRows rows along the axis and kWallRings rings on an end disk.
constexpr int kWallSides = 24;
constexpr double kWallAspect = 7.0;
constexpr double kWallBend = 0.125;
constexpr double kWallRows = 256.0;
constexpr double kWallNeedle = 6.0 * kPi / 180.0;  // wall triangles at a rim refined below this angle
constexpr double kWallRings = 24.0;
// Old vertices within this many rim spacings of the cylinder's side, with crossings of two of
// their edges within kSnapClose rim spacings, are slid onto it (snap_shallow_vertices).
constexpr double kSnapBand = 0.1;
constexpr double kSnapClose = 0.5;
// Steiner points on crossed edges (see edge()) lie at least this many rim spacings outside.
constexpr double kSteinerClear = 0.3;
constexpr double kSteinerParentAngle = 10.0 * kPi / 180.0;

std::uint64_t edge_key(VertexId a, VertexId b) {
  const auto lo = std::min(a.index, b.index), hi = std::max(a.index, b.index);
  return (std::uint64_t(lo) << 32) | hi;
}

double wrap_2pi(double x) {
  x = std::fmod(x, 2.0 * kPi);
  return x < 0.0 ? x + 2.0 * kPi : x;
}

using geometry::bridge;
using geometry::clip_polygon;
using geometry::FlipTriangulation;
using geometry::incircle;
using geometry::LocalTri;
using geometry::orient;
using geometry::triangulate;

// The cylinder in double precision, with an orthonormal frame (u, w, d).
struct Frame {
  glm::dvec3 a, d, u, w;
  double len = 0.0, r = 0.0;

  double s(const glm::dvec3& p) const { return glm::dot(p - a, d); }
  glm::dvec3 perp(const glm::dvec3& p) const {
    const glm::dvec3 q = p - a;
    return q - glm::dot(q, d) * d;
  }
  double rho(const glm::dvec3& p) const { return glm::length(perp(p)); }
  double theta(const glm::dvec3& p) const {
    const glm::dvec3 q = perp(p);
    return std::atan2(glm::dot(q, w), glm::dot(q, u));
  }
  // Signed distance-like function: negative inside, 1-Lipschitz, <= the true distance outside.
  double sd(const glm::dvec3& p) const {
    const double sv = s(p);
    return std::max({rho(p) - r, -sv, sv - len});
  }
  glm::dvec3 ruling(double th) const { return std::cos(th) * u + std::sin(th) * w; }
  glm::dvec3 at(double th, double sv) const { return a + r * ruling(th) + sv * d; }
};

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
  double phi = 0.0;     // angle around the ellipse centre (normalised frame)
  bool on_rim = false;  // lies on the cylinder's boundary
};

// The region the solid cylinder cuts from one triangle's plane, in plane coordinates (a, b):
// an ellipse (semi-axes ra along e1, rb along e2) clipped to alo <= a <= ahi by the end planes.
struct PlaneCut {
  glm::dvec3 o, n, e1, e2;
  double dn = 0.0;  // d . n
  bool parallel = false, empty = true;
  double a0 = 0.0, b0 = 0.0, ra = kInf, rb = 0.0, c1 = 0.0, so = 0.0;
  double alo = -kInf, ahi = kInf, ac = 0.0, ha = 1.0;

  glm::dvec2 coords(const glm::dvec3& x) const { return {glm::dot(x - o, e1), glm::dot(x - o, e2)}; }
  glm::dvec3 point(double av, double bv) const { return o + av * e1 + bv * e2; }
  double phi(const glm::dvec2& q) const { return std::atan2((q.y - b0) / rb, (q.x - ac) / ha); }
};

PlaneCut plane_cut(const Frame& cyl, const glm::dvec3 p[3]) {
  PlaneCut pc;
  glm::dvec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
  const double nl = glm::length(n);
  if (!(nl > 0.0)) return pc;
  n /= nl;
  pc.o = p[0];
  pc.n = n;
  pc.dn = glm::dot(cyl.d, n);
  const glm::dvec3 proj = cyl.d - pc.dn * n;
  pc.c1 = glm::length(proj);
  pc.e1 = pc.c1 > 1e-12 ? proj / pc.c1 : glm::normalize(cyl.u - glm::dot(cyl.u, n) * n);
  if (pc.c1 <= 1e-12) pc.c1 = 0.0;
  pc.e2 = glm::cross(n, pc.e1);
  pc.so = cyl.s(pc.o);
  pc.parallel = std::abs(pc.dn) < 1e-9;
  if (!pc.parallel) {
    const glm::dvec3 centre = cyl.a + cyl.d * (glm::dot(pc.o - cyl.a, n) / pc.dn);
    const glm::dvec2 c = pc.coords(centre);
    pc.a0 = c.x;
    pc.b0 = c.y;
    pc.ra = cyl.r / std::abs(pc.dn);
    pc.rb = cyl.r;
  } else {
    const glm::dvec3 m = cyl.perp(pc.o);
    const double me2 = glm::dot(m, pc.e2);
    const double h2 = cyl.r * cyl.r - (glm::dot(m, m) - me2 * me2);
    if (!(h2 > 0.0)) return pc;
    pc.b0 = -me2;
    pc.rb = std::sqrt(h2);
  }
  if (pc.c1 > 0.0) {
    pc.alo = -pc.so / pc.c1;
    pc.ahi = (cyl.len - pc.so) / pc.c1;
  } else if (!(pc.so > 0.0 && pc.so < cyl.len)) {
    return pc;
  }
  const double lo = pc.parallel ? pc.alo : std::max(pc.a0 - pc.ra, pc.alo);
  const double hi = pc.parallel ? pc.ahi : std::min(pc.a0 + pc.ra, pc.ahi);
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi)) return pc;
  pc.ac = 0.5 * (lo + hi);
  pc.ha = 0.5 * (hi - lo);
  pc.empty = false;
  return pc;
}

class Driller {
 public:
  Driller(SurfaceMesh& mesh, const std::vector<glm::vec3>& posed, const Cylinder& cylinder,
          const DrillOptions& options, const TriangleGrid* index, const Unposer& unpose)
      : mesh_(mesh), editor_(mesh), posed_(posed), options_(options), index_(index), unpose_(unpose) {
    cyl_.a = glm::dvec3(cylinder.a);
    const glm::dvec3 b(cylinder.b);
    cyl_.len = glm::length(b - cyl_.a);
    cyl_.d = (b - cyl_.a) / cyl_.len;
    cyl_.r = cylinder.radius;
    const glm::dvec3 helper = std::abs(cyl_.d.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    cyl_.u = glm::normalize(glm::cross(helper, cyl_.d));
    cyl_.w = glm::cross(cyl_.d, cyl_.u);
    const double scale = glm::length(cyl_.a) + glm::length(b) + cyl_.len;
    eps_ = std::max(double(options.relative_tolerance) * cyl_.r, 1e-6 * scale);
    samples_ = options.min_rim_edges;
    sep_ = 0.3 * 2.0 * cyl_.r * std::sin(kPi / samples_);
    first_new_ = static_cast<std::uint32_t>(mesh.vertex_count());
    for (int k = 0; k < samples_; ++k)
      ruling_base_.push_back(cyl_.a + cyl_.r * cyl_.ruling(2.0 * kPi * k / samples_));
  }

  DrillResult run();

 private:
  glm::dvec3 posed(VertexId v) const {
    if (v.index >= first_new_) return added_posed_[v.index - first_new_];
    if (!moved_.empty()) {
      const auto it = std::lower_bound(moved_.begin(), moved_.end(), std::make_pair(v.index, glm::dvec3(-kInf)),
                                       [](const auto& x, const auto& y) { return x.first < y.first; });
      if (it != moved_.end() && it->first == v.index) return it->second;
    }
    return glm::dvec3(posed_[v.index]);
  }
  void snap_shallow_vertices();
  const EdgeCut& edge(VertexId a, VertexId b);
  void merge_crossings(FaceId f);
  void allow_steiner();
  VertexId merged(VertexId v) const {
    for (auto it = merged_.find(v.index); it != merged_.end(); it = merged_.find(v.index)) v = it->second;
    return v;
  }
  void process_face(FaceId f);
  void emit_polygon(FaceId f, const Triangle& tri, std::vector<LocalPoint>& pts,
                    const std::vector<std::vector<std::uint32_t>>& loops);
  VertexId vertex_of(const Triangle& tri, LocalPoint& lp);
  void refine(FlipTriangulation& ft, std::vector<glm::dvec2>& q, std::vector<LocalPoint>& pts,
              const std::vector<std::vector<std::uint32_t>>& loops);
  // The plane of the triangle being processed, and barycentric coordinates in it.
  PlaneCut plane_;
  glm::dvec2 corner_q_[3];
  double corner_area2_ = 1.0;
  glm::dvec3 bary_of_(const glm::dvec2& x) const {
    return glm::dvec3(orient(x, corner_q_[1], corner_q_[2]), orient(corner_q_[0], x, corner_q_[2]),
                      orient(corner_q_[0], corner_q_[1], x)) /
           corner_area2_;
  }
  void place(VertexId v, const glm::dvec3& target);
  void collect_holes(DrillResult& result);
  void build_walls(DrillResult& result);

  // Walls.
  struct WallPt {
    glm::dvec3 p{0.0};  // posed, on the cylinder's surface
    double theta = 0.0, s = 0.0, rho = 0.0;
    int where = 0;       // 0 side, 1 end disk at A, 2 end disk at B
    bool pole = false;   // the B disk's centre when the plane map sends it to the origin
    VertexId v;          // the vertex (rim), or invalid until a Steiner point is created
  };
  struct WallCoord {
    double theta, s;
    int where;
    VertexId v;
  };
  bool wall_shell(const std::vector<std::size_t>& hole_ids, const DrillResult& result, bool open_shell,
                  std::vector<char>& walled_ok);
  VertexId wall_vertex(VertexId a, VertexId b, float t, const glm::dvec3& p);
  FaceId wall_face(const Triangle& t, int kind);
  void finish_wall_attributes();

  SurfaceMesh& mesh_;
  MeshEditor editor_;
  const std::vector<glm::vec3>& posed_;
  DrillOptions options_;
  const TriangleGrid* index_;
  const Unposer& unpose_;
  Frame cyl_;
  double eps_ = 0.0, sep_ = 0.0;
  int samples_ = 32;
  std::uint32_t first_new_ = 0;
  std::vector<glm::dvec3> added_posed_;
  // Old vertices snap_shallow_vertices moved onto the cylinder: (index, new posed), by index.
  std::vector<std::pair<std::uint32_t, glm::dvec3>> moved_;
  std::vector<glm::dvec3> ruling_base_;  // where each sampled ruling starts (s = 0)
  // Edges met so far: an open-addressing table (at most half full) of edge keys to indices into
  // edge_cuts_, sized for the candidates' edges up front: no allocation per edge. A deque, so
  // references to earlier edges stay valid as edges are added.
  static constexpr std::uint64_t kNoEdge = ~std::uint64_t(0);  // edge_key of no real edge
  void size_edge_table(std::size_t edges);
  std::vector<std::uint64_t> edge_keys_;
  std::vector<std::uint32_t> edge_index_;
  std::deque<EdgeCut> edge_cuts_;
  int edge_shift_ = 64;
  std::vector<FaceId> candidates_;  // faces near the cylinder, in processing order
  std::unordered_set<std::uint64_t> steiner_edges_;  // edges that may take Steiner points (allow_steiner)
  // Crossings that fell on one bind position (the two long edges of a needle crossed at the same
  // parameter): the later vertex maps to the earlier, so the needle's tip is not a zero-area face.
  std::unordered_map<std::uint32_t, VertexId> merged_;
  std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> rim_next_;  // directed rim edges
  std::unordered_map<std::uint32_t, std::uint32_t> copy_of_;  // pinch-split copy -> original (no wall)
  std::size_t crossings_ = 0, removed_ = 0, added_ = 0;
  // Wall faces: 0 tube, 1 disk; vertex normals of the tube are accumulated over tube faces.
  std::vector<std::pair<FaceId, int>> wall_faces_;
  // process_face's working lists, kept between faces so their memory is reused.
  std::vector<LocalPoint> pts_scratch_, rim_scratch_, all_scratch_, poly_scratch_;
  std::vector<std::uint8_t> seg_scratch_, used_scratch_;
  std::vector<VertexId> ring_scratch_;
  std::array<std::vector<VertexId>, 2> border_scratch_;  // edges ahead of / behind a vertex in its faces
  std::unordered_map<std::uint32_t, WallCoord> wall_coords_;
};

void Driller::size_edge_table(std::size_t edges) {
  std::size_t size = 16;
  int shift = 60;
  while (size < 2 * edges) {
    size *= 2;
    --shift;
  }
  if (size <= edge_keys_.size()) return;
  edge_keys_.assign(size, kNoEdge);
  edge_index_.assign(size, 0);
  edge_shift_ = shift;
  for (std::uint32_t i = 0; i < edge_cuts_.size(); ++i) {
    const std::uint64_t key = edge_key(edge_cuts_[i].lo, edge_cuts_[i].hi);
    std::size_t slot = static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> edge_shift_);
    while (edge_keys_[slot] != kNoEdge) slot = (slot + 1) & (size - 1);
    edge_keys_[slot] = key;
    edge_index_[slot] = i;
  }
}

const EdgeCut& Driller::edge(VertexId a, VertexId b) {
  const auto key = edge_key(a, b);
  if (2 * (edge_cuts_.size() + 1) > edge_keys_.size()) size_edge_table(2 * edge_cuts_.size() + 16);
  std::size_t slot = static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> edge_shift_);
  const std::size_t mask = edge_keys_.size() - 1;
  while (edge_keys_[slot] != kNoEdge) {
    if (edge_keys_[slot] == key) return edge_cuts_[edge_index_[slot]];
    slot = (slot + 1) & mask;
  }
  EdgeCut e;
  e.lo = a < b ? a : b;
  e.hi = a < b ? b : a;
  const glm::dvec3 p = posed(e.lo), q = posed(e.hi);
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
        added_posed_.push_back(glm::mix(p, q, cuts[i]));
        place(e.v[i], added_posed_.back());
        ++crossings_;
      }
      // The kept parts of a crossed edge get points a rim spacing from each crossing, then 2,
      // 4, ... spacings (Ruppert's grading), up to a spacing before the far end: both faces on
      // the edge are processed (it is crossed), so both take them, and their kept parts meet
      // the rim with boundary points at its scale instead of fanning a far corner to close rim
      // points or leaving rim points near a long edge (needles the in-plane refinement cannot
      // mend: its points would fall outside the parent). Only points well outside the cylinder.
      const double spacing = 2.0 * cyl_.r * std::sin(kPi / samples_);
      for (int i = 0; i < n && steiner_edges_.count(key); ++i) {
        const double dir = e.inside[i + 1] ? -1.0 : 1.0;  // toward the kept part
        const double room = (dir > 0.0 ? 1.0 - cuts[i] : cuts[i]) * len;
        for (double step = spacing; step + spacing <= room; step *= 2.0) {
          const double t = cuts[i] + dir * step / len;
          const glm::dvec3 x = glm::mix(p, q, t);
          if (!(cyl_.sd(x) > kSteinerClear * spacing)) continue;
          const VertexId v = editor_.add_vertex_on_edge(e.lo, e.hi, static_cast<float>(t));
          added_posed_.push_back(x);
          place(v, x);
          e.steiner.emplace_back(t, v);
        }
      }
      std::sort(e.steiner.begin(), e.steiner.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    }
  }
  edge_keys_[slot] = key;
  edge_index_[slot] = static_cast<std::uint32_t>(edge_cuts_.size());
  edge_cuts_.push_back(e);
  return edge_cuts_.back();
}

// Skinning is not linear in the blended weights, so a new vertex interpolated in bind space
// would land beside its posed target: with an unposer it is placed by inverse skinning.
void Driller::place(VertexId v, const glm::dvec3& target) {
  if (!unpose_) return;
  const glm::vec3 bind = unpose_(mesh_, v, glm::vec3(target));
  if (bind != mesh_.position(v)) editor_.move_vertex(v, bind);
}

VertexId Driller::vertex_of(const Triangle& tri, LocalPoint& lp) {
  if (lp.v.valid()) return lp.v;
  lp.v = editor_.add_vertex_in_triangle(tri, glm::vec3(lp.bary));
  added_posed_.push_back(lp.p);
  place(lp.v, lp.p);
  return lp.v;
}

// Crosses a candidate's edges (in the order process_face asks for them). A face whose corner has
// two long edges to corners a hair apart (a needle: the lips of a narrow tear, a sliver) can have
// crossings of the two edges rounded to one bind position: they become one vertex, and the
// needle's tip, or the kept part at its far end when the circle crosses each edge twice (a
// triangle with two corners at one point), is not made. Same rule as the cut and the tear.
void Driller::merge_crossings(FaceId f) {
  const Triangle tri = mesh_.face(f);
  for (int k = 0; k < 3; ++k) edge(tri[k], tri[(k + 1) % 3]);
  for (int k = 0; k < 3; ++k) {
    const VertexId x = tri[k];
    const EdgeCut ea = edge(x, tri[(k + 1) % 3]), eb = edge(x, tri[(k + 2) % 3]);
    for (int i = 0; i < ea.n; ++i)
      for (int j = 0; j < eb.n; ++j) {
        const VertexId a = merged(ea.v[i]), b = merged(eb.v[j]);
        if (a != b && mesh_.position(a) == mesh_.position(b)) merged_.emplace(std::max(a, b).index, std::min(a, b));
      }
  }
}

// Steiner points (see edge()) go only on edges between two candidates of good shape (smallest
// angle 10 degrees or more), one on each side: not on the mesh's border or a non-manifold edge,
// where a point off the cylinder could end up on the hole's boundary, and not on a needle's long
// edges, whose points at one parameter would round to one bind position (zero-area faces).
void Driller::allow_steiner() {
  steiner_edges_.clear();
  std::unordered_map<std::uint64_t, int> sides;  // +1 per half-edge lo -> hi, +16 per hi -> lo
  std::unordered_set<std::uint64_t> bad;
  for (FaceId f : candidates_) {
    const Triangle& t = mesh_.face(f);
    double smallest = kInf;
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 a = posed(t[k]), b = posed(t[(k + 1) % 3]), c = posed(t[(k + 2) % 3]);
      const double lb = glm::length(b - a), lc = glm::length(c - a);
      smallest = lb > 0.0 && lc > 0.0 ? std::min(smallest, std::acos(std::clamp(glm::dot(b - a, c - a) / (lb * lc), -1.0, 1.0)))
                                      : 0.0;
    }
    const bool good = smallest >= kSteinerParentAngle;
    for (int k = 0; k < 3; ++k) {
      const VertexId a = t[k], b = t[(k + 1) % 3];
      const std::uint64_t key = edge_key(a, b);
      sides[key] += a < b ? 1 : 16;
      if (!good) bad.insert(key);
    }
  }
  for (const auto& [key, count] : sides)
    if (count == 17 && !bad.count(key)) steiner_edges_.insert(key);
}

// An old vertex lying just inside (or just outside) the cylinder leaves the crossings of two of
// its edges a hair apart: the far corners of its faces fan to those two close rim points (needles
// under a degree), or it stays as the tip of a sliver between them. Such a vertex, within
// kSnapBand rim spacings of the side, is slid in its tangent plane onto the cylinder before any
// edge is split, so it becomes a rim vertex itself and its edges are not cut there. Only where
// every face around it keeps its orientation (and a non-zero area) in posed and in bind space;
// the bind position moves by the vertex's own skinning inverted (the unposer), so the edit is a
// VertexMoved in the log and the new posed position is reported (DrillResult::moved).
void Driller::snap_shallow_vertices() {
  const double spacing = 2.0 * cyl_.r * std::sin(kPi / samples_);
  const double band = kSnapBand * spacing, close = kSnapClose * spacing;
  // Every face around a vertex within the band of the side is a candidate (the reach covers it).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> corners;  // (old vertex, candidate face)
  for (FaceId f : candidates_)
    for (VertexId v : mesh_.face(f))
      if (v.index < first_new_) corners.emplace_back(v.index, f.index);
  std::sort(corners.begin(), corners.end());
  for (std::size_t i = 0, j = 0; i < corners.size(); i = j) {
    while (j < corners.size() && corners[j].first == corners[i].first) ++j;
    const VertexId x(corners[i].first);
    const glm::dvec3 p = posed(x);
    const double sv = cyl_.s(p), off = cyl_.rho(p) - cyl_.r;
    if (sv < spacing || sv > cyl_.len - spacing || std::abs(off) > band || std::abs(off) <= 1e-9 * cyl_.r) continue;
    // The crossings its edges would get near it (entering from outside, leaving from inside).
    const glm::dvec3 m = cyl_.perp(p);
    int near = 0;
    glm::dvec3 normal(0.0);
    std::vector<VertexId>& ring = ring_scratch_;
    ring.clear();
    for (std::size_t c = i; c < j; ++c) {
      const Triangle& t = mesh_.face(FaceId(corners[c].second));
      normal += glm::cross(posed(t[1]) - posed(t[0]), posed(t[2]) - posed(t[0]));
      for (VertexId y : t)
        if (y != x) ring.push_back(y);
    }
    // A vertex on the mesh's border stays where it is: primitives split at a material seam keep
    // a copy of each seam vertex each, and sliding one copy alone would open a crack along the
    // seam. It is on the border when an edge from it has a face on one side only.
    std::vector<VertexId>& ahead = border_scratch_[0];
    std::vector<VertexId>& behind = border_scratch_[1];
    ahead.clear();
    behind.clear();
    for (std::size_t c = i; c < j; ++c) {
      const Triangle& t = mesh_.face(FaceId(corners[c].second));
      const int q = t[0] == x ? 0 : t[1] == x ? 1 : 2;
      ahead.push_back(t[(q + 1) % 3]);
      behind.push_back(t[(q + 2) % 3]);
    }
    std::sort(ahead.begin(), ahead.end());
    std::sort(behind.begin(), behind.end());
    if (ahead != behind) continue;
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    for (VertexId y : ring) {
      const glm::dvec3 q = posed(y), k = cyl_.perp(q) - m;
      const double a = glm::dot(k, k), b = glm::dot(m, k), cq = glm::dot(m, m) - cyl_.r * cyl_.r;
      const double disc = b * b - a * cq;
      if (!(a > 0.0) || disc < 0.0) continue;
      const double tt = off > 0.0 ? (-b - std::sqrt(disc)) / a : (-b + std::sqrt(disc)) / a;
      near += tt > 0.0 && tt < 1.0 && tt * glm::length(q - p) < close;
    }
    if (near < 2) continue;
    const double nl = glm::length(normal);
    if (!(nl > 0.0)) continue;
    normal /= nl;
    const glm::dvec3 radial = m / glm::length(m);
    glm::dvec3 dir = radial - glm::dot(radial, normal) * normal;
    const double dl = glm::length(dir);
    if (dl < 0.5) continue;  // the surface runs along the cylinder there: no slide reaches it
    dir /= dl;
    const glm::dvec3 k = dir - glm::dot(dir, cyl_.d) * cyl_.d;
    const double a = glm::dot(k, k), b = glm::dot(m, k), cq = glm::dot(m, m) - cyl_.r * cyl_.r;
    const double disc = b * b - a * cq;
    if (!(a > 0.0) || disc < 0.0) continue;
    const double l1 = (-b - std::sqrt(disc)) / a, l2 = (-b + std::sqrt(disc)) / a;
    const double step = std::abs(l1) < std::abs(l2) ? l1 : l2;
    if (!(std::abs(step) <= 2.0 * band)) continue;
    const glm::dvec3 target = p + step * dir;
    const double st = cyl_.s(target);
    if (st < spacing || st > cyl_.len - spacing) continue;
    const glm::vec3 bind = mesh_.position(x);
    glm::dvec3 shift = target - p;
    if (unpose_) shift = glm::dvec3(unpose_(mesh_, x, glm::vec3(target))) - glm::dvec3(unpose_(mesh_, x, glm::vec3(p)));
    const glm::vec3 moved = glm::vec3(glm::dvec3(bind) + shift);
    if (!(std::isfinite(moved.x) && std::isfinite(moved.y) && std::isfinite(moved.z)) || moved == bind) continue;
    bool ok = true;
    for (std::size_t c = i; c < j && ok; ++c) {
      const Triangle& t = mesh_.face(FaceId(corners[c].second));
      glm::dvec3 pp[3], pn[3], bp[3], bn[3];
      for (int q = 0; q < 3; ++q) {
        pp[q] = posed(t[q]);
        pn[q] = t[q] == x ? target : pp[q];
        bp[q] = glm::dvec3(mesh_.position(t[q]));
        bn[q] = glm::dvec3(t[q] == x ? moved : mesh_.position(t[q]));
      }
      for (int space = 0; space < 2 && ok; ++space) {
        const glm::dvec3* o = space == 0 ? pp : bp;
        const glm::dvec3* n = space == 0 ? pn : bn;
        const glm::dvec3 before = glm::cross(o[1] - o[0], o[2] - o[0]), after = glm::cross(n[1] - n[0], n[2] - n[0]);
        const double longest =
            std::max({glm::dot(n[1] - n[0], n[1] - n[0]), glm::dot(n[2] - n[1], n[2] - n[1]), glm::dot(n[0] - n[2], n[0] - n[2])});
        ok = glm::length(after) > 1e-9 * longest && glm::dot(before, after) > 0.5 * glm::length(before) * glm::length(after);
      }
    }
    if (!ok) continue;
    editor_.move_vertex(x, moved);
    moved_.emplace_back(x.index, target);  // in index order: the corners are sorted
  }
}

void Driller::process_face(FaceId f) {
  const Triangle tri = mesh_.face(f);
  const glm::dvec3 corner[3] = {posed(tri[0]), posed(tri[1]), posed(tri[2])};
  // The triangle's boundary: corners and crossings in order, with the state of each segment.
  std::vector<LocalPoint>& pts = pts_scratch_;
  std::vector<std::uint8_t>& seg_inside = seg_scratch_;
  pts.clear();
  seg_inside.clear();
  for (int k = 0; k < 3; ++k) {
    const int k1 = (k + 1) % 3;
    const EdgeCut& e = edge(tri[k], tri[k1]);
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
      x.p = added_posed_[sv.index - first_new_];
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
      x.p = added_posed_[sv.index - first_new_];
      x.bary = glm::dvec3(0.0);
      x.bary[k] = 1.0 - t;
      x.bary[k1] = t;
      pts.push_back(x);
      seg_inside.push_back(seg_inside.back());
    }
  }
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
  const double area2 = orient(tq[0], tq[1], tq[2]);
  if (!(area2 > 0.0)) {
    if (any_inside) {
      editor_.remove_face(f);
      ++removed_;
    }
    return;
  }
  plane_ = pc;
  for (int k = 0; k < 3; ++k) corner_q_[k] = tq[k];
  corner_area2_ = area2;
  auto bary_of = [&](const glm::dvec2& q) {
    return glm::dvec3(orient(q, tq[1], tq[2]), orient(tq[0], q, tq[2]), orient(tq[0], tq[1], q)) / area2;
  };
  if (!any_inside) {
    // Only a hole wholly inside the triangle can be left: its centre must lie inside.
    const glm::dvec3 cb = bary_of({pc.ac, pc.b0});
    if (cb.x <= 0.0 || cb.y <= 0.0 || cb.z <= 0.0) return;
  }
  for (auto& lp : pts) {
    lp.q = pc.coords(lp.p);
    lp.phi = pc.phi(lp.q);
  }
  // Distance of a plane point from each edge is its barycentric coordinate times the height.
  double height[3];
  for (int k = 0; k < 3; ++k) height[k] = area2 / std::max(glm::length(tq[(k + 2) % 3] - tq[(k + 1) % 3]), 1e-300);
  // Rim samples: the fixed rulings' points in this plane, and the ellipse's end-plane corners.
  std::vector<LocalPoint>& rim = rim_scratch_;
  rim.clear();
  auto consider = [&](const glm::dvec3& x, bool corner_point) {
    LocalPoint lp;
    lp.p = x;
    lp.q = pc.coords(x);
    lp.bary = bary_of(lp.q);
    int low = -1, lows = 0;
    for (int k = 0; k < 3; ++k)
      if (lp.bary[k] < 1e-7) low = k, ++lows;
    if (lows > 0) {
      // A ruling's point just beyond an edge the cylinder only grazes (too shallowly to be cut):
      // the rim bulges over that edge by about the tolerance, and no neighbour takes the point
      // (at a crease the ruling meets its plane beyond the edge too, and no rim crosses an uncut
      // edge). Dropped, the hole lost a rim edge (SimpleSkin, seed 3 drill 23: 31 of 32); it is
      // moved inside, a tolerance from the edge, when that moves it and keeps it within half a
      // percent of r (not on holes smaller than the absolute tolerance: the move would round
      // away in float and leave zero-area faces).
      if (corner_point || lows > 1) return;
      const int k1 = (low + 1) % 3, k2 = (low + 2) % 3;
      const double shift = eps_ - lp.bary[low] * height[low], bound = 0.005 * cyl_.r;
      if (shift > bound || edge(tri[k1], tri[k2]).n != 0) return;
      const glm::dvec2 along = glm::normalize(tq[k2] - tq[k1]);
      lp.q += shift * glm::dvec2(-along.y, along.x);  // inside is on the left
      lp.bary = bary_of(lp.q);
      lp.p = pc.point(lp.q.x, lp.q.y);
      for (int k = 0; k < 3; ++k)
        if (lp.bary[k] < 1e-7) return;
      if (std::abs(cyl_.sd(lp.p)) > bound) return;
    }
    // An end-plane corner gives way only to a rim point a hair away: without it the chord from
    // the end-plane part to the side part of a D-shaped rim cuts the corner off, as deep as
    // the gap (a triangle of kept surface with its centroid inside the cylinder).
    const double gap = corner_point ? 2.0 * eps_ : sep_;
    for (const auto& b : pts)
      if (b.on_rim && glm::length(b.p - lp.p) < gap) return;
    if (!corner_point)
      for (const auto& other : rim)
        if (glm::length(other.p - lp.p) < sep_) return;
    lp.phi = pc.phi(lp.q);
    lp.on_rim = true;
    rim.push_back(lp);
  };
  // Distance of a plane point inside the triangle from its nearest edge (negative outside).
  auto clearance = [&](const glm::dvec2& q) {
    const glm::dvec3 b = bary_of(q);
    return std::min({b.x * height[0], b.y * height[1], b.z * height[2]});
  };
  // The corner where the rim's straight part (on an end plane) meets its arc. One lying just
  // outside the triangle (within a rim spacing: an edge grazes the hole there, too shallowly to
  // be cut, or cuts off the corner alone) still bends the rim inside: the rim then gets the
  // first points of both parts 2 tolerances inside, or the chord between the two parts'
  // crossings cuts the corner off (kept surface up to a few % of r inside the cylinder).
  auto end_corner = [&](double a_cap, double hh, double sign) {
    const glm::dvec2 qc(a_cap, pc.b0 + sign * hh);
    const double out = -clearance(qc);
    if (out <= 0.0 || out > sep_) {
      consider(pc.point(qc.x, qc.y), true);
      return;
    }
    const double margin = 2.0 * eps_, toward = pc.ac > a_cap ? 1.0 : -1.0;
    for (int part = 0; part < 2; ++part)
      for (double t = margin; t < hh; t *= 2.0) {
        glm::dvec2 q(a_cap, pc.b0 + sign * (hh - t));  // along the end plane's line
        if (part == 1) {  // along the arc
          q.x = a_cap + toward * t;
          const double e = pc.parallel ? 0.0 : (q.x - pc.a0) / pc.ra;
          if (std::abs(e) >= 1.0) break;
          q.y = pc.b0 + sign * pc.rb * std::sqrt(1.0 - e * e);
        }
        if (clearance(q) >= margin) {
          consider(pc.point(q.x, q.y), true);
          break;
        }
      }
  };
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
  const std::size_t before_rulings = rim.size();
  if (!pc.parallel) {
    for (int k = 0; k < samples_; ++k) {
      const glm::dvec3& base = ruling_base_[static_cast<std::size_t>(k)];
      const double sv = glm::dot(pc.o - base, pc.n) / pc.dn;
      if (sv < 0.0 || sv > cyl_.len) continue;
      ++arc_rulings;
      consider(base + sv * cyl_.d, false);
    }
  }
  const bool arc_sampled = rim.size() > before_rulings;
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
    const double spacing = 2.0 * cyl_.r * std::sin(kPi / samples_);
    const int by_spacing = static_cast<int>(std::ceil(2.0 * hh / spacing));
    const int by_count = std::min(samples_ - arc_rulings + 1, static_cast<int>(std::floor(4.0 * hh / spacing)));
    const int pieces = std::min(std::max(by_spacing, by_count), 4 * samples_);
    for (int j = 1; j < pieces; ++j) consider(pc.point(a_cap, pc.b0 - hh + 2.0 * hh * j / pieces), false);
  }
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
    emit_polygon(f, tri, all, {outer, hole});
    return;
  }
  // Runs of outside segments; each closes with the rim arc from its end back to its start.
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
    const double phi_end = pts[k].phi, span = wrap_2pi(phi_end - pts[j].phi);
    std::vector<std::pair<double, std::size_t>> arc;
    for (std::size_t i = 0; i < rim.size(); ++i) {
      if (used[i]) continue;
      const double delta = wrap_2pi(phi_end - rim[i].phi);
      if (delta > 0.0 && delta < span) arc.emplace_back(delta, i);
    }
    std::sort(arc.begin(), arc.end());
    for (const auto& [delta, i] : arc) {
      used[i] = 1;
      poly.push_back(rim[i]);
    }
    std::vector<std::uint32_t> loop(poly.size());
    for (std::size_t i = 0; i < poly.size(); ++i) loop[i] = static_cast<std::uint32_t>(i);
    emit_polygon(f, tri, poly, {loop});
  }
}

// Chew-style refinement of one kept part: points at the circumcentres of skinny triangles that
// are larger than the rim spacing (needles from a far corner to a small hole), kept away from
// the part's boundary so no edge of the parent triangle is split (its neighbour shares it).
void Driller::refine(FlipTriangulation& ft, std::vector<glm::dvec2>& q, std::vector<LocalPoint>& pts,
                     const std::vector<std::vector<std::uint32_t>>& loops) {
  const double spacing = 2.0 * cyl_.r * std::sin(kPi / samples_);
  const std::size_t boundary = pts.size();
  std::vector<std::pair<std::uint32_t, std::uint32_t>> segments;
  for (const auto& l : loops)
    for (std::size_t i = 0; i < l.size(); ++i) segments.emplace_back(l[i], l[(i + 1) % l.size()]);
  std::unordered_set<std::uint64_t> failed;
  auto tri_key = [](const LocalTri& t) {
    std::array<std::uint32_t, 3> s = {t[0], t[1], t[2]};
    std::sort(s.begin(), s.end());
    return (std::uint64_t(s[0]) << 42) ^ (std::uint64_t(s[1]) << 21) ^ s[2];
  };
  const std::size_t budget = 4 * boundary + 8;
  for (std::size_t added = 0; added < budget;) {
    const LocalTri* worst = nullptr;
    double worst_ratio = 0.684;  // shortest edge / circumradius = 2 sin(min angle): 20 degrees
    for (const auto& t : ft.triangles()) {
      const glm::dvec2 &a = q[t[0]], &b = q[t[1]], &c = q[t[2]];
      const double la = glm::length(b - c), lb = glm::length(c - a), lc = glm::length(a - b);
      const double area2 = std::abs(orient(a, b, c));
      if (!(area2 > 0.0) || std::max({la, lb, lc}) < 2.0 * spacing) continue;
      const double circumradius = la * lb * lc / (2.0 * area2);
      const double ratio = std::min({la, lb, lc}) / circumradius;
      if (ratio < worst_ratio && !failed.count(tri_key(t))) {
        worst_ratio = ratio;
        worst = &t;
      }
    }
    if (!worst) return;
    const LocalTri t = *worst;
    const glm::dvec2 &a = q[t[0]], &b = q[t[1]], &c = q[t[2]];
    const glm::dvec2 ab = b - a, ac = c - a;
    const double d = 2.0 * (ab.x * ac.y - ab.y * ac.x);
    const glm::dvec2 centre = a + glm::dvec2(ac.y * glm::dot(ab, ab) - ab.y * glm::dot(ac, ac),
                                             ab.x * glm::dot(ac, ac) - ac.x * glm::dot(ab, ab)) /
                                      d;
    bool ok = std::isfinite(centre.x) && std::isfinite(centre.y);
    const glm::dvec3 bary = ok ? bary_of_(centre) : glm::dvec3(-1.0);
    ok = ok && bary.x > 1e-6 && bary.y > 1e-6 && bary.z > 1e-6;
    for (std::size_t i = 0; i < boundary && ok; ++i) ok = glm::length(q[i] - centre) > 0.5 * spacing;
    for (const auto& [u, v] : segments) {
      if (!ok) break;
      const glm::dvec2 e = q[v] - q[u];
      const double tt = std::clamp(glm::dot(centre - q[u], e) / std::max(glm::dot(e, e), 1e-300), 0.0, 1.0);
      ok = glm::length(q[u] + tt * e - centre) > 0.35 * spacing;
    }
    if (!ok || !ft.insert(centre)) {
      failed.insert(tri_key(t));
      continue;
    }
    LocalPoint lp;
    lp.q = centre;
    lp.p = plane_.point(centre.x, centre.y);
    lp.bary = bary;
    pts.push_back(lp);
    ++added;
  }
}

void Driller::emit_polygon(FaceId f, const Triangle& tri, std::vector<LocalPoint>& pts,
                           const std::vector<std::vector<std::uint32_t>>& loops) {
  std::vector<glm::dvec2> q(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) q[i] = pts[i].q;
  std::vector<LocalTri> tris;
  if (loops.size() == 1 && loops[0].size() == 3) {
    tris.push_back({loops[0][0], loops[0][1], loops[0][2]});
  } else {
    FlipTriangulation ft(q, triangulate(q, loops));
    ft.make_delaunay();
    refine(ft, q, pts, loops);
    tris = ft.triangles();
  }
  for (auto& lp : pts) vertex_of(tri, lp);
  for (const auto& t : tris) {
    if (pts[t[0]].v == pts[t[1]].v || pts[t[1]].v == pts[t[2]].v || pts[t[0]].v == pts[t[2]].v) continue;  // merged tip
    editor_.add_face_from({pts[t[0]].v, pts[t[1]].v, pts[t[2]].v}, f,
                          {glm::vec3(pts[t[0]].bary), glm::vec3(pts[t[1]].bary), glm::vec3(pts[t[2]].bary)});
    ++added_;
  }
}

// Rim edges are found from the topology the edits left: boundary half-edges of the new faces
// whose ends lie on the cylinder. An edge between two old vertices is an edge of the parent
// triangle; it is a boundary only if the face across it was removed and not replaced there.
void Driller::collect_holes(DrillResult& result) {
  // Half-edges of the added and of the removed faces, as sorted lists (only membership matters).
  std::vector<std::uint64_t> added, removed;
  auto directed = [](VertexId a, VertexId b) { return (std::uint64_t(a.index) << 32) | b.index; };
  for (const Edit& e : editor_.log().edits) {
    if (const auto* fa = std::get_if<FaceAdded>(&e)) {
      for (int k = 0; k < 3; ++k) added.push_back(directed(fa->vertices[k], fa->vertices[(k + 1) % 3]));
    } else if (const auto* fr = std::get_if<FaceRemoved>(&e)) {
      for (int k = 0; k < 3; ++k) removed.push_back(directed(fr->vertices[k], fr->vertices[(k + 1) % 3]));
    }
  }
  std::sort(added.begin(), added.end());
  std::sort(removed.begin(), removed.end());
  auto contains = [](const std::vector<std::uint64_t>& list, std::uint64_t key) {
    return std::binary_search(list.begin(), list.end(), key);
  };
  // A copy the pinch split made of an old vertex is new, but the faces moved onto it keep their
  // old edges: both are judged by the original (an old boundary edge at a split vertex is not rim).
  auto base = [&](VertexId v) {
    const auto it = copy_of_.find(v.index);
    return it == copy_of_.end() ? v : VertexId(it->second);
  };
  auto on_rim = [&](VertexId v) {
    v = base(v);
    return v.index >= first_new_ || std::abs(cyl_.sd(posed(v))) <= 2.0 * eps_;
  };
  // Faces the drill left alone can border the hole too: an old edge that lies on the cylinder
  // (within the tolerance) between a removed face and an untouched one.
  std::vector<std::uint64_t> untouched;
  for (FaceId f : candidates_)
    if (!mesh_.is_deleted(f)) {
      const Triangle& t = mesh_.face(f);
      for (int k = 0; k < 3; ++k) untouched.push_back(directed(t[k], t[(k + 1) % 3]));
    }
  std::sort(untouched.begin(), untouched.end());
  auto consider = [&](VertexId a, VertexId b) {
    if (!on_rim(a) || !on_rim(b) || contains(added, directed(b, a)) || contains(untouched, directed(b, a))) return;
    const VertexId oa = base(a), ob = base(b);
    if (oa.index < first_new_ && ob.index < first_new_ && !contains(removed, directed(ob, oa))) return;
    rim_next_[a.index].push_back(b.index);
  };
  for (const Edit& e : editor_.log().edits) {
    const auto* fa = std::get_if<FaceAdded>(&e);
    if (!fa || mesh_.is_deleted(fa->f)) continue;
    for (int k = 0; k < 3; ++k) consider(fa->vertices[k], fa->vertices[(k + 1) % 3]);
  }
  for (FaceId f : candidates_)
    if (!mesh_.is_deleted(f)) {
      const Triangle t = mesh_.face(f);
      for (int k = 0; k < 3; ++k) consider(t[k], t[(k + 1) % 3]);
    }
  std::unordered_map<std::uint32_t, int> indegree;
  for (const auto& [v, next] : rim_next_)
    for (auto w : next) ++indegree[w];
  std::vector<std::uint32_t> starts;
  for (const auto& [v, next] : rim_next_) starts.push_back(v);
  std::sort(starts.begin(), starts.end());
  // Open chains first (from vertices nothing leads to), then closed loops.
  std::stable_partition(starts.begin(), starts.end(), [&](std::uint32_t v) { return indegree[v] == 0; });
  // Where several rims meet at one vertex (a vertex on the cylinder whose surface the hole pinches,
  // or two holes touching there), each incoming rim edge continues with the outgoing one of its
  // own fan: turning around the vertex through the kept faces from the incoming edge's face to
  // the next boundary edge. Pairing them otherwise crosses the rims there (they cannot be walled,
  // and after the pinch split the rim would jump between the vertex's copies).
  std::unordered_map<std::uint64_t, std::uint32_t> third;  // half-edge a->b of a kept face: its third corner
  auto add_face = [&](const Triangle& t) {
    for (int k = 0; k < 3; ++k) third[directed(t[k], t[(k + 1) % 3])] = t[(k + 2) % 3].index;
  };
  for (const Edit& e : editor_.log().edits)
    if (const auto* fa = std::get_if<FaceAdded>(&e))
      if (!mesh_.is_deleted(fa->f)) add_face(mesh_.face(fa->f));
  for (FaceId f : candidates_)
    if (!mesh_.is_deleted(f)) add_face(mesh_.face(f));
  std::unordered_map<std::uint32_t, std::vector<char>> used;  // per outgoing rim edge
  for (const auto& [v, next] : rim_next_) used[v].assign(next.size(), 0);
  // The outgoing rim edge of `cur` in the fan of prev->cur (used or not; -1 when the faces
  // around do not say).
  auto fan_next = [&](std::uint32_t prev, std::uint32_t cur) -> int {
    const auto& next = rim_next_[cur];
    std::uint32_t from = prev;  // turn from the face holding prev->cur
    for (std::size_t guard = 0; guard < 256; ++guard) {
      const auto it = third.find(directed(VertexId(from), VertexId(cur)));
      if (it == third.end()) return -1;
      const std::uint32_t out = it->second;  // cur->out is the next half-edge of that face
      int found = -1;
      for (std::size_t i = 0; i < next.size(); ++i)
        if (next[i] == out && (found < 0 || !used[cur][i])) found = static_cast<int>(i);
      if (found >= 0) return found;
      if (out == prev) return -1;  // went all the way round
      from = out;  // across cur->out to the face holding out->cur
    }
    return -1;
  };
  for (std::uint32_t s : starts) {
    for (std::size_t first = 0; first < rim_next_[s].size(); ++first) {
      if (used[s][first]) continue;
      used[s][first] = 1;
      DrillHole hole;
      hole.rim.push_back(VertexId(s));
      std::uint32_t prev = s, cur = rim_next_[s][first];
      hole.closed = false;
      while (true) {
        const auto it = rim_next_.find(cur);
        const int fan = it == rim_next_.end() ? -1 : fan_next(prev, cur);
        if (cur == s && (fan < 0 || fan == static_cast<int>(first))) {  // back through the start's own fan
          hole.closed = true;
          break;
        }
        hole.rim.push_back(VertexId(cur));
        if (it == rim_next_.end()) break;
        int i = fan >= 0 && !used[cur][static_cast<std::size_t>(fan)] ? fan : -1;
        for (std::size_t j = 0; j < it->second.size() && i < 0; ++j)
          if (!used[cur][j]) i = static_cast<int>(j);
        if (i < 0) break;
        used[cur][static_cast<std::size_t>(i)] = 1;
        prev = cur;
        cur = it->second[static_cast<std::size_t>(i)];
      }
      if (hole.closed) {
        double turn = 0.0;
        for (std::size_t i = 0; i < hole.rim.size(); ++i) {
          const double a = cyl_.theta(posed(hole.rim[i])),
                       b = cyl_.theta(posed(hole.rim[(i + 1) % hole.rim.size()]));
          double dth = b - a;
          while (dth > kPi) dth -= 2.0 * kPi;
          while (dth < -kPi) dth += 2.0 * kPi;
          turn += dth;
        }
        hole.winding = static_cast<int>(std::lround(turn / (2.0 * kPi)));
      }
      result.holes.push_back(std::move(hole));
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Walls

VertexId Driller::wall_vertex(VertexId a, VertexId b, float t, const glm::dvec3& p) {
  const VertexId v = editor_.add_vertex_on_edge(a, b, t);
  added_posed_.push_back(p);
  const glm::vec3 bind = unpose_ ? unpose_(mesh_, v, glm::vec3(p)) : glm::vec3(p);
  editor_.move_vertex(v, bind);
  return v;
}

FaceId Driller::wall_face(const Triangle& t, int kind) {
  const FaceId f = editor_.add_face(t);
  wall_faces_.emplace_back(f, kind);
  ++added_;
  return f;
}


// Angle at `c` in the triangle (a, b, c), in 3D.
double angle_at(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 u = a - c, v = b - c;
  const double lu = glm::length(u), lv = glm::length(v);
  if (!(lu > 0.0) || !(lv > 0.0)) return kPi;
  return std::acos(std::clamp(glm::dot(u, v) / (lu * lv), -1.0, 1.0));
}

// Lawson flips on a curved surface (the cylinder): an interior edge whose opposite angles sum
// to more than pi is flipped when the two new triangles keep the orientation, so the plane
// map's distortion (compressed along the axis on long walls) leaves no needles. Edges with one
// triangle (the rims) are constraints; `forbidden` says whether a new edge may not be made.
template <class Forbidden>
void flip_on_surface(std::vector<LocalTri>& tris, const std::vector<glm::dvec3>& p, const Forbidden& forbidden) {
  auto key = [](std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; };
  std::unordered_map<std::uint64_t, std::uint32_t> half;  // directed edge -> triangle
  half.reserve(3 * tris.size());
  for (std::uint32_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) half[key(tris[t][k], tris[t][(k + 1) % 3])] = t;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> stack;
  for (const auto& tri : tris)
    for (int k = 0; k < 3; ++k) stack.emplace_back(tri[k], tri[(k + 1) % 3]);
  std::size_t guard = 50 * tris.size() + 100;
  while (!stack.empty() && guard-- > 0) {
    const auto [a, b] = stack.back();
    stack.pop_back();
    const auto i1 = half.find(key(a, b)), i2 = half.find(key(b, a));
    if (i1 == half.end() || i2 == half.end()) continue;
    const std::uint32_t t1 = i1->second, t2 = i2->second;
    if (t1 == t2) continue;
    std::uint32_t c = 0, d = 0;
    for (int k = 0; k < 3; ++k) {
      if (tris[t1][k] != a && tris[t1][k] != b) c = tris[t1][k];
      if (tris[t2][k] != a && tris[t2][k] != b) d = tris[t2][k];
    }
    if (c == d || half.count(key(c, d)) || half.count(key(d, c)) || forbidden(c, d)) continue;
    if (angle_at(p[a], p[b], p[c]) + angle_at(p[a], p[b], p[d]) <= kPi + 1e-9) continue;
    // On a curved surface both diagonals of a quad can fail the test: flip only to one that
    // passes it, or the two would be flipped back and forth until the guard.
    if (angle_at(p[c], p[d], p[a]) + angle_at(p[c], p[d], p[b]) >= kPi - 1e-9) continue;
    const glm::dvec3 n_old = glm::cross(p[b] - p[a], p[c] - p[a]) + glm::cross(p[a] - p[b], p[d] - p[b]);
    const glm::dvec3 n1 = glm::cross(p[d] - p[a], p[c] - p[a]), n2 = glm::cross(p[b] - p[d], p[c] - p[d]);
    if (glm::dot(n1, n_old) <= 0.0 || glm::dot(n2, n_old) <= 0.0) continue;
    for (std::uint32_t t : {t1, t2})
      for (int k = 0; k < 3; ++k) half.erase(key(tris[t][k], tris[t][(k + 1) % 3]));
    tris[t1] = {a, d, c};
    tris[t2] = {d, b, c};
    for (std::uint32_t t : {t1, t2})
      for (int k = 0; k < 3; ++k) half[key(tris[t][k], tris[t][(k + 1) % 3])] = t;
    stack.insert(stack.end(), {{a, d}, {d, c}, {c, a}, {d, b}, {b, c}});
  }
}

// Winding number of closed loops (indices into `xy`) around `p`.
int winding(const std::vector<glm::dvec2>& xy, const std::vector<std::vector<std::uint32_t>>& loops,
            const glm::dvec2& p) {
  int w = 0;
  for (const auto& l : loops)
    for (std::size_t i = 0; i < l.size(); ++i) {
      const glm::dvec2 &a = xy[l[i]], &b = xy[l[(i + 1) % l.size()]];
      if (a.y <= p.y) {
        if (b.y > p.y && orient(a, b, p) > 0.0) ++w;
      } else if (b.y <= p.y && orient(a, b, p) < 0.0) {
        --w;
      }
    }
  return w;
}

double segment_distance2(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 e = b - a;
  const double t = std::clamp(glm::dot(p - a, e) / std::max(glm::dot(e, e), 1e-300), 0.0, 1.0);
  const glm::dvec3 d = a + t * e - p;
  return glm::dot(d, d);
}

// How far apart two vertices' skins are: half the L1 distance of their joint weights (0 for the
// same influences, 1 for disjoint ones; 0 without a skin).
double skin_change(const SurfaceMesh& mesh, VertexId a, VertexId b) {
  const auto& va = mesh.vertex_attrs();
  std::array<std::pair<std::uint16_t, float>, 16> diff;
  std::size_t n = 0;
  const char* names[2][2] = {{attr::kJoints0, attr::kWeights0}, {attr::kJoints1, attr::kWeights1}};
  for (const auto& pair : names) {
    const auto* j = va.find<glm::u16vec4>(pair[0]);
    const auto* w = va.find<glm::vec4>(pair[1]);
    if (!j || !w) break;
    for (int side = 0; side < 2; ++side) {
      const VertexId v = side == 0 ? a : b;
      for (int c = 0; c < 4; ++c) {
        const float weight = (side == 0 ? 1.0f : -1.0f) * (*w)[v.index][c];
        if (weight == 0.0f) continue;
        const std::uint16_t joint = (*j)[v.index][c];
        std::size_t i = 0;
        while (i < n && diff[i].first != joint) ++i;
        if (i == n) diff[n++] = {joint, 0.0f};
        diff[i].second += weight;
      }
    }
  }
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) sum += std::abs(diff[i].second);
  return 0.5 * sum;
}


// The wall of one closed shell is the part of the cylinder's surface (side and both end disks)
// inside that shell, bounded by the shell's rims. The surface is mapped to one plane:
// z = exp(l) (cos theta, sin theta), with l = (s - base) / (r kappa) on the side, and the end
// disks continuing it conformally (l - l_A = ln(rho / r) on the disk at A, l_B - l = ln(rho / r)
// at B, whose centre goes to infinity). The rims become closed loops there, the region inside
// the shell is where their winding number plus a constant is 1, and it is triangulated as outer
// loops with holes (a Moebius map first brings the centre of the B disk in from infinity when it
// lies inside). Steiner points on a grid of the rim spacing over the side and on rings over the
// disks keep the triangles small and well shaped (the map is conformal for kappa = 1).
bool Driller::wall_shell(const std::vector<std::size_t>& hole_ids, const DrillResult& result, bool open_shell,
                         std::vector<char>& walled_ok) {
  // The end disk whose rims are mapped without distortion is the one at A: when more rim
  // vertices lie on the disk at B, the wall is built in the reversed frame (B to A).
  const double tol = 2.0 * eps_;
  int at_a = 0, at_b = 0;
  for (std::size_t h : hole_ids)
    for (VertexId v : result.holes[h].rim) {
      const double sv = cyl_.s(posed(v));
      at_a += std::abs(sv) <= tol;
      at_b += std::abs(sv - cyl_.len) <= tol;
    }
  Frame reversed = cyl_;
  reversed.a = cyl_.a + cyl_.len * cyl_.d;
  reversed.d = -cyl_.d;
  reversed.w = -cyl_.w;
  const Frame& cy = at_b > at_a ? reversed : cyl_;
  std::vector<WallPt> pts;
  std::vector<std::vector<std::uint32_t>> rim_loops;
  std::vector<std::size_t> loop_hole;  // the hole each loop comes from
  auto classify = [&](const glm::dvec3& p, WallPt& w) {
    w.p = p;
    w.s = cy.s(p);
    const double rho = cy.rho(p);
    w.rho = rho;
    w.theta = cy.theta(p);
    w.where = 0;
    if (rho < cy.r - tol) {
      if (std::abs(w.s) <= tol) w.where = 1;
      else if (std::abs(w.s - cy.len) <= tol) w.where = 2;
      else return false;  // neither on the side nor on an end disk
    } else if (std::abs(rho - cy.r) > tol || w.s < -tol || w.s > cy.len + tol) {
      return false;
    }
    return true;
  };
  double s_lo = kInf, s_hi = -kInf;
  for (std::size_t h : hole_ids) {
    const DrillHole& hole = result.holes[h];
    // The wall runs along each rim the other way. A rim that touches itself (a vertex on the
    // cylinder where two arcs of the rim meet) is split there into simple loops.
    std::vector<std::uint32_t> stack;
    std::unordered_map<std::uint32_t, std::size_t> at;  // vertex -> position in stack
    for (std::size_t i = hole.rim.size(); i-- > 0;) {
      const VertexId v = hole.rim[i];
      const auto seen = at.find(v.index);
      if (seen != at.end()) {
        const std::size_t first = seen->second;
        std::vector<std::uint32_t> loop(stack.begin() + static_cast<std::ptrdiff_t>(first), stack.end());
        for (std::size_t k = first + 1; k < stack.size(); ++k) at.erase(pts[stack[k]].v.index);
        stack.resize(first + 1);
        if (loop.size() >= 3) {
          rim_loops.push_back(std::move(loop));
          loop_hole.push_back(h);
        }
        continue;
      }
      WallPt w;
      if (!classify(posed(v), w)) return false;
      w.v = v;
      s_lo = std::min(s_lo, std::clamp(w.s, 0.0, cy.len));
      s_hi = std::max(s_hi, std::clamp(w.s, 0.0, cy.len));
      at[v.index] = stack.size();
      stack.push_back(static_cast<std::uint32_t>(pts.size()));
      pts.push_back(w);
    }
    if (stack.size() >= 3) {
      rim_loops.push_back(std::move(stack));
      loop_hole.push_back(h);
    }
  }
  // The plane map (and its inverse, for points placed in the plane).
  double base = s_lo, kappa = std::max(1.0, (s_hi - s_lo) / (kWallSpan * cy.r));
  bool mobius = false;
  glm::dvec2 z0(0.0);
  auto l_a = [&] { return (0.0 - base) / (cy.r * kappa); };
  auto l_b = [&] { return (cy.len - base) / (cy.r * kappa); };
  auto to_plane = [&](const WallPt& w) {
    double l = (w.s - base) / (cy.r * kappa);
    if (w.where == 1) l = l_a() + std::log(std::max(w.rho, 1e-12 * cy.r) / cy.r);
    if (w.where == 2) l = l_b() - std::log(std::max(w.rho, 1e-12 * cy.r) / cy.r);
    glm::dvec2 z = std::exp(l) * glm::dvec2(std::cos(w.theta), std::sin(w.theta));
    if (w.where == 1 && w.rho <= 0.0) z = glm::dvec2(0.0);
    if (mobius) {
      const glm::dvec2 d = z - z0;
      z = glm::dvec2(d.x, -d.y) / glm::dot(d, d);
    }
    return z;
  };
  auto from_plane = [&](glm::dvec2 z) {
    if (mobius) z = z0 + glm::dvec2(z.x, -z.y) / glm::dot(z, z);
    WallPt w;
    w.theta = std::atan2(z.y, z.x);
    const double l = std::log(glm::length(z));
    if (l < l_a()) {
      w.where = 1;
      w.s = 0.0;
      w.rho = cy.r * std::exp(l - l_a());
    } else if (l > l_b()) {
      w.where = 2;
      w.s = cy.len;
      w.rho = cy.r * std::exp(l_b() - l);
    } else {
      w.s = base + cy.r * kappa * l;
      w.rho = cy.r;
    }
    w.p = cy.a + w.s * cy.d + w.rho * cy.ruling(w.theta);
    return w;
  };
  std::vector<glm::dvec2> xy;
  auto map_loops = [&] {
    xy.clear();
    for (const auto& w : pts) xy.push_back(to_plane(w));
  };
  map_loops();
  // A rim crosses itself on the cylinder where the posed surface passes through itself (a skin
  // folding at a joint: CesiumMan seed 1 step 247, Fox seed 5 step 132 once the wall needles
  // were refined). No wall lying on the cylinder can close it, so the wall folds with the
  // surface: where steps a->b and c->d cross, the loop is short-cut by a->d, and the lobe cut
  // off (b ... c, the shorter side) is closed by the triangles (a, b, c), (a, c, d) and a fan
  // from b over the lobe, all in the loop's direction (closed and consistently oriented; it
  // overlaps itself there as the surface does).
  // The wall maps the loops again per sheet (over its own extent), where a fold can show that
  // the first map did not: each map is folded (`emit` gets the loop and the lobe's triangles).
  auto fold = [&](std::vector<std::vector<std::uint32_t>>& loops_to_fold, auto&& emit) -> bool {
  for (int fold_round = 0; fold_round < 8; ++fold_round) {
    bool found = false;
    for (std::size_t li = 0; li < loops_to_fold.size() && !found; ++li) {
      auto& l = loops_to_fold[li];
      const std::size_t m = l.size();
      for (std::size_t i = 0; i < m && !found; ++i)
        for (std::size_t j = i + 2; j < m && !found; ++j) {
          if ((j + 1) % m == i) continue;
          const std::uint32_t a = l[i], b = l[(i + 1) % m], c = l[j], d = l[(j + 1) % m];
          if (a == c || a == d || b == c || b == d) continue;
          const double d1 = orient(xy[a], xy[b], xy[c]), d2 = orient(xy[a], xy[b], xy[d]);
          const double d3 = orient(xy[c], xy[d], xy[a]), d4 = orient(xy[c], xy[d], xy[b]);
          if (!(((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))) continue;
          found = true;
          // Steps i (a->b) and j (c->d); the lobe is b..c (positions i+1..j) or d..a (j+1..i).
          std::size_t first = i, second = j;
          if (j - i > m - (j - i)) std::swap(first, second);
          const std::uint32_t fa = l[first], fb = l[(first + 1) % m], fc = l[second], fd = l[(second + 1) % m];
          if (m - ((second + m - first) % m) < 3) return false;  // nothing would be left of the loop
          emit(li, LocalTri{fa, fb, fc});
          emit(li, LocalTri{fa, fc, fd});
          for (std::size_t k = (first + 1) % m; (k + 1) % m != second; k = (k + 1) % m)
            emit(li, LocalTri{fb, l[(k + 1) % m], l[(k + 2) % m]});
          std::vector<std::uint32_t> kept;
          for (std::size_t k = (second + 1) % m;; k = (k + 1) % m) {
            kept.push_back(l[k]);
            if (k == first) break;
          }
          l = std::move(kept);
        }
    }
    if (!found) break;
  }
  return true;
  };
  std::vector<std::pair<std::size_t, LocalTri>> lobe_tris;  // loop, triangle (indices into pts)
  if (!fold(rim_loops, [&](std::size_t li, const LocalTri& t) { lobe_tris.push_back({li, t}); })) return false;
  // Loops of one shell never cross, unless the shell intersects itself (a limb modelled into
  // the body): then the loops form two sheets, each walled on its own (crossing loops go to
  // different sheets; the others to the first sheet they are consistent with, largest first).
  std::vector<std::size_t> seg_loop;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> all_segments;
  for (std::size_t li = 0; li < rim_loops.size(); ++li)
    for (std::size_t i = 0; i < rim_loops[li].size(); ++i) {
      all_segments.emplace_back(rim_loops[li][i], rim_loops[li][(i + 1) % rim_loops[li].size()]);
      seg_loop.push_back(li);
    }
  std::vector<std::vector<std::size_t>> crossing(rim_loops.size());
  for (std::size_t i = 0; i < all_segments.size(); ++i)
    for (std::size_t j = i + 1; j < all_segments.size(); ++j) {
      const auto [a, b] = all_segments[i];
      const auto [c, d] = all_segments[j];
      if (a == c || a == d || b == c || b == d) continue;
      const double d1 = orient(xy[a], xy[b], xy[c]), d2 = orient(xy[a], xy[b], xy[d]);
      const double d3 = orient(xy[c], xy[d], xy[a]), d4 = orient(xy[c], xy[d], xy[b]);
      if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) {
        if (seg_loop[i] == seg_loop[j]) return false;  // a loop crossing itself
        crossing[seg_loop[i]].push_back(seg_loop[j]);
        crossing[seg_loop[j]].push_back(seg_loop[i]);
      }
    }
  auto side_point = [&](std::uint32_t a, std::uint32_t b, double offset) {
    const glm::dvec2 e = xy[b] - xy[a];
    return 0.5 * (xy[a] + xy[b]) + offset * glm::dvec2(-e.y, e.x);
  };
  auto longest_step = [&](const std::vector<std::uint32_t>& l) {
    std::size_t best = 0;
    double len2 = -1.0;
    for (std::size_t i = 0; i < l.size(); ++i) {
      const glm::dvec2 e = xy[l[(i + 1) % l.size()]] - xy[l[i]];
      if (glm::dot(e, e) > len2) {
        len2 = glm::dot(e, e);
        best = i;
      }
    }
    return best;
  };
  // Inside a sheet: winding + c == 1 just left of every rim step, 0 just right of it.
  auto consistent = [&](const std::vector<std::vector<std::uint32_t>>& ls, int& c) {
    for (std::size_t li = 0; li < ls.size(); ++li) {
      const auto& l = ls[li];
      const std::size_t i = longest_step(l);
      const std::uint32_t a = l[i], b = l[(i + 1) % l.size()];
      const int left = winding(xy, ls, side_point(a, b, 1e-6)), right = winding(xy, ls, side_point(a, b, -1e-6));
      if (left - right != 1) return false;
      if (li == 0) c = 1 - left;
      else if (left + c != 1) return false;
    }
    return true;
  };
  std::vector<int> sheet(rim_loops.size(), -1);
  for (std::size_t li = 0; li < rim_loops.size(); ++li) {
    if (sheet[li] >= 0 || crossing[li].empty()) continue;
    std::vector<std::size_t> queue = {li};
    sheet[li] = 0;
    for (std::size_t qi = 0; qi < queue.size(); ++qi)
      for (std::size_t other : crossing[queue[qi]]) {
        if (sheet[other] < 0) {
          sheet[other] = 1 - sheet[queue[qi]];
          queue.push_back(other);
        } else if (sheet[other] == sheet[queue[qi]]) {
          return false;  // three sheets through one spot
        }
      }
  }
  std::vector<std::size_t> free_loops;
  for (std::size_t li = 0; li < rim_loops.size(); ++li)
    if (sheet[li] < 0) free_loops.push_back(li);
  std::sort(free_loops.begin(), free_loops.end(), [&](std::size_t x, std::size_t y) {
    return std::abs(detail::signed_area2(xy, rim_loops[x])) > std::abs(detail::signed_area2(xy, rim_loops[y]));
  });
  auto sheet_loops = [&](int k, std::size_t extra) {
    std::vector<std::vector<std::uint32_t>> ls;
    for (std::size_t li = 0; li < rim_loops.size(); ++li)
      if (sheet[li] == k || li == extra) ls.push_back(rim_loops[li]);
    return ls;
  };
  for (std::size_t li : free_loops) {
    int c = 0;
    for (int k = 0; k < 2 && sheet[li] < 0; ++k)
      if (consistent(sheet_loops(k, li), c)) sheet[li] = k;
    if (sheet[li] < 0) return false;
  }
  // One sheet's region, triangulated and added (nothing is added when it returns false).
  auto wall_sheet = [&](const std::vector<std::vector<std::uint32_t>>& sheet_loops_in, int sheet_id) -> bool {
  std::vector<std::vector<std::uint32_t>> loops = sheet_loops_in;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> segments;
  for (const auto& l : loops)
    for (std::size_t i = 0; i < l.size(); ++i) segments.emplace_back(l[i], l[(i + 1) % l.size()]);
  double smin = kInf, smax = -kInf;
  for (const auto& l : loops)
    for (auto i : l) {
      smin = std::min(smin, std::clamp(pts[i].s, 0.0, cy.len));
      smax = std::max(smax, std::clamp(pts[i].s, 0.0, cy.len));
    }
  base = s_lo;
  kappa = std::max(1.0, (s_hi - s_lo) / (kWallSpan * cy.r));
  mobius = false;
  map_loops();
  int c = 0;
  if (!consistent(loops, c)) return false;
  // Which end disks the region reaches; then the final map over that extent.
  const bool a_inside = winding(xy, loops, glm::dvec2(0.0)) + c == 1;
  const bool b_inside = c == 1;
  // A shell with a boundary of its own (an open sheet, a torn part) has no inside: its rims'
  // orientation still picks a side, but a region holding an end disk's centre is then a cup out
  // to that end, or the whole cylinder but a small patch where a rim does not go around the
  // axis (56 of them in one drill of a torn CesiumMan, 131 000 triangles). Such a shell gets
  // tubes between its rims only.
  if (open_shell && (a_inside || b_inside)) return false;
  bool touches_a = a_inside, touches_b = b_inside;
  for (const auto& l : loops)
    for (auto i : l) {
      touches_a |= pts[i].where == 1 || pts[i].s <= tol;
      touches_b |= pts[i].where == 2 || pts[i].s >= cy.len - tol;
    }
  const double lo = touches_a ? 0.0 : smin, hi = touches_b ? cy.len : smax;
  base = lo;
  kappa = std::max(1.0, (hi - lo) / (kWallSpan * cy.r));
  map_loops();
  if (b_inside) {  // bring infinity (the B disk's centre) in: a point outside the shell goes there
    bool found = false;
    for (std::size_t li = 0; li < loops.size() && !found; ++li) {
      const auto& l = loops[li];
      const std::size_t i = longest_step(l);
      const std::uint32_t a = l[i], b = l[(i + 1) % l.size()];
      for (double offset : {-0.3, -0.1, -0.03, -0.01}) {
        const glm::dvec2 z = side_point(a, b, offset);
        if (winding(xy, loops, z) + c != 0) continue;
        const double e2 = glm::dot(xy[b] - xy[a], xy[b] - xy[a]);
        bool clear = true;
        for (const auto& [u, v] : segments) {
          const glm::dvec2 e = xy[v] - xy[u];
          const double t = std::clamp(glm::dot(z - xy[u], e) / std::max(glm::dot(e, e), 1e-300), 0.0, 1.0);
          const glm::dvec2 q = xy[u] + t * e - z;
          if (glm::dot(q, q) < 0.25 * offset * offset * e2) clear = false;
        }
        if (!clear) continue;
        z0 = z;
        found = true;
        break;
      }
    }
    if (!found) return false;
    mobius = true;
    map_loops();
  }
  std::vector<LocalTri> sheet_lobes;
  if (!fold(loops, [&](std::size_t, const LocalTri& t) { sheet_lobes.push_back(t); })) return false;
  // Outer loops (counter-clockwise now) and the holes each one holds.
  std::vector<double> area(loops.size());
  std::vector<std::size_t> outers;
  for (std::size_t i = 0; i < loops.size(); ++i) {
    area[i] = detail::signed_area2(xy, loops[i]);
    if (area[i] > 0.0) outers.push_back(i);
  }
  std::vector<std::vector<std::size_t>> holes_of(loops.size());
  for (std::size_t hidx = 0; hidx < loops.size(); ++hidx) {
    if (area[hidx] > 0.0) continue;
    std::size_t owner = loops.size();
    for (std::size_t o : outers) {
      // Judged at a corner of the hole that is not on the outer loop: rims can touch at a vertex
      // on the cylinder, where the winding number is that of the boundary (0 or 1 by rounding).
      std::size_t probe = loops[hidx].size();
      for (std::size_t i = 0; i < loops[hidx].size() && probe == loops[hidx].size(); ++i) {
        const WallPt& w = pts[loops[hidx][i]];
        bool shared = false;
        for (auto j : loops[o]) shared |= pts[j].v == w.v || xy[j] == xy[loops[hidx][i]];
        if (!shared) probe = i;
      }
      if (probe == loops[hidx].size()) continue;
      if (winding(xy, {loops[o]}, xy[loops[hidx][probe]]) != 0 && (owner == loops.size() || area[o] < area[owner]))
        owner = o;
    }
    if (owner == loops.size()) return false;
    holes_of[owner].push_back(hidx);
  }
  // Steiner candidates on the cylinder's surface, away from the rims.
  const double h = 2.0 * kPi * cy.r / samples_, row = 0.866 * h;
  auto near_boundary = [&](const glm::dvec3& p) {
    for (const auto& [u, v] : segments)
      if (segment_distance2(p, pts[u].p, pts[v].p) < 0.2 * h * h) return true;
    return false;
  };
  std::vector<WallPt> candidates;
  auto consider = [&](WallPt w) {
    w.p = cy.a + w.s * cy.d + w.rho * cy.ruling(w.theta);
    if (!near_boundary(w.p)) candidates.push_back(w);
  };
  // Rows of side points: the end circles, then staggered rings. Next to the rims (and end
  // circles) rings have a rim spacing between points and rows are a spacing apart; away from
  // them both grow geometrically, the rings down to kWallSides points and the rows up to
  // kWallAspect of the ring spacing apart. Rows closer than that come only from the skin: where
  // the weights of the rims on either side of a stretch differ, kWallBend of change per row.
  // A straight wall in one bone costs its rims' rows plus a few triangles per radius of length,
  // whatever the rim count (a drill with 48 rim edges had rows every 0.8 r: 120 triangles per r).
  std::vector<std::pair<double, VertexId>> features;  // s of every rim point on the side, end circles
  for (const auto& l : loops)
    for (auto i : l)
      if (pts[i].where == 0) features.emplace_back(std::clamp(pts[i].s, 0.0, cy.len), pts[i].v);
  if (touches_a) features.emplace_back(0.0, VertexId());
  if (touches_b) features.emplace_back(cy.len, VertexId());
  std::sort(features.begin(), features.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  auto after = [&](double sv) {
    return std::lower_bound(features.begin(), features.end(), sv,
                            [](const auto& f, double x) { return f.first < x; });
  };
  auto gap = [&](double sv) {
    const auto it = after(sv);
    double g = kInf;
    if (it != features.end()) g = it->first - sv;
    if (it != features.begin()) g = std::min(g, sv - std::prev(it)->first);
    return g;
  };
  auto bend = [&](double sv) {  // the widest row step the skins on either side allow
    const auto it = after(sv);
    if (it == features.begin() || it == features.end() || !it->second.valid() || !std::prev(it)->second.valid())
      return kInf;
    const double change = skin_change(mesh_, std::prev(it)->second, it->second);
    return change > 0.0 ? (it->first - std::prev(it)->first) / std::ceil(change / kWallBend) : kInf;
  };
  const int fewest = std::min(samples_, kWallSides);
  const double widest_ring = 2.0 * kPi * cy.r / fewest;
  auto ring_spacing = [&](double sv) { return std::clamp(0.2 * gap(sv), h, widest_ring); };
  std::vector<double> rows;
  if (touches_a) rows.push_back(0.0);
  for (double sv = lo + 0.5 * row; sv <= hi - (touches_b ? 0.4 * row : 0.0) && rows.size() < 2 * kWallRows;) {
    rows.push_back(sv);
    const double grown = std::min({0.45 * gap(sv), kWallAspect * ring_spacing(sv), bend(sv)});
    sv += std::max({row, (hi - lo) / kWallRows, grown});
  }
  if (touches_b) rows.push_back(cy.len);
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const bool end_circle = (touches_a && rows[j] == 0.0) || (touches_b && rows[j] == cy.len);
    const int n = end_circle ? samples_
                             : std::clamp(static_cast<int>(std::lround(2.0 * kPi * cy.r / ring_spacing(rows[j]))),
                                          fewest, samples_);
    for (int k = 0; k < n; ++k) {
      WallPt w;
      w.theta = std::remainder((k + (j % 2 ? 0.5 : 0.0)) * 2.0 * kPi / n, 2.0 * kPi);
      w.s = rows[j];
      w.rho = cy.r;
      consider(w);
    }
  }
  for (int end = 1; end <= 2; ++end) {
    if (!(end == 1 ? touches_a : touches_b)) continue;
    // Rings a row apart (at most kWallRings of them), each with points a rim spacing apart.
    const double ring = std::max(row, cy.r / kWallRings);
    for (int j = 0;; ++j) {
      const double rho = cy.r - (j + 0.5) * ring;
      if (rho < 0.5 * ring) break;
      const int n = std::clamp(static_cast<int>(std::lround(2.0 * kPi * rho / std::max(h, ring))), 3, samples_);
      for (int k = 0; k < n; ++k) {
        WallPt w;
        w.where = end;
        w.theta = std::remainder(2.0 * kPi * (k + 0.5 * (j % 2)) / n, 2.0 * kPi);
        w.s = end == 1 ? 0.0 : cy.len;
        w.rho = rho;
        consider(w);
      }
    }
    if (end == 1) {  // the centre of the A disk (the B disk's is infinity, or the Moebius pole)
      WallPt w;
      w.where = 1;
      w.s = 0.0;
      w.rho = 0.0;
      w.theta = 0.0;
      consider(w);
    } else if (mobius) {
      WallPt w;
      w.where = 2;
      w.s = cy.len;
      w.rho = 0.0;
      w.theta = 0.0;
      w.p = cy.a + cy.len * cy.d;
      if (!near_boundary(w.p)) {
        w.pole = true;
        candidates.push_back(w);
      }
    }
  }
  // Surface edges between rim vertices: the wall must not reuse one as a diagonal.
  std::unordered_set<std::uint64_t> surface_edges;
  for (const Edit& e : editor_.log().edits)
    if (const auto* fa = std::get_if<FaceAdded>(&e))
      for (int k = 0; k < 3; ++k) surface_edges.insert(edge_key(fa->vertices[k], fa->vertices[(k + 1) % 3]));
  // Old faces the drill kept can join two rim vertices too (both within the tolerance of the
  // cylinder): their edges are as forbidden (random sequence SimpleSkin seed 20261982 step 221).
  for (FaceId f : candidates_)
    if (!mesh_.is_deleted(f))
      for (int k = 0; k < 3; ++k) surface_edges.insert(edge_key(mesh_.face(f)[k], mesh_.face(f)[(k + 1) % 3]));
  std::vector<std::uint8_t> taken(candidates.size(), 0);
  std::vector<LocalTri> wall_tris;  // indices into pts
  for (std::size_t o : outers) {
    std::vector<glm::dvec2> local = xy;  // FlipTriangulation appends Steiner points
    std::vector<std::uint32_t> global(xy.size());  // local point -> pts (loop points first)
    for (std::uint32_t i = 0; i < xy.size(); ++i) global[i] = i;
    std::vector<std::vector<std::uint32_t>> holes_local;
    for (std::size_t hidx : holes_of[o]) holes_local.push_back(loops[hidx]);
    std::sort(holes_local.begin(), holes_local.end(), [&](const auto& a, const auto& b) {
      double ma = -kInf, mb = -kInf;
      for (auto i : a) ma = std::max(ma, local[i].x);
      for (auto i : b) mb = std::max(mb, local[i].x);
      return ma > mb;
    });
    std::vector<std::uint32_t> poly = loops[o];
    for (std::size_t k = 0; k < holes_local.size(); ++k) {
      std::vector<std::vector<std::uint32_t>> others(holes_local.begin() + static_cast<std::ptrdiff_t>(k) + 1,
                                                     holes_local.end());
      poly = bridge(local, poly, holes_local[k], others);
    }
    std::vector<LocalTri> tris;
    clip_polygon(local, poly, tris);
    std::vector<std::vector<std::uint32_t>> region = {loops[o]};
    for (std::size_t hidx : holes_of[o]) region.push_back(loops[hidx]);
    FlipTriangulation ft(local, std::move(tris));
    ft.make_delaunay();
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      if (taken[i]) continue;
      const glm::dvec2 z = candidates[i].pole ? glm::dvec2(0.0) : to_plane(candidates[i]);
      if (!std::isfinite(z.x) || !std::isfinite(z.y) || winding(xy, region, z) != 1) continue;
      if (!ft.insert(z)) continue;
      taken[i] = 1;
      global.push_back(static_cast<std::uint32_t>(pts.size()));
      pts.push_back(candidates[i]);
    }
    // No wall diagonal may repeat a surface edge between two rim vertices (that edge would get
    // four faces): a point next to its midpoint makes the flips remove it.
    const std::size_t loop_points = xy.size();
    for (int pass = 0; pass < 8; ++pass) {
      bool changed = false;
      const auto tri_copy = ft.triangles();
      for (const auto& t : tri_copy) {
        for (int k = 0; k < 3 && !changed; ++k) {
          const std::uint32_t a = t[k], b = t[(k + 1) % 3], cc = t[(k + 2) % 3];
          if (a >= loop_points || b >= loop_points) continue;
          if (!surface_edges.count(edge_key(pts[global[a]].v, pts[global[b]].v))) continue;
          if (!ft.is_interior(a, b)) continue;
          const glm::dvec2 m = 0.5 * (local[a] + local[b]);
          const glm::dvec2 p = m + 0.01 * (local[cc] - m);
          if (ft.insert(p)) {
            WallPt w = from_plane(p);
            global.push_back(static_cast<std::uint32_t>(pts.size()));
            pts.push_back(w);
            changed = true;
          }
        }
        if (changed) break;
      }
      if (!changed) break;
    }
    // Rim vertices a hair apart (two surface edges crossing the cylinder next to each other: 97%
    // of the cactus' wall needles) make needles with any point a rim spacing away. Triangles at a
    // rim under kWallNeedle degrees (on the cylinder) get a point at their circumcentre in the plane when it
    // lies in the region and outside every rim step's diametral circle (no rim step is
    // encroached); repeated, the points grade down towards the short step. In passes, worst
    // first, skipping a triangle whose circumcircle holds a point this pass added (it is gone),
    // with a budget of points per rim point: the cost follows the needles.
    {
      std::vector<std::pair<std::uint32_t, std::uint32_t>> steps;
      for (const auto& l : region)
        for (std::size_t i = 0; i < l.size(); ++i) steps.emplace_back(l[i], l[(i + 1) % l.size()]);
      auto min_angle = [&](const LocalTri& t) {
        const glm::dvec3 &p0 = pts[global[t[0]]].p, &p1 = pts[global[t[1]]].p, &p2 = pts[global[t[2]]].p;
        return std::min({angle_at(p1, p2, p0), angle_at(p2, p0, p1), angle_at(p0, p1, p2)});
      };
      std::unordered_set<std::uint64_t> failed;
      auto tri_key = [](const LocalTri& t) {
        std::array<std::uint32_t, 3> k = {t[0], t[1], t[2]};
        std::sort(k.begin(), k.end());
        return (std::uint64_t(k[0]) << 42) ^ (std::uint64_t(k[1]) << 21) ^ k[2];
      };
      std::size_t budget = 2 * loop_points + 16;
      for (int pass = 0; pass < 12 && budget > 0; ++pass) {
        std::vector<std::pair<double, LocalTri>> skinny;
        for (const auto& t : ft.triangles()) {
          // At the rims only: elsewhere the plane map's compression (kappa) leaves triangles the
          // flips on the cylinder below make well shaped.
          if (t[0] >= loop_points && t[1] >= loop_points && t[2] >= loop_points) continue;
          const double angle = min_angle(t);
          if (angle < kWallNeedle && !failed.count(tri_key(t))) skinny.emplace_back(angle, t);
        }
        if (skinny.empty()) break;
        std::sort(skinny.begin(), skinny.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
        std::vector<glm::dvec2> added_now;
        for (const auto& [angle, t] : skinny) {
          if (budget == 0) break;
          const glm::dvec2 &p0 = local[t[0]], &p1 = local[t[1]], &p2 = local[t[2]];
          const glm::dvec2 ab = p1 - p0, ac = p2 - p0;
          const double d = 2.0 * (ab.x * ac.y - ab.y * ac.x);
          const glm::dvec2 centre = p0 + glm::dvec2(ac.y * glm::dot(ab, ab) - ab.y * glm::dot(ac, ac),
                                                   ab.x * glm::dot(ac, ac) - ac.x * glm::dot(ab, ab)) / d;
          if (!std::isfinite(centre.x) || !std::isfinite(centre.y)) {
            failed.insert(tri_key(t));
            continue;
          }
          const double radius = glm::length(p0 - centre);
          bool stale = false;
          for (const glm::dvec2& q : added_now) stale |= glm::length(q - centre) < radius;
          if (stale) continue;
          failed.insert(tri_key(t));
          bool ok = true;
          for (std::size_t i = 0; i < steps.size() && ok; ++i) {
            const glm::dvec2 &u = local[steps[i].first], &v = local[steps[i].second];
            ok = glm::length(centre - 0.5 * (u + v)) > 0.525 * glm::length(v - u);
          }
          if (!ok || winding(xy, region, centre) != 1 || !ft.insert(centre)) continue;
          added_now.push_back(centre);
          global.push_back(static_cast<std::uint32_t>(pts.size()));
          pts.push_back(from_plane(centre));
          --budget;
        }
        if (added_now.empty()) break;
      }
    }
    std::vector<LocalTri> sheet_tris;
    for (const auto& t : ft.triangles()) sheet_tris.push_back({global[t[0]], global[t[1]], global[t[2]]});
    std::vector<glm::dvec3> where3(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) where3[i] = pts[i].p;
    flip_on_surface(sheet_tris, where3, [&](std::uint32_t x, std::uint32_t y) {
      return pts[x].v.valid() && pts[y].v.valid() && surface_edges.count(edge_key(pts[x].v, pts[y].v)) > 0;
    });
    // The triangles must cover the region exactly: each step of its loops once, every other
    // edge once each way. Ear clipping can find no proper ear where rims run a hair apart in
    // the plane map and leave a gap: the sheet is then left open and its holes reported
    // unwalled rather than walled with a crack (cactus, random drill test seed 2, drill 1).
    {
      auto key = [](std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; };
      std::unordered_set<std::uint64_t> half, rim_steps;
      for (const auto& t : sheet_tris)
        for (int k = 0; k < 3; ++k)
          if (!half.insert(key(t[k], t[(k + 1) % 3])).second) return false;
      for (const auto& l : region)
        for (std::size_t i = 0; i < l.size(); ++i) rim_steps.insert(key(l[i], l[(i + 1) % l.size()]));
      for (const std::uint64_t e : half)
        if (!half.count(key(static_cast<std::uint32_t>(e), static_cast<std::uint32_t>(e >> 32))) && !rim_steps.count(e))
          return false;
      for (const std::uint64_t e : rim_steps)
        if (!half.count(e)) return false;
    }
    wall_tris.insert(wall_tris.end(), sheet_tris.begin(), sheet_tris.end());
  }
  if (wall_tris.empty()) return false;
  for (const auto& [li, t] : lobe_tris)
    if (sheet[li] == sheet_id) wall_tris.push_back(t);
  wall_tris.insert(wall_tris.end(), sheet_lobes.begin(), sheet_lobes.end());
  // A wall face may use an edge between two existing vertices only against the one face that
  // borders it (a rim edge): anything else (a diagonal along a kept surface edge, an edge an
  // earlier sheet used) would make the edge non-manifold, so the sheet is left open instead.
  {
    auto directed = [](VertexId a, VertexId b) { return (std::uint64_t(a.index) << 32) | b.index; };
    std::unordered_set<std::uint64_t> used;
    auto add_face_edges = [&](const Triangle& t) {
      for (int k = 0; k < 3; ++k) used.insert(directed(t[k], t[(k + 1) % 3]));
    };
    for (const Edit& e : editor_.log().edits)
      if (const auto* fa = std::get_if<FaceAdded>(&e))
        if (!mesh_.is_deleted(fa->f)) add_face_edges(mesh_.face(fa->f));
    for (FaceId f : candidates_)
      if (!mesh_.is_deleted(f)) add_face_edges(mesh_.face(f));
    std::unordered_set<std::uint64_t> mine;
    for (const auto& t : wall_tris)
      for (int k = 0; k < 3; ++k) {
        const VertexId a = pts[t[k]].v, b = pts[t[(k + 1) % 3]].v;
        if (!a.valid() || !b.valid()) continue;
        if (used.count(directed(a, b)) || !mine.insert(directed(a, b)).second) return false;
      }
  }
  // Create the new vertices (attributes from the nearest vertices of the two nearest rims) and
  // the faces.
  for (auto& w : pts) {
    if (!w.v.valid()) {
      double best[2] = {kInf, kInf};
      VertexId src[2];
      for (std::size_t h2 : hole_ids) {
        double d = kInf;
        VertexId v;
        for (VertexId rv : result.holes[h2].rim) {
          const glm::dvec3 q = posed(rv) - w.p;
          if (glm::dot(q, q) < d) {
            d = glm::dot(q, q);
            v = rv;
          }
        }
        if (d < best[0]) {
          best[1] = best[0];
          src[1] = src[0];
          best[0] = d;
          src[0] = v;
        } else if (d < best[1]) {
          best[1] = d;
          src[1] = v;
        }
      }
      if (!src[1].valid()) {
        src[1] = src[0];
        best[1] = best[0];
      }
      const double d0 = std::sqrt(best[0]), d1 = std::sqrt(best[1]);
      w.v = wall_vertex(src[0], src[1], static_cast<float>(d0 / std::max(d0 + d1, 1e-300)), w.p);
    }
    wall_coords_[w.v.index] = {w.theta, std::clamp(w.s, 0.0, cy.len), w.where, w.v};
  }
  // A kept surface triangle whose three corners all lie on the rim (an island on the cylinder)
  // would get its own mirror image as wall: both go instead.
  // Keyed by the sorted corner ids themselves: a packed 64-bit key would collide once vertex ids
  // pass 2^21, and the drill would then remove an unrelated face.
  std::map<std::array<std::uint32_t, 3>, FaceId> surface_tri;
  auto tri_key = [](VertexId x, VertexId y, VertexId z) {
    std::array<std::uint32_t, 3> k = {x.index, y.index, z.index};
    std::sort(k.begin(), k.end());
    return k;
  };
  for (const Edit& e : editor_.log().edits)
    if (const auto* fa = std::get_if<FaceAdded>(&e))
      if (!mesh_.is_deleted(fa->f)) surface_tri[tri_key(fa->vertices[0], fa->vertices[1], fa->vertices[2])] = fa->f;
  for (FaceId f : candidates_)
    if (!mesh_.is_deleted(f)) surface_tri[tri_key(mesh_.face(f)[0], mesh_.face(f)[1], mesh_.face(f)[2])] = f;
  for (const auto& t : wall_tris) {
    const auto twin = surface_tri.find(tri_key(pts[t[0]].v, pts[t[1]].v, pts[t[2]].v));
    if (twin != surface_tri.end() && !mesh_.is_deleted(twin->second)) {
      editor_.remove_face(twin->second);
      ++removed_;
      continue;
    }
    const int kind = pts[t[0]].where != 0 && pts[t[0]].where == pts[t[1]].where &&
                             pts[t[1]].where == pts[t[2]].where
                         ? 1
                         : 0;
    wall_face({pts[t[0]].v, pts[t[1]].v, pts[t[2]].v}, kind);
  }
  return true;
  };
  bool any = false;
  for (int k = 0; k < 2; ++k) {
    const auto ls = sheet_loops(k, rim_loops.size());
    if (ls.empty()) continue;
    const bool ok = wall_sheet(ls, k);
    for (std::size_t li = 0; li < rim_loops.size(); ++li)
      if (sheet[li] == k && !ok) walled_ok[loop_hole[li]] = false;
    any |= ok;
  }
  return any;
}



// Vertex groups of the connected surface sheets (union-find over the faces' corners).
std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}


// Walls close each shell separately: its rims (which never cross each other) bound the part of
// the cylinder's surface inside it. Rims of different shells (overlapping closed components, as
// the cactus' arms and trunk) may cross; each shell gets its own wall.
void Driller::build_walls(DrillResult& result) {
  if (result.holes.empty()) return;
  std::vector<std::uint32_t> parent(mesh_.vertex_count());
  for (std::uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
  mesh_.for_each_face([&](FaceId, const Triangle& t) {
    const std::uint32_t a = find_root(parent, t[0].index);
    for (int k = 1; k < 3; ++k) {
      const std::uint32_t b = find_root(parent, t[k].index);
      if (a != b) parent[b] = a;
    }
  });
  std::unordered_map<std::uint32_t, std::vector<std::size_t>> shells;
  for (std::size_t h = 0; h < result.holes.size(); ++h)
    shells[find_root(parent, result.holes[h].rim[0].index)].push_back(h);
  // Shells with a boundary other than this drill's rims: a directed edge of one of their faces
  // whose reverse no face has and that is not a rim step. The reverse is looked for among the
  // faces around the edge's first corner, from a flat vertex-to-face table (a counting sort over
  // the drilled shells' faces): O(their faces) in flat arrays. A hash set of every directed edge
  // took about 1.2 s of a walled drill on a 1M-triangle cactus.
  std::unordered_set<std::uint64_t> rim_steps;
  auto directed = [](VertexId a, VertexId b) { return (std::uint64_t(a.index) << 32) | b.index; };
  for (const DrillHole& hole : result.holes)
    for (std::size_t i = 0; i < hole.rim.size(); ++i) {
      const VertexId a = hole.rim[i], b = hole.rim[(i + 1) % hole.rim.size()];
      rim_steps.insert(directed(a, b));
      rim_steps.insert(directed(b, a));
    }
  const std::vector<Triangle>& faces = mesh_.faces();
  const std::size_t nv = mesh_.vertex_count();
  std::vector<char> drilled(nv, 0);  // by shell root
  constexpr std::uint32_t kNoShell = ~std::uint32_t{0};
  for (const auto& [root, ids] : shells) drilled[root] = 1;
  std::vector<std::uint32_t> shell_of(faces.size(), kNoShell);
  std::vector<std::uint32_t> first(nv + 1, 0);
  mesh_.for_each_face([&](FaceId f, const Triangle& t) {
    const std::uint32_t root = find_root(parent, t[0].index);
    if (!drilled[root]) return;
    shell_of[f.index] = root;
    for (VertexId v : t) ++first[v.index + 1];
  });
  for (std::size_t i = 0; i < nv; ++i) first[i + 1] += first[i];
  std::vector<std::uint32_t> around(first[nv]);
  {
    std::vector<std::uint32_t> next(first.begin(), first.end() - 1);
    for (std::uint32_t f = 0; f < faces.size(); ++f)
      if (shell_of[f] != kNoShell)
        for (VertexId v : faces[f]) around[next[v.index]++] = f;
  }
  auto has_reverse = [&](VertexId a, VertexId b) {  // some face has the directed edge b -> a
    for (std::uint32_t i = first[a.index]; i < first[a.index + 1]; ++i) {
      const Triangle& g = faces[around[i]];
      for (int k = 0; k < 3; ++k)
        if (g[k] == b && g[(k + 1) % 3] == a) return true;
    }
    return false;
  };
  std::vector<char> open(nv, 0);  // by shell root
  for (std::uint32_t f = 0; f < faces.size(); ++f) {
    const std::uint32_t root = shell_of[f];
    if (root == kNoShell || open[root]) continue;
    const Triangle& t = faces[f];
    for (int k = 0; k < 3 && !open[root]; ++k) {
      const VertexId a = t[k], b = t[(k + 1) % 3];
      if (!has_reverse(a, b) && !rim_steps.count(directed(a, b))) open[root] = 1;
    }
  }
  std::vector<char> walled_ok(result.holes.size(), 0);
  std::vector<std::uint32_t> order;
  for (const auto& [root, ids] : shells) order.push_back(root);
  std::sort(order.begin(), order.end());
  for (std::uint32_t root : order) {
    const auto& ids = shells[root];
    bool closed = true;
    for (std::size_t h : ids) closed &= result.holes[h].closed;
    if (!closed) continue;  // a rim merged with an older boundary: the shell was open already
    for (std::size_t h : ids) walled_ok[h] = 1;
    if (!wall_shell(ids, result, open[root] != 0, walled_ok))  // builds nothing when it returns false
      for (std::size_t h : ids) walled_ok[h] = 0;
  }
  for (std::size_t h = 0; h < result.holes.size(); ++h) result.holes[h].walled = walled_ok[h] != 0;
  finish_wall_attributes();
}


void Driller::finish_wall_attributes() {
  if (wall_faces_.empty()) return;
  auto* flag = mesh_.face_attrs().find<std::uint8_t>(attr::kCutSurface);
  if (!flag) flag = &mesh_.face_attrs().add<std::uint8_t>(attr::kCutSurface);
  auto& ca = mesh_.corner_attrs();
  auto* normals = ca.find<glm::vec3>(attr::kNormal);
  auto* tangents = ca.find<glm::vec4>(attr::kTangent);
  auto* colors = ca.find<glm::vec4>(attr::kColor0);
  std::vector<AttributeArray<glm::vec2>*> uvs;
  for (int set = 0; set < 8; ++set)
    if (auto* uv = ca.find<glm::vec2>(attr::uv_name(set))) uvs.push_back(uv);
  const auto& bind = mesh_.positions();
  // Smooth tube normals from the bind-space tube faces; disks are flat.
  std::unordered_map<std::uint32_t, glm::dvec3> tube_normal;
  for (const auto& [f, kind] : wall_faces_) {
    if (kind != 0) continue;
    const auto& t = mesh_.face(f);
    const glm::dvec3 n = glm::cross(glm::dvec3(bind[t[1].index] - bind[t[0].index]),
                                    glm::dvec3(bind[t[2].index] - bind[t[0].index]));
    for (auto v : t) tube_normal[v.index] += n;
  }
  const double circumference = 2.0 * kPi * cyl_.r;
  for (const auto& [f, kind] : wall_faces_) {
    (*flag)[f.index] = 1;
    const Triangle t = mesh_.face(f);
    glm::dvec2 uv[3];
    if (kind == 0) {
      double th[3];
      for (int k = 0; k < 3; ++k) th[k] = wall_coords_.at(t[k].index).theta;
      for (int k = 1; k < 3; ++k) th[k] = th[0] + std::remainder(th[k] - th[0], 2.0 * kPi);
      for (int k = 0; k < 3; ++k)
        uv[k] = {th[k] / (2.0 * kPi), wall_coords_.at(t[k].index).s / circumference};
    } else {
      for (int k = 0; k < 3; ++k) {
        const glm::dvec3 q = cyl_.perp(posed(t[k]));
        uv[k] = {0.5 + 0.5 * glm::dot(q, cyl_.u) / cyl_.r, 0.5 + 0.5 * glm::dot(q, cyl_.w) / cyl_.r};
      }
    }
    const glm::dvec3 p0(bind[t[0].index]), p1(bind[t[1].index]), p2(bind[t[2].index]);
    glm::dvec3 fn = glm::cross(p1 - p0, p2 - p0);
    fn = glm::length(fn) > 0.0 ? glm::normalize(fn) : -cyl_.d;
    // Tangent: the bind-space direction of increasing u.
    const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0;
    const glm::dvec2 d1 = uv[1] - uv[0], d2 = uv[2] - uv[0];
    const double det = d1.x * d2.y - d2.x * d1.y;
    glm::dvec3 tangent = std::abs(det) > 1e-300 ? (e1 * d2.y - e2 * d1.y) / det : e1;
    tangent -= fn * glm::dot(fn, tangent);
    tangent = glm::length(tangent) > 0.0 ? glm::normalize(tangent) : glm::normalize(e1);
    for (int k = 0; k < 3; ++k) {
      const auto c = SurfaceMesh::corner(f, k);
      for (auto* a : uvs) (*a)[c] = glm::vec2(uv[k]);
      if (normals) {
        glm::dvec3 n = fn;
        if (kind == 0) {
          const glm::dvec3 acc = tube_normal[t[k].index];
          if (glm::length(acc) > 0.0) n = glm::normalize(acc);
        }
        (*normals)[c] = glm::vec3(n);
      }
      if (tangents) (*tangents)[c] = glm::vec4(glm::vec3(tangent), 1.0f);
      if (colors) (*colors)[c] = glm::vec4(1.0f);
    }
  }
}

DrillResult Driller::run() {
  DrillResult result;
  result.first_new_vertex = first_new_;
  std::vector<FaceId>& candidates = candidates_;
  // Far enough to hold every face around a vertex snap_shallow_vertices may move.
  const double reach = cyl_.r + std::max(2.0 * eps_, (kSnapBand + 0.01) * 2.0 * cyl_.r * std::sin(kPi / samples_));
  auto near_axis = [&](const Triangle& t) {
    const glm::dvec3 p0 = posed(t[0]), p1 = posed(t[1]), p2 = posed(t[2]);
    const glm::dvec3 c = (p0 + p1 + p2) / 3.0;
    const double rad =
        std::sqrt(std::max({glm::dot(p0 - c, p0 - c), glm::dot(p1 - c, p1 - c), glm::dot(p2 - c, p2 - c)}));
    const double sv = std::clamp(cyl_.s(c), 0.0, cyl_.len);
    const glm::dvec3 closest = cyl_.a + sv * cyl_.d;
    return glm::length(c - closest) <= reach + rad;
  };
  if (index_) {
    for (FaceId f : index_->query_capsule(glm::vec3(cyl_.a), glm::vec3(cyl_.a + cyl_.len * cyl_.d),
                                          static_cast<float>(reach)))
      if (f.index < mesh_.face_slots() && !mesh_.is_deleted(f) && near_axis(mesh_.face(f)))
        candidates.push_back(f);
  } else {
    mesh_.for_each_face([&](FaceId f, const Triangle& t) {
      if (near_axis(t)) candidates.push_back(f);
    });
  }
  size_edge_table(3 * candidates.size() + 3);  // every edge looked up is a candidate's
  snap_shallow_vertices();
  allow_steiner();
  for (FaceId f : candidates) merge_crossings(f);
  for (FaceId f : candidates) process_face(f);
  if (editor_.log().size() == moved_.size()) {  // nothing cut: the snaps go back, the log stays empty
    for (const Edit& e : editor_.log().edits)
      if (const auto* mv = std::get_if<VertexMoved>(&e)) mesh_.positions()[mv->v.index] = mv->from;
    result.status = OpStatus::NoIntersection;
    return result;
  }
  // A rim through a vertex snapped onto the cylinder can leave it joining two fans: one vertex
  // each. Without walls before the rims are traced, so each rim runs through its own copy; with
  // walls after them (a wall can join the fans again), the rims following the copies.
  auto split_pinches = [&]() {
    const auto touched = detail::edited_vertices(editor_.log());
    // With the index, faces are found where their old vertices were filed; the faces around a
    // snapped vertex (filed where it was, and `posed_` may be the mesh's own positions) are all
    // candidates.
    auto around = detail::faces_around(mesh_, editor_.log(), touched, first_new_, index_, posed_);
    if (index_ && !moved_.empty()) around.insert(around.end(), candidates_.begin(), candidates_.end());
    auto pinches = detail::split_pinched_vertices(editor_, touched, around);
    for (const auto& [v, c] : pinches.copies) {
      (void)c;
      added_posed_.push_back(posed(v));
    }
    return pinches;
  };
  if (!options_.wall)
    for (const auto& [v, c] : split_pinches().copies) copy_of_.emplace(c.index, v.index);
  collect_holes(result);
  if (options_.wall) {
    build_walls(result);
    const auto pinches = split_pinches();
    for (DrillHole& h : result.holes) detail::follow_pinch_splits(mesh_, pinches, h.rim, h.closed);
  }
  for (const auto& [f, kind] : wall_faces_) {
    (void)kind;
    ++result.wall_triangles;
  }
  result.intersection_points = crossings_;
  result.triangles_removed = removed_;
  result.triangles_added = added_;
  result.added_posed.reserve(added_posed_.size());
  for (const auto& p : added_posed_) result.added_posed.push_back(glm::vec3(p));
  for (const auto& [v, p] : moved_) result.moved.push_back({VertexId(v), glm::vec3(p)});
  result.log = editor_.take_log();
  return result;
}

double axis_scale(const Cylinder& c) {
  const glm::dvec3 a(c.a), b(c.b);
  return glm::length(a) + glm::length(b) + glm::length(b - a);
}

void check_arguments(const Cylinder& c, const DrillOptions& options) {
  auto finite = [](const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  };
  if (!finite(c.a) || !finite(c.b))
    throw Error(ErrorCode::InvalidArgument, "drill: the axis end points are not finite");
  if (!std::isfinite(c.radius) || !(c.radius > 0.0f))
    throw Error(ErrorCode::InvalidArgument, "drill: the radius must be a positive number");
  const double len = glm::length(glm::dvec3(c.b) - glm::dvec3(c.a));
  const double scale = glm::length(glm::dvec3(c.a)) + glm::length(glm::dvec3(c.b));
  if (!(len > 1e-7 * scale) || len == 0.0)
    throw Error(ErrorCode::InvalidArgument, "drill: the axis end points A and B coincide");
  if (options.min_rim_edges < 3 || options.min_rim_edges > 4096)
    throw Error(ErrorCode::InvalidArgument, "drill: min_rim_edges must be between 3 and 4096");
  // Rim points closer than the absolute tolerance (a few float steps of the coordinates there)
  // round onto each other or onto one line in float: faces of zero area.
  if (c.radius < min_drill_radius(c, options.min_rim_edges)) {
    char text[240];
    std::snprintf(text, sizeof text,
                  "drill: radius %.3g with %d rim edges puts rim points %.3g apart, finer than the precision of "
                  "positions around the axis (%.3g); the radius must be at least %.3g",
                  double(c.radius), options.min_rim_edges, 2.0 * c.radius * std::sin(kPi / options.min_rim_edges),
                  1e-6 * axis_scale(c), double(min_drill_radius(c, options.min_rim_edges)));
    throw Error(ErrorCode::InvalidArgument, text);
  }
  if (!std::isfinite(options.relative_tolerance) || options.relative_tolerance < 0.0f ||
      options.relative_tolerance > 0.1f)
    throw Error(ErrorCode::InvalidArgument, "drill: relative_tolerance must be between 0 and 0.1");
}

}  // namespace

float min_drill_radius(const Cylinder& cylinder, int min_rim_edges) {
  const double spacing = 1e-6 * axis_scale(cylinder);  // the Driller's absolute tolerance
  const double r = spacing / (2.0 * std::sin(kPi / std::max(min_rim_edges, 3)));
  return std::nextafter(static_cast<float>(r), std::numeric_limits<float>::infinity());
}

DrillResult drill_mesh(SurfaceMesh& mesh, const std::vector<glm::vec3>& posed, const Cylinder& cylinder,
                       const DrillOptions& options, const TriangleGrid* index, const Unposer& unpose) {
  check_arguments(cylinder, options);
  if (posed.size() != mesh.vertex_count())
    throw Error(ErrorCode::InvalidArgument, "drill: " + std::to_string(posed.size()) +
                                                " posed positions for " +
                                                std::to_string(mesh.vertex_count()) + " vertices");
  return Driller(mesh, posed, cylinder, options, index, unpose).run();
}

ModelDrillResult drill_model(Model& model, const Cylinder& cylinder, const DrillOptions& options,
                             int animation, float time, PosedModel* index) {
  check_arguments(cylinder, options);
  const Pose pose = sample_pose(model, animation, time);
  const auto world = world_matrices(model, pose);
  if (index) index->prepare(model, animation, time);
  ModelDrillResult result;
  result.status = OpStatus::NoIntersection;
  std::vector<int> mesh_users(model.meshes.size(), 0);
  for (const auto& n : model.nodes)
    if (n.mesh >= 0 && static_cast<std::size_t>(n.mesh) < model.meshes.size()) ++mesh_users[n.mesh];
  int cut_material = -1;
  std::vector<glm::vec3> own_posed;
  for (std::size_t ni = 0; ni < model.nodes.size(); ++ni) {
    const int mi = model.nodes[ni].mesh;
    if (mi < 0 || static_cast<std::size_t>(mi) >= model.meshes.size()) continue;
    const int node_id = static_cast<int>(ni);
    std::vector<glm::mat4> joints;
    if (model.nodes[ni].skin >= 0 && static_cast<std::size_t>(model.nodes[ni].skin) < model.skins.size())
      joints = joint_matrices(model, model.nodes[ni].skin, world);
    const glm::mat4 node_world = world.at(ni);
    // The primitives are drilled in place (no copy, no re-extraction: the cost follows the hole);
    // a mesh drawn by several instances is drilled on a copy that this instance then owns.
    const bool shared = mesh_users[mi] > 1;
    Mesh copy;
    Mesh& target = shared ? (copy = model.meshes[mi], copy) : model.meshes[mi];
    std::vector<Primitive> walls;
    bool any = false;
    for (std::size_t pi = 0; pi < target.primitives.size(); ++pi) {
      Primitive& prim = target.primitives[pi];
      PosedMesh* inst = index ? index->find(node_id, static_cast<int>(pi)) : nullptr;
      if (!inst) own_posed = posed_positions(model, node_id, prim.mesh, world);
      const std::vector<glm::vec3>& posed = inst ? inst->posed : own_posed;
      // Inverse of the vertex's blended skinning (or of the node's world matrix).
      const Unposer unpose = [&](const SurfaceMesh& m, VertexId v, const glm::vec3& p) {
        const SkinBlend blend(m, joints);  // per call: the drill grows the mesh between calls
        const glm::mat4 mat = blend.skinned() ? blend.matrix(v.index) : node_world;
        const glm::dmat4 inv = glm::inverse(glm::dmat4(mat));
        const glm::dvec4 b = inv * glm::dvec4(glm::dvec3(p), 1.0);
        return std::isfinite(b.x) && std::isfinite(b.y) && std::isfinite(b.z) ? glm::vec3(b) : p;
      };
      // Faces flagged before the drill (a mesh made in code) go to the wall too, as new ones do.
      const bool flagged_before = prim.mesh.face_attrs().contains(attr::kCutSurface);
      DrillResult r = drill_mesh(prim.mesh, posed, cylinder, options, inst ? &inst->grid : nullptr, unpose);
      if (r.status == OpStatus::NoIntersection) continue;
      any = true;
      result.status = OpStatus::Ok;
      result.intersection_points += r.intersection_points;
      result.triangles_removed += r.triangles_removed;
      result.triangles_added += r.triangles_added;
      result.wall_triangles += r.wall_triangles;
      for (const auto& h : r.holes) {
        result.rim_vertices.push_back(h.rim.size());
        result.unwalled_holes += options.wall && !h.walled;
      }
      // Wall faces move to a primitive of their own (the "Cut surface" material): gathered from
      // the log, extracted at the wall's cost, and removed from the body through the editor.
      std::vector<FaceId> wall;
      if (const auto* flag = prim.mesh.face_attrs().find<std::uint8_t>(attr::kCutSurface)) {
        if (flagged_before) {
          prim.mesh.for_each_face([&](FaceId f, const Triangle&) {
            if ((*flag)[f.index]) wall.push_back(f);
          });
        } else {
          for (const Edit& e : r.log.edits)
            if (const auto* a = std::get_if<FaceAdded>(&e))
              if (!prim.mesh.is_deleted(a->f) && (*flag)[a->f.index]) wall.push_back(a->f);
          std::sort(wall.begin(), wall.end());
        }
      }
      if (!wall.empty()) {
        Primitive w;
        w.mesh = detail::extract(prim.mesh, wall);
        w.mesh.face_attrs().remove(attr::kCutSurface);
        if (cut_material < 0) cut_material = detail::cut_surface_material(model);
        w.material = cut_material;
        w.extras_json = prim.extras_json;
        walls.push_back(std::move(w));
        MeshEditor editor(prim.mesh);
        for (FaceId f : wall) editor.remove_face(f);
        r.log.append(editor.take_log());
      }
      prim.mesh.face_attrs().remove(attr::kCutSurface);
      if (inst) index->follow(model, node_id, static_cast<int>(pi), prim.mesh, r.log);
    }
    if (!any) continue;
    // Primitives the cylinder swallowed go; the walls follow the primitives.
    for (std::size_t pi = target.primitives.size(); pi-- > 0;)
      if (target.primitives[pi].mesh.face_count() == 0) {
        target.primitives.erase(target.primitives.begin() + static_cast<std::ptrdiff_t>(pi));
        if (index) index->erase_primitive(node_id, static_cast<int>(pi));
      }
    const std::size_t first_wall = target.primitives.size();
    for (auto& w : walls) target.primitives.push_back(std::move(w));
    if (target.primitives.empty()) {  // the cylinder swallowed the whole instance: it draws nothing now
      if (--mesh_users[mi] == 0) model.meshes[mi].primitives.clear();
      model.nodes[ni].mesh = -1;
      model.nodes[ni].skin = -1;
      if (index) index->erase_node(node_id);
      continue;
    }
    const std::size_t primitives = target.primitives.size();
    if (shared) {
      --mesh_users[mi];
      model.meshes.push_back(std::move(copy));
      model.nodes[ni].mesh = static_cast<int>(model.meshes.size() - 1);
      if (index) index->rename_mesh(node_id, model.nodes[ni].mesh);
    }
    if (index)
      for (std::size_t pi = first_wall; pi < primitives; ++pi) index->add(model, node_id, static_cast<int>(pi));
  }
  return result;
}

}  // namespace deepcut
