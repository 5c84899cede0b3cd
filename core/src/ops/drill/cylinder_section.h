// SPDX-License-Identifier: MIT
#pragma once
// The drill's cylinder in double precision (an orthonormal frame, its tolerances) and the region
// it cuts from one triangle's plane. Private to the drill (core/src/ops/drill/); the algorithm is
// described in core/include/deepcut/core/ops/drill.h.

#include <algorithm>
#include <cstdint>
#include <glm/glm.hpp>
#include <limits>

#include "deepcut/core/ops/drill.h"
#include "deepcut/core/surface_mesh.h"
#include "geometry/predicates.h"
#include "ops/common/crossing_table.h"

namespace deepcut::drill {

constexpr double kInf = std::numeric_limits<double>::infinity();

using detail::directed_key;
using detail::edge_key;

// The cylinder in double precision, with an orthonormal frame (u, w, d), the snapping tolerance
// `eps` (absolute) and the number of rulings sampled around the axis.
struct CylinderFrame {
  glm::dvec3 a, d, u, w;
  double len = 0.0, r = 0.0;
  double eps = 0.0;
  int samples = 32;
  double spacing = 0.0;  // between rim samples: 2 r sin(pi / samples)

  /// The frame of `cylinder` with the tolerance and sampling of `options`.
  static CylinderFrame make(const Cylinder& cylinder, const DrillOptions& options);

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
  double sd(const glm::dvec3& p) const { return sd_of(s(p), rho(p) - r); }
  // sd of a point at s(p) = sv and rho(p) - r = rho_off (for a caller that has both already).
  double sd_of(double sv, double rho_off) const { return std::max({rho_off, -sv, sv - len}); }
  // Well inside the solid (beyond twice the tolerance): no edge between two such points is
  // crossed or grazed (the solid is convex), and a face with three such corners is removed
  // whole, leaving its corners without faces.
  bool deep_inside(const glm::dvec3& p) const { return deep_sd(sd(p)); }
  // Whether a point with this sd lies deep inside (deep_inside).
  bool deep_sd(double sdv) const { return sdv < -2.0 * eps; }
  // theta(p) within 1.7e-6 (radians, modulo a turn; 0 on the axis), without the library's atan2:
  // for ruling windows only (ruling_window), whose margin is far wider than that. Not finite
  // for a point that is not (the window is then every ruling).
  double window_theta(const glm::dvec3& p) const;
  glm::dvec3 ruling(double th) const { return std::cos(th) * u + std::sin(th) * w; }
  glm::dvec3 at(double th, double sv) const { return a + r * ruling(th) + sv * d; }
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

/// The cut of the triangle `p` (posed corners) by the solid cylinder, in the triangle's plane.
PlaneCut plane_cut(const CylinderFrame& cyl, const glm::dvec3 p[3]);

/// Sampled rulings (cyl.samples equal angles around the axis, ruling k at 2 pi k / samples) by
/// index: `count` of them from `first` on, modulo samples.
struct RulingWindow {
  int first = 0, count = 0;  // 0 <= first < samples, 0 <= count <= samples
};

/// How far (as a fraction of the radius) the rim sampling's consider() (rim_faces.cpp) moves a
/// ruling's point that falls just beyond an edge back inside: the shift, and the point's distance
/// from the cylinder after it, stay within this. chord_pieces() skips chord points from the same
/// figure, so the skip can never drop a point consider() would keep.
inline constexpr double kShiftBound = 0.005;
/// The reach the rim sampling's ruling windows ask for, as a fraction of the radius: four times
/// kShiftBound, so a window holds every ruling that can give a point (one within kShiftBound r)
/// with room far beyond CylinderFrame::window_theta's error (ruling_window).
inline constexpr double kWindowReach = 4.0 * kShiftBound;

/// How far around the axis, beyond a triangle's shadow on the axis's normal plane, a point of
/// the cylinder's side within `reach` of the triangle can lie: asin(reach / (r - reach)), or a
/// negative value when `reach` is not small against r (every ruling can then reach it).
double ruling_reach_angle(const CylinderFrame& cyl, double reach);

/// The rulings that can pass within `reach` of the triangle whose corners lie at the angles
/// `angle` around the axis (CylinderFrame::window_theta of its posed corners), given
/// `reach_angle` = ruling_reach_angle(cyl, reach): those within that angle of the triangle's
/// shadow, or all of them when the shadow comes round the axis, so the rim sampling tests only
/// the rulings that can give it a point. The rim sampling keeps points within kShiftBound r
/// of a triangle and asks for a reach of kWindowReach r, four times that: the window holds every
/// ruling that can give a point with room far beyond window_theta's error, so a ruling more or
/// less at its ends changes nothing (one outside gives no point).
RulingWindow ruling_window(const CylinderFrame& cyl, const double angle[3], double reach_angle);

}  // namespace deepcut::drill
