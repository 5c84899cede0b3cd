// SPDX-License-Identifier: MIT
#pragma once
// The planar kernel the drill uses (core/src/geometry/), under the names the drill's stages call.
// Private to the drill.

#include <cmath>

#include "geometry/delaunay_flip.h"
#include "geometry/polygon_triangulation.h"
#include "geometry/predicates.h"
#include "ops/drill/cylinder_section.h"

namespace deepcut::drill {

using geometry::angle_at;
using geometry::bridge;
using geometry::clip_polygon;
using geometry::FlipTriangulation;
using geometry::LocalTri;
using geometry::orient;
using geometry::segment_distance2;
using geometry::segments_cross;
using geometry::signed_area2;
using geometry::triangulate;
using geometry::winding;

/// `x` wrapped to [0, 2 pi).
inline double wrap_2pi(double x) {
  x = std::fmod(x, 2.0 * kPi);
  return x < 0.0 ? x + 2.0 * kPi : x;
}

}  // namespace deepcut::drill
