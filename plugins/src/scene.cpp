// SPDX-License-Identifier: MIT
#include "deepcut/plugins/scene.h"

#include <algorithm>
#include <atomic>
#include <memory>
#include <set>
#include <unordered_set>

#include "deepcut/core/errors.h"
#include "deepcut/core/flags.h"
#include "deepcut/core/operation_room.h"
#include "deepcut/core/parallel.h"
#include "deepcut/core/skinning.h"
#include "deepcut/core/smallest_fit.h"
#include "deepcut/plugins/colors.h"

namespace deepcut::plugins {
namespace {

void collect_instances(const Model& model, int node, std::vector<int>& out, std::vector<char>& seen) {
  if (node < 0 || node >= static_cast<int>(model.nodes.size()) || seen[static_cast<std::size_t>(node)])
    return;
  seen[static_cast<std::size_t>(node)] = 1;
  const Node& n = model.nodes[static_cast<std::size_t>(node)];
  if (n.mesh >= 0 && n.mesh < static_cast<int>(model.meshes.size())) out.push_back(node);
  for (int child : n.children) collect_instances(model, child, out, seen);
}

void check_animation(const Model& model, int animation) {
  if (animation >= static_cast<int>(model.animations.size()))
    throw Error(ErrorCode::InvalidArgument, "pose: animation " + std::to_string(animation) +
                                                " does not exist (the model has " +
                                                std::to_string(model.animations.size()) + ")");
}

/// One instance per triangle primitive of every mesh instance reachable from the default scene's
/// roots, in node order (not posed).
std::vector<SceneInstance> list_instances(const Model& m) {
  std::vector<SceneInstance> out;
  std::vector<int> mesh_nodes;
  std::vector<char> seen(m.nodes.size(), 0);
  for (int root : m.root_nodes()) collect_instances(m, root, mesh_nodes, seen);
  for (int node : mesh_nodes) {
    const Node& n = m.nodes[static_cast<std::size_t>(node)];
    const Mesh& mesh = m.meshes[static_cast<std::size_t>(n.mesh)];
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      SceneInstance instance;
      instance.node = node;
      instance.mesh = n.mesh;
      instance.primitive = static_cast<int>(p);
      instance.skin = n.skin >= 0 && n.skin < static_cast<int>(m.skins.size()) ? n.skin : -1;
      instance.surface = &mesh.primitives[p].mesh;
      out.push_back(std::move(instance));
    }
  }
  return out;
}

// Whether `a` and `b` give every node the same transform and morph weights, value for value.
bool same_pose(const Pose& a, const Pose& b) {
  return a.translation == b.translation && a.rotation == b.rotation && a.scale == b.scale &&
         a.weights == b.weights;
}

// The model's bounds at rest (world_bounds of the rest pose: what sizes the camera and the tools).
// A scene whose pose is the rest pose (posed at rest, or at a clip's time whose pose is the rest
// pose, as the first key of many clips is) and whose instances are every primitive of every node
// with a mesh measures its own positions, which are those of the rest pose (posed the same way,
// bit for bit), so its bounds equal world_bounds' in value, bit for bit except the sign of a zero
// (face order here, vertex order there); any other scene poses the model again at rest.
BoundingBox rest_bounds(const Scene& scene, const PoseKey& key) {
  const Model& m = *scene.model;
  std::size_t primitives = 0;
  for (const Node& node : m.nodes)
    if (node.mesh >= 0 && static_cast<std::size_t>(node.mesh) < m.meshes.size())
      primitives += m.meshes[static_cast<std::size_t>(node.mesh)].primitives.size();
  const Pose rest = rest_pose(m);
  if (!key.weights.empty() || primitives != scene.instances.size() ||
      (key.animation >= 0 && !same_pose(sample_pose(m, key.animation, key.time), rest)))
    return world_bounds(m, rest);
  BoundingBox box;
  for (const SceneInstance& instance : scene.instances)
    box.add(face_bounds(*instance.surface, instance.posed()));
  return box;
}

}  // namespace

Scene make_scene(std::shared_ptr<const Model> model, int animation, float time, bool with_normals) {
  return make_scene(std::move(model), PoseKey(animation, time), with_normals);
}

Scene make_scene(std::shared_ptr<const Model> model, const PoseKey& key, bool with_normals) {
  if (!model) throw Error(ErrorCode::InvalidArgument, "make_scene: no model");
  Scene scene;
  scene.model = std::move(model);
  const Model& m = *scene.model;
  scene.instances = list_instances(m);
  scene.weights = key.weights;
  pose_scene(scene, key.animation, key.time, with_normals);
  const BoundingBox box = rest_bounds(scene, key);
  scene.size = box.empty() || box.diagonal() <= 0.0f ? 1.0f : box.diagonal();
  return scene;
}

void pose_scene(Scene& scene, int animation, float time, bool with_normals) {
  const Model& m = *scene.model;
  check_animation(m, animation);
  // A copy of the scene shares the posed model: pose one of its own.
  const PoseKey key(animation, time, scene.weights);
  if (scene.posed && scene.posed.use_count() == 1)
    scene.posed->repose(m, key);
  else
    scene.posed = std::make_shared<PosedModel>(PosedModel::build(m, key, PoseDetail::Positions));
  scene.animation = animation;
  scene.time = time;
  scene.world = scene.posed->world();
  for (SceneInstance& instance : scene.instances) {
    instance.pose = scene.posed->find(instance.node, instance.primitive);
    if (with_normals)
      instance.posed_normals = instance.pose->corner_normals(*instance.surface);
    else
      instance.posed_normals.clear();
  }
}

namespace {

const SurfaceMesh* primitive_mesh(const Model& model, int mesh, int primitive) {
  if (mesh < 0 || static_cast<std::size_t>(mesh) >= model.meshes.size()) return nullptr;
  const auto& prims = model.meshes[static_cast<std::size_t>(mesh)].primitives;
  if (primitive < 0 || static_cast<std::size_t>(primitive) >= prims.size()) return nullptr;
  return &prims[static_cast<std::size_t>(primitive)].mesh;
}

}  // namespace

namespace {

/// The corner normals of `instance`, built in a structural step: copied from the normals drawn
/// before (`old`, posed as `old_poses` say) for the faces a piece has of the instance it was made
/// out of (ModelChange::origins) when that was posed alike, computed for the others. The copy is
/// written into one of `spare` where one fits (take_smallest_fit: its memory reused).
std::vector<glm::vec3> built_normals(const SceneInstance& instance, const ModelChange& change,
                                     const std::vector<SceneInstance>& old,
                                     const std::vector<PosedMeshHeader>& old_poses,
                                     std::vector<std::vector<glm::vec3>>& spare) {
  const PosedMesh& pose = *instance.pose;
  for (const auto& o : change.origins) {
    if (!o || o->node != instance.node || o->mesh != instance.mesh || o->primitive != instance.primitive) continue;
    for (std::size_t i = 0; i < old.size(); ++i) {
      const SceneInstance& before = old[i];
      const PosedMeshHeader& posed = old_poses[i];
      if (before.node == o->node_before && before.mesh == o->mesh_before &&
          before.primitive == o->primitive_before && !before.posed_normals.empty() &&
          posed.world == pose.world && posed.joints == pose.joints && posed.weights == pose.weights) {
        // At most twice the piece's own room, so a small piece keeps no large array alive (a new
        // one gets the piece's own room, piece_corner_room).
        const std::size_t slots = instance.surface->face_slots();
        std::vector<glm::vec3> out = take_smallest_fit(spare, 3 * slots, 2 * operation_corner_room(slots),
                                                       [](const std::vector<glm::vec3>& a) { return a.capacity(); });
        pose.corner_normals(*instance.surface, *o, before.posed_normals, out);
        return out;
      }
    }
  }
  return pose.corner_normals(*instance.surface);
}

/// follow_scene of a mapped structural step. Whether the posed model kept an instance shows in
/// its positions' buffer: a kept or stashed PosedMesh is moved, buffers and all, while every
/// instance built meanwhile gets buffers of its own (the old ones are alive until it returns).
void follow_structure(Scene& scene, std::shared_ptr<const Model> model, const ModelChange& change,
                      bool with_normals) {
  if (scene.posed.use_count() > 1) scene.posed = std::make_shared<PosedModel>(*scene.posed);
  if (!scene.stash || scene.stash.use_count() > 1) scene.stash = std::make_shared<SceneStash>();
  std::vector<SceneInstance> old = std::move(scene.instances);
  std::map<const glm::vec3*, std::size_t> old_data;  // posed positions' buffer -> instance before
  std::vector<PosedMeshHeader> old_poses;  // how each was posed (its posed mesh may go)
  for (std::size_t i = 0; i < old.size(); ++i) {
    old_data[old[i].pose->posed.data()] = i;
    if (!change.origins.empty()) old_poses.push_back(*old[i].pose);
  }
  // Only what an arrival may take back (the posed model drops the rest before building, so
  // the buffers listed here stay alive while it builds).
  std::set<std::uint64_t> arriving;
  for (const PrimitiveContent& a : change.arrived) arriving.insert(a.tag);
  std::map<const glm::vec3*, std::pair<std::uint64_t, int>> stashed;
  for (const auto& [key, inst] : scene.stash->posed)
    if (arriving.count(key.first)) stashed[inst.posed.data()] = key;
  // The normals of what does not come back are spare: a piece's copied normals reuse their
  // memory (the pages are there already).
  auto normals_back = std::move(scene.stash->normals);
  scene.stash->normals.clear();
  std::vector<std::vector<glm::vec3>> spare = take_unclaimed(normals_back, arriving);
  // The fullest first: of equal rooms, the largest piece takes the one with the most pages in.
  largest_first(spare, [](const std::vector<glm::vec3>& a) { return a.size(); });
  scene.model = std::move(model);
  const Model& m = *scene.model;
  scene.posed->follow(m, change, PoseDetail::Positions, &scene.stash->posed);
  scene.world = scene.posed->world();
  scene.instances = list_instances(m);
  scene.origins.assign(scene.instances.size(), InstanceOrigin());
  std::vector<std::size_t> built;  // the instances whose corner normals are made below
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    SceneInstance& instance = scene.instances[i];
    instance.pose = scene.posed->find(instance.node, instance.primitive);
    InstanceOrigin& origin = scene.origins[i];
    const glm::vec3* data = instance.pose->posed.data();
    if (const auto k = old_data.find(data); k != old_data.end()) {
      origin.kind = InstanceOrigin::Kind::Kept;
      origin.instance = k->second;
      instance.posed_normals = std::move(old[k->second].posed_normals);
    } else if (const auto s = stashed.find(data); s != stashed.end()) {
      origin.kind = InstanceOrigin::Kind::Stashed;
      origin.key = s->second;
      const auto n = normals_back.find(s->second);
      if (n != normals_back.end()) instance.posed_normals = std::move(n->second);
    }
    const bool normals_fit = instance.posed_normals.size() == 3 * instance.surface->face_slots();
    if (origin.kind == InstanceOrigin::Kind::Built || (with_normals && !normals_fit)) {
      instance.posed_normals = std::vector<glm::vec3>();
      if (with_normals) built.push_back(i);
    }
  }
  largest_first(built, [&](std::size_t i) { return scene.instances[i].surface->face_slots(); });
  for (std::size_t i : built)
    scene.instances[i].posed_normals = built_normals(scene.instances[i], change, old, old_poses, spare);
  // The instances whose posed mesh went into the stash, with their normals.
  scene.departed.clear();
  for (const auto& [key, inst] : scene.stash->posed)
    if (const auto k = old_data.find(inst.posed.data()); k != old_data.end()) {
      scene.departed.emplace_back(k->second, key);
      scene.stash->normals[key] = std::move(old[k->second].posed_normals);
    }
}

}  // namespace

bool follow_scene(Scene& scene, std::shared_ptr<const Model> model, const ModelChange& change, bool with_normals) {
  if (!model || !scene.model || !scene.posed) return false;
  if (change.structure) {
    if (!change.mapped || !scene.posed->valid()) return false;
    follow_structure(scene, std::move(model), change, with_normals);
    return true;
  }
  const Model& m = *model;
  if (m.nodes.size() != scene.model->nodes.size()) return false;
  for (const SceneInstance& instance : scene.instances)
    if (!primitive_mesh(m, instance.mesh, instance.primitive) ||
        m.nodes[static_cast<std::size_t>(instance.node)].mesh != instance.mesh ||
        !scene.posed->find(instance.node, instance.primitive))
      return false;
  // The scene must show the state before the step.
  for (const PrimitiveChange& edit : change.primitives)
    for (const SceneInstance& instance : scene.instances)
      if (instance.mesh == edit.mesh && instance.primitive == edit.primitive &&
          (instance.pose->posed.size() != edit.vertices_before ||
           (!instance.posed_normals.empty() && instance.posed_normals.size() != 3 * edit.faces_before)))
        return false;
  // A copy of the scene shares the posed model: follow one of its own.
  if (scene.posed.use_count() > 1) scene.posed = std::make_shared<PosedModel>(*scene.posed);
  scene.origins.clear();
  scene.departed.clear();
  scene.model = std::move(model);
  // The linear maps of the listed vertices before the step: where one changes (new skin
  // weights), the corner normals around the vertex change too.
  std::vector<std::vector<std::pair<VertexId, glm::mat3>>> linear_before(scene.instances.size());
  for (const PrimitiveChange& edit : change.primitives)
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
      const SceneInstance& instance = scene.instances[i];
      if (instance.mesh != edit.mesh || instance.primitive != edit.primitive) continue;
      const auto& linear = instance.pose->linear;
      for (VertexId v : edit.vertices)
        if (v.index < linear.size()) linear_before[i].emplace_back(v, linear[v.index]);
    }
  scene.posed->follow(m, change);
  if (!scene.posed->valid()) {  // it could not follow: pose afresh
    pose_scene(scene, scene.animation, scene.time, with_normals);
    return true;
  }
  for (SceneInstance& instance : scene.instances) {
    instance.surface = primitive_mesh(m, instance.mesh, instance.primitive);
    instance.pose = scene.posed->find(instance.node, instance.primitive);
  }
  for (const PrimitiveChange& edit : change.primitives)
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
      SceneInstance& instance = scene.instances[i];
      if (instance.mesh != edit.mesh || instance.primitive != edit.primitive) continue;
      std::vector<VertexId> relinked;
      for (const auto& [v, before] : linear_before[i])
        if (v.index < instance.pose->linear.size() && instance.pose->linear[v.index] != before) relinked.push_back(v);
      if (with_normals && instance.posed_normals.size() != 3 * edit.faces_before)
        instance.posed_normals = instance.pose->corner_normals(*instance.surface);  // none to follow
      else if (with_normals)
        instance.pose->follow_corner_normals(*instance.surface, edit, relinked, instance.posed_normals);
      else
        instance.posed_normals.clear();
    }
  return true;
}

std::vector<int> joint_nodes(const Model& model) {
  std::vector<int> out;
  std::unordered_set<int> seen;
  for (const Skin& skin : model.skins)
    for (int j : skin.joints)
      if (j >= 0 && j < static_cast<int>(model.nodes.size()) && seen.insert(j).second) out.push_back(j);
  return out;
}

std::vector<std::pair<int, int>> skeleton_bones(const Model& model) {
  const std::vector<int> joints = joint_nodes(model);
  std::vector<char> is_joint(model.nodes.size(), 0);
  for (int j : joints) is_joint[static_cast<std::size_t>(j)] = 1;
  const std::vector<int> parents = model.parents();
  std::vector<std::pair<int, int>> bones;
  for (int j : joints) {
    int p = parents[static_cast<std::size_t>(j)];
    // Nearest joint ancestor; a cycle guard keeps malformed hierarchies from looping.
    for (std::size_t guard = 0;
         p >= 0 && !is_joint[static_cast<std::size_t>(p)] && guard < model.nodes.size(); ++guard)
      p = parents[static_cast<std::size_t>(p)];
    if (p >= 0 && is_joint[static_cast<std::size_t>(p)]) bones.emplace_back(p, j);
  }
  return bones;
}

std::string node_label(const Model& model, int node) {
  if (node < 0 || node >= static_cast<int>(model.nodes.size())) return "(none)";
  const std::string& name = model.nodes[static_cast<std::size_t>(node)].name;
  return name.empty() ? "node " + std::to_string(node) : name;
}

Overlay skeleton_overlay(const Scene& scene) {
  Overlay overlay;
  const Model& m = *scene.model;
  auto origin = [&](int node) { return glm::vec3(scene.world[static_cast<std::size_t>(node)][3]); };
  OverlayLines bones;
  bones.color = palette::kBone;
  bones.width_px = 3.0f;
  bones.on_top = true;
  for (const auto& [parent, child] : skeleton_bones(m)) {
    bones.endpoints.push_back(origin(parent));
    bones.endpoints.push_back(origin(child));
  }
  OverlayPoints joints;
  joints.color = glm::vec3(0.9f, 0.95f, 1.0f);
  joints.size_px = 7.0f;
  joints.on_top = true;
  for (int j : joint_nodes(m)) joints.positions.push_back(origin(j));
  overlay.lines.push_back(std::move(bones));
  overlay.points.push_back(std::move(joints));
  return overlay;
}

SceneCounts scene_counts(const Scene& scene) {
  // Each instance's referenced vertices marked, then counted, over the pool (the status bar
  // asks after every frame).
  constexpr std::size_t kGrain = 65536;
  SceneCounts counts;
  for (const SceneInstance& instance : scene.instances) {
    const SurfaceMesh& mesh = *instance.surface;
    counts.triangles += mesh.face_count();
    const Flags used = cleared_flags(mesh.vertex_count(), kGrain);
    parallel_for(mesh.face_slots(), kGrain, [&](std::size_t b, std::size_t e) {
      const Triangle* const faces = mesh.faces().data();
      for (std::size_t f = b; f < e; ++f)
        if (!mesh.is_deleted(FaceId(static_cast<std::uint32_t>(f))))
          for (VertexId v : faces[f]) used[v.index].store(1, std::memory_order_relaxed);
    });
    counts.vertices += parallel_reduce(
        mesh.vertex_count(), kGrain, std::size_t(0),
        [&](std::size_t b, std::size_t e) {
          std::size_t n = 0;
          for (std::size_t v = b; v < e; ++v) n += used[v].load(std::memory_order_relaxed);
          return n;
        },
        [](std::size_t a, std::size_t b) { return a + b; });
  }
  return counts;
}

}  // namespace deepcut::plugins
