// SPDX-License-Identifier: MIT
// The inspector plugins and their shared scene, without a display: what each inspector
// answers (colours, overlay, colour bar, summary) for small models built in code.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

#include "deepcut/core/adjacency.h"
#include "deepcut/core/attributes.h"
#include "deepcut/core/errors.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/parallel.h"
#include "deepcut/core/skinning.h"
#include "deepcut/core/softbody/clustering.h"
#include "deepcut/core/softbody/simulation.h"
#include "deepcut/plugins/colors.h"
#include "deepcut/plugins/inspector_registry.h"
#include "deepcut/plugins/scene.h"
#include "fixtures.h"

namespace deepcut::plugins {
namespace {

std::shared_ptr<const Model> tube_model() {
  return std::make_shared<const Model>(test::make_skinned_tube_model());
}

/// A model with one unskinned grid instance (boundary and a UV seam, see make_grid).
std::shared_ptr<const Model> grid_model(int n) {
  Model model;
  Primitive prim;
  prim.mesh = test::make_grid(n, n);
  model.meshes.push_back({"grid", {}, ""});
  model.meshes[0].primitives.push_back(std::move(prim));
  Node node;
  node.name = "grid";
  node.mesh = 0;
  model.nodes.push_back(node);
  model.scenes = {{0}};
  return std::make_shared<const Model>(std::move(model));
}

bool contains(const std::vector<std::string>& lines, const std::string& text) {
  return std::any_of(lines.begin(), lines.end(),
                     [&](const std::string& l) { return l.find(text) != std::string::npos; });
}

TEST(InspectorRegistryTest, builtin_list_has_every_inspector_and_rejects_unknown_ids) {
  const InspectorRegistry& registry = builtin_inspectors();
  ASSERT_NE(registry.find("weights"), nullptr);
  ASSERT_NE(registry.find("adjacency"), nullptr);
  ASSERT_NE(registry.find("clusters"), nullptr);
  for (const InspectorInfo& info : registry.list()) {
    const auto inspector = registry.create(info.id);
    EXPECT_EQ(inspector->id(), info.id);
    EXPECT_EQ(inspector->title(), info.title);
  }
  try {
    registry.create("nope");
    FAIL() << "unknown inspector accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
    EXPECT_NE(std::string(e.what()).find("weights"), std::string::npos) << e.what();
  }
  InspectorRegistry copy = registry;
  EXPECT_THROW(copy.add(*registry.find("weights")), Error);
  EXPECT_THROW(copy.add({"", "x", registry.find("weights")->create}), Error);
}

TEST(SceneTest, the_scene_pose_is_a_posed_model_equal_to_a_fresh_build_at_every_time) {
  const auto model = tube_model();
  Scene scene = make_scene(model, 0, 0.0f);
  ASSERT_TRUE(scene.posed);
  for (float t : {0.25f, 1.0f, 0.5f}) {
    pose_scene(scene, 0, t);
    const PosedModel fresh = PosedModel::build(*model, 0, t);
    ASSERT_EQ(scene.posed->size(), fresh.size());
    EXPECT_EQ(scene.world, fresh.world());
    for (const SceneInstance& piece : scene.instances) {
      const PosedMesh* want = fresh.find(piece.node, piece.primitive);
      ASSERT_NE(want, nullptr);
      EXPECT_EQ(piece.pose, scene.posed->find(piece.node, piece.primitive)) << "the instance views the posed model";
      EXPECT_EQ(piece.posed(), want->posed) << "bit for bit, t " << t;
      EXPECT_EQ(piece.pose->linear, want->linear);
      EXPECT_EQ(piece.pose->bounds.min, want->bounds.min);
      EXPECT_EQ(piece.pose->bounds.max, want->bounds.max);
      EXPECT_TRUE(piece.pose->gridless) << "drawing a pose builds no grid";
      EXPECT_EQ(piece.posed_normals, posed_normals(*model, piece.node, *piece.surface, fresh.world()));
    }
  }
  // A copy shares the posed model until one of them is posed: then it poses one of its own.
  Scene copy = scene;
  pose_scene(copy, 0, 0.0f);
  EXPECT_NE(copy.posed, scene.posed);
  EXPECT_EQ(scene.posed->time(), 0.5f);
  EXPECT_EQ(copy.instances[0].posed(), PosedModel::build(*model, 0, 0.0f).find(0, 0)->posed);
  // The operations' prepare gives a gridless posed model its grids at the same pose.
  PosedModel operations = *scene.posed;
  operations.prepare(*model, 0, 0.5f);
  const PosedMesh* inst = operations.find(0, 0);
  EXPECT_FALSE(inst->gridless);
  EXPECT_EQ(inst->grid.face_count(), model->meshes[0].primitives[0].mesh.face_count());
}

// A scene made at rest (or at a clip's start that is the rest pose) measures the model's size from
// its own posed positions; it equals the rest pose's world bounds bit for bit on skinned, morphing
// and multi-node models, and so does the size of a scene made at another pose (which poses the
// model again at rest).
TEST(SceneTest, the_size_is_the_rest_pose_s_world_bounds_at_any_pose) {
  for (const char* name :
       {"cactus.glb", "models/Fox/Fox.glb", "models/CesiumMan/CesiumMan.glb",
        "models/RiggedFigure/RiggedFigure.glb", "models/AnimatedMorphCube/AnimatedMorphCube.gltf",
        "models/AnimatedMorphSphere/AnimatedMorphSphere.gltf"}) {
    const auto model = std::make_shared<const Model>(read_gltf(std::string(DEEPCUT_ASSETS_DIR) + "/" + name));
    const float expected = world_bounds(*model, rest_pose(*model)).diagonal();
    EXPECT_EQ(make_scene(model, -1, 0.0f).size, expected) << name;
    if (!model->animations.empty()) {
      EXPECT_EQ(make_scene(model, 0, 0.0f).size, expected) << name << " at its first clip's start";
      EXPECT_EQ(make_scene(model, 0, 0.5f).size, expected) << name << " posed by its first clip";
    }
  }
}

TEST(SceneTest, pieces_follow_the_pose_and_skeleton_links_joints) {
  const auto model = tube_model();
  Scene scene = make_scene(model, -1, 0.0f);
  ASSERT_EQ(scene.instances.size(), 1u);
  const SceneInstance& piece = scene.instances[0];
  EXPECT_EQ(piece.node, 0);
  EXPECT_EQ(piece.skin, 0);
  ASSERT_EQ(piece.posed().size(), piece.surface->vertex_count());
  for (std::size_t v = 0; v < piece.posed().size(); ++v)
    EXPECT_LT(glm::distance(piece.posed()[v], piece.surface->positions()[v]), 1e-5f);
  EXPECT_GT(scene.size, 4.0f);

  pose_scene(scene, 0, 1.0f);  // joint1 rotated by 60 degrees: the top of the tube moves
  float moved = 0.0f;
  for (std::size_t v = 0; v < piece.posed().size(); ++v)
    moved = std::max(moved, glm::distance(scene.instances[0].posed()[v], piece.surface->positions()[v]));
  EXPECT_GT(moved, 0.5f);
  EXPECT_THROW(pose_scene(scene, 3, 0.0f), Error);

  EXPECT_EQ(joint_nodes(*model), (std::vector<int>{1, 3}));
  EXPECT_EQ(skeleton_bones(*model), (std::vector<std::pair<int, int>>{{1, 3}}));
  const Overlay skeleton = skeleton_overlay(scene);
  ASSERT_EQ(skeleton.lines.size(), 1u);
  EXPECT_EQ(skeleton.lines[0].endpoints.size(), 2u);
  EXPECT_EQ(skeleton.points[0].positions.size(), 2u);
  const SceneCounts counts = scene_counts(scene);
  EXPECT_EQ(counts.triangles, piece.surface->face_count());
}

TEST(WeightsInspectorTest, heat_map_of_a_joint_runs_from_blue_to_red) {
  const auto model = tube_model();
  const Scene scene = make_scene(model, 0, 0.0f);
  auto inspector = builtin_inspectors().create("weights");
  inspector->set_scene(scene, SceneChange::Model);
  inspector->set_option("joint", "joint1");
  EXPECT_TRUE(contains(inspector->summary(), "joint1"));
  EXPECT_TRUE(contains(inspector->summary(), "All weights normalised"));
  const InstanceColors colors = inspector->instance_colors(0);
  ASSERT_EQ(colors.kind, InstanceColors::Kind::PerVertex);
  ASSERT_EQ(colors.colors.size(), scene.instances[0].surface->vertex_count());
  const auto& positions = scene.instances[0].surface->positions();
  for (std::size_t v = 0; v < positions.size(); ++v) {
    // joint1's weight is y / 4 on this tube.
    EXPECT_EQ(colors.colors[v], to_rgb8(weight_color(positions[v].y / 4.0f))) << "vertex " << v;
  }
  const auto bottom =
      std::min_element(positions.begin(), positions.end(), [](auto& a, auto& b) { return a.y < b.y; });
  const auto top =
      std::max_element(positions.begin(), positions.end(), [](auto& a, auto& b) { return a.y < b.y; });
  EXPECT_EQ(colors.colors[std::size_t(bottom - positions.begin())], glm::u8vec3(0, 0, 255));
  EXPECT_EQ(colors.colors[std::size_t(top - positions.begin())], glm::u8vec3(255, 0, 0));
  ASSERT_TRUE(inspector->color_bar().has_value());
  EXPECT_EQ(inspector->color_bar()->stops.size(), weight_ramp().size());

  try {
    inspector->set_option("joint", "elbow");
    FAIL() << "unknown joint accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
    EXPECT_NE(std::string(e.what()).find("elbow"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("joint0"), std::string::npos) << "lists the joints";
  }
  EXPECT_THROW(inspector->set_option("colour", "x"), Error);
}

TEST(WeightsInspectorTest, dominant_joint_colours_by_largest_weight_and_bone_pick_selects_joint) {
  const auto model = tube_model();
  const Scene scene = make_scene(model, 0, 0.0f);
  auto inspector = builtin_inspectors().create("weights");
  inspector->set_scene(scene, SceneChange::Model);
  inspector->set_option("mode", "dominant");
  EXPECT_FALSE(inspector->color_bar().has_value());
  const InstanceColors colors = inspector->instance_colors(0);
  const auto& positions = scene.instances[0].surface->positions();
  for (std::size_t v = 0; v < positions.size(); ++v) {
    if (std::abs(positions[v].y - 2.0f) < 1e-3f) continue;  // a tie at mid height
    const std::size_t joint = positions[v].y < 2.0f ? 0 : 1;
    EXPECT_EQ(colors.colors[v], to_rgb8(category_color(joint))) << "vertex " << v;
  }
  Pick pick;
  pick.joint_node = 1;
  EXPECT_TRUE(inspector->pick(pick));
  EXPECT_TRUE(contains(inspector->summary(), "joint0"));
  ASSERT_TRUE(inspector->color_bar().has_value()) << "clicking a bone shows that joint's weights";
  pick.joint_node = 0;  // the mesh node is not a joint
  EXPECT_FALSE(inspector->pick(pick));
}

TEST(WeightsInspectorTest, flags_vertices_whose_weights_do_not_sum_to_one) {
  Model broken = test::make_skinned_tube_model();
  auto& weights = broken.meshes[0].primitives[0].mesh.vertex_attrs().get<glm::vec4>(attr::kWeights0);
  weights[5] = {0.3f, 0.3f, 0.0f, 0.0f};
  weights[9] = {0.9f, 0.3f, 0.0f, 0.0f};
  const Scene scene = make_scene(std::make_shared<const Model>(std::move(broken)), 0, 1.0f);
  auto inspector = builtin_inspectors().create("weights");
  inspector->set_scene(scene, SceneChange::Model);
  EXPECT_TRUE(contains(inspector->summary(), "2 vertices with weights not summing to 1"));
  const Overlay overlay = inspector->overlay();
  const auto flagged = std::find_if(overlay.points.begin(), overlay.points.end(),
                                    [](const OverlayPoints& p) { return p.color == palette::kFlagged; });
  ASSERT_NE(flagged, overlay.points.end());
  ASSERT_EQ(flagged->positions.size(), 2u);
  EXPECT_EQ(flagged->positions[0], scene.instances[0].posed()[5]) << "markers sit on the posed vertex";
  EXPECT_EQ(flagged->positions[1], scene.instances[0].posed()[9]);
}

TEST(AdjacencyInspectorTest, draws_boundary_and_seam_edges_and_counts_components) {
  const auto model = grid_model(4);
  const Scene scene = make_scene(model, -1, 0.0f);
  auto inspector = builtin_inspectors().create("adjacency");
  inspector->set_scene(scene, SceneChange::Model);
  const Adjacency adjacency = Adjacency::build(*scene.instances[0].surface);
  const auto boundary = adjacency.boundary_edges().size(),
             seams = adjacency.seam_edges(*scene.instances[0].surface).size();
  ASSERT_GT(boundary, 0u);
  ASSERT_GT(seams, 0u);
  const Overlay overlay = inspector->overlay();
  auto lines_of = [&](const glm::vec3& color) -> std::size_t {
    for (const OverlayLines& l : overlay.lines)
      if (l.color == color) return l.endpoints.size() / 2;
    return 0;
  };
  EXPECT_EQ(lines_of(palette::kBoundary), boundary);
  EXPECT_EQ(lines_of(palette::kSeam), seams);
  EXPECT_EQ(lines_of(palette::kNonManifold), 0u);
  EXPECT_TRUE(contains(inspector->summary(), "1 component"));
  EXPECT_TRUE(contains(inspector->summary(), std::to_string(boundary) + " boundary"));
  const InstanceColors colors = inspector->instance_colors(0);
  ASSERT_EQ(colors.kind, InstanceColors::Kind::PerFace);
  EXPECT_EQ(colors.colors.size(), scene.instances[0].surface->face_slots());
}

TEST(AdjacencyInspectorTest, picked_vertex_highlights_its_one_ring) {
  const auto model = grid_model(4);
  const Scene scene = make_scene(model, -1, 0.0f);
  auto inspector = builtin_inspectors().create("adjacency");
  inspector->set_scene(scene, SceneChange::Model);
  const SurfaceMesh& mesh = *scene.instances[0].surface;
  const Adjacency adjacency = Adjacency::build(mesh);
  // An interior vertex: (1, 1) of the 5 x 5 grid of vertices.
  VertexId interior;
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v)
    if (glm::distance(mesh.positions()[v], glm::vec3(0.25f, 0.25f, 0.0f)) < 1e-5f) interior = VertexId(v);
  ASSERT_TRUE(interior.valid());
  const InstanceColors before = inspector->instance_colors(0);
  Pick pick;
  pick.instance = 0;
  pick.vertex = interior;
  pick.face = adjacency.vertex_faces(interior).front();
  ASSERT_TRUE(inspector->pick(pick));
  const InstanceColors after = inspector->instance_colors(0);
  const auto ring = adjacency.vertex_faces(interior);
  std::size_t highlighted = 0;
  for (std::uint32_t f = 0; f < after.colors.size(); ++f) {
    const bool in_ring = std::find(ring.begin(), ring.end(), FaceId(f)) != ring.end();
    highlighted += after.colors[f] == to_rgb8(palette::kHighlight);
    EXPECT_EQ(after.colors[f] != before.colors[f], in_ring) << "face " << f;
  }
  EXPECT_EQ(highlighted, ring.size());
  const std::size_t neighbours = adjacency.vertex_neighbors(interior).size();
  EXPECT_TRUE(contains(inspector->summary(), "Vertex " + std::to_string(interior.index) + ": " +
                                                 std::to_string(neighbours) + " neighbour vertices, " +
                                                 std::to_string(ring.size()) + " faces"));
  const Overlay overlay = inspector->overlay();
  const auto spokes = std::find_if(overlay.lines.begin(), overlay.lines.end(),
                                   [](const OverlayLines& l) { return l.color == palette::kHighlight; });
  ASSERT_NE(spokes, overlay.lines.end());
  EXPECT_EQ(spokes->endpoints.size(), 2 * neighbours);

  EXPECT_THROW(inspector->set_option("vertex", "x1"), Error);
  EXPECT_THROW(inspector->set_option("vertex", "100000"), Error);
  inspector->set_option("vertex", std::to_string(interior.index));
  EXPECT_TRUE(contains(inspector->summary(), "Vertex " + std::to_string(interior.index)));
}

TEST(AdjacencyInspectorTest, overlay_follows_the_pose) {
  const auto model = tube_model();
  Scene scene = make_scene(model, 0, 0.0f);
  auto inspector = builtin_inspectors().create("adjacency");
  inspector->set_scene(scene, SceneChange::Model);
  // A vertex at the top of the tube, which the animation moves.
  const auto& positions = scene.instances[0].surface->positions();
  const auto top = static_cast<std::uint32_t>(
      std::max_element(positions.begin(), positions.end(), [](auto& a, auto& b) { return a.y < b.y; }) -
      positions.begin());
  inspector->set_option("vertex", std::to_string(top));
  auto picked_marker = [&]() {
    for (const OverlayPoints& p : inspector->overlay().points)
      if (p.color == palette::kPicked) return p.positions.at(0);
    return glm::vec3(-1e9f);
  };
  EXPECT_EQ(picked_marker(), scene.instances[0].posed()[top]);
  pose_scene(scene, 0, 1.0f);
  inspector->set_scene(scene, SceneChange::Pose);
  EXPECT_EQ(picked_marker(), scene.instances[0].posed()[top]);
  EXPECT_GT(glm::distance(picked_marker(), positions[top]), 0.5f);
  EXPECT_TRUE(contains(inspector->summary(), "Vertex " + std::to_string(top)))
      << "a pose change keeps the pick";
}

TEST(ClustersInspectorTest, colours_vertices_by_particle_and_reclusters_with_rho) {
  const auto model = tube_model();
  Scene scene = make_scene(model, 0, 0.0f);
  auto inspector = builtin_inspectors().create("clusters");
  inspector->set_scene(scene, SceneChange::Model);
  inspector->set_option("rho", "0.5");
  const SurfaceMesh& mesh = *scene.instances[0].surface;
  const Clusters reference = Clusters::build(mesh, scene.instances[0].posed(), ClusterOptions{0.5f});
  const std::size_t particles = reference.particle_count();
  ASSERT_GT(particles, 4u);
  EXPECT_TRUE(contains(inspector->summary(), std::to_string(particles) + " particles at rho 0.5"));
  // Every vertex is coloured by the particle holding it most strongly.
  const InstanceColors colors = inspector->instance_colors(0);
  ASSERT_EQ(colors.kind, InstanceColors::Kind::PerVertex);
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    std::uint32_t best = kInvalidIndex;
    float weight = -1.0f;
    for (const Influence& i : reference.influences(VertexId(v)))
      if (i.weight > weight) weight = i.weight, best = i.particle;
    ASSERT_NE(best, kInvalidIndex);
    EXPECT_EQ(colors.colors[v], to_rgb8(category_color(best))) << "vertex " << v;
  }
  // Centres and radius spheres, one per particle, at rho, following the pose.
  auto sphere_set = [&]() {
    const Overlay overlay = inspector->overlay();
    return overlay.spheres.empty() ? OverlaySpheres{} : overlay.spheres[0];
  };
  OverlaySpheres spheres = sphere_set();
  ASSERT_EQ(spheres.centers.size(), particles);
  for (float r : spheres.radii) EXPECT_FLOAT_EQ(r, 0.5f);
  const auto rest_centres = spheres.centers;
  pose_scene(scene, 0, 1.0f);
  inspector->set_scene(scene, SceneChange::Pose);
  const auto posed_centres = sphere_set().centers;
  EXPECT_EQ(posed_centres, posed_particle_centres(reference, scene.instances[0].posed()));
  EXPECT_NE(posed_centres, rest_centres);

  inspector->set_option("rho", "1.5");
  EXPECT_LT(sphere_set().centers.size(), particles) << "a larger rho gives fewer particles";
  EXPECT_THROW(inspector->set_option("rho", "-1"), Error);
  EXPECT_THROW(inspector->set_option("rho", "big"), Error);

  Pick pick;
  pick.instance = 0;
  pick.vertex = VertexId(3);
  EXPECT_FALSE(inspector->focus().has_value());
  ASSERT_TRUE(inspector->pick(pick));
  EXPECT_TRUE(contains(inspector->summary(), "Particle "));
  ASSERT_TRUE(inspector->focus().has_value());
  EXPECT_FLOAT_EQ(inspector->focus()->radius, 3.0f);
}

// The status bar's counts (vertices marked over the pool) are the same whatever the thread
// count, and equal to a serial count, over several chunks of vertices with deleted faces (whose
// vertices only they used are not counted).
TEST(SceneCountsTest, the_same_whatever_the_thread_count) {
  Model model;
  Primitive prim;
  prim.mesh = test::make_grid(260, 260);
  ASSERT_GT(prim.mesh.vertex_count(), 65536u);
  {
    MeshEditor editor(prim.mesh);
    for (std::uint32_t f = 0; f < prim.mesh.face_slots(); f += 5) editor.remove_face(FaceId(f));
    for (std::uint32_t f = 1; f < 2000; ++f)  // a patch whose vertices no live face uses
      if (!prim.mesh.is_deleted(FaceId(f))) editor.remove_face(FaceId(f));
  }
  std::vector<char> used(prim.mesh.vertex_count(), 0);
  std::size_t faces = 0;
  for (std::uint32_t f = 0; f < prim.mesh.face_slots(); ++f) {
    if (prim.mesh.is_deleted(FaceId(f))) continue;
    ++faces;
    for (VertexId v : prim.mesh.face(FaceId(f))) used[v.index] = 1;
  }
  const auto vertices = static_cast<std::size_t>(std::count(used.begin(), used.end(), 1));
  ASSERT_LT(vertices, prim.mesh.vertex_count());
  model.meshes.push_back({"grid", {}, ""});
  model.meshes[0].primitives.push_back(std::move(prim));
  Node node;
  node.mesh = 0;
  model.nodes.push_back(node);
  model.scenes = {{0}};
  const Scene scene = make_scene(std::make_shared<const Model>(std::move(model)), -1, 0.0f, false);
  const std::size_t saved = thread_count();
  for (std::size_t threads : {1u, 2u, 3u}) {
    set_thread_count(threads);
    const SceneCounts counts = scene_counts(scene);
    EXPECT_EQ(counts.vertices, vertices) << threads << " threads";
    EXPECT_EQ(counts.triangles, faces) << threads << " threads";
  }
  set_thread_count(saved);
}

}  // namespace
}  // namespace deepcut::plugins
