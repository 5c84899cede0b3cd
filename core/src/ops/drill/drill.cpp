// SPDX-License-Identifier: MIT
// Drill (core/include/deepcut/core/ops/drill.h): the stages of drilling one mesh, and drill_model
// on the one instance loop of the model operations (ops/common/model_surgery.h).
//
// 1. Candidate faces come from the posed mesh's spatial index; old vertices a hair
//    from the cylinder's side are slid onto it (rim_insertion.h).
// 2. The rim is inserted into each crossed triangle in its own plane (rim_insertion.cpp).
// 3. Rims are traced from the edits (rim_tracing.cpp); with `wall`, each connected shell gets the
//    part of the cylinder's surface (side and end disks) inside it (walls/wall.h).
#include "deepcut/core/ops/drill.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <unordered_map>

#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/core/skinning.h"
#include "ops/common/model_surgery.h"
#include "ops/common/pinches.h"
#include "ops/common/vertex_slots.h"
#include "ops/drill/cylinder_section.h"
#include "ops/drill/posed_overlay.h"
#include "ops/drill/rim_insertion.h"
#include "ops/drill/walls/wall.h"
#include "sorted_ids.h"

namespace deepcut {
namespace {

using geometry::kPi;

double axis_scale(const Cylinder& c) {
  const glm::dvec3 a(c.a), b(c.b);
  return glm::length(a) + glm::length(b) + glm::length(b - a);
}

}  // namespace

void check_drill_arguments(const Cylinder& c, const DrillOptions& options, const ParameterName& name) {
  auto finite = [](const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  };
  if (!finite(c.a) || !finite(c.b))
    throw Error(ErrorCode::InvalidArgument, "drill: the axis end points are not finite");
  if (!std::isfinite(c.radius) || !(c.radius > 0.0f))
    throw Error(ErrorCode::InvalidArgument, "drill: " + parameter_name(name, "radius") + " must be positive");
  const double len = glm::length(glm::dvec3(c.b) - glm::dvec3(c.a));
  const double scale = glm::length(glm::dvec3(c.a)) + glm::length(glm::dvec3(c.b));
  if (!(len > 1e-7 * scale) || len == 0.0)
    throw Error(ErrorCode::InvalidArgument, "drill: the axis end points A and B coincide");
  if (options.min_rim_edges < DrillOptions::kMinRimEdgesMin || options.min_rim_edges > DrillOptions::kMinRimEdgesMax)
    throw Error(ErrorCode::InvalidArgument, "drill: " + parameter_name(name, "min_rim_edges") + " must be between " +
                                                std::to_string(DrillOptions::kMinRimEdgesMin) + " and " +
                                                std::to_string(DrillOptions::kMinRimEdgesMax));
  // Rim points closer than the absolute tolerance (a few float steps of the coordinates there)
  // round onto each other or onto one line in float: faces of zero area.
  if (c.radius < min_drill_radius(c, options.min_rim_edges)) {
    char text[240];
    std::snprintf(
        text, sizeof text,
        "drill: radius %.3g with %d rim edges puts rim points %.3g apart, finer than the precision of "
        "positions around the axis (%.3g); the radius must be at least %.3g",
        double(c.radius), options.min_rim_edges, 2.0 * c.radius * std::sin(kPi / options.min_rim_edges),
        1e-6 * axis_scale(c), double(min_drill_radius(c, options.min_rim_edges)));
    throw Error(ErrorCode::InvalidArgument, text);
  }
  if (!std::isfinite(options.relative_tolerance) || options.relative_tolerance < 0.0f ||
      options.relative_tolerance > 0.1f)
    throw Error(ErrorCode::InvalidArgument, "drill: relative_tolerance must be between 0 and 0.1");
}

namespace {

void check_arguments(const Cylinder& c, const DrillOptions& options) { check_drill_arguments(c, options); }

// The vertices the edits used or freed (detail::edited_vertices), less the old ones deep inside
// the cylinder: every face around those was removed or lost that corner, so they have no fans.
std::vector<VertexId> pinch_candidates(const SurfaceMesh& mesh, const EditLog& log,
                                       const drill::CylinderFrame& cyl, const drill::PosedOverlay& posed) {
  std::vector<VertexId> out;
  detail::VertexSlots& seen = detail::VertexSlots::scratch();  // each vertex listed or judged once
  seen.reset(mesh.vertex_count());
  auto add = [&](VertexId v) {
    if (v.index >= mesh.vertex_count() || seen.has(v.index)) return;
    seen.set(v.index, 0);
    if (v.index < posed.first_new() && drill::deep_vertex(cyl, posed, v)) return;
    out.push_back(v);
  };
  for (const Edit& e : log.edits) {
    if (const auto* a = std::get_if<FaceAdded>(&e)) {
      for (const VertexId v : a->vertices) add(v);
    } else if (const auto* r = std::get_if<FaceRemoved>(&e)) {
      for (const VertexId v : r->vertices) add(v);
    } else if (const auto* s = std::get_if<VertexSplit>(&e)) {
      add(s->original);
      add(s->copy);
    }
  }
  detail::sort_unique_ids(out);
  return out;
}

// Where the edits can have pinched the surface: the candidate vertices `touched` (sorted) and
// the live faces around them (read-only).
struct PinchInput {
  std::vector<VertexId> touched;
  std::vector<FaceId> around;
};

PinchInput pinch_input(const SurfaceMesh& mesh, const EditLog& log, const drill::PosedOverlay& posed,
                       std::vector<VertexId> touched, const std::vector<FaceId>& candidates,
                       const TriangleGrid& index) {
  // Faces are found where their old vertices were filed in the grid; the live faces around a
  // snapped vertex (filed where it was, and the input's posed positions may be the mesh's own
  // positions) are merged in (the list stays in id order). Those are the live candidates with a
  // moved corner, which relies on two things:
  // - only rim_snapping.cpp moves old vertices in `posed` (posed.moved() lists every vertex away
  //   from where the grid filed it), and it moves only vertices whose faces are all candidates;
  // - faces are never rewritten in place (an edit removes a face and adds a new one, found through
  //   the log by faces_around), so a live candidate still has the corners it was a candidate with.
  auto around =
      detail::faces_around(mesh, log, touched, posed.first_new(), &index, posed.input());
  if (!posed.moved().empty()) {
    std::vector<FaceId> snapped;
    for (const FaceId f : candidates)
      if (!mesh.is_deleted(f)) {
        const Triangle& t = mesh.face(f);
        if (posed.is_moved(t[0]) || posed.is_moved(t[1]) || posed.is_moved(t[2])) snapped.push_back(f);
      }
    std::sort(snapped.begin(), snapped.end());
    const auto middle = static_cast<std::ptrdiff_t>(around.size());
    around.insert(around.end(), snapped.begin(), snapped.end());
    std::inplace_merge(around.begin(), around.begin() + middle, around.end());
  }
  return {std::move(touched), std::move(around)};
}

// Splits the vertices where a rim pinches the surface (a vertex joining two fans: one vertex
// each), found in `in` (pinch_input); the copies' posed positions go to `posed`.
detail::PinchSplits split_pinches(MeshEditor& editor, drill::PosedOverlay& posed, const PinchInput& in) {
  auto pinches = detail::split_pinched_vertices(editor, in.touched, in.around);
  for (const auto& [v, c] : pinches.copies) {
    (void)c;
    posed.add(posed(v));
  }
  return pinches;
}

// The vertices the rim insertion can have pinched (without walls): those on the rims just
// traced, and the corners it bared (RimInsertion::bared: no face added for a removed candidate
// uses them, none deep inside). Elsewhere no fan is parted: an old vertex off the cylinder keeps
// every face around it, each as a kept part holding that corner and the first pieces of its two
// edges there, and the kept parts on either side of an edge split its pieces alike (one set of
// crossings and Steiner points per edge; a needle's merged crossings are merged in both), so
// faces joined through an edge at the vertex still are; a new vertex off the rim (a Steiner point
// on an edge with one face on each side, a refinement point inside a kept part) lies in one fan;
// a vertex whose faces part leaves boundary edges there, and on the cylinder those are rim. As
// the cut, the drill mends the pinches it makes, not those the input had.
std::vector<VertexId> rim_pinch_candidates(const std::vector<drill::Rim>& rims,
                                           const std::vector<VertexId>& bared) {
  std::vector<VertexId> out;
  for (const drill::Rim& rim : rims) out.insert(out.end(), rim.vertices.begin(), rim.vertices.end());
  out.insert(out.end(), bared.begin(), bared.end());
  detail::sort_unique_ids(out);
  return out;
}

// Of the rim pinch candidates (rim_pinch_candidates), those that can be pinched: without merged
// crossings, the old ones only. A new vertex joins one fan: a crossing or a Steiner point lies on
// one mesh edge, and every kept part holding it holds the edge's piece beside it (outside the
// cylinder, one set of points per edge), so all its faces are joined through that piece; a rim
// sample or a refinement point lies in one kept part, a triangulated disk (or a triangle with a
// hole), where the faces around a point form one fan. A merged crossing stands on two edges
// (and a merged tip drops faces), and a kept part whose clip dropped a degenerate ear may leave
// a gap beside a point: then (`every`) every candidate is looked at.
std::vector<VertexId> old_pinch_candidates(const std::vector<VertexId>& touched, std::uint32_t first_new,
                                           bool every) {
  if (every) return touched;
  std::vector<VertexId> out;
  for (const VertexId v : touched)
    if (v.index < first_new) out.push_back(v);  // `touched` is sorted: so is `out`
  return out;
}

// Without walls: the pinch split, then the rims traced through the copies. The rims are traced
// first and the search for pinches looks only at their vertices that can be pinched
// (old_pinch_candidates) and the bared corners; a pinch is rare, so the rims are traced again
// only when a vertex was split (the split itself is given every rim vertex and bared corner).
std::vector<drill::Rim> split_and_trace(MeshEditor& editor, const drill::CylinderFrame& cyl,
                                        drill::PosedOverlay& posed, const std::vector<FaceId>& candidates,
                                        const TriangleGrid& index, const drill::RimInsertion& inserted) {
  const SurfaceMesh& mesh = editor.mesh();
  std::vector<drill::Rim> rims = drill::trace_rims(mesh, editor.log(), cyl, posed, candidates, {});
  std::vector<VertexId> touched = rim_pinch_candidates(rims, inserted.bared);
  {
    std::vector<VertexId> old_ones =
        old_pinch_candidates(touched, posed.first_new(), inserted.merged || inserted.gaps);
    if (old_ones.empty()) return rims;  // nothing to look at (pinch_input would walk the log)
    const PinchInput old = pinch_input(mesh, editor.log(), posed, std::move(old_ones), candidates, index);
    if (!detail::any_pinched(mesh, old.touched, old.around)) return rims;
  }
  const PinchInput in = pinch_input(mesh, editor.log(), posed, std::move(touched), candidates, index);
  std::unordered_map<std::uint32_t, std::uint32_t> copy_of;  // pinch-split copy -> original
  for (const auto& [v, c] : split_pinches(editor, posed, in).copies) copy_of.emplace(c.index, v.index);
  return drill::trace_rims(mesh, editor.log(), cyl, posed, candidates, copy_of);
}

DrillResult run(SurfaceMesh& mesh, const std::vector<glm::vec3>& input_posed, const Cylinder& cylinder,
                const DrillOptions& options, const TriangleGrid& index, const drill::Unposer& unpose) {
  const drill::CylinderFrame cyl = drill::CylinderFrame::make(cylinder, options);
  MeshEditor editor(mesh);
  drill::PosedOverlay posed(input_posed, unpose);
  DrillResult result;
  result.first_new_vertex = posed.first_new();
  const std::vector<FaceId> candidates = drill::find_candidates(mesh, cyl, posed, index);
  std::vector<std::uint8_t> deep_corners;  // per candidate (snap_shallow_vertices)
  drill::snap_shallow_vertices(editor, cyl, posed, candidates, deep_corners);
  const drill::RimInsertion inserted = drill::insert_rim(editor, cyl, posed, candidates, deep_corners);
  if (editor.log().size() == posed.moved().size()) {  // nothing cut: the snaps go back, the log stays empty
    for (const Edit& e : editor.log().edits)
      if (const auto* mv = std::get_if<VertexMoved>(&e)) mesh.positions()[mv->v.index] = mv->from;
    result.status = OpStatus::NoIntersection;
    return result;
  }
  // A rim through a vertex snapped onto the cylinder can leave it joining two fans: one vertex
  // each. Without walls before the rims are traced, so each rim runs through its own copy; with
  // walls after them (a wall can join the fans again), the rims following the copies.
  const std::vector<drill::Rim> rims = options.wall
                                           ? drill::trace_rims(mesh, editor.log(), cyl, posed, candidates, {})
                                           : split_and_trace(editor, cyl, posed, candidates, index, inserted);
  for (const drill::Rim& rim : rims) {
    DrillHole hole;
    hole.rim = rim.vertices;
    hole.closed = rim.closed;
    hole.winding = rim.winding;
    result.holes.push_back(std::move(hole));
  }
  result.intersection_points = inserted.crossings;
  result.triangles_removed = inserted.removed;
  result.triangles_added = inserted.added;
  if (options.wall) {
    const drill::WallResult walls = drill::build_drill_walls(editor, cyl, rims, posed, candidates);
    for (std::size_t h = 0; h < walls.walled.size(); ++h) result.holes[h].walled = walls.walled[h] != 0;
    result.wall_triangles = walls.wall_triangles;
    result.triangles_removed += walls.triangles_removed;
    result.triangles_added += walls.wall_triangles;
    const auto pinches =
        split_pinches(editor, posed,
                      pinch_input(mesh, editor.log(), posed, pinch_candidates(mesh, editor.log(), cyl, posed),
                                  candidates, index));
    for (DrillHole& h : result.holes) detail::follow_pinch_splits(mesh, pinches, h.rim, h.closed);
  }
  result.added_posed.reserve(posed.added().size());
  for (const auto& p : posed.added()) result.added_posed.push_back(glm::vec3(p));
  for (const auto& [v, p] : posed.moved()) result.moved.push_back({VertexId(v), glm::vec3(p)});
  result.log = editor.take_log();
  return result;
}

// Drills primitive `pi` of the instance's mesh (InstanceEdit::edit) in place, adds its counts to
// `result`, and moves its wall faces to a primitive of their own appended to `walls` (the "Cut
// surface" material, added to the model on first use into `cut_material`); the posed instance
// follows. Returns false when the cylinder misses it.
bool drill_primitive(detail::InstanceEdit& inst, int pi, const Cylinder& cylinder, const DrillOptions& options,
                     int& cut_material, ModelDrillResult& result, std::vector<Primitive>& walls) {
  Primitive& prim = inst.edit().primitives[static_cast<std::size_t>(pi)];
  // Faces flagged before the drill (a mesh made in code) go to the wall too, as new ones do.
  const bool flagged_before = prim.mesh.face_attrs().contains(attr::kCutSurface);
  DrillResult r = drill_mesh(prim.mesh, *inst.posed(pi), cylinder, options);  // prepare() made every instance
  if (r.status == OpStatus::NoIntersection) return false;
  result.status = OpStatus::Ok;
  result.intersection_points += r.intersection_points;
  result.triangles_removed += r.triangles_removed;
  result.triangles_added += r.triangles_added;
  result.wall_triangles += r.wall_triangles;
  for (const auto& h : r.holes) {
    result.rim_vertices.push_back(h.rim.size());
    result.unwalled_holes += options.wall && !h.walled;
  }
  // Wall faces move to a primitive of their own: gathered from the log, extracted at the wall's
  // cost, and removed from the body through the editor.
  std::vector<FaceId> wall;
  if (const auto* flag = prim.mesh.face_attrs().find<std::uint8_t>(attr::kCutSurface)) {
    if (flagged_before) {
      prim.mesh.for_each_face([&](FaceId f, const Triangle&) {
        if ((*flag)[f.index]) wall.push_back(f);
      });
    } else {
      for (const Edit& e : r.log.edits)
        if (const auto* a = std::get_if<FaceAdded>(&e))
          if (!prim.mesh.is_deleted(a->f) && (*flag)[a->f.index]) wall.push_back(a->f);
      std::sort(wall.begin(), wall.end());
    }
  }
  if (!wall.empty()) {
    Primitive w;
    w.mesh = detail::extract(prim.mesh, wall);
    w.mesh.face_attrs().remove(attr::kCutSurface);
    if (cut_material < 0) cut_material = detail::cut_surface_material(inst.model());
    w.material = cut_material;
    w.extras_json = prim.extras_json;
    walls.push_back(std::move(w));
    MeshEditor editor(prim.mesh);
    for (FaceId f : wall) editor.remove_face(f);
    r.log.append(editor.take_log());
  }
  prim.mesh.face_attrs().remove(attr::kCutSurface);
  inst.posed_model().follow(inst.model(), inst.node(), pi, prim.mesh, r.log);
  return true;
}

}  // namespace

float min_drill_radius(const Cylinder& cylinder, int min_rim_edges) {
  const double spacing = 1e-6 * axis_scale(cylinder);  // the floor of CylinderFrame::eps
  const double r = spacing / (2.0 * std::sin(kPi / std::max(min_rim_edges, 3)));
  return std::nextafter(static_cast<float>(r), std::numeric_limits<float>::infinity());
}

DrillResult drill_mesh(SurfaceMesh& mesh, const PosedMesh& posed, const Cylinder& cylinder,
                       const DrillOptions& options) {
  check_arguments(cylinder, options);
  if (posed.posed.size() != mesh.vertex_count())
    throw Error(ErrorCode::InvalidArgument, "drill: " + std::to_string(posed.posed.size()) +
                                                " posed positions for " +
                                                std::to_string(mesh.vertex_count()) + " vertices");
  const drill::Unposer unpose = [&posed](const SurfaceMesh& m, VertexId v, const glm::vec3& p) {
    return posed.unpose(m, v, p);
  };
  return run(mesh, posed.posed, cylinder, options, posed.grid, posed.no_unpose ? drill::Unposer() : unpose);
}

ModelDrillResult drill_model(Model& model, const Cylinder& cylinder, const DrillOptions& options,
                             int animation, float time) {
  check_arguments(cylinder, options);
  PosedModel posed = PosedModel::build(model, animation, time);
  return drill_model(model, posed, cylinder, options, animation, time);
}

ModelDrillResult drill_model(Model& model, PosedModel& posed, const Cylinder& cylinder,
                             const DrillOptions& options, int animation, float time) {
  check_arguments(cylinder, options);
  posed.prepare(model, animation, time);
  ModelDrillResult result;
  result.status = OpStatus::NoIntersection;
  int cut_material = -1;
  detail::for_each_instance(model, posed, [&](detail::InstanceEdit& inst) {
    // The primitives are drilled in place (no copy, no re-extraction: the cost follows the hole);
    // a mesh drawn by several instances is drilled on a copy that this instance then owns.
    Mesh& target = inst.edit();
    std::vector<Primitive> walls;
    bool any = false;
    for (std::size_t pi = 0; pi < target.primitives.size(); ++pi)
      any |= drill_primitive(inst, static_cast<int>(pi), cylinder, options, cut_material, result, walls);
    if (!any) return false;
    // Primitives the cylinder swallowed go; the walls follow the primitives.
    for (std::size_t pi = target.primitives.size(); pi-- > 0;)
      if (target.primitives[pi].mesh.face_count() == 0) inst.erase_primitive(static_cast<int>(pi));
    for (auto& w : walls) inst.add_primitive(std::move(w));
    if (target.primitives.empty()) inst.drop();  // the cylinder swallowed the whole instance
    return true;
  });
  return result;
}

}  // namespace deepcut
