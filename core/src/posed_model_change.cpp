// SPDX-License-Identifier: MIT
// The posed model following an undo or a redo (PosedModel::follow with a ModelChange): the
// change said as an edit log each instance follows, after cutting off what the step removed; a
// mapped structural step keeps the instances of the contents it kept or brought back.
#include <algorithm>
#include <map>
#include <set>

#include "deepcut/core/posed_model.h"
#include "deepcut/core/smallest_fit.h"

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

using Place = std::pair<int, int>;  // (mesh, primitive)

/// An instance a structural step makes out of one drawn before (PosedModel::derive_instance).
struct Derivation {
  std::pair<int, int> key;  // (node, primitive)
  Place place;
};

/// Calls `fn(node, mesh, primitive)` for every primitive of every node with a mesh, in order.
template <class Fn>
void for_each_instance(const Model& model, Fn&& fn) {
  for (std::size_t ni = 0; ni < model.nodes.size(); ++ni) {
    const int mi = model.nodes[ni].mesh;
    if (mi < 0 || static_cast<std::size_t>(mi) >= model.meshes.size()) continue;
    for (std::size_t p = 0; p < model.meshes[static_cast<std::size_t>(mi)].primitives.size(); ++p)
      fn(static_cast<int>(ni), mi, static_cast<int>(p));
  }
}

/// What a structural change says of the places (mesh, primitive) now: where the content kept
/// there was before, and the tag of the content that arrived there (`tags`: all of them).
struct Arrivals {
  std::map<Place, Place> kept_from;
  std::map<Place, std::uint64_t> arrived;
  std::set<std::uint64_t> tags;
};

Arrivals arrivals_of(const ModelChange& change) {
  Arrivals out;
  for (const PrimitiveKept& k : change.kept)
    out.kept_from[{k.mesh, k.primitive}] = {k.mesh_before, k.primitive_before};
  for (const PrimitiveContent& a : change.arrived) {
    out.arrived[{a.mesh, a.primitive}] = a.tag;
    out.tags.insert(a.tag);
  }
  return out;
}

/// What `stash` holds for no arrival, moved out: a derived instance takes the arrays of one
/// (their memory reused, no new pages to fault in); the others are freed with the list. Those
/// that held the most vertices come first: of spares with equal room, the largest piece, derived
/// first, takes the one with the most pages already faulted in, and so on down.
std::vector<PosedMesh> spares_of(PoseStash& stash, const Arrivals& arrivals) {
  std::vector<PosedMesh> spare = take_unclaimed(stash, arrivals.tags);
  largest_first(spare, [](const PosedMesh& m) { return m.posed.size(); });
  return spare;
}

/// The vertices of the primitive a derivation makes.
std::size_t vertices_of(const Model& model, const Derivation& d) {
  const Node& node = model.nodes[static_cast<std::size_t>(d.key.first)];
  const Mesh& mesh = model.meshes[static_cast<std::size_t>(node.mesh)];
  return mesh.primitives[static_cast<std::size_t>(d.key.second)].mesh.vertex_count();
}

/// Moves the instances of the contents that left (`left`) out of `old` into `stash`.
void stash_left(const std::vector<PrimitiveContent>& left, std::map<std::pair<int, int>, PosedMesh>& old,
                PoseStash& stash) {
  for (const PrimitiveContent& l : left)
    for (auto& [key, inst] : old)
      if (inst.mesh == l.mesh && inst.primitive == l.primitive && !inst.posed.empty())
        stash[{l.tag, inst.node}] = std::move(inst);
}

}  // namespace

void PosedModel::follow(const Model& model, const ModelChange& change, PoseDetail detail, PoseStash* stash) {
  if (!change.structure || !change.mapped || !valid_) {
    if (stash) stash->clear();
    follow(model, change);
    return;
  }
  std::map<std::pair<int, int>, PosedMesh> old = std::move(instances_);  // by (node, primitive)
  instances_.clear();
  PoseStash back;
  if (stash) back.swap(*stash);
  set_pose(model, key_);
  const Arrivals arrivals = arrivals_of(change);
  std::vector<PosedMesh> spare = spares_of(back, arrivals);
  // Posed as a build would pose `place` for `node` (the sizes: a guard against a follower that
  // did not show the state before the step).
  auto posed_alike = [&](const PosedMesh& inst, int node, const Place& place) {
    const SurfaceMesh& mesh =
        model.meshes[static_cast<std::size_t>(place.first)].primitives[static_cast<std::size_t>(place.second)].mesh;
    return inst.posed.size() == mesh.vertex_count() && inst.world == world_[static_cast<std::size_t>(node)] &&
           inst.joints == joints_of(model, node) && inst.weights == weights(node) &&
           !(detail == PoseDetail::Full && inst.gridless);
  };
  // The instance of content `place` drew before (kept) or that `stash` holds, if posed alike.
  auto reuse = [&](int node, const Place& place, PosedMesh& out) {
    const auto k = arrivals.kept_from.find(place);
    if (k != arrivals.kept_from.end()) {
      const auto it = old.find({node, k->second.second});
      if (it == old.end() || it->second.mesh != k->second.first || !posed_alike(it->second, node, place))
        return false;
      out = std::move(it->second);
      old.erase(it);
      return true;
    }
    const auto a = arrivals.arrived.find(place);
    if (a == arrivals.arrived.end()) return false;
    const auto it = back.find({a->second, node});
    if (it == back.end() || !posed_alike(it->second, node, place)) return false;
    out = std::move(it->second);
    back.erase(it);
    return true;
  };
  // The instance drawn before of the content a primitive was made out of (ModelChange::origins),
  // posed as a build would pose that content for `node`: what derive_instance copies from.
  auto source_of = [&](int node, const Place& place) -> std::pair<const PosedMesh*, const PrimitiveOrigin*> {
    if (detail != PoseDetail::Positions) return {nullptr, nullptr};
    for (const auto& o : change.origins) {
      if (!o || o->node != node || o->mesh != place.first || o->primitive != place.second) continue;
      const auto it = old.find({o->node_before, o->primitive_before});
      const PosedMesh* source = it == old.end() ? nullptr : &it->second;
      if (!source || source->mesh != o->mesh_before || source->world != world_[static_cast<std::size_t>(node)] ||
          source->joints != joints_of(model, node) || source->weights != weights(node))
        return {nullptr, nullptr};
      return {source, o.get()};
    }
    return {nullptr, nullptr};
  };
  std::vector<Derivation> derived;  // made once every instance kept or brought back is in place
  for_each_instance(model, [&](int node, int mi, int prim) {
    PosedMesh inst;
    if (reuse(node, {mi, prim}, inst)) {
      inst.mesh = mi;
      inst.primitive = prim;
    } else if (source_of(node, {mi, prim}).first) {
      derived.push_back({{node, prim}, {mi, prim}});  // its place held until it is made
    } else {
      inst = make_instance(model, node, prim, detail);
    }
    instances_[{node, prim}] = std::move(inst);
  });
  largest_first(derived, [&](const Derivation& d) { return vertices_of(model, d); });
  for (const Derivation& d : derived) {
    // Looked up again: a later reuse may have taken it out of `old` (a cut never does).
    const auto [source, origin] = source_of(d.key.first, d.place);
    instances_[d.key] = source ? derive_instance(model, d.key.first, d.key.second, *source, *origin, spare)
                               : make_instance(model, d.key.first, d.key.second, detail);
  }
  if (stash) stash_left(change.left, old, *stash);
}

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
