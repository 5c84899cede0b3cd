// SPDX-License-Identifier: MIT
// The parts of an undo record: one primitive's in-place edit, the model's small parts, the text
// of the root extras that changed.
#include "model_undo_parts.h"

#include <algorithm>

#include "deepcut/core/parallel.h"
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

/// Indices per task of `unlisted`: small, so that most hold only listed indices and are skipped.
constexpr std::size_t kRestGrain = 4096;

/// The indices below `count` that no list holds, increasing. The lists are increasing and
/// disjoint (the pieces of a split): a stretch of indices whose parts of the lists (found by
/// bisection) add up to its length holds none and is skipped; only the others are walked. The
/// rest of a split is small (deleted faces, unused vertices), so this is about O(rest) over the
/// pool, stretches joined in order (the same list whatever the threads).
std::vector<std::uint32_t> unlisted(const std::vector<std::vector<std::uint32_t>>& lists, std::size_t count) {
  const std::size_t stretches = (count + kRestGrain - 1) / kRestGrain;
  std::vector<std::vector<std::uint32_t>> parts(stretches);
  parallel_for(stretches, 16, [&](std::size_t first, std::size_t last) {
    std::vector<std::pair<const std::uint32_t*, const std::uint32_t*>> held(lists.size());
    for (std::size_t r = first; r < last; ++r) {
      const std::size_t b = r * kRestGrain, e = std::min(count, b + kRestGrain);
      std::size_t listed = 0;
      for (std::size_t s = 0; s < lists.size(); ++s) {
        const std::uint32_t* const end = lists[s].data() + lists[s].size();
        const std::uint32_t* const lo = std::lower_bound(lists[s].data(), end, b);
        held[s] = {lo, std::lower_bound(lo, end, e)};
        listed += static_cast<std::size_t>(held[s].second - lo);
      }
      if (listed == e - b) continue;
      for (std::size_t i = b; i < e; ++i) {
        bool in_list = false;
        for (auto& [next, stop] : held)
          if (next != stop && *next == i) {
            ++next;
            in_list = true;
          }
        if (!in_list) parts[r].push_back(static_cast<std::uint32_t>(i));
      }
    }
  });
  std::vector<std::uint32_t> out;
  for (const auto& part : parts) out.insert(out.end(), part.begin(), part.end());
  return out;
}

}  // namespace

void SplitPart::take_rest(const SurfaceMesh& mesh) {
  vertex_count = mesh.vertex_count();
  face_count = mesh.face_slots();
  for (int kind = 0; kind < 3; ++kind) names[static_cast<std::size_t>(kind)] = detail::set_of(mesh, kind).names();
  rest_vertices = unlisted(vertices, vertex_count);
  rest_faces = unlisted(faces, face_count);
  std::vector<std::uint32_t> corners;
  corners.reserve(3 * rest_faces.size());
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
  if (piece.vertex_count() != vertices[k].size() || piece.face_slots() != faces[k].size()) return false;
  for (int kind = 0; kind < 3; ++kind)
    if (detail::set_of(piece, kind).names() != names[static_cast<std::size_t>(kind)]) return false;
  return true;
}

bool SplitPart::covers(std::size_t k, const SurfaceMesh& piece) const {
  if (piece.vertex_count() < vertices[k].size() || piece.face_slots() < faces[k].size()) return false;
  for (int kind = 0; kind < 3; ++kind) {
    const auto i = static_cast<std::size_t>(kind);
    for (const std::string& name : names[i]) {
      const AttributeArrayBase* array = detail::set_of(piece, kind).base(name);
      if (!array || array->type() != rest_values[i].base(name)->type()) return false;
    }
  }
  return true;
}

SurfaceMesh SplitPart::grow(SurfaceMesh&& big_piece, const std::vector<const SurfaceMesh*>& pieces) const {
  SurfaceMesh out = std::move(big_piece);
  std::vector<detail::Room> rooms;  // the other pieces and the rest, whose elements come in
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    if (k == big) continue;
    const SurfaceMesh& p = *pieces[k];
    rooms.push_back({{&p.vertex_attrs(), &p.face_attrs(), &p.corner_attrs()}, p.faces().data(), vertices[k].size(),
                     faces[k].size()});
  }
  rooms.push_back({{&rest_values[0], &rest_values[1], &rest_values[2]}, rest_corners.data(), rest_vertices.size(),
                   rest_faces.size()});
  detail::expand_piece(out, vertices[big], faces[big], vertex_count, face_count, rooms);
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    if (k == big) continue;
    const SurfaceMesh& p = *pieces[k];
    detail::scatter(out,
                    {{&p.vertex_attrs(), &p.face_attrs(), &p.corner_attrs()}, p.faces().data(), &vertices[k],
                     p.faces().size()},
                    vertices[k], faces[k]);
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

SurfaceMesh SplitPart::shrink(SurfaceMesh&& whole) const {
  const std::vector<std::uint32_t>& kept = vertices[big];
  detail::UninitVector<std::uint32_t> rank(vertex_count);  // read for the piece's vertices only
  parallel_for(kept.size(), detail::kIndexGrain, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) rank[kept[i]] = static_cast<std::uint32_t>(i);
  });
  // Planned on `whole` before it changes (a move keeps its arrays where they are): a failure to
  // allocate leaves it whole.
  const detail::MovePlan plan = detail::plan_compaction(whole, kept, faces[big]);
  SurfaceMesh out = std::move(whole);
  detail::compact_piece(out, plan, kept, faces[big], rank.data());
  return out;
}

std::size_t SplitPart::bytes() const {
  std::size_t out = sizeof(SplitPart) + (rest_vertices.capacity() + rest_faces.capacity()) * sizeof(std::uint32_t) +
                    rest_corners.capacity() * sizeof(Triangle) + rest_deleted.capacity() +
                    fresh.capacity() * sizeof(std::size_t);
  for (const auto& list : vertices) out += list.capacity() * sizeof(std::uint32_t);
  for (const auto& list : faces) out += list.capacity() * sizeof(std::uint32_t);
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

std::size_t shell_bytes(const Model& shell) {
  std::size_t out = sizeof(Model) + shell.extras_json.capacity();
  for (const Node& n : shell.nodes)
    out += sizeof(Node) + n.name.capacity() + n.children.capacity() * sizeof(int) + n.weights.capacity() * 4 +
           n.extras_json.capacity() + n.extensions_json.capacity();
  for (const Skin& s : shell.skins)
    out += sizeof(Skin) + s.joints.capacity() * sizeof(int) + s.inverse_bind_matrices.capacity() * sizeof(glm::mat4);
  for (const Animation& a : shell.animations) {
    out += sizeof(Animation) + a.channels.capacity() * sizeof(AnimationChannel);
    for (const AnimationSampler& s : a.samplers)
      out += sizeof(AnimationSampler) + (s.input.capacity() + s.output.capacity()) * sizeof(float);
  }
  for (const Mesh& m : shell.meshes) out += sizeof(Mesh) + m.extras_json.capacity() + m.primitives.size() * 512;
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
