// SPDX-License-Identifier: MIT
#pragma once
/// @file model_change.h
/// What one step (an operation, its undo or its redo) changed in a model, in a form that the
/// things drawn from the model (the studio's scene, its VTK arrays, the posed models) follow in
/// O(change) instead of rebuilding: per edited primitive, the sizes before the step and the
/// existing elements it rewrote. Elements past the old sizes are new (when the mesh grew) or gone
/// (when it shrank, as an undo does); everything not listed is unchanged, byte for byte.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "deepcut/core/types.h"

namespace deepcut {

struct Model;
class SurfaceMesh;

/// One primitive edited in place (mesh `mesh`, primitive `primitive`, at the same indices before
/// and after the step).
struct PrimitiveChange {
  int mesh = -1, primitive = -1;
  /// Vertex and face slot counts before the step (compare with the mesh's counts now).
  std::size_t vertices_before = 0, faces_before = 0;
  /// Existing vertices (index < min(vertices_before, vertex_count now)) whose position or other
  /// vertex attributes changed, each once, increasing.
  std::vector<VertexId> vertices;
  /// Existing face slots (index < min(faces_before, face_slots now)) whose corners, deleted mark,
  /// corner or face attributes changed, each once, increasing.
  std::vector<FaceId> faces;
};

/// A primitive's content (its mesh: element data and attributes) in a structural step: its place
/// and a tag naming that very content, byte for byte. Equal tags, equal content: a follower that
/// kept what it drew of a content when it left the model (tag of the state before a step) draws
/// it again when it comes back with the same tag (an undo or redo of that step restores it byte
/// for byte).
struct PrimitiveContent {
  int mesh = -1, primitive = -1;
  std::uint64_t tag = 0;
};

/// Where the content of an arrived primitive came from, element by element, when the step made it
/// out of a primitive before it (a cut's piece out of the primitive it cut): a follower that drew
/// the source instance copies what it drew of the elements listed here and computes only the
/// others (the rim), instead of everything. Instance (`node`, `mesh`, `primitive`) after the step
/// comes from instance (`node_before`, `mesh_before`, `primitive_before`) before it.
struct PrimitiveOrigin {
  int node = -1, mesh = -1, primitive = -1;
  int node_before = -1, mesh_before = -1, primitive_before = -1;
  /// Per vertex: the source vertex whose attributes it has, byte for byte (kInvalidIndex: a new
  /// or rewritten vertex).
  std::vector<std::uint32_t> vertices;
  /// Per face slot: the source face slot whose corners it has (each corner's vertex mapped by
  /// `vertices`, its corner attributes byte for byte), or kInvalidIndex.
  std::vector<std::uint32_t> faces;
};

/// A primitive whose content a structural step left as it was, perhaps at another place.
struct PrimitiveKept {
  int mesh = -1, primitive = -1;                ///< its place after the step
  int mesh_before = -1, primitive_before = -1;  ///< its place before
};

struct ModelChange {
  /// Anything beyond in-place primitive edits changed: nodes, meshes or primitives were added,
  /// removed or replaced (a cut makes piece nodes; a drill's wall adds a primitive), or the step
  /// cannot say what it changed. Followers rebuild; `primitives` is then not meaningful.
  bool structure = false;
  /// The primitives edited in place (none when nothing changed), in (mesh, primitive) order.
  std::vector<PrimitiveChange> primitives;
  /// A structural step that says what became of the primitives (`mapped`): every primitive after
  /// the step is either `kept` (its content unchanged) or `arrived` (a content new to the model,
  /// tagged); every primitive before it whose content is not kept `left` (tagged). The nodes and
  /// the other small parts may have changed in any way (followers compare what they use of them).
  /// Not mapped: followers rebuild everything.
  bool mapped = false;
  std::vector<PrimitiveKept> kept;
  std::vector<PrimitiveContent> left, arrived;
  /// Of the arrived primitives, where those made out of a primitive before the step came from
  /// (the step that made them, not its undo or redo: those bring back content a follower kept).
  std::vector<std::shared_ptr<const PrimitiveOrigin>> origins;
  bool empty() const { return !structure && primitives.empty(); }
};

/// What turning `before` into `after` changed, found by comparing them: the reference every
/// recorded change (operations, undo, redo) is checked against in tests. O(mesh).
/// `structure` is set when anything but the primitives' element data and the root `extras_json`
/// (where the operation history lives) differs: nodes, scenes, skins, animations, meshes and
/// their primitives (count, material, extras), materials, textures, images, samplers, cameras,
/// the root extensions and asset, or the names and types of a primitive's attributes. Otherwise
/// `primitives` lists, per primitive, the sizes before and the existing elements whose bytes
/// differ; the root `extras_json` is not reported (it is no part of what is drawn).
ModelChange diff_models(const Model& before, const Model& after);

/// What turning mesh `before` into `after` changed (PrimitiveChange's sizes and element lists,
/// `mesh` and `primitive` left -1). @returns false when their attribute names or types differ
/// (nothing then describes the change element by element).
bool diff_meshes(const SurfaceMesh& before, const SurfaceMesh& after, PrimitiveChange& out);

/// True when the models are equal in everything but their primitives' element data (vertices,
/// faces, attribute values) and the root `extras_json`: the parts `diff_models` calls structure.
/// Compares attribute names and types, not values; images only when `images`. Floats (node
/// transforms and weights, skins' matrices, animation keys) are compared bit for bit, as the
/// model's bytes: -0.0 differs from +0.0, a NaN equals itself.
/// O(everything but the element data).
bool same_structure(const Model& a, const Model& b, bool images = true);

}  // namespace deepcut
