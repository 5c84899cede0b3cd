// SPDX-License-Identifier: MIT
#include "ops/common/placement.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "deepcut/core/parallel.h"
#include "deepcut/core/skinning.h"

namespace deepcut::detail {

namespace {

// True when every joint matrix equals the first within float noise: `noise` relative to the
// largest entry of its linear part, `reach` (world units) for its translation.
bool one_matrix(const std::vector<glm::mat4>& joints, double noise, double reach) {
  const glm::mat4& first = joints.front();
  double scale = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) scale = std::max(scale, std::abs(double(first[c][r])));
  for (const glm::mat4& m : joints) {
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r)
        if (!(std::abs(double(m[c][r]) - double(first[c][r])) <= noise * scale)) return false;
    if (!(glm::length(glm::dvec3(m[3]) - glm::dvec3(first[3])) <= reach)) return false;
  }
  return true;
}

}  // namespace

Placement::Placement(const PosedMesh& posed, const SurfaceMesh& mesh) {
  if (posed.no_unpose || !SkinBlend(mesh, posed.joints).skinned()) return;
  posed_ = &posed;
  noise_ = kNoise * double(posed.bounds.diagonal());
  near_one_matrix_ = one_matrix(posed.joints, kNearRest, kNearRest * double(posed.bounds.diagonal()));
}

glm::vec3 Placement::bind_position(const SurfaceMesh& mesh, VertexId v, const glm::vec3& target,
                                   const glm::vec3& guess) const {
  if (!posed_) return guess;
  const glm::vec3 exact = posed_->unpose(mesh, v, target);
  if (!near_one_matrix_ || exact == guess) return exact;
  // How far `guess` poses from `target`: the vertex's own linear map applied to the bind-space
  // difference (a morph offset, the same for both, cancels).
  const SkinBlend blend(mesh, posed_->joints);
  const glm::dmat3 linear(glm::mat3(blend.matrix(v.index)));
  return glm::length(linear * (glm::dvec3(guess) - glm::dvec3(exact))) <= noise_ ? guess : exact;
}

void Placement::move_if_changed(MeshEditor& editor, VertexId v, const glm::vec3& guess,
                                const glm::vec3& bind) {
  if (bind != guess) editor.move_vertex(v, bind);
}

void Placement::place(MeshEditor& editor, VertexId v, const glm::vec3& target) const {
  if (!posed_) return;
  const glm::vec3 guess = editor.mesh().position(v);
  move_if_changed(editor, v, guess, bind_position(editor.mesh(), v, target, guess));
}

void Placement::place_all(MeshEditor& editor, const VertexId* ids, const glm::vec3* targets,
                          std::size_t n) const {
  if (!posed_ || n == 0) return;
  const SurfaceMesh& mesh = editor.mesh();
  std::vector<glm::vec3> bind(n);
  parallel_for(n, kPlaceGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i)
      bind[i] = bind_position(mesh, ids[i], targets[i], mesh.position(ids[i]));
  });
  for (std::size_t i = 0; i < n; ++i) move_if_changed(editor, ids[i], mesh.position(ids[i]), bind[i]);
}

}  // namespace deepcut::detail
