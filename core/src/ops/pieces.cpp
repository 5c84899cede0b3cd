// SPDX-License-Identifier: MIT
#include "ops/pieces.h"

namespace deepcut::detail {

SurfaceMesh extract(const SurfaceMesh& mesh, const std::vector<FaceId>& faces) {
  SurfaceMesh out = mesh;
  std::vector<std::uint8_t> keep(mesh.face_slots(), 0);
  for (FaceId f : faces) keep[f.index] = 1;
  for (std::uint32_t f = 0; f < out.face_slots(); ++f)
    if (!keep[f] && !out.is_deleted(FaceId(f))) out.mark_deleted(FaceId(f));
  out.compact();
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
