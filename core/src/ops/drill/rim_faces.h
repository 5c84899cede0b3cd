// SPDX-License-Identifier: MIT
#pragma once
// The rim insertion's work on one crossed triangle, in its own plane (rim_insertion.cpp runs it):
// the kept parts of the triangle are found and triangulated without touching the mesh, and what
// to do is written down as a plan (remove the triangle, add these kept parts). The plans of the
// crossed candidates are made in parallel (each reads only the crossings made before) and carried
// out in candidate order, so the edits are the same whatever the thread count. Private to the drill.

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "geometry/delaunay_flip.h"
#include "geometry/polygon_triangulation.h"
#include "kept_lists.h"
#include "ops/common/crossing_table.h"
#include "ops/drill/cylinder_section.h"
#include "ops/drill/posed_overlay.h"

namespace deepcut::drill {

// What the solid cylinder does to one mesh edge, from `lo` to `hi` (lo < hi).
struct EdgeCut {
  VertexId lo, hi;
  int n = 0;                           // kept crossings
  double t[2] = {0.0, 0.0};            // their parameters, increasing
  VertexId v[2];                       // their vertices
  std::uint8_t inside[3] = {0, 0, 0};  // sub-segments between 0, t[0..n-1], 1
  // Points on the kept parts of a crossed edge, graded away from the crossings (see
  // RimInserter::cross): parameters, increasing once RimInserter::make_edge_vertices has made
  // their vertices.
  std::vector<std::pair<double, VertexId>> steiner;
  // The faces on the edge among the candidates of kind kCut, neither deep inside nor clear of the
  // cylinder (file_side: kLoHi for each with lo -> hi, kHiLo for each with hi -> lo), whether one
  // of them has a bad shape, and whether the vertices of the edge's crossings have been made
  // (RimInserter::make_edge_vertices; the edge may be left uncrossed).
  // All three are written only before planning starts (planning only reads them).
  std::uint32_t sides = 0;
  bool bad_side = false, resolved = false;

  static constexpr std::uint32_t kLoHi = 1, kHiLo = 16;
  /// Files a candidate face holding the half-edge a -> b of this edge; `bad`: of bad shape.
  void file_side(VertexId a, VertexId b, bool bad) {
    sides += a < b ? kLoHi : kHiLo;
    bad_side |= bad;
  }
  /// Whether the edge may take Steiner points: exactly one face on each side, neither of bad
  /// shape (RimInserter::allow_steiner).
  bool takes_steiner() const { return sides == kLoHi + kHiLo && !bad_side; }
};

// What the planning reads of one candidate: its edges' records (edge k from corner k to corner
// k + 1; records never move) and, for a candidate with a piece of an edge inside
// (any_piece_inside), its corners' angles around the axis (CylinderFrame::window_theta), worked out
// once per vertex before planning (the window of rulings each such face samples). Left
// unwritten for a candidate deep inside or clear of the cylinder (nothing reads it).
struct CandidateFace {
  std::array<EdgeCut*, 3> edges;
  std::array<double, 3> angle;
  bool angled;  // angle holds the corners' angles
};

/// Whether a piece of one of the candidate's edges lies inside the cylinder (FacePlanner::plan
/// then works out its boundary).
inline bool any_piece_inside(const CandidateFace& face) {
  for (const EdgeCut* e : face.edges) {
    for (int j = 0; j <= e->n; ++j)
      if (e->inside[j]) return true;
  }
  return false;
}

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

// What every face's planning reads (made before planning starts, unchanged while it runs).
struct RimShared {
  const SurfaceMesh& mesh;
  const PosedOverlay& posed;
  const CylinderFrame& cyl;
  const detail::NeedleMerges& merges;
  // Per candidate its records (read-only: planning runs in parallel).
  const CandidateFace* faces;
  double eps = 0.0, sep = 0.0, ruling_reach = -1.0;
  int samples = 32;
  std::vector<glm::dvec3> ruling_base;  // where each sampled ruling starts (s = 0)
};

// One kept part to add: points [first_pt, first_pt + pts) and triangles of a PlanChunk.
struct PolygonPlan {
  std::uint32_t first_pt = 0, pts = 0, first_tri = 0, tris = 0;
};

// The triangles a whole clip of `outer` with `holes` (kRimTriangulation) makes: two fewer than
// its corners, the bridge of each hole adding two corners. A clip that makes fewer has dropped a
// degenerate ear (most_convex found none to emit, or the closing triangle was flat).
inline std::size_t whole_clip_triangles(const std::vector<std::uint32_t>& outer,
                                        const std::vector<std::vector<std::uint32_t>>& holes) {
  std::size_t corners = outer.size();
  for (const auto& hole : holes) corners += hole.size() + 2;
  return corners >= 2 ? corners - 2 : 0;
}

// The plans of a run of candidates: their kept parts' points and triangles.
struct PlanChunk {
  std::vector<LocalPoint> pts;
  std::vector<geometry::LocalTri> tris;
  std::vector<PolygonPlan> polys;
  /// Whether the ear clipping of one of these kept parts gave fewer triangles than its corners
  /// call for (a degenerate ear dropped): that part may leave a gap, and a point of it two fans.
  bool gaps = false;

  /// A list holding more bytes than this gives its memory back when a drill ends
  /// (detail::give_back_if_big); smaller ones keep it, so the next drill of that size plans
  /// without allocating.
  static constexpr std::size_t kKeptBytes = std::size_t(1) << 16;

  /// This thread's chunks, kept from drill to drill.
  static std::vector<PlanChunk>& local() {
    thread_local std::vector<PlanChunk> chunks;
    return chunks;
  }

  /// `count` empty chunks: this thread's (local()), those beyond `count` gone. A list above
  /// kKeptBytes (a drill that ended before give_back_big) gives its memory back here.
  static std::vector<PlanChunk>& reused(std::size_t count) {
    std::vector<PlanChunk>& chunks = local();
    chunks.resize(count);
    for (PlanChunk& c : chunks) {
      c.give_back_lists();
      c.pts.clear();
      c.tris.clear();
      c.polys.clear();
      c.gaps = false;
    }
    return chunks;
  }

  /// Gives back the memory of every list of `chunks` above kKeptBytes: run when a drill's plans
  /// are applied.
  static void give_back_big(std::vector<PlanChunk>& chunks) {
    for (PlanChunk& c : chunks) c.give_back_lists();
  }

 private:
  void give_back_lists() {
    detail::give_back_if_big(pts, kKeptBytes);
    detail::give_back_if_big(tris, kKeptBytes);
    detail::give_back_if_big(polys, kKeptBytes);
  }
};

// What to do with one candidate: remove it, then add kept parts [first_poly, first_poly +
// polys) of chunk `chunk`.
struct FacePlan {
  std::uint8_t remove = 0;
  std::uint32_t chunk = 0, first_poly = 0, polys = 0;
};

// Working lists of the planning, reused from face to face and from call to call (one set per
// thread). They hold one face's plan at a time, so their size follows the largest face planned,
// not the drill's size.
struct PlanScratch {
  std::vector<LocalPoint> pts, rim;
  std::vector<std::uint8_t> seg_inside, used;
  std::vector<std::pair<double, std::size_t>> arc;
  std::vector<std::uint32_t> loop;
  std::vector<glm::dvec2> q;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> segments;
  std::vector<geometry::LocalTri> clipped, failed;
  geometry::FlipTriangulation flips;

  /// This thread's lists.
  static PlanScratch& local() {
    thread_local PlanScratch scratch;
    return scratch;
  }
};

/// Whether the triangle with posed corners `p` lies wholly outside the solid cylinder, a
/// tolerance clear of it (then none of its edges is crossed and no hole lies inside it).
bool clear_of_cylinder(const CylinderFrame& cyl, const glm::dvec3 p[3]);

/// The triangles of the quad 0-1-2-3 over `q` (counter-clockwise) as the general path of a kept
/// part makes them (ear clipping by kRimTriangulation, then Lawson flips: FlipTriangulation), in
/// the same order with the same first corners, worked out without the general path's lists (most
/// kept parts are quads). Returns false where that path would take a step this one does not
/// follow (no ear, a last triangle without area, a flip undone or a second one): the caller runs
/// the general path there.
bool quad_triangles(const glm::dvec2 q[4], std::array<geometry::LocalTri, 2>& out);

/// Plans candidates of one chunk into `out` (see the file comment).
class FacePlanner {
 public:
  FacePlanner(const RimShared& shared, PlanChunk& out, std::uint32_t chunk)
      : s_(shared), out_(out), chunk_(chunk), w_(PlanScratch::local()) {}

  /// The plan for candidate `c` (face `f`, neither deep inside nor clear of the cylinder).
  void plan(std::size_t c, FaceId f, FacePlan& plan);

 private:
  bool boundary(const Triangle& tri, const glm::dvec3 corner[3]);
  void face_boundary(const Triangle& tri, const glm::dvec3 corner[3]);
  void sample_rim();
  int sample_rulings(bool count_all);
  std::pair<int, int> chord_pieces(double a_cap, double hh, int pieces) const;
  void consider(const glm::dvec3& x, bool corner_point);
  void end_corner(double a_cap, double hh, double sign);
  void kept_parts();
  std::size_t add_arc(const LocalPoint& start, const LocalPoint& end, std::vector<LocalPoint>& poly);
  void add_polygon(std::size_t first, const std::vector<std::uint32_t>& outer,
                   const std::vector<std::vector<std::uint32_t>>& holes);
  void refine(geometry::FlipTriangulation& ft, std::vector<glm::dvec2>& q,
              const std::vector<std::uint32_t>& outer, const std::vector<std::vector<std::uint32_t>>& holes);
  const geometry::LocalTri* worst_triangle(const geometry::LocalTri* begin, const geometry::LocalTri* end,
                                           const glm::dvec2* q) const;
  bool add_quad(const LocalPoint* pts, std::size_t count, const std::vector<std::uint32_t>& outer);

  const RimShared& s_;
  PlanChunk& out_;
  std::uint32_t chunk_;
  PlanScratch& w_;
  FacePlan* plan_ = nullptr;                                  // the candidate being planned
  const CandidateFace* cur_ = nullptr;                        // its records
  const EdgeCut& cur_edge(int k) const { return *cur_->edges[k]; }
  FacePlane face_;
  const std::vector<std::vector<std::uint32_t>> no_holes_;
};

}  // namespace deepcut::drill
