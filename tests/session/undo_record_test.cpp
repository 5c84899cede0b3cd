// SPDX-License-Identifier: MIT
// Undo by edit record: for seeded sequences of drills, tears and cuts through a Session, the
// change every step reports (apply, undo, redo) equals diff_models of copies taken before and
// after it, undo and redo give back those copies byte for byte, the posed model follows local
// undos and redos as a fresh build would, and the bytes the undo stack holds for a small drill on
// a big generated mesh follow the edit, not the model.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "deepcut/core/generate/cactus.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/model_change.h"
#include "deepcut/core/posed_model.h"
#include "session.h"
#include "posed_checks.h"

namespace deepcut::session {
namespace {

/// The model's bytes: every primitive's arrays (room reserved included).
std::size_t model_bytes(const Model& model) {
  std::size_t out = 0;
  for (const Mesh& m : model.meshes)
    for (const Primitive& p : m.primitives) out += p.mesh.capacity_bytes();
  return out;
}

/// Every element of both models, byte for byte (faces, deleted marks, attribute arrays), and the
/// small parts.
void expect_same(const Model& a, const Model& b, const std::string& when) {
  ASSERT_TRUE(same_structure(a, b)) << when;
  EXPECT_EQ(a.extras_json, b.extras_json) << when;
  const ModelChange d = diff_models(a, b);
  EXPECT_TRUE(d.empty()) << when << ": " << d.primitives.size() << " primitives differ";
}

void expect_change(const ModelChange& got, const ModelChange& want, const std::string& when) {
  ASSERT_EQ(got.structure, want.structure) << when;
  if (want.structure) return;
  ASSERT_EQ(got.primitives.size(), want.primitives.size()) << when;
  for (std::size_t i = 0; i < want.primitives.size(); ++i) {
    const PrimitiveChange &g = got.primitives[i], &w = want.primitives[i];
    EXPECT_EQ(g.mesh, w.mesh) << when;
    EXPECT_EQ(g.primitive, w.primitive) << when;
    EXPECT_EQ(g.vertices_before, w.vertices_before) << when;
    EXPECT_EQ(g.faces_before, w.faces_before) << when;
    EXPECT_TRUE(g.vertices == w.vertices) << when << ": " << g.vertices.size() << " vertices vs " << w.vertices.size();
    EXPECT_TRUE(g.faces == w.faces) << when << ": " << g.faces.size() << " faces vs " << w.faces.size();
  }
}

bool same_mesh(const SurfaceMesh& a, const SurfaceMesh& b) {
  PrimitiveChange d;
  return diff_meshes(a, b, d) && d.vertices.empty() && d.faces.empty() && d.vertices_before == b.vertex_count() &&
         d.faces_before == b.face_slots();
}

const SurfaceMesh& mesh_at(const Model& model, int mesh, int primitive) {
  return model.meshes.at(static_cast<std::size_t>(mesh)).primitives.at(static_cast<std::size_t>(primitive)).mesh;
}

/// A mapped structural change says truly what became of the primitives from `before` to `after`:
/// every primitive after is kept (the same content as at its place before) or arrived, every one
/// before is kept or left, and a content arriving with a tag seen leave earlier (`contents`) is
/// that content, byte for byte.
void expect_mapping(const ModelChange& got, const Model& before, const Model& after,
                    std::map<std::uint64_t, SurfaceMesh>& contents, const std::string& when) {
  if (!got.structure) return;
  ASSERT_TRUE(got.mapped) << when;
  std::map<std::pair<int, int>, int> now, then;  // places counted
  for (const PrimitiveKept& k : got.kept) {
    ++now[{k.mesh, k.primitive}];
    ++then[{k.mesh_before, k.primitive_before}];
    EXPECT_TRUE(same_mesh(mesh_at(before, k.mesh_before, k.primitive_before), mesh_at(after, k.mesh, k.primitive))) << when;
  }
  for (const PrimitiveContent& l : got.left) {
    ++then[{l.mesh, l.primitive}];
    contents[l.tag] = mesh_at(before, l.mesh, l.primitive);
  }
  for (const PrimitiveContent& a : got.arrived) {
    ++now[{a.mesh, a.primitive}];
    const auto it = contents.find(a.tag);
    if (it != contents.end()) {
      EXPECT_TRUE(same_mesh(it->second, mesh_at(after, a.mesh, a.primitive))) << when;
    }
    contents[a.tag] = mesh_at(after, a.mesh, a.primitive);
  }
  auto expect_each_once = [&](const Model& model, const std::map<std::pair<int, int>, int>& counted) {
    std::size_t count = 0;
    for (std::size_t mi = 0; mi < model.meshes.size(); ++mi)
      for (std::size_t pi = 0; pi < model.meshes[mi].primitives.size(); ++pi) {
        ++count;
        const auto it = counted.find({static_cast<int>(mi), static_cast<int>(pi)});
        EXPECT_TRUE(it != counted.end() && it->second == 1) << when << ": primitive " << mi << "/" << pi;
      }
    EXPECT_EQ(counted.size(), count) << when;
  };
  expect_each_once(before, then);
  expect_each_once(after, now);
}

/// The posed model, when the session has one, equals a fresh build at its pose.
void expect_posed_fresh(const Session& session, const std::string& when) {
  const PosedModel* posed = session.posed_model();
  if (!posed) return;
  EXPECT_EQ(test::difference_from_fresh_build(*posed, *session.current()), "") << when;
}

/// Seeded operations around the middle of `box` (a linear congruential sequence).
class Operations {
 public:
  Operations(const BoundingBox& box, std::uint32_t seed) : box_(box), state_(seed) {}
  float next() {
    state_ = state_ * 1664525u + 1013904223u;
    return static_cast<float>(state_ >> 8) / static_cast<float>(1u << 24);
  }
  glm::vec3 centre() const { return 0.5f * (box_.min + box_.max); }
  float size() const { return box_.diagonal(); }
  Operation drill(float radius) {
    const glm::vec3 c = centre() + glm::vec3((next() - 0.5f) * 0.1f * size(), (next() - 0.5f) * 0.6f * size(), 0.0f);
    DrillOperation d;
    d.cylinder = {c - glm::vec3(0.0f, 0.0f, size()), c + glm::vec3(0.0f, 0.0f, size()), radius * size()};
    d.options.wall = next() < 0.3f;
    return Operation{d, -1, 0.0f};
  }
  Operation tear() {
    const glm::vec3 d(0.0f, 0.0f, -1.0f), up(0.0f, 1.0f, 0.0f);
    const glm::vec3 c = centre() + glm::vec3((next() - 0.5f) * 0.2f * size(), (next() - 0.5f) * 0.4f * size(), 0.0f);
    const float depth = 0.5f * (box_.max.z - box_.min.z), height = 0.1f * (box_.max.y - box_.min.y);
    TearOperation t;
    t.start = {c - 1.5f * depth * d + height * up, c + height * up};
    t.end = {c - 1.5f * depth * d - height * up, c - height * up};
    return Operation{t, -1, 0.0f};
  }
  Operation cut() {
    CutOperation cut;
    cut.plane.point = centre() + glm::vec3(0.0f, (next() - 0.5f) * 0.6f * size(), 0.0f);
    cut.plane.normal = glm::vec3(next() - 0.5f, 1.0f, next() - 0.5f);
    return Operation{cut, -1, 0.0f};
  }
  Operation any() {
    const float r = next();
    return r < 0.45f ? drill(0.01f + 0.02f * next()) : r < 0.85f ? tear() : cut();
  }

 private:
  BoundingBox box_;
  std::uint32_t state_;
};

BoundingBox rest_bounds(const Model& model) {
  BoundingBox box;
  const PosedModel rest = PosedModel::build(model, -1, 0.0f);
  for (const auto& [key, mesh] : rest.instances()) box.add(mesh.bounds);
  return box;
}

std::shared_ptr<const Model> cactus(std::size_t triangles) {
  CactusOptions options;
  options.target_triangles = triangles;
  Model model = make_cactus(options);
  reserve_for_operations(model);
  return std::make_shared<const Model>(std::move(model));
}

TEST(UndoRecordTest, every_step_reports_what_diff_models_finds_and_undo_redo_are_exact) {
  for (const std::uint32_t seed : {1u, 2u, 3u}) {
    Session session;
    session.open(cactus(20000));
    ASSERT_TRUE(session.refresh_posed_model(-1, 0.0f));
    Operations ops(rest_bounds(*session.current()), seed);
    std::vector<Model> states = {*session.current()};  // copies, after each step
    std::map<std::uint64_t, SurfaceMesh> contents;      // by tag, as they left or arrived
    int mapped = 0;
    for (int i = 0; i < 12; ++i) {
      const std::string when = "seed " + std::to_string(seed) + " operation " + std::to_string(i);
      const Applied applied = session.apply(ops.any());
      if (applied.result.status != OpStatus::Ok) {
        EXPECT_TRUE(applied.change.empty()) << when;
        continue;
      }
      expect_change(applied.change, diff_models(states.back(), *session.current()), when);
      expect_mapping(applied.change, states.back(), *session.current(), contents, when);
      mapped += applied.change.mapped;
      states.push_back(*session.current());
      expect_posed_fresh(session, when);
    }
    EXPECT_GE(mapped, 1) << "seed " << seed << ": cuts are mapped structural steps";
    ASSERT_GE(states.size(), 6u);
    for (std::size_t i = states.size() - 1; i-- > 0;) {
      const std::string when = "seed " + std::to_string(seed) + " undo to " + std::to_string(i);
      const ModelChange change = session.undo();
      expect_change(change, diff_models(states[i + 1], states[i]), when);
      expect_mapping(change, states[i + 1], states[i], contents, when);
      expect_same(*session.current(), states[i], when);
      expect_posed_fresh(session, when);
    }
    for (std::size_t i = 1; i < states.size(); ++i) {
      const std::string when = "seed " + std::to_string(seed) + " redo to " + std::to_string(i);
      const ModelChange change = session.redo();
      expect_change(change, diff_models(states[i - 1], states[i]), when);
      expect_mapping(change, states[i - 1], states[i], contents, when);
      expect_same(*session.current(), states[i], when);
      expect_posed_fresh(session, when);
    }
    // Half undone, a new operation on the followed posed model drops the rest.
    for (std::size_t i = 0; i < states.size() / 2; ++i) session.undo();
    const Applied applied = session.apply(ops.drill(0.02f));
    if (applied.result.status == OpStatus::Ok) expect_posed_fresh(session, "after undo then drill");
    EXPECT_FALSE(session.can_redo());
  }
}

// done_bytes counts the steps an apply keeps (it drops those undone): the studio bench reads a
// new step's bytes as undo_bytes() after the apply less done_bytes() before it.
TEST(UndoRecordTest, done_bytes_counts_the_steps_an_apply_keeps) {
  Session session;
  session.open(cactus(20000));
  Operations ops(rest_bounds(*session.current()), 5);
  const auto drill = [&] {
    for (int tries = 0; tries < 20; ++tries)
      if (session.apply(ops.drill(0.01f)).result.status == OpStatus::Ok) return;
    FAIL() << "the drills keep missing the model";
  };
  EXPECT_EQ(session.done_bytes(), session.undo_bytes());
  drill();
  drill();
  EXPECT_EQ(session.done_bytes(), session.undo_bytes());
  session.undo();
  const std::size_t kept = session.done_bytes();
  EXPECT_LT(kept, session.undo_bytes()) << "the step undone is held but not counted as done";
  drill();
  EXPECT_FALSE(session.can_redo());
  EXPECT_EQ(session.done_bytes(), session.undo_bytes());
  EXPECT_GT(session.undo_bytes(), kept) << "the new step holds what its drill touched";
}

TEST(UndoRecordTest, a_small_drill_on_a_big_mesh_holds_bytes_of_the_edit_not_of_the_model) {
  Session session;
  session.open(cactus(400000));
  const std::size_t model = model_bytes(*session.current());
  Operations ops(rest_bounds(*session.current()), 11);
  std::size_t held = session.undo_bytes();
  int drills = 0;
  for (int i = 0; i < 10; ++i) {
    Operation op = ops.drill(0.004f);
    std::get<DrillOperation>(op.params).options.wall = false;
    if (session.apply(op).result.status != OpStatus::Ok) continue;
    ++drills;
    const std::size_t now = session.undo_bytes();
    std::printf("drill %d: the undo stack grew by %zu bytes (model %zu bytes)\n", i, now - held, model);
    // Each step holds what it touched: far below the model (a copy would be 100%).
    EXPECT_LT(now - held, model / 100) << "drill " << i << ": " << (now - held) << " bytes of " << model;
    EXPECT_LT(now - held, std::size_t(1) << 20) << "drill " << i;
    held = now;
  }
  EXPECT_GE(drills, 5);
  // A longer session of small tears as well: the stack stays a small fraction of the model.
  for (int i = 0; i < 10; ++i) session.apply(ops.tear());
  EXPECT_LT(session.undo_bytes(), model / 20) << session.undo_bytes() << " bytes of " << model;
  const Model copy = *session.current();
  while (session.can_undo()) session.undo();
  while (session.can_redo()) session.redo();
  expect_same(*session.current(), copy, "after undo and redo all");
}

TEST(UndoRecordTest, a_tear_on_a_shared_mesh_and_a_walled_drill_are_structure_and_exact) {
  // Two nodes drawing one mesh: a tear copies it for the instance it tears.
  Model model = *cactus(20000);
  Node twin = model.nodes[0];
  for (Node& n : model.nodes)
    if (n.mesh >= 0) twin = n;
  twin.children.clear();
  twin.name = "twin";
  twin.translation += glm::vec3(100.0f, 0.0f, 0.0f);
  model.nodes.push_back(twin);
  model.scenes[0].push_back(static_cast<int>(model.nodes.size() - 1));
  Session session;
  session.open(std::make_shared<const Model>(model));
  Operations ops(rest_bounds(model), 5);
  int structural = 0;
  std::vector<Model> states = {*session.current()};
  for (int i = 0; i < 6; ++i) {
    Operation op = i % 2 ? ops.tear() : ops.drill(0.02f);
    if (i % 2 == 0) std::get<DrillOperation>(op.params).options.wall = true;
    const Applied applied = session.apply(op);
    if (applied.result.status != OpStatus::Ok) continue;
    structural += applied.change.structure;
    expect_change(applied.change, diff_models(states.back(), *session.current()), "operation " + std::to_string(i));
    states.push_back(*session.current());
  }
  EXPECT_GE(structural, 1);
  for (std::size_t i = states.size() - 1; i-- > 0;) {
    session.undo();
    expect_same(*session.current(), states[i], "undo to " + std::to_string(i));
  }
  for (std::size_t i = 1; i < states.size(); ++i) {
    session.redo();
    expect_same(*session.current(), states[i], "redo to " + std::to_string(i));
  }
}

/// Undoes every step then redoes them, `cycles` times, each state byte for byte.
void expect_cycles(Session& session, const std::vector<Model>& states, int cycles, const std::string& what) {
  for (int cycle = 0; cycle < cycles; ++cycle) {
    for (std::size_t i = states.size() - 1; i-- > 0;) {
      session.undo();
      const std::string when = what + ": cycle " + std::to_string(cycle) + " undo to " + std::to_string(i);
      expect_same(*session.current(), states[i], when);
    }
    for (std::size_t i = 1; i < states.size(); ++i) {
      session.redo();
      const std::string when = what + ": cycle " + std::to_string(cycle) + " redo to " + std::to_string(i);
      expect_same(*session.current(), states[i], when);
    }
  }
}

TEST(UndoRecordTest, a_cut_keeps_its_largest_piece_in_place_and_its_step_holds_what_no_piece_holds) {
  // The cut splits the watched primitive in place (one piece keeps the arrays); the step
  // keeps which elements each piece holds and the slots none holds, and puts the primitive back
  // together from the pieces on undo. Cuts of pieces, into components, keeping one side (the
  // step then holds the dropped side) and capped (copied out as before) are all exact.
  Session session;
  session.open(cactus(60000));
  ASSERT_TRUE(session.refresh_posed_model(-1, 0.0f));
  Operations ops(rest_bounds(*session.current()), 21);
  std::vector<Model> states = {*session.current()};
  int small = 0;
  for (int i = 0; i < 8; ++i) {
    Operation op = ops.cut();
    CutOptions& options = std::get<CutOperation>(op.params).options;
    options.split_components = i == 2;
    options.keep = i == 5 ? CutKeep::Positive : CutKeep::Both;
    options.cap = i == 1;
    const std::size_t held = session.undo_bytes(), model = model_bytes(*session.current());
    if (session.apply(op).result.status != OpStatus::Ok) {
      std::printf("cut %d: missed\n", i);
      continue;
    }
    // Signed: a step that is not exact clears the steps before it, so the bytes may drop.
    const long long step = static_cast<long long>(session.undo_bytes()) - static_cast<long long>(held);
    std::printf("cut %d: the step holds %lld bytes (model %zu bytes)\n", i, step, model);
    if (!options.cap && options.keep == CutKeep::Both) {
      EXPECT_LT(step, static_cast<long long>(model / 10)) << "cut " << i;
      ++small;
    }
    states.push_back(*session.current());
  }
  EXPECT_GE(small, 3);
  ASSERT_GE(states.size(), 5u);
  expect_cycles(session, states, 3, "cuts");
}

TEST(UndoRecordTest, one_step_over_cuts_of_pieces_and_drills_into_them_is_exact) {
  // One recording over a whole history: later operations cut and drill the pieces of earlier
  // cuts, so the primitive a cut split is put back together before its pieces change.
  for (const std::uint32_t seed : {3u, 8u}) {
    Session session(Session::Undo::None);
    session.open(cactus(30000));
    ASSERT_TRUE(session.refresh_posed_model(-1, 0.0f));
    Operations ops(rest_bounds(*session.current()), seed);
    History history;
    for (int i = 0; i < 7; ++i)
      history.operations.push_back(i % 3 == 2 ? ops.drill(0.02f) : i == 4 ? ops.tear() : ops.cut());
    const Model before = *session.current();
    session.apply_history(history, "history");
    const Model after = *session.current();
    ASSERT_TRUE(session.can_undo());
    expect_cycles(session, {before, after}, 2, "seed " + std::to_string(seed));

    Session one_by_one;  // the same operations, one step each
    one_by_one.open(std::make_shared<const Model>(before));
    for (const Operation& op : history.operations) one_by_one.apply(op);
    expect_same(*one_by_one.current(), after, "seed " + std::to_string(seed) + ": one by one");
  }
}

}  // namespace
}  // namespace deepcut::session
