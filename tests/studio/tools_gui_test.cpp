// SPDX-License-Identifier: MIT
// GUI tests of the operation tools (QTest under xvfb-run): choose Plane, Scalpel and Drill on
// the tool bar, edit their panels, apply with the button and with Enter, undo all (each export
// byte-equal to the one before that operation), redo all, export, validate, and compare with
// `deepcut apply` of the exported history on the original model.
#include <QVTKOpenGLNativeWidget.h>

#include <QAction>
#include <QApplication>
#include <QDoubleSpinBox>
#include <QPushButton>
#include <QSpinBox>
#include <QStandardPaths>
#include <QSurfaceFormat>
#include <QUndoStack>
#include <QtTest/QtTest>
#include <cstdint>
#include <functional>
#include <limits>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/ops/operation.h"
#include "deepcut/plugins/tool.h"
#include "main_window.h"
#include "morph_panel.h"
#include "posed_checks.h"
#include "scene_view.h"
#include "studio_test_support.h"
#include "timeline.h"
#include "tools.h"

using deepcut::studio::MainWindow;
using deepcut::test::studio::check_cli_apply_equals;
using deepcut::test::studio::model_bytes;
using deepcut::test::studio::check_undo_all_redo_all;
using deepcut::test::studio::export_bytes;
using deepcut::test::studio::kCactus;
using deepcut::test::studio::read_bytes;
using deepcut::test::studio::shown_window;

namespace {

QAction* action_named(MainWindow& window, const QString& name) {
  return window.findChild<QAction*>(name);
}

/// Number of preview line segments of the active tool's first line set (contour, path or rim).
std::size_t preview_segments(MainWindow& window) {
  const deepcut::Overlay overlay = window.tool()->preview(*window.scene());
  return overlay.lines.empty() ? 0 : overlay.lines.front().endpoints.size() / 2;
}

const QString kMorphCube =
    QStringLiteral(DEEPCUT_ASSETS_DIR "/models/AnimatedMorphCube/AnimatedMorphCube.gltf");

/// The cut tool's parameters with its plane (unit normal as placed) through the middle of the
/// drawn bounds at the shown pose.
deepcut::CutOperation cut_through_the_middle(MainWindow& window) {
  auto cut = std::get<deepcut::CutOperation>(window.tool()->parameters());
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const auto& instance : window.scene()->instances)
    for (const glm::vec3& p : instance.posed()) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
  cut.plane.point = 0.5f * (lo + hi);
  cut.plane.normal = glm::normalize(cut.plane.normal);
  return cut;
}

void save_shot(MainWindow& window, const std::string& dir, const std::string& name) {
  window.screenshot().save(QString::fromStdString(dir + "/" + name + ".png"));
}

}  // namespace

class StudioToolsTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase() {
    QStandardPaths::setTestModeEnabled(true);
    QSettings().clear();
  }

  void the_registry_offers_plane_scalpel_and_drill() {
    QStringList titles;
    for (const auto& info : deepcut::plugins::builtin_tools().list()) titles << QString::fromStdString(info.title);
    QCOMPARE(titles, (QStringList{"Plane", "Scalpel", "Drill", "Poke"}));
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY_EXCEPTION_THROWN(window->set_tool("saw"), deepcut::Error);
    QVERIFY(!window->apply_tool());  // no model, no tool
    QVERIFY(!window->last_error().isEmpty());
  }

  void cut_tear_drill_undo_redo_and_export_equal_the_cli() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    const std::string dir = deepcut::test::temp_dir("studio-tools");
    const std::string shots = dir;
    std::vector<std::string> before;  // export before each operation
    auto export_to = [&](const std::string& name) { return export_bytes(*window, dir, name); };

    // Plane: chosen on the tool bar, placed through the centre; move it with the panel.
    action_named(*window, "tool_cut")->trigger();
    QCOMPARE(window->tool_id(), std::string("cut"));
    const auto placed = std::get<deepcut::CutOperation>(window->tool()->parameters());
    auto* point_y = window->findChild<QDoubleSpinBox*>("cut.point.y");
    QVERIFY(point_y);
    point_y->setValue(point_y->value() + 0.05 * window->scene()->size);
    const auto moved = std::get<deepcut::CutOperation>(window->tool()->parameters());
    QVERIFY(moved.plane.point.y > placed.plane.point.y);
    QVERIFY2(preview_segments(*window) > 10, "the cut contour is previewed on the model");
    save_shot(*window, shots, "cut_preview");
    before.push_back(export_to("before0"));
    QVERIFY(!before.back().empty());
    QTest::mouseClick(window->findChild<QPushButton*>("apply_button"), Qt::LeftButton);
    QVERIFY2(window->last_error().isEmpty(), qPrintable(window->last_error()));
    QCOMPARE(window->history()->count(), 1);
    QVERIFY(window->history()->text(0).startsWith("Cut"));
    QVERIFY(window->last_operation().contains("ms"));
    save_shot(*window, shots, "cut_applied");

    // Scalpel: placed across the front, applied with Enter at a posed time.
    if (!window->model()->animations.empty()) window->timeline()->set_time(0.25f);
    action_named(*window, "tool_tear")->trigger();
    QCOMPARE(window->tool_id(), std::string("tear"));
    QVERIFY2(preview_segments(*window) > 2, "the tear path is previewed on the model");
    auto* width = window->findChild<QDoubleSpinBox*>("tear.width");
    QVERIFY(width);
    width->setValue(0.01 * window->scene()->size);
    QCOMPARE(std::get<deepcut::TearOperation>(window->tool()->parameters()).options.width,
             static_cast<float>(width->value()));
    save_shot(*window, shots, "tear_preview");
    before.push_back(export_to("before1"));
    // Enter is the Apply action's shortcut; without a window manager the window never becomes
    // active under xvfb, so the action is triggered as the shortcut would.
    QAction* apply = action_named(*window, "apply_tool");
    QVERIFY(apply && apply->isEnabled());
    QVERIFY(apply->shortcuts().contains(QKeySequence(Qt::Key_Return)));
    apply->trigger();
    QVERIFY2(window->last_error().isEmpty(), qPrintable(window->last_error()));
    QCOMPARE(window->history()->count(), 2);
    QVERIFY(window->history()->text(1).startsWith("Tear"));
    save_shot(*window, shots, "tear_applied");

    // Drill: along the view direction through the centre, radius from the panel.
    window->timeline()->set_time(0.0f);
    action_named(*window, "tool_drill")->trigger();
    auto* radius = window->findChild<QDoubleSpinBox*>("drill.radius");
    QVERIFY(radius);
    radius->setValue(0.04 * window->scene()->size);
    auto* rim_edges = window->findChild<QSpinBox*>("drill.min_rim_edges");
    rim_edges->setValue(24);
    QCOMPARE(std::get<deepcut::DrillOperation>(window->tool()->parameters()).options.min_rim_edges, 24);
    QVERIFY2(preview_segments(*window) > 8, "the drill rims are previewed on the model");
    save_shot(*window, shots, "drill_preview");
    before.push_back(export_to("before2"));
    QTest::mouseClick(window->findChild<QPushButton*>("apply_button"), Qt::LeftButton);
    QVERIFY2(window->last_error().isEmpty(), qPrintable(window->last_error()));
    QCOMPARE(window->history()->count(), 3);
    QVERIFY(window->history()->text(2).startsWith("Drill"));
    save_shot(*window, shots, "drill_applied");
    const std::string final_bytes = export_to("final");

    // Undo all (each state exports exactly as it did before its operation), redo all, validate.
    check_undo_all_redo_all(*window, dir, before, final_bytes);
    if (QTest::currentTestFailed()) return;

    // The exported history replayed by the command line on the original model.
    const deepcut::History history = deepcut::model_history(deepcut::read_gltf(dir + "/redo.glb"));
    QCOMPARE(history.operations.size(), std::size_t(3));
    check_cli_apply_equals(history, dir, final_bytes);
    if (QTest::currentTestFailed()) return;

    // Clicking the first history entry goes back to that state (QUndoView sets the index).
    window->history()->setIndex(1);
    QVERIFY(export_to("back") == before[1]);
  }

  void thirty_mixed_operations_with_undo_redo_replay_with_the_cli() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    const std::string dir = deepcut::test::temp_dir("studio-session");
    std::uint32_t state = 12345u;  // a fixed linear congruential sequence: the same session every run
    auto next = [&state] {
      state = state * 1664525u + 1013904223u;
      return static_cast<float>(state >> 8) / static_cast<float>(1u << 24);  // [0, 1)
    };
    int applied = 0;
    for (int i = 0; i < 30; ++i) {
      const float size = window->scene()->size;
      const char* ids[3] = {"cut", "tear", "drill"};
      window->set_tool(ids[i % 3]);
      deepcut::OperationParams params = window->tool()->parameters();
      if (auto* cut = std::get_if<deepcut::CutOperation>(&params)) {
        cut->plane.point.y += (next() - 0.5f) * 0.6f * size;
        cut->plane.normal = glm::vec3(next() - 0.5f, 1.0f, next() - 0.5f);
      } else if (auto* tear = std::get_if<deepcut::TearOperation>(&params)) {
        const glm::vec3 shift((next() - 0.5f) * 0.2f * size, (next() - 0.5f) * 0.4f * size, 0.0f);
        for (glm::vec3* p : {&tear->start.handle, &tear->start.tip, &tear->end.handle, &tear->end.tip}) *p += shift;
      } else if (auto* drill = std::get_if<deepcut::DrillOperation>(&params)) {
        const glm::vec3 shift(0.0f, (next() - 0.5f) * 0.5f * size, 0.0f);
        drill->cylinder.a += shift;
        drill->cylinder.b += shift;
        drill->cylinder.radius = (0.01f + 0.02f * next()) * size;
      }
      window->tool()->set_parameters(params);
      // Undo after any operation restores the model byte for byte (export equality).
      const std::string snapshot = dir + "/state.glb";
      QVERIFY(window->export_file(QString::fromStdString(snapshot)));
      const std::string before = read_bytes(snapshot);
      const bool ok = window->apply_tool();
      if (ok) ++applied;
      else QVERIFY2(window->last_error().contains("misses"), qPrintable(window->last_error()));
      if (i % 4 == 3) {
        window->undo_action()->trigger();
        if (ok) {
          QVERIFY(window->export_file(QString::fromStdString(snapshot)));
          QVERIFY2(read_bytes(snapshot) == before, ("undo of operation " + std::to_string(i) + " does not restore the export").c_str());
        }
      }
      if (i % 8 == 7) window->redo_action()->trigger();
      if (!window->model()->animations.empty()) window->timeline()->set_time(next() * 2.0f);
    }
    QVERIFY(applied >= 15);
    const std::string studio = dir + "/session.glb";
    QVERIFY(window->export_file(QString::fromStdString(studio)));
    const deepcut::History history = deepcut::model_history(deepcut::read_gltf(studio));
    QCOMPARE(static_cast<int>(history.operations.size()), window->history()->index());
    check_cli_apply_equals(history, dir, read_bytes(studio));
    if (QTest::currentTestFailed()) return;
    const auto validation = deepcut::test::validate_gltf(studio);
    QVERIFY2(validation.exit_code == 0, (validation.out + validation.err).c_str());
  }

  // The studio keeps the operations' preprocessing (posed positions, grids) across drills and
  // tears: after each it describes the new state exactly as a fresh build would; undo and a new
  // pose leave it for a rebuild, which then matches too.
  void the_tools_keep_the_operation_index_equal_to_a_rebuild() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    QVERIFY(window->posed_model() != nullptr);
    auto expect_fresh = [&](const char* when) {
      const deepcut::PosedModel* index = window->posed_model();
      QVERIFY2(index != nullptr, when);
      const std::string difference = deepcut::test::difference_from_fresh_build(*index, *window->model());
      QVERIFY2(difference.empty(), (std::string(when) + ": " + difference).c_str());
    };
    // The previews visit the posed model's grid cells and draw exactly what a scan of every face draws.
    auto expect_same_previews = [&](const char* when) {
      const deepcut::plugins::Scene& scene = *window->scene();
      QVERIFY2(std::any_of(scene.instances.begin(), scene.instances.end(),
                           [](const auto& p) { return p.grid != nullptr; }),
               when);
      deepcut::plugins::Scene scan = scene;
      for (auto& piece : scan.instances) piece.grid = nullptr;
      for (const char* id : {"cut", "tear", "drill"}) {
        window->set_tool(id);
        const deepcut::Overlay with_grid = window->tool()->preview(scene), without = window->tool()->preview(scan);
        QVERIFY2(!with_grid.lines.empty() && !with_grid.lines.front().endpoints.empty(), when);
        QVERIFY2(with_grid.lines.front().endpoints == without.lines.front().endpoints, when);
      }
    };
    expect_same_previews("after opening");
    if (QTest::currentTestFailed()) return;
    const float size = window->scene()->size;
    window->set_tool("drill");
    auto drill = std::get<deepcut::DrillOperation>(window->tool()->parameters());
    drill.cylinder.radius = 0.02f * size;
    window->tool()->set_parameters(drill);
    QVERIFY2(window->apply_tool(), qPrintable(window->last_error()));
    expect_fresh("after a drill");
    if (QTest::currentTestFailed()) return;
    window->set_tool("tear");
    QVERIFY2(window->apply_tool(), qPrintable(window->last_error()));
    expect_fresh("after a tear");
    if (QTest::currentTestFailed()) return;
    expect_same_previews("after a drill and a tear");
    if (QTest::currentTestFailed()) return;
    window->undo_action()->trigger();
    // A local undo leaves the posed model following the model (as a fresh build), else none.
    if (window->posed_model()) {
      expect_fresh("followed through undo");
      if (QTest::currentTestFailed()) return;
    }
    window->refresh_posed_model();
    expect_fresh("after undo");
    if (QTest::currentTestFailed()) return;
    if (!window->model()->animations.empty()) {
      window->timeline()->set_time(1.5f);
      window->refresh_posed_model();
      QVERIFY(window->posed_model()->time() == window->scene()->time);
      expect_fresh("after a new pose");
      if (QTest::currentTestFailed()) return;
      expect_same_previews("after a new pose");
      if (QTest::currentTestFailed()) return;
      window->set_tool("drill");
      QVERIFY2(window->apply_tool(), qPrintable(window->last_error()));
      expect_fresh("after a drill in the new pose");
    }
  }

  // A cut drops the operations' posed model (its pieces are new meshes); the studio rebuilds it once
  // idle, so the previews and the next drill or tear do not pay for a whole build themselves.
  void a_cut_leaves_the_operation_index_to_an_idle_rebuild() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    QVERIFY(window->posed_model() != nullptr);
    window->set_tool("cut");
    QVERIFY2(window->apply_tool(), qPrintable(window->last_error()));
    QTRY_VERIFY_WITH_TIMEOUT(window->posed_model() != nullptr, 20000);
    const deepcut::PosedModel* index = window->posed_model();
    const std::string difference = deepcut::test::difference_from_fresh_build(*index, *window->model());
    QVERIFY2(difference.empty(), difference.c_str());
  }

  // The time line moved: see cut_right_after_the_pose_moved.
  void a_cut_right_after_the_time_line_moved_cuts_at_the_shown_pose() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    QVERIFY(!window->model()->animations.empty());
    cut_right_after_the_pose_moved(*window, "time_line", [&](int round) {
      window->timeline()->set_time(round == 0 ? 1.5f : 1.0f);
      QCOMPARE(window->scene()->time, round == 0 ? 1.5f : 1.0f);
    });
  }

  // The morph weights were set by hand (AnimatedMorphCube): see cut_right_after_the_pose_moved.
  void a_cut_right_after_the_morph_weights_moved_cuts_at_the_shown_pose() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY2(window->open_file(kMorphCube), qPrintable(window->last_error()));
    auto* panel = window->findChild<deepcut::studio::MorphPanel*>();
    QVERIFY(panel);
    const int node = window->scene()->instances[0].node;
    cut_right_after_the_pose_moved(*window, "morph_weights", [&](int round) {
      panel->set_weight(node, 0, round == 0 ? 1.0f : 0.5f);
      panel->set_weight(node, 1, 0.0f);
      const std::vector<float> hand = {round == 0 ? 1.0f : 0.5f, 0.0f};
      QCOMPARE(window->scene()->weights.at(node), hand);
    });
  }

  void a_tool_that_misses_reports_and_keeps_the_model() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    window->set_tool("cut");
    auto op = std::get<deepcut::CutOperation>(window->tool()->parameters());
    op.plane.point.y += 10.0f * window->scene()->size;
    window->tool()->set_parameters(op);
    QVERIFY(qAbs(window->findChild<QDoubleSpinBox*>("cut.point.y")->value() - static_cast<double>(op.plane.point.y)) < 1e-3);
    const std::string model = model_bytes(*window, "before_miss");
    QVERIFY(!window->apply_tool());
    QVERIFY(window->last_error().contains("misses"));
    QVERIFY(model_bytes(*window, "after_miss") == model);
    QCOMPARE(window->history()->count(), 0);
    QVERIFY_EXCEPTION_THROWN(window->tool()->set_parameters(deepcut::DrillOperation{}), deepcut::Error);
  }

 private:
  // The pose moved (`move_pose(round)`: the time line or the morph weights) while the operations'
  // posed model is still at the old pose (the idle rebuild has not run yet). A cut right away is
  // lent the scene's posed positions (OperationsHost::lend_scene_pose) instead of posing the whole
  // model again, which gives the same pieces: so the lend is seen where a cut that misses leaves
  // it (the lend comes before the cut, hit or miss): the operations' posed model is then another
  // object than before, at the shown pose, without grids: the scene's copy. Without the lend it
  // stays at the old pose (the time line: the cut poses the model on its own) or is the same
  // object posed again in place (the weights: Operation::weights re-pose it); an idle rebuild has
  // grids. Then, the pose moved again, a cut that hits equals the operation applied on its own.
  static void cut_right_after_the_pose_moved(MainWindow& window, const std::string& name,
                                             const std::function<void(int round)>& move_pose) {
    QTRY_VERIFY_WITH_TIMEOUT(window.posed_model() != nullptr, 20000);
    const deepcut::plugins::Scene& scene = *window.scene();
    auto shown = [&] { return deepcut::PoseKey(scene.animation, scene.time, scene.weights); };
    window.set_tool("cut");

    move_pose(0);
    if (QTest::currentTestFailed()) return;
    const deepcut::PosedModel* old_posed = window.posed_model();
    QVERIFY(old_posed && !old_posed->matches(shown()));
    const auto old_address = reinterpret_cast<std::uintptr_t>(old_posed);
    deepcut::CutOperation away = cut_through_the_middle(window);
    away.plane.point += 2.0f * scene.size * away.plane.normal;
    window.tool()->set_parameters(away);
    const std::string model = model_bytes(window, name + "_before_miss");
    QVERIFY(!window.apply_tool());
    QVERIFY(window.last_error().contains("misses"));
    QVERIFY(model_bytes(window, name + "_after_miss") == model);
    QCOMPARE(window.history()->count(), 0);
    const deepcut::PosedModel* lent = window.posed_model();
    QVERIFY2(lent && lent->matches(shown()), "the operations' posed model is not at the shown pose");
    QVERIFY2(reinterpret_cast<std::uintptr_t>(lent) != old_address,
             "the old posed model was posed again in place");
    QVERIFY(lent->size() > 0);
    for (const auto& [id, mesh] : lent->instances())
      QVERIFY2(mesh.gridless, "the operations' posed model has grids: not the scene's positions");

    move_pose(1);
    if (QTest::currentTestFailed()) return;
    QVERIFY(window.posed_model() != nullptr && !window.posed_model()->matches(shown()));
    window.tool()->set_parameters(cut_through_the_middle(window));
    deepcut::Operation op;
    op.params = window.tool()->parameters();
    op.animation = scene.animation;
    op.time = scene.time;
    op.weights = scene.weights;
    deepcut::Model expected = *window.model();
    QVERIFY(deepcut::apply_operation(expected, op).status == deepcut::OpStatus::Ok);
    QVERIFY2(window.apply_tool(), qPrintable(window.last_error()));
    const std::string path = deepcut::test::temp_dir("studio-states") + "/" + name + "_cut_expected.glb";
    deepcut::write_gltf(expected, path);
    QVERIFY2(model_bytes(window, name + "_cut") == read_bytes(path),
             "the cut differs from the operation alone");
  }
};

int main(int argc, char** argv) {
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setOrganizationName("DeepCut");
  QApplication::setApplicationName("DeepCut Studio Tool Tests");
  StudioToolsTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "tools_gui_test.moc"
