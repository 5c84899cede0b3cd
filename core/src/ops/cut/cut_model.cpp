// SPDX-License-Identifier: MIT
// The model-level cut: every instance of a model cut at a pose, each side a piece node.
#include "deepcut/core/ops/cut.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <variant>

#include "deepcut/core/parallel.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/core/skinning.h"
#include "ops/common/model_surgery.h"

namespace deepcut {

namespace {

// Rim vertices lie on the plane in the pose the cut was made in up to float rounding (new ones
// are their posed crossing points unposed), and input vertices within the tolerance of the plane
// count as on it. Move each rim vertex in bind space by the amount that puts it on the plane in
// that pose (`posed`: the instance after the cut), so a second cut with the same plane finds
// nothing left to cut. A bind move maps through the vertex's linear map alone (a morph offset
// stays as it is).
void snap_rim_to_plane(const PosedMesh& posed, const Plane& plane, const CutResult& result, SurfaceMesh& mesh) {
  const glm::vec3 n = glm::normalize(plane.normal);
  auto& bind = mesh.positions();
  for (VertexId v : result.rim_vertices) {
    const float off = glm::dot(posed.posed[v.index] - plane.point, n);
    if (off == 0.0f) continue;
    const glm::mat3 linear = posed.linear.empty() ? glm::mat3(1.0f) : posed.linear[v.index];
    if (std::abs(glm::determinant(linear)) < 1e-12f) continue;
    mesh.writing_vertex(v);  // an input vertex on the plane: an undo record keeps its old value
    bind[v.index] -= off * (glm::inverse(linear) * n);
  }
}

// The instance (node, primitive mesh `mesh`) posed on its own, as PosedModel poses it without a
// grid: for an instance the posed model does not index.
PosedMesh pose_alone(const Model& model, int node, const SurfaceMesh& mesh, const std::vector<glm::mat4>& world,
                     const std::vector<float>& weights) {
  PosedMesh out;
  out.world = world[static_cast<std::size_t>(node)];
  const int skin = model.nodes[static_cast<std::size_t>(node)].skin;
  if (skin >= 0 && static_cast<std::size_t>(skin) < model.skins.size()) out.joints = joint_matrices(model, skin, world);
  out.weights = weights;
  out.posed = posed_positions(model, node, mesh, world, weights);
  for (const glm::mat4& m : vertex_skin_matrices(model, node, mesh, world)) out.linear.emplace_back(m);
  for (const glm::vec3& p : out.posed) out.bounds.add(p);
  out.gridless = true;
  return out;
}

// Side an untouched primitive lies on (it may be on the side that is dropped).
int side_of(const SurfaceMesh& mesh, const std::vector<glm::vec3>& posed, const Plane& plane) {
  double d = 0.0;
  mesh.for_each_face([&](FaceId, const Triangle& t) {
    for (auto v : t) d += glm::dot(glm::dvec3(posed[v.index]) - glm::dvec3(plane.point), glm::dvec3(plane.normal));
  });
  return d >= 0.0 ? 1 : -1;
}

// The cut of one instance's primitives, made in place on the node's mesh (InstanceEdit::edit: a
// copy only when other nodes draw it too). A primitive the plane misses is left untouched
// (cut_mesh changes nothing then), so an instance missed everywhere needs no undoing.
struct InstanceCut {
  std::vector<CutResult> results;
  std::vector<std::pair<std::size_t, std::size_t>> sizes_before;  // each primitive's vertex and face slot counts
  bool any = false;
};

InstanceCut cut_instance(detail::InstanceEdit& inst, const std::vector<glm::mat4>& world, const Plane& plane,
                         const CutOptions& options) {
  InstanceCut out;
  auto& prims = inst.edit().primitives;
  for (std::size_t p = 0; p < prims.size(); ++p) {
    // A watched mesh (the session's undo record follows it) is cut in place like any other: the
    // record keeps the old values of what the cut rewrites, and split_disjoint takes it apart as
    // it takes any mesh apart, the record keeping only what no piece holds (SplitWatcher): its
    // undo grows the piece that kept the arrays back and takes the cut back on it.
    SurfaceMesh& mesh = prims[p].mesh;
    PosedMesh own;
    PosedMesh* posed = inst.posed(static_cast<int>(p));
    if (!posed) {
      own = pose_alone(inst.model(), inst.node(), mesh, world, inst.posed_model().weights(inst.node()));
      posed = &own;
    }
    out.sizes_before.emplace_back(mesh.vertex_count(), mesh.face_slots());
    // A cut instance leaves the posed model (its pieces replace the mesh, and the next prepare
    // indexes them): its grid would be kept in step with the cut only to be dropped, so the cut
    // follows it as gridless (positions and linear maps, which the rim's snap reads). A primitive
    // the plane misses keeps its grid as it was.
    const bool gridless = posed->gridless;
    posed->gridless = true;
    out.results.push_back(cut_mesh(mesh, *posed, plane, options));
    CutResult& r = out.results.back();
    if (r.status != OpStatus::Ok) posed->gridless = gridless;
    if (r.status == OpStatus::Ok) snap_rim_to_plane(*posed, plane, r, mesh);
    if (r.status == OpStatus::NoIntersection) r.piece_sides = {side_of(mesh, posed->posed, plane)};
    out.any |= r.status == OpStatus::Ok;
  }
  return out;
}

// Each piece of a cut primitive as primitives: its original-material faces and its cut-surface
// faces (caps), each extracted straight from the cut mesh, without the cut-surface flag. The cut
// mesh is taken apart (split_disjoint): one piece keeps its arrays, the others are
// copied out of it, in parallel (a watched mesh too, when its watcher follows it: SplitWatcher).
// `sides` (the cut's sides of the pieces and vertices, or nullptr) spares the surgery finding
// each vertex's piece.
std::vector<std::vector<Primitive>> piece_primitives(SurfaceMesh&& mesh, const std::vector<std::vector<FaceId>>& pieces,
                                                     const detail::PieceSides* sides, int material, int cut_material,
                                                     std::vector<detail::PieceElements>* elements) {
  const auto* flag = mesh.face_attrs().find<std::uint8_t>(attr::kCutSurface);
  const bool flagged = flag != nullptr;
  std::vector<std::vector<FaceId>> body, cap;
  if (flagged) {
    body.resize(pieces.size());
    cap.resize(pieces.size());
    for (std::size_t k = 0; k < pieces.size(); ++k)
      for (FaceId f : pieces[k]) ((*flag)[f.index] ? cap[k] : body[k]).push_back(f);
  }
  std::vector<SurfaceMesh> cap_meshes = flagged ? detail::extract_disjoint(mesh, cap) : std::vector<SurfaceMesh>();
  std::vector<SurfaceMesh> body_meshes = detail::split_disjoint(std::move(mesh), flagged ? body : pieces,
                                                                sides && !flagged ? *sides : detail::PieceSides{}, elements);
  // Only the bodies that become primitives (first of their piece) keep their elements.
  if (elements && elements->size() != pieces.size()) elements->assign(pieces.size(), {});
  for (std::size_t k = 0; elements && k < pieces.size(); ++k)
    if (body_meshes[k].face_count() == 0) (*elements)[k] = {};
  std::vector<std::vector<Primitive>> out(pieces.size());
  auto add = [&](SurfaceMesh& m, int mat, std::vector<Primitive>& to) {
    if (m.face_count() == 0) return;
    Primitive prim;
    prim.mesh = std::move(m);
    prim.mesh.face_attrs().remove(attr::kCutSurface);
    prim.material = mat;
    to.push_back(std::move(prim));
  };
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    add(body_meshes[k], material, out[k]);
    if (flagged) add(cap_meshes[k], cut_material, out[k]);
  }
  return out;
}

// The elements of a primitive (`vertices_before` and `faces_before` slots before the cut) that the
// cut added or rewrote, by its result: the rim's vertices (new, or snapped onto the plane), moved
// or added vertices, and removed or added face slots.
struct Rewritten {
  std::vector<char> vertices, faces;
};

Rewritten rewritten_by(const CutResult& r, std::pair<std::size_t, std::size_t> before) {
  Rewritten out{std::vector<char>(before.first, 0), std::vector<char>(before.second, 0)};
  auto vertex = [&](VertexId v) {
    if (v.index < out.vertices.size()) out.vertices[v.index] = 1;
  };
  auto face = [&](FaceId f) {
    if (f.index < out.faces.size()) out.faces[f.index] = 1;
  };
  for (VertexId v : r.rim_vertices) vertex(v);
  for (const Edit& e : r.log.edits) {
    if (const auto* m = std::get_if<VertexMoved>(&e)) vertex(m->v);
    if (const auto* a = std::get_if<VertexAdded>(&e)) vertex(a->v);
    if (const auto* s = std::get_if<VertexSplit>(&e)) vertex(s->copy);
    if (const auto* fa = std::get_if<FaceAdded>(&e)) face(fa->f);
    if (const auto* fr = std::get_if<FaceRemoved>(&e)) face(fr->f);
  }
  return out;
}

// Where the elements of `piece` (split out of primitive `primitive` as `elements` says) came from
// before the cut (PrimitiveOrigin): a vertex the cut neither added nor rewrote is the source vertex
// of the same index; a face slot it neither added nor removed whose corners all have a source
// vertex, the source face slot of the same index. The places are set once the pieces are
// installed.
std::shared_ptr<PrimitiveOrigin> piece_origin(detail::PieceElements&& elements, const SurfaceMesh& piece,
                                              const Rewritten& rewritten, int primitive) {
  auto out = std::make_shared<PrimitiveOrigin>();
  out->primitive_before = primitive;
  const std::vector<char>&rv = rewritten.vertices, &rf = rewritten.faces;
  // The elements' arrays become the origin's (no new memory), each entry kept or made invalid.
  out->vertices = std::move(elements.vertices);
  parallel_for(out->vertices.size(), 65536, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const std::uint32_t v = out->vertices[i];
      if (v >= rv.size() || rv[v]) out->vertices[i] = kInvalidIndex;
    }
  });
  out->faces = std::move(elements.faces);
  parallel_for(out->faces.size(), 65536, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const std::uint32_t f = out->faces[i];
      const Triangle& t = piece.face(FaceId(static_cast<std::uint32_t>(i)));
      const bool kept = f < rf.size() && !rf[f] && out->vertices[t[0].index] != kInvalidIndex &&
                        out->vertices[t[1].index] != kInvalidIndex && out->vertices[t[2].index] != kInvalidIndex;
      if (!kept) out->faces[i] = kInvalidIndex;
    }
  });
  return out;
}

// Groups each primitive's pieces into output meshes: without split_components piece k of every
// primitive (0 positive, 1 negative) shares a mesh; with it, every piece is its own. `origins`
// gets, per output mesh and primitive, where a piece's body came from (null for caps, and where
// the surgery could not say).
std::vector<Mesh> group_pieces(Mesh& edited, const InstanceCut& cut, const CutOptions& options, int cut_material,
                               ModelCutResult& result, std::vector<std::vector<std::shared_ptr<PrimitiveOrigin>>>& origins) {
  std::vector<Mesh> piece_meshes;
  for (std::size_t p = 0; p < cut.results.size(); ++p) {
    const CutResult& r = cut.results[p];
    SurfaceMesh& mesh = edited.primitives[p].mesh;  // taken apart into its pieces
    result.intersection_points += r.intersection_points;
    result.rim_vertices += r.rim_vertices.size();
    std::vector<std::vector<FaceId>> whole;
    if (r.status == OpStatus::NoIntersection) {
      const int side = r.piece_sides[0];
      if ((options.keep == CutKeep::Positive && side < 0) || (options.keep == CutKeep::Negative && side > 0)) continue;
      whole.emplace_back();
      mesh.for_each_face([&](FaceId f, const Triangle&) { whole[0].push_back(f); });
    }
    const auto& pieces = r.status == OpStatus::NoIntersection ? whole : r.pieces;
    const std::vector<std::int8_t>& vertex_sides = detail::CutSides::of(r);
    const detail::PieceSides sides{&r.piece_sides, &vertex_sides};
    const bool by_side = r.status == OpStatus::Ok && !vertex_sides.empty();
    // Origins for a mesh an undo record watches: a front end that follows the steps (the
    // studio's session) hands them on; a one-off cut (the command line) spares the passes.
    std::vector<detail::PieceElements> elements;
    const bool followed = mesh.observer() != nullptr;
    std::vector<std::vector<Primitive>> prims =
        piece_primitives(std::move(mesh), pieces, by_side ? &sides : nullptr, edited.primitives[p].material, cut_material,
                         followed ? &elements : nullptr);
    if (!followed) elements.assign(pieces.size(), {});
    const Rewritten rewritten = followed ? rewritten_by(r, cut.sizes_before[p]) : Rewritten();
    for (std::size_t k = 0; k < pieces.size(); ++k) {
      const int side = r.piece_sides[k];
      const std::size_t slot = options.split_components ? piece_meshes.size() : (side > 0 ? 0 : 1);
      if (slot >= piece_meshes.size()) {
        piece_meshes.resize(slot + 1);
        origins.resize(slot + 1);
      }
      for (std::size_t j = 0; j < prims[k].size(); ++j) {
        const bool body = j == 0 && !elements[k].faces.empty();
        origins[slot].push_back(
            body ? piece_origin(std::move(elements[k]), prims[k][j].mesh, rewritten, static_cast<int>(p)) : nullptr);
        piece_meshes[slot].primitives.push_back(std::move(prims[k][j]));
      }
    }
  }
  for (std::size_t k = piece_meshes.size(); k-- > 0;)
    if (piece_meshes[k].primitives.empty()) {
      piece_meshes.erase(piece_meshes.begin() + static_cast<std::ptrdiff_t>(k));
      origins.erase(origins.begin() + static_cast<std::ptrdiff_t>(k));
    }
  return piece_meshes;
}

// The instance draws the first piece; every other piece becomes a node beside it. The pieces'
// origins get their places (but the mesh after the step: once the surgery is done) and go to
// `made`.
void install_pieces(detail::InstanceEdit& inst, std::vector<Mesh> piece_meshes,
                    const std::vector<std::vector<std::shared_ptr<PrimitiveOrigin>>>& origins, ModelCutResult& result,
                    std::vector<std::shared_ptr<PrimitiveOrigin>>& made) {
  // Copies: replacing the mesh below overwrites the source.
  const std::string source_name = inst.source().name, source_extras = inst.source().extras_json;
  const std::string& node_name = inst.model().nodes[static_cast<std::size_t>(inst.node())].name;
  const std::string base = node_name.empty() ? source_name : node_name;
  for (std::size_t k = 0; k < piece_meshes.size(); ++k) {
    Mesh& m = piece_meshes[k];
    m.name = (source_name.empty() ? base : source_name) + "_piece" + std::to_string(k);
    m.extras_json = source_extras;
    if (k == 0) {
      inst.replace_mesh(std::move(m));
      result.piece_nodes.push_back(inst.node());
    } else {
      result.piece_nodes.push_back(inst.add_piece_node(std::move(m), base + "_piece" + std::to_string(k)));
    }
    for (std::size_t j = 0; j < origins[k].size(); ++j) {
      if (!origins[k][j]) continue;
      PrimitiveOrigin& origin = *origins[k][j];
      origin.node = result.piece_nodes.back();
      origin.primitive = static_cast<int>(j);
      origin.node_before = inst.node();
      origin.mesh_before = inst.mesh();
      made.push_back(origins[k][j]);
    }
  }
}

}  // namespace

ModelCutResult cut_model(Model& model, PosedModel& posed, const Plane& plane, const CutOptions& options, int animation,
                         float time) {
  // The cut classifies every vertex of the instances it visits: it needs positions, not grids.
  posed.prepare(model, animation, time, PoseDetail::Positions);
  const std::vector<glm::mat4> world = posed.world();
  ModelCutResult result;
  result.status = OpStatus::NoIntersection;
  int cut_material = -1;
  std::vector<std::pair<int, int>> missed;  // instance node, side it lies on
  std::vector<std::shared_ptr<PrimitiveOrigin>> made;  // the pieces' origins
  detail::ModelSurgery surgery(model, posed);
  surgery.for_each_instance([&](detail::InstanceEdit& inst) {
    const InstanceCut cut = cut_instance(inst, world, plane, options);
    if (!cut.any) {
      int votes = 0;
      for (const auto& r : cut.results) votes += r.piece_sides.empty() ? 0 : r.piece_sides[0];
      missed.emplace_back(inst.node(), votes >= 0 ? 1 : -1);
      return false;
    }
    result.status = OpStatus::Ok;
    if (options.cap && cut_material < 0) cut_material = detail::cut_surface_material(model);
    std::vector<std::vector<std::shared_ptr<PrimitiveOrigin>>> origins;
    std::vector<Mesh> piece_meshes = group_pieces(inst.edit(), cut, options, cut_material, result, origins);
    if (piece_meshes.empty()) {
      posed.erase_node(inst.node());  // its posed primitives grew with the cut: indexed anew
      return false;
    }
    install_pieces(inst, std::move(piece_meshes), origins, result, made);
    return true;
  });
  // Whole instances on the dropped side go too (only when something was cut: a plane that
  // misses everything leaves the model unchanged).
  if (result.status == OpStatus::Ok && options.keep != CutKeep::Both) {
    const int drop = options.keep == CutKeep::Positive ? -1 : 1;
    for (const auto& [node, side] : missed)
      if (side == drop) surgery.drop_instance(node);
  }
  // The pieces' meshes, now that the surgery is done (an origin whose node no longer draws the
  // primitive is dropped).
  for (const std::shared_ptr<PrimitiveOrigin>& origin : made) {
    const int mesh = model.nodes[static_cast<std::size_t>(origin->node)].mesh;
    if (mesh < 0 || static_cast<std::size_t>(mesh) >= model.meshes.size() ||
        static_cast<std::size_t>(origin->primitive) >= model.meshes[static_cast<std::size_t>(mesh)].primitives.size())
      continue;
    origin->mesh = mesh;
    result.origins.push_back(origin);
  }
  return result;
}

ModelCutResult cut_model(Model& model, const Plane& plane, const CutOptions& options, int animation, float time) {
  PosedModel posed;
  return cut_model(model, posed, plane, options, animation, time);
}

}  // namespace deepcut
