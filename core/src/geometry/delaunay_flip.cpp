// SPDX-License-Identifier: MIT
#include "geometry/delaunay_flip.h"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace deepcut::geometry {

FlipTriangulation::FlipTriangulation(std::vector<glm::dvec2>& pts, std::vector<LocalTri> tris)
    : pts_(pts), tris_(std::move(tris)) {
  nbr_.assign(tris_.size(), {-1, -1, -1});
  // Half-edges sorted by key (a flat table: a polygon has a few dozen); where a half-edge
  // repeats, the last triangle listing it is the one found, as a map overwritten in order gives.
  auto key = [](std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; };
  std::vector<std::pair<std::uint64_t, int>> half;
  half.reserve(3 * tris_.size());
  for (std::size_t i = 0; i < tris_.size(); ++i)
    for (int k = 0; k < 3; ++k) half.emplace_back(key(tris_[i][k], tris_[i][(k + 1) % 3]), static_cast<int>(i));
  std::stable_sort(half.begin(), half.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  for (std::size_t i = 0; i < tris_.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t want = key(tris_[i][(k + 1) % 3], tris_[i][k]);
      auto it = std::upper_bound(half.begin(), half.end(), want,
                                 [](std::uint64_t v, const auto& x) { return v < x.first; });
      if (it == half.begin() || std::prev(it)->first != want) continue;
      if (std::prev(it)->second != static_cast<int>(i)) nbr_[i][k] = std::prev(it)->second;
    }
}

bool FlipTriangulation::is_interior(std::uint32_t a, std::uint32_t b) const {
  for (std::size_t t = 0; t < tris_.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (tris_[t][k] == a && tris_[t][(k + 1) % 3] == b) return nbr_[t][k] >= 0;
  return false;
}

void FlipTriangulation::make_delaunay() {
  std::vector<std::pair<int, int>> stack;
  for (std::size_t i = 0; i < tris_.size(); ++i)
    for (int k = 0; k < 3; ++k) stack.emplace_back(static_cast<int>(i), k);
  legalize(stack);
}

bool FlipTriangulation::insert(const glm::dvec2& p) {
  const int t = locate(p);
  if (t < 0) return false;
  const auto id = static_cast<std::uint32_t>(pts_.size());
  pts_.push_back(p);
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
  std::vector<std::pair<int, int>> stack = {{t, 0}, {t1, 0}, {t2, 0}};
  legalize(stack);
  last_ = static_cast<std::size_t>(t);
  return true;
}

void FlipTriangulation::relink(int n, int from, int to) {
  if (n < 0) return;
  for (int k = 0; k < 3; ++k)
    if (nbr_[n][k] == from) nbr_[n][k] = to;
}

double FlipTriangulation::orient_rel(std::uint32_t a, std::uint32_t b, const glm::dvec2& p) const {
  const glm::dvec2 e = pts_[b] - pts_[a], f = p - pts_[a];
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

void FlipTriangulation::legalize(std::vector<std::pair<int, int>>& stack) {
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
    const glm::dvec2 &pa = pts_[a], &pb = pts_[b], &pc = pts_[c], &pd = pts_[d];
    double scale = 0.0;
    for (const auto* q : {&pa, &pb, &pc}) scale = std::max(scale, glm::dot(*q - pd, *q - pd));
    if (incircle(pa, pb, pc, pd) <= 1e-10 * scale * scale) continue;
    if (orient(pc, pa, pd) <= 0.0 || orient(pd, pb, pc) <= 0.0) continue;
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
