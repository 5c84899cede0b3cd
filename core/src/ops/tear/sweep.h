// SPDX-License-Identifier: MIT
#pragma once
// The tear surface: the quad a blade sweeps, as one or two planar sweep facets, and the
// half-plane tests that clip mesh chords to it. Private to the tear (ops/tear.h describes the
// operation).

#include <array>
#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

#include "deepcut/core/ops/tear.h"
#include "deepcut/core/spatial_index.h"

namespace deepcut::detail::tear {

/// One planar part of the tear surface: a plane and one or two triangles in it, each given by its
/// three inward half-planes in the plane's 2D frame (h(q) = dot(q - corner, inward) >= 0 inside).
struct SweepFacet {
  glm::dvec3 origin{0.0}, normal{0.0}, e1{0.0}, e2{0.0};
  std::vector<std::array<glm::dvec2, 3>> corners;  // counter-clockwise in (e1, e2)
  std::vector<std::array<glm::dvec2, 3>> inward;   // unit inward normal of edge k (corner k -> k+1)
  std::vector<std::array<glm::vec3, 3>> world;     // the triangles in world space
  BoundingBox box;

  glm::dvec2 project(const glm::dvec3& p) const { return {glm::dot(p - origin, e1), glm::dot(p - origin, e2)}; }
  std::size_t hcount() const { return 3 * corners.size(); }
};

/// The tear surface of a blade swept from `start` to `end`: one facet (the planar quad) or two
/// (the quad folded along H0-T1), as ops/tear.h's swept_quad_triangles describes.
/// @throws Error{InvalidArgument} for a non-finite, zero-length or out-of-scale blade, identical
///         poses, or a sweep without area.
std::vector<SweepFacet> make_sweep(const Blade& start, const Blade& end);

/// Half-plane values of one point against every triangle of a facet (at most two triangles).
using HValues = std::array<double, 6>;

HValues hvalues(const SweepFacet& facet, const glm::dvec2& q);

/// True when the half-plane values put the point inside one of the facet's triangles.
bool inside(const SweepFacet& facet, const HValues& h);

/// A parameter range [lo, hi] along a segment.
struct Interval {
  double lo, hi;
};

/// The parts of the segment a -> b (parameter 0..1) inside the facet, from the endpoints'
/// half-plane values (the same values decide inside(a), so the two tests never disagree), merged,
/// snapped to the ends within `snap` and without parts shorter than `snap` (a whole segment is
/// always kept).
std::vector<Interval> clip_segment(const SweepFacet& facet, const HValues& ha, const HValues& hb, double snap);

/// True when `s` lies in one of `ivs`.
bool in_intervals(const std::vector<Interval>& ivs, double s);

/// On which side of the tear surface `p` lies, as a signed distance: to the plane of the nearest
/// of the facets `which` (nearest by the distance to the facet's triangles), except where the two
/// facets of a folded quad put `p` on opposite sides of their planes: there the fold decides
/// (beyond a facet's triangle the nearer facet can be the wrong one).
double nearest_side(const std::vector<SweepFacet>& facets, const std::vector<std::size_t>& which, const glm::dvec3& p);

}  // namespace deepcut::detail::tear
