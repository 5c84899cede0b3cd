// SPDX-License-Identifier: MIT
#include "ops/drill/walls/wall_map.h"

#include <algorithm>
#include <cmath>

#include "geometry/predicates.h"

namespace deepcut::drill {

void WallMap::span(double lo, double hi) {
  base = lo;
  kappa = std::max(1.0, (hi - lo) / (kWallSpan * cy.r));
  mobius = false;
}

glm::dvec2 WallMap::to_plane(const WallPt& w) const {
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
}

WallPt WallMap::from_plane(glm::dvec2 z) const {
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
}

bool classify(const CylinderFrame& cy, double tol, const glm::dvec3& p, WallPt& w) {
  w.p = p;
  w.s = cy.s(p);
  const double rho = cy.rho(p);
  w.rho = rho;
  w.theta = cy.theta(p);
  w.where = 0;
  if (rho < cy.r - tol) {
    if (std::abs(w.s) <= tol)
      w.where = 1;
    else if (std::abs(w.s - cy.len) <= tol)
      w.where = 2;
    else
      return false;  // neither on the side nor on an end disk
  } else if (std::abs(rho - cy.r) > tol || w.s < -tol || w.s > cy.len + tol) {
    return false;
  }
  return true;
}

glm::dvec2 side_point(const std::vector<glm::dvec2>& xy, std::uint32_t a, std::uint32_t b, double offset) {
  const glm::dvec2 e = xy[b] - xy[a];
  return 0.5 * (xy[a] + xy[b]) + offset * glm::dvec2(-e.y, e.x);
}

std::size_t longest_step(const std::vector<glm::dvec2>& xy, const std::vector<std::uint32_t>& l) {
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
}

bool consistent(const std::vector<glm::dvec2>& xy, const Loops& ls, int& c) {
  for (std::size_t li = 0; li < ls.size(); ++li) {
    const auto& l = ls[li];
    const std::size_t i = longest_step(xy, l);
    const std::uint32_t a = l[i], b = l[(i + 1) % l.size()];
    const int left = geometry::winding(xy, ls, side_point(xy, a, b, 1e-6)),
              right = geometry::winding(xy, ls, side_point(xy, a, b, -1e-6));
    if (left - right != 1) return false;
    if (li == 0)
      c = 1 - left;
    else if (left + c != 1)
      return false;
  }
  return true;
}

}  // namespace deepcut::drill
