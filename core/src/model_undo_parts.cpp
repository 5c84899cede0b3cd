// SPDX-License-Identifier: MIT
// The parts of an undo record: one primitive's in-place edit, the model's small parts, the text
// of the root extras that changed.
#include "model_undo_parts.h"

#include <algorithm>
#include <iterator>

#include "deepcut/core/model_change.h"
#include "deepcut/core/parallel.h"
#include "model_parts_equal.h"
#include "ops/common/model_surgery_in_place.h"
#include "uninit_vector.h"

namespace deepcut::undo {

void MeshDelta::swap_existing(SurfaceMesh& mesh) {
  for (std::size_t i = 0; i < vertices.size(); ++i) mesh.vertex_attrs().swap_elements(vertex_values, vertices[i], i);
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const std::uint32_t f = faces[i];
    mesh.swap_face(FaceId(f), corners[i], deleted[i]);
    mesh.face_attrs().swap_elements(face_values, f, i);
    for (std::size_t k = 0; k < 3; ++k) mesh.corner_attrs().swap_elements(corner_values, 3 * f + k, 3 * i + k);
  }
}

void MeshDelta::undo(SurfaceMesh& mesh) {
  swap_existing(mesh);
  for (HeldArray& a : added) a.array = detail::set_of(mesh, a.kind).take(a.name);
  tail = mesh.take_tail(v0, f0);
  for (HeldArray& r : removed) detail::set_of(mesh, r.kind).put(r.name, std::move(r.array));
}

void MeshDelta::redo(SurfaceMesh& mesh) {
  for (HeldArray& r : removed) r.array = detail::set_of(mesh, r.kind).take(r.name);
  if (tail) mesh.append_tail(*tail);
  tail.reset();
  for (HeldArray& a : added) detail::set_of(mesh, a.kind).put(a.name, std::move(a.array));
  swap_existing(mesh);
}

std::size_t MeshDelta::bytes() const {
  std::size_t out = sizeof(MeshDelta) + (vertices.capacity() + faces.capacity()) * sizeof(std::uint32_t) +
                    corners.capacity() * sizeof(Triangle) + deleted.capacity() + vertex_values.capacity_bytes() +
                    face_values.capacity_bytes() + corner_values.capacity_bytes();
  if (tail) out += tail->bytes();
  for (const HeldArray& a : added)
    if (a.array) out += a.array->capacity_bytes();
  for (const HeldArray& r : removed)
    if (r.array) out += r.array->capacity_bytes();
  return out;
}

namespace {

/// The slots of `rest` (increasing) below `n` that `rewritten` (increasing) does not hold.
std::vector<std::uint32_t> not_rewritten(const std::vector<std::uint32_t>& rest, std::size_t n,
                                         const std::vector<std::uint32_t>& rewritten) {
  std::vector<std::uint32_t> out;
  const auto below = std::lower_bound(rest.begin(), rest.end(), n);
  std::set_difference(rest.begin(), below, rewritten.begin(), rewritten.end(), std::back_inserter(out));
  out.shrink_to_fit();  // a record holds no spare room
  return out;
}

}  // namespace

void SplitPart::take_rest(const SurfaceMesh& mesh, const MeshDelta& at_split) {
  for (int kind = 0; kind < 3; ++kind) names[static_cast<std::size_t>(kind)] = detail::set_of(mesh, kind).names();
  rest_vertices = not_rewritten(vertices.list(pieces()), at_split.v0, at_split.vertices);
  rest_faces = not_rewritten(faces.list(pieces()), at_split.f0, at_split.faces);
  std::vector<std::uint32_t> corners;
  corners.reserve(3 * rest_faces.size());
  rest_corners.reserve(rest_faces.size());
  rest_deleted.reserve(rest_faces.size());
  for (std::uint32_t f : rest_faces) {
    for (std::uint32_t k = 0; k < 3; ++k) corners.push_back(3 * f + k);
    rest_corners.push_back(mesh.face(FaceId(f)));
    rest_deleted.push_back(mesh.is_deleted(FaceId(f)) ? 1 : 0);
  }
  rest_values[0] = mesh.vertex_attrs().subset(rest_vertices);
  rest_values[1] = mesh.face_attrs().subset(rest_faces);
  rest_values[2] = mesh.corner_attrs().subset(corners);
}

bool SplitPart::holds(std::size_t k, const SurfaceMesh& piece) const {
  if (piece.vertex_count() != vertices.size(k) || piece.face_slots() != faces.size(k)) return false;
  for (int kind = 0; kind < 3; ++kind)
    if (detail::set_of(piece, kind).names() != names[static_cast<std::size_t>(kind)]) return false;
  return true;
}

bool SplitPart::covers(std::size_t k, const SurfaceMesh& piece) const {
  if (piece.vertex_count() < vertices.size(k) || piece.face_slots() < faces.size(k)) return false;
  for (int kind = 0; kind < 3; ++kind) {
    const auto i = static_cast<std::size_t>(kind);
    for (const std::string& name : names[i]) {
      const AttributeArrayBase* array = detail::set_of(piece, kind).base(name);
      if (!array || array->type() != rest_values[i].base(name)->type()) return false;
    }
  }
  return true;
}

std::vector<detail::Room> rooms_to_grow(const SplitPart& part, const std::vector<const SurfaceMesh*>& pieces,
                                        const SplitPart::Lists& lists) {
  const auto &vl = lists.vertices, &fl = lists.faces;
  auto room_of = [](const SurfaceMesh& p, std::size_t vertices, std::size_t faces) {
    return detail::Room{
        {&p.vertex_attrs(), &p.face_attrs(), &p.corner_attrs()}, p.faces().data(), vertices, faces};
  };
  std::vector<detail::Room> out;  // the other pieces and the rest, whose elements come in
  for (std::size_t k = 0; k < pieces.size(); ++k)
    if (k != part.big) out.push_back(room_of(*pieces[k], vl[k].size(), fl[k].size()));
  out.push_back({{&part.rest_values[0], &part.rest_values[1], &part.rest_values[2]},
                 part.rest_corners.data(),
                 part.rest_vertices.size(),
                 part.rest_faces.size()});
  // The slots take_rest left out need room too: rooms that do not add up to the growth leave
  // every array to grow by a slow fill of default values. Copies of the other pieces' first
  // elements make it up, vertices and faces apart, from as many pieces as it takes; they are
  // written over or left unspecified.
  std::size_t missing_v = vl.back().size() - part.rest_vertices.size();
  std::size_t missing_f = fl.back().size() - part.rest_faces.size();
  for (std::size_t k = 0; k < pieces.size() && missing_v + missing_f > 0; ++k) {
    const std::size_t v = std::min(missing_v, vl[k].size()), f = std::min(missing_f, fl[k].size());
    if (k == part.big || v + f == 0) continue;
    out.push_back(room_of(*pieces[k], v, f));
    missing_v -= v;
    missing_f -= f;
  }
  return out;
}

SplitPart::Lists SplitPart::lists() const { return {vertices.lists(), faces.lists()}; }

SplitPart::Lists SplitPart::big_lists() const {
  Lists out;
  out.vertices.resize(pieces() + 1);
  out.faces.resize(pieces() + 1);
  out.vertices[big] = vertices.list(big);
  out.faces[big] = faces.list(big);
  return out;
}

SurfaceMesh SplitPart::grow(SurfaceMesh&& big_piece, const std::vector<const SurfaceMesh*>& pieces,
                            const Lists& lists) const {
  const auto &vl = lists.vertices, &fl = lists.faces;  // the rest last
  SurfaceMesh out = std::move(big_piece);
  detail::expand_piece(out, vl[big], fl[big], vertices.count(), faces.count(),
                       rooms_to_grow(*this, pieces, lists));
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    if (k == big) continue;
    const SurfaceMesh& p = *pieces[k];
    detail::scatter(
        out,
        {{&p.vertex_attrs(), &p.face_attrs(), &p.corner_attrs()}, p.faces().data(), &vl[k], p.faces().size()},
        vl[k], fl[k]);
  }
  detail::scatter(out,
                  {{&rest_values[0], &rest_values[1], &rest_values[2]}, rest_corners.data(), nullptr,
                   rest_corners.size()},
                  rest_vertices, rest_faces);
  for (std::size_t j = 0; j < rest_faces.size(); ++j)
    if (rest_deleted[j]) {
      Triangle t = rest_corners[j];
      std::uint8_t mark = 1;
      out.swap_face(FaceId(rest_faces[j]), t, mark);
    }
  return out;
}

SurfaceMesh SplitPart::shrink(SurfaceMesh&& whole, const Lists& lists) const {
  const std::vector<std::uint32_t>&kept = lists.vertices[big], &kept_faces = lists.faces[big];
  detail::UninitVector<std::uint32_t> rank(vertices.count());  // read for the piece's vertices only
  parallel_for(kept.size(), detail::kIndexGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) rank[kept[i]] = static_cast<std::uint32_t>(i);
  });
  // Planned on `whole` before it changes (a move keeps its arrays where they are): a failure to
  // allocate leaves it whole.
  const detail::MovePlan plan = detail::plan_compaction(whole, kept, kept_faces);
  SurfaceMesh out = std::move(whole);
  detail::compact_piece(out, plan, kept, kept_faces, rank.data());
  return out;
}

std::size_t SplitPart::bytes() const {
  std::size_t out = sizeof(SplitPart) + vertices.bytes() + faces.bytes() +
                    (rest_vertices.capacity() + rest_faces.capacity()) * sizeof(std::uint32_t) +
                    rest_corners.capacity() * sizeof(Triangle) + rest_deleted.capacity() +
                    fresh.capacity() * sizeof(std::size_t);
  for (const AttributeSet& set : rest_values) out += set.capacity_bytes();
  return out;
}

Model shell_of(const Model& model) {
  Model shell;
  shell.nodes = model.nodes;
  shell.scenes = model.scenes;
  shell.default_scene = model.default_scene;
  shell.skins = model.skins;
  shell.animations = model.animations;
  shell.meshes.reserve(model.meshes.size());
  for (const Mesh& m : model.meshes) {
    Mesh copy;
    copy.name = m.name;
    copy.extras_json = m.extras_json;
    copy.weights = m.weights;
    copy.target_names = m.target_names;
    copy.primitives.reserve(m.primitives.size());
    for (const Primitive& p : m.primitives) {
      Primitive q;
      q.material = p.material;
      q.extras_json = p.extras_json;
      q.gltf_vertices = p.gltf_vertices;
      q.welded_merged = p.welded_merged;
      q.mesh.assign({}, p.mesh.vertex_attrs().subset({}), p.mesh.face_attrs().subset({}),
                    p.mesh.corner_attrs().subset({}));
      copy.primitives.push_back(std::move(q));
    }
    shell.meshes.push_back(std::move(copy));
  }
  shell.materials = model.materials;
  shell.textures = model.textures;
  shell.samplers = model.samplers;
  shell.cameras = model.cameras;
  shell.extensions_used = model.extensions_used;
  shell.extensions_required = model.extensions_required;
  shell.extras_json = model.extras_json;
  shell.extensions_json = model.extensions_json;
  shell.asset_copyright = model.asset_copyright;
  shell.asset_extras_json = model.asset_extras_json;
  shell.import_problems = model.import_problems;
  return shell;
}

void restore_shell(Model& model, Model shell) {
  std::vector<Image> images = std::move(model.images);
  model = std::move(shell);
  model.images = std::move(images);
}

namespace {

// The parts of a kept shell shared whole, as indices of KeptShell::slices_ (the nodes and
// meshes are shared one by one).
constexpr std::size_t kAnimations = 0, kRest = 1, kSlices = 2;

std::size_t node_bytes(const Node& n) {
  return sizeof(Node) + n.name.capacity() + n.children.capacity() * sizeof(int) +
         n.weights.capacity() * sizeof(float) + n.extras_json.capacity() + n.extensions_json.capacity();
}

std::size_t mesh_bytes(const Mesh& m) {
  std::size_t out =
      sizeof(Mesh) + m.extras_json.capacity() + m.name.capacity() + m.weights.capacity() * sizeof(float);
  for (const Primitive& p : m.primitives)
    out += sizeof(Primitive) + p.extras_json.capacity() + p.mesh.capacity_bytes();
  return out;
}

/// `bytes` over the holders of `p`: a holder's share.
template <class T>
std::size_t share_of(const std::shared_ptr<const T>& p, std::size_t bytes) {
  return bytes / static_cast<std::size_t>(std::max<long>(p.use_count(), 1));
}

/// Each element of `from`, shared with the element at its index in `like` (nullptr: none)
/// where equal, else kept anew.
template <class T>
std::vector<std::shared_ptr<const T>> share_elements(std::vector<T>&& from,
                                                     const std::vector<std::shared_ptr<const T>>* like) {
  std::vector<std::shared_ptr<const T>> out;
  out.reserve(from.size());
  for (std::size_t i = 0; i < from.size(); ++i) {
    if (like && i < like->size() && detail::same_part(*(*like)[i], from[i])) {
      out.push_back((*like)[i]);
    } else {
      out.push_back(std::make_shared<const T>(std::move(from[i])));
    }
  }
  return out;
}

}  // namespace

KeptShell::KeptShell(Model shell, const KeptShell* like) {
  shell.extras_json = std::string();
  for (Mesh& m : shell.meshes)
    for (Primitive& p : m.primitives) p.mesh = SurfaceMesh();
  nodes_ = share_elements(std::move(shell.nodes), like ? &like->nodes_ : nullptr);
  meshes_ = share_elements(std::move(shell.meshes), like ? &like->meshes_ : nullptr);
  std::array<Model, kSlices> slices;
  slices[kAnimations].animations = std::move(shell.animations);
  shell.nodes.clear();
  shell.meshes.clear();
  shell.animations.clear();
  slices[kRest] = std::move(shell);
  for (std::size_t k = 0; k < kSlices; ++k) {
    const std::shared_ptr<const Model>* before = like ? &like->slices_[k] : nullptr;
    if (before && *before && same_structure(**before, slices[k], false)) {
      slices_[k] = *before;
    } else {
      slices_[k] = std::make_shared<const Model>(std::move(slices[k]));
    }
  }
}

Model KeptShell::model() const {
  Model out = *slices_[kRest];
  out.animations = slices_[kAnimations]->animations;
  out.nodes.reserve(nodes_.size());
  for (const auto& n : nodes_) out.nodes.push_back(*n);
  out.meshes.reserve(meshes_.size());
  for (const auto& m : meshes_) out.meshes.push_back(*m);
  return out;
}

std::size_t KeptShell::bytes() const {
  std::size_t out = (nodes_.capacity() + meshes_.capacity()) * sizeof(std::shared_ptr<const Node>);
  for (const auto& slice : slices_)
    if (slice) out += share_of(slice, shell_bytes(*slice));
  for (const auto& n : nodes_) out += share_of(n, node_bytes(*n));
  for (const auto& m : meshes_) out += share_of(m, mesh_bytes(*m));
  return out;
}

std::size_t shell_bytes(const Model& shell) {
  std::size_t out = sizeof(Model) + shell.extras_json.capacity();
  for (const Node& n : shell.nodes) out += node_bytes(n);
  for (const Skin& s : shell.skins)
    out += sizeof(Skin) + s.joints.capacity() * sizeof(int) + s.inverse_bind_matrices.capacity() * sizeof(glm::mat4);
  for (const Animation& a : shell.animations) {
    out += sizeof(Animation) + a.channels.capacity() * sizeof(AnimationChannel);
    for (const AnimationSampler& s : a.samplers)
      out += sizeof(AnimationSampler) + (s.input.capacity() + s.output.capacity()) * sizeof(float);
  }
  for (const Mesh& m : shell.meshes) out += mesh_bytes(m);
  for (const auto* list : {&shell.materials, &shell.textures, &shell.samplers, &shell.cameras})
    for (const PassthroughObject& o : *list) out += sizeof(PassthroughObject) + o.name.capacity() + o.json.capacity();
  return out;
}

TextDelta TextDelta::make(const std::string& before, const std::string& after) {
  TextDelta d;
  const std::size_t n = std::min(before.size(), after.size());
  while (d.head < n && before[d.head] == after[d.head]) ++d.head;
  while (d.tail < n - d.head && before[before.size() - 1 - d.tail] == after[after.size() - 1 - d.tail]) ++d.tail;
  d.before = before.substr(d.head, before.size() - d.head - d.tail);
  d.after = after.substr(d.head, after.size() - d.head - d.tail);
  return d;
}

void TextDelta::undo(std::string& text) const { text.replace(head, after.size(), before); }

void TextDelta::redo(std::string& text) const { text.replace(head, before.size(), after); }

}  // namespace deepcut::undo
