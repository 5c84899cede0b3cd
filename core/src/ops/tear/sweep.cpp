// SPDX-License-Identifier: MIT
#include "ops/tear/sweep.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "deepcut/core/errors.h"
#include "geometry/predicates.h"

namespace deepcut::detail::tear {
namespace {

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void check_blade(const Blade& b, const char* which) {
  if (!finite(b.handle) || !finite(b.tip))
    throw Error(ErrorCode::InvalidArgument, std::string("tear: the ") + which + " blade is not finite");
}

// Refuses blades of zero length, and a blade a million times shorter than the sweep (as
// degenerate as a zero-length one): says which pose is out of scale (usually a mistyped
// coordinate) rather than blame the shorter one.
void check_blade_lengths(double len0, double len1, double size) {
  if (len0 == 0.0 || size == 0.0)
    throw Error(ErrorCode::InvalidArgument, "tear: the start blade has zero length (handle == tip)");
  if (len1 == 0.0) throw Error(ErrorCode::InvalidArgument, "tear: the end blade has zero length (handle == tip)");
  if (std::min(len0, len1) > 1e-6 * size) return;
  const auto text = [](double v) {
    std::ostringstream o;
    o << v;
    return o.str();
  };
  const bool start_longer = len0 > len1;
  const double longer = std::max(len0, len1), shorter = std::min(len0, len1);
  if (longer > 1e6 * shorter)
    throw Error(ErrorCode::InvalidArgument,
                std::string("tear: the ") + (start_longer ? "start" : "end") + " blade (length " + text(longer) +
                    ") is over a million times longer than the " + (start_longer ? "end" : "start") +
                    " blade (length " + text(shorter) + "); check its coordinates");
  throw Error(ErrorCode::InvalidArgument, "tear: the blade (length " + text(shorter) +
                                              ") is over a million times shorter than its sweep (" + text(size) +
                                              "); check the end pose's coordinates");
}

SweepFacet make_facet(const glm::dvec3& normal, const glm::dvec3& origin) {
  SweepFacet p;
  p.normal = glm::normalize(normal);
  p.origin = origin;
  const glm::dvec3 axis = std::abs(p.normal.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  p.e1 = glm::normalize(glm::cross(p.normal, axis));
  p.e2 = glm::cross(p.normal, p.e1);
  return p;
}

// Adds a triangle (world corners, assumed in or projected onto the facet's plane).
void add_triangle(SweepFacet& facet, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                  double min_area2) {
  std::array<glm::dvec2, 3> q = {facet.project(a), facet.project(b), facet.project(c)};
  const double area2 = geometry::orient(q[0], q[1], q[2]);
  if (std::abs(area2) <= min_area2) return;
  if (area2 < 0.0) std::swap(q[1], q[2]);
  std::array<glm::dvec2, 3> m;
  for (int k = 0; k < 3; ++k) {
    const glm::dvec2 d = q[(k + 1) % 3] - q[k];
    m[k] = glm::normalize(glm::dvec2(-d.y, d.x));
  }
  facet.corners.push_back(q);
  facet.inward.push_back(m);
  std::array<glm::vec3, 3> w;
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3 p = facet.origin + q[k].x * facet.e1 + q[k].y * facet.e2;
    w[k] = glm::vec3(p);
    facet.box.add(w[k]);
  }
  facet.world.push_back(w);
}

}  // namespace

std::vector<SweepFacet> make_sweep(const Blade& start, const Blade& end) {
  check_blade(start, "start");
  check_blade(end, "end");
  const glm::dvec3 h0(start.handle), t0(start.tip), h1(end.handle), t1(end.tip);
  const double size = std::max({glm::length(t0 - h0), glm::length(t1 - h1), glm::length(h1 - h0),
                                glm::length(t1 - t0), glm::length(t1 - h0), glm::length(h1 - t0)});
  check_blade_lengths(glm::length(t0 - h0), glm::length(t1 - h1), size);
  if (glm::length(h1 - h0) + glm::length(t1 - t0) <= 1e-6 * size)
    throw Error(ErrorCode::InvalidArgument, "tear: the blade's start and end poses are identical");
  const glm::dvec3 n1 = glm::cross(t0 - h0, t1 - h0), n2 = glm::cross(t1 - h0, h1 - h0);
  glm::dvec3 n = n1 + n2;
  const double min_area2 = 1e-9 * size * size;
  if (glm::length(n) <= min_area2) n = glm::length(n1) >= glm::length(n2) ? n1 : n2;
  if (glm::length(n) <= min_area2)
    throw Error(ErrorCode::InvalidArgument, "tear: the blade moves along its own line; the swept quad has no area");
  const glm::dvec3 centre = 0.25 * (h0 + t0 + t1 + h1);
  const glm::dvec3 nn = glm::normalize(n);
  double off = 0.0;
  for (const auto& p : {h0, t0, t1, h1}) off = std::max(off, std::abs(glm::dot(p - centre, nn)));
  std::vector<SweepFacet> facets;
  if (off <= 1e-3 * size) {
    SweepFacet p = make_facet(nn, centre);
    add_triangle(p, h0, t0, t1, min_area2);
    add_triangle(p, h0, t1, h1, min_area2);
    facets.push_back(std::move(p));
  } else {
    for (const auto& tri : {std::array<glm::dvec3, 3>{h0, t0, t1}, std::array<glm::dvec3, 3>{h0, t1, h1}}) {
      const glm::dvec3 tn = glm::cross(tri[1] - tri[0], tri[2] - tri[0]);
      if (glm::length(tn) <= min_area2) continue;
      SweepFacet p = make_facet(tn, (tri[0] + tri[1] + tri[2]) / 3.0);
      add_triangle(p, tri[0], tri[1], tri[2], min_area2);
      facets.push_back(std::move(p));
    }
  }
  std::size_t tris = 0;
  for (const auto& p : facets) tris += p.corners.size();
  if (tris == 0) throw Error(ErrorCode::InvalidArgument, "tear: the swept quad has no area");
  return facets;
}

HValues hvalues(const SweepFacet& facet, const glm::dvec2& q) {
  HValues h{};
  for (std::size_t j = 0; j < facet.corners.size(); ++j)
    for (int k = 0; k < 3; ++k) h[3 * j + k] = glm::dot(q - facet.corners[j][k], facet.inward[j][k]);
  return h;
}

bool inside(const SweepFacet& facet, const HValues& h) {
  for (std::size_t j = 0; j < facet.corners.size(); ++j)
    if (h[3 * j] >= 0.0 && h[3 * j + 1] >= 0.0 && h[3 * j + 2] >= 0.0) return true;
  return false;
}

std::vector<Interval> clip_segment(const SweepFacet& facet, const HValues& ha, const HValues& hb, double snap) {
  std::vector<Interval> raw;
  for (std::size_t j = 0; j < facet.corners.size(); ++j) {
    double lo = 0.0, hi = 1.0;
    bool empty = false;
    for (int k = 0; k < 3 && !empty; ++k) {
      const double a = ha[3 * j + k], b = hb[3 * j + k];
      if (a >= 0.0 && b >= 0.0) continue;
      if (a < 0.0 && b < 0.0) {
        empty = true;
        break;
      }
      const double s = a / (a - b);
      if (a < 0.0)
        lo = std::max(lo, s);
      else
        hi = std::min(hi, s);
    }
    if (!empty && lo <= hi) raw.push_back({lo, hi});
  }
  std::sort(raw.begin(), raw.end(), [](const Interval& x, const Interval& y) { return x.lo < y.lo; });
  std::vector<Interval> merged;
  for (const Interval& iv : raw) {
    if (!merged.empty() && iv.lo <= merged.back().hi + snap)
      merged.back().hi = std::max(merged.back().hi, iv.hi);
    else
      merged.push_back(iv);
  }
  std::vector<Interval> out;
  for (Interval iv : merged) {
    if (iv.lo < snap) iv.lo = 0.0;
    if (iv.hi > 1.0 - snap) iv.hi = 1.0;
    const bool whole = iv.lo == 0.0 && iv.hi == 1.0;
    if (whole || iv.hi - iv.lo > snap) out.push_back(iv);
  }
  return out;
}

bool in_intervals(const std::vector<Interval>& ivs, double s) {
  for (const Interval& iv : ivs)
    if (s >= iv.lo && s <= iv.hi) return true;
  return false;
}

double nearest_side(const std::vector<SweepFacet>& facets, const std::vector<std::size_t>& which, const glm::dvec3& p) {
  if (which.size() == 2) {
    // Two facets of a folded quad: where their planes disagree the fold decides, not the nearer
    // facet. The positive side of the fold is the intersection of the planes' positive sides when
    // each facet stands on the other's positive side (the fold is convex there), else their union.
    const SweepFacet &f0 = facets[which[0]], &f1 = facets[which[1]];
    const double d0 = glm::dot(p - f0.origin, f0.normal), d1 = glm::dot(p - f1.origin, f1.normal);
    if ((d0 > 0.0 && d1 < 0.0) || (d0 < 0.0 && d1 > 0.0)) {
      const double lean = glm::dot(f1.origin - f0.origin, f0.normal);
      if (lean != 0.0) return lean > 0.0 ? std::min(d0, d1) : std::max(d0, d1);
    }
  }
  double best = 1e300, side = 0.0;
  for (std::size_t i : which) {
    const SweepFacet& pc = facets[i];
    const double d = glm::dot(p - pc.origin, pc.normal);
    const HValues h = hvalues(pc, pc.project(p));
    double out = 1e300;
    for (std::size_t j = 0; j < pc.corners.size(); ++j)
      out = std::min(out, std::max({0.0, -h[3 * j], -h[3 * j + 1], -h[3 * j + 2]}));
    const double dist = d * d + out * out;
    if (dist < best) {
      best = dist;
      side = d;
    }
  }
  return side;
}

}  // namespace deepcut::detail::tear
