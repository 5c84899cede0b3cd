// SPDX-License-Identifier: MIT
#include "deepcut/core/spatial_index.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace deepcut {

TriangleGrid TriangleGrid::build(const SurfaceMesh& mesh, const std::vector<glm::vec3>& points,
                                 float cell_size) {
  if (points.size() != mesh.vertex_count())
    throw Error(ErrorCode::InvalidArgument, "spatial index: " + std::to_string(points.size()) +
                                                " positions for " + std::to_string(mesh.vertex_count()) +
                                                " vertices");
  TriangleGrid grid;
  double extent_sum = 0.0;
  std::size_t faces = 0;
  mesh.for_each_face([&](FaceId, const Triangle& t) {
    BoundingBox b;
    for (auto v : t) b.add(points[v.index]);
    grid.bounds_.add(b);
    const glm::vec3 e = b.max - b.min;
    extent_sum += std::max({e.x, e.y, e.z});
    ++faces;
  });
  grid.alive_.assign(mesh.face_slots(), 0);
  if (faces == 0) return grid;
  const glm::vec3 size =
      glm::max(grid.bounds_.max - grid.bounds_.min, glm::vec3(1e-6f * (grid.bounds_.diagonal() + 1.0f)));
  float cell = cell_size > 0.0f ? cell_size : static_cast<float>(2.0 * extent_sum / double(faces));
  // At most about one cell per face (and never a degenerate cell).
  const double volume = double(size.x) * size.y * size.z;
  const double min_cell = std::cbrt(volume / double(faces + 64));
  cell = std::max(cell, static_cast<float>(min_cell));
  if (!(cell > 0.0f)) cell = std::max({size.x, size.y, size.z});
  grid.cell_ = cell;
  grid.origin_ = grid.bounds_.min;
  grid.dims_ = glm::max(glm::ivec3(glm::ceil(size / cell)), glm::ivec3(1));
  grid.cells_.resize(static_cast<std::size_t>(grid.dims_.x) * grid.dims_.y * grid.dims_.z);
  mesh.for_each_face([&](FaceId f, const Triangle& t) { grid.insert(f, t, points); });
  return grid;
}

glm::ivec3 TriangleGrid::cell_of(const glm::vec3& p) const {
  const glm::vec3 q = (p - origin_) / cell_;
  glm::ivec3 c;
  for (int i = 0; i < 3; ++i) {
    const float v = std::isfinite(q[i]) ? std::floor(q[i]) : 0.0f;
    c[i] = static_cast<int>(std::clamp(v, 0.0f, float(dims_[i] - 1)));
  }
  return c;
}

void TriangleGrid::insert(FaceId f, const Triangle& t, const std::vector<glm::vec3>& points) {
  if (f.index >= alive_.size()) alive_.resize(f.index + 1, 0);
  if (alive_[f.index]) return;
  alive_[f.index] = 1;
  ++live_;
  BoundingBox b;
  for (auto v : t) b.add(points[v.index]);
  const glm::ivec3 lo = cell_of(b.min), hi = cell_of(b.max);
  for (int z = lo.z; z <= hi.z; ++z)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) cells_[cell_index(x, y, z)].push_back(f.index);
}

void TriangleGrid::apply(const EditLog& log, const std::vector<glm::vec3>& points) {
  if (cells_.empty()) return;
  for (const Edit& e : log.edits) {
    if (const auto* r = std::get_if<FaceRemoved>(&e)) {
      if (r->f.index < alive_.size() && alive_[r->f.index]) {
        alive_[r->f.index] = 0;
        --live_;
      }
    } else if (const auto* a = std::get_if<FaceAdded>(&e)) {
      insert(a->f, a->vertices, points);
    }
  }
}

void TriangleGrid::sort_unique(std::vector<FaceId>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

void TriangleGrid::collect(int x, int y, int z0, int z1, std::vector<FaceId>& out) const {
  for (int z = z0; z <= z1; ++z)
    for (std::uint32_t f : cells_[cell_index(x, y, z)])
      if (alive_[f]) out.push_back(FaceId(f));
}

std::vector<FaceId> TriangleGrid::query_box(const BoundingBox& box) const {
  std::vector<FaceId> out;
  if (cells_.empty() || box.empty()) return out;
  const glm::ivec3 lo = cell_of(box.min), hi = cell_of(box.max);
  for (int y = lo.y; y <= hi.y; ++y)
    for (int x = lo.x; x <= hi.x; ++x) collect(x, y, lo.z, hi.z, out);
  sort_unique(out);
  return out;
}

std::vector<FaceId> TriangleGrid::query_capsule(const glm::vec3& a, const glm::vec3& b, float radius) const {
  std::vector<FaceId> out;
  if (cells_.empty()) return out;
  BoundingBox box;
  box.add(glm::min(a, b) - glm::vec3(radius));
  box.add(glm::max(a, b) + glm::vec3(radius));
  const glm::ivec3 lo = cell_of(box.min), hi = cell_of(box.max);
  // Column by column (x, y): the part of the segment whose xy projection passes within reach of
  // the column gives the z range to visit.
  const glm::dvec2 a2(a.x, a.y), d2(double(b.x) - a.x, double(b.y) - a.y);
  const double dd = glm::dot(d2, d2);
  const double reach = double(radius) + 0.7072 * double(cell_);
  for (int y = lo.y; y <= hi.y; ++y)
    for (int x = lo.x; x <= hi.x; ++x) {
      const glm::dvec2 c(origin_.x + (x + 0.5) * cell_, origin_.y + (y + 0.5) * cell_);
      double t0 = 0.0, t1 = 1.0;
      const glm::dvec2 m = a2 - c;
      if (dd > 0.0) {
        // |m + t d2|^2 <= reach^2
        const double bq = glm::dot(m, d2), cq = glm::dot(m, m) - reach * reach;
        const double disc = bq * bq - dd * cq;
        if (disc < 0.0) continue;
        const double s = std::sqrt(disc);
        t0 = std::max(0.0, (-bq - s) / dd);
        t1 = std::min(1.0, (-bq + s) / dd);
        if (t0 > t1) continue;
      } else if (glm::dot(m, m) > reach * reach) {
        continue;
      }
      const double za = a.z + t0 * (double(b.z) - a.z), zb = a.z + t1 * (double(b.z) - a.z);
      const float zlo = static_cast<float>(std::min(za, zb) - radius),
                  zhi = static_cast<float>(std::max(za, zb) + radius);
      const int cz0 = cell_of(glm::vec3(origin_.x, origin_.y, zlo)).z,
                cz1 = cell_of(glm::vec3(origin_.x, origin_.y, zhi)).z;
      collect(x, y, cz0, cz1, out);
    }
  sort_unique(out);
  return out;
}

}  // namespace deepcut
