// SPDX-License-Identifier: MIT
// One sheet of a wall: its loops mapped over its own extent, nested into outer loops and holes,
// triangulated in the plane with Steiner points, refined at the rims and flipped on the cylinder.
#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <unordered_map>
#include <unordered_set>

#include "ops/drill/walls/wall_shell.h"

namespace deepcut::drill {
namespace {

constexpr double kWallNeedle =
    6.0 * geometry::kPi / 180.0;  // wall triangles at a rim refined below this angle

// Lawson flips on a curved surface (the cylinder): an interior edge whose opposite angles sum
// to more than pi is flipped when the two new triangles keep the orientation, so the plane
// map's distortion (compressed along the axis on long walls) leaves no needles. Edges with one
// triangle (the rims) are constraints; `forbidden` says whether a new edge may not be made.
template <class Forbidden>
void flip_on_surface(std::vector<geometry::LocalTri>& tris, const std::vector<glm::dvec3>& p,
                     const Forbidden& forbidden) {
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
    if (geometry::angle_at(p[a], p[b], p[c]) + geometry::angle_at(p[a], p[b], p[d]) <= geometry::kPi + 1e-9)
      continue;
    // On a curved surface both diagonals of a quad can fail the test: flip only to one that
    // passes it, or the two would be flipped back and forth until the guard.
    if (geometry::angle_at(p[c], p[d], p[a]) + geometry::angle_at(p[c], p[d], p[b]) >= geometry::kPi - 1e-9)
      continue;
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

// Maps the sheet's loops over its own extent, bringing the B disk's centre in from infinity when
// the region holds it: false when the sheet cannot be walled.
bool map_sheet(WallShell& shell, const Loops& loops, const Segments& segments, bool open_shell,
               SheetExtent& extent) {
  const std::vector<WallPt>& pts = shell.pts;
  const std::vector<glm::dvec2>& xy = shell.xy;
  const CylinderFrame& cy = shell.map.cy;
  const double tol = shell.tol;
  double smin = kInf, smax = -kInf;
  for (const auto& l : loops)
    for (auto i : l) {
      smin = std::min(smin, std::clamp(pts[i].s, 0.0, cy.len));
      smax = std::max(smax, std::clamp(pts[i].s, 0.0, cy.len));
    }
  shell.map.span(shell.s_lo, shell.s_hi);
  shell.map_points();
  int c = 0;
  if (!consistent(xy, loops, c)) return false;
  // Which end disks the region reaches; then the final map over that extent.
  const bool a_inside = geometry::winding(xy, loops, glm::dvec2(0.0)) + c == 1;
  const bool b_inside = c == 1;
  // A shell with a boundary of its own (an open sheet, a torn part) has no inside: its rims'
  // orientation still picks a side, but a region holding an end disk's centre is then a cup out
  // to that end, or the whole cylinder but a small patch where a rim does not go around the
  // axis (tens of thousands of triangles for a small hole in a torn part). Such a shell gets
  // tubes between its rims only.
  if (open_shell && (a_inside || b_inside)) return false;
  bool touches_a = a_inside, touches_b = b_inside;
  for (const auto& l : loops)
    for (auto i : l) {
      touches_a |= pts[i].where == 1 || pts[i].s <= tol;
      touches_b |= pts[i].where == 2 || pts[i].s >= cy.len - tol;
    }
  const double lo = touches_a ? 0.0 : smin, hi = touches_b ? cy.len : smax;
  extent = {lo, hi, touches_a, touches_b};
  shell.map.span(lo, hi);
  shell.map_points();
  if (b_inside) {  // bring infinity (the B disk's centre) in: a point outside the shell goes there
    bool found = false;
    for (std::size_t li = 0; li < loops.size() && !found; ++li) {
      const auto& l = loops[li];
      const std::size_t i = longest_step(xy, l);
      const std::uint32_t a = l[i], b = l[(i + 1) % l.size()];
      for (double offset : {-0.3, -0.1, -0.03, -0.01}) {
        const glm::dvec2 z = side_point(xy, a, b, offset);
        if (geometry::winding(xy, loops, z) + c != 0) continue;
        const double e2 = glm::dot(xy[b] - xy[a], xy[b] - xy[a]);
        bool clear = true;
        for (const auto& [u, v] : segments)
          if (geometry::segment_distance2(z, xy[u], xy[v]) < 0.25 * offset * offset * e2) clear = false;
        if (!clear) continue;
        shell.map.z0 = z;
        found = true;
        break;
      }
    }
    if (!found) return false;
    shell.map.mobius = true;
    shell.map_points();
  }
  return true;
}

// Outer loops (counter-clockwise now) and the holes each one holds.
bool nest_loops(const WallShell& shell, const Loops& loops, std::vector<std::size_t>& outers,
                std::vector<std::vector<std::size_t>>& holes_of) {
  const std::vector<WallPt>& pts = shell.pts;
  const std::vector<glm::dvec2>& xy = shell.xy;
  std::vector<double> area(loops.size());

  for (std::size_t i = 0; i < loops.size(); ++i) {
    area[i] = geometry::signed_area2(xy, loops[i]);
    if (area[i] > 0.0) outers.push_back(i);
  }
  holes_of.assign(loops.size(), {});
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
      if (geometry::winding(xy, {loops[o]}, xy[loops[hidx][probe]]) != 0 &&
          (owner == loops.size() || area[o] < area[owner]))
        owner = o;
    }
    if (owner == loops.size()) return false;
    holes_of[owner].push_back(hidx);
  }
  return true;
}

// Surface edges between rim vertices: the wall must not reuse one as a diagonal.
std::unordered_set<std::uint64_t> forbidden_surface_edges(const WallContext& ctx) {
  const SurfaceMesh& mesh = ctx.editor.mesh();
  std::unordered_set<std::uint64_t> surface_edges;
  for (const Edit& e : ctx.editor.log().edits)
    if (const auto* fa = std::get_if<FaceAdded>(&e))
      for (int k = 0; k < 3; ++k) surface_edges.insert(edge_key(fa->vertices[k], fa->vertices[(k + 1) % 3]));
  // Old faces the drill kept can join two rim vertices too (both within the tolerance of the
  // cylinder): their edges are as forbidden.
  for (FaceId f : ctx.surface_faces)
    if (!mesh.is_deleted(f))
      for (int k = 0; k < 3; ++k) surface_edges.insert(edge_key(mesh.face(f)[k], mesh.face(f)[(k + 1) % 3]));
  return surface_edges;
}

// Rim vertices a hair apart (two surface edges crossing the cylinder next to each other: most
// wall needles) make needles with any point a rim spacing away. Triangles at a rim under
// kWallNeedle degrees (on the cylinder) get a point at their circumcentre in the plane when it
// lies in the region and outside every rim step's diametral circle (no rim step is encroached);
// repeated, the points grade down towards the short step. In passes, worst first, skipping a
// triangle whose circumcircle holds a point this pass added (it is gone), with a budget of
// points per rim point: the cost follows the needles.
void refine_rim_needles(WallShell& shell, geometry::FlipTriangulation& ft,
                        const std::vector<glm::dvec2>& local, std::vector<std::uint32_t>& global,
                        const Loops& region, std::size_t loop_points) {
  std::vector<WallPt>& pts = shell.pts;
  const std::vector<glm::dvec2>& xy = shell.xy;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> steps;
  for (const auto& l : region)
    for (std::size_t i = 0; i < l.size(); ++i) steps.emplace_back(l[i], l[(i + 1) % l.size()]);
  auto min_angle = [&](const geometry::LocalTri& t) {
    const glm::dvec3 &p0 = pts[global[t[0]]].p, &p1 = pts[global[t[1]]].p, &p2 = pts[global[t[2]]].p;
    return std::min(
        {geometry::angle_at(p1, p2, p0), geometry::angle_at(p2, p0, p1), geometry::angle_at(p0, p1, p2)});
  };
  std::set<geometry::LocalTri> failed;  // by sorted_corners
  std::size_t budget = 2 * loop_points + 16;
  for (int pass = 0; pass < 12 && budget > 0; ++pass) {
    std::vector<std::pair<double, geometry::LocalTri>> skinny;
    for (const auto& t : ft.triangles()) {
      // At the rims only: elsewhere the plane map's compression (kappa) leaves triangles the
      // flips on the cylinder below make well shaped.
      if (t[0] >= loop_points && t[1] >= loop_points && t[2] >= loop_points) continue;
      const double angle = min_angle(t);
      if (angle < kWallNeedle && !failed.count(geometry::sorted_corners(t))) skinny.emplace_back(angle, t);
    }
    if (skinny.empty()) break;
    std::sort(skinny.begin(), skinny.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    std::vector<glm::dvec2> added_now;
    for (const auto& [angle, t] : skinny) {
      if (budget == 0) break;
      const glm::dvec2 centre = geometry::circumcentre(local[t[0]], local[t[1]], local[t[2]]);
      if (!std::isfinite(centre.x) || !std::isfinite(centre.y)) {
        failed.insert(geometry::sorted_corners(t));
        continue;
      }
      const double radius = glm::length(local[t[0]] - centre);
      bool stale = false;
      for (const glm::dvec2& q : added_now) stale |= glm::length(q - centre) < radius;
      if (stale) continue;
      failed.insert(geometry::sorted_corners(t));
      bool ok = true;
      for (std::size_t i = 0; i < steps.size() && ok; ++i) {
        const glm::dvec2 &u = local[steps[i].first], &v = local[steps[i].second];
        ok = glm::length(centre - 0.5 * (u + v)) > 0.525 * glm::length(v - u);
      }
      if (!ok || geometry::winding(xy, region, centre) != 1 || !ft.insert(centre)) continue;
      added_now.push_back(centre);
      global.push_back(static_cast<std::uint32_t>(pts.size()));
      pts.push_back(shell.map.from_plane(centre));
      --budget;
    }
    if (added_now.empty()) break;
  }
}

// The triangles must cover the region exactly: each step of its loops once, every other edge
// once each way. Ear clipping can find no proper ear where rims run a hair apart in the plane
// map and leave a gap: the sheet is then left open and its holes reported unwalled rather than
// walled with a crack.
bool covers_region(const std::vector<geometry::LocalTri>& sheet_tris, const Loops& region) {
  auto key = [](std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; };
  std::unordered_set<std::uint64_t> half, rim_steps;
  for (const auto& t : sheet_tris)
    for (int k = 0; k < 3; ++k)
      if (!half.insert(key(t[k], t[(k + 1) % 3])).second) return false;
  for (const auto& l : region)
    for (std::size_t i = 0; i < l.size(); ++i) rim_steps.insert(key(l[i], l[(i + 1) % l.size()]));
  for (const std::uint64_t e : half)
    if (!half.count(key(static_cast<std::uint32_t>(e), static_cast<std::uint32_t>(e >> 32))) &&
        !rim_steps.count(e))
      return false;
  for (const std::uint64_t e : rim_steps)
    if (!half.count(e)) return false;
  return true;
}

// Triangulates the region of outer loop `o` and its holes with the free Steiner candidates
// (marking those it takes), in the plane and then flipped on the cylinder: false when the
// triangles do not cover the region exactly.
bool triangulate_outer(WallShell& shell, const Loops& loops, std::size_t o,
                       const std::vector<std::size_t>& holes, const std::vector<WallPt>& candidates,
                       std::vector<std::uint8_t>& taken,
                       const std::unordered_set<std::uint64_t>& surface_edges,
                       std::vector<geometry::LocalTri>& sheet_tris) {
  std::vector<WallPt>& pts = shell.pts;
  const std::vector<glm::dvec2>& xy = shell.xy;
  std::vector<glm::dvec2> local = xy;            // FlipTriangulation appends Steiner points
  std::vector<std::uint32_t> global(xy.size());  // local point -> pts (loop points first)
  for (std::uint32_t i = 0; i < xy.size(); ++i) global[i] = i;
  std::vector<std::vector<std::uint32_t>> holes_local;
  for (std::size_t hidx : holes) holes_local.push_back(loops[hidx]);
  std::vector<geometry::LocalTri> tris;
  geometry::triangulate_polygon(local, loops[o], std::move(holes_local), kRimTriangulation, tris);
  std::vector<std::vector<std::uint32_t>> region = {loops[o]};
  for (std::size_t hidx : holes) region.push_back(loops[hidx]);
  geometry::FlipTriangulation ft(local, std::move(tris));
  ft.make_delaunay();
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (taken[i]) continue;
    const glm::dvec2 z = candidates[i].pole ? glm::dvec2(0.0) : shell.map.to_plane(candidates[i]);
    if (!std::isfinite(z.x) || !std::isfinite(z.y) || geometry::winding(xy, region, z) != 1) continue;
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
          WallPt w = shell.map.from_plane(p);
          global.push_back(static_cast<std::uint32_t>(pts.size()));
          pts.push_back(w);
          changed = true;
        }
      }
      if (changed) break;
    }
    if (!changed) break;
  }
  refine_rim_needles(shell, ft, local, global, region, loop_points);
  for (const auto& t : ft.triangles()) sheet_tris.push_back({global[t[0]], global[t[1]], global[t[2]]});
  std::vector<glm::dvec3> where3(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) where3[i] = pts[i].p;
  flip_on_surface(sheet_tris, where3, [&](std::uint32_t x, std::uint32_t y) {
    return pts[x].v.valid() && pts[y].v.valid() && surface_edges.count(edge_key(pts[x].v, pts[y].v)) > 0;
  });
  return covers_region(sheet_tris, region);
}

}  // namespace

bool wall_sheet(WallShell& shell, WallContext& ctx, const Loops& sheet_loops, int sheet_id, bool open_shell) {
  Loops loops = sheet_loops;
  Segments segments;
  for (const auto& l : loops)
    for (std::size_t i = 0; i < l.size(); ++i) segments.emplace_back(l[i], l[(i + 1) % l.size()]);
  SheetExtent extent;
  if (!map_sheet(shell, loops, segments, open_shell, extent)) return false;
  std::vector<std::pair<std::size_t, geometry::LocalTri>> sheet_lobes;
  if (!fold_loops(shell.xy, loops, sheet_lobes)) return false;
  std::vector<std::size_t> outers;
  std::vector<std::vector<std::size_t>> holes_of;
  if (!nest_loops(shell, loops, outers, holes_of)) return false;
  const std::vector<WallPt> candidates =
      steiner_candidates(shell, loops, segments, extent, ctx.editor.mesh());
  const std::unordered_set<std::uint64_t> surface = forbidden_surface_edges(ctx);
  std::vector<std::uint8_t> taken(candidates.size(), 0);
  std::vector<geometry::LocalTri> wall_tris;  // indices into shell.pts
  for (std::size_t o : outers) {
    std::vector<geometry::LocalTri> sheet_tris;
    if (!triangulate_outer(shell, loops, o, holes_of[o], candidates, taken, surface, sheet_tris))
      return false;
    wall_tris.insert(wall_tris.end(), sheet_tris.begin(), sheet_tris.end());
  }
  if (wall_tris.empty()) return false;
  for (const auto& [li, t] : shell.lobe_tris)
    if (shell.sheet[li] == sheet_id) wall_tris.push_back(t);
  for (const auto& lobe : sheet_lobes) wall_tris.push_back(lobe.second);
  return emit_sheet(shell, ctx, wall_tris);
}

}  // namespace deepcut::drill
