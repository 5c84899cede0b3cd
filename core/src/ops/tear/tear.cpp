// SPDX-License-Identifier: MIT
// The tear (ops/tear.h). Its stages, each handing explicit data to the next:
//   1. sweep (sweep.cpp): the swept quad as one or two planar sweep facets;
//   2. slit insertion (slit_insertion.cpp), per facet: the mesh split along where the facet
//      crosses it, the torn edges recorded (Slits);
//   3. lips (lips.cpp): lone torn edges split, the vertices along the slits copied per wedge and
//      the lips pushed apart (Separation);
//   4. pinch repair (ops/common/pinches.h), then the PosedMesh follows the log.
// tear_model runs tear_mesh on every mesh instance of a posed model.
#include "deepcut/core/ops/tear.h"

#include <algorithm>
#include <cmath>
#include <memory_resource>
#include <string>

#include "deepcut/core/mesh_editor.h"
#include "ops/common/model_surgery.h"
#include "ops/common/pinches.h"
#include "ops/tear/stages.h"

namespace deepcut {
namespace {

using detail::tear::SweepFacet;

void check_inputs(const SurfaceMesh& mesh, const PosedMesh& posed, const TearOptions& options) {
  const std::size_t nv = mesh.vertex_count();
  if (posed.posed.size() != nv)
    throw Error(ErrorCode::InvalidArgument,
                "tear: " + std::to_string(posed.posed.size()) + " posed positions for " + std::to_string(nv) + " vertices");
  if (!posed.linear.empty() && posed.linear.size() != nv)
    throw Error(ErrorCode::InvalidArgument,
                "tear: " + std::to_string(posed.linear.size()) + " skin matrices for " + std::to_string(nv) + " vertices");
  if (!std::isfinite(options.width)) throw Error(ErrorCode::InvalidArgument, "tear: the width is not finite");
  if (!(options.relative_tolerance >= 0.0f) || !std::isfinite(options.relative_tolerance))
    throw Error(ErrorCode::InvalidArgument, "tear: the tolerance must be a finite number >= 0");
}

// Lips are split per wedge of untorn edges; a vertex the tear touched elsewhere (a slit end on an
// old boundary, a face replaced around a vertex on the quad) can still join two fans: split those
// pinches, and list the copies of tear vertices among the tear vertices.
void repair_pinches(MeshEditor& editor, const PosedMesh& posed, std::uint32_t first_new, TearResult& result) {
  const auto touched = detail::edited_vertices(editor.log());
  const auto pinches = detail::split_pinched_vertices(
      editor, touched,
      detail::faces_around(editor.mesh(), editor.log(), touched, first_new, &posed.grid, posed.posed));
  for (const auto& [v, c] : pinches.copies)
    if (std::binary_search(result.tear_vertices.begin(), result.tear_vertices.end(), v)) result.tear_vertices.push_back(c);
  std::sort(result.tear_vertices.begin(), result.tear_vertices.end());
}

}  // namespace

std::vector<std::array<glm::vec3, 3>> swept_quad_triangles(const Blade& start, const Blade& end) {
  std::vector<std::array<glm::vec3, 3>> out;
  for (const SweepFacet& p : detail::tear::make_sweep(start, end)) out.insert(out.end(), p.world.begin(), p.world.end());
  return out;
}

float resolved_tear_width(const Blade& start, const Blade& end, const TearOptions& options) {
  if (options.width >= 0.0f) return options.width;
  return 0.05f * 0.5f * (glm::length(start.tip - start.handle) + glm::length(end.tip - end.handle));
}

TearResult tear_mesh(SurfaceMesh& mesh, PosedMesh& posed, const Blade& start, const Blade& end,
                     const TearOptions& options) {
  namespace stage = detail::tear;
  const auto first_new = static_cast<std::uint32_t>(mesh.vertex_count());
  const auto first_new_face = static_cast<std::uint32_t>(mesh.face_slots());
  std::pmr::monotonic_buffer_resource arena{std::size_t(1) << 16};  // before every map using it
  MeshEditor editor(mesh);
  TearResult result;
  check_inputs(mesh, posed, options);
  const std::vector<SweepFacet> facets = stage::make_sweep(start, end);
  const float width = resolved_tear_width(start, end, options);
  result.width = width;
  stage::TearPose pose(posed, mesh, &arena);
  const double tol = double(options.relative_tolerance) * double(posed.bounds.diagonal());
  stage::TearContext ctx{mesh, editor, pose, posed.grid, first_new_face, tol, &arena};
  stage::Slits slits(&arena);
  for (std::size_t i = 0; i < facets.size(); ++i) stage::insert_slit(ctx, facets[i], i, slits);
  if (slits.torn.empty() && editor.log().empty()) {
    result.status = OpStatus::NoIntersection;
    return result;
  }
  stage::split_lone_edges(ctx, slits);
  const stage::Separation lips = stage::separate_and_open(ctx, facets, width, slits);
  result.tear_vertices = lips.tear_vertices;
  result.slits = lips.slits;
  result.closed_slits = lips.closed_slits;
  result.opening = lips.opening;
  repair_pinches(editor, posed, first_new, result);
  result.intersection_points = slits.intersections;
  result.log = editor.take_log();
  posed.follow(mesh, result.log);
  return result;
}

ModelTearResult tear_model(Model& model, PosedModel& posed, const Blade& start, const Blade& end,
                           const TearOptions& options, int animation, float time) {
  detail::tear::make_sweep(start, end);  // reject a degenerate blade even when the model has no mesh
  posed.prepare(model, animation, time);
  ModelTearResult result;
  result.status = OpStatus::NoIntersection;
  result.width = resolved_tear_width(start, end, options);
  // A mesh drawn by several instances is torn on a copy that the instance then owns.
  detail::for_each_instance(model, posed, [&](detail::InstanceEdit& inst) {
    Mesh& target = inst.edit();
    bool any = false;
    for (std::size_t pi = 0; pi < target.primitives.size(); ++pi) {
      PosedMesh* instance = inst.posed(static_cast<int>(pi));
      if (!instance) continue;  // prepare indexes every instance
      const TearResult r = tear_mesh(target.primitives[pi].mesh, *instance, start, end, options);
      if (r.status != OpStatus::Ok) continue;
      any = true;
      result.intersection_points += r.intersection_points;
      result.tear_vertices += r.tear_vertices.size();
      result.slits += r.slits;
      result.opening = std::max(result.opening, r.opening);
    }
    if (any) result.status = OpStatus::Ok;
    return any;
  });
  return result;
}

ModelTearResult tear_model(Model& model, const Blade& start, const Blade& end, const TearOptions& options,
                           int animation, float time) {
  detail::tear::make_sweep(start, end);  // a degenerate blade fails before the model is posed
  PosedModel posed = PosedModel::build(model, animation, time);
  return tear_model(model, posed, start, end, options, animation, time);
}

}  // namespace deepcut
