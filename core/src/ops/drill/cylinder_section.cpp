// SPDX-License-Identifier: MIT
#include "ops/drill/cylinder_section.h"

#include <cmath>

namespace deepcut::drill {

CylinderFrame CylinderFrame::make(const Cylinder& cylinder, const DrillOptions& options) {
  CylinderFrame cyl;
  cyl.a = glm::dvec3(cylinder.a);
  const glm::dvec3 b(cylinder.b);
  cyl.len = glm::length(b - cyl.a);
  cyl.d = (b - cyl.a) / cyl.len;
  cyl.r = cylinder.radius;
  const glm::dvec3 helper = std::abs(cyl.d.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  cyl.u = glm::normalize(glm::cross(helper, cyl.d));
  cyl.w = glm::cross(cyl.d, cyl.u);
  const double scale = glm::length(cyl.a) + glm::length(b) + cyl.len;
  cyl.eps = std::max(double(options.relative_tolerance) * cyl.r, 1e-6 * scale);
  cyl.samples = options.min_rim_edges;
  cyl.spacing = 2.0 * cyl.r * std::sin(geometry::kPi / cyl.samples);
  return cyl;
}

double CylinderFrame::window_theta(const glm::dvec3& p) const {
  const glm::dvec3 q = perp(p);
  const double x = glm::dot(q, u), y = glm::dot(q, w);
  if (std::isnan(x) || std::isnan(y)) return x + y;  // NaN, as atan2 gives (not angle 0)
  const double ax = std::abs(x), ay = std::abs(y), hi = std::max(ax, ay);
  if (!(hi > 0.0)) return 0.0;
  // atan on [0, 1] by a minimax polynomial (error under 1.7e-6), then the octant's symmetries.
  const double ratio = std::min(ax, ay) / hi, s2 = ratio * ratio;
  double t =
      ratio *
      (0.99997726 +
       s2 * (-0.33262347 + s2 * (0.19354346 + s2 * (-0.11643287 + s2 * (0.05265332 - s2 * 0.01172120)))));
  if (ay > ax) t = 0.5 * geometry::kPi - t;
  if (x < 0.0) t = geometry::kPi - t;
  return std::copysign(t, y);  // y = -0 takes -t as atan2 does
}

PlaneCut plane_cut(const CylinderFrame& cyl, const glm::dvec3 p[3]) {
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

double ruling_reach_angle(const CylinderFrame& cyl, double reach) {
  if (!(reach >= 0.0 && reach < 0.5 * cyl.r)) return -1.0;
  return std::asin(reach / (cyl.r - reach)) + 1e-9;
}

namespace {

// std::remainder(x, 2 pi) for |x| at most 2 pi (a difference of two atan2 angles), without the
// library call: the nearest multiple of the turn is -1, 0 or 1 (0 on a tie, the even one), and
// x -+ 2 pi is exact for |x| >= pi (Sterbenz), so the result is the same value (a zero may lose
// its sign: std::remainder gives -0.0 for x = -2 pi, this +0.0).
double wrap_half_turn(double x) {
  const double turn = 2.0 * geometry::kPi;
  if (x > 0.5 * turn) return x - turn;
  if (x < -0.5 * turn) return x + turn;
  return x;
}

}  // namespace

RulingWindow ruling_window(const CylinderFrame& cyl, const double angle[3], double reach_angle) {
  const int n = cyl.samples;
  const RulingWindow all{0, n};
  if (!(reach_angle >= 0.0)) return all;
  if (!std::isfinite(angle[0] + angle[1] + angle[2])) return all;  // a corner not finite
  // The shadow's angles from corner 0's, each within half a turn of it: the remainder of the
  // difference by a turn (|difference| <= a turn, and the step by a turn is exact there).
  double lo = 0.0, hi = 0.0;
  for (int k = 1; k < 3; ++k) {
    const double d = wrap_half_turn(angle[k] - angle[0]);
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  const double margin = reach_angle;
  if (!(hi - lo + 2.0 * margin < geometry::kPi)) return all;  // round the axis
  const double step = 2.0 * geometry::kPi / n;
  const double first = std::ceil((angle[0] + lo - margin) / step);
  const double last = std::floor((angle[0] + hi + margin) / step);
  if (last < first) return {0, 0};
  const int f = static_cast<int>(first);
  return {(f % n + n) % n, static_cast<int>(last - first) + 1};
}

}  // namespace deepcut::drill
