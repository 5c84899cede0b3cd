// SPDX-License-Identifier: MIT
#pragma once
// SceneView's state (its Impl and what it draws each instance with), shared by the files that
// implement the view: scene_view.cpp (the widget, drawing, picking) and scene_view_follow.cpp
// (following the scene's steps). Private to them: VTK in full.

#include <vtkActor.h>
#include <vtkCallbackCommand.h>
#include <vtkCellPicker.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkNew.h>
#include <vtkOrientationMarkerWidget.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProp.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTexture.h>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "click_style.h"
#include "deepcut/widgets/material_look.h"
#include "deepcut/widgets/overlay_props.h"
#include "deepcut/widgets/view_poly_data.h"
#include "scene_view.h"
#include "scene_view_caption.h"

class QVTKOpenGLNativeWidget;

namespace deepcut::studio {

struct InstanceActor {
  std::shared_ptr<ViewPolyData> data;  // follows the instance's mesh step by step
  vtkSmartPointer<vtkPolyData> poly;   // data's
  vtkSmartPointer<vtkPolyDataMapper> mapper;
  vtkSmartPointer<vtkActor> actor;
  vtkSmartPointer<vtkTexture> texture;  // the material's base colour texture, or null
  MaterialLook look;
  bool displaced = false;                    // drawn at positions set by hand (set_instance_positions)
  int node = -1, mesh = -1, primitive = -1;  // the scene instance it draws
};

struct SceneView::Prepared {
  // One per scene instance: the view's own data (set_scene takes it, then it follows the steps).
  std::vector<std::shared_ptr<ViewPolyData>> data;
};

struct SceneView::Impl {
  QVTKOpenGLNativeWidget* widget = nullptr;
  vtkNew<vtkGenericOpenGLRenderWindow> window;
  vtkNew<vtkRenderer> renderer;  // the model and depth-tested overlays
  vtkNew<vtkRenderer> tools;     // the tool widget, over the model
  vtkNew<vtkRenderer> top;       // overlays drawn over the model and the widget
  vtkNew<vtkCellPicker> picker;
  vtkNew<CaptionActor> caption;
  vtkNew<vtkOrientationMarkerWidget> axes;
  vtkNew<ClickStyle> style;
  vtkSmartPointer<vtkProp> color_bar;
  vtkSmartPointer<vtkActor> normals;
  std::map<Layer, OverlayProps> overlays;
  std::vector<InstanceActor> instances;
  // The drawn data of the instances the last structural step removed, by the scene's stash keys.
  std::map<std::pair<std::uint64_t, int>, std::shared_ptr<ViewPolyData>> stash;
  // The working memory of the copies a structural step makes (a cut's pieces), kept for the next.
  ViewPolyData::CopyScratch copy_scratch;
  std::map<int, vtkSmartPointer<vtkTexture>> textures;  // by image index
  const plugins::Scene* scene = nullptr;
  DisplayMode mode = DisplayMode::Shaded;
  bool show_normals = false;
  std::vector<BoneHandle> bones;
  std::function<void(const plugins::Pick&)> pick_handler;
  vtkSmartPointer<vtkAbstractWidget> tool_widget;
  vtkNew<vtkCallbackCommand> clipping;
  std::function<bool(const PointerEvent&)> pointer_handler;
  std::function<void()> render_listener;
  bool hold_renders = false, render_due = false;
  bool updates_due = false;  // a new scene's data waits for prepare_updates after its first frame
  double last_render_cpu_ms = 0.0;
  int frames_drawn = 0;

  int warmed = 0;  // how many of warm_up_next's variants were drawn

  /// Adds the actor of scene instance `sp` drawing `data`.
  void add_actor(const plugins::SceneInstance& sp, std::shared_ptr<ViewPolyData> data,
                 std::vector<std::string>& notes);
  /// update_scene of a structural step (the scene followed it: Scene::origins, Scene::departed).
  void follow_structure(const ModelChange& change);
  /// The data of `sp`, new in a structural step: copied through the step's origins from the data
  /// drawn for the instance it was made out of (among `old`), else built afresh.
  /// `spare`: data no longer drawn, held nowhere else, whose arrays a copy may take.
  std::shared_ptr<ViewPolyData> built_data(const plugins::SceneInstance& sp, const ModelChange& change,
                                           const std::vector<InstanceActor>& old,
                                           std::vector<std::shared_ptr<ViewPolyData>>& spare);
  /// The look and display mode every instance's actor gets.
  void set_up(InstanceActor& instance) const;
  /// Draws the next shader variant of SceneView::warm_up. @returns whether one remains.
  bool warm_up_next();
  void apply_look(InstanceActor& instance) const;
  void apply_display_mode(InstanceActor& instance) const;
  void rebuild_normals();
  glm::dvec2 to_display(const glm::vec3& p) const;
  bool pick_display(int x, int y);
  /// The model (not the bones) under display (x, y).
  bool pick_model(int x, int y, plugins::Pick& pick);
  /// The ray through display (x, y), world space.
  void display_ray(int x, int y, PointerEvent& event) const;
};

}  // namespace deepcut::studio
