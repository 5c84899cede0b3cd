// SPDX-License-Identifier: MIT
// The scalpel, drill and plane widget/representation pairs on their own (VTK only, no Qt): an
// offscreen render window, a generic interactor and event logs played by
// vtkInteractorEventRecorder. Each drag must move exactly the grabbed part, in the view plane,
// to under the cursor, with one StartInteractionEvent and one EndInteractionEvent around it.
#include <gtest/gtest.h>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkCommand.h>
#include <vtkGenericRenderWindowInteractor.h>
#include <vtkInteractorEventRecorder.h>
#include <vtkNew.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <string>

#include "deepcut/widgets/drill_widget.h"
#include "deepcut/widgets/plane_widget.h"
#include "deepcut/widgets/scalpel_widget.h"

namespace deepcut {
namespace {

glm::dvec3 vec(const double* p) { return {p[0], p[1], p[2]}; }

/// A 400 x 400 offscreen view looking down -z at the origin from z = 10.
struct View {
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkRenderWindow> window;
  vtkNew<vtkGenericRenderWindowInteractor> interactor;
  vtkNew<vtkCallbackCommand> counter;
  int starts = 0, moves = 0, ends = 0;

  View() {
    window->SetOffScreenRendering(1);
    window->SetSize(400, 400);
    window->AddRenderer(renderer);
    interactor->SetRenderWindow(window);
    vtkCamera* camera = renderer->GetActiveCamera();
    camera->SetPosition(0.0, 0.0, 10.0);
    camera->SetFocalPoint(0.0, 0.0, 0.0);
    camera->SetViewUp(0.0, 1.0, 0.0);
    renderer->ResetCameraClippingRange(-5.0, 5.0, -5.0, 5.0, -5.0, 5.0);
    counter->SetClientData(this);
    counter->SetCallback([](vtkObject*, unsigned long event, void* client, void*) {
      auto* view = static_cast<View*>(client);
      if (event == vtkCommand::StartInteractionEvent) ++view->starts;
      if (event == vtkCommand::InteractionEvent) ++view->moves;
      if (event == vtkCommand::EndInteractionEvent) ++view->ends;
    });
  }

  void watch(vtkAbstractWidget* widget) {
    widget->SetInteractor(interactor);
    widget->SetCurrentRenderer(renderer);
    widget->AddObserver(vtkCommand::StartInteractionEvent, counter);
    widget->AddObserver(vtkCommand::InteractionEvent, counter);
    widget->AddObserver(vtkCommand::EndInteractionEvent, counter);
    widget->On();
    window->Render();
  }

  glm::ivec2 pixel(const glm::dvec3& p) {
    renderer->SetWorldPoint(p.x, p.y, p.z, 1.0);
    renderer->WorldToDisplay();
    double d[3];
    renderer->GetDisplayPoint(d);
    return {static_cast<int>(std::lround(d[0])), static_cast<int>(std::lround(d[1]))};
  }

  void play(const std::string& events) {
    vtkNew<vtkInteractorEventRecorder> recorder;
    recorder->SetInteractor(interactor);
    recorder->ReadFromInputStringOn();
    const std::string log = "# StreamVersion 1\n" + events;
    recorder->SetInputString(log.c_str());
    recorder->Play();
    recorder->Off();
  }
};

std::string line(const std::string& name, const glm::ivec2& p) {
  return name + " " + std::to_string(p.x) + " " + std::to_string(p.y) + " 0 0 0 0 0\n";
}

std::string drag(const glm::ivec2& from, const glm::ivec2& to, const std::string& button = "Left") {
  std::string log = line("MouseMoveEvent", from) + line(button + "ButtonPressEvent", from);
  for (int k = 1; k <= 4; ++k) log += line("MouseMoveEvent", from + (to - from) * k / 4);
  return log + line(button + "ButtonReleaseEvent", to);
}

/// A scalpel whose swept quad faces the camera: blades along x at y = 0.5 (start) and -0.5 (end).
vtkNew<ScalpelWidget> make_scalpel(View& view) {
  vtkNew<ScalpelWidget> widget;
  ScalpelRepresentation* rep = widget->GetScalpelRepresentation();
  const double sh[3] = {-1.0, 0.5, 0.0}, st[3] = {1.0, 0.5, 0.0}, eh[3] = {-1.0, -0.5, 0.0},
               et[3] = {1.0, -0.5, 0.0};
  rep->SetStartHandle(sh);
  rep->SetStartTip(st);
  rep->SetEndHandle(eh);
  rep->SetEndTip(et);
  view.watch(widget);
  return widget;
}

TEST(ScalpelWidgetTest, dragging_the_end_tip_moves_only_it_to_under_the_cursor) {
  View view;
  auto widget = make_scalpel(view);
  ScalpelRepresentation* rep = widget->GetScalpelRepresentation();
  const glm::ivec2 from = view.pixel({1.0, -0.5, 0.0}), to = from + glm::ivec2(30, -20);
  view.play(drag(from, to));
  EXPECT_EQ(view.starts, 1);
  EXPECT_EQ(view.ends, 1);
  EXPECT_EQ(view.moves, 4);
  EXPECT_EQ(vec(rep->GetStartHandle()), glm::dvec3(-1.0, 0.5, 0.0));
  EXPECT_EQ(vec(rep->GetStartTip()), glm::dvec3(1.0, 0.5, 0.0));
  EXPECT_EQ(vec(rep->GetEndHandle()), glm::dvec3(-1.0, -0.5, 0.0));
  const glm::dvec3 tip = vec(rep->GetEndTip());
  EXPECT_NEAR(tip.z, 0.0, 1e-9);  // the view plane through the tip
  EXPECT_GT(tip.x, 1.0);
  EXPECT_LT(tip.y, -0.5);
  EXPECT_LE(glm::length(glm::dvec2(view.pixel(tip) - to)), 1.0);
}

TEST(ScalpelWidgetTest, blades_move_their_pose_and_the_quad_moves_everything) {
  View view;
  auto widget = make_scalpel(view);
  ScalpelRepresentation* rep = widget->GetScalpelRepresentation();
  // The start blade's middle: both start points move by the same amount, the end pose stays.
  const glm::ivec2 blade = view.pixel({0.0, 0.5, 0.0});
  view.play(drag(blade, blade + glm::ivec2(0, 25)));
  const glm::dvec3 shift = vec(rep->GetStartHandle()) - glm::dvec3(-1.0, 0.5, 0.0);
  EXPECT_GT(shift.y, 0.0);
  EXPECT_NEAR(glm::length(vec(rep->GetStartTip()) - glm::dvec3(1.0, 0.5, 0.0) - shift), 0.0, 1e-9);
  EXPECT_EQ(vec(rep->GetEndTip()), glm::dvec3(1.0, -0.5, 0.0));
  // Inside the swept quad, away from the blades: the whole scalpel moves.
  const glm::dvec3 before[4] = {vec(rep->GetStartHandle()), vec(rep->GetStartTip()), vec(rep->GetEndHandle()),
                                vec(rep->GetEndTip())};
  const glm::ivec2 inside = view.pixel({0.3, 0.0, 0.0});
  view.play(drag(inside, inside + glm::ivec2(-20, 0)));
  const glm::dvec3 after[4] = {vec(rep->GetStartHandle()), vec(rep->GetStartTip()), vec(rep->GetEndHandle()),
                               vec(rep->GetEndTip())};
  const glm::dvec3 d = after[0] - before[0];
  EXPECT_LT(d.x, 0.0);
  for (int i = 1; i < 4; ++i) EXPECT_NEAR(glm::length(after[i] - before[i] - d), 0.0, 1e-9);
  // A middle drag over a part moves everything too.
  const glm::ivec2 tip = view.pixel(after[3]);
  view.play(drag(tip, tip + glm::ivec2(0, 15), "Middle"));
  const glm::dvec3 m = vec(rep->GetStartHandle()) - after[0];
  EXPECT_GT(m.y, 0.0);
  EXPECT_NEAR(glm::length(vec(rep->GetEndTip()) - after[3] - m), 0.0, 1e-9);
}

TEST(ScalpelWidgetTest, a_press_outside_leaves_the_scalpel_and_escape_restores_a_drag) {
  View view;
  auto widget = make_scalpel(view);
  ScalpelRepresentation* rep = widget->GetScalpelRepresentation();
  view.play(drag({20, 20}, {60, 40}));
  EXPECT_EQ(view.starts, 0);
  EXPECT_EQ(vec(rep->GetStartHandle()), glm::dvec3(-1.0, 0.5, 0.0));
  // Hovering a tip selects it as the part under the cursor.
  view.play(line("MouseMoveEvent", view.pixel({1.0, 0.5, 0.0})));
  EXPECT_EQ(rep->GetInteractionState(), ScalpelRepresentation::OnStartTip);
  // Escape in the middle of a drag.
  const glm::ivec2 handle = view.pixel({-1.0, 0.5, 0.0});
  view.play(line("MouseMoveEvent", handle) + line("LeftButtonPressEvent", handle) +
            line("MouseMoveEvent", handle + glm::ivec2(30, 30)));
  EXPECT_NE(vec(rep->GetStartHandle()), glm::dvec3(-1.0, 0.5, 0.0));
  view.interactor->SetKeyEventInformation(0, 0, 27, 1, "Escape");
  view.interactor->InvokeEvent(vtkCommand::KeyPressEvent, nullptr);
  EXPECT_EQ(vec(rep->GetStartHandle()), glm::dvec3(-1.0, 0.5, 0.0));
  EXPECT_EQ(view.ends, 1);
  EXPECT_FALSE(widget->IsDragging());
  // The release that follows does nothing more.
  view.play(line("LeftButtonReleaseEvent", handle + glm::ivec2(30, 30)));
  EXPECT_EQ(view.ends, 1);
}

/// A drill along the view: A = (0, 0, 1) in front, B = (0, 0, -1) behind, radius 0.5.
vtkNew<DrillWidget> make_drill(View& view) {
  vtkNew<DrillWidget> widget;
  DrillRepresentation* rep = widget->GetDrillRepresentation();
  const double a[3] = {0.0, 0.0, 1.0}, b[3] = {0.0, 0.0, -1.0};
  rep->SetEndA(a);
  rep->SetEndB(b);
  rep->SetRadius(0.5);
  view.watch(widget);
  return widget;
}

TEST(DrillWidgetTest, the_radius_handle_sets_the_distance_from_the_cursor_to_the_axis) {
  View view;
  auto widget = make_drill(view);
  DrillRepresentation* rep = widget->GetDrillRepresentation();
  // On A's ring, towards the camera's right (+x).
  EXPECT_NEAR(glm::length(vec(rep->GetRadiusHandle()) - glm::dvec3(0.5, 0.0, 1.0)), 0.0, 1e-9);
  const glm::ivec2 from = view.pixel(vec(rep->GetRadiusHandle())), to = from + glm::ivec2(30, 0);
  view.play(drag(from, to));
  EXPECT_EQ(view.starts, 1);
  EXPECT_GT(rep->GetRadius(), 0.5);
  EXPECT_EQ(vec(rep->GetEndA()), glm::dvec3(0.0, 0.0, 1.0));
  EXPECT_EQ(vec(rep->GetEndB()), glm::dvec3(0.0, 0.0, -1.0));
  view.window->Render();
  EXPECT_LE(glm::length(glm::dvec2(view.pixel(vec(rep->GetRadiusHandle())) - to)), 1.0);
}

TEST(DrillWidgetTest, the_nearer_end_is_dragged_alone_and_the_side_moves_both) {
  View view;
  auto widget = make_drill(view);
  DrillRepresentation* rep = widget->GetDrillRepresentation();
  // A and B project to the same pixel: A (nearer the camera) is picked.
  const glm::ivec2 centre = view.pixel({0.0, 0.0, 1.0});
  view.play(drag(centre, centre + glm::ivec2(0, 30)));
  EXPECT_GT(rep->GetEndA()[1], 0.0);
  EXPECT_NEAR(rep->GetEndA()[2], 1.0, 1e-9);
  EXPECT_EQ(vec(rep->GetEndB()), glm::dvec3(0.0, 0.0, -1.0));
  EXPECT_NEAR(rep->GetRadius(), 0.5, 1e-12);
  // The side (left of the axis, inside the ring): both ends move together.
  const glm::dvec3 a = vec(rep->GetEndA()), b = vec(rep->GetEndB());
  const glm::ivec2 side = view.pixel({-0.45, 0.0, 0.0});
  view.play(drag(side, side + glm::ivec2(-20, 0)));
  const glm::dvec3 da = vec(rep->GetEndA()) - a, db = vec(rep->GetEndB()) - b;
  EXPECT_LT(da.x, 0.0);
  EXPECT_NEAR(glm::length(da - db), 0.0, 1e-9);
}

TEST(PlaneWidgetTest, has_the_studio_look_and_leaves_right_drags_to_the_camera) {
  View view;
  vtkNew<PlaneWidget> widget;
  PlaneRepresentation* rep = widget->GetPlaneRepresentation();
  double bounds[6] = {-1.0, 1.0, -1.0, 1.0, -1.0, 1.0};
  rep->PlaceWidget(bounds);
  rep->SetOrigin(0.0, 0.0, 0.0);
  rep->SetNormal(0.0, 0.6, 0.8);  // facing the camera, its arrow pointing up the screen
  view.watch(widget);
  EXPECT_LT(rep->GetPlaneProperty()->GetOpacity(), 1.0);
  EXPECT_FALSE(rep->GetScaleEnabled());
  EXPECT_FALSE(rep->GetOutlineTranslation());
  const glm::ivec2 origin = view.pixel({0.0, 0.0, 0.0});
  view.play(drag(origin, origin + glm::ivec2(0, 40), "Right"));
  EXPECT_EQ(view.starts, 0);
  // A left drag on the origin moves it within the plane.
  view.play(drag(origin, origin + glm::ivec2(40, 0)));
  EXPECT_EQ(view.starts, 1);
  double moved[3];
  rep->GetOrigin(moved);
  EXPECT_GT(moved[0], 0.0);
  EXPECT_NEAR(0.6 * moved[1] + 0.8 * moved[2], 0.0, 1e-9);  // still in the plane
}

}  // namespace
}  // namespace deepcut
