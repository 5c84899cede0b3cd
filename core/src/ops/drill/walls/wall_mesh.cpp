// SPDX-License-Identifier: MIT
// The wall's faces: each shell's sheets emitted as faces (new vertices placed by inverse
// skinning, attributes blended from the nearest rims), the shells found from the mesh, and the
// wall faces' texture coordinates, normals and tangents.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <unordered_map>
#include <unordered_set>

#include "deepcut/core/morph.h"
#include "ops/drill/walls/wall.h"
#include "ops/drill/walls/wall_shell.h"

namespace deepcut::drill {
namespace {

VertexId wall_vertex(WallContext& ctx, VertexId a, VertexId b, float t, const glm::dvec3& p) {
  const VertexId v = ctx.editor.add_vertex_on_edge(a, b, t);
  ctx.posed.add(p);
  const Unposer& unpose = ctx.posed.unpose();
  const glm::vec3 bind = unpose ? unpose(ctx.editor.mesh(), v, glm::vec3(p)) : glm::vec3(p);
  ctx.editor.move_vertex(v, bind);
  return v;
}

FaceId wall_face(WallContext& ctx, const Triangle& t, int kind) {
  const FaceId f = ctx.editor.add_face(t);
  ctx.faces.emplace_back(f, kind);
  ++ctx.added;
  return f;
}

// A wall face may use an edge between two existing vertices only against the one face that
// borders it (a rim edge): anything else (a diagonal along a kept surface edge, an edge an
// earlier sheet used) would make the edge non-manifold, so the sheet is left open instead.
bool keeps_manifold(const WallShell& shell, const WallContext& ctx,
                    const std::vector<geometry::LocalTri>& wall_tris) {
  const SurfaceMesh& mesh = ctx.editor.mesh();
  const std::vector<WallPt>& pts = shell.pts;
  std::unordered_set<std::uint64_t> used;
  auto add_face_edges = [&](const Triangle& t) {
    for (int k = 0; k < 3; ++k) used.insert(directed_key(t[k], t[(k + 1) % 3]));
  };
  for (const Edit& e : ctx.editor.log().edits)
    if (const auto* fa = std::get_if<FaceAdded>(&e))
      if (!mesh.is_deleted(fa->f)) add_face_edges(mesh.face(fa->f));
  for (FaceId f : ctx.surface_faces)
    if (!mesh.is_deleted(f)) add_face_edges(mesh.face(f));
  std::unordered_set<std::uint64_t> mine;
  for (const auto& t : wall_tris)
    for (int k = 0; k < 3; ++k) {
      const VertexId a = pts[t[k]].v, b = pts[t[(k + 1) % 3]].v;
      if (!a.valid() || !b.valid()) continue;
      if (used.count(directed_key(a, b)) || !mine.insert(directed_key(a, b)).second) return false;
    }
  return true;
}

// Creates the new vertices (attributes from the nearest vertices of the two nearest rims).
void create_vertices(WallShell& shell, WallContext& ctx) {
  std::vector<WallPt>& pts = shell.pts;
  const std::vector<std::size_t>& hole_ids = shell.hole_ids;
  for (auto& w : pts) {
    if (!w.v.valid()) {
      double best[2] = {kInf, kInf};
      VertexId src[2];
      for (std::size_t h2 : hole_ids) {
        double d = kInf;
        VertexId v;
        for (VertexId rv : ctx.rims[h2].vertices) {
          const glm::dvec3 q = ctx.posed(rv) - w.p;
          if (glm::dot(q, q) < d) {
            d = glm::dot(q, q);
            v = rv;
          }
        }
        if (d < best[0]) {
          best[1] = best[0];
          src[1] = src[0];
          best[0] = d;
          src[0] = v;
        } else if (d < best[1]) {
          best[1] = d;
          src[1] = v;
        }
      }
      if (!src[1].valid()) {
        src[1] = src[0];
        best[1] = best[0];
      }
      const double d0 = std::sqrt(best[0]), d1 = std::sqrt(best[1]);
      w.v = wall_vertex(ctx, src[0], src[1], static_cast<float>(d0 / std::max(d0 + d1, 1e-300)), w.p);
    }
    ctx.coords[w.v.index] = {w.theta, std::clamp(w.s, 0.0, shell.map.cy.len), w.where, w.v};
  }
}

}  // namespace

bool emit_sheet(WallShell& shell, WallContext& ctx, const std::vector<geometry::LocalTri>& wall_tris) {
  if (!keeps_manifold(shell, ctx, wall_tris)) return false;
  create_vertices(shell, ctx);
  SurfaceMesh& mesh = ctx.editor.mesh();
  const std::vector<WallPt>& pts = shell.pts;
  // A kept surface triangle whose three corners all lie on the rim (an island on the cylinder)
  // would get its own mirror image as wall: both go instead.
  // Keyed by the sorted corner ids themselves: a packed 64-bit key would collide once vertex ids
  // pass 2^21, and the drill would then remove an unrelated face.
  std::map<std::array<std::uint32_t, 3>, FaceId> surface_tri;
  auto tri_key = [](VertexId x, VertexId y, VertexId z) {
    return geometry::sorted_corners({x.index, y.index, z.index});
  };
  for (const Edit& e : ctx.editor.log().edits)
    if (const auto* fa = std::get_if<FaceAdded>(&e))
      if (!mesh.is_deleted(fa->f))
        surface_tri[tri_key(fa->vertices[0], fa->vertices[1], fa->vertices[2])] = fa->f;
  for (FaceId f : ctx.surface_faces)
    if (!mesh.is_deleted(f)) surface_tri[tri_key(mesh.face(f)[0], mesh.face(f)[1], mesh.face(f)[2])] = f;
  for (const auto& t : wall_tris) {
    const auto twin = surface_tri.find(tri_key(pts[t[0]].v, pts[t[1]].v, pts[t[2]].v));
    if (twin != surface_tri.end() && !mesh.is_deleted(twin->second)) {
      ctx.editor.remove_face(twin->second);
      ++ctx.removed;
      continue;
    }
    const int kind =
        pts[t[0]].where != 0 && pts[t[0]].where == pts[t[1]].where && pts[t[1]].where == pts[t[2]].where ? 1
                                                                                                         : 0;
    wall_face(ctx, {pts[t[0]].v, pts[t[1]].v, pts[t[2]].v}, kind);
  }
  return true;
}

void finish_wall_attributes(WallContext& ctx) {
  SurfaceMesh& mesh = ctx.editor.mesh();
  if (ctx.faces.empty()) return;
  auto* flag = mesh.face_attrs().find<std::uint8_t>(attr::kCutSurface);
  if (!flag) flag = &mesh.face_attrs().add<std::uint8_t>(attr::kCutSurface);
  auto& ca = mesh.corner_attrs();
  auto* normals = ca.find<glm::vec3>(attr::kNormal);
  auto* tangents = ca.find<glm::vec4>(attr::kTangent);
  auto* colors = ca.find<glm::vec4>(attr::kColor0);
  const auto morph_deltas = corner_morph_deltas(mesh);
  std::vector<AttributeArray<glm::vec2>*> uvs;
  for (int set = 0; set < 8; ++set)
    if (auto* uv = ca.find<glm::vec2>(attr::uv_name(set))) uvs.push_back(uv);
  const auto& bind = mesh.positions();
  // Smooth tube normals from the bind-space tube faces; disks are flat.
  std::unordered_map<std::uint32_t, glm::dvec3> tube_normal;
  for (const auto& [f, kind] : ctx.faces) {
    if (kind != 0) continue;
    const auto& t = mesh.face(f);
    const glm::dvec3 n = glm::cross(glm::dvec3(bind[t[1].index] - bind[t[0].index]),
                                    glm::dvec3(bind[t[2].index] - bind[t[0].index]));
    for (auto v : t) tube_normal[v.index] += n;
  }
  const double circumference = 2.0 * geometry::kPi * ctx.cyl.r;
  for (const auto& [f, kind] : ctx.faces) {
    (*flag)[f.index] = 1;
    const Triangle t = mesh.face(f);
    glm::dvec2 uv[3];
    if (kind == 0) {
      double th[3];
      for (int k = 0; k < 3; ++k) th[k] = ctx.coords.at(t[k].index).theta;
      for (int k = 1; k < 3; ++k) th[k] = th[0] + std::remainder(th[k] - th[0], 2.0 * geometry::kPi);
      for (int k = 0; k < 3; ++k)
        uv[k] = {th[k] / (2.0 * geometry::kPi), ctx.coords.at(t[k].index).s / circumference};
    } else {
      for (int k = 0; k < 3; ++k) {
        const glm::dvec3 q = ctx.cyl.perp(ctx.posed(t[k]));
        uv[k] = {0.5 + 0.5 * glm::dot(q, ctx.cyl.u) / ctx.cyl.r,
                 0.5 + 0.5 * glm::dot(q, ctx.cyl.w) / ctx.cyl.r};
      }
    }
    const glm::dvec3 p0(bind[t[0].index]), p1(bind[t[1].index]), p2(bind[t[2].index]);
    glm::dvec3 fn = glm::cross(p1 - p0, p2 - p0);
    fn = glm::length(fn) > 0.0 ? glm::normalize(fn) : -ctx.cyl.d;
    // Tangent: the bind-space direction of increasing u.
    const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0;
    const glm::dvec2 d1 = uv[1] - uv[0], d2 = uv[2] - uv[0];
    const double det = d1.x * d2.y - d2.x * d1.y;
    glm::dvec3 tangent = std::abs(det) > 1e-300 ? (e1 * d2.y - e2 * d1.y) / det : e1;
    tangent -= fn * glm::dot(fn, tangent);
    tangent = glm::length(tangent) > 0.0 ? glm::normalize(tangent) : glm::normalize(e1);
    for (int k = 0; k < 3; ++k) {
      const auto c = SurfaceMesh::corner(f, k);
      for (auto* a : uvs) (*a)[c] = glm::vec2(uv[k]);
      if (normals) {
        glm::dvec3 n = fn;
        if (kind == 0) {
          const glm::dvec3 acc = tube_normal[t[k].index];
          if (glm::length(acc) > 0.0) n = glm::normalize(acc);
        }
        (*normals)[c] = glm::vec3(n);
      }
      if (tangents) (*tangents)[c] = glm::vec4(glm::vec3(tangent), 1.0f);
      if (colors) (*colors)[c] = glm::vec4(1.0f);
      for (auto* d : morph_deltas) (*d)[c] = glm::vec3(0.0f);
    }
  }
}

}  // namespace deepcut::drill
