// SPDX-License-Identifier: MIT
#include "deepcut/plugins/tool.h"

#include <algorithm>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "deepcut/core/errors.h"

namespace deepcut::plugins {

std::unique_ptr<Tool> create_tool(const ToolRegistry& registry, const std::string& id) {
  const ToolInfo* info = registry.find(id);
  if (!info || !info->create)
    throw Error(ErrorCode::InvalidArgument, "unknown tool '" + id + "' (known: " + registry.ids() + ")");
  return info->create();
}

namespace {

/// The segment where triangle (p0, p1, p2) crosses the plane (point, unit normal), if any.
bool triangle_plane_segment(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2, const glm::vec3& point,
                            const glm::vec3& normal, glm::vec3& a, glm::vec3& b) {
  const glm::vec3 p[3] = {p0, p1, p2};
  float d[3];
  for (int k = 0; k < 3; ++k) d[k] = glm::dot(p[k] - point, normal);
  glm::vec3 hits[3];
  int n = 0;
  for (int k = 0; k < 3 && n < 2; ++k) {
    const int l = (k + 1) % 3;
    if (d[k] == 0.0f) {
      hits[n++] = p[k];
    } else if ((d[k] < 0.0f && d[l] > 0.0f) || (d[k] > 0.0f && d[l] < 0.0f)) {
      const float t = d[k] / (d[k] - d[l]);
      hits[n++] = p[k] + t * (p[l] - p[k]);
    }
  }
  if (n < 2) return false;
  a = hits[0];
  b = hits[1];
  return true;
}

// Calls `fn` on the posed triangles of every piece that `candidates(grid)` returns when the
// piece has a grid (faces in id order, as the scan visits them), else on every live triangle.
template <class Query, class F>
void for_each_posed_triangle(const Scene& scene, Query&& candidates, F&& fn) {
  for (const SceneInstance& piece : scene.pieces) {
    if (!piece.surface || piece.posed().size() < piece.surface->vertex_count()) continue;
    const SurfaceMesh& mesh = *piece.surface;
    if (piece.grid) {
      for (FaceId f : candidates(*piece.grid)) {
        if (f.index >= mesh.face_slots() || mesh.is_deleted(f)) continue;
        const Triangle& t = mesh.face(f);
        fn(piece.posed()[t[0].index], piece.posed()[t[1].index], piece.posed()[t[2].index]);
      }
      continue;
    }
    mesh.for_each_face([&](FaceId, const Triangle& t) {
      fn(piece.posed()[t[0].index], piece.posed()[t[1].index], piece.posed()[t[2].index]);
    });
  }
}

}  // namespace

std::vector<glm::vec3> plane_contour(const Scene& scene, const Plane& plane) {
  std::vector<glm::vec3> out;
  const float len = glm::length(plane.normal);
  if (!(len > 0.0f)) return out;
  const glm::vec3 n = plane.normal / len;
  // With a grid only the cells along the plane are visited (its bounds cover every cell).
  auto along_plane = [&](const TriangleGrid& grid) { return grid.query_slab(grid.bounds(), plane.point, n, 0.0f); };
  for_each_posed_triangle(scene, along_plane, [&](const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2) {
    glm::vec3 a, b;
    if (triangle_plane_segment(p0, p1, p2, plane.point, n, a, b)) {
      out.push_back(a);
      out.push_back(b);
    }
  });
  return out;
}

std::vector<glm::vec3> triangle_contour(const Scene& scene, const std::array<glm::vec3, 3>& tri) {
  std::vector<glm::vec3> out;
  const glm::vec3 cross = glm::cross(tri[1] - tri[0], tri[2] - tri[0]);
  const float len = glm::length(cross);
  if (!(len > 0.0f)) return out;
  const glm::vec3 n = cross / len;
  // Inward normals of the tool triangle's edges, in its plane: clip the crossing segment to it.
  glm::vec3 edge_normal[3];
  for (int k = 0; k < 3; ++k) edge_normal[k] = glm::cross(n, tri[(k + 1) % 3] - tri[k]);
  const glm::vec3 lo = glm::min(tri[0], glm::min(tri[1], tri[2])), hi = glm::max(tri[0], glm::max(tri[1], tri[2]));
  BoundingBox box;
  box.add(lo);
  box.add(hi);
  auto in_box = [&](const TriangleGrid& grid) { return grid.query_box(box); };
  for_each_posed_triangle(scene, in_box, [&](const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2) {
    const glm::vec3 flo = glm::min(p0, glm::min(p1, p2)), fhi = glm::max(p0, glm::max(p1, p2));
    if (glm::any(glm::lessThan(fhi, lo)) || glm::any(glm::greaterThan(flo, hi))) return;
    glm::vec3 a, b;
    if (!triangle_plane_segment(p0, p1, p2, tri[0], n, a, b)) return;
    float t0 = 0.0f, t1 = 1.0f;
    for (int k = 0; k < 3; ++k) {
      const float da = glm::dot(a - tri[k], edge_normal[k]), db = glm::dot(b - tri[k], edge_normal[k]);
      if (da < 0.0f && db < 0.0f) return;
      if (da < 0.0f) t0 = std::max(t0, da / (da - db));
      if (db < 0.0f) t1 = std::min(t1, da / (da - db));
    }
    if (t0 >= t1) return;
    out.push_back(a + t0 * (b - a));
    out.push_back(a + t1 * (b - a));
  });
  return out;
}

BoundingBox scene_bounds(const Scene& scene) {
  BoundingBox box;
  for (const SceneInstance& piece : scene.pieces) {
    if (!piece.surface) continue;
    piece.surface->for_each_face([&](FaceId, const Triangle& t) {
      for (VertexId v : t)
        if (v.index < piece.posed().size()) box.add(piece.posed()[v.index]);
    });
  }
  return box;
}

}  // namespace deepcut::plugins
