// SPDX-License-Identifier: MIT
#pragma once
// The drill wall's plane: the cylinder's surface (side and end disks) mapped conformally to one
// plane, where the rims of a shell are closed loops (see core/src/ops/drill/walls/wall.h), and
// the winding-number tests the wall's stages make there. Private to the drill.

#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "deepcut/core/surface_mesh.h"
#include "ops/drill/cylinder_section.h"

namespace deepcut::drill {

using Loops = std::vector<std::vector<std::uint32_t>>;

// The wall plane map spans at most exp(kWallSpan) in scale: exact orientation tests stay
// reliable, and longer walls are compressed along the axis (kappa).
constexpr double kWallSpan = 8.0;

// A point of the wall on the cylinder's surface.
struct WallPt {
  glm::dvec3 p{0.0};  // posed, on the cylinder's surface
  double theta = 0.0, s = 0.0, rho = 0.0;
  int where = 0;      // 0 side, 1 end disk at A, 2 end disk at B
  bool pole = false;  // the B disk's centre when the plane map sends it to the origin
  VertexId v;         // the vertex (rim), or invalid until a Steiner point is created
};

// z = exp(l) (cos theta, sin theta), with l = (s - base) / (r kappa) on the side, and the end
// disks continuing it conformally (l - l_A = ln(rho / r) on the disk at A, l_B - l = ln(rho / r)
// at B, whose centre goes to infinity); with `mobius`, z -> conj(1 / (z - z0)) after that, which
// brings the B disk's centre in from infinity.
struct WallMap {
  CylinderFrame cy;
  double base = 0.0, kappa = 1.0;
  bool mobius = false;
  glm::dvec2 z0{0.0};

  double l_a() const { return (0.0 - base) / (cy.r * kappa); }
  double l_b() const { return (cy.len - base) / (cy.r * kappa); }
  /// Sets base and kappa for the extent [lo, hi] along the axis (no Moebius step).
  void span(double lo, double hi);
  glm::dvec2 to_plane(const WallPt& w) const;
  WallPt from_plane(glm::dvec2 z) const;
};

/// Fills `w` for the posed point `p`: false when `p` lies neither on the side nor on an end disk
/// (within `tol`).
bool classify(const CylinderFrame& cy, double tol, const glm::dvec3& p, WallPt& w);

/// A point beside the step a->b: `offset` times its length to the left (negative: right).
glm::dvec2 side_point(const std::vector<glm::dvec2>& xy, std::uint32_t a, std::uint32_t b, double offset);
/// The longest step of a loop (its index).
std::size_t longest_step(const std::vector<glm::dvec2>& xy, const std::vector<std::uint32_t>& l);
/// Inside a sheet: winding + c == 1 just left of every rim step, 0 just right of it. Sets `c`.
bool consistent(const std::vector<glm::dvec2>& xy, const Loops& ls, int& c);

}  // namespace deepcut::drill
