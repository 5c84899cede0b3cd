// SPDX-License-Identifier: MIT
// Undo records of steps made on a model edited in place: the recorder that watches an operation
// and the step it makes (model_undo.h).
#include "deepcut/core/model_undo.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cstring>
#include <functional>
#include <optional>
#include <unordered_set>
#include <utility>

#include "deepcut/core/errors.h"
#include "deepcut/core/smallest_fit.h"
#include "model_undo_parts.h"
#include "ops/common/model_surgery.h"
#include "ops/common/model_surgery_in_place.h"

namespace deepcut {

using undo::HeldArray;
using undo::MeshDelta;
using undo::Place;
using undo::SplitPart;

namespace {

SurfaceMesh& mesh_at(Model& model, Place p) {
  return model.meshes[static_cast<std::size_t>(p.mesh)].primitives[static_cast<std::size_t>(p.primitive)].mesh;
}

/// True when element `i` of some array of `old` differs from element `j` of the same-named
/// array of `now` (`group` consecutive elements each: 3 for corners).
bool differs(const AttributeSet& old, std::size_t i, const AttributeSet& now, std::size_t j, std::size_t group = 1) {
  for (const std::string& name : old.names()) {
    const AttributeArrayBase* a = old.base(name);
    const AttributeArrayBase* b = now.base(name);
    if (!b) return true;
    if (std::memcmp(a->element_data(i * group), b->element_data(j * group), a->element_bytes() * group) != 0)
      return true;
  }
  return false;
}

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

/// A ModelChange entry for `delta` at `place`, with the sizes before undo (after the step) or
/// before redo (before the step).
PrimitiveChange change_of(const MeshDelta& delta, Place place, bool undoing) {
  PrimitiveChange c;
  c.mesh = place.mesh;
  c.primitive = place.primitive;
  c.vertices_before = undoing ? delta.v1 : delta.v0;
  c.faces_before = undoing ? delta.f1 : delta.f0;
  c.vertices.reserve(delta.vertices.size());  // a step keeps its change: no spare room
  c.faces.reserve(delta.faces.size());
  for (std::uint32_t v : delta.vertices) c.vertices.push_back(VertexId(v));
  for (std::uint32_t f : delta.faces) c.faces.push_back(FaceId(f));
  return c;
}

/// Bytes a change holds (capacity).
std::size_t change_bytes(const ModelChange& c) {
  std::size_t out = c.primitives.capacity() * sizeof(PrimitiveChange) +
                    c.kept.capacity() * sizeof(PrimitiveKept) +
                    (c.left.capacity() + c.arrived.capacity()) * sizeof(PrimitiveContent);
  for (const PrimitiveChange& p : c.primitives)
    out += p.vertices.capacity() * sizeof(VertexId) + p.faces.capacity() * sizeof(FaceId);
  return out;
}

}  // namespace

// --- the step ---------------------------------------------------------------------------------

struct ModelStep::Impl {
  struct Edited {
    std::uint32_t id = 0;
    Place before, after;  // `after` invalid: the step released the primitive
    MeshDelta delta;
    std::optional<SplitPart> split;  // the step split it in place: its pieces stand for it
  };
  bool whole = false;  // replace(): `other` is the model not current
  Model other;
  bool structure = false, exact = true;
  std::vector<Edited> edited;  // in the order of their places before
  undo::TextDelta extras;      // the root extras (the history)
  // Structure: every watched primitive's place before and after (invalid: released), the
  // released ones' content while done, the primitives the step made (places after) and their
  // content while undone, and the small parts before and after.
  std::vector<Place> before_all, after_all;
  std::vector<std::optional<SurfaceMesh>> kept;
  std::vector<Place> fresh;
  std::vector<SurfaceMesh> fresh_meshes;
  undo::KeptShell shell_before, shell_after;
  ModelChange change;       // what the step made (and what redo makes)
  ModelChange undo_change;  // what undo makes
  std::uint64_t serial = 0;  // names the step in content tags
  bool taken = false;        // take_meshes handed its meshes over: it can be neither undone nor redone

  /// Says in `change` and `undo_change` where the primitives' contents went (ModelChange::mapped).
  void map_structure();

  ModelChange local(Model& model, bool undoing);
  void undo_structure(Model& model);
  void redo_structure(Model& model);
};

ModelStep::ModelStep() : impl_(std::make_unique<Impl>()) {}
ModelStep::~ModelStep() = default;
ModelStep::ModelStep(ModelStep&&) noexcept = default;
ModelStep& ModelStep::operator=(ModelStep&&) noexcept = default;

ModelStep ModelStep::replace(Model& model, Model state) {
  ModelStep step;
  step.impl_->whole = true;
  step.impl_->structure = true;
  step.impl_->change.structure = true;
  step.impl_->other = std::move(model);
  model = std::move(state);
  return step;
}

const ModelChange& ModelStep::change() const { return impl_->change; }
bool ModelStep::exact() const { return impl_->exact; }

ModelChange ModelStep::Impl::local(Model& model, bool undoing) {
  ModelChange out;
  for (Edited& e : edited) {
    SurfaceMesh& mesh = mesh_at(model, e.before);
    if (undoing) {
      e.delta.undo(mesh);
    } else {
      e.delta.redo(mesh);
    }
    out.primitives.push_back(change_of(e.delta, e.before, undoing));
  }
  if (undoing) {
    extras.undo(model.extras_json);
  } else {
    extras.redo(model.extras_json);
  }
  return out;
}

void ModelStep::Impl::map_structure() {
  static std::atomic<std::uint64_t> steps{0};
  serial = ++steps;
  // Tags: the step, which state (0 before, 1 after, 2 made by the step) and the primitive.
  auto tag = [&](std::uint64_t state, std::size_t i) { return (serial << 24) | (state << 22) | i; };
  std::vector<char> changed(before_all.size(), 0);
  for (const Edited& e : edited) changed[e.id] = 1;
  ModelChange &made = change, &undone = undo_change;
  made.mapped = undone.mapped = true;
  undone.structure = true;
  for (std::size_t id = 0; id < before_all.size(); ++id) {
    const Place b = before_all[id], a = after_all[id];
    if (a.valid() && !changed[id]) {
      made.kept.push_back({a.mesh, a.primitive, b.mesh, b.primitive});
      undone.kept.push_back({b.mesh, b.primitive, a.mesh, a.primitive});
      continue;
    }
    made.left.push_back({b.mesh, b.primitive, tag(0, id)});
    undone.arrived.push_back({b.mesh, b.primitive, tag(0, id)});
    if (!a.valid()) continue;
    made.arrived.push_back({a.mesh, a.primitive, tag(1, id)});
    undone.left.push_back({a.mesh, a.primitive, tag(1, id)});
  }
  for (std::size_t k = 0; k < fresh.size(); ++k) {
    made.arrived.push_back({fresh[k].mesh, fresh[k].primitive, tag(2, k)});
    undone.left.push_back({fresh[k].mesh, fresh[k].primitive, tag(2, k)});
  }
}

// Undo and redo allocate what they need around the primitives (the shell's copy, the lists that
// hold the meshes, a split primitive's element lists) before a mesh leaves the model, so only a
// primitive's own edit can fail once one has (growing a split primitive back or compacting it
// again, which make its arrays, a delta).
void ModelStep::Impl::undo_structure(Model& model) {
  Model shell = shell_before.model();
  shell.extras_json = model.extras_json;
  extras.undo(shell.extras_json);
  std::vector<SplitPart::Lists> lists(edited.size());
  for (std::size_t i = 0; i < edited.size(); ++i)
    if (edited[i].split) lists[i] = edited[i].split->lists();
  std::vector<std::optional<SurfaceMesh>> held(before_all.size());
  fresh_meshes.reserve(fresh.size());
  for (std::size_t id = 0; id < held.size(); ++id) {
    if (after_all[id].valid()) {
      held[id].emplace(std::move(mesh_at(model, after_all[id])));
    } else if (kept[id]) {
      held[id] = std::move(kept[id]);
      kept[id].reset();
    }
  }
  for (Place p : fresh) fresh_meshes.push_back(std::move(mesh_at(model, p)));
  for (std::size_t i = 0; i < edited.size(); ++i) {
    Edited& e = edited[i];
    if (e.split) {
      const SplitPart& part = *e.split;
      std::vector<const SurfaceMesh*> pieces;
      for (std::size_t k : part.fresh) pieces.push_back(&fresh_meshes[k]);
      held[e.id].emplace(part.grow(std::move(fresh_meshes[part.fresh[part.big]]), pieces, lists[i]));
      lists[i] = {};  // freed before the next grows
    }
    if (held[e.id]) e.delta.undo(*held[e.id]);
  }
  undo::restore_shell(model, std::move(shell));
  for (std::size_t id = 0; id < held.size(); ++id)
    if (held[id]) mesh_at(model, before_all[id]) = std::move(*held[id]);
}

void ModelStep::Impl::redo_structure(Model& model) {
  Model shell = shell_after.model();
  shell.extras_json = model.extras_json;
  extras.redo(shell.extras_json);
  std::vector<SplitPart::Lists> lists(edited.size());
  for (std::size_t i = 0; i < edited.size(); ++i)
    if (edited[i].split) lists[i] = edited[i].split->big_lists();
  std::vector<std::optional<SurfaceMesh>> held(before_all.size());
  for (std::size_t id = 0; id < held.size(); ++id) held[id].emplace(std::move(mesh_at(model, before_all[id])));
  for (std::size_t i = 0; i < edited.size(); ++i) {
    Edited& e = edited[i];
    e.delta.redo(*held[e.id]);
    if (!e.split) continue;
    fresh_meshes[e.split->fresh[e.split->big]] = e.split->shrink(std::move(*held[e.id]), lists[i]);
    held[e.id].reset();
    lists[i] = {};
  }
  undo::restore_shell(model, std::move(shell));
  for (std::size_t id = 0; id < held.size(); ++id) {
    if (after_all[id].valid()) {
      mesh_at(model, after_all[id]) = std::move(*held[id]);
    } else {
      kept[id] = std::move(held[id]);
    }
  }
  for (std::size_t k = 0; k < fresh.size(); ++k) mesh_at(model, fresh[k]) = std::move(fresh_meshes[k]);
  fresh_meshes.clear();
}

namespace {
void check_not_taken(bool taken) {
  if (taken) throw Error(ErrorCode::InvariantViolated, "a step whose meshes were taken cannot be undone or redone");
}
}  // namespace

ModelChange ModelStep::undo(Model& model) {
  check_not_taken(impl_->taken);
  if (impl_->whole) {
    std::swap(model, impl_->other);
    return impl_->change;
  }
  if (!impl_->structure) return impl_->local(model, true);
  impl_->undo_structure(model);
  return impl_->undo_change;
}

ModelChange ModelStep::redo(Model& model) {
  check_not_taken(impl_->taken);
  if (impl_->whole) {
    std::swap(model, impl_->other);
    return impl_->change;
  }
  if (!impl_->structure) return impl_->local(model, false);
  impl_->redo_structure(model);
  return impl_->change;
}

std::size_t ModelStep::bytes() const {
  const Impl& s = *impl_;
  std::size_t out = sizeof(Impl) + s.extras.bytes() + change_bytes(s.change) + change_bytes(s.undo_change);
  if (s.whole) out += undo::shell_bytes(s.other);  // its primitives' meshes included
  for (const auto& e : s.edited) out += e.delta.bytes() + (e.split ? e.split->bytes() : 0);
  for (const auto& k : s.kept)
    if (k) out += k->capacity_bytes();
  for (const auto& m : s.fresh_meshes) out += m.capacity_bytes();
  if (s.structure && !s.whole) out += s.shell_before.bytes() + s.shell_after.bytes();
  out += (s.before_all.capacity() + s.after_all.capacity() + s.fresh.capacity()) * sizeof(Place);
  return out;
}

std::vector<SurfaceMesh> ModelStep::take_meshes() {
  Impl& s = *impl_;
  s.taken = true;  // the lists keep their sizes (no index into them can go out of range)
  std::vector<SurfaceMesh> out;
  for (SurfaceMesh& m : s.fresh_meshes) out.push_back(std::move(m));
  for (std::optional<SurfaceMesh>& k : s.kept)
    if (k) {
      out.push_back(std::move(*k));
      k.reset();
    }
  return out;
}

// --- the recorder -----------------------------------------------------------------------------

namespace {

/// What the recorder knows of one primitive it watches.
struct Watched {
  Place before;
  std::size_t v0 = 0, f0 = 0;
  std::array<std::vector<std::string>, 3> names;  // attribute names when the recording began
  std::unordered_set<std::uint32_t> seen_v, seen_f;
  std::vector<std::uint32_t> order_v, order_f;  // existing elements written, first write first
  std::array<AttributeSet, 3> old;              // their values before (start names; 3 per face for corners)
  std::vector<Triangle> old_corners;
  std::vector<std::uint8_t> old_deleted;
  std::vector<HeldArray> saved;  // attributes an operation may remove, as they were
  std::optional<SurfaceMesh> released;
  // Split in place (SplitWatcher): the edits up to the split, and what the pieces (watched as
  // pieces, see Piece) do not hold while they stand for the primitive. Put back together into
  // `released` once a piece changes; `lost` when a piece left for where the recorder cannot see.
  std::optional<MeshDelta> at_split;
  std::optional<SplitPart> split;
  std::vector<std::uint32_t> pieces;  // indices into ModelRecorder::Impl::pieces
  bool lost = false;
};

/// A piece of a primitive split in place, watched as kPiece | its index until it changes.
struct Piece {
  std::uint32_t owner = 0;  // the primitive split
  std::optional<SurfaceMesh> released;
};

constexpr std::uint32_t kPiece = 0x80000000u;

}  // namespace

struct ModelRecorder::Impl final : MeshObserver, detail::SplitWatcher {
  Model& model;
  Model shell;
  std::vector<Watched> watched;
  std::vector<Piece> pieces;
  std::vector<std::pair<const void*, std::size_t>> images;
  bool exact = true;
  // Memory lent for the pieces copied out (lend_spares): the source until first asked, then its
  // meshes' arrays and triangles not reused yet.
  std::function<std::vector<SurfaceMesh>()> spare_source;
  std::vector<std::unique_ptr<AttributeArrayBase>> spare_arrays;
  std::vector<std::vector<Triangle>> spare_tris;

  explicit Impl(Model& m);
  void unwatch_all();
  void vertex_writing(std::uint32_t id, const SurfaceMesh& mesh, VertexId v) override;
  void face_writing(std::uint32_t id, const SurfaceMesh& mesh, FaceId f) override;
  void released(std::uint32_t id, SurfaceMesh&& content) noexcept override;
  bool accepts(std::uint32_t id, const SurfaceMesh& mesh) const override;
  void splitting(std::uint32_t id, SurfaceMesh& mesh, const std::vector<std::vector<std::uint32_t>>& vertices,
                 const std::vector<std::vector<std::uint32_t>>& faces, std::size_t big) override;
  void split(std::uint32_t id, std::vector<SurfaceMesh>& made) override;
  std::unique_ptr<AttributeArrayBase> spare_array(const AttributeArrayBase& like, std::size_t elements,
                                                  std::size_t most) override;
  std::vector<Triangle> spare_triangles(std::size_t count, std::size_t most) override;
  void take_spares();
  /// Where each watched primitive is now (`after`; invalid: gone), the primitives the step made
  /// (`fresh`, the pieces standing for a split included) and each standing piece's index in
  /// `fresh`. The model is no longer watched after it.
  struct Placed {
    std::vector<Place> after, fresh;
    std::vector<std::size_t> piece_at;
  };
  Placed unwatch_placing();
  /// Each watched primitive's edit, handed to `keep(id, delta, split)` (`split`: its pieces stand
  /// for it); a primitive gone where the recorder cannot see makes the step inexact.
  template <class Keep>
  void collect_edits(const Placed& placed, Keep&& keep);
  std::vector<SurfaceMesh*> live_pieces();
  void put_together(Watched& w, const std::vector<SurfaceMesh*>& live);
  void piece_writing(std::uint32_t piece, std::uint32_t index, int kind);
  void settle_splits();
  /// One primitive's edit as the recording saw it (MeshDelta), with the saved attributes it
  /// takes (indices into Watched::saved) and whether undo gives the primitive back exactly.
  struct DeltaDraft {
    MeshDelta delta;
    std::vector<std::size_t> removed;
    bool lossless = true;
  };
  /// Made apart from `w` and `exact`, which change only once it is committed: a failure (out of
  /// memory) leaves the recording as it was.
  static DeltaDraft draft_delta(const Watched& w, const SurfaceMesh& now);
  /// The draft's delta, taking the saved attributes it removed from `w`; allocates nothing.
  MeshDelta commit(Watched& w, DeltaDraft&& draft);
  static void keep_changed_vertices(const Watched& w, const std::array<AttributeSet, 3>& old, const SurfaceMesh& now,
                                    MeshDelta& d);
  static void keep_changed_faces(const Watched& w, const std::array<AttributeSet, 3>& old, const SurfaceMesh& now,
                                 MeshDelta& d);
};

ModelRecorder::Impl::Impl(Model& m) : model(m), shell(undo::shell_of(m)) {
  for (const Image& image : m.images) images.emplace_back(image.data.data(), image.data.size());
  for (std::size_t mi = 0; mi < m.meshes.size(); ++mi)
    for (std::size_t pi = 0; pi < m.meshes[mi].primitives.size(); ++pi) {
      SurfaceMesh& mesh = m.meshes[mi].primitives[pi].mesh;
      Watched w;
      w.before = {static_cast<int>(mi), static_cast<int>(pi)};
      w.v0 = mesh.vertex_count();
      w.f0 = mesh.face_slots();
      for (int kind = 0; kind < 3; ++kind) {
        w.names[static_cast<std::size_t>(kind)] = detail::set_of(mesh, kind).names();
        w.old[static_cast<std::size_t>(kind)] = detail::set_of(mesh, kind).subset({});
      }
      if (const AttributeArrayBase* flag = mesh.face_attrs().base(attr::kCutSurface))
        w.saved.push_back({1, attr::kCutSurface, flag->clone()});
      mesh.watch(this, static_cast<std::uint32_t>(watched.size()));
      watched.push_back(std::move(w));
    }
}

void ModelRecorder::Impl::unwatch_all() {
  for (Mesh& m : model.meshes)
    for (Primitive& p : m.primitives)
      if (p.mesh.observer() == this) p.mesh.watch(nullptr, 0);
}

void ModelRecorder::Impl::vertex_writing(std::uint32_t id, const SurfaceMesh& mesh, VertexId v) {
  if (id & kPiece) return piece_writing(id & ~kPiece, v.index, 0);
  Watched& w = watched[id];
  if (v.index >= w.v0 || !w.seen_v.insert(v.index).second) return;
  w.order_v.push_back(v.index);
  try {
    w.old[0].append_from(mesh.vertex_attrs(), v.index, v.index + 1);
  } catch (const Error&) {
    exact = false;  // an attribute it had is gone: the old value cannot be kept
  }
}

void ModelRecorder::Impl::face_writing(std::uint32_t id, const SurfaceMesh& mesh, FaceId f) {
  if (id & kPiece) return piece_writing(id & ~kPiece, f.index, 1);
  Watched& w = watched[id];
  if (f.index >= w.f0 || !w.seen_f.insert(f.index).second) return;
  w.order_f.push_back(f.index);
  w.old_corners.push_back(mesh.face(f));
  w.old_deleted.push_back(mesh.is_deleted(f) ? 1 : 0);
  try {
    w.old[1].append_from(mesh.face_attrs(), f.index, f.index + 1);
    w.old[2].append_from(mesh.corner_attrs(), 3 * std::size_t(f.index), 3 * std::size_t(f.index) + 3);
  } catch (const Error&) {
    exact = false;
  }
}

void ModelRecorder::Impl::released(std::uint32_t id, SurfaceMesh&& content) noexcept {
  if (id & kPiece) {
    pieces[id & ~kPiece].released.emplace(std::move(content));
  } else {
    watched[id].released.emplace(std::move(content));
  }
}

bool ModelRecorder::Impl::accepts(std::uint32_t id, const SurfaceMesh& mesh) const {
  // Once per primitive and recording, and never a mesh with cut-surface flags: its pieces lose
  // them right after (cut_model), so they would not stand for it.
  return !(id & kPiece) && !watched[id].at_split && !mesh.face_attrs().base(attr::kCutSurface);
}

void ModelRecorder::Impl::splitting(std::uint32_t id, SurfaceMesh& mesh,
                                    const std::vector<std::vector<std::uint32_t>>& vertices,
                                    const std::vector<std::vector<std::uint32_t>>& faces, std::size_t big) {
  Watched& w = watched[id];
  // split() then allocates nothing; the recording changes only once the delta is committed (which
  // allocates nothing), so a failure up to there leaves the mesh whole and watched as before.
  DeltaDraft at_split = draft_delta(w, mesh);
  SplitPart part;
  part.vertices = undo::PieceLabels(vertices, mesh.vertex_count());
  part.faces = undo::PieceLabels(faces, mesh.face_slots());
  part.big = big;
  part.take_rest(mesh, at_split.delta);
  w.pieces.reserve(vertices.size());
  pieces.reserve(pieces.size() + vertices.size());
  w.at_split.emplace(commit(w, std::move(at_split)));
  w.split.emplace(std::move(part));
  mesh.watch(nullptr, 0);
}

void ModelRecorder::Impl::split(std::uint32_t id, std::vector<SurfaceMesh>& made) {
  Watched& w = watched[id];
  for (std::size_t k = 0; k < made.size(); ++k) {
    w.pieces.push_back(static_cast<std::uint32_t>(pieces.size()));
    made[k].watch(this, kPiece | static_cast<std::uint32_t>(pieces.size()));
    pieces.push_back({id, std::nullopt});
  }
}

void ModelRecorder::Impl::take_spares() {
  if (!spare_source) return;
  std::vector<SurfaceMesh> meshes = spare_source();
  spare_source = nullptr;
  for (SurfaceMesh& mesh : meshes) {
    for (int kind = 0; kind < 3; ++kind)
      for (const std::string& name : detail::set_of(mesh, kind).names())
        spare_arrays.push_back(detail::set_of(mesh, kind).take(name));
    spare_tris.push_back(std::move(detail::TrustedAssign::faces(mesh)));
  }
}

std::unique_ptr<AttributeArrayBase> ModelRecorder::Impl::spare_array(const AttributeArrayBase& like,
                                                                     std::size_t elements, std::size_t most) {
  take_spares();
  return take_smallest_fit(spare_arrays, elements, most, [&](const std::unique_ptr<AttributeArrayBase>& a) {
    return a->type() == like.type() ? a->capacity_bytes() / a->element_bytes() : 0;
  });
}

std::vector<Triangle> ModelRecorder::Impl::spare_triangles(std::size_t count, std::size_t most) {
  take_spares();
  std::vector<Triangle> out =
      take_smallest_fit(spare_tris, count, most, [](const std::vector<Triangle>& t) { return t.capacity(); });
  out.clear();
  return out;
}

std::vector<SurfaceMesh*> ModelRecorder::Impl::live_pieces() {
  // The pieces in the model now, by index (nullptr: not there), from one pass over the model.
  std::vector<SurfaceMesh*> out(pieces.size(), nullptr);
  for (Mesh& m : model.meshes)
    for (Primitive& p : m.primitives)
      if (p.mesh.observer() == this && (p.mesh.observer_id() & kPiece)) out[p.mesh.observer_id() & ~kPiece] = &p.mesh;
  return out;
}

void ModelRecorder::Impl::put_together(Watched& w, const std::vector<SurfaceMesh*>& live_now) {
  if (!w.split) return;
  const SplitPart& part = *w.split;
  std::vector<const SurfaceMesh*> found(w.pieces.size(), nullptr);
  w.lost = w.lost || w.pieces.size() != part.pieces();  // the split never finished
  for (std::size_t k = 0; k < w.pieces.size(); ++k) {
    Piece& piece = pieces[w.pieces[k]];
    SurfaceMesh* live = piece.released ? nullptr : live_now[w.pieces[k]];
    if (live) live->watch(nullptr, 0);  // an ordinary primitive the step made from now on
    found[k] = piece.released ? &*piece.released : live;
    // A piece that shrank or lost an attribute of the split no longer holds its elements.
    w.lost = w.lost || !found[k] || !part.covers(k, *found[k]);
  }
  if (!w.lost) {
    try {
      const SplitPart::Lists lists = part.lists();  // before the piece that keeps the arrays moves
      // The pieces' elements past the split's (appended since) and attributes added since are
      // not the primitive's.
      // The piece that keeps the arrays, moved when the recorder holds it (released), else copied.
      std::optional<SurfaceMesh>& released = pieces[w.pieces[part.big]].released;
      SurfaceMesh whole = released ? std::move(*released) : *found[part.big];
      whole.take_tail(part.vertices.size(part.big), part.faces.size(part.big));
      for (int kind = 0; kind < 3; ++kind)
        for (const std::string& name : detail::set_of(whole, kind).names())
          if (!contains(part.names[static_cast<std::size_t>(kind)], name)) detail::set_of(whole, kind).remove(name);
      w.released.emplace(part.grow(std::move(whole), found, lists));
    } catch (const Error&) {
      w.lost = true;
    }
  }
  for (std::uint32_t i : w.pieces) pieces[i].released.reset();
  w.split.reset();
}

void ModelRecorder::Impl::piece_writing(std::uint32_t piece, std::uint32_t index, int kind) {
  // An element the piece appended since the split is not the primitive's (put_together cuts it
  // off), so writing it leaves the split standing, as writes past v0 / f0 are ignored unsplit.
  Watched& w = watched[pieces[piece].owner];
  if (!w.split) return;
  const auto at = std::find(w.pieces.begin(), w.pieces.end(), piece);
  if (at != w.pieces.end()) {
    const auto k = static_cast<std::size_t>(at - w.pieces.begin());
    if (index >= (kind == 0 ? w.split->vertices : w.split->faces).size(k)) return;
  }
  put_together(w, live_pieces());
}

void ModelRecorder::Impl::settle_splits() {
  // A split whose pieces are not all in the model as the split made them is put back together
  // now: its pieces are then primitives the step made, like any other.
  const std::vector<SurfaceMesh*> live = live_pieces();  // putting a split together moves no mesh
  for (Watched& w : watched) {
    if (!w.split) continue;
    bool standing = w.pieces.size() == w.split->pieces();
    for (std::size_t k = 0; k < w.pieces.size() && standing; ++k) {
      const SurfaceMesh* piece = pieces[w.pieces[k]].released ? nullptr : live[w.pieces[k]];
      standing = piece && w.split->holds(k, *piece);
    }
    if (!standing) put_together(w, live);
  }
}

void ModelRecorder::Impl::keep_changed_vertices(const Watched& w, const std::array<AttributeSet, 3>& old,
                                                const SurfaceMesh& now, MeshDelta& d) {
  std::vector<std::uint32_t> keep;  // indices into order_v
  for (std::uint32_t i = 0; i < w.order_v.size(); ++i)
    if (differs(old[0], i, now.vertex_attrs(), w.order_v[i])) keep.push_back(i);
  std::sort(keep.begin(), keep.end(), [&](std::uint32_t a, std::uint32_t b) { return w.order_v[a] < w.order_v[b]; });
  d.vertices.reserve(keep.size());  // a record holds no spare room
  for (std::uint32_t i : keep) d.vertices.push_back(w.order_v[i]);
  d.vertex_values = old[0].subset(keep);
}

void ModelRecorder::Impl::keep_changed_faces(const Watched& w, const std::array<AttributeSet, 3>& old,
                                             const SurfaceMesh& now, MeshDelta& d) {
  std::vector<std::uint32_t> keep, keep3;
  for (std::uint32_t i = 0; i < w.order_f.size(); ++i) {
    const FaceId f(w.order_f[i]);
    if (w.old_corners[i] != now.face(f) || (w.old_deleted[i] != 0) != now.is_deleted(f) ||
        differs(old[1], i, now.face_attrs(), f.index) || differs(old[2], i, now.corner_attrs(), f.index, 3))
      keep.push_back(i);
  }
  std::sort(keep.begin(), keep.end(), [&](std::uint32_t a, std::uint32_t b) { return w.order_f[a] < w.order_f[b]; });
  d.faces.reserve(keep.size());  // a record holds no spare room
  d.corners.reserve(keep.size());
  d.deleted.reserve(keep.size());
  keep3.reserve(3 * keep.size());
  for (std::uint32_t i : keep) {
    d.faces.push_back(w.order_f[i]);
    d.corners.push_back(w.old_corners[i]);
    d.deleted.push_back(w.old_deleted[i]);
    for (std::uint32_t k = 0; k < 3; ++k) keep3.push_back(3 * i + k);
  }
  d.face_values = old[1].subset(keep);
  d.corner_values = old[2].subset(keep3);
}

ModelRecorder::Impl::DeltaDraft ModelRecorder::Impl::draft_delta(const Watched& w, const SurfaceMesh& now) {
  DeltaDraft out;
  MeshDelta& d = out.delta;
  d.v0 = w.v0;
  d.f0 = w.f0;
  d.v1 = now.vertex_count();
  d.f1 = now.face_slots();
  out.lossless = d.v1 >= d.v0 && d.f1 >= d.f0;  // shrunk in place: not an edit this records
  const std::array<AttributeSet, 3>* old = &w.old;
  std::array<AttributeSet, 3> trimmed;  // the old values of the attributes both states have
  for (int kind = 0; kind < 3; ++kind) {
    const auto k = static_cast<std::size_t>(kind);
    const std::vector<std::string> names = detail::set_of(now, kind).names();
    for (const std::string& n : names)
      if (!contains(w.names[k], n)) d.added.push_back({kind, n, nullptr});
    for (const std::string& n : w.names[k]) {
      if (contains(names, n)) continue;
      if (old == &w.old) old = &(trimmed = w.old);
      trimmed[k].take(n);
      auto saved = std::find_if(w.saved.begin(), w.saved.end(),
                                [&](const HeldArray& h) { return h.kind == kind && h.name == n; });
      if (saved == w.saved.end())
        out.lossless = false;
      else
        out.removed.push_back(static_cast<std::size_t>(saved - w.saved.begin()));
    }
  }
  keep_changed_vertices(w, *old, now, d);
  keep_changed_faces(w, *old, now, d);
  d.removed.reserve(out.removed.size());
  return out;
}

MeshDelta ModelRecorder::Impl::commit(Watched& w, DeltaDraft&& draft) {
  // Nothing here allocates: the removed attributes leave what the recording saved.
  MeshDelta d = std::move(draft.delta);
  std::vector<std::size_t>& removed = draft.removed;
  for (std::size_t i : removed) d.removed.push_back(std::move(w.saved[i]));
  std::sort(removed.begin(), removed.end(), std::greater<>());
  for (std::size_t i : removed) w.saved.erase(w.saved.begin() + static_cast<std::ptrdiff_t>(i));
  exact = exact && draft.lossless;
  return d;
}

ModelRecorder::ModelRecorder(Model& model) : impl_(std::make_unique<Impl>(model)) {}

ModelRecorder::~ModelRecorder() {
  if (impl_) impl_->unwatch_all();
}

void ModelRecorder::lend_spares(std::function<std::vector<SurfaceMesh>()> source) {
  impl_->spare_source = std::move(source);
}

ModelRecorder::Impl::Placed ModelRecorder::Impl::unwatch_placing() {
  Placed out;
  out.after.resize(watched.size());
  out.piece_at.assign(pieces.size(), 0);
  for (std::size_t mi = 0; mi < model.meshes.size(); ++mi)
    for (std::size_t pi = 0; pi < model.meshes[mi].primitives.size(); ++pi) {
      SurfaceMesh& mesh = model.meshes[mi].primitives[pi].mesh;
      const Place place{static_cast<int>(mi), static_cast<int>(pi)};
      const bool mine = mesh.observer() == this;
      if (mine && !(mesh.observer_id() & kPiece)) {
        out.after[mesh.observer_id()] = place;
      } else {
        if (mine) out.piece_at[mesh.observer_id() & ~kPiece] = out.fresh.size();
        out.fresh.push_back(place);
      }
      if (mine) mesh.watch(nullptr, 0);
    }
  return out;
}

template <class Keep>
void ModelRecorder::Impl::collect_edits(const Placed& placed, Keep&& keep) {
  for (std::uint32_t id = 0; id < watched.size(); ++id) {
    Watched& w = watched[id];
    const Place after = placed.after[id];
    if (w.split) {  // its pieces stand for it (settle_splits)
      SplitPart part = std::move(*w.split);
      for (std::uint32_t i : w.pieces) part.fresh.push_back(placed.piece_at[i]);
      keep(id, std::move(*w.at_split), std::optional<SplitPart>(std::move(part)));
      continue;
    }
    SurfaceMesh* now = after.valid() ? &mesh_at(model, after) : w.released ? &*w.released : nullptr;
    if (!now || w.lost) {
      exact = false;  // it left the model for somewhere the recorder cannot see
      continue;
    }
    MeshDelta d = w.at_split ? std::move(*w.at_split) : commit(w, draft_delta(w, *now));
    if (!d.empty()) keep(id, std::move(d), std::optional<SplitPart>());
  }
}

ModelStep ModelRecorder::finish(const ModelStep* last) {
  Impl& r = *impl_;
  r.settle_splits();
  ModelStep step;
  ModelStep::Impl& s = *step.impl_;
  const std::size_t n = r.watched.size();
  Impl::Placed placed = r.unwatch_placing();
  std::vector<Place>& after = placed.after;
  bool local = placed.fresh.empty();
  for (std::uint32_t id = 0; id < n; ++id) local = local && after[id] == r.watched[id].before;
  r.collect_edits(placed, [&](std::uint32_t id, MeshDelta&& d, std::optional<SplitPart>&& split) {
    s.edited.push_back({id, r.watched[id].before, after[id], std::move(d), std::move(split)});
  });
  std::vector<std::pair<const void*, std::size_t>> images;
  for (const Image& image : r.model.images) images.emplace_back(image.data.data(), image.data.size());
  if (images != r.images) r.exact = false;
  local = local && same_structure(r.shell, r.model, false);
  s.exact = r.exact;
  s.extras = undo::TextDelta::make(r.shell.extras_json, r.model.extras_json);
  if (local) {
    for (const auto& e : s.edited) s.change.primitives.push_back(change_of(e.delta, e.before, false));
    return step;
  }
  s.structure = true;
  s.change.structure = true;
  s.before_all.resize(n);
  s.kept.resize(n);
  for (std::uint32_t id = 0; id < n; ++id) {
    s.before_all[id] = r.watched[id].before;
    if (!after[id].valid()) s.kept[id] = std::move(r.watched[id].released);
  }
  s.after_all = std::move(after);
  s.fresh = std::move(placed.fresh);
  const ModelStep::Impl* l = last ? last->impl_.get() : nullptr;
  // The shell after of `last`, which the model's small parts are now but for this step's edits
  // (a replace() step keeps none).
  const undo::KeptShell* like = l && l->structure && !l->whole ? &l->shell_after : nullptr;
  s.shell_before = undo::KeptShell(std::move(r.shell), like);
  s.shell_after = undo::KeptShell(undo::shell_of(r.model), &s.shell_before);
  s.map_structure();
  return step;
}

}  // namespace deepcut
