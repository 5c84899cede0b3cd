// SPDX-License-Identifier: MIT
#include "ops/common/face_refinement.h"

#include <algorithm>
#include <cmath>

#include "geometry/predicates.h"

namespace deepcut::detail {

FaceRefinement::FaceRefinement(const Triangle& face) {
  points_ = {{face[0], {1, 0, 0}}, {face[1], {0, 1, 0}}, {face[2], {0, 0, 1}}};
  tris_ = {{0, 1, 2}};
}

VertexId FaceRefinement::insert(VertexId v, const glm::dvec3& bary) {
  const glm::dvec2 q(bary.y, bary.z);
  // The sub-triangle the point is deepest in (largest smallest barycentric coordinate).
  int best = -1;
  glm::dvec3 best_l(0.0);
  double best_min = -1e300;
  for (std::size_t i = 0; i < tris_.size(); ++i) {
    const glm::dvec3 l = local_bary(tris_[i], q);
    const double m = std::min({l.x, l.y, l.z});
    if (m > best_min) {
      best_min = m;
      best = static_cast<int>(i);
      best_l = l;
    }
  }
  constexpr double eps = 1e-9;
  int zeros = 0, zk = -1, nz = -1;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(best_l[k]) <= eps) {
      ++zeros;
      zk = k;
    } else {
      nz = k;
    }
  }
  const std::array<int, 3> t = tris_[best];
  if (zeros >= 2) return points_[t[nz]].v;  // coincides with an existing point
  const int id = static_cast<int>(points_.size());
  points_.push_back({v, bary});
  if (zeros == 0) {
    tris_[best] = {t[0], t[1], id};
    tris_.push_back({t[1], t[2], id});
    tris_.push_back({t[2], t[0], id});
    return v;
  }
  // On the edge opposite corner zk: split this triangle and the one across the edge.
  const int a = t[zk], b = t[(zk + 1) % 3], c = t[(zk + 2) % 3];
  tris_[best] = {a, b, id};
  tris_.push_back({a, id, c});
  for (std::size_t i = 0; i < tris_.size(); ++i) {
    auto& o = tris_[i];
    for (int k = 0; k < 3; ++k)
      if (o[k] == c && o[(k + 1) % 3] == b) {
        const int x = o[(k + 2) % 3];
        o = {x, c, id};
        tris_.push_back({x, id, b});
        return v;
      }
  }
  return v;
}

glm::dvec3 FaceRefinement::local_bary(const std::array<int, 3>& t, const glm::dvec2& q) const {
  const glm::dvec2 a(points_[t[0]].bary.y, points_[t[0]].bary.z), b(points_[t[1]].bary.y, points_[t[1]].bary.z),
      c(points_[t[2]].bary.y, points_[t[2]].bary.z);
  const double d = geometry::orient(a, b, c);
  if (d == 0.0) return glm::dvec3(-1e300);
  const double l1 = geometry::orient(a, q, c) / d;
  const double l2 = geometry::orient(a, b, q) / d;
  return {1.0 - l1 - l2, l1, l2};
}

}  // namespace deepcut::detail
