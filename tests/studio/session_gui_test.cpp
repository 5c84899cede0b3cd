// SPDX-License-Identifier: MIT
// GUI tests of the Poke tool and of editing the history (QTest under xvfb-run):
//  - synthesised press / move / release on the view with the Poke: vertices move while dragging,
//    come back to the skinned pose after release, also while the animation plays; the model and
//    its history never change;
//  - three operations, the first edited from the History panel: the later ones re-run, the export
//    equals `deepcut apply` of the edited history on the original model and validates, undo
//    restores the previous export byte for byte; an edit that makes a later operation miss marks
//    it instead of failing;
//  - once idle (no step for MainWindow::kIdleReleaseMs, no task running) the studio hands the
//    heap's free memory back to the system, which it otherwise keeps for the next operation.
#include <QVTKOpenGLNativeWidget.h>
#include <unistd.h>

#include <QAction>
#include <QApplication>
#include <QDoubleSpinBox>
#include <QLabel>
#include <QListWidget>
#include <QMouseEvent>
#include <QPushButton>
#include <QStandardPaths>
#include <QSurfaceFormat>
#include <QUndoStack>
#include <QtTest/QtTest>
#include <algorithm>
#include <fstream>
#include <vector>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/ops/operation.h"
#include "deepcut/core/process_memory.h"
#include "deepcut/plugins/tool.h"
#include "main_window.h"
#include "resident.h"
#include "scene_view.h"
#include "studio_test_support.h"
#include "timeline.h"
#include "tools.h"

using deepcut::studio::MainWindow;
using deepcut::test::resident_mib;
using deepcut::test::studio::export_bytes;
using deepcut::test::studio::kCactus;
using deepcut::test::studio::model_bytes;
using deepcut::test::studio::read_bytes;
using deepcut::test::studio::shown_window;

namespace {

bool g_keeps_freed_memory = false;  // keep_freed_memory took effect (main)

/// Largest distance between what the view draws for instance 0 and the skinned pose of the scene.
float drawn_offset(MainWindow& window) {
  const std::vector<glm::vec3> drawn = window.view()->instance_positions(0);
  const std::vector<glm::vec3>& posed = window.scene()->instances[0].posed();
  float largest = 0.0f;
  for (std::size_t v = 0; v < drawn.size() && v < posed.size(); ++v)
    largest = std::max(largest, glm::length(drawn[v] - posed[v]));
  return largest;
}

/// The posed vertex of instance 0 nearest the camera (on the surface facing it).
glm::vec3 front_point(MainWindow& window) {
  const glm::vec3 towards_camera = -window.view()->view_direction();
  const std::vector<glm::vec3>& posed = window.scene()->instances[0].posed();
  return *std::max_element(posed.begin(), posed.end(), [&](const glm::vec3& a, const glm::vec3& b) {
    return glm::dot(a, towards_camera) < glm::dot(b, towards_camera);
  });
}

void send_mouse(QWidget* target, QEvent::Type type, const QPoint& at, Qt::MouseButtons buttons) {
  const Qt::MouseButton button = type == QEvent::MouseMove ? Qt::NoButton : Qt::LeftButton;
  QMouseEvent event(type, at, target->mapToGlobal(at), button, buttons, Qt::NoModifier);
  QApplication::sendEvent(target, &event);
}

/// Presses on `at`, drags by `by` in a few steps and lets the simulation run while held.
void press_and_drag(MainWindow& window, const QPoint& at, const QPoint& by) {
  QWidget* vtk = window.findChild<QWidget*>("vtk_view");
  send_mouse(vtk, QEvent::MouseButtonPress, at, Qt::LeftButton);
  for (int k = 1; k <= 5; ++k) {
    send_mouse(vtk, QEvent::MouseMove, at + by * k / 5, Qt::LeftButton);
    QTest::qWait(40);
  }
  QTest::qWait(300);
}

void release(MainWindow& window, const QPoint& at) {
  send_mouse(window.findChild<QWidget*>("vtk_view"), QEvent::MouseButtonRelease, at, Qt::NoButton);
}

std::string cli_apply(const std::vector<MainWindow::OperationEntry>& entries, const std::string& dir,
                      const std::string& name) {
  deepcut::History history;
  for (const auto& entry : entries) history.operations.push_back(entry.operation);
  return deepcut::test::studio::cli_apply(history, dir, name);
}

}  // namespace

class StudioSessionTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase() {
    QStandardPaths::setTestModeEnabled(true);
    QSettings().clear();
  }

  void poke_drag_deforms_the_model_and_it_springs_back() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    const std::string model = model_bytes(*window, "before_poke");
    const std::size_t faces = window->scene()->instances[0].surface->face_count();
    window->set_tool("poke");
    QVERIFY(!window->tool()->makes_operation());
    QVERIFY(!window->findChild<QPushButton*>("apply_button")->isEnabled());
    QVERIFY2(window->findChild<QLabel*>("poke.status")->text().contains("particles"),
             qPrintable(window->findChild<QLabel*>("poke.status")->text()));
    const float size = window->scene()->size;
    QCOMPARE(drawn_offset(*window), 0.0f);

    const QPoint at = window->view()->project(front_point(*window));
    press_and_drag(*window, at, QPoint(90, -30));
    // The springs pull the grabbed particles after the cursor on the timer (however busy the machine).
    QTRY_VERIFY_WITH_TIMEOUT(drawn_offset(*window) > 0.02f * size, 10000);
    QVERIFY(!window->tool()->preview(*window->scene()).empty());  // grab point and reach drawn
    save_shot(*window, "poke_drag");
    release(*window, at + QPoint(90, -30));
    // Springs back (damped) to exactly the skinned pose once settled.
    QTRY_VERIFY_WITH_TIMEOUT(drawn_offset(*window) <= 1e-5f * size, 15000);
    // The poke never changes the model or its history.
    QVERIFY(model_bytes(*window, "after_poke") == model);
    QCOMPARE(window->history()->count(), 0);
    QCOMPARE(window->scene()->instances[0].surface->face_count(), faces);
    QVERIFY(window->operations().empty());
    QVERIFY(!window->apply_tool());

    // A click without dragging pushes the surface in; it settles again.
    QWidget* vtk = window->findChild<QWidget*>("vtk_view");
    send_mouse(vtk, QEvent::MouseButtonPress, at, Qt::LeftButton);
    send_mouse(vtk, QEvent::MouseButtonRelease, at, Qt::NoButton);
    QTRY_VERIFY_WITH_TIMEOUT(drawn_offset(*window) > 1e-3f * size, 5000);
    QTRY_VERIFY_WITH_TIMEOUT(drawn_offset(*window) <= 1e-5f * size, 15000);

    // Another tool: the camera gets the mouse again and the model is drawn as posed.
    window->set_tool("cut");
    QCOMPARE(drawn_offset(*window), 0.0f);
  }

  void poke_works_while_the_animation_plays() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    QVERIFY(!window->model()->animations.empty());
    window->set_tool("poke");
    const float size = window->scene()->size;
    const QPoint at = window->view()->project(front_point(*window));
    window->timeline()->play();
    const float t0 = window->scene()->time;
    press_and_drag(*window, at, QPoint(-80, 40));
    // Dented against the pose of the moment, while the time runs; the dent stays while held.
    QTRY_VERIFY_WITH_TIMEOUT(drawn_offset(*window) > 0.02f * size, 10000);
    QTRY_VERIFY_WITH_TIMEOUT(window->scene()->time != t0, 5000);
    QVERIFY2(drawn_offset(*window) > 0.02f * size, "the dent stays while held and the model animates");
    save_shot(*window, "poke_playing");
    release(*window, at + QPoint(-80, 40));
    QTRY_VERIFY_WITH_TIMEOUT(drawn_offset(*window) <= 1e-5f * size, 15000);
    const float t1 = window->scene()->time;
    QTRY_VERIFY_WITH_TIMEOUT(window->scene()->time != t1, 5000);  // still playing
    QCOMPARE(drawn_offset(*window), 0.0f);
    window->timeline()->pause();
    QCOMPARE(window->history()->count(), 0);
  }

  void an_idle_studio_hands_free_memory_back() {
    if (!g_keeps_freed_memory) QSKIP("this C library has no setting to keep freed memory");
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    window->set_tool("tear");
    QVERIFY2(window->apply_tool(), qPrintable(window->last_error()));
    while (window->task()->busy()) QTest::qWait(20);   // the posed model the step rebuilds
    QTest::qWait(MainWindow::kIdleReleaseMs * 3 / 4);  // most of the tear's idle interval
    // 64 MiB written and freed: the heap keeps it for the next operation ...
    constexpr std::size_t kBlock = std::size_t(64) << 20;
    auto* block = new std::vector<char>(kBlock, 1);
    QVERIFY(block->back() == 1);
    delete block;
    const double kept = resident_mib();
    window->undo_action()->trigger();  // a step shown: the interval starts again
    // Past the end of the tear's interval, within the undo's: still kept.
    QTest::qWait(MainWindow::kIdleReleaseMs / 2);
    QVERIFY2(resident_mib() > kept - 16.0, "the free memory went back before the studio was idle");
    // ... until the studio has been idle for the interval.
    while (window->task()->busy()) QTest::qWait(20);
    QTest::qWait(MainWindow::kIdleReleaseMs + 500);
    const double released = resident_mib();
    QVERIFY2(released < kept - 32.0,
             qPrintable(QString("resident %1 MiB once idle, %2 MiB before").arg(released).arg(kept)));
  }

  void editing_the_first_of_three_operations_reruns_the_rest() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    const std::string dir = deepcut::test::temp_dir("studio-edit");
    auto export_to = [&](const std::string& name) { return export_bytes(*window, dir, name); };
    const float size = window->scene()->size;
    const deepcut::plugins::SceneCounts opened = deepcut::plugins::scene_counts(*window->scene());

    // Three operations with the tools, as placed (the cut a little above the centre).
    window->set_tool("cut");
    auto cut = std::get<deepcut::CutOperation>(window->tool()->parameters());
    cut.plane.point.y += 0.1f * size;
    window->tool()->set_parameters(cut);
    QVERIFY2(window->apply_tool(), qPrintable(window->last_error()));
    window->set_tool("tear");
    QVERIFY2(window->apply_tool(), qPrintable(window->last_error()));
    window->set_tool("drill");
    window->findChild<QDoubleSpinBox*>("drill.radius")->setValue(0.04 * size);
    QVERIFY2(window->apply_tool(), qPrintable(window->last_error()));
    QCOMPARE(window->history()->count(), 3);
    QCOMPARE(window->operations().size(), std::size_t(3));
    QCOMPARE(window->operations_list()->count(), 3);
    const std::string before_edit = export_to("before_edit");

    // Select the cut in the History panel and edit it: the model as it was before it, the Plane
    // tool with its parameters.
    window->operations_list()->setCurrentRow(0);
    auto* edit = window->findChild<QPushButton*>("edit_operation");
    QVERIFY(edit && edit->isEnabled());
    QTest::mouseClick(edit, Qt::LeftButton);
    QCOMPARE(window->editing_operation(), 0);
    QCOMPARE(window->tool_id(), std::string("cut"));
    QCOMPARE(std::get<deepcut::CutOperation>(window->tool()->parameters()).plane.point, cut.plane.point);
    QCOMPARE(deepcut::plugins::scene_counts(*window->scene()).triangles, opened.triangles);
    QVERIFY(window->findChild<QLabel*>("edit_banner")->isVisible());
    auto* point_y = window->findChild<QDoubleSpinBox*>("cut.point.y");
    point_y->setValue(point_y->value() - 0.2 * size);
    QTest::mouseClick(window->findChild<QPushButton*>("apply_button"), Qt::LeftButton);
    QVERIFY2(window->last_error().isEmpty(), qPrintable(window->last_error()));
    QCOMPARE(window->editing_operation(), -1);
    QCOMPARE(window->history()->count(), 4);  // one undoable step
    const auto entries = window->operations();
    QCOMPARE(entries.size(), std::size_t(3));
    for (const auto& entry : entries) QVERIFY(entry.applied());
    QVERIFY(std::get<deepcut::CutOperation>(entries[0].operation.params).plane.point.y < cut.plane.point.y);
    QVERIFY(std::holds_alternative<deepcut::TearOperation>(entries[1].operation.params));
    QVERIFY(std::holds_alternative<deepcut::DrillOperation>(entries[2].operation.params));
    const std::string edited = export_to("edited");
    QVERIFY(edited != before_edit);
    QVERIFY2(cli_apply(entries, dir, "cli_edited") == edited,
             "deepcut apply of the edited history on the original model differs from the studio");
    const auto validation = deepcut::test::validate_gltf(dir + "/edited.glb");
    QVERIFY2(validation.exit_code == 0, (validation.out + validation.err).c_str());

    // Undo restores the previous history exactly; redo the edit.
    window->undo_action()->trigger();
    QVERIFY2(export_to("undone") == before_edit, "undo of the edit does not restore the previous export");
    QCOMPARE(window->operations().size(), std::size_t(3));
    QCOMPARE(std::get<deepcut::CutOperation>(window->operations()[0].operation.params).plane.point, cut.plane.point);
    window->redo_action()->trigger();
    QVERIFY(export_to("redone") == edited);

    // Cancelling an edit changes nothing.
    QVERIFY(window->edit_operation(1));
    QCOMPARE(window->tool_id(), std::string("tear"));
    window->cancel_edit();
    QCOMPARE(window->editing_operation(), -1);
    QVERIFY(export_to("cancelled") == edited);
    QCOMPARE(window->history()->count(), 4);
  }

  void an_edit_that_makes_a_later_operation_miss_marks_it() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    const std::string dir = deepcut::test::temp_dir("studio-edit-miss");
    const float size = window->scene()->size;
    // A cut, then a drill through the middle.
    window->set_tool("cut");
    QVERIFY2(window->apply_tool(), qPrintable(window->last_error()));
    window->set_tool("drill");
    window->findChild<QDoubleSpinBox*>("drill.radius")->setValue(0.03 * size);
    QVERIFY2(window->apply_tool(), qPrintable(window->last_error()));
    const std::string drilled = model_bytes(*window, "drilled");

    // Edit the cut to keep only what lies well above the drill: the drill no longer applies.
    QVERIFY(window->edit_operation(0));
    auto cut = std::get<deepcut::CutOperation>(window->tool()->parameters());
    cut.plane.point.y += 0.25f * size;
    cut.options.keep = deepcut::CutKeep::Positive;
    window->tool()->set_parameters(cut);
    QVERIFY2(window->apply_tool(), qPrintable(window->last_error()));
    const auto entries = window->operations();
    QCOMPARE(entries.size(), std::size_t(2));
    QVERIFY(entries[0].applied());
    QVERIFY(!entries[1].applied());
    QCOMPARE(entries[1].status, deepcut::OpStatus::NoIntersection);
    QVERIFY2(window->operations_list()->item(1)->text().contains("no longer applies"),
             qPrintable(window->operations_list()->item(1)->text()));
    save_shot(*window, "edit_marked");
    // The result is still what the command line makes of the edited history.
    const std::string studio = dir + "/studio.glb";
    QVERIFY(window->export_file(QString::fromStdString(studio)));
    QVERIFY2(cli_apply(entries, dir, "cli") == read_bytes(studio), "deepcut apply of the edited history differs");
    // The skipped drill can be edited in turn (it is listed), and undo brings it back applied.
    window->undo_action()->trigger();
    QVERIFY(model_bytes(*window, "undone") == drilled);
    QVERIFY(window->operations()[1].applied());
  }

 private:
  static void save_shot(MainWindow& window, const std::string& name) {
    const std::string dir = deepcut::test::temp_dir("studio-session-shots");
    window.screenshot().save(QString::fromStdString(dir + "/" + name + ".png"));
  }
};

int main(int argc, char** argv) {
  g_keeps_freed_memory = deepcut::keep_freed_memory();  // as the studio runs (main.cpp)
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setOrganizationName("DeepCut");
  QApplication::setApplicationName("DeepCut Studio Session Tests");
  StudioSessionTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "session_gui_test.moc"
