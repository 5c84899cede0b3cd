// SPDX-License-Identifier: MIT
// The session without a window: apply, undo, redo, apply a history, edit a past operation and
// re-run the later ones, and 30 mixed cuts, tears and drills at poses undone and redone all the
// way, every state compared byte for byte (glTF export) and the posed model compared with a
// fresh build after each step; what it writes is what `deepcut apply` writes, and both refuse a
// drill that would swallow an instance alike. No display needed.
#include "session.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "deepcut/core/errors.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/operation_room.h"
#include "deepcut/core/posed_model.h"
#include "posed_checks.h"
#include "tools.h"

namespace deepcut::session {
namespace {

/// The mesh of instance (node, primitive) of `model`.
const SurfaceMesh* instance_surface(const Model& model, int node, int primitive) {
  const int mesh = model.nodes.at(static_cast<std::size_t>(node)).mesh;
  return &model.meshes.at(static_cast<std::size_t>(mesh)).primitives.at(static_cast<std::size_t>(primitive)).mesh;
}

std::shared_ptr<const Model> load_cactus() {
  Model model = read_gltf(DEEPCUT_ASSETS_DIR "/cactus.glb");
  reserve_for_operations(model);
  return std::make_shared<const Model>(std::move(model));
}

/// The glTF export of `model`, as bytes.
std::string bytes(const Model& model) {
  static const std::string dir = test::temp_dir("session");
  const std::string path = dir + "/state.glb";
  write_gltf(model, path);
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Bounds of the model at rest.
BoundingBox rest_bounds(const Model& model) {
  BoundingBox box;
  const PosedModel rest = PosedModel::build(model, -1, 0.0f);
  for (const auto& [key, mesh] : rest.instances()) box.add(mesh.bounds);
  return box;
}

/// Seeded cuts, tears and drills around the model's middle (a linear congruential sequence: the
/// same operations on every platform).
class Operations {
 public:
  explicit Operations(const Model& model, std::uint32_t seed) : box_(rest_bounds(model)), state_(seed) {
    if (!model.animations.empty()) duration_ = model.animations.front().duration();
  }

  Operation cut() {
    CutOperation cut;
    cut.plane.point = centre() + glm::vec3(0.0f, (next() - 0.5f) * 0.6f * size(), 0.0f);
    cut.plane.normal = glm::vec3(next() - 0.5f, 1.0f, next() - 0.5f);
    return posed(cut);
  }
  Operation tear() {
    const glm::vec3 d(0.0f, 0.0f, -1.0f), up(0.0f, 1.0f, 0.0f);
    const glm::vec3 c = centre() + glm::vec3((next() - 0.5f) * 0.2f * size(), (next() - 0.5f) * 0.4f * size(), 0.0f);
    const float depth = 0.5f * (box_.max.z - box_.min.z), height = 0.5f * (box_.max.y - box_.min.y);
    const glm::vec3 handle = c - 1.5f * depth * d;
    TearOperation tear;
    tear.start = {handle + 0.3f * height * up, c + 0.3f * height * up};
    tear.end = {handle - 0.3f * height * up, c - 0.3f * height * up};
    return posed(tear);
  }
  Operation drill() {
    const glm::vec3 c = centre() + glm::vec3(0.0f, (next() - 0.5f) * 0.5f * size(), 0.0f);
    DrillOperation drill;
    drill.cylinder.a = c - glm::vec3(0.0f, 0.0f, size());
    drill.cylinder.b = c + glm::vec3(0.0f, 0.0f, size());
    drill.cylinder.radius = (0.01f + 0.02f * next()) * size();
    drill.options.wall = next() < 0.3f;
    return posed(drill);
  }
  Operation any(int i) { return i % 3 == 0 ? cut() : i % 3 == 1 ? tear() : drill(); }

 private:
  float next() {
    state_ = state_ * 1664525u + 1013904223u;
    return static_cast<float>(state_ >> 8) / static_cast<float>(1u << 24);  // [0, 1)
  }
  glm::vec3 centre() const { return 0.5f * (box_.min + box_.max); }
  float size() const { return box_.diagonal(); }
  Operation posed(OperationParams params) {
    Operation op;
    op.params = std::move(params);
    if (duration_ > 0.0f && next() < 0.7f) {
      op.animation = 0;
      op.time = next() * duration_;
    }
    return op;
  }

  BoundingBox box_;
  std::uint32_t state_;
  float duration_ = 0.0f;
};

/// The session's posed model describes its current state as a fresh build at the same pose
/// does (after `refresh_posed_model` when the last step left it for a rebuild).
void expect_posed_model_fresh(Session& session, int animation, float time, const std::string& when) {
  if (!session.posed_model()) {
    ASSERT_TRUE(session.refresh_posed_model(animation, time)) << when;
  }
  const PosedModel* posed = session.posed_model();
  ASSERT_NE(posed, nullptr) << when;
  EXPECT_EQ(test::difference_from_fresh_build(*posed, *session.current()), "") << when;
}

History history_of(const std::vector<OperationEntry>& entries) {
  History history;
  for (const auto& entry : entries) history.operations.push_back(entry.operation);
  return history;
}

/// What `deepcut apply` makes of `history` on the opened cactus.
std::string applied_bytes(const History& history) {
  Session replay(Session::Undo::None);
  replay.open(load_cactus());
  replay.apply_history(history, "replay");
  return bytes(*replay.current());
}

TEST(SessionTest, apply_makes_one_undo_step_and_undo_redo_give_back_the_states) {
  Session session;
  session.open(load_cactus());
  const auto opened = session.current();
  const std::string opened_bytes = bytes(*opened);
  Operations ops(*opened, 1);
  const Operation cut = ops.cut();
  const Applied applied = session.apply(cut);
  ASSERT_EQ(applied.result.status, OpStatus::Ok);
  EXPECT_TRUE(applied.change.structure);  // a cut makes piece nodes
  EXPECT_EQ(session.undo_count(), 1u);
  ASSERT_EQ(session.operations().size(), 1u);
  const std::string after_bytes = bytes(*session.current());  // the live model changes: keep its bytes
  EXPECT_NE(after_bytes, opened_bytes);

  EXPECT_TRUE(session.undo().structure);
  EXPECT_EQ(bytes(*session.current()), opened_bytes);
  EXPECT_TRUE(session.operations().empty());
  EXPECT_FALSE(session.can_undo());
  EXPECT_TRUE(session.redo().structure);
  EXPECT_EQ(bytes(*session.current()), after_bytes);
  EXPECT_FALSE(session.can_redo());

  // A new operation after an undo drops the undone step.
  session.undo();
  ASSERT_EQ(session.apply(ops.drill()).result.status, OpStatus::Ok);
  EXPECT_EQ(session.undo_count(), 1u);
  EXPECT_FALSE(session.can_redo());
}

TEST(SessionTest, a_miss_or_a_bad_operation_changes_nothing) {
  Session session;
  session.open(load_cactus());
  const std::string opened = bytes(*session.current());
  ASSERT_TRUE(session.refresh_posed_model(-1, 0.0f));
  CutOperation far;
  far.plane.point = glm::vec3(0.0f, 1000.0f, 0.0f);
  Operation miss;
  miss.params = far;
  const Applied missed = session.apply(miss);
  EXPECT_EQ(missed.result.status, OpStatus::NoIntersection);
  EXPECT_TRUE(missed.change.empty());
  EXPECT_EQ(bytes(*session.current()), opened);
  EXPECT_EQ(session.undo_count(), 0u);
  EXPECT_NE(session.posed_model(), nullptr);  // a miss keeps it

  DrillOperation bad;
  bad.cylinder.radius = -1.0f;
  Operation invalid;
  invalid.params = bad;
  EXPECT_THROW(session.apply(invalid), Error);
  EXPECT_EQ(bytes(*session.current()), opened);
  EXPECT_EQ(session.undo_count(), 0u);
  expect_posed_model_fresh(session, -1, 0.0f, "after a failed operation");
}

TEST(SessionTest, apply_history_equals_applying_one_by_one_and_a_bad_one_changes_nothing) {
  const auto cactus = load_cactus();
  Operations ops(*cactus, 7);
  History history;
  for (int i = 0; i < 6; ++i) history.operations.push_back(ops.any(i));

  Session one_by_one;
  one_by_one.open(cactus);
  std::size_t ok = 0;
  for (const Operation& op : history.operations) ok += one_by_one.apply(op).result.status == OpStatus::Ok;
  const std::string want = bytes(*one_by_one.current());

  Session session;
  session.open(cactus);
  const std::vector<Applied> reports = session.apply_history(history, "h.json");
  ASSERT_EQ(reports.size(), history.operations.size());
  EXPECT_EQ(session.undo_count(), ok);  // one step per operation that applied
  EXPECT_EQ(bytes(*session.current()), want);
  EXPECT_EQ(applied_bytes(history), want);  // one copy, no undo steps: the same bytes
  EXPECT_EQ(session.operations().size(), ok);

  History bad = history;
  DrillOperation broken;
  broken.cylinder.radius = 0.0f;
  bad.operations.insert(bad.operations.begin() + 2, Operation{broken, -1, 0.0f});
  const std::string before = bytes(*session.current());
  try {
    session.apply_history(bad, "bad.json");
    FAIL() << "a bad operation must throw";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("bad.json: operation 2: ", 0), 0u) << e.what();
  }
  EXPECT_EQ(bytes(*session.current()), before);
  EXPECT_EQ(session.undo_count(), ok);
}

TEST(SessionTest, editing_an_operation_reruns_the_later_ones_as_one_undo_step) {
  Session session;
  session.open(load_cactus());
  const std::string opened_bytes = bytes(*session.current());
  Operations ops(*session.current(), 3);
  Operation cut = ops.cut();
  std::get<CutOperation>(cut.params).plane.normal = glm::vec3(0.0f, 1.0f, 0.0f);
  ASSERT_EQ(session.apply(cut).result.status, OpStatus::Ok);
  ASSERT_EQ(session.apply(ops.tear()).result.status, OpStatus::Ok);
  ASSERT_EQ(session.apply(ops.drill()).result.status, OpStatus::Ok);
  const std::string before_bytes = bytes(*session.current());

  // Editing shows the state before the operation; cancelling changes nothing.
  ASSERT_FALSE(session.begin_edit(3));
  ASSERT_TRUE(session.begin_edit(1));
  EXPECT_EQ(session.editing(), 1);
  EXPECT_EQ(session.undo_count(), 3u);
  session.cancel_edit();
  EXPECT_EQ(session.editing(), -1);
  EXPECT_EQ(bytes(*session.current()), before_bytes);

  ASSERT_TRUE(session.begin_edit(0));
  EXPECT_EQ(bytes(*session.current()), opened_bytes);
  EXPECT_EQ(session.operations().size(), 3u);
  Operation edited = session.edited_entry().operation;
  std::get<CutOperation>(edited.params).plane.point.y -= 0.05f * rest_bounds(*session.current()).diagonal();
  const EditOutcome outcome = session.finish_edit(edited);
  ASSERT_TRUE(outcome.edited.applied()) << outcome.edited.error;
  EXPECT_EQ(session.editing(), -1);
  EXPECT_EQ(session.undo_count(), 4u);
  const std::vector<OperationEntry> entries = session.operations();
  ASSERT_EQ(entries.size(), 3u);
  EXPECT_EQ(std::get<CutOperation>(entries[0].operation.params).plane.point,
            std::get<CutOperation>(edited.params).plane.point);
  const std::string edited_bytes = bytes(*session.current());
  EXPECT_NE(edited_bytes, before_bytes);
  EXPECT_EQ(applied_bytes(history_of(entries)), edited_bytes);
  expect_posed_model_fresh(session, -1, 0.0f, "after the re-run");

  session.undo();
  EXPECT_EQ(bytes(*session.current()), before_bytes);
  session.redo();
  EXPECT_EQ(bytes(*session.current()), edited_bytes);
}

TEST(SessionTest, an_edit_that_makes_a_later_operation_miss_marks_it_and_undo_brings_it_back) {
  Session session;
  session.open(load_cactus());
  const float size = rest_bounds(*session.current()).diagonal();
  Operations ops(*session.current(), 5);
  Operation cut = ops.cut();
  cut.animation = -1;
  std::get<CutOperation>(cut.params).plane.normal = glm::vec3(0.0f, 1.0f, 0.0f);
  Operation drill = ops.drill();
  drill.animation = -1;
  std::get<DrillOperation>(drill.params).cylinder.a.y = std::get<CutOperation>(cut.params).plane.point.y - 0.05f * size;
  std::get<DrillOperation>(drill.params).cylinder.b.y = std::get<DrillOperation>(drill.params).cylinder.a.y;
  ASSERT_EQ(session.apply(cut).result.status, OpStatus::Ok);
  ASSERT_EQ(session.apply(drill).result.status, OpStatus::Ok);
  const std::string drilled = bytes(*session.current());

  ASSERT_TRUE(session.begin_edit(0));
  Operation edited = session.edited_entry().operation;
  auto& plane = std::get<CutOperation>(edited.params);
  plane.plane.point.y += 0.25f * size;
  plane.options.keep = CutKeep::Positive;
  const EditOutcome outcome = session.finish_edit(edited);
  ASSERT_TRUE(outcome.edited.applied()) << outcome.edited.error;
  EXPECT_EQ(outcome.skipped, 1u);
  const auto entries = session.operations();
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_TRUE(entries[0].applied());
  EXPECT_EQ(entries[1].status, OpStatus::NoIntersection);
  EXPECT_EQ(applied_bytes(history_of(entries)), bytes(*session.current()));
  session.undo();
  EXPECT_EQ(bytes(*session.current()), drilled);
  EXPECT_TRUE(session.operations()[1].applied());
}

TEST(SessionTest, thirty_mixed_operations_undone_and_redone_all_the_way_are_byte_exact) {
  Session session;
  session.open(load_cactus());
  Operations ops(*session.current(), 12345);
  std::vector<std::string> states = {bytes(*session.current())};  // after each undo step
  int misses = 0;
  for (int i = 0; i < 30; ++i) {
    const Operation op = ops.any(i);
    const std::string when = "operation " + std::to_string(i);
    const Applied applied = session.apply(op);
    if (applied.result.status != OpStatus::Ok) {
      ++misses;
      EXPECT_EQ(bytes(*session.current()), states.back()) << when;
    } else {
      states.push_back(bytes(*session.current()));
    }
    ASSERT_EQ(session.undo_count(), states.size() - 1) << when;
    expect_posed_model_fresh(session, op.animation, op.time, when);
  }
  EXPECT_LE(misses, 10);
  for (std::size_t i = states.size() - 1; i-- > 0;) {
    session.undo();
    ASSERT_EQ(bytes(*session.current()), states[i]) << "undo to state " << i;
    // A local undo leaves the posed model following (as a fresh build); a structural one, none.
    if (const PosedModel* posed = session.posed_model())
      expect_posed_model_fresh(session, posed->animation(), posed->time(), "undo to state " + std::to_string(i));
  }
  expect_posed_model_fresh(session, 0, 0.5f, "after undo all");
  for (std::size_t i = 1; i < states.size(); ++i) {
    session.redo();
    ASSERT_EQ(bytes(*session.current()), states[i]) << "redo to state " << i;
    if (const PosedModel* posed = session.posed_model())
      expect_posed_model_fresh(session, posed->animation(), posed->time(), "redo to state " + std::to_string(i));
  }
  EXPECT_EQ(applied_bytes(history_of(session.operations())), states.back());
}

TEST(SessionTest, a_cut_undone_and_redone_again_keeps_the_posed_model_following_without_a_rebuild) {
  Session session;
  session.open(load_cactus());
  ASSERT_TRUE(session.refresh_posed_model(-1, 0.0f));
  Operations ops(*session.current(), 7);
  Operation cut = ops.cut();
  cut.animation = -1;
  cut.time = 0.0f;
  ASSERT_EQ(session.apply(cut).result.status, OpStatus::Ok);
  ASSERT_TRUE(session.refresh_posed_model(-1, 0.0f));  // the cut's pieces are new meshes
  // The first undo brings back a content the session never stashed: rebuilt when asked for.
  ASSERT_TRUE(session.undo().mapped);
  expect_posed_model_fresh(session, -1, 0.0f, "first undo");
  // From then on each side comes back as it left: the posed model follows, equal to a build.
  for (int i = 0; i < 2; ++i) {
    const std::string when = "cycle " + std::to_string(i);
    ASSERT_TRUE(session.redo().mapped);
    ASSERT_NE(session.posed_model(), nullptr) << when << ": redo";
    expect_posed_model_fresh(session, -1, 0.0f, when + ": redo");
    ASSERT_TRUE(session.undo().mapped);
    ASSERT_NE(session.posed_model(), nullptr) << when << ": undo";
    expect_posed_model_fresh(session, -1, 0.0f, when + ": undo");
  }
  // A refresh at the same pose keeps what was stashed: the redo after it still follows.
  ASSERT_TRUE(session.refresh_posed_model(-1, 0.0f));
  ASSERT_TRUE(session.redo().mapped);
  ASSERT_NE(session.posed_model(), nullptr) << "redo after a refresh at the same pose";
  expect_posed_model_fresh(session, -1, 0.0f, "redo after a refresh at the same pose");
}

TEST(SessionTest, a_cut_hands_its_pieces_origins_and_a_follower_that_copies_by_them_equals_a_fresh_build) {
  for (const float time : {-1.0f, 0.5f}) {  // rest pose, and skinned at a time of the animation
    const int animation = time < 0.0f ? -1 : 0;
    const float at = time < 0.0f ? 0.0f : time;
    Session session;
    session.open(load_cactus());
    // A follower as the studio's scene keeps one: positions without grids, and corner normals.
    PosedModel follower = PosedModel::build(*session.current(), animation, at, PoseDetail::Positions);
    std::map<std::pair<int, int>, std::vector<glm::vec3>> normals_before;
    for (const auto& [key, inst] : follower.instances())
      normals_before[key] = inst.corner_normals(*instance_surface(*session.current(), key.first, key.second));
    Operations ops(*session.current(), 7);
    Operation cut = ops.cut();
    cut.animation = animation;
    cut.time = at;
    const session::Applied applied = session.apply(cut);
    ASSERT_EQ(applied.result.status, OpStatus::Ok);
    ASSERT_TRUE(applied.change.mapped);
    ASSERT_FALSE(applied.change.origins.empty()) << "a cut in a session says where its pieces came from";
    PoseStash stash;
    follower.follow(*session.current(), applied.change, PoseDetail::Positions, &stash);
    EXPECT_EQ(test::difference_from_fresh_build(follower, *session.current()), "") << "time " << time;
    std::size_t copied = 0;
    for (const auto& origin : applied.change.origins) {
      const PosedMesh* inst = follower.find(origin->node, origin->primitive);
      ASSERT_NE(inst, nullptr);
      const SurfaceMesh& surface = *instance_surface(*session.current(), origin->node, origin->primitive);
      const auto before = normals_before.find({origin->node_before, origin->primitive_before});
      ASSERT_NE(before, normals_before.end());
      EXPECT_EQ(inst->corner_normals(surface, *origin, before->second), inst->corner_normals(surface));
      for (std::uint32_t f : origin->faces) copied += f != kInvalidIndex;
    }
    EXPECT_GT(copied, 0u) << "the faces away from the rim are copied";
  }
}

// A follower that stashed a cut's pieces (its undo) and follows another cut takes the arrays of
// a piece it set aside for a piece it derives (their memory reused), and still equals a fresh
// build.
TEST(SessionTest, a_follower_derives_a_new_cut_s_piece_into_the_arrays_of_a_piece_it_set_aside) {
  Session session;
  session.open(load_cactus());
  PosedModel follower = PosedModel::build(*session.current(), -1, 0.0f, PoseDetail::Positions);
  PoseStash stash;
  Operations ops(*session.current(), 7);
  const Operation first = ops.cut();
  const Applied cut = session.apply(first);
  ASSERT_EQ(cut.result.status, OpStatus::Ok);
  follower.follow(*session.current(), cut.change, PoseDetail::Positions, &stash);
  // Its undo: the pieces go into the stash.
  follower.follow(*session.current(), session.undo(), PoseDetail::Positions, &stash);
  ASSERT_FALSE(stash.empty());
  std::set<const glm::vec3*> set_aside;
  for (const auto& [key, inst] : stash) set_aside.insert(inst.posed.data());
  // A little lower: the pieces differ from the stashed ones (a value left over would show).
  Operation second = first;
  std::get<CutOperation>(second.params).plane.point.y -= 0.01f * rest_bounds(*session.current()).diagonal();
  const Applied applied = session.apply(second);
  ASSERT_EQ(applied.result.status, OpStatus::Ok);
  follower.follow(*session.current(), applied.change, PoseDetail::Positions, &stash);
  EXPECT_EQ(test::difference_from_fresh_build(follower, *session.current()), "");
  std::size_t derived = 0, reused = 0;
  for (const auto& origin : applied.change.origins)
    if (const PosedMesh* inst = follower.find(origin->node, origin->primitive)) {
      ++derived;
      reused += set_aside.count(inst->posed.data());
    }
  // Each piece holds about as many vertices as one set aside: the one that grew takes the arrays
  // of the one it was (their room holds it), not new ones.
  EXPECT_EQ(derived, set_aside.size());
  EXPECT_EQ(reused, derived) << "every derived piece takes the arrays of a piece set aside";
}

// A cut's pieces get posed arrays with their own room, not the room of the content they were
// cut out of: the small piece a cut low down makes keeps no room for half the cactus (a long
// session's many small pieces would each keep it alive). After the undo, a cut across the middle
// derives its pieces into arrays set aside where one fits, and no piece's arrays exceed the most
// a spare may be taken at (twice its own room: take_smallest_fit).
TEST(SessionTest, a_follower_gives_a_cut_s_pieces_arrays_bounded_by_their_own_room) {
  Session session;
  session.open(load_cactus());
  const BoundingBox box = rest_bounds(*session.current());
  auto cut_at = [&](float height) {  // a level cut at `height` of the rest bounds (0: the bottom)
    CutOperation cut;
    cut.plane.point = box.min + height * (box.max - box.min);
    cut.plane.normal = glm::vec3(0.02f, 1.0f, 0.01f);
    return session.apply(Operation{cut, -1, 0.0f});
  };
  // Capacities of every derived piece's arrays against its own room (`most`: times that room).
  auto within_room = [&](const PosedModel& follower, const Applied& applied, std::size_t most) {
    std::size_t derived = 0;
    for (const auto& origin : applied.change.origins) {
      const PosedMesh* inst = follower.find(origin->node, origin->primitive);
      if (!inst) continue;
      ++derived;
      const std::size_t room = most * piece_vertex_room(inst->posed.size()) + (most > 1 ? 1 : 0);
      EXPECT_LE(inst->posed.capacity(), room) << inst->posed.size() << " vertices";
      EXPECT_LE(inst->linear.capacity(), room) << inst->posed.size() << " vertices";
    }
    return derived;
  };
  PosedModel follower = PosedModel::build(*session.current(), -1, 0.0f, PoseDetail::Positions);
  const std::size_t whole = follower.instances().begin()->second.posed.size();
  PoseStash stash;
  const Applied low = cut_at(0.15f);
  ASSERT_EQ(low.result.status, OpStatus::Ok);
  follower.follow(*session.current(), low.change, PoseDetail::Positions, &stash);
  EXPECT_EQ(test::difference_from_fresh_build(follower, *session.current()), "");
  EXPECT_GE(within_room(follower, low, 1), 2u) << "no spare: every piece gets new arrays of its own room";
  std::size_t smallest = whole;
  for (const auto& origin : low.change.origins)
    smallest = std::min(smallest, follower.find(origin->node, origin->primitive)->posed.size());
  ASSERT_LT(operation_vertex_room(smallest), operation_vertex_room(whole / 2)) << "a lopsided cut";
  follower.follow(*session.current(), session.undo(), PoseDetail::Positions, &stash);
  std::set<const glm::vec3*> set_aside;
  for (const auto& [key, inst] : stash) set_aside.insert(inst.posed.data());
  ASSERT_GE(set_aside.size(), 2u);
  const Applied middle = cut_at(0.5f);
  ASSERT_EQ(middle.result.status, OpStatus::Ok);
  follower.follow(*session.current(), middle.change, PoseDetail::Positions, &stash);
  EXPECT_EQ(test::difference_from_fresh_build(follower, *session.current()), "");
  EXPECT_GE(within_room(follower, middle, 2), 2u);
  std::size_t reused = 0;
  for (const auto& origin : middle.change.origins)
    reused += set_aside.count(follower.find(origin->node, origin->primitive)->posed.data());
  EXPECT_GE(reused, 1u) << "the larger set-aside piece holds a piece of the even cut";
}

// With one spare that holds every piece of a cut, the piece with the most vertices takes it and
// the others get new arrays: pieces are derived largest first, so a smaller one met earlier in
// node order does not take the spare the largest needs (the fewest bytes are new pages).
TEST(SessionTest, a_follower_derives_the_largest_piece_into_the_one_spare_that_holds_it) {
  Session session;
  session.open(load_cactus());
  for (std::uint32_t seed = 1; seed < 40; ++seed) {
    PosedModel follower = PosedModel::build(*session.current(), -1, 0.0f, PoseDetail::Positions);
    Operation op = Operations(*session.current(), seed / 2).cut();
    if (seed % 2) {  // the plane flipped: the pieces swap sides (and their order in the model)
      Plane& plane = std::get<CutOperation>(op.params).plane;
      plane.normal = -plane.normal;
    }
    const Applied cut = session.apply(op);
    if (cut.result.status != OpStatus::Ok) continue;
    std::map<std::pair<int, int>, std::size_t> pieces;  // vertices by (node, primitive): met in this order
    for (const auto& o : cut.change.origins)
      pieces[{o->node, o->primitive}] =
          instance_surface(*session.current(), o->node, o->primitive)->vertex_count();
    const auto largest = std::max_element(pieces.begin(), pieces.end(),
                                          [](const auto& a, const auto& b) { return a.second < b.second; });
    // A smaller piece met before the largest that the spare would also fit (it is at most twice
    // the room that piece would get): unsorted, that piece would take it.
    const bool smaller_first = std::any_of(pieces.begin(), largest, [&](const auto& p) {
      return 2 * operation_vertex_room(p.second) + 1 >= largest->second;
    });
    if (!smaller_first) {  // the largest met first, or no smaller piece would fit: another cut
      session.undo();
      continue;
    }
    // Set aside by no arrival (a tag no content has), with room for the largest piece only.
    // Its arrays hold a sentinel past their (zero) size, as a spare set aside after use holds
    // old values: a linear map the taken-spare path missed (an UninitVector: growing it writes
    // nothing) would read 7s, not the zeros of fresh memory.
    PosedMesh spare;
    spare.posed.reserve(largest->second);
    spare.linear.reserve(largest->second);
    spare.posed.assign(largest->second, glm::vec3(7.0f));
    spare.linear.assign(largest->second, glm::mat3(glm::vec3(7.0f), glm::vec3(7.0f), glm::vec3(7.0f)));
    spare.posed.clear();
    spare.linear.clear();
    const glm::vec3* memory = spare.posed.data();
    PoseStash stash;
    stash[{~std::uint64_t(0), 0}] = std::move(spare);
    follower.follow(*session.current(), cut.change, PoseDetail::Positions, &stash);
    EXPECT_EQ(test::difference_from_fresh_build(follower, *session.current()), "");
    const PosedMesh* inst = follower.find(largest->first.first, largest->first.second);
    ASSERT_NE(inst, nullptr);
    EXPECT_EQ(inst->posed.data(), memory) << "the largest piece takes the spare";
    return;
  }
  FAIL() << "no cut whose largest piece a follower meets after a smaller one";
}

/// The memory of every non-empty array of the model's primitives (attributes and triangles).
std::set<const void*> array_memory(const Model& model) {
  std::set<const void*> out;
  for (const Mesh& m : model.meshes)
    for (const Primitive& p : m.primitives) {
      if (p.mesh.face_slots() > 0) out.insert(p.mesh.faces().data());
      for (const AttributeSet* set : {&p.mesh.vertex_attrs(), &p.mesh.face_attrs(), &p.mesh.corner_attrs()})
        for (const std::string& name : set->names())
          if (set->size() > 0) out.insert(set->base(name)->element_data(0));
    }
  return out;
}

// A cut made after an undo drops the undone step: the pieces it copies out take the memory of
// the pieces that step held (where they fit: a piece copied out has room to grow), and the state
// is the one a session that never made the undone cut reaches, byte for byte. A miss after an
// undo takes nothing: the undone step can still be redone.
TEST(SessionTest, a_cut_after_an_undo_copies_its_pieces_into_the_memory_of_the_step_it_drops) {
  const auto cactus = load_cactus();
  Session session;
  session.open(cactus);
  const std::set<const void*> opened = array_memory(*session.current());
  Operations ops(*cactus, 7);
  Operation first = ops.cut();
  first.animation = -1;
  first.time = 0.0f;
  ASSERT_EQ(session.apply(first).result.status, OpStatus::Ok);
  // The arrays the cut copied out (the piece that keeps the source's is compacted in place), and
  // the side of the plane their piece lies on.
  std::set<const void*> copied;
  for (const void* memory : array_memory(*session.current()))
    if (!opened.count(memory)) copied.insert(memory);
  ASSERT_FALSE(copied.empty());
  const Plane plane = std::get<CutOperation>(first.params).plane;
  ASSERT_TRUE(session.refresh_posed_model(-1, 0.0f));
  float side = 0.0f;
  for (const auto& [key, inst] : session.posed_model()->instances())
    if (copied.count(instance_surface(*session.current(), key.first, key.second)->faces().data()))
      side = glm::dot(0.5f * (inst.bounds.min + inst.bounds.max) - plane.point, plane.normal);
  ASSERT_NE(side, 0.0f);
  session.undo();
  session.redo();
  session.undo();
  CutOperation far;
  far.plane.point = glm::vec3(0.0f, 1000.0f, 0.0f);
  ASSERT_EQ(session.apply(Operation{far, -1, 0.0f}).result.status, OpStatus::NoIntersection);
  ASSERT_TRUE(session.can_redo()) << "a miss keeps the step undone";
  // The plane moved towards that piece (it comes out a little smaller, and different), then past
  // where it was (a little larger: the room the piece was given holds it).
  const float step = 0.01f * rest_bounds(*cactus).diagonal();
  for (const float shift : {1.0f, -0.5f}) {
    Operation next = first;
    std::get<CutOperation>(next.params).plane.point +=
        shift * (side > 0.0f ? step : -step) * glm::normalize(plane.normal);
    ASSERT_EQ(session.apply(next).result.status, OpStatus::Ok);
    EXPECT_FALSE(session.can_redo());
    std::size_t reused = 0;
    for (const void* memory : array_memory(*session.current())) reused += copied.count(memory);
    EXPECT_GT(reused, 0u) << "shift " << shift
                          << ": a piece copied out reuses the memory of the step dropped";
    Session fresh;
    fresh.open(cactus);
    ASSERT_EQ(fresh.apply(next).result.status, OpStatus::Ok);
    EXPECT_EQ(bytes(*session.current()), bytes(*fresh.current())) << "shift " << shift;
    session.undo();
  }
}

// A small piece (a few hundred vertices: the cactus's top, cut off near its tip) is copied out
// with the operations' fixed room, several times its size; cut again a little lower after the
// undo, its larger successor still takes that memory.
TEST(SessionTest, a_small_piece_cut_again_after_an_undo_takes_the_memory_of_the_one_dropped) {
  const auto cactus = load_cactus();
  const BoundingBox box = rest_bounds(*cactus);
  Session session;
  session.open(cactus);
  const std::set<const void*> opened = array_memory(*session.current());
  const float height = box.max.y - box.min.y;
  Operation first{CutOperation{}, -1, 0.0f};
  std::get<CutOperation>(first.params).plane =
      Plane{glm::vec3(0.0f, box.max.y - 0.04f * height, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f)};
  ASSERT_EQ(session.apply(first).result.status, OpStatus::Ok);
  std::set<const void*> copied;
  for (const void* memory : array_memory(*session.current()))
    if (!opened.count(memory)) copied.insert(memory);
  ASSERT_FALSE(copied.empty());
  session.undo();
  Operation lower = first;
  std::get<CutOperation>(lower.params).plane.point.y -= 0.01f * height;
  ASSERT_EQ(session.apply(lower).result.status, OpStatus::Ok);
  std::size_t reused = 0;
  for (const void* memory : array_memory(*session.current())) reused += copied.count(memory);
  EXPECT_GT(reused, 0u) << "the small piece copied out reuses the memory of the step dropped";
  Session fresh;
  fresh.open(cactus);
  ASSERT_EQ(fresh.apply(lower).result.status, OpStatus::Ok);
  EXPECT_EQ(bytes(*session.current()), bytes(*fresh.current()));
}

// An apply that took the undone step's memory and then ended without a step (here its observer
// throws after the cut copied its pieces out) drops that step: it can no longer be redone (its
// meshes are gone), and the session can still undo, redo and apply as one that never had it.
TEST(SessionTest, an_apply_that_took_the_undone_step_s_memory_and_pushed_no_step_drops_it) {
  const auto cactus = load_cactus();
  Session session;
  session.open(cactus);
  Operations ops(*cactus, 7);
  Operation first = ops.cut();
  first.animation = -1;
  first.time = 0.0f;
  ASSERT_EQ(session.apply(first).result.status, OpStatus::Ok);
  session.undo();
  ASSERT_TRUE(session.can_redo());
  History history;
  history.operations.push_back(first);
  EXPECT_THROW(session.apply_history(history, "h.json",
                                     [](std::size_t, const Model&, const Applied&) {
                                       throw std::runtime_error("the observer fails");
                                     }),
               std::runtime_error);
  EXPECT_EQ(bytes(*session.current()), bytes(*cactus)) << "the history's failure changes nothing";
  EXPECT_FALSE(session.can_redo()) << "the step whose memory was taken is dropped";
  EXPECT_TRUE(session.redo().empty()) << "nothing to redo";
  ASSERT_EQ(session.apply(first).result.status, OpStatus::Ok);
  Session fresh;
  fresh.open(cactus);
  ASSERT_EQ(fresh.apply(first).result.status, OpStatus::Ok);
  EXPECT_EQ(bytes(*session.current()), bytes(*fresh.current()));
  session.undo();
  EXPECT_EQ(bytes(*session.current()), bytes(*cactus));
}

TEST(SessionTest, a_session_writes_what_deepcut_apply_writes_and_refuses_a_swallowing_drill_alike) {
  const std::string dir = test::temp_dir("session-cli");
  Session session;
  session.open(load_cactus());
  Operations ops(*session.current(), 99);
  History history;
  for (int i = 0; i < 6; ++i) {
    const Operation op = ops.any(i);
    if (session.apply(op).result.status == OpStatus::Ok) history.operations.push_back(op);
  }
  ASSERT_GE(history.operations.size(), 3u);
  const std::string studio = bytes(*session.current());
  {
    std::ofstream out(dir + "/history.json");
    out << history_to_json(history);
  }
  const std::string cactus = DEEPCUT_ASSETS_DIR "/cactus.glb";
  const auto run = test::run_cli("apply " + test::quote(cactus) + " " + test::quote(dir + "/history.json") +
                                 " -o " + test::quote(dir + "/cli.glb"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::ifstream in(dir + "/cli.glb", std::ios::binary);
  EXPECT_TRUE(std::string(std::istreambuf_iterator<char>(in), {}) == studio) << "deepcut apply wrote other bytes";

  // A drill that would remove every triangle of an instance: refused, nothing changes.
  session.open(load_cactus());
  DrillOperation swallow;
  swallow.cylinder = {{0.0f, -10.0f, 0.0f}, {0.0f, 20.0f, 0.0f}, 100.0f};
  const std::string before = bytes(*session.current());
  const std::size_t steps = session.undo_count();
  std::string message;
  try {
    session.apply(Operation{swallow, -1, 0.0f});
    FAIL() << "the session drilled away a whole instance";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
    message = e.what();
  }
  EXPECT_NE(message.find("removes every triangle of node"), std::string::npos) << message;
  EXPECT_TRUE(bytes(*session.current()) == before);
  EXPECT_EQ(session.undo_count(), steps);
  {
    std::ofstream out(dir + "/swallow.json");
    out << history_to_json(History{{Operation{swallow, -1, 0.0f}}});
  }
  const auto refused = test::run_cli("apply " + test::quote(cactus) + " " + test::quote(dir + "/swallow.json") +
                                     " -o " + test::quote(dir + "/swallow.glb"));
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find(": operation 0: " + message + "\n"), std::string::npos) << refused.err;
}

/// A drill around the model's axis (vertical, wider than the model) from `from_y` to above the
/// top: it removes every triangle above `from_y`.
Operation top_drill(const BoundingBox& box, float from_y) {
  const glm::vec3 c = 0.5f * (box.min + box.max);
  DrillOperation drill;
  drill.cylinder = {{c.x, from_y, c.z}, {c.x, box.max.y + box.diagonal(), c.z}, 2.0f * box.diagonal()};
  return Operation{drill, -1, 0.0f};
}

/// A horizontal cut at `y`, both sides kept (the part above becomes its own instance).
Operation level_cut(float y) {
  CutOperation cut;
  cut.plane = {{0.0f, y, 0.0f}, {0.0f, 1.0f, 0.0f}};
  return Operation{cut, -1, 0.0f};
}

TEST(SessionTest, a_rerun_skips_a_drill_that_now_swallows_an_instance_and_leaves_no_trace_of_it) {
  Session session;
  session.open(load_cactus());
  const BoundingBox box = rest_bounds(*session.current());
  const float height = box.max.y - box.min.y;
  // A cut low down, a drill taking the top off the upper piece, a cut across.
  const Operation drill = top_drill(box, box.min.y + 0.75f * height);
  CutOperation across;
  across.plane = {0.5f * (box.min + box.max), {1.0f, 0.0f, 0.0f}};
  const Operation last{across, -1, 0.0f};
  ASSERT_EQ(session.apply(level_cut(box.min.y + 0.6f * height)).result.status, OpStatus::Ok);
  ASSERT_EQ(session.apply(drill).result.status, OpStatus::Ok);
  ASSERT_EQ(session.apply(last).result.status, OpStatus::Ok);

  // The cut moved above the drill's lower end: the upper piece lies wholly inside the drill.
  const Operation higher = level_cut(box.min.y + 0.85f * height);
  ASSERT_TRUE(session.begin_edit(0));
  const EditOutcome outcome = session.finish_edit(higher);
  ASSERT_TRUE(outcome.edited.applied()) << outcome.edited.error;
  EXPECT_EQ(outcome.skipped, 1u);
  const std::vector<OperationEntry> entries = session.operations();
  ASSERT_EQ(entries.size(), 3u);
  EXPECT_TRUE(entries[0].applied());
  EXPECT_FALSE(entries[1].applied());
  EXPECT_NE(entries[1].error.find("removes every triangle of node"), std::string::npos) << entries[1].error;
  EXPECT_TRUE(entries[2].applied()) << entries[2].error;

  // What apply_operation (and so `deepcut apply`) makes of the operations that applied.
  Model want = *load_cactus();
  ASSERT_EQ(apply_operation(want, higher).status, OpStatus::Ok);
  ASSERT_EQ(apply_operation(want, last).status, OpStatus::Ok);
  EXPECT_TRUE(bytes(*session.current()) == bytes(want)) << "the skipped drill left changes behind";
  EXPECT_TRUE(applied_bytes(History{{higher, last}}) == bytes(want));

  // Applied directly, or in a history (either undo mode), the drill changes nothing.
  const auto before = std::make_shared<const Model>(*session.current());  // a copy: the live model changes
  const std::string before_bytes = bytes(*before);
  const std::size_t steps = session.undo_count();
  EXPECT_THROW(session.apply(drill), Error);
  EXPECT_TRUE(bytes(*session.current()) == before_bytes);
  EXPECT_EQ(session.undo_count(), steps);
  EXPECT_THROW(session.apply_history(History{{drill}}, "h.json"), Error);
  EXPECT_TRUE(bytes(*session.current()) == before_bytes);
  EXPECT_EQ(session.undo_count(), steps);
  EXPECT_TRUE(bytes(*session.current()) == before_bytes);
  Session single(Session::Undo::None);
  single.open(before);
  EXPECT_THROW(single.apply_history(History{{last, drill}}, "h.json"), Error);
  EXPECT_TRUE(bytes(*single.current()) == before_bytes);
  EXPECT_TRUE(bytes(*before) == before_bytes);
}

}  // namespace
}  // namespace deepcut::session
