// SPDX-License-Identifier: MIT
// The posed model following an undo or a redo (PosedModel::follow with a ModelChange): the
// change said as an edit log each instance follows, after cutting off what the step removed.
#include <algorithm>

#include "deepcut/core/posed_model.h"

namespace deepcut {
namespace {

/// The change of one primitive as an edit log on its mesh now: rewritten faces leave and, when
/// live, join again (filed where they are now); faces past the old count join; rewritten
/// vertices move (posed again, their faces filed again).
EditLog log_of(const SurfaceMesh& mesh, const PrimitiveChange& change) {
  EditLog log;
  for (FaceId f : change.faces) {
    log.edits.push_back(FaceRemoved{f, mesh.face(f)});
    if (!mesh.is_deleted(f)) log.edits.push_back(FaceAdded{f, FaceId(), mesh.face(f)});
  }
  for (std::size_t f = change.faces_before; f < mesh.face_slots(); ++f) {
    const FaceId id(static_cast<std::uint32_t>(f));
    if (!mesh.is_deleted(id)) log.edits.push_back(FaceAdded{id, FaceId(), mesh.face(id)});
  }
  for (VertexId v : change.vertices) {
    const glm::vec3 p = mesh.position(v);
    log.edits.push_back(VertexMoved{v, p, p});
  }
  return log;
}

/// Cuts instance `inst` back to `mesh`'s sizes (the step removed the elements past them).
void cut_back(PosedMesh& inst, const SurfaceMesh& mesh) {
  const std::size_t n = mesh.vertex_count();
  if (!inst.gridless) inst.grid.truncate(mesh.face_slots(), n);
  if (inst.posed.size() <= n) return;
  inst.posed.resize(n);
  if (!inst.linear.empty()) inst.linear.resize(n);
  inst.bounds = BoundingBox();
  for (const glm::vec3& p : inst.posed) inst.bounds.add(p);
}

}  // namespace

void PosedModel::follow(const Model& model, const ModelChange& change) {
  if (!valid_ || change.empty()) return;
  if (change.structure) {
    invalidate();
    return;
  }
  for (const PrimitiveChange& c : change.primitives) {
    if (c.mesh < 0 || static_cast<std::size_t>(c.mesh) >= model.meshes.size()) continue;
    const Mesh& m = model.meshes[static_cast<std::size_t>(c.mesh)];
    if (c.primitive < 0 || static_cast<std::size_t>(c.primitive) >= m.primitives.size()) continue;
    const SurfaceMesh& mesh = m.primitives[static_cast<std::size_t>(c.primitive)].mesh;
    const EditLog log = log_of(mesh, c);
    for (auto& [key, inst] : instances_) {
      if (inst.mesh != c.mesh || key.second != c.primitive) continue;
      if (inst.posed.size() != c.vertices_before) {  // it did not describe the state before
        invalidate();
        return;
      }
      cut_back(inst, mesh);
      inst.follow(mesh, log);
    }
  }
}

}  // namespace deepcut
