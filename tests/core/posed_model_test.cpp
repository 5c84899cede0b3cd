// SPDX-License-Identifier: MIT
// PosedModel: the model-level operations' preprocessing, followed through random drills and tears,
// must equal a fresh build, and the operations must give the same model with and without it.
#include "deepcut/core/posed_model.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <variant>
#include <vector>

#include "deepcut/core/generate/cactus.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/model_undo.h"
#include "deepcut/core/operation_room.h"
#include "deepcut/core/ops/operation.h"
#include "deepcut/core/skinning.h"
#include "fixtures.h"
#include "parallel_beside.h"
#include "posed_checks.h"
#include "thread_count.h"

namespace deepcut {
namespace {

// Every attribute array of `a` and `b` element for element, byte for byte.
void expect_same_attributes(const AttributeSet& a, const AttributeSet& b, const std::string& where) {
  ASSERT_EQ(a.names(), b.names()) << where;
  ASSERT_EQ(a.size(), b.size()) << where;
  for (const auto& name : a.names()) {
    const AttributeArrayBase* x = a.base(name);
    const AttributeArrayBase* y = b.base(name);
    ASSERT_EQ(x->element_bytes(), y->element_bytes()) << where << " " << name;
    for (std::size_t i = 0; i < x->size(); ++i)
      ASSERT_EQ(std::memcmp(x->element_data(i), y->element_data(i), x->element_bytes()), 0)
          << where << " " << name << " element " << i;
  }
}

// The two models hold the same data: nodes' meshes and skins, materials, history, and every
// mesh's face slots, deleted marks and attributes.
void expect_identical(const Model& a, const Model& b) {
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    EXPECT_EQ(a.nodes[i].mesh, b.nodes[i].mesh) << "node " << i;
    EXPECT_EQ(a.nodes[i].skin, b.nodes[i].skin) << "node " << i;
  }
  ASSERT_EQ(a.materials.size(), b.materials.size());
  EXPECT_EQ(a.extras_json, b.extras_json);
  ASSERT_EQ(a.meshes.size(), b.meshes.size());
  for (std::size_t m = 0; m < a.meshes.size(); ++m) {
    ASSERT_EQ(a.meshes[m].primitives.size(), b.meshes[m].primitives.size()) << "mesh " << m;
    for (std::size_t p = 0; p < a.meshes[m].primitives.size(); ++p) {
      const std::string where = "mesh " + std::to_string(m) + " primitive " + std::to_string(p);
      const Primitive &x = a.meshes[m].primitives[p], &y = b.meshes[m].primitives[p];
      EXPECT_EQ(x.material, y.material) << where;
      ASSERT_EQ(x.mesh.face_slots(), y.mesh.face_slots()) << where;
      for (std::uint32_t f = 0; f < x.mesh.face_slots(); ++f) {
        ASSERT_EQ(x.mesh.is_deleted(FaceId(f)), y.mesh.is_deleted(FaceId(f))) << where << " face " << f;
        ASSERT_EQ(x.mesh.face(FaceId(f)), y.mesh.face(FaceId(f))) << where << " face " << f;
      }
      expect_same_attributes(x.mesh.vertex_attrs(), y.mesh.vertex_attrs(), where + " vertex");
      expect_same_attributes(x.mesh.face_attrs(), y.mesh.face_attrs(), where + " face");
      expect_same_attributes(x.mesh.corner_attrs(), y.mesh.corner_attrs(), where + " corner");
    }
  }
}

BoundingBox face_box(const SurfaceMesh& mesh, const std::vector<glm::vec3>& posed, FaceId f) {
  BoundingBox b;
  for (VertexId v : mesh.face(f)) b.add(posed[v.index]);
  return b;
}

bool overlaps(const BoundingBox& a, const BoundingBox& b) {
  return a.min.x <= b.max.x && b.min.x <= a.max.x && a.min.y <= b.max.y && b.min.y <= a.max.y &&
         a.min.z <= b.max.z && b.min.z <= a.max.z;
}

// The faces of a query's answer whose posed box really meets `box`.
std::vector<FaceId> meeting(const std::vector<FaceId>& answer, const SurfaceMesh& mesh,
                            const std::vector<glm::vec3>& posed, const BoundingBox& box) {
  std::vector<FaceId> out;
  for (FaceId f : answer)
    if (overlaps(face_box(mesh, posed, f), box)) out.push_back(f);
  return out;
}

// The followed index equals a fresh build of `model`: same instances, the same posed positions,
// linear maps and bounds bit for bit, and grids whose answers to box queries hold the same faces
// (those of the brute-force answer) wherever the query lands.
void expect_index_matches_rebuild(const PosedModel& index, const Model& model, std::mt19937& rng) {
  ASSERT_TRUE(index.valid());
  const PosedModel fresh = PosedModel::build(model, index.key());
  ASSERT_EQ(index.size(), fresh.size());
  for (const auto& [key, want] : fresh.instances()) {
    const PosedMesh* got = index.find(key.first, key.second);
    ASSERT_NE(got, nullptr) << "node " << key.first << " primitive " << key.second;
    const SurfaceMesh& mesh = model.meshes[static_cast<std::size_t>(want.mesh)].primitives[static_cast<std::size_t>(key.second)].mesh;
    EXPECT_EQ(got->grid.face_count(), mesh.face_count());
    std::vector<FaceId> live;
    mesh.for_each_face([&](FaceId f, const Triangle&) { live.push_back(f); });
    if (live.empty()) continue;
    const float size = want.bounds.diagonal();
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int q = 0; q < 40; ++q) {
      // A box around a random live face (every face in turn near the tool's path), grown by up
      // to 5% of the instance's size.
      const FaceId at = live[std::uniform_int_distribution<std::size_t>(0, live.size() - 1)(rng)];
      BoundingBox box = face_box(mesh, want.posed, at);
      const glm::vec3 grow(u(rng) * 0.05f * size);
      box.min -= grow;
      box.max += grow;
      std::vector<FaceId> brute;
      for (FaceId f : live)
        if (overlaps(face_box(mesh, want.posed, f), box)) brute.push_back(f);
      ASSERT_EQ(meeting(got->grid.query_box(box), mesh, want.posed, box), brute) << "followed grid, query " << q;
      ASSERT_EQ(meeting(want.grid.query_box(box), mesh, want.posed, box), brute) << "fresh grid, query " << q;
    }
  }
}

// Random drills and tears through the posed surface (as a designer places them), some missing.
class OperationMaker {
 public:
  OperationMaker(unsigned seed) : rng_(seed) {}
  std::mt19937& rng() { return rng_; }
  float uniform(float a, float b) { return std::uniform_real_distribution<float>(a, b)(rng_); }
  glm::vec3 unit() {
    std::normal_distribution<float> g;
    glm::vec3 d;
    do d = {g(rng_), g(rng_), g(rng_)};
    while (glm::length(d) < 1e-3f);
    return glm::normalize(d);
  }

  // A point on the posed surface of a random instance and its normal (false for an empty model).
  bool surface_point(const PosedModel& index, const Model& model, glm::vec3& p, glm::vec3& n) {
    std::vector<const PosedMesh*> instances;
    for (const auto& [key, inst] : index.instances())
      if (model.meshes[static_cast<std::size_t>(inst.mesh)].primitives[static_cast<std::size_t>(key.second)].mesh.face_count() > 0)
        instances.push_back(&inst);
    if (instances.empty()) return false;
    const auto& inst = *instances[std::uniform_int_distribution<std::size_t>(0, instances.size() - 1)(rng_)];
    const SurfaceMesh& mesh = model.meshes[static_cast<std::size_t>(inst.mesh)].primitives[static_cast<std::size_t>(inst.primitive)].mesh;
    for (int attempt = 0; attempt < 100; ++attempt) {
      const FaceId f(std::uniform_int_distribution<std::uint32_t>(0, static_cast<std::uint32_t>(mesh.face_slots() - 1))(rng_));
      if (mesh.is_deleted(f)) continue;
      const auto& t = mesh.face(f);
      const glm::vec3 a = inst.posed[t[0].index], b = inst.posed[t[1].index], c = inst.posed[t[2].index];
      const glm::vec3 cr = glm::cross(b - a, c - a);
      if (!(glm::length(cr) > 0.0f)) continue;
      const float s = uniform(0.0f, 1.0f), r = uniform(0.0f, 1.0f);
      p = test::point_in_triangle(a, b, c, s, r);
      n = glm::normalize(cr);
      return true;
    }
    return false;
  }

  OperationParams make(const glm::vec3& p, const glm::vec3& n, float size) {
    if (uniform(0.0f, 1.0f) < 0.5f) {
      DrillOperation drill;
      const glm::vec3 axis = glm::normalize(-n + 0.4f * unit() + 1e-4f);
      drill.cylinder.radius = size * std::exp(uniform(std::log(0.01f), std::log(0.15f)));
      drill.cylinder.a = p - uniform(0.02f, 0.2f) * size * axis;
      drill.cylinder.b = p + uniform(0.02f, 1.2f) * size * axis;
      drill.options.wall = uniform(0.0f, 1.0f) < 0.5f;
      drill.options.min_rim_edges = uniform(0.0f, 1.0f) < 0.5f ? 12 : 32;
      return drill;
    }
    TearOperation tear;
    glm::vec3 t = glm::cross(n, unit());
    t = glm::length(t) > 1e-4f ? glm::normalize(t) : glm::normalize(glm::cross(n, glm::vec3(1, 0, 0)) + 1e-3f);
    const float length = uniform(0.03f, 0.3f) * size;
    const glm::vec3 blade = glm::normalize(n + 0.3f * unit());
    const float above = uniform(0.005f, 0.05f) * size, below = uniform(0.01f, 0.1f) * size;
    const glm::vec3 from = p - 0.5f * length * t, to = p + 0.5f * length * t;
    tear.start = {from + above * blade, from - below * blade};
    tear.end = {to + above * blade, to - below * blade};
    if (uniform(0.0f, 1.0f) < 0.3f) tear.options.width = 0.0f;
    return tear;
  }

 private:
  std::mt19937 rng_;
};

// Runs `steps` random drills and tears on two copies of `model`: one through the operations with
// a PosedModel kept across them, one without. After each: identical models, index == rebuild.
// What a tear or drill reported (the counts `deepcut apply` prints), comparable with ==.
std::vector<double> summary(const OperationResult& r) {
  std::vector<double> out{double(r.status)};
  if (const auto* t = std::get_if<ModelTearResult>(&r.result))
    out.insert(out.end(), {double(t->intersection_points), double(t->tear_vertices), double(t->slits), double(t->width)});
  if (const auto* d = std::get_if<ModelDrillResult>(&r.result)) {
    out.insert(out.end(), {double(d->rim_vertices.size()), double(d->triangles_removed), double(d->triangles_added)});
    out.insert(out.end(), d->rim_vertices.begin(), d->rim_vertices.end());
  }
  return out;
}

void check_random_sequence(const Model& model, int steps, unsigned seed) {
  Model cached = model, plain = model;
  OperationMaker maker(seed);
  int animation = model.animations.empty() ? -1 : 0;
  float time = model.animations.empty() ? 0.0f : 0.37f * model.animations[0].duration();
  PosedModel index = PosedModel::build(cached, animation, time);
  const float size = [&] {
    BoundingBox box;
    for (const auto& [key, inst] : index.instances()) box.add(inst.bounds);
    return box.diagonal();
  }();
  int applied = 0, drills = 0, tears = 0;
  for (int step = 0; step < steps; ++step) {
    SCOPED_TRACE("step " + std::to_string(step));
    if (!model.animations.empty() && step > 0 && step % 10 == 0)  // now and then another pose
      time = maker.uniform(0.0f, model.animations[0].duration());
    index.prepare(cached, animation, time);
    glm::vec3 p, n;
    if (!maker.surface_point(index, cached, p, n)) break;
    Operation op;
    op.params = maker.make(p, n, size);
    op.animation = animation;
    op.time = time;
    // A miss, ten sizes away (its radius stays above what float positions resolve out there,
    // min_drill_radius, or the drill refuses it instead of missing).
    if (step % 7 == 6) op.params = maker.make(p + 10.0f * size * n, n, 0.1f * size);
    const OperationResult a = apply_operation(cached, op, index);
    const OperationResult b = apply_operation(plain, op);
    ASSERT_EQ(a.status, b.status);
    ASSERT_EQ(a.result.index(), b.result.index());
    ASSERT_EQ(summary(a), summary(b));
    if (a.status == OpStatus::Ok) {
      ++applied;
      (std::holds_alternative<DrillOperation>(op.params) ? drills : tears)++;
    }
    expect_identical(cached, plain);
    expect_index_matches_rebuild(index, cached, maker.rng());
    if (::testing::Test::HasFatalFailure()) return;
  }
  EXPECT_GT(drills, 0);
  EXPECT_GT(tears, 0);
  EXPECT_GT(applied, steps / 3);
}

}  // namespace

TEST(PosedModelTest, skinned_tube_random_drills_and_tears_match_a_rebuild_and_the_uncached_path) {
  check_random_sequence(test::make_skinned_tube_model(), 40, 1);
}

TEST(PosedModelTest, morphing_tube_random_drills_and_tears_match_a_rebuild_and_the_uncached_path) {
  check_random_sequence(test::make_morph_tube_model(), 30, 11);
}

TEST(PosedModelTest, animated_cactus_random_drills_and_tears_match_a_rebuild_and_the_uncached_path) {
  CactusOptions options;
  options.target_triangles = 8000;
  check_random_sequence(make_cactus(options), 30, 2);
}

// A new instance's positions are posed beside the fill that sizes them (some chunks into a
// scratch array, copied after): positions, linear maps and bounds are the same bytes for every
// thread count, whether the fill runs before every chunk (none in scratch), after every chunk
// (all in scratch) or where the pool puts it, and the arrays keep their room to grow.
TEST(PosedModelTest, a_build_poses_the_same_bytes_for_every_thread_count) {
  CactusOptions options;
  options.target_triangles = 120000;  // about 60k vertices: several posing chunks
  const Model model = make_cactus(options);
  const int animation = model.animations.empty() ? -1 : 0;
  auto posed_bytes = [&](std::size_t threads, detail::BesideOrder order) {
    test::ThreadCount guard(threads);
    const PosedModel posed = [&] {
      const detail::BesideOrderForTests beside(order);
      return PosedModel::build(model, animation, 0.7f, PoseDetail::Positions);
    }();
    std::vector<unsigned char> out;
    auto append = [&out](const void* p, std::size_t n) {
      out.insert(out.end(), static_cast<const unsigned char*>(p), static_cast<const unsigned char*>(p) + n);
    };
    for (const auto& [key, inst] : posed.instances()) {
      EXPECT_GE(inst.posed.capacity(), operation_vertex_room(inst.posed.size()));
      append(inst.posed.data(), inst.posed.size() * sizeof(glm::vec3));
      append(inst.linear.data(), inst.linear.size() * sizeof(glm::mat3));
      append(&inst.bounds, sizeof(inst.bounds));
    }
    return out;
  };
  const std::vector<unsigned char> one = posed_bytes(1, detail::BesideOrder::Shared);
  ASSERT_GT(one.size(), 60000 * sizeof(glm::vec3));
  for (const auto order :
       {detail::BesideOrder::Shared, detail::BesideOrder::First, detail::BesideOrder::Last})
    for (const std::size_t threads : {1u, 2u, 3u, 8u})
      EXPECT_TRUE(posed_bytes(threads, order) == one) << int(order) << ", " << threads << " threads";
}

TEST(PosedModelTest, asset_models_random_drills_and_tears_match_a_rebuild_and_the_uncached_path) {
  unsigned seed = 3;
  for (const std::string& path : test::asset_models()) {
    SCOPED_TRACE(path);
    check_random_sequence(read_gltf(path), 12, seed++);
    if (HasFatalFailure()) return;
  }
}

TEST(PosedModelTest, follows_moved_vertices_and_shrinking_bounds) {
  // Operations may move existing vertices (VertexMoved): their posed positions, the bounds (which
  // shrink when an extreme vertex moves inward) and the grid cells of the faces around them follow.
  Model model = test::make_skinned_tube_model();
  const float t = 0.5f * model.animations[0].duration();
  PosedModel index = PosedModel::build(model, 0, t);
  SurfaceMesh& mesh = model.meshes[0].primitives[0].mesh;
  std::mt19937 rng(7);
  for (int round = 0; round < 20; ++round) {
    SCOPED_TRACE("round " + std::to_string(round));
    MeshEditor editor(mesh);
    const PosedMesh& inst = *index.find(0, 0);
    // The vertex at the top of the posed bounds, and a few random ones, move by up to a ring.
    std::uint32_t top = 0;
    for (std::uint32_t v = 0; v < inst.posed.size(); ++v)
      if (inst.posed[v].y > inst.posed[top].y) top = v;
    std::vector<std::uint32_t> which{top};
    for (int k = 0; k < 5; ++k)
      which.push_back(std::uniform_int_distribution<std::uint32_t>(0, static_cast<std::uint32_t>(mesh.vertex_count() - 1))(rng));
    std::uniform_real_distribution<float> u(-0.3f, 0.3f);
    for (std::uint32_t v : which)
      editor.move_vertex(VertexId(v), mesh.position(VertexId(v)) + glm::vec3(u(rng), u(rng) - 0.2f, u(rng)));
    // And a face split at its centre, so moves and additions come in one log.
    FaceId f;
    mesh.for_each_face([&](FaceId g, const Triangle&) { f = g; });
    const Triangle tri = mesh.face(f);
    const VertexId c = editor.add_vertex_in_triangle(tri, glm::vec3(1.0f / 3.0f));
    editor.remove_face(f);
    for (int k = 0; k < 3; ++k) editor.add_face({tri[k], tri[(k + 1) % 3], c});
    index.follow(model, 0, 0, mesh, editor.take_log());
    expect_index_matches_rebuild(index, model, rng);
    if (HasFatalFailure()) return;
  }
}

TEST(PosedModelTest, a_mesh_shared_by_two_instances_is_copied_for_the_drilled_one) {
  Model model = test::make_skinned_tube_model();
  // A second, rigid instance of the same mesh, moved aside.
  Node twin;
  twin.mesh = model.nodes[0].mesh;
  twin.translation = glm::vec3(10.0f, 0.0f, 0.0f);
  model.nodes.push_back(twin);
  model.scenes[0].push_back(static_cast<int>(model.nodes.size() - 1));
  Model plain = model;
  PosedModel index = PosedModel::build(model, -1, 0.0f);
  EXPECT_EQ(index.size(), 2u);
  DrillOptions options;
  options.wall = true;
  const Cylinder c{{10.0f, 2.0f, -3.0f}, {10.0f, 2.0f, 3.0f}, 0.3f};
  ASSERT_EQ(drill_model(model, index, c, options, -1, 0.0f).status, OpStatus::Ok);
  ASSERT_EQ(drill_model(plain, c, options).status, OpStatus::Ok);
  expect_identical(model, plain);
  EXPECT_NE(model.nodes.back().mesh, model.nodes[0].mesh) << "the drilled instance owns a copy";
  std::mt19937 rng(5);
  expect_index_matches_rebuild(index, model, rng);
}

TEST(PosedModelTest, another_pose_rebuilds_and_a_cut_invalidates) {
  Model model = test::make_skinned_tube_model();
  PosedModel index = PosedModel::build(model, -1, 0.0f);
  EXPECT_TRUE(index.matches(-1, 0.0f));
  const float t = model.animations[0].duration();
  Operation drill{DrillOperation{Cylinder{{0.0f, 2.0f, -3.0f}, {0.0f, 2.0f, 3.0f}, 0.3f}, {}}, 0, t};
  Model plain = model;
  ASSERT_EQ(apply_operation(model, drill, index).status, OpStatus::Ok);
  ASSERT_EQ(apply_operation(plain, drill).status, OpStatus::Ok);
  expect_identical(model, plain);
  EXPECT_TRUE(index.matches(0, t)) << "prepared for the operation's pose";
  std::mt19937 rng(6);
  expect_index_matches_rebuild(index, model, rng);
  Operation cut{CutOperation{Plane{{0.0f, 1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}}, {}}, 0, t};
  ASSERT_EQ(apply_operation(model, cut, index).status, OpStatus::Ok);
  EXPECT_FALSE(index.valid());
  ASSERT_EQ(apply_operation(plain, cut).status, OpStatus::Ok);
  ASSERT_EQ(apply_operation(model, drill, index).status, apply_operation(plain, drill).status);
  expect_identical(model, plain);
  expect_index_matches_rebuild(index, model, rng);
}

TEST(PosedModelTest, reserved_room_survives_copies_so_operations_on_snapshots_do_not_reallocate) {
  Model model = test::make_skinned_tube_model();
  reserve_for_operations(model);
  const SurfaceMesh& mesh = model.meshes[0].primitives[0].mesh;
  const std::size_t vertex_room = mesh.positions().capacity(), face_room = mesh.faces().capacity();
  EXPECT_GT(vertex_room, mesh.vertex_count());
  EXPECT_GT(face_room, mesh.face_slots());
  const Model snapshot = model;  // the studio copies its state before every operation
  const SurfaceMesh& copy = snapshot.meshes[0].primitives[0].mesh;
  EXPECT_GE(copy.positions().capacity(), vertex_room);
  EXPECT_GE(copy.faces().capacity(), face_room);
  const auto* weights = copy.vertex_attrs().find<glm::vec4>(attr::kWeights0);
  ASSERT_NE(weights, nullptr);
  EXPECT_GE(weights->data().capacity(), vertex_room);
  // A drill on the copy that stays within the room keeps the arrays where they were.
  const glm::vec3* positions = copy.positions().data();
  Model edited = snapshot;
  const glm::vec3* before = edited.meshes[0].primitives[0].mesh.positions().data();
  ASSERT_EQ(drill_model(edited, Cylinder{{0.0f, 2.0f, -3.0f}, {0.0f, 2.0f, 3.0f}, 0.3f}).status, OpStatus::Ok);
  EXPECT_EQ(edited.meshes[0].primitives[0].mesh.positions().data(), before) << "no reallocation";
  EXPECT_EQ(copy.positions().data(), positions);
}

TEST(PosedModelTest, a_small_drill_leaves_the_body_in_place_and_extracts_only_the_wall) {
  Model model = test::make_skinned_tube_model();
  const std::size_t slots = model.meshes[0].primitives[0].mesh.face_slots();
  DrillOptions options;
  options.wall = true;
  const ModelDrillResult r =
      drill_model(model, Cylinder{{0.0f, 2.0f, -3.0f}, {0.0f, 2.0f, 3.0f}, 0.3f}, options);
  ASSERT_EQ(r.status, OpStatus::Ok);
  ASSERT_EQ(model.meshes[0].primitives.size(), 2u);
  const SurfaceMesh& body = model.meshes[0].primitives[0].mesh;
  const SurfaceMesh& wall = model.meshes[0].primitives[1].mesh;
  EXPECT_GE(body.face_slots(), slots) << "edited in place: old face slots keep their ids";
  EXPECT_FALSE(body.face_attrs().contains(attr::kCutSurface));
  EXPECT_EQ(wall.face_count(), r.wall_triangles);
  EXPECT_EQ(wall.face_slots(), wall.face_count()) << "the wall primitive is compact";
  test::expect_valid(body, 2);
  test::expect_valid(wall, 2);
}

TEST(PosedModelTest, a_positions_copy_equals_a_positions_build_and_a_cut_given_it_matches_one_posing_itself) {
  Model model = make_cactus({});
  reserve_for_operations(model);
  const float t = 0.5f;
  const PosedModel full = PosedModel::build(model, 0, t);
  const PosedModel copy = full.positions_copy();
  const PosedModel fresh = PosedModel::build(model, 0, t, PoseDetail::Positions);
  ASSERT_TRUE(copy.matches(0, t));
  ASSERT_EQ(copy.size(), fresh.size());
  for (const auto& [key, inst] : fresh.instances()) {
    const PosedMesh* c = copy.find(key.first, key.second);
    ASSERT_NE(c, nullptr);
    EXPECT_TRUE(c->gridless);
    EXPECT_EQ(c->grid.face_count(), 0u);
    EXPECT_EQ(c->mesh, inst.mesh);
    EXPECT_EQ(c->posed, inst.posed);
    EXPECT_EQ(c->linear, inst.linear);
    EXPECT_EQ(c->bounds.min, inst.bounds.min);
    EXPECT_EQ(c->bounds.max, inst.bounds.max);
    EXPECT_GT(c->posed.capacity(), c->posed.size()) << "room to follow an operation";
  }
  // A cut given the copy makes the model a cut posing the model itself makes.
  Operation cut{CutOperation{Plane{model.meshes[0].primitives[0].mesh.bounds().min +
                                       0.5f * (model.meshes[0].primitives[0].mesh.bounds().max -
                                               model.meshes[0].primitives[0].mesh.bounds().min),
                                   {0.05f, 1.0f, 0.02f}},
                             {}},
                0, t};
  Model plain = model;
  PosedModel lent = copy;
  ASSERT_EQ(apply_operation(model, cut, lent).status, OpStatus::Ok);
  ASSERT_EQ(apply_operation(plain, cut).status, OpStatus::Ok);
  expect_identical(model, plain);
}

// positions_copy copies the linear maps in parts of 16384 (its grain), one task each, and the
// positions beside them (detail::parallel_for_beside): a primitive of more than two parts (the
// default cactus has fewer vertices than one) has a first, a middle and a last, shorter part,
// each of which must land at its own offset, whole, whether the positions are copied before every
// part, after every part or where the pool puts them.
TEST(PosedModelTest, a_positions_copy_of_a_primitive_of_several_parts_equals_its_source_element_for_element) {
  CactusOptions options;
  options.target_triangles = 100000;
  Model model = make_cactus(options);
  reserve_for_operations(model);
  const PosedModel source = PosedModel::build(model, 0, 0.5f, PoseDetail::Positions);
  constexpr std::size_t kPart = 16384;
  for (const auto order :
       {detail::BesideOrder::Shared, detail::BesideOrder::First, detail::BesideOrder::Last}) {
    SCOPED_TRACE(static_cast<int>(order));
    const PosedModel copy = [&] {
      const detail::BesideOrderForTests beside(order);
      return source.positions_copy();
    }();
    ASSERT_EQ(copy.size(), source.size());
    std::size_t largest = 0;
    for (const auto& [key, inst] : source.instances()) {
      const PosedMesh* c = copy.find(key.first, key.second);
      ASSERT_NE(c, nullptr);
      ASSERT_EQ(c->linear.size(), inst.linear.size());
      ASSERT_EQ(c->posed.size(), inst.posed.size());
      largest = std::max(largest, inst.linear.size());
      for (std::size_t v = 0; v < inst.linear.size(); ++v) {
        ASSERT_EQ(std::memcmp(&c->linear[v], &inst.linear[v], sizeof(glm::mat3)), 0) << "linear map " << v;
        ASSERT_EQ(std::memcmp(&c->posed[v], &inst.posed[v], sizeof(glm::vec3)), 0) << "position " << v;
      }
    }
    ASSERT_GT(largest, 2 * kPart) << "a primitive with a middle part";
    ASSERT_NE(largest % kPart, 0u) << "a shorter last part";
  }
}

namespace {

// Whether `a` and `b` hold the same values, bit for bit.
bool same_bits(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::vec3)) == 0;
}

const SurfaceMesh& primitive_of(const Model& m, int mesh, int primitive) {
  return m.meshes[static_cast<std::size_t>(mesh)].primitives[static_cast<std::size_t>(primitive)].mesh;
}

// A cut piece's corner normals written into a given array (how a spare's memory is reused) are
// bit-equal to the returned ones and to a fresh corner_normals, whatever the array held (NaN)
// and its size (empty, smaller, exact, bigger); an origin that does not fit falls back to the
// fresh computation.
TEST(PosedModelTest, corner_normals_written_into_an_array_equal_the_returned_ones) {
  Model model = test::make_morph_tube_model();
  const Model before = model;
  Operation op;
  op.params = CutOperation{};
  std::get<CutOperation>(op.params).plane.point = glm::vec3(0.0f, 1.8f, 0.0f);
  std::get<CutOperation>(op.params).plane.normal = glm::vec3(-0.1f, 1.0f, 0.2f);
  op.animation = 0;
  op.time = 0.5f;
  PosedModel posed;
  OperationResult result;
  {
    ModelRecorder recorder(model);  // (under a record, the cut says where its pieces came from)
    result = apply_operation(model, op, posed);
    recorder.finish();
  }
  ASSERT_EQ(result.status, OpStatus::Ok);
  const auto& origins = std::get<ModelCutResult>(result.result).origins;
  ASSERT_FALSE(origins.empty());
  const PosedModel posed_before = PosedModel::build(before, 0, 0.5f, PoseDetail::Positions);
  const PosedModel posed_after = PosedModel::build(model, 0, 0.5f, PoseDetail::Positions);
  const glm::vec3 nan(std::nanf(""));
  for (const auto& o : origins) {
    ASSERT_TRUE(o);
    const SurfaceMesh& source_mesh = primitive_of(before, o->mesh_before, o->primitive_before);
    const SurfaceMesh& mesh = primitive_of(model, o->mesh, o->primitive);
    const PosedMesh* from = posed_before.find(o->node_before, o->primitive_before);
    const PosedMesh* pose = posed_after.find(o->node, o->primitive);
    ASSERT_TRUE(from && pose);
    const std::vector<glm::vec3> source = from->corner_normals(source_mesh);
    const std::vector<glm::vec3> fresh = pose->corner_normals(mesh);
    const std::vector<glm::vec3> returned = pose->corner_normals(mesh, *o, source);
    ASSERT_EQ(fresh.size(), 3 * mesh.face_slots());
    EXPECT_TRUE(same_bits(returned, fresh)) << "the copy differs from a fresh computation";
    const std::size_t n = fresh.size();
    for (std::size_t size : {std::size_t(0), n / 2, n, 2 * n + 5}) {
      std::vector<glm::vec3> out(size, nan);
      pose->corner_normals(mesh, *o, source, out);
      EXPECT_TRUE(same_bits(out, returned)) << "written into " << size << " values";
    }
    // Room for the faces operations add, so the array grows in place and, set aside, takes a
    // larger piece (the pages past its corners untouched).
    const std::size_t room = operation_corner_room(mesh.face_slots());
    EXPECT_GE(fresh.capacity(), room) << "a fresh array has room to grow";
    EXPECT_GE(returned.capacity(), room) << "a copied array has room to grow";
    PrimitiveOrigin misfit = *o;
    misfit.faces.pop_back();
    std::vector<glm::vec3> out(n, nan);
    pose->corner_normals(mesh, misfit, source, out);
    EXPECT_TRUE(same_bits(out, fresh)) << "the fallback differs from a fresh computation";
  }
}

}  // namespace

}  // namespace deepcut
