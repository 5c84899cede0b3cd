// SPDX-License-Identifier: MIT
// GUI test (QTest under xvfb-run) of the incremental view: after each of a series of seeded
// tears and drills (and cuts: structural steps that keep or bring back what they can), then each
// undo and each redo, the scene followed in O(change) from what the
// session says the step changed
// (plugins::follow_scene) and the view's VTK data updated from the same change
// (SceneView::update_scene) equal a full build of the new state (make_scene and a fresh
// ViewPolyData): posed positions and corner normals bit for bit, as many points, and per drawn
// cell its points' positions, normals, texture coordinates, vertex ids, face id and colours.

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkTypeInt64Array.h>
#include <vtkWeakPointer.h>

#include <QtTest/QtTest>
#include <algorithm>
#include <cstring>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <variant>
#include <vector>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/operation_room.h"
#include "deepcut/core/ops/operation.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/plugins/scene.h"
#include "deepcut/widgets/poly_data_bridge.h"
#include "deepcut/widgets/view_poly_data.h"
#include "scene_view.h"
#include "session.h"

using namespace deepcut;

namespace {

// Seeded tears and small drills (no wall: both are local steps) around the model's middle, and
// with `cuts` every third a cut across it (a structural step).
class LocalOperations {
 public:
  LocalOperations(const BoundingBox& box, int animation, float time, bool cuts)
      : box_(box), animation_(animation), time_(time), cuts_(cuts) {}
  Operation next_operation(int i) {
    const glm::vec3 c = 0.5f * (box_.min + box_.max);
    const float size = box_.diagonal();
    Operation op;
    op.animation = animation_;
    op.time = time_;
    if (cuts_ && i % 3 == 2) {
      CutOperation cut;
      cut.plane.point = c + glm::vec3(0.0f, (next() - 0.5f) * 0.4f * (box_.max.y - box_.min.y), 0.0f);
      cut.plane.normal = glm::vec3(0.2f * (next() - 0.5f), 1.0f, 0.1f * (next() - 0.5f));
      op.params = cut;
    } else if (i % 2 == 0) {
      const glm::vec3 at = c + glm::vec3((next() - 0.5f) * 0.2f * size, (next() - 0.5f) * 0.4f * size, 0.0f);
      const float depth = 0.5f * (box_.max.z - box_.min.z), height = 0.5f * (box_.max.y - box_.min.y);
      const glm::vec3 up(0.0f, 1.0f, 0.0f), handle = at + 1.5f * depth * glm::vec3(0.0f, 0.0f, 1.0f);
      TearOperation tear;
      tear.start = {handle + 0.2f * height * up, at + 0.2f * height * up};
      tear.end = {handle - 0.2f * height * up, at - 0.2f * height * up};
      op.params = tear;
    } else {
      const glm::vec3 at = c + glm::vec3(0.0f, (next() - 0.5f) * 0.5f * size, 0.0f);
      DrillOperation drill;
      drill.cylinder.a = at - glm::vec3(0.0f, 0.0f, size);
      drill.cylinder.b = at + glm::vec3(0.0f, 0.0f, size);
      drill.cylinder.radius = (0.01f + 0.02f * next()) * size;
      op.params = drill;
    }
    return op;
  }

 private:
  float next() {
    state_ = state_ * 1664525u + 1013904223u;
    return static_cast<float>(state_ >> 8) / static_cast<float>(1u << 24);
  }
  BoundingBox box_;
  int animation_;
  float time_;
  bool cuts_;
  std::uint32_t state_ = 7u;
};

bool same_tuple(vtkDataArray* a, vtkIdType i, vtkDataArray* b, vtkIdType j) {
  if (!a || !b) return !a && !b;
  if (a->GetNumberOfComponents() != b->GetNumberOfComponents()) return false;
  for (int k = 0; k < a->GetNumberOfComponents(); ++k)
    if (a->GetComponent(i, k) != b->GetComponent(j, k)) return false;
  return true;
}

// Cell by cell, what `followed` draws equals what `fresh` draws. @returns "" or what differs.
std::string compare_drawn(vtkPolyData* followed, vtkPolyData* fresh) {
  if (followed->GetNumberOfCells() != fresh->GetNumberOfCells()) return "cell counts differ";
  // Corners share points as a full build shares them: none left unused, none split apart.
  if (followed->GetNumberOfPoints() != fresh->GetNumberOfPoints()) return "point counts differ";
  vtkIdType na = 0, nb = 0;
  const vtkIdType *a = nullptr, *b = nullptr;
  vtkPointData *pa = followed->GetPointData(), *pb = fresh->GetPointData();
  for (vtkIdType cell = 0; cell < fresh->GetNumberOfCells(); ++cell) {
    followed->GetPolys()->GetCellAtId(cell, na, a);
    fresh->GetPolys()->GetCellAtId(cell, nb, b);
    if (na != 3 || nb != 3) return "cell " + std::to_string(cell) + " is not a triangle";
    const bool degenerate = b[0] == b[1] && b[1] == b[2];
    if ((a[0] == a[1] && a[1] == a[2]) != degenerate) return "cell " + std::to_string(cell) + " drawn differently";
    if (!same_tuple(followed->GetCellData()->GetArray("face_id"), cell, fresh->GetCellData()->GetArray("face_id"), cell) ||
        !same_tuple(followed->GetCellData()->GetArray("colors"), cell, fresh->GetCellData()->GetArray("colors"), cell))
      return "cell " + std::to_string(cell) + ": face id or colour differs";
    if (degenerate) continue;
    for (int k = 0; k < 3; ++k) {
      double p[3], q[3];
      followed->GetPoint(a[k], p);
      fresh->GetPoint(b[k], q);
      if (p[0] != q[0] || p[1] != q[1] || p[2] != q[2]) return "cell " + std::to_string(cell) + ": a position differs";
      for (const char* name : {"vertex_id", "normal", "uv0", "colors"})
        if (!same_tuple(pa->GetArray(name), a[k], pb->GetArray(name), b[k]))
          return "cell " + std::to_string(cell) + ": '" + name + "' differs";
    }
  }
  return "";
}

// Opens the bundled cactus in `session` (room reserved as the front ends reserve it) and gives
// its bounds at rest.
BoundingBox open_cactus(session::Session& session) {
  auto opened = std::make_shared<Model>(read_gltf(DEEPCUT_ASSETS_DIR "/cactus.glb"));
  reserve_for_operations(*opened);
  session.open(opened);
  const PosedModel rest = PosedModel::build(*opened, -1, 0.0f);
  BoundingBox box;
  for (const auto& entry : rest.instances()) box.add(entry.second.bounds);
  return box;
}

// Whether each instance of `scene` has the posed corner normals, bit for bit, of a scene made
// afresh from `model` at rest.
bool normals_as_fresh(const plugins::Scene& scene, std::shared_ptr<const Model> model) {
  const plugins::Scene fresh = plugins::make_scene(std::move(model), -1, 0.0f);
  if (scene.instances.size() != fresh.instances.size()) return false;
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const std::vector<glm::vec3>& got = scene.instances[i].posed_normals;
    const std::vector<glm::vec3>& want = fresh.instances[i].posed_normals;
    if (got.size() != want.size()) return false;
    if (!got.empty() && std::memcmp(got.data(), want.data(), got.size() * sizeof(glm::vec3)) != 0)
      return false;
  }
  return true;
}

}  // namespace

class ViewFollowGuiTest : public QObject {
  Q_OBJECT

 private slots:
  void local_steps_undo_and_redo_follow_like_a_full_build() { follow_steps(false); }
  // A cut, its undo and its redo are followed too: what they kept or bring back is drawn from
  // what was drawn before (not built again), and the result equals a full build.
  void cuts_undo_and_redo_follow_like_a_full_build() { follow_steps(true); }
  // Two cuts in a row, then two undos and two redos: the second cut's larger piece takes the
  // arrays of the data the first cut set aside (a spare: what no undo brings back any more), and
  // every step draws what a full build draws.
  void a_second_cut_reuses_what_the_first_set_aside() { follow_steps(true, true); }
  // A cut, its undo, then a cut a little lower (a user trying again): the pieces are copied in
  // the working memory the view kept from the first cut's copies, into the arrays the undo set
  // aside, and every step draws what a full build draws.
  void a_cut_again_after_its_undo_draws_like_a_full_build() { follow_steps(true, true, true); }
  // A cut, its undo, then a cut a little lower (what a user trying again does): every piece of
  // the second cut writes its posed corner normals into those a piece of the first set aside
  // (their room holds the piece that grew), and they equal a fresh scene's.
  void a_cut_again_after_its_undo_writes_every_piece_s_normals_into_a_set_aside_array() {
    session::Session session;
    const BoundingBox box = open_cactus(session);
    plugins::Scene scene = plugins::make_scene(session.current(), -1, 0.0f);
    Operation op;
    op.animation = -1;
    CutOperation cut;
    cut.plane.point = 0.5f * (box.min + box.max) + glm::vec3(0.0f, 0.1f * (box.max.y - box.min.y), 0.0f);
    cut.plane.normal = glm::vec3(0.05f, 1.0f, 0.02f);
    op.params = cut;
    const session::Applied first = session.apply(op);
    QCOMPARE(first.result.status, OpStatus::Ok);
    QVERIFY(plugins::follow_scene(scene, session.current(), first.change));
    QVERIFY(plugins::follow_scene(scene, session.current(), session.undo()));
    std::vector<const glm::vec3*> set_aside;
    for (const auto& entry : scene.stash->normals) set_aside.push_back(entry.second.data());
    QVERIFY2(set_aside.size() >= 2, "the undo set the pieces' normals aside");
    std::get<CutOperation>(op.params).plane.point.y -= 0.01f * (box.max.y - box.min.y);
    const session::Applied second = session.apply(op);
    QCOMPARE(second.result.status, OpStatus::Ok);
    QVERIFY(plugins::follow_scene(scene, session.current(), second.change));
    QVERIFY(normals_as_fresh(scene, session.current()));
    std::size_t pieces = 0, written = 0;
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
      if (scene.origins[i].kind != plugins::InstanceOrigin::Kind::Built) continue;
      ++pieces;
      const glm::vec3* data = scene.instances[i].posed_normals.data();
      written += std::find(set_aside.begin(), set_aside.end(), data) != set_aside.end();
    }
    QVERIFY(pieces >= 2);
    QCOMPARE(written, pieces);
  }

  // A cut low down, its undo, then a cut across the middle (the studio's cuts after a drill and
  // a tear): a new piece's corner normals get its own room (piece_corner_room), not the room of
  // the content it was cut out of, so the small piece of the lopsided cut keeps no room for half
  // the cactus; the even cut's pieces write into the arrays set aside where one fits, none past
  // twice its own room (take_smallest_fit), and every step draws what a fresh scene draws.
  void a_cut_s_pieces_normals_are_bounded_by_their_own_room() {
    session::Session session;
    const BoundingBox box = open_cactus(session);
    plugins::Scene scene = plugins::make_scene(session.current(), -1, 0.0f);
    auto cut_at = [&](float height) {  // a level cut at `height` of the rest bounds (0: the bottom)
      CutOperation cut;
      cut.plane.point = box.min + height * (box.max - box.min);
      cut.plane.normal = glm::vec3(0.02f, 1.0f, 0.01f);
      return session.apply(Operation{cut, -1, 0.0f});
    };
    // The built pieces' normals, each within `most` times its own room.
    auto within_room = [&](std::size_t most) {
      std::size_t pieces = 0;
      for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        if (scene.origins[i].kind != plugins::InstanceOrigin::Kind::Built) continue;
        ++pieces;
        const std::size_t room = piece_corner_room(scene.instances[i].surface->face_slots());
        if (scene.instances[i].posed_normals.capacity() > most * room) return std::size_t(0);
      }
      return pieces;
    };
    const session::Applied low = cut_at(0.15f);
    QCOMPARE(low.result.status, OpStatus::Ok);
    QVERIFY(plugins::follow_scene(scene, session.current(), low.change));
    QVERIFY(normals_as_fresh(scene, session.current()));
    QVERIFY2(within_room(1) >= 2, "no array set aside: every piece's normals get its own room");
    QVERIFY(plugins::follow_scene(scene, session.current(), session.undo()));
    std::set<const glm::vec3*> set_aside;
    for (const auto& entry : scene.stash->normals) set_aside.insert(entry.second.data());
    QVERIFY2(set_aside.size() >= 2, "the undo set the pieces' normals aside");
    const session::Applied middle = cut_at(0.5f);
    QCOMPARE(middle.result.status, OpStatus::Ok);
    QVERIFY(plugins::follow_scene(scene, session.current(), middle.change));
    QVERIFY(normals_as_fresh(scene, session.current()));
    QVERIFY(within_room(2) >= 2);
    std::size_t written = 0;
    for (const plugins::SceneInstance& instance : scene.instances)
      written += set_aside.count(instance.posed_normals.data());
    QVERIFY2(written >= 1, "the larger set-aside piece's array holds a piece of the even cut");
  }

  // With one set-aside array that holds the corner normals of every piece of a cut, the piece
  // with the most face slots writes into it and the others get new arrays: the pieces' normals
  // are made largest first, so a smaller piece drawn earlier does not take the array the
  // largest needs.
  void the_largest_piece_writes_its_normals_into_the_one_set_aside_array_that_holds_it() {
    auto opened = std::make_shared<Model>(read_gltf(DEEPCUT_ASSETS_DIR "/cactus.glb"));
    reserve_for_operations(*opened);
    session::Session session;
    session.open(opened);
    const BoundingBox box = opened->meshes.front().primitives.front().mesh.bounds();
    for (int attempt = 0; attempt < 40; ++attempt) {
      plugins::Scene scene = plugins::make_scene(session.current(), -1, 0.0f);
      CutOperation cut;
      const float dy = (static_cast<float>(attempt / 2) / 20.0f - 0.5f) * (box.max.y - box.min.y);
      cut.plane.point = 0.5f * (box.min + box.max) + glm::vec3(0.0f, dy, 0.0f);
      cut.plane.normal = glm::vec3(0.05f, attempt % 2 ? -1.0f : 1.0f, 0.02f);  // flipped: sides swap
      const session::Applied applied = session.apply(Operation{cut, -1, 0.0f});
      if (applied.result.status != OpStatus::Ok) continue;
      // The pieces' face slots in drawing order (the order follow_scene meets them).
      std::vector<std::size_t> face_slots;
      const auto fresh = plugins::make_scene(session.current(), -1, 0.0f);
      for (const plugins::SceneInstance& s : fresh.instances)
        for (const auto& o : applied.change.origins)
          if (o->node == s.node && o->primitive == s.primitive) face_slots.push_back(s.surface->face_slots());
      // A cut where a piece met before the largest could take the largest's array (its room is
      // at most twice a fresh array's for that piece: take_smallest_fit) tells the order.
      const auto largest = std::max_element(face_slots.begin(), face_slots.end());
      const bool smaller_first = std::any_of(face_slots.begin(), largest, [&](std::size_t n) {
        return 2 * operation_corner_room(n) >= 3 * *largest;
      });
      if (!smaller_first) {
        session.undo();
        continue;
      }
      // Set aside by no arrival (a tag no content has), with room for the largest piece only.
      std::vector<glm::vec3> spare;
      spare.reserve(3 * *largest);
      const glm::vec3* memory = spare.data();
      scene.stash = std::make_shared<plugins::SceneStash>();
      scene.stash->normals[{~std::uint64_t(0), 0}] = std::move(spare);
      QVERIFY(plugins::follow_scene(scene, session.current(), applied.change));
      std::size_t written = 0;
      for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        QVERIFY(scene.instances[i].posed_normals == fresh.instances[i].posed_normals);
        if (scene.instances[i].posed_normals.data() != memory) continue;
        ++written;
        QCOMPARE(scene.instances[i].surface->face_slots(), *largest);
      }
      QCOMPARE(written, std::size_t(1));
      return;
    }
    QFAIL("no cut whose largest piece the scene meets after a smaller one");
  }

 private:
  void follow_steps(bool cuts, bool two_cuts = false, bool undo_between = false) {
    auto opened = std::make_shared<Model>(read_gltf(DEEPCUT_ASSETS_DIR "/cactus.glb"));
    reserve_for_operations(*opened);
    const int animation = opened->animations.empty() ? -1 : 0;
    const float time = animation < 0 ? 0.0f : 0.4f * opened->animations.front().duration();
    session::Session session;
    session.open(opened);
    studio::SceneView view;
    view.resize(640, 480);
    view.show();
    QVERIFY(QTest::qWaitForWindowExposed(&view));
    plugins::Scene scene = plugins::make_scene(session.current(), animation, time);
    view.set_scene(scene);
    view.render();
    int followed = 0, structural = 0, reused = 0, taken = 0;
    // The connectivity arrays drawn after some step, and those drawn after the last one: an
    // operation's piece drawing one seen before but not last took a spare's arrays.
    std::vector<vtkSmartPointer<vtkTypeInt64Array>> seen, last;
    auto drawn_arrays = [&] {
      std::vector<vtkSmartPointer<vtkTypeInt64Array>> out;
      for (std::size_t i = 0; i < scene.instances.size(); ++i)
        out.emplace_back(view.instance_poly_data(i)->GetPolys()->GetConnectivityArray64());
      return out;
    };
    auto count_taken = [&] {
      const auto now = drawn_arrays();
      for (const auto& a : now)
        if (std::find(seen.begin(), seen.end(), a) != seen.end() &&
            std::find(last.begin(), last.end(), a) == last.end())
          ++taken;
      seen.insert(seen.end(), now.begin(), now.end());
      last = now;
    };
    count_taken();
    // `change`: what the session says the step changed (as the studio is told).
    auto check_step = [&](const ModelChange& change, const std::string& what) {
      std::vector<const glm::vec3*> normals_before;
      for (const plugins::SceneInstance& s : scene.instances) normals_before.push_back(s.posed_normals.data());
      if (plugins::follow_scene(scene, session.current(), change)) {
        // A local step's corner normals grow (or shrink) in place, in the room they were made with.
        for (std::size_t i = 0; !change.structure && i < scene.instances.size(); ++i)
          QVERIFY2(scene.instances[i].posed_normals.data() == normals_before[i],
                   (what + ": a local step moved the corner normals").c_str());
        view.update_scene(change);
        ++followed;
        structural += change.structure;
        for (const plugins::InstanceOrigin& origin : scene.origins)
          reused += origin.kind != plugins::InstanceOrigin::Kind::Built;
      } else {
        scene = plugins::make_scene(session.current(), animation, time);
        view.set_scene(scene);
      }
      view.render();
      // The view's data (drawn and set aside) holds room for its own elements and a step's
      // growth, whatever spare's memory a piece took and however the arrays grew (a few dozen
      // elements of room per array: a few kilobytes per data).
      const studio::SceneView::DataBytes bytes = view.data_bytes();
      QVERIFY2(bytes.used > 0 && bytes.held <= bytes.used + bytes.used / 4 + 16 * 1024 * bytes.count,
               (what + ": the view's data holds " + std::to_string(bytes.held) + " bytes for " +
                std::to_string(bytes.used))
                   .c_str());
      const plugins::Scene fresh = plugins::make_scene(session.current(), animation, time);
      QCOMPARE(scene.instances.size(), fresh.instances.size());
      for (std::size_t i = 0; i < fresh.instances.size(); ++i) {
        const plugins::SceneInstance &s = scene.instances[i], &f = fresh.instances[i];
        QVERIFY2(s.posed() == f.posed(), (what + ": posed positions differ").c_str());
        QVERIFY2(s.posed_normals == f.posed_normals, (what + ": posed corner normals differ").c_str());
        QVERIFY2(s.pose->bounds.min == f.pose->bounds.min && s.pose->bounds.max == f.pose->bounds.max,
                 (what + ": posed bounds differ").c_str());
        // Colours follow the elements: the inspectors colour after every step.
        std::vector<glm::u8vec3> colors(f.surface->vertex_count());
        for (std::size_t v = 0; v < colors.size(); ++v) colors[v] = glm::u8vec3(v % 251, v % 13, v % 7);
        plugins::InstanceColors paint;
        paint.kind = plugins::InstanceColors::Kind::PerVertex;
        paint.colors = colors;
        view.set_instance_colors(i, paint);
        ViewPolyData built(*f.surface, f.posed(), &f.posed_normals);
        set_vertex_colors(built.poly(), colors);
        const std::string diff = compare_drawn(view.instance_poly_data(i), built.poly());
        QVERIFY2(diff.empty(), (what + ", instance " + std::to_string(i) + ": " + diff).c_str());
      }
    };
    const PosedModel rest = PosedModel::build(*opened, -1, 0.0f);
    BoundingBox box;
    for (const auto& entry : rest.instances()) box.add(entry.second.bounds);
    LocalOperations operations(box, animation, time, cuts);
    const int steps = two_cuts ? 2 : 8;
    // The data drawn before the first step: set aside by the first cut, then spare at the second
    // (taken or dropped), held by nothing after it (no actor, mapper, picker or cache keeps it).
    const vtkWeakPointer<vtkPolyData> first_drawn = view.instance_poly_data(0);
    QVERIFY(first_drawn);
    for (int i = 0; i < steps; ++i) {
      Operation op = operations.next_operation(two_cuts ? 2 : i);
      if (two_cuts) {  // the first across the top, the second across the larger piece's top
        const float h = box.max.y - box.min.y;
        auto& plane = std::get<CutOperation>(op.params).plane;
        const float at = i == 0 ? 0.3f : undo_between ? 0.25f : 0.15f;
        plane.point = 0.5f * (box.min + box.max) + glm::vec3(0.0f, at * h, 0.0f);
        plane.normal = glm::vec3(0.05f, 1.0f, 0.02f);
      }
      if (undo_between && i == 1) {
        check_step(session.undo(), "undo between the cuts");
        if (QTest::currentTestFailed()) return;
        count_taken();
      }
      const session::Applied applied = session.apply(op);
      if (applied.result.status != OpStatus::Ok) continue;
      check_step(applied.change, "operation " + std::to_string(i));
      if (QTest::currentTestFailed()) return;
      count_taken();
    }
    if (two_cuts) QVERIFY2(taken >= 1, "the second cut's piece took the arrays the first cut set aside");
    if (two_cuts && !undo_between) QVERIFY2(!first_drawn, "the data the first cut set aside is still held");
    while (session.can_undo()) {
      check_step(session.undo(), "undo");
      if (QTest::currentTestFailed()) return;
    }
    while (session.can_redo()) {
      check_step(session.redo(), "redo");
      if (QTest::currentTestFailed()) return;
    }
    QVERIFY2(followed >= (two_cuts ? (undo_between ? 5 : 6) : steps), "the view followed the steps");
    if (cuts) {
      QVERIFY2(structural >= 3, "cuts, their undo and redo were followed");
      QVERIFY2(reused >= 2, "undo and redo of cuts drew what was drawn before");
    }
  }
};

QTEST_MAIN(ViewFollowGuiTest)
#include "view_follow_gui_test.moc"
