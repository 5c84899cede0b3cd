// SPDX-License-Identifier: MIT
#include "fixtures.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "deepcut/core/validate.h"

namespace deepcut::test {

SurfaceMesh make_grid(int nx, int ny) {
  SurfaceMesh mesh;
  auto& joints = mesh.vertex_attrs().add<glm::u16vec4>(attr::kJoints0);
  auto& weights = mesh.vertex_attrs().add<glm::vec4>(attr::kWeights0);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const float x = float(i) / float(nx), y = float(j) / float(ny);
      const VertexId v = mesh.add_vertex({x, y, 0.0f});
      joints[v.index] = {0, 1, 0, 0};
      weights[v.index] = {1.0f - x, x, 0.0f, 0.0f};
      if (weights[v.index][1] == 0.0f) joints[v.index][1] = 0;
    }
  auto& uv = mesh.corner_attrs().add<glm::vec2>(attr::kUv0);
  auto& normal = mesh.corner_attrs().add<glm::vec3>(attr::kNormal);
  auto id = [&](int i, int j) { return VertexId(static_cast<std::uint32_t>(j * (nx + 1) + i)); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const bool right = (i + 0.5f) / float(nx) > 0.5f;
      for (const auto& tri : {Triangle{id(i, j), id(i + 1, j), id(i + 1, j + 1)}, Triangle{id(i, j), id(i + 1, j + 1), id(i, j + 1)}}) {
        const FaceId f = mesh.add_face(tri[0], tri[1], tri[2]);
        for (int k = 0; k < 3; ++k) {
          const glm::vec3 p = mesh.position(tri[k]);
          uv[SurfaceMesh::corner(f, k)] = {p.x + (right ? 1.0f : 0.0f), p.y};
          normal[SurfaceMesh::corner(f, k)] = {0.0f, 0.0f, 1.0f};
        }
      }
    }
  return mesh;
}

SurfaceMesh make_needle_fan() {
  SurfaceMesh mesh;
  const float one_up = std::nextafter(1.0f, 2.0f);
  const VertexId x = mesh.add_vertex({0, 1, 0}), p = mesh.add_vertex({1, 0.5f, 0}), a = mesh.add_vertex({1, 1, 0}),
                 b = mesh.add_vertex({1, one_up, 0}), q = mesh.add_vertex({1, 1.5f, 0});
  mesh.add_face(x, p, a);
  mesh.add_face(x, a, b);
  mesh.add_face(x, b, q);
  return mesh;
}

SurfaceMesh make_tube(int around, int along, float radius, float length) {
  SurfaceMesh mesh;
  auto ring = [&](int j, int i) { return VertexId(static_cast<std::uint32_t>(j * around + (i % around))); };
  for (int j = 0; j <= along; ++j)
    for (int i = 0; i < around; ++i) {
      const float a = 2.0f * float(M_PI) * float(i) / float(around);
      mesh.add_vertex({radius * std::cos(a), length * float(j) / float(along), -radius * std::sin(a)});
    }
  const VertexId bottom = mesh.add_vertex({0.0f, 0.0f, 0.0f});
  const VertexId top = mesh.add_vertex({0.0f, length, 0.0f});
  for (int j = 0; j < along; ++j)
    for (int i = 0; i < around; ++i) {
      mesh.add_face(ring(j, i), ring(j, i + 1), ring(j + 1, i + 1));
      mesh.add_face(ring(j, i), ring(j + 1, i + 1), ring(j + 1, i));
    }
  for (int i = 0; i < around; ++i) {
    mesh.add_face(bottom, ring(0, i + 1), ring(0, i));
    mesh.add_face(top, ring(along, i), ring(along, i + 1));
  }
  return mesh;
}

Model make_skinned_tube_model() {
  Model model;
  Primitive prim;
  prim.mesh = make_tube(16, 8, 0.5f, 4.0f);
  auto& joints = prim.mesh.vertex_attrs().add<glm::u16vec4>(attr::kJoints0);
  auto& weights = prim.mesh.vertex_attrs().add<glm::vec4>(attr::kWeights0);
  for (std::size_t v = 0; v < prim.mesh.vertex_count(); ++v) {
    const float y = prim.mesh.positions()[v].y / 4.0f;
    joints[v] = {0, 1, 0, 0};
    weights[v] = {1.0f - y, y, 0.0f, 0.0f};
    if (y == 0.0f) joints[v][1] = 0;
  }
  model.meshes.push_back({"tube", {}, ""});
  model.meshes[0].primitives.push_back(std::move(prim));
  Node mesh_node;
  mesh_node.name = "tube";
  mesh_node.mesh = 0;
  mesh_node.skin = 0;
  Node root_joint;
  root_joint.name = "joint0";
  root_joint.children = {3};
  Node scene_root;
  scene_root.name = "root";
  scene_root.children = {1};
  Node tip_joint;
  tip_joint.name = "joint1";
  tip_joint.translation = {0.0f, 2.0f, 0.0f};
  model.nodes = {mesh_node, root_joint, scene_root, tip_joint};
  model.nodes[1].children = {3};
  model.scenes = {{0, 2}};
  Skin skin;
  skin.joints = {1, 3};
  skin.inverse_bind_matrices = {glm::mat4(1.0f), glm::inverse(glm::translate(glm::mat4(1.0f), glm::vec3(0, 2, 0)))};
  skin.skeleton = 2;
  model.skins.push_back(skin);
  Animation anim;
  anim.name = "bend";
  AnimationSampler s;
  s.input = {0.0f, 1.0f, 2.0f};
  const glm::quat q0(1, 0, 0, 0), q1 = glm::angleAxis(glm::radians(60.0f), glm::vec3(0, 0, 1));
  s.output = {q0.x, q0.y, q0.z, q0.w, q1.x, q1.y, q1.z, q1.w, q0.x, q0.y, q0.z, q0.w};
  s.components = 4;
  anim.samplers.push_back(s);
  anim.channels.push_back({0, 3, AnimationPath::Rotation});
  model.animations.push_back(anim);
  model.materials.push_back({"red", R"({"name":"red","pbrMetallicRoughness":{"baseColorFactor":[1,0,0,1]}})"});
  model.meshes[0].primitives[0].material = 0;
  return model;
}

Model make_morph_tube_model() {
  Model model = make_skinned_tube_model();
  SurfaceMesh& mesh = model.meshes[0].primitives[0].mesh;
  auto& va = mesh.vertex_attrs();
  auto& swell = va.add<glm::vec3>(attr::morph_position_name(0));
  auto& lean = va.add<glm::vec3>(attr::morph_position_name(1));
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const glm::vec3 p = mesh.positions()[v];
    swell[v] = 0.6f * std::sin(float(M_PI) * p.y / 4.0f) * glm::vec3(p.x, 0.0f, p.z);
    lean[v] = {0.4f * (p.y / 4.0f) * (p.y / 4.0f), 0.0f, 0.0f};
  }
  auto& normals = mesh.corner_attrs().add<glm::vec3>(attr::kNormal);
  auto& swell_normals = mesh.corner_attrs().add<glm::vec3>(attr::morph_normal_name(0));
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 p = mesh.positions()[t[k].index];
      const glm::vec3 radial(p.x, 0.0f, p.z);
      const bool cap_centre = glm::length(radial) < 1e-6f;
      const glm::vec3 face_n = glm::normalize(glm::cross(mesh.positions()[t[1].index] - mesh.positions()[t[0].index],
                                                         mesh.positions()[t[2].index] - mesh.positions()[t[0].index]));
      const bool cap_face = std::abs(face_n.y) > 0.9f;
      normals[SurfaceMesh::corner(f, k)] = cap_face || cap_centre ? face_n : glm::normalize(radial);
      swell_normals[SurfaceMesh::corner(f, k)] = {0.0f, 0.25f, 0.0f};
    }
  });
  model.meshes[0].weights = {0.1f, 0.2f};
  model.meshes[0].target_names = {"swell", "lean"};
  AnimationSampler w;
  w.input = {0.0f, 1.0f, 2.0f};
  w.output = {0.5f, 0.8f, 1.0f, 0.0f, 0.0f, 1.0f};
  w.components = 2;
  Animation& anim = model.animations[0];
  anim.samplers.push_back(w);
  anim.channels.push_back({static_cast<int>(anim.samplers.size() - 1), 0, AnimationPath::Weights});
  return model;
}

std::vector<VertexId> pinched_vertices(const SurfaceMesh& mesh) {
  // Per vertex, its faces and a union-find over them joined by the other corner they share.
  std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> around(mesh.vertex_count());  // (other, face)
  mesh.for_each_face([&](FaceId f, const Triangle& t) {
    for (int k = 0; k < 3; ++k) {
      around[t[k].index].emplace_back(t[(k + 1) % 3].index, f.index);
      around[t[k].index].emplace_back(t[(k + 2) % 3].index, f.index);
    }
  });
  std::vector<VertexId> out;
  for (std::uint32_t v = 0; v < around.size(); ++v) {
    auto& list = around[v];
    if (list.size() < 4) continue;
    std::vector<std::uint32_t> faces;
    for (const auto& [u, f] : list) faces.push_back(f);
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    std::vector<std::uint32_t> parent(faces.size());
    for (std::uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
    auto slot = [&](std::uint32_t f) { return static_cast<std::uint32_t>(std::lower_bound(faces.begin(), faces.end(), f) - faces.begin()); };
    auto root = [&](std::uint32_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    std::sort(list.begin(), list.end());
    for (std::size_t i = 1; i < list.size(); ++i)
      if (list[i].first == list[i - 1].first) {
        const auto a = root(slot(list[i].second)), b = root(slot(list[i - 1].second));
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
      }
    std::size_t fans = 0;
    for (std::uint32_t i = 0; i < parent.size(); ++i) fans += root(i) == i;
    if (fans > 1) out.push_back(VertexId(v));
  }
  return out;
}

void expect_valid(const SurfaceMesh& mesh, std::size_t joint_count) {
  EXPECT_NO_THROW(validate_mesh(mesh, joint_count));
}

void follow_checked(Adjacency& adj, const SurfaceMesh& mesh, OpStatus status, const EditLog& log) {
  EXPECT_EQ(status, OpStatus::Ok);
  if (status != OpStatus::Ok) return;
  adj.apply(log);
  expect_adjacency_matches_rebuild(adj, mesh);
  expect_valid(mesh);
}

void expect_adjacency_matches_rebuild(const Adjacency& incremental, const SurfaceMesh& mesh) {
  const Adjacency rebuilt = Adjacency::build(mesh);
  ASSERT_EQ(incremental.vertex_count(), rebuilt.vertex_count());
  EXPECT_EQ(incremental.edge_count(), rebuilt.edge_count());
  EXPECT_TRUE(incremental == rebuilt) << "incremental adjacency differs from a full rebuild";
  EXPECT_EQ(incremental.boundary_edges().size(), rebuilt.boundary_edges().size());
  EXPECT_EQ(incremental.component_count(), rebuilt.component_count());
}

std::vector<std::string> asset_models() {
  std::vector<std::string> out;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(DEEPCUT_ASSETS_DIR)) {
    const auto ext = entry.path().extension().string();
    if (entry.is_regular_file() && (ext == ".glb" || ext == ".gltf")) out.push_back(entry.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::string> static_models() {
  std::vector<std::string> out = {std::string(DEEPCUT_ASSETS_DIR) + "/models/spot/spot.obj"};
  const std::string local = std::string(DEEPCUT_SHARED_MODELS_DIR) + "/local-only/";
  for (const char* rel : {"stanford-bunny/stanford-bunny.obj", "bunny-libigl/bunny.off", "fandisk/fandisk-libigl.off",
                          "fertility/fertility.off", "horse/horse.ply", "armadillo/armadillo.obj",
                          "cactus-cagedeform/cactus.obj"})
    if (std::filesystem::is_regular_file(local + rel)) out.push_back(local + rel);
  return out;
}

glm::vec3 point_in_triangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, float s, float r) {
  if (s + r > 1.0f) s = 1.0f - s, r = 1.0f - r;
  return a + s * (b - a) + r * (c - a);
}

}  // namespace deepcut::test
