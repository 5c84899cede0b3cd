// SPDX-License-Identifier: MIT
// Planning one crossed triangle of the rim insertion (rim_faces.h): its boundary with the
// crossings, the rim sampled where the fixed rulings meet its plane, and its kept parts
// triangulated, flipped to Delaunay and refined in that plane.
#include "ops/drill/rim_faces.h"

#include <algorithm>
#include <cmath>

#include "geometry/predicates.h"
#include "ops/drill/rim_insertion.h"

namespace deepcut::drill {

namespace {

// Whether FlipTriangulation::legalize flips edge a-b of triangle a-b-c, with d across it (over
// the points `q`).
bool flips(const glm::dvec2 q[4], std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
  return geometry::delaunay_flips(q[a], q[b], q[c], q[d]);
}

// The corner of the quad 0-1-2-3 that ear clipping (EarSearch::kExhaustive) clips: the ear of
// best quality (the first on ties) among the corners with area beyond the tolerance whose closed
// triangle leaves out the opposite corner; 4 when none is.
int quad_ear(const glm::dvec2 q[4]) {
  int best = 4;
  double best_quality = -1.0;
  for (int i = 0; i < 4; ++i) {
    const glm::dvec2 &a = q[(i + 3) % 4], &b = q[i], &c = q[(i + 1) % 4], &p = q[(i + 2) % 4];
    const double turn = geometry::orient(a, b, c), longest = geometry::longest_edge2(a, b, c);
    const double tiny = geometry::ear_tolerance(longest);
    if (turn <= tiny || geometry::blocks_ear(a, b, c, p, tiny)) continue;
    const double quality = geometry::ear_quality(turn, longest);
    if (quality > best_quality) {
      best_quality = quality;
      best = i;
    }
  }
  return best;
}

// Whether every side and diagonal of the quad 0-1-2-3 over `q` is shorter than two rim spacings
// by a margin far beyond rounding: then worst_triangle (which looks only at triangles with an
// edge of two spacings or more) finds nothing in its triangles, and need not be run.
bool within_refine_size(const glm::dvec2 q[4], double spacing) {
  const double bound = 4.0 * spacing * spacing * (1.0 - 1e-9);
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j)
      if (!(glm::dot(q[j] - q[i], q[j] - q[i]) < bound)) return false;
  return true;
}

}  // namespace

// Whether the triangle with corners `p` lies wholly outside the solid cylinder, a tolerance
// clear of it: beyond one end plane, or beyond the line tangent to the cylinder across the
// corners' mean direction from the axis (every corner farther than r + eps along it). Then no
// point of the cylinder's cut in its plane, the centre of a hole included, lies in the triangle.
bool clear_of_cylinder(const CylinderFrame& cyl, const glm::dvec3 p[3]) {
  const double s0 = cyl.s(p[0]), s1 = cyl.s(p[1]), s2 = cyl.s(p[2]);
  if ((s0 < -cyl.eps && s1 < -cyl.eps && s2 < -cyl.eps) ||
      (s0 > cyl.len + cyl.eps && s1 > cyl.len + cyl.eps && s2 > cyl.len + cyl.eps))
    return true;
  const glm::dvec3 m[3] = {cyl.perp(p[0]), cyl.perp(p[1]), cyl.perp(p[2])};
  const glm::dvec3 sum = m[0] + m[1] + m[2];
  const double sl = glm::length(sum);
  if (!(sl > 0.0)) return false;
  const glm::dvec3 e = sum / sl;
  const double beyond = cyl.r + cyl.eps;
  return glm::dot(m[0], e) > beyond && glm::dot(m[1], e) > beyond && glm::dot(m[2], e) > beyond;
}

bool quad_triangles(const glm::dvec2 q[4], std::array<geometry::LocalTri, 2>& out) {
  const int i = quad_ear(q);
  if (i == 4) return false;
  const auto ear = static_cast<std::uint32_t>(i), prev = (ear + 3) % 4, next = (ear + 1) % 4,
             far = (ear + 2) % 4;
  // The last triangle starts at the first corner left (in input order): the three left, sorted.
  geometry::LocalTri last{};
  for (std::uint32_t k = 0, n = 0; k < 4; ++k)
    if (k != ear) last[n++] = k;
  if (!(geometry::orient(q[last[0]], q[last[1]], q[last[2]]) > 0.0)) return false;
  // The flips look at the last triangle's side of the diagonal first (prev -> next, with `far`
  // opposite), then at the other: after a flip, at the new diagonal from the first triangle.
  if (!flips(q, prev, next, far, ear)) {
    if (flips(q, next, prev, ear, far)) return false;
    out = {geometry::LocalTri{prev, ear, next}, last};
    return true;
  }
  if (flips(q, far, ear, next, prev)) return false;
  out = {geometry::LocalTri{ear, next, far}, geometry::LocalTri{far, prev, ear}};
  return true;
}

void FacePlanner::plan(std::size_t c, FaceId f, FacePlan& plan) {
  plan_ = &plan;
  plan.chunk = chunk_;
  plan.first_poly = static_cast<std::uint32_t>(out_.polys.size());
  const Triangle tri = s_.mesh.face(f);
  cur_ = &s_.faces[c];
  const glm::dvec3 corner[3] = {s_.posed(tri[0]), s_.posed(tri[1]), s_.posed(tri[2])};
  // A face with no piece of an edge inside keeps all of itself but a hole wholly inside it: its
  // boundary is worked out only for such a hole (most of those candidates are beside the rim).
  // A face clear of the cylinder (clear_of_cylinder) is not planned: none is cut there.
  const bool any_inside = any_piece_inside(*cur_);
  if (any_inside && boundary(tri, corner)) {  // all inside
    plan_->remove = 1;
    return;
  }
  face_.pc = plane_cut(s_.cyl, corner);  // worked out in place (the face's plane from here on)
  const PlaneCut& pc = face_.pc;
  if (pc.empty) {
    if (any_inside) plan_->remove = 1;  // a degenerate triangle or a plane the cylinder only touches
    return;
  }
  glm::dvec2 tq[3];
  for (int k = 0; k < 3; ++k) tq[k] = pc.coords(corner[k]);
  const double area2 = geometry::orient(tq[0], tq[1], tq[2]);
  if (!(area2 > 0.0)) {
    if (any_inside) plan_->remove = 1;
    return;
  }
  for (int k = 0; k < 3; ++k) face_.tq[k] = tq[k], face_.corner[k] = corner[k];
  face_.area2 = area2;
  if (!any_inside) {
    // Only a hole wholly inside the triangle can be left: its centre must lie inside.
    const glm::dvec3 cb = face_.bary_of({pc.ac, pc.b0});
    if (cb.x <= 0.0 || cb.y <= 0.0 || cb.z <= 0.0) return;
    boundary(tri, corner);
  }
  for (auto& lp : w_.pts) lp.q = pc.coords(lp.p);
  // Distance of a plane point from each edge is its barycentric coordinate times the height.
  for (int k = 0; k < 3; ++k)
    face_.height[k] = area2 / std::max(glm::length(tq[(k + 2) % 3] - tq[(k + 1) % 3]), 1e-300);
  sample_rim();
  if (any_inside) {
    kept_parts();
    return;
  }
  std::vector<LocalPoint>& rim = w_.rim;
  if (rim.size() < 3) return;
  // Triangle with an elliptic hole: the hole runs clockwise (decreasing phi).
  std::sort(rim.begin(), rim.end(), [](const LocalPoint& x, const LocalPoint& y) { return x.phi > y.phi; });
  const std::size_t first = out_.pts.size();
  out_.pts.insert(out_.pts.end(), w_.pts.begin(), w_.pts.begin() + 3);
  std::vector<std::uint32_t> outer = {0, 1, 2}, hole;
  for (auto& lp : rim) {
    hole.push_back(static_cast<std::uint32_t>(out_.pts.size() - first));
    out_.pts.push_back(lp);
  }
  plan_->remove = 1;
  add_polygon(first, outer, {hole});
}

// The triangle's boundary (face_boundary) with its rim points marked: the ends of every segment
// inside, and the points within the tolerance of the cylinder. Returns whether every segment
// lies inside.
bool FacePlanner::boundary(const Triangle& tri, const glm::dvec3 corner[3]) {
  face_boundary(tri, corner);
  std::vector<LocalPoint>& pts = w_.pts;
  const std::vector<std::uint8_t>& seg_inside = w_.seg_inside;
  const std::size_t m = pts.size();
  bool all_inside = true;
  for (std::size_t i = 0, before = m - 1; i < m; before = i++) {
    all_inside &= seg_inside[i] != 0;
    if (seg_inside[i] || seg_inside[before] || std::abs(s_.cyl.sd(pts[i].p)) <= s_.eps) pts[i].on_rim = true;
  }
  return all_inside;
}

// The triangle's boundary: corners, crossings and Steiner points in order (w_.pts), with the
// state of each segment (w_.seg_inside).
void FacePlanner::face_boundary(const Triangle& tri, const glm::dvec3 corner[3]) {
  std::vector<LocalPoint>& pts = w_.pts;
  std::vector<std::uint8_t>& seg_inside = w_.seg_inside;
  pts.clear();
  seg_inside.clear();
  for (int k = 0; k < 3; ++k) {
    const int k1 = (k + 1) % 3;
    const EdgeCut& e = cur_edge(k);
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
      x.v = steiner_first ? sv : s_.merges.merged(sv);
      x.p = s_.posed(sv);
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
      x.p = s_.posed(sv);
      x.bary = glm::dvec3(0.0);
      x.bary[k] = 1.0 - t;
      x.bary[k1] = t;
      pts.push_back(x);
      seg_inside.push_back(seg_inside.back());
    }
  }
}

// A rim sample at `x` (a ruling's point in the triangle's plane, or a corner of the rim on an
// end plane) joins w_.rim unless it falls outside the triangle or next to a boundary or rim point.
void FacePlanner::consider(const glm::dvec3& x, bool corner_point) {
  LocalPoint lp;
  lp.p = x;
  lp.q = face_.pc.coords(x);
  lp.bary = face_.bary_of(lp.q);
  int low = -1, lows = 0;
  for (int k = 0; k < 3; ++k)
    if (lp.bary[k] < 1e-7) low = k, ++lows;
  if (lows > 0) {
    // A ruling's point just beyond an edge the cylinder only grazes (too shallowly to be cut)
    // belongs to no face: the rim bulges over that edge by about the tolerance, and the face
    // across it does not take the point either (at a crease the ruling meets that plane beyond
    // the edge too, and no rim crosses an uncut edge). So that every ruling keeps its rim point,
    // it moves inside, a tolerance from the edge, when the move keeps it within half a percent
    // of r. On holes smaller than the absolute tolerance the move would round away in float
    // (zero-area faces): there the point is left out.
    if (corner_point || lows > 1) return;
    const int k1 = (low + 1) % 3, k2 = (low + 2) % 3;
    const double shift = s_.eps - lp.bary[low] * face_.height[low], bound = kShiftBound * s_.cyl.r;
    if (shift > bound || cur_edge(k1).n != 0) return;
    const glm::dvec2 along = glm::normalize(face_.tq[k2] - face_.tq[k1]);
    lp.q += shift * glm::dvec2(-along.y, along.x);  // inside is on the left
    lp.bary = face_.bary_of(lp.q);
    lp.p = face_.pc.point(lp.q.x, lp.q.y);
    for (int k = 0; k < 3; ++k)
      if (lp.bary[k] < 1e-7) return;
    if (std::abs(s_.cyl.sd(lp.p)) > bound) return;
  }
  // An end-plane corner gives way only to a rim point a hair away (two tolerances), not a rim
  // spacing: it is where a D-shaped rim's straight part meets its arc, and the chord that would
  // replace it leaves kept surface inside the cylinder, as deep as the gap.
  const double gap = corner_point ? 2.0 * s_.eps : s_.sep;
  for (const auto& b : w_.pts)
    if (b.on_rim && glm::length(b.p - lp.p) < gap) return;
  if (!corner_point)
    for (const auto& other : w_.rim)
      if (glm::length(other.p - lp.p) < s_.sep) return;
  lp.phi = face_.pc.phi(lp.q);
  lp.on_rim = true;
  w_.rim.push_back(lp);
}

// The corner where the rim's straight part (on an end plane) meets its arc. A corner inside the
// triangle is a rim sample. One just outside it (within a rim spacing: an edge grazes the hole
// there, too shallowly to be cut, or cuts the corner off alone) still bends the rim inside the
// triangle: the first points of both parts two tolerances inside stand for it, so the chord
// between the two parts' crossings does not leave kept surface inside the cylinder.
void FacePlanner::end_corner(double a_cap, double hh, double sign) {
  const PlaneCut& pc = face_.pc;
  const glm::dvec2 qc(a_cap, pc.b0 + sign * hh);
  const double out = -face_.clearance(qc);
  if (out <= 0.0 || out > s_.sep) {
    consider(pc.point(qc.x, qc.y), true);
    return;
  }
  const double margin = 2.0 * s_.eps, toward = pc.ac > a_cap ? 1.0 : -1.0;
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

// Rim samples (w_.rim): the fixed rulings' points in this plane, and the ellipse's end-plane
// corners.
void FacePlanner::sample_rim() {
  const PlaneCut& pc = face_.pc;
  w_.rim.clear();
  std::array<std::pair<double, double>, 2> chords{};  // (a, half length) on each end plane
  if (pc.c1 > 0.0) {  // end-plane corners first, so rulings next to them give way
    for (double s_cap : {0.0, s_.cyl.len}) {
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
  const std::size_t before_rulings = w_.rim.size();
  // Rulings whose point in this plane lies between the end planes.
  const int arc_rulings = pc.parallel ? 0 : sample_rulings(chords[0].second > 0.0 || chords[1].second > 0.0);
  const bool arc_sampled = w_.rim.size() > before_rulings;
  // A layer that only clips the cylinder's rim edge (one end plane, no ruling point kept between
  // the end planes here) cuts a thin lens. Its arc gets one point, the ellipse's apex (taken
  // before the straight part's points, which give way to it), so the lens has an area: with the
  // corners alone its arc would be the chord along the straight part, a slit no wall can close.
  if (!pc.parallel && !arc_sampled && (chords[0].second > 0.0) != (chords[1].second > 0.0)) {
    const double a_cap = chords[0].second > 0.0 ? chords[0].first : chords[1].first;
    consider(pc.point(a_cap < pc.ac ? pc.a0 + pc.ra : pc.a0 - pc.ra, pc.b0), false);
  }
  // A layer that crosses an end disk gets a D-shaped rim: its straight part on the end plane is
  // sampled at the rim spacing, and densely enough (down to half of it) that the whole D has
  // min_rim_edges edges when the axis crosses the layer (its arc is then at least half a turn).
  for (const auto& [a_cap, hh] : chords) {
    if (!(hh > 0.0)) continue;
    const double spacing = s_.cyl.spacing;
    const int by_spacing = static_cast<int>(std::ceil(2.0 * hh / spacing));
    const int by_count =
        std::min(s_.samples - arc_rulings + 1, static_cast<int>(std::floor(4.0 * hh / spacing)));
    const int pieces = std::min(std::max(by_spacing, by_count), 4 * s_.samples);
    const auto [first, last] = chord_pieces(a_cap, hh, pieces);
    for (int j = first; j < last; ++j) consider(pc.point(a_cap, pc.b0 - hh + 2.0 * hh * j / pieces), false);
  }
}

// The rulings' points in this (not parallel) plane, in increasing order of ruling (an earlier
// point wins over a later one too close to it): those of the rulings in the window are
// considered. Returns how many rulings meet the plane between the end planes, counted over
// every ruling when `count_all` (a chord needs that count), else over the window's.
int FacePlanner::sample_rulings(bool count_all) {
  const PlaneCut& pc = face_.pc;
  double angle[3];
  for (int k = 0; k < 3; ++k) angle[k] = cur_->angled ? cur_->angle[k] : s_.cyl.window_theta(face_.corner[k]);
  const RulingWindow w = ruling_window(s_.cyl, angle, s_.ruling_reach);
  int arc_rulings = 0;
  auto ruling = [&](int k, bool in_window) {
    const glm::dvec3& base = s_.ruling_base[static_cast<std::size_t>(k)];
    const double sv = glm::dot(pc.o - base, pc.n) / pc.dn;
    if (sv < 0.0 || sv > s_.cyl.len) return;
    ++arc_rulings;
    if (in_window) consider(base + sv * s_.cyl.d, false);
  };
  // The window is [first, first + count) modulo samples: its part past the last ruling wraps
  // round to [0, wrapped), below `first` (count <= samples).
  const int wrapped = std::max(0, w.first + w.count - s_.samples),
            last = std::min(w.first + w.count, s_.samples);
  if (count_all) {
    for (int k = 0; k < s_.samples; ++k) ruling(k, k < wrapped || (k >= w.first && k < last));
    return arc_rulings;
  }
  for (int k = 0; k < wrapped; ++k) ruling(k, true);
  for (int k = w.first; k < last; ++k) ruling(k, true);
  return arc_rulings;
}

// The points j of an end plane's chord at a = a_cap, split into `pieces` (b from b0 - hh to
// b0 + hh, 0 < j < pieces), that consider() can keep, as [first, last): it keeps a point only
// inside the triangle, or outside one edge by at most its shift bound (kShiftBound r). A point farther
// out than twice that (plus two tolerances: rounding is far smaller) is left out without being
// looked at; one more point each side of the range is looked at.
std::pair<int, int> FacePlanner::chord_pieces(double a_cap, double hh, int pieces) const {
  const double reach = 2.0 * (kShiftBound * s_.cyl.r + s_.eps);
  const glm::dvec3 from = face_.bary_of({a_cap, face_.pc.b0 - hh}),
                   to = face_.bary_of({a_cap, face_.pc.b0 + hh});
  double lo = 0.0, hi = 1.0;  // along the chord: distance from edge k is d0 + t (d1 - d0)
  for (int k = 0; k < 3; ++k) {
    const double d0 = from[k] * face_.height[k], slope = to[k] * face_.height[k] - d0;
    if (slope > 0.0)
      lo = std::max(lo, (-reach - d0) / slope);
    else if (slope < 0.0)
      hi = std::min(hi, (-reach - d0) / slope);
    else if (d0 < -reach)
      return {1, 1};
  }
  if (!(lo <= hi)) return {1, 1};
  const int first = std::max(1, static_cast<int>(std::floor(lo * pieces)) - 1);
  return {first, std::min(pieces, static_cast<int>(std::ceil(hi * pieces)) + 2)};
}

// Appends to `poly` the rim samples not yet used (w_.used) on the arc from `end` back to `start`
// (boundary points on the rim), in order from `end`, and marks them used. Returns how many.
std::size_t FacePlanner::add_arc(const LocalPoint& start, const LocalPoint& end,
                                 std::vector<LocalPoint>& poly) {
  const std::vector<LocalPoint>& rim = w_.rim;
  std::vector<std::uint8_t>& used = w_.used;
  const double phi_end = face_.pc.phi(end.q);
  const double span = geometry::wrap_2pi(phi_end - face_.pc.phi(start.q));
  std::vector<std::pair<double, std::size_t>>& arc = w_.arc;
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
  return arc.size();
}

// Runs of outside segments; each closes with the rim arc from its end back to its start.
void FacePlanner::kept_parts() {
  const std::vector<LocalPoint>& pts = w_.pts;
  const std::vector<std::uint8_t>& seg_inside = w_.seg_inside;
  const std::size_t m = pts.size();
  const auto next = [m](std::size_t i) { return i + 1 == m ? 0 : i + 1; };
  // A part starts at point i: the segment before it inside, the one after it outside.
  const auto starts_part = [&](std::size_t i) {
    return seg_inside[i == 0 ? m - 1 : i - 1] && !seg_inside[i];
  };
  std::size_t start = 0;
  while (start < m && !starts_part(start)) ++start;
  plan_->remove = 1;
  if (start == m) return;
  w_.used.assign(w_.rim.size(), 0);
  std::size_t left = w_.rim.size();  // rim samples in no part yet (no angles needed once none is)
  for (std::size_t step = 0, j = start; step < m; ++step, j = next(j)) {
    if (!starts_part(j)) continue;
    // The part's points go straight to the chunk's list (add_polygon plans them there).
    std::vector<LocalPoint>& poly = out_.pts;
    const std::size_t first = poly.size();
    std::size_t k = j;
    poly.push_back(pts[k]);
    while (!seg_inside[k]) {
      k = next(k);
      poly.push_back(pts[k]);
      if (k == j) break;
    }
    if (left > 0) left -= add_arc(pts[j], pts[k], poly);
    std::vector<std::uint32_t>& loop = w_.loop;
    loop.resize(poly.size() - first);
    for (std::size_t i = 0; i < loop.size(); ++i) loop[i] = static_cast<std::uint32_t>(i);
    add_polygon(first, loop, no_holes_);
  }
}

// Chew-style refinement of one kept part: points at the circumcentres of skinny triangles that
// are larger than the rim spacing (needles from a far corner to a small hole), kept away from
// the part's boundary so no edge of the parent triangle is split (its neighbour shares it).
void FacePlanner::refine(geometry::FlipTriangulation& ft, std::vector<glm::dvec2>& q,
                         const std::vector<std::uint32_t>& outer,
                         const std::vector<std::vector<std::uint32_t>>& holes) {
  const double spacing = s_.cyl.spacing;
  const std::size_t boundary = q.size();
  std::vector<std::pair<std::uint32_t, std::uint32_t>>& segments = w_.segments;
  segments.clear();
  const auto add_segments = [&segments](const std::vector<std::uint32_t>& l) {
    for (std::size_t i = 0; i < l.size(); ++i) segments.emplace_back(l[i], l[(i + 1) % l.size()]);
  };
  add_segments(outer);
  for (const auto& l : holes) add_segments(l);
  std::vector<geometry::LocalTri>& failed = w_.failed;  // by sorted_corners
  failed.clear();
  const std::size_t budget = 4 * boundary + 8;
  for (std::size_t added = 0; added < budget;) {
    const std::vector<geometry::LocalTri>& tris = ft.triangles();
    const geometry::LocalTri* worst = worst_triangle(tris.data(), tris.data() + tris.size(), q.data());
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
      failed.push_back(geometry::sorted_corners(t));  // not there: worst_triangle leaves those out
      continue;
    }
    LocalPoint lp;
    lp.q = centre;
    lp.p = face_.pc.point(centre.x, centre.y);
    lp.bary = bary;
    out_.pts.push_back(lp);
    ++added;
  }
}

// The triangle refine splits next: the one of worst shape (shortest edge over circumradius, under
// 20 degrees' worth) among those with an edge of two rim spacings or more, not in w_.failed (by
// sorted_corners); null when none is.
const geometry::LocalTri* FacePlanner::worst_triangle(const geometry::LocalTri* begin,
                                                      const geometry::LocalTri* end,
                                                      const glm::dvec2* q) const {
  const double spacing = s_.cyl.spacing;
  const std::vector<geometry::LocalTri>& failed = w_.failed;
  const geometry::LocalTri* worst = nullptr;
  double worst_ratio = 0.684;  // shortest edge / circumradius = 2 sin(min angle): 20 degrees
  for (const geometry::LocalTri* t = begin; t != end; ++t) {
    const glm::dvec2 &a = q[(*t)[0]], &b = q[(*t)[1]], &c = q[(*t)[2]];
    const double la = glm::length(b - c), lb = glm::length(c - a), lc = glm::length(a - b);
    const double area2 = std::abs(geometry::orient(a, b, c));
    if (!(area2 > 0.0) || std::max({la, lb, lc}) < 2.0 * spacing) continue;
    const double circumradius = la * lb * lc / (2.0 * area2);
    const double ratio = std::min({la, lb, lc}) / circumradius;
    if (ratio < worst_ratio &&
        std::find(failed.begin(), failed.end(), geometry::sorted_corners(*t)) == failed.end()) {
      worst_ratio = ratio;
      worst = t;
    }
  }
  return worst;
}

// A kept part that is a quad (points 0-3 in order) whose triangles quad_triangles works out and
// that refine would leave alone: its two triangles go to the chunk's list. Returns false (nothing
// added) for any other part.
bool FacePlanner::add_quad(const LocalPoint* pts, std::size_t count,
                           const std::vector<std::uint32_t>& outer) {
  if (outer.size() != 4 || count != 4) return false;
  const glm::dvec2 q[4] = {pts[0].q, pts[1].q, pts[2].q, pts[3].q};
  std::array<geometry::LocalTri, 2> tris;
  for (std::uint32_t k = 0; k < 4; ++k)
    if (outer[k] != k) return false;
  if (!quad_triangles(q, tris)) return false;
  w_.failed.clear();  // refine starts with none failed
  if (!within_refine_size(q, s_.cyl.spacing) && worst_triangle(tris.data(), tris.data() + 2, q)) return false;
  out_.tris.insert(out_.tris.end(), tris.begin(), tris.end());
  return true;
}

// A kept part that is a triangle is added as it is, most quads as add_quad works them out; any
// other is triangulated, flipped to Delaunay and refined in the plane. Its points (with the
// refinement's) and triangles go to the chunk's lists.
void FacePlanner::add_polygon(std::size_t first, const std::vector<std::uint32_t>& outer,
                              const std::vector<std::vector<std::uint32_t>>& holes) {
  PolygonPlan poly;
  poly.first_tri = static_cast<std::uint32_t>(out_.tris.size());
  const std::size_t count = out_.pts.size() - first;
  if (holes.empty() && outer.size() == 3) {
    out_.tris.push_back({outer[0], outer[1], outer[2]});
  } else if (!(holes.empty() && add_quad(out_.pts.data() + first, count, outer))) {
    std::vector<glm::dvec2>& q = w_.q;
    q.resize(count);
    for (std::size_t i = 0; i < count; ++i) q[i] = out_.pts[first + i].q;
    std::vector<geometry::LocalTri>& clipped = w_.clipped;
    clipped.clear();
    geometry::triangulate_polygon(q, outer, holes, kRimTriangulation, clipped);
    out_.gaps = out_.gaps || clipped.size() < whole_clip_triangles(outer, holes);
    geometry::FlipTriangulation& ft = w_.flips;
    ft.reset(q, clipped);
    ft.make_delaunay();
    refine(ft, q, outer, holes);
    out_.tris.insert(out_.tris.end(), ft.triangles().begin(), ft.triangles().end());
  }
  poly.tris = static_cast<std::uint32_t>(out_.tris.size()) - poly.first_tri;
  poly.first_pt = static_cast<std::uint32_t>(first);
  poly.pts = static_cast<std::uint32_t>(out_.pts.size() - first);
  out_.polys.push_back(poly);
  ++plan_->polys;
}

}  // namespace deepcut::drill
