// SPDX-License-Identifier: MIT
// Steiner points of a wall sheet: rows of points around the cylinder's side and rings on its end
// disks, graded away from the rims.
#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>

#include "ops/drill/walls/wall_shell.h"

namespace deepcut::drill {
namespace {

// Wall Steiner rows: away from the rims a ring keeps at least kWallSides points (an inscribed
// 24-gon holds 98.9% of the circle's area), rows are at most kWallAspect of its spacing apart
// (triangles of about 8 degrees at the narrowest), and where the rims' skin weights differ, rows
// at most kWallBend of weight change apart let the wall bend with them. At most kWallRows rows
// along the axis and kWallRings rings on an end disk.
constexpr int kWallSides = 24;
constexpr double kWallAspect = 7.0;
constexpr double kWallBend = 0.125;
constexpr double kWallRows = 256.0;
constexpr double kWallRings = 24.0;

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

}  // namespace

std::vector<WallPt> steiner_candidates(const WallShell& shell, const Loops& loops, const Segments& segments,
                                       const SheetExtent& extent, const SurfaceMesh& mesh) {
  const CylinderFrame& cy = shell.map.cy;
  const std::vector<WallPt>& pts = shell.pts;
  const int samples = cy.samples;
  const bool touches_a = extent.touches_a, touches_b = extent.touches_b, mobius = shell.map.mobius;
  const double lo = extent.lo, hi = extent.hi;
  // Steiner candidates on the cylinder's surface, away from the rims.
  const double h = 2.0 * geometry::kPi * cy.r / samples, row = 0.866 * h;
  auto near_boundary = [&](const glm::dvec3& p) {
    for (const auto& [u, v] : segments)
      if (geometry::segment_distance2(p, pts[u].p, pts[v].p) < 0.2 * h * h) return true;
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
    if (it == features.begin() || it == features.end() || !it->second.valid() ||
        !std::prev(it)->second.valid())
      return kInf;
    const double change = skin_change(mesh, std::prev(it)->second, it->second);
    return change > 0.0 ? (it->first - std::prev(it)->first) / std::ceil(change / kWallBend) : kInf;
  };
  const int fewest = std::min(samples, kWallSides);
  const double widest_ring = 2.0 * geometry::kPi * cy.r / fewest;
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
    const int n =
        end_circle
            ? samples
            : std::clamp(static_cast<int>(std::lround(2.0 * geometry::kPi * cy.r / ring_spacing(rows[j]))),
                         fewest, samples);
    for (int k = 0; k < n; ++k) {
      WallPt w;
      w.theta = std::remainder((k + (j % 2 ? 0.5 : 0.0)) * 2.0 * geometry::kPi / n, 2.0 * geometry::kPi);
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
      const int n = std::clamp(static_cast<int>(std::lround(2.0 * geometry::kPi * rho / std::max(h, ring))),
                               3, samples);
      for (int k = 0; k < n; ++k) {
        WallPt w;
        w.where = end;
        w.theta = std::remainder(2.0 * geometry::kPi * (k + 0.5 * (j % 2)) / n, 2.0 * geometry::kPi);
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
  return candidates;
}

}  // namespace deepcut::drill
