// SPDX-License-Identifier: MIT
// GUI tests of the tool widgets (QTest under xvfb-run): each widget is placed by choosing its
// tool and driven with recorded VTK interaction events (vtkInteractorEventRecorder playing an
// event string on the view's interactor): drags move handles, the panel's numbers follow the
// drag, typed numbers move the widget, Escape restores. The end-to-end case drags, applies cut,
// tear and drill, undoes and redoes them all, exports, validates, and compares with the
// command line's cut, tear and drill run on the parameters read back from the panels.
#include <QVTKOpenGLNativeWidget.h>
#include <vtkCamera.h>
#include <vtkCommand.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkInteractorEventRecorder.h>
#include <vtkNew.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>

#include <QAction>
#include <QApplication>
#include <QCursor>
#include <QDoubleSpinBox>
#include <QPushButton>
#include <QSpinBox>
#include <QStandardPaths>
#include <QSurfaceFormat>
#include <QUndoStack>
#include <QtTest/QtTest>
#include <cstdio>
#include <glm/geometric.hpp>
#include <sstream>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/ops/operation.h"
#include "deepcut/plugins/tool.h"
#include "deepcut/widgets/drill_widget.h"
#include "deepcut/widgets/plane_widget.h"
#include "deepcut/widgets/scalpel_widget.h"
#include "main_window.h"
#include "scene_view.h"
#include "timeline.h"
#include "studio_test_support.h"
#include "tools.h"

using deepcut::studio::MainWindow;
using deepcut::test::studio::check_cli_apply_equals;
using deepcut::test::studio::check_undo_all_redo_all;
using deepcut::test::studio::export_bytes;
using deepcut::test::studio::kCactus;
using deepcut::test::studio::read_bytes;
using deepcut::test::studio::shown_window;

namespace {

QVTKOpenGLNativeWidget* vtk_view(MainWindow& window) {
  return window.findChild<QVTKOpenGLNativeWidget*>("vtk_view");
}

vtkRenderer* model_renderer(MainWindow& window) {
  return vtk_view(window)->renderWindow()->GetRenderers()->GetFirstRenderer();
}

/// VTK display coordinates (pixels, origin bottom left) of world point `p`.
glm::dvec2 display(MainWindow& window, const glm::vec3& p) {
  vtkRenderer* renderer = model_renderer(window);
  renderer->SetWorldPoint(p.x, p.y, p.z, 1.0);
  renderer->WorldToDisplay();
  double d[3];
  renderer->GetDisplayPoint(d);
  return {d[0], d[1]};
}

glm::ivec2 pixel(const glm::dvec2& d) {
  return {static_cast<int>(std::lround(d.x)), static_cast<int>(std::lround(d.y))};
}

/// Plays `events` on the view (vtkInteractorEventRecorder's stream version 1, one event a line:
/// name, x, y, ctrl, shift, key code, repeat count, key sym).
void play(MainWindow& window, const std::string& events) {
  vtkNew<vtkInteractorEventRecorder> recorder;
  recorder->SetInteractor(vtk_view(window)->interactor());
  recorder->ReadFromInputStringOn();
  const std::string log = "# StreamVersion 1\n" + events;
  recorder->SetInputString(log.c_str());
  recorder->Play();
  recorder->Off();
  QApplication::processEvents();
}

std::string event_line(const char* name, const glm::ivec2& p) {
  return std::string(name) + " " + std::to_string(p.x) + " " + std::to_string(p.y) + " 0 0 0 0 0\n";
}

/// A left-button drag from `from` to `to` (display pixels) in a few steps, as a mouse would.
std::string drag_events(const glm::ivec2& from, const glm::ivec2& to, const char* button = "Left") {
  std::string log = event_line("MouseMoveEvent", from) +
                    event_line((std::string(button) + "ButtonPressEvent").c_str(), from);
  for (int k = 1; k <= 6; ++k) log += event_line("MouseMoveEvent", from + (to - from) * k / 6);
  return log + event_line((std::string(button) + "ButtonReleaseEvent").c_str(), to);
}

glm::vec3 panel_vec(MainWindow& window, const QString& name) {
  glm::vec3 v;
  const char* axes[3] = {".x", ".y", ".z"};
  for (int k = 0; k < 3; ++k)
    v[k] = static_cast<float>(window.findChild<QDoubleSpinBox*>(name + axes[k])->value());
  return v;
}

/// The panel shows 4 decimals.
bool panel_shows(const glm::vec3& panel, const glm::vec3& value) {
  return glm::length(panel - value) < 1.5e-4f * std::sqrt(3.0f);
}

glm::vec3 to_vec(const double* p) { return glm::vec3(p[0], p[1], p[2]); }

std::string number(float v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", static_cast<double>(v));
  return buffer;
}
std::string numbers(std::initializer_list<glm::vec3> vs) {
  std::string out;
  for (const glm::vec3& v : vs)
    for (int k = 0; k < 3; ++k) out += (out.empty() ? "" : ",") + number(v[k]);
  return out;
}

/// Clicks the model at world point `p` (a press and release without motion: a pick). The
/// skeleton is hidden first: a click on a bone picks the bone, not the surface.
void click(MainWindow& window, const glm::vec3& p) {
  window.set_skeleton_visible(false);
  const glm::ivec2 at = pixel(display(window, p));
  play(window, event_line("MouseMoveEvent", at) + event_line("LeftButtonPressEvent", at) +
                   event_line("LeftButtonReleaseEvent", at));
}

/// The middle of the cactus's trunk at the front, found by picking through the view centre.
glm::vec3 front_surface_point(MainWindow& window) {
  deepcut::studio::SceneView* view = window.view();
  const QPoint centre(view->width() / 2, view->height() / 2);
  const auto p = view->surface_point_at(centre);
  return p ? *p : glm::vec3(0.0f);
}

/// Drags the plane's origin sideways and pushes the plane up; checks panel and contour.
void drag_plane(MainWindow& window) {
  auto* widget = static_cast<deepcut::PlaneWidget*>(window.tool()->widget());
  QVERIFY(widget && widget->GetEnabled());
  const auto before = std::get<deepcut::CutOperation>(window.tool()->parameters());
  // The origin handle: moves within the plane (y stays, x/z follow the mouse).
  const glm::ivec2 origin = pixel(display(window, before.plane.point));
  play(window, drag_events(origin, origin + glm::ivec2(60, 0)));
  const auto moved = std::get<deepcut::CutOperation>(window.tool()->parameters());
  QVERIFY2(glm::length(moved.plane.point - before.plane.point) > 1e-3f * window.scene()->size,
           "dragging the origin handle moves the plane's point");
  QVERIFY(std::abs(moved.plane.point.y - before.plane.point.y) < 1e-4f * window.scene()->size);
  QVERIFY(glm::length(moved.plane.normal - before.plane.normal) < 1e-5f);
  QVERIFY(panel_shows(panel_vec(window, "cut.point"), moved.plane.point));
  // The new origin is under the release point (within two pixels).
  QVERIFY(glm::length(display(window, moved.plane.point) - glm::dvec2(origin + glm::ivec2(60, 0))) < 2.0);
  QVERIFY(glm::length(to_vec(widget->GetPlaneRepresentation()->GetOrigin()) - moved.plane.point) < 1e-5f);

  // The plane itself (left of the origin, on the translucent polygon): pushed up along +Y.
  const glm::vec3 on_plane = moved.plane.point - glm::vec3(0.25f * window.scene()->size, 0.0f, 0.0f);
  const glm::ivec2 grab = pixel(display(window, on_plane));
  play(window, drag_events(grab, grab + glm::ivec2(0, 40)));
  const auto pushed = std::get<deepcut::CutOperation>(window.tool()->parameters());
  QVERIFY2(pushed.plane.point.y > moved.plane.point.y + 1e-3f * window.scene()->size,
           "dragging the plane up pushes it along +Y");
  QVERIFY(panel_shows(panel_vec(window, "cut.point"), pushed.plane.point));
  // The preview follows: every contour point lies on the pushed plane.
  const deepcut::Overlay overlay = window.tool()->preview(*window.scene());
  QVERIFY(!overlay.lines.empty() && overlay.lines.front().endpoints.size() > 20);
  const glm::vec3 n = glm::normalize(pushed.plane.normal);
  for (const glm::vec3& p : overlay.lines.front().endpoints)
    QVERIFY(std::abs(glm::dot(p - pushed.plane.point, n)) < 1e-4f * window.scene()->size);
}

/// Turns the camera about the view up (degrees) so blades and axes are seen from the side.
void turn_camera(MainWindow& window, double degrees) {
  model_renderer(window)->GetActiveCamera()->Azimuth(degrees);
  window.view()->render();
}

}  // namespace

class StudioWidgetsTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase() {
    QStandardPaths::setTestModeEnabled(true);
    QSettings().clear();
  }
  // A tool is placed at the surface under the mouse cursor when the cursor is over the view:
  // keep the cursor off the view so the tests place tools by clicks.
  void init() { QCursor::setPos(0, 0); }

  void plane_widget_drags_and_mirrors_the_panel() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    window->findChild<QAction*>("tool_cut")->trigger();
    QCOMPARE(window->tool_id(), std::string("cut"));
    // Placed through the bounding box's centre.
    const deepcut::BoundingBox box = deepcut::plugins::scene_bounds(*window->scene());
    const auto placed = std::get<deepcut::CutOperation>(window->tool()->parameters());
    QVERIFY(glm::length(placed.plane.point - 0.5f * (box.min + box.max)) < 1e-5f * window->scene()->size);
    drag_plane(*window);
    if (QTest::currentTestFailed()) return;
    // Typed numbers move the widget, and do not come back as a drag.
    auto* widget = static_cast<deepcut::PlaneWidget*>(window->tool()->widget());
    window->findChild<QDoubleSpinBox*>("cut.normal.x")->setValue(1.0);
    const glm::vec3 normal = glm::normalize(glm::vec3(1.0f, 1.0f, 0.0f));
    QVERIFY(glm::length(to_vec(widget->GetPlaneRepresentation()->GetNormal()) - normal) < 1e-5f);
    QCOMPARE(std::get<deepcut::CutOperation>(window->tool()->parameters()).plane.normal,
             glm::vec3(1.0f, 1.0f, 0.0f));
    // The quick normal buttons turn the plane about its point, panel and widget alike.
    const glm::vec3 point = std::get<deepcut::CutOperation>(window->tool()->parameters()).plane.point;
    QTest::mouseClick(window->findChild<QPushButton*>("cut.normal_x"), Qt::LeftButton);
    const auto across_x = std::get<deepcut::CutOperation>(window->tool()->parameters());
    QCOMPARE(across_x.plane.normal, glm::vec3(1.0f, 0.0f, 0.0f));
    QCOMPARE(across_x.plane.point, point);
    QCOMPARE(panel_vec(*window, "cut.normal"), glm::vec3(1.0f, 0.0f, 0.0f));
    QVERIFY(glm::length(to_vec(widget->GetPlaneRepresentation()->GetNormal()) - glm::vec3(1.0f, 0.0f, 0.0f)) <
            1e-6f);
    // Choosing no tool hides the widget.
    window->set_tool("");
    QVERIFY(!widget->GetEnabled());
  }

  void scalpel_widget_placed_at_the_click_drags_the_end_tip() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    const float size = window->scene()->size;
    // A click on the model, then the Scalpel: the swept quad passes through the clicked point.
    const glm::vec3 p = front_surface_point(*window);
    click(*window, p);
    window->set_tool("tear");
    auto op = std::get<deepcut::TearOperation>(window->tool()->parameters());
    const glm::vec3 quad_normal =
        glm::normalize(glm::cross(op.start.tip - op.start.handle, op.end.handle - op.start.handle));
    QVERIFY(std::abs(glm::dot(p - op.start.handle, quad_normal)) < 1e-4f * size);
    const glm::vec3 centre = 0.25f * (op.start.handle + op.start.tip + op.end.handle + op.end.tip);
    QVERIFY2(glm::length(centre - p) < 0.05f * size, "the blade sits at the clicked point");
    QVERIFY2(!window->tool()->preview(*window->scene()).lines.front().endpoints.empty(),
             "the tear path is previewed at the clicked point");

    // Seen from the side, drag the end pose's tip: only it moves, in the view plane, and lands
    // under the cursor; the panel shows it.
    turn_camera(*window, 60.0);
    auto* widget = static_cast<deepcut::ScalpelWidget*>(window->tool()->widget());
    const glm::ivec2 tip = pixel(display(*window, op.end.tip));
    const glm::ivec2 to = tip + glm::ivec2(-35, -25);
    play(*window, drag_events(tip, to));
    const auto dragged = std::get<deepcut::TearOperation>(window->tool()->parameters());
    QCOMPARE(dragged.start.handle, op.start.handle);
    QCOMPARE(dragged.start.tip, op.start.tip);
    QCOMPARE(dragged.end.handle, op.end.handle);
    QVERIFY(glm::length(dragged.end.tip - op.end.tip) > 1e-3f * size);
    QVERIFY(glm::length(display(*window, dragged.end.tip) - glm::dvec2(to)) < 2.0);
    QVERIFY(std::abs(glm::dot(dragged.end.tip - op.end.tip, window->view()->view_direction())) <
            1e-3f * size);
    QVERIFY(panel_shows(panel_vec(*window, "tear.end.tip"), dragged.end.tip));
    QVERIFY(glm::length(to_vec(widget->GetScalpelRepresentation()->GetEndTip()) - dragged.end.tip) < 1e-5f);

    // Escape during a drag puts the scalpel back where the drag started.
    const glm::ivec2 handle = pixel(display(*window, dragged.start.handle));
    std::string log = event_line("MouseMoveEvent", handle) + event_line("LeftButtonPressEvent", handle);
    log += event_line("MouseMoveEvent", handle + glm::ivec2(20, 20)) +
           event_line("MouseMoveEvent", handle + glm::ivec2(40, 30));
    play(*window, log);
    QVERIFY(glm::length(std::get<deepcut::TearOperation>(window->tool()->parameters()).start.handle -
                        dragged.start.handle) > 1e-3f * size);
    vtkRenderWindowInteractor* interactor = vtk_view(*window)->interactor();
    interactor->SetKeyEventInformation(0, 0, 27, 1, "Escape");
    interactor->InvokeEvent(vtkCommand::KeyPressEvent, nullptr);
    play(*window, event_line("LeftButtonReleaseEvent", handle + glm::ivec2(40, 30)));
    const auto restored = std::get<deepcut::TearOperation>(window->tool()->parameters());
    QCOMPARE(restored.start.handle, dragged.start.handle);
    QVERIFY(panel_shows(panel_vec(*window, "tear.start.handle"), dragged.start.handle));

    // A drag on empty background turns the camera, not the scalpel.
    play(*window, drag_events(glm::ivec2(15, 15), glm::ivec2(60, 25)));
    QCOMPARE(std::get<deepcut::TearOperation>(window->tool()->parameters()).end.tip, dragged.end.tip);
  }

  void drill_widget_along_the_view_drags_radius_and_end() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    const float size = window->scene()->size;
    const glm::vec3 p = front_surface_point(*window);
    click(*window, p);
    window->findChild<QAction*>("tool_drill")->trigger();
    const auto placed = std::get<deepcut::DrillOperation>(window->tool()->parameters());
    // Along the view direction through the clicked point.
    const glm::vec3 axis = glm::normalize(placed.cylinder.b - placed.cylinder.a);
    QVERIFY(glm::dot(axis, window->view()->view_direction()) > 0.9999f);
    const glm::vec3 to_p = p - placed.cylinder.a;
    QVERIFY(glm::length(to_p - glm::dot(to_p, axis) * axis) < 1e-4f * size);
    QVERIFY(!window->tool()->preview(*window->scene()).lines.front().endpoints.empty());

    // The radius handle sits on A's ring to the right: dragging it right widens the cylinder by
    // what the cursor moved, and the handle stays under the cursor.
    auto* widget = static_cast<deepcut::DrillWidget*>(window->tool()->widget());
    window->view()->render();
    const glm::vec3 handle = to_vec(widget->GetDrillRepresentation()->GetRadiusHandle());
    QVERIFY(std::abs(glm::length(handle - placed.cylinder.a) - placed.cylinder.radius) < 1e-4f * size);
    const glm::ivec2 grab = pixel(display(*window, handle));
    const glm::ivec2 to = grab + glm::ivec2(25, 0);
    play(*window, drag_events(grab, to));
    const auto widened = std::get<deepcut::DrillOperation>(window->tool()->parameters());
    QVERIFY2(widened.cylinder.radius > placed.cylinder.radius * 1.2f,
             "dragging the radius handle out widens");
    QCOMPARE(widened.cylinder.a, placed.cylinder.a);
    QCOMPARE(widened.cylinder.b, placed.cylinder.b);
    QVERIFY(std::abs(window->findChild<QDoubleSpinBox*>("drill.radius")->value() - widened.cylinder.radius) <
            1e-4);
    const glm::vec3 moved_handle = to_vec(widget->GetDrillRepresentation()->GetRadiusHandle());
    QVERIFY(glm::length(display(*window, moved_handle) - glm::dvec2(to)) < 2.0);

    // End A (in front; B behind it on the same pixel): dragged up, B stays.
    const glm::ivec2 a = pixel(display(*window, widened.cylinder.a));
    play(*window, drag_events(a, a + glm::ivec2(0, 30)));
    const auto tilted = std::get<deepcut::DrillOperation>(window->tool()->parameters());
    QCOMPARE(tilted.cylinder.b, widened.cylinder.b);
    QVERIFY(tilted.cylinder.a.y > widened.cylinder.a.y);
    QVERIFY(glm::length(display(*window, tilted.cylinder.a) - glm::dvec2(a + glm::ivec2(0, 30))) < 2.0);
    QVERIFY(panel_shows(panel_vec(*window, "drill.a"), tilted.cylinder.a));

    // Typed numbers move the widget.
    auto* radius = window->findChild<QDoubleSpinBox*>("drill.radius");
    radius->setValue(0.02 * size);
    QVERIFY(std::abs(radius->value() - 0.02 * size) < 1e-4);
    QCOMPARE(static_cast<float>(widget->GetDrillRepresentation()->GetRadius()),
             static_cast<float>(radius->value()));
    QCOMPARE(std::get<deepcut::DrillOperation>(window->tool()->parameters()).cylinder.radius,
             static_cast<float>(radius->value()));
  }

  void dragged_cut_tear_drill_undo_redo_export_equal_the_cli() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    const float size = window->scene()->size;
    const std::string dir = deepcut::test::temp_dir("studio-widgets");
    std::vector<std::string> before;
    auto export_to = [&](const std::string& name) { return export_bytes(*window, dir, name); };
    auto shot = [&](const std::string& name) {
      window->view()->grab_view().save(QString::fromStdString(dir + "/" + name + ".png"));
    };

    // Plane: dragged, then applied with the panel's button.
    window->findChild<QAction*>("tool_cut")->trigger();
    drag_plane(*window);
    if (QTest::currentTestFailed()) return;
    shot("widget_plane");
    before.push_back(export_to("before0"));
    QTest::mouseClick(window->findChild<QPushButton*>("apply_button"), Qt::LeftButton);
    QVERIFY2(window->last_error().isEmpty(), qPrintable(window->last_error()));
    const auto cut = std::get<deepcut::CutOperation>(window->tool()->parameters());

    // Scalpel: placed at a click on the trunk, its end tip dragged down and sideways so the tear
    // runs diagonally; applied with the Apply action (Enter).
    window->set_tool("");  // the plane would take the click
    window->view()->reset_camera();
    const glm::vec3 p = front_surface_point(*window);
    click(*window, p);
    window->set_tool("tear");
    turn_camera(*window, 35.0);
    auto tear = std::get<deepcut::TearOperation>(window->tool()->parameters());
    const glm::ivec2 tip = pixel(display(*window, tear.end.tip));
    play(*window, drag_events(tip, tip + glm::ivec2(20, -20)));
    tear = std::get<deepcut::TearOperation>(window->tool()->parameters());
    QVERIFY(panel_shows(panel_vec(*window, "tear.end.tip"), tear.end.tip));
    window->findChild<QDoubleSpinBox*>("tear.width")->setValue(0.01 * size);
    tear = std::get<deepcut::TearOperation>(window->tool()->parameters());
    QVERIFY2(!window->tool()->preview(*window->scene()).lines.front().endpoints.empty(),
             "the tear path is drawn");
    window->view()->frame(p, 0.22f * size);
    shot("widget_scalpel");
    before.push_back(export_to("before1"));
    window->findChild<QAction*>("apply_tool")->trigger();
    QVERIFY2(window->last_error().isEmpty(), qPrintable(window->last_error()));

    // Drill: along the view through a click on the upper trunk, radius dragged wider.
    window->set_tool("");
    window->view()->reset_camera();
    const glm::vec3 upper = p + glm::vec3(0.0f, 0.12f * size, 0.0f);
    const auto hit = window->view()->surface_point_at(window->view()->project(upper));
    QVERIFY(hit);
    click(*window, *hit);
    window->set_tool("drill");
    auto* drill_widget = static_cast<deepcut::DrillWidget*>(window->tool()->widget());
    window->view()->render();
    const glm::ivec2 grab =
        pixel(display(*window, to_vec(drill_widget->GetDrillRepresentation()->GetRadiusHandle())));
    play(*window, drag_events(grab, grab + glm::ivec2(10, 0)));
    turn_camera(*window, 40.0);
    const auto drill = std::get<deepcut::DrillOperation>(window->tool()->parameters());
    QVERIFY(std::abs(window->findChild<QDoubleSpinBox*>("drill.radius")->value() - drill.cylinder.radius) <
            1e-4);
    QVERIFY2(window->tool()->preview(*window->scene()).lines.front().endpoints.size() > 16,
             "the rims are drawn");
    shot("widget_drill");
    before.push_back(export_to("before2"));
    window->findChild<QAction*>("apply_tool")->trigger();
    QVERIFY2(window->last_error().isEmpty(), qPrintable(window->last_error()));
    QCOMPARE(window->history()->count(), 3);
    const std::string final_bytes = export_to("final");

    // Undo all (each state exports as it did before its operation), redo all, validate.
    check_undo_all_redo_all(*window, dir, before, final_bytes);
    if (QTest::currentTestFailed()) return;

    // The whole session replayed by `deepcut apply` on the original model.
    const deepcut::History history = deepcut::model_history(deepcut::read_gltf(dir + "/redo.glb"));
    QCOMPARE(history.operations.size(), std::size_t(3));
    check_cli_apply_equals(history, dir, final_bytes);
    if (QTest::currentTestFailed()) return;
    using deepcut::test::quote;
    const std::string original = quote(kCactus.toStdString());

    // Each operation alone on the original model equals `deepcut cut`, `tear` or `drill` run with
    // the numbers the panel shows (read back from the history, at the pose they were applied).
    const auto& h_cut = std::get<deepcut::CutOperation>(history.operations[0].params);
    const auto& h_tear = std::get<deepcut::TearOperation>(history.operations[1].params);
    const auto& h_drill = std::get<deepcut::DrillOperation>(history.operations[2].params);
    QCOMPARE(h_cut.plane.point, cut.plane.point);
    QCOMPARE(h_tear.end.tip, tear.end.tip);
    QCOMPARE(h_drill.cylinder.radius, drill.cylinder.radius);
    auto pose = [&](const deepcut::Operation& op) {
      return " --time " + number(op.time) + " --animation " + std::to_string(op.animation);
    };
    const std::string cli_args[3] = {
        "cut " + original + " --plane " + numbers({h_cut.plane.point, h_cut.plane.normal}) +
            pose(history.operations[0]),
        "tear " + original + " --blade-start " + numbers({h_tear.start.handle, h_tear.start.tip}) +
            " --blade-end " + numbers({h_tear.end.handle, h_tear.end.tip}) + " --width " +
            number(h_tear.options.width) + pose(history.operations[1]),
        "drill " + original + " --axis " + numbers({h_drill.cylinder.a, h_drill.cylinder.b}) + " --radius " +
            number(h_drill.cylinder.radius) + " --min-rim-edges " +
            std::to_string(h_drill.options.min_rim_edges) + pose(history.operations[2])};
    const char* ids[3] = {"cut", "tear", "drill"};
    for (int i = 0; i < 3; ++i) {
      while (window->history()->index() > 0) window->undo_action()->trigger();
      window->set_tool(ids[i]);
      window->tool()->set_parameters(history.operations[static_cast<std::size_t>(i)].params);
      window->set_pose(history.operations[static_cast<std::size_t>(i)].animation,
                       history.operations[static_cast<std::size_t>(i)].time);
      QVERIFY(window->apply_tool());
      const std::string alone = dir + "/alone_" + ids[i] + ".glb", cli = dir + "/cli_" + ids[i] + ".glb";
      QVERIFY(window->export_file(QString::fromStdString(alone)));
      const auto run = deepcut::test::run_cli(cli_args[i] + " -o " + quote(cli));
      QVERIFY2(run.exit_code == 0, run.err.c_str());
      QVERIFY2(read_bytes(cli) == read_bytes(alone),
               (std::string("deepcut ") + ids[i] + " differs from the studio").c_str());
      const auto checked = deepcut::test::validate_gltf(alone);
      QVERIFY2(checked.exit_code == 0, (checked.out + checked.err).c_str());
    }
  }
};

int main(int argc, char** argv) {
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setOrganizationName("DeepCut");
  QApplication::setApplicationName("DeepCut Studio Widget Tests");
  StudioWidgetsTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "widgets_gui_test.moc"
