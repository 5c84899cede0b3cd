// SPDX-License-Identifier: MIT
#pragma once
/// @file scene.h
/// What the studio shows, as data shared by the view and the inspectors: the model, its pose (a
/// PosedModel, core/include/deepcut/core/posed_model.h, built without grids), one instance per
/// drawn primitive (mesh instance x primitive) viewing that pose's PosedMesh and adding the posed
/// corner normals, and the skeleton. No VTK and no Qt here.

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "deepcut/core/model.h"
#include "deepcut/core/model_change.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/core/skinning.h"
#include "deepcut/core/spatial_index.h"
#include "deepcut/widgets/overlay.h"

namespace deepcut::plugins {

/// One drawn primitive: primitive `primitive` of mesh `mesh`, instanced by node `node`.
struct SceneInstance {
  int node = -1, mesh = -1, primitive = -1;
  int skin = -1;  ///< the node's skin, or -1 for a rigid instance
  const SurfaceMesh* surface = nullptr;
  /// This instance in the scene's posed model (`Scene::posed`).
  const PosedMesh* pose = nullptr;
  /// World positions for the current pose, one per vertex (the posed model's).
  const std::vector<glm::vec3>& posed() const { return pose->posed; }
  std::vector<glm::vec3> posed_normals;  ///< world normals, one per corner (empty without normals)
  /// A grid over the live faces at `posed` (the studio's operations' posed model, attached while it
  /// matches this pose and model), or nullptr: the tools' previews then test every face.
  const TriangleGrid* grid = nullptr;
};

/// What a scene keeps of the instances whose content left the model in the last structural step
/// (`follow_scene`), by (content tag, node), until the next structural step (local steps between
/// leave it): taken back when an undo or redo brings the content back (ModelChange::arrived), so
/// it is not posed again.
struct SceneStash {
  PoseStash posed;
  std::map<std::pair<std::uint64_t, int>, std::vector<glm::vec3>> normals;  ///< SceneInstance::posed_normals
};

/// Where an instance's posed data came from in the last `follow_scene` of a structural step (the
/// view takes its drawn data from the same place).
struct InstanceOrigin {
  enum class Kind { Built, Kept, Stashed };
  Kind kind = Kind::Built;
  std::size_t instance = 0;           ///< Kept: its index in the scene before the step
  std::pair<std::uint64_t, int> key;  ///< Stashed: its key in the stash
};

struct Scene {
  std::shared_ptr<const Model> model;
  /// The model at the current pose (PoseDetail::Positions: no grids); shared by copies of the
  /// scene, so posing a copy poses a posed model of its own.
  std::shared_ptr<PosedModel> posed;
  std::vector<SceneInstance> instances;  ///< the drawn instances (indexed as `Pick::instance`)
  std::vector<glm::mat4> world;  ///< world matrix of every node for the current pose (the posed model's)
  int animation = -1;            ///< -1: rest pose
  float time = 0.0f;             ///< seconds
  /// Morph weights set by hand per node (PoseKey::weights), replacing the animation's for those
  /// nodes: the pose is PoseKey(animation, time, weights). Kept when the scene is posed again.
  std::map<int, std::vector<float>> weights;
  float size = 1.0f;             ///< diagonal of the rest-pose world bounds (1 when empty)
  /// Kept of the instances the last structural step removed (see SceneStash); null: nothing.
  std::shared_ptr<SceneStash> stash;
  /// Set by `follow_scene` for a mapped structural step (else empty): where each instance's posed
  /// data came from, and the instances before the step whose content left, with their stash keys.
  std::vector<InstanceOrigin> origins;
  std::vector<std::pair<std::size_t, std::pair<std::uint64_t, int>>> departed;
};

/// Builds the scene of `model` posed by `animation` at `time`: one instance per triangle primitive
/// of every mesh instance reachable from the default scene's roots, in node order.
/// @param with_normals  also compute posed corner normals (the view needs them; default on).
/// @throws Error{InvalidArgument} if `model` is null or `animation` is out of range.
Scene make_scene(std::shared_ptr<const Model> model, int animation, float time, bool with_normals = true);
/// The same at `key`: its animation and time, and its weights set by hand (`Scene::weights`).
Scene make_scene(std::shared_ptr<const Model> model, const PoseKey& key, bool with_normals = true);

/// Re-poses `scene` in place (positions, normals, world matrices) at `time` of `animation` and the
/// scene's `weights`: PosedModel::repose on its posed model, O(vertices) in parallel, without grids.
/// @throws Error{InvalidArgument} if `animation` is out of range.
void pose_scene(Scene& scene, int animation, float time, bool with_normals = true);

/// Makes `scene` show `model`, the state one step (an operation, its undo or redo) made from the
/// scene's model, as `change` describes the step: the posed meshes of the edited primitives
/// follow it (PosedMesh::follow) and their corner normals are recomputed only where it touched
/// them (PosedMesh::follow_corner_normals), so the scene equals `make_scene` of `model` at the
/// same pose in O(change). `size` stays the scene's (the rest bounds are not measured again).
/// A mapped structural step (ModelChange::mapped: a cut, its undo or redo) is followed too: the
/// instances are listed again; those whose content the step kept, or that come back from the
/// scene's stash, keep their posed mesh and corner normals when their node is posed as before;
/// the others are posed afresh; those that left go into the stash (`origins` and `departed` say
/// which went where). O(nodes + what the step made).
/// @returns false, changing nothing, when the change is structural and not mapped (or the scene
///          has none of the instances it names as they were): the caller builds the scene again.
bool follow_scene(Scene& scene, std::shared_ptr<const Model> model, const ModelChange& change,
                  bool with_normals = true);

/// Every joint node of every skin, each once, in skin order.
std::vector<int> joint_nodes(const Model& model);

/// Bones as (parent joint node, child joint node): each joint linked to its nearest ancestor
/// that is also a joint. Roots of the skeleton have no bone.
std::vector<std::pair<int, int>> skeleton_bones(const Model& model);

/// Display name of node `node`: its name, or "node N" when it has none.
std::string node_label(const Model& model, int node);

/// The skeleton drawn over the model: bones as lines and joints as markers, in world space for
/// the scene's pose, sized relative to the model.
Overlay skeleton_overlay(const Scene& scene);

/// Number of live triangles and of referenced (welded) vertices over all instances.
struct SceneCounts {
  std::size_t vertices = 0, triangles = 0;
};
SceneCounts scene_counts(const Scene& scene);

}  // namespace deepcut::plugins
