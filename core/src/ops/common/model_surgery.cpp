// SPDX-License-Identifier: MIT
#include "ops/common/model_surgery.h"

#include <algorithm>

namespace deepcut::detail {

SurfaceMesh extract(const SurfaceMesh& mesh, const std::vector<FaceId>& faces) {
  // What a copy with every other face deleted, compacted, holds (faces and vertices in id
  // order), gathered straight from `mesh`: the cost follows `faces`, not the mesh, so a drill's
  // wall or a small piece comes out in time proportional to its own size.
  std::vector<std::uint32_t> keep_faces;
  keep_faces.reserve(faces.size());
  for (FaceId f : faces)
    if (!mesh.is_deleted(f)) keep_faces.push_back(f.index);
  std::sort(keep_faces.begin(), keep_faces.end());
  keep_faces.erase(std::unique(keep_faces.begin(), keep_faces.end()), keep_faces.end());
  std::vector<std::uint32_t> keep_vertices, keep_corners;
  keep_vertices.reserve(3 * keep_faces.size());
  keep_corners.reserve(3 * keep_faces.size());
  for (std::uint32_t f : keep_faces)
    for (int k = 0; k < 3; ++k) {
      keep_vertices.push_back(mesh.face(FaceId(f))[k].index);
      keep_corners.push_back(3 * f + static_cast<std::uint32_t>(k));
    }
  std::sort(keep_vertices.begin(), keep_vertices.end());
  keep_vertices.erase(std::unique(keep_vertices.begin(), keep_vertices.end()), keep_vertices.end());
  auto new_index = [&](VertexId v) {
    return VertexId(static_cast<std::uint32_t>(
        std::lower_bound(keep_vertices.begin(), keep_vertices.end(), v.index) - keep_vertices.begin()));
  };
  std::vector<Triangle> tris;
  tris.reserve(keep_faces.size());
  for (std::uint32_t f : keep_faces) {
    const Triangle& t = mesh.face(FaceId(f));
    tris.push_back({new_index(t[0]), new_index(t[1]), new_index(t[2])});
  }
  SurfaceMesh out;
  out.assign(std::move(tris), mesh.vertex_attrs().subset(keep_vertices), mesh.face_attrs().subset(keep_faces),
             mesh.corner_attrs().subset(keep_corners));
  return out;
}

int cut_surface_material(Model& model) {
  for (std::size_t i = 0; i < model.materials.size(); ++i)
    if (model.materials[i].name == "Cut surface") return static_cast<int>(i);
  model.materials.push_back({"Cut surface",
                             R"({"name":"Cut surface","doubleSided":false,"pbrMetallicRoughness":)"
                             R"({"baseColorFactor":[0.8,0.18,0.16,1.0],"metallicFactor":0.0,"roughnessFactor":0.9}})"});
  return static_cast<int>(model.materials.size() - 1);
}

}  // namespace deepcut::detail
