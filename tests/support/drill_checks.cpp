// SPDX-License-Identifier: MIT
#include "drill_checks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "deepcut/core/adjacency.h"
#include "deepcut/core/spatial_index.h"
#include "fixtures.h"

namespace deepcut::test {
namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

Axis::Axis(const Cylinder& c) : a(c.a), len(glm::length(glm::dvec3(c.b) - glm::dvec3(c.a))), r(c.radius) {
  d = (glm::dvec3(c.b) - a) / len;
}
double Axis::s(const glm::vec3& p) const { return glm::dot(glm::dvec3(p) - a, d); }
double Axis::rho(const glm::vec3& p) const {
  const glm::dvec3 q = glm::dvec3(p) - a;
  return glm::length(q - glm::dot(q, d) * d);
}

EdgeCensus census(const SurfaceMesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  mesh.for_each_face([&](FaceId, const Triangle& t) {
    for (int k = 0; k < 3; ++k) ++directed[{t[k].index, t[(k + 1) % 3].index}];
  });
  EdgeCensus c;
  for (const auto& [e, n] : directed) {
    if (n > 1) ++c.inconsistent;
    if (!directed.count({e.second, e.first})) ++c.boundary;
  }
  return c;
}

// Signed volume of the solid inside the finite cylinder, integrated along lines parallel to the
// axis (winding number of each point, so overlapping closed components count like the signed
// volume of the mesh does): `rings` x 4 `rings` lines over the disk, the midpoint rule.
double drilled_volume(const SurfaceMesh& mesh, const Cylinder& c, int rings) {
  const Axis ax(c);
  const glm::dvec3 helper = std::abs(ax.d.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 u = glm::normalize(glm::cross(helper, ax.d)), w = glm::cross(ax.d, u);
  const int sectors = 4 * rings;
  // Faces whose shadow meets the disk, bucketed on a grid over it.
  const int cells = 32;
  std::vector<std::vector<FaceId>> grid(cells * cells);
  auto cell_of = [&](double x) {
    return std::clamp(static_cast<int>((x / ax.r + 1.0) * 0.5 * cells), 0, cells - 1);
  };
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    for (VertexId v : t) {
      const glm::dvec3 q = glm::dvec3(mesh.position(v)) - ax.a;
      const double x[2] = {glm::dot(q, u), glm::dot(q, w)};
      for (int k = 0; k < 2; ++k) lo[k] = std::min(lo[k], x[k]), hi[k] = std::max(hi[k], x[k]);
    }
    if (lo[0] > ax.r || lo[1] > ax.r || hi[0] < -ax.r || hi[1] < -ax.r) return;
    for (int i = cell_of(lo[0]); i <= cell_of(hi[0]); ++i)
      for (int j = cell_of(lo[1]); j <= cell_of(hi[1]); ++j) grid[i * cells + j].push_back(f);
  });
  double volume = 0.0;
  for (int i = 0; i < rings; ++i) {
    const double r0 = ax.r * i / rings, r1 = ax.r * (i + 1) / rings, rm = 0.5 * (r0 + r1);
    const double cell = 0.5 * (r1 * r1 - r0 * r0) * 2.0 * kPi / sectors;
    for (int j = 0; j < sectors; ++j) {
      const double th = 2.0 * kPi * (j + 0.5) / sectors;
      const double x = rm * std::cos(th), y = rm * std::sin(th);
      const glm::dvec3 o = ax.a + x * u + y * w;
      std::vector<std::pair<double, int>> hits;  // s, winding change
      for (FaceId f : grid[cell_of(x) * cells + cell_of(y)]) {
        const Triangle& t = mesh.face(f);
        const glm::dvec3 p0(mesh.position(t[0])), p1(mesh.position(t[1])), p2(mesh.position(t[2]));
        const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0, pv = glm::cross(ax.d, e2);
        const double det = glm::dot(e1, pv);
        if (std::abs(det) < 1e-300) continue;
        const glm::dvec3 tv = o - p0;
        const double bu = glm::dot(tv, pv) / det;
        if (bu < 0.0 || bu > 1.0) continue;
        const glm::dvec3 qv = glm::cross(tv, e1);
        const double bv = glm::dot(ax.d, qv) / det;
        if (bv < 0.0 || bu + bv > 1.0) continue;
        const double sv = glm::dot(e2, qv) / det;
        hits.emplace_back(sv, glm::dot(glm::cross(e1, e2), ax.d) < 0.0 ? 1 : -1);
      }
      std::sort(hits.begin(), hits.end());
      int winding = 0;
      double prev = -1e300;
      for (const auto& [sv, change] : hits) {
        const double lo = std::max(prev, 0.0), hi = std::min(sv, ax.len);
        if (hi > lo) volume += winding * (hi - lo) * cell;
        winding += change;
        prev = sv;
      }
      if (prev < ax.len) volume += winding * (ax.len - std::max(prev, 0.0)) * cell;
    }
  }
  return volume;
}

// Smallest angle of a triangle, degrees.
double min_angle(const SurfaceMesh& mesh, const Triangle& t) {
  double best = 180.0;
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3 c(mesh.position(t[k])), a(mesh.position(t[(k + 1) % 3])),
        b(mesh.position(t[(k + 2) % 3]));
    const double la = glm::length(a - c), lb = glm::length(b - c);
    if (!(la > 0.0) || !(lb > 0.0)) return 0.0;
    best = std::min(best, std::acos(std::clamp(glm::dot(a - c, b - c) / (la * lb), -1.0, 1.0)) * 180.0 / kPi);
  }
  return best;
}

namespace {

// One drill's input, result and the measures every check below uses.
struct DrillCase {
  const SurfaceMesh& input;
  const SurfaceMesh& mesh;
  const Cylinder& cyl;
  const DrillOptions& options;
  const DrillResult& r;
  Axis ax;
  double tol;
  const AttributeArray<std::uint8_t>* wall_flag;

  DrillCase(const SurfaceMesh& in, const SurfaceMesh& out, const Cylinder& c, const DrillOptions& o,
            const DrillResult& result)
      : input(in), mesh(out), cyl(c), options(o), r(result), ax(c),
        tol(2.0 * o.relative_tolerance * c.radius + 1e-5 * (glm::length(c.a) + glm::length(c.b) + ax.len)),
        wall_flag(out.face_attrs().find<std::uint8_t>(attr::kCutSurface)) {}
  bool is_wall(FaceId f) const { return wall_flag && (*wall_flag)[f.index] && f.index >= input.face_slots(); }
  // On the cylinder's side (within 1% of r) or on an end plane.
  bool on_cylinder(VertexId v) const {
    const glm::vec3& p = mesh.position(v);
    const double s = ax.s(p);
    return std::abs(ax.rho(p) - ax.r) <= 0.01 * ax.r || std::abs(s) <= tol || std::abs(s - ax.len) <= tol;
  }
};

// Counts the new triangles by kind, and the thin and degenerate ones.
void count_new_faces(Checked& out, const DrillCase& c) {
  for (const Edit& e : c.r.log.edits) {
    const auto* fa = std::get_if<FaceAdded>(&e);
    if (!fa || c.mesh.is_deleted(fa->f)) continue;
    const double angle = min_angle(c.mesh, c.mesh.face(fa->f));
    out.degenerate += angle < 1e-3;
    if (c.is_wall(fa->f)) {
      ++out.wall;
      out.wall_thin += angle < 5.0;
    } else if (!fa->parent.valid() || fa->parent.index >= c.input.face_slots() ||  // re-added in this drill
               min_angle(c.input, c.input.face(fa->parent)) >= 10.0) {
      ++out.surface;
      out.surface_thin += angle < 5.0;
    }
  }
}

// No surface left inside the open cylinder (the rim polygon's chords may cut 1% of r inside,
// on the side as at the end planes, where a chord joins a side point to an end-plane point).
void check_nothing_inside(const DrillCase& c) {
  const Axis& ax = c.ax;
  const double end_margin = c.tol + 0.01 * ax.r;
  c.mesh.for_each_face([&](FaceId f, const Triangle& t) {
    if (c.is_wall(f)) return;
    const SurfaceMesh& mesh = c.mesh;
    const glm::vec3 center = (mesh.position(t[0]) + mesh.position(t[1]) + mesh.position(t[2])) / 3.0f;
    const double s = ax.s(center);
    bool inside = ax.rho(center) < 0.99 * ax.r && s > end_margin && s < ax.len - end_margin;
    // A triangle whose corners all lie on or outside the cylinder spans a rim chord: on a layer
    // the axis grazes, its centroid can sit a little deeper (2%).
    bool corners_out = true;
    for (VertexId v : t) corners_out &= ax.rho(mesh.position(v)) >= ax.r - c.tol;
    if (corners_out) inside = ax.rho(center) < 0.98 * ax.r && s > end_margin && s < ax.len - end_margin;
    ASSERT_FALSE(inside) << "face " << f.index << " centroid inside the cylinder (rho "
                         << ax.rho(center) / ax.r << " r)"
                         << " corners " << t[0].index << ":" << ax.rho(mesh.position(t[0])) / ax.r << " "
                         << t[1].index << ":" << ax.rho(mesh.position(t[1])) / ax.r << " " << t[2].index
                         << ":" << ax.rho(mesh.position(t[2])) / ax.r << " s " << ax.s(mesh.position(t[0]))
                         << " " << ax.s(mesh.position(t[1])) << " " << ax.s(mesh.position(t[2])) << " of "
                         << ax.len << " input v " << c.input.vertex_count() << " faces "
                         << c.input.face_slots() << " r " << ax.r;
  });
}

// Every new vertex on a boundary lies on the cylinder (within 1% of r) or on an end plane;
// every boundary edge is new rim or a piece of an old boundary edge (no cracks elsewhere).
void check_boundary_edges(const DrillCase& c, const Adjacency& before, const Adjacency& adj) {
  std::vector<std::array<std::uint32_t, 2>> origin(c.mesh.vertex_count());
  for (std::uint32_t v = 0; v < c.input.vertex_count(); ++v) origin[v] = {v, v};
  for (const Edit& e : c.r.log.edits)
    if (const auto* a = std::get_if<VertexAdded>(&e))
      origin[a->v.index] = {a->from[0].index, a->from[2].valid() ? kInvalidIndex : a->from[1].index};
  const auto old_boundary = before.boundary_edges();
  const Axis& ax = c.ax;
  for (const Edge& e : adj.boundary_edges()) {
    for (VertexId v : {e.a, e.b})
      if (v.index >= c.input.vertex_count()) {
        ASSERT_TRUE(c.on_cylinder(v)) << "new boundary vertex off the cylinder: rho "
                                      << ax.rho(c.mesh.position(v)) / ax.r;
      }
    if (c.on_cylinder(e.a) && c.on_cylinder(e.b)) continue;
    std::vector<std::uint32_t> ends = {origin[e.a.index][0], origin[e.a.index][1], origin[e.b.index][0],
                                       origin[e.b.index][1]};
    std::sort(ends.begin(), ends.end());
    ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
    ASSERT_TRUE(ends.size() == 2 && std::binary_search(old_boundary.begin(), old_boundary.end(),
                                                       make_edge(VertexId(ends[0]), VertexId(ends[1]))))
        << "boundary edge (" << e.a.index << "," << e.b.index << ") is neither rim nor old boundary; rho/r "
        << ax.rho(c.mesh.position(e.a)) / ax.r << " " << ax.rho(c.mesh.position(e.b)) / ax.r << " s "
        << ax.s(c.mesh.position(e.a)) << " " << ax.s(c.mesh.position(e.b)) << " len " << ax.len
        << " input vertices " << c.input.vertex_count();
  }
}

// What a failure message says about the rim edge `e` of hole `h`: the splits at its ends, every
// hole, and the rim around it.
std::string rim_trace(const DrillResult& r, const DrillHole& h, const Edge& e) {
  std::string o;
  for (const Edit& ed : r.log.edits)
    if (const auto* sp = std::get_if<VertexSplit>(&ed))
      if (sp->original == e.a || sp->original == e.b || sp->copy == e.a || sp->copy == e.b)
        o += " split " + std::to_string(sp->original.index) + "->" + std::to_string(sp->copy.index);
  for (const DrillHole& h2 : r.holes)
    o += " [hole rim " + std::to_string(h2.rim.size()) + " walled " + std::to_string(h2.walled) + " closed " +
         std::to_string(h2.closed) + "]";
  int pos = 0;
  for (std::size_t j = 0; j < h.rim.size(); ++j)
    if (h.rim[j] == e.a || h.rim[j] == e.b) pos = int(j);
  o += " at " + std::to_string(pos) + " of rim:";
  for (int j = std::max(0, pos - 3); j < std::min<int>(int(h.rim.size()), pos + 3); ++j)
    o += " " + std::to_string(h.rim[j].index);
  return o;
}

// An open hole's rim edges are boundary edges.
void check_rim_is_boundary(const DrillCase& c, const DrillHole& h, const Adjacency& adj,
                           const std::vector<Edge>& boundary) {
  for (std::size_t i = 0; i + 1 < h.rim.size() + (h.closed ? 1 : 0); ++i) {
    const Edge e = make_edge(h.rim[i], h.rim[(i + 1) % h.rim.size()]);
    ASSERT_TRUE(std::binary_search(boundary.begin(), boundary.end(), e))
        << "rim edge is not a boundary edge: " << e.a.index << "-" << e.b.index << " faces "
        << adj.edge_faces(e.a, e.b).size() << " hole closed " << h.closed << " rim " << h.rim.size() << " holes "
        << c.r.holes.size() << " first new " << c.r.first_new_vertex << rim_trace(c.r, h, e);
  }
}

// Holes the axis goes through are round; their rims are boundary edges (or walled).
void check_holes(Checked& out, const DrillCase& c, const Adjacency& adj) {
  const auto boundary = adj.boundary_edges();
  const Axis& ax = c.ax;
  out.all_walled = true;
  for (const DrillHole& h : c.r.holes) {
    out.all_walled &= h.walled;
    if (!h.walled) {
      check_rim_is_boundary(c, h, adj, boundary);
      if (::testing::Test::HasFatalFailure()) return;
    }
    // A hole the axis goes through whose rim stays on the cylinder's side is round; one that
    // reaches an end plane is D-shaped (the layer crosses the end disk), its side arc sampled
    // at the same angles and its straight part at the same spacing.
    bool on_side = true;
    for (VertexId v : h.rim) {
      const double sv = ax.s(c.mesh.position(v));
      on_side &= sv > c.tol && sv < ax.len - c.tol;
    }
    // A rim wholly on an end plane (a part the plane severs inside the cylinder) is the part's
    // cross-section, sampled at the rim spacing.
    bool on_end = true;
    for (VertexId v : h.rim) on_end &= std::abs(ax.rho(c.mesh.position(v)) - ax.r) > c.tol;
    if (h.closed && std::abs(h.winding) == 1 && !on_end) {
      ++(on_side ? out.round_holes : out.d_holes);
      EXPECT_GE(h.rim.size(), static_cast<std::size_t>(c.options.min_rim_edges)) << (on_side ? "round" : "D-shaped");
    }
  }
}

// The wall's measures the volume check allows for: its side area, the widest chord across the
// axis, and the allowance of the triangles that join an end disk to the side.
struct WallMeasures {
  double side_area = 0.0, corner = 0.0, chord = 0.0;
};

WallMeasures wall_measures(const DrillCase& c) {
  const Axis& ax = c.ax;
  WallMeasures w;
  w.chord = 2.0 * kPi * ax.r / c.options.min_rim_edges;
  c.mesh.for_each_face([&](FaceId f, const Triangle& t) {
    if (!c.is_wall(f)) return;
    const glm::dvec3 p0(c.mesh.position(t[0])), p1(c.mesh.position(t[1])), p2(c.mesh.position(t[2]));
    const glm::dvec3 nrm = glm::cross(p1 - p0, p2 - p0);
    for (const glm::dvec3& e : {p1 - p0, p2 - p1, p0 - p2})
      w.chord = std::max(w.chord, glm::length(e - glm::dot(e, ax.d) * ax.d));
    // A wall triangle from an end disk to the side cuts the cylinder's rim edge: at most its
    // area times half its longest edge.
    bool on_end = false, on_side = false;
    for (VertexId v : t) {
      const double sv = ax.s(c.mesh.position(v)), rho = ax.rho(c.mesh.position(v));
      on_end |= (std::abs(sv) <= c.tol || std::abs(sv - ax.len) <= c.tol) && rho < ax.r - c.tol;
      on_side |= std::abs(rho - ax.r) <= c.tol && sv > c.tol && sv < ax.len - c.tol;
    }
    if (on_end && on_side)
      w.corner += 0.25 * glm::length(nrm) *
                  std::max({glm::length(p1 - p0), glm::length(p2 - p1), glm::length(p0 - p2)});
    if (glm::length(nrm) > 0.0 && std::abs(glm::dot(nrm, ax.d)) < 0.5 * glm::length(nrm))
      w.side_area += 0.5 * glm::length(nrm);
  });
  return w;
}

// A walled drill of a closed input is closed, consistently oriented, and removes the volume of
// an N-gon prism inscribed in the cylinder (min_rim_edges vertices around).
void check_wall_volume(const DrillCase& c) {
  const EdgeCensus census_after = census(c.mesh);
  EXPECT_EQ(census_after.boundary, 0u) << "walled drill of closed input is closed";
  EXPECT_EQ(census_after.inconsistent, 0u) << "walled drill is consistently oriented";
  const Axis& ax = c.ax;
  const double n = c.options.min_rim_edges;
  // The reference is a quadrature: its own error (fine vs coarse) widens the 2% where the
  // drilled volume is a thin shaving that the lines barely resolve.
  const double fine = drilled_volume(c.input, c.cyl, 48), coarse = drilled_volume(c.input, c.cyl, 24);
  // The wall's side is inscribed in the cylinder: its chords leave r pi^2 / (3 n^2) of volume
  // per unit of side area (exact for a full prism). Snapping moves the cut surface by at most
  // twice the tolerance: that much of the wall's area in volume is the drill's own allowance
  // (it shows only on shavings). Wall triangles wider (across the axis) than the ruling
  // spacing, as across a narrow notch, cut deeper chords: their sagitta L^2 / 8r bounds the rest.
  const WallMeasures w = wall_measures(c);
  const double expected = fine - w.side_area * ax.r * kPi * kPi / (3.0 * n * n);
  const double removed = c.input.volume() - c.mesh.volume();
  const double sagitta = w.side_area * (w.chord * w.chord - std::pow(2.0 * kPi * ax.r / n, 2.0)) / (8.0 * ax.r);
  const double slack = 0.02 * std::abs(expected) + 2.0 * std::abs(fine - coarse) + sagitta + w.corner;
  if (std::abs(removed - expected) <= slack) return;
  // Surface within the snapping tolerance of the cylinder may stay (a graze shallower than the
  // tolerance is not cut) or go: between the cylinder shrunk and grown by it.
  const double band = 2.0 * (c.options.relative_tolerance * c.cyl.radius + 1e-6 * ax.len);
  Cylinder shrunk = c.cyl, grown = c.cyl;
  const glm::vec3 dir = glm::vec3(ax.d) * static_cast<float>(band);
  shrunk.a += dir, shrunk.b -= dir, shrunk.radius -= static_cast<float>(band);
  grown.a -= dir, grown.b += dir, grown.radius += static_cast<float>(band);
  const double lower = drilled_volume(c.input, shrunk, 48) * expected / fine,
               upper = drilled_volume(c.input, grown, 48);
  EXPECT_GE(removed, lower - slack) << "volume " << c.input.volume() << " expected " << expected;
  EXPECT_LE(removed, upper + slack) << "volume " << c.input.volume() << " expected " << expected;
}

}  // namespace

// All the invariants of one mesh-level drill on bind positions (posed == bind).
void check_drill_into(Checked& out, const SurfaceMesh& input, const Cylinder& cyl,
                      const DrillOptions& options, std::size_t joints, [[maybe_unused]] bool use_index) {
  SurfaceMesh mesh = input;
  const Adjacency before = Adjacency::build(input);
  const bool closed = before.boundary_edges().empty() && before.nonmanifold_edges().empty();
  const DrillResult r = drill_mesh(mesh, PosedMesh::at_positions(mesh), cyl, options);
  if (r.status == OpStatus::NoIntersection) {
    EXPECT_TRUE(r.log.empty());
    EXPECT_EQ(mesh.faces(), input.faces());
    return;
  }
  out.intersected = true;
  char cyl_text[200];
  std::snprintf(cyl_text, sizeof cyl_text, "cylinder %.9g,%.9g,%.9g,%.9g,%.9g,%.9g r %.9g", cyl.a.x, cyl.a.y,
                cyl.a.z, cyl.b.x, cyl.b.y, cyl.b.z, cyl.radius);
  SCOPED_TRACE(cyl_text);
  EXPECT_EQ(r.added_posed.size(), mesh.vertex_count() - input.vertex_count());
  Adjacency adj = before;
  adj.apply(r.log);
  test::expect_adjacency_matches_rebuild(adj, mesh);
  test::expect_valid(mesh, joints);
  const DrillCase c(input, mesh, cyl, options, r);
  count_new_faces(out, c);
  check_nothing_inside(c);
  check_boundary_edges(c, before, adj);
  if (::testing::Test::HasFatalFailure()) return;
  check_holes(out, c, adj);
  if (::testing::Test::HasFatalFailure()) return;
  if (options.wall && closed) {
    EXPECT_TRUE(out.all_walled) << "every rim of a closed input gets its wall";
    check_wall_volume(c);
  }
}

Checked check_drill(const SurfaceMesh& input, const Cylinder& cyl, const DrillOptions& options,
                    std::size_t joints, bool use_index) {
  Checked out;
  check_drill_into(out, input, cyl, options, joints, use_index);
  return out;
}

Checked check_asset_drill(const Model& model, const Cylinder& cyl, bool wall, bool use_index) {
  DrillOptions options;
  options.wall = wall;
  return check_drill(model.meshes[0].primitives[0].mesh, cyl, options,
                     model.skins.empty() ? 0 : model.skins[0].joints.size(), use_index);
}

}  // namespace deepcut::test
