// SPDX-License-Identifier: MIT
#include "geometry/delaunay_flip.h"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace deepcut::geometry {

FlipTriangulation::FlipTriangulation(std::vector<glm::dvec2>& pts, std::vector<LocalTri> tris)
    : pts_(&pts), tris_(std::move(tris)) {
  nbr_.assign(tris_.size(), {-1, -1, -1});
  link_neighbours();
}

void FlipTriangulation::reset(std::vector<glm::dvec2>& pts, const std::vector<LocalTri>& tris) {
  pts_ = &pts;
  tris_.assign(tris.begin(), tris.end());
  nbr_.assign(tris_.size(), {-1, -1, -1});
  last_ = 0;
  link_neighbours();
}

// Each half-edge a->b finds the triangle holding b->a; where b->a repeats, the last triangle
// listing it is the one found (as a map overwritten in triangle order gives). The half-edges are
// grouped by start point with a counting sort, which keeps each group in triangle order.
void FlipTriangulation::link_neighbours() {
  std::size_t points = 0;
  for (const LocalTri& t : tris_) points = std::max<std::size_t>(points, std::max({t[0], t[1], t[2]}) + std::size_t(1));
  first_out_.assign(points + 1, 0);
  for (const LocalTri& t : tris_)
    for (int k = 0; k < 3; ++k) ++first_out_[t[k] + 1];
  for (std::size_t p = 0; p < points; ++p) first_out_[p + 1] += first_out_[p];
  out_.resize(3 * tris_.size());
  for (std::size_t i = 0; i < tris_.size(); ++i)
    for (int k = 0; k < 3; ++k) out_[first_out_[tris_[i][k]]++] = {tris_[i][(k + 1) % 3], static_cast<int>(i)};
  for (std::size_t p = points; p > 0; --p) first_out_[p] = first_out_[p - 1];  // back to group starts
  first_out_[0] = 0;
  for (std::size_t i = 0; i < tris_.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = tris_[i][k], b = tris_[i][(k + 1) % 3];
      int found = -1;
      for (std::uint32_t h = first_out_[b]; h < first_out_[b + 1]; ++h)
        if (out_[h].first == a) found = out_[h].second;
      if (found >= 0 && found != static_cast<int>(i)) nbr_[i][k] = found;
    }
}

bool FlipTriangulation::is_interior(std::uint32_t a, std::uint32_t b) const {
  for (std::size_t t = 0; t < tris_.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (tris_[t][k] == a && tris_[t][(k + 1) % 3] == b) return nbr_[t][k] >= 0;
  return false;
}

void FlipTriangulation::make_delaunay() {
  stack_.clear();
  for (std::size_t i = 0; i < tris_.size(); ++i)
    for (int k = 0; k < 3; ++k) stack_.emplace_back(static_cast<int>(i), k);
  legalize();
}

bool FlipTriangulation::insert(const glm::dvec2& p) {
  const int t = locate(p);
  if (t < 0) return false;
  const auto id = static_cast<std::uint32_t>(pts_->size());
  pts_->push_back(p);
  const LocalTri old = tris_[t];
  const auto n = nbr_[t];
  const int t1 = static_cast<int>(tris_.size()), t2 = t1 + 1;
  tris_[t] = {old[0], old[1], id};
  tris_.push_back({old[1], old[2], id});
  tris_.push_back({old[2], old[0], id});
  nbr_[t] = {n[0], t1, t2};
  nbr_.push_back({n[1], t2, t});
  nbr_.push_back({n[2], t, t1});
  relink(n[1], t, t1);
  relink(n[2], t, t2);
  stack_.assign({{t, 0}, {t1, 0}, {t2, 0}});
  legalize();
  last_ = static_cast<std::size_t>(t);
  return true;
}

void FlipTriangulation::relink(int n, int from, int to) {
  if (n < 0) return;
  for (int k = 0; k < 3; ++k)
    if (nbr_[n][k] == from) nbr_[n][k] = to;
}

double FlipTriangulation::orient_rel(std::uint32_t a, std::uint32_t b, const glm::dvec2& p) const {
  const std::vector<glm::dvec2>& pts = *pts_;
  const glm::dvec2 e = pts[b] - pts[a], f = p - pts[a];
  const double scale = std::max(glm::dot(e, e), glm::dot(f, f));
  const double o = e.x * f.y - e.y * f.x;
  return std::abs(o) <= 1e-12 * scale ? 0.0 : o;
}

int FlipTriangulation::locate(const glm::dvec2& p) const {
  int t = last_ < tris_.size() ? static_cast<int>(last_) : 0;
  for (std::size_t steps = 0; steps < tris_.size() + 3; ++steps) {
    int next = -2;
    for (int k = 0; k < 3 && next == -2; ++k)
      if (orient_rel(tris_[t][k], tris_[t][(k + 1) % 3], p) < 0.0) next = nbr_[t][k];
    if (next == -2) break;  // inside (or on an edge)
    if (next < 0) return scan(p);
    t = next;
  }
  for (int k = 0; k < 3; ++k)
    if (orient_rel(tris_[t][k], tris_[t][(k + 1) % 3], p) <= 0.0) return scan(p);
  return t;
}

int FlipTriangulation::scan(const glm::dvec2& p) const {
  for (std::size_t t = 0; t < tris_.size(); ++t) {
    bool in = true;
    for (int k = 0; k < 3 && in; ++k) in = orient_rel(tris_[t][k], tris_[t][(k + 1) % 3], p) > 0.0;
    if (in) return static_cast<int>(t);
  }
  return -1;
}

void FlipTriangulation::legalize() {
  std::vector<std::pair<int, int>>& stack = stack_;
  const std::vector<glm::dvec2>& pts = *pts_;
  std::size_t guard = 64 * (tris_.size() + 16) * (tris_.size() + 16);
  while (!stack.empty() && guard-- > 0) {
    const auto [t, k] = stack.back();
    stack.pop_back();
    const int u = nbr_[t][k];
    if (u < 0) continue;
    const std::uint32_t a = tris_[t][k], b = tris_[t][(k + 1) % 3], c = tris_[t][(k + 2) % 3];
    int j = -1;
    for (int m = 0; m < 3; ++m)
      if (tris_[u][m] == b && tris_[u][(m + 1) % 3] == a) j = m;
    if (j < 0) continue;
    const std::uint32_t d = tris_[u][(j + 2) % 3];
    if (d == c) continue;
    if (!delaunay_flips(pts[a], pts[b], pts[c], pts[d])) continue;
    const int n_bc = nbr_[t][(k + 1) % 3], n_ca = nbr_[t][(k + 2) % 3];
    const int n_ad = nbr_[u][(j + 1) % 3], n_db = nbr_[u][(j + 2) % 3];
    tris_[t] = {c, a, d};
    nbr_[t] = {n_ca, n_ad, u};
    tris_[u] = {d, b, c};
    nbr_[u] = {n_db, n_bc, t};
    relink(n_ad, u, t);
    relink(n_bc, t, u);
    stack.emplace_back(t, 0);
    stack.emplace_back(t, 1);
    stack.emplace_back(u, 0);
    stack.emplace_back(u, 1);
  }
}

}  // namespace deepcut::geometry
