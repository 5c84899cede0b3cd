// SPDX-License-Identifier: MIT
#include "scene_view.h"

#include <QVTKOpenGLNativeWidget.h>
#include <vtkAbstractWidget.h>
#include <vtkActor.h>
#include <vtkAxesActor.h>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkCaptionActor2D.h>
#include <vtkCellData.h>
#include <vtkCellPicker.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkIdTypeArray.h>
#include <vtkLightKit.h>
#include <vtkMath.h>
#include <vtkNew.h>
#include <vtkOrientationMarkerWidget.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkProperty.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>
#include <vtkTextProperty.h>
#include <vtkTexture.h>

#include <QCursor>
#include <QTimer>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>

#include "anti_aliasing.h"
#include "click_style.h"
#include "deepcut/core/errors.h"
#include "deepcut/widgets/material_look.h"
#include "deepcut/widgets/overlay_props.h"
#include "deepcut/widgets/poly_data_bridge.h"
#include "deepcut/widgets/texture.h"
#include "deepcut/widgets/view_poly_data.h"
#include "instance_data.h"
#include "scene_view_impl.h"
#include "surface_mapper.h"
#include "thread_cpu_time.h"

namespace deepcut::studio {
namespace {

double distance_to_segment(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b) {
  const glm::dvec2 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + t * ab));
}

}  // namespace

void SceneView::Impl::set_up(InstanceActor& instance) const {
  vtkProperty* property = instance.actor->GetProperty();
  property->SetInterpolationToPhong();
  property->SetAmbient(0.12);
  property->SetDiffuse(0.88);
  property->SetSpecularPower(24.0);
  property->BackfaceCullingOff();
  apply_look(instance);
  apply_display_mode(instance);
}

bool SceneView::Impl::warm_up_next() {
  if (warmed >= 2 || !window->GetReadyForRendering()) return false;
  const bool textured = warmed++ == 1;
  InstanceActor warm;
  warm.poly = stand_in_triangle(renderer->GetActiveCamera(), textured);
  if (textured) warm.texture = stand_in_texture();
  warm.mapper = vtkSmartPointer<SurfaceMapper>::New();
  warm.mapper->SetInputData(warm.poly);
  warm.mapper->SetColorModeToDirectScalars();
  warm.actor = vtkSmartPointer<vtkActor>::New();
  warm.actor->SetMapper(warm.mapper);
  warm.actor->UseBoundsOff();  // leaves the clipping range to the scene
  set_up(warm);
  // Alone in the frame (drawing the scene's actors is not the point), and the frame never
  // shown: without a buffer swap the widget keeps showing the last one.
  std::vector<vtkActor*> hidden;
  for (const InstanceActor& instance : instances)
    if (instance.actor->GetVisibility()) hidden.push_back(instance.actor);
  if (normals && normals->GetVisibility()) hidden.push_back(normals);
  for (vtkActor* actor : hidden) actor->VisibilityOff();
  renderer->AddActor(warm.actor);
  // With the untextured surface, a skinned model's skeleton overlay (its own shaders).
  const OverlayProps skeleton =
      textured ? OverlayProps{} : make_overlay_props(stand_in_skeleton(renderer->GetActiveCamera()));
  for (const auto& prop : skeleton.on_top) top->AddViewProp(prop);
  window->SwapBuffersOff();
  window->Render();
  window->SwapBuffersOn();
  for (const auto& prop : skeleton.on_top) top->RemoveViewProp(prop);
  renderer->RemoveActor(warm.actor);
  for (vtkActor* actor : hidden) actor->VisibilityOn();
  return warmed < 2;
}

void SceneView::Impl::apply_look(InstanceActor& instance) const {
  vtkProperty* property = instance.actor->GetProperty();
  const glm::vec4 c = instance.look.base_color;
  property->SetColor(c.r, c.g, c.b);
  property->SetOpacity(instance.look.blend ? c.a : 1.0);
  instance.mapper->ScalarVisibilityOff();
  instance.actor->SetTexture(instance.texture);
  // Rough, non-metallic materials get a dull highlight; shiny ones a sharper one.
  property->SetSpecular(0.05 + 0.3 * (1.0 - instance.look.roughness));
}

void SceneView::Impl::apply_display_mode(InstanceActor& instance) const {
  vtkProperty* property = instance.actor->GetProperty();
  property->SetRepresentation(mode == DisplayMode::Wireframe ? VTK_WIREFRAME : VTK_SURFACE);
  property->SetEdgeVisibility(mode == DisplayMode::ShadedEdges);
  property->SetEdgeColor(0.08, 0.09, 0.1);
  property->SetLineWidth(1.0f);
}

void SceneView::Impl::rebuild_normals() {
  if (normals) renderer->RemoveActor(normals);
  normals = nullptr;
  if (!show_normals || !scene) return;
  std::vector<vtkPolyData*> polys;
  for (const InstanceActor& instance : instances) polys.push_back(instance.poly);
  const vtkSmartPointer<vtkPolyData> poly = normal_lines(polys, 0.015f * scene->size);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(poly);
  normals = vtkSmartPointer<vtkActor>::New();
  normals->SetMapper(mapper);
  normals->GetProperty()->SetColor(0.35, 0.85, 1.0);
  normals->GetProperty()->LightingOff();
  normals->PickableOff();
  renderer->AddActor(normals);
}

glm::dvec2 SceneView::Impl::to_display(const glm::vec3& p) const {
  renderer->SetWorldPoint(p.x, p.y, p.z, 1.0);
  renderer->WorldToDisplay();
  double d[3];
  renderer->GetDisplayPoint(d);
  return {d[0], d[1]};
}

bool SceneView::Impl::pick_display(int x, int y) {
  if (!scene || !pick_handler) return false;
  plugins::Pick pick;
  // Bones first: they are drawn over the model.
  const double ratio = widget->devicePixelRatioF();
  double best = 8.0 * ratio;
  for (const BoneHandle& bone : bones) {
    const glm::dvec2 click(x, y);
    const bool marker = bone.head == bone.tail;
    const double d = distance_to_segment(click, to_display(bone.head), to_display(bone.tail)) -
                     (marker ? 2.0 * ratio : 0.0);
    if (d < best) {
      best = d;
      pick.joint_node = bone.joint;
    }
  }
  if (pick.joint_node >= 0) {
    pick_handler(pick);
    return true;
  }
  if (!pick_model(x, y, pick)) return false;
  pick_handler(pick);
  return true;
}

bool SceneView::Impl::pick_model(int x, int y, plugins::Pick& pick) {
  if (!picker->Pick(x, y, 0.0, renderer) || picker->GetCellId() < 0) return false;
  vtkActor* actor = picker->GetActor();
  const auto it = std::find_if(instances.begin(), instances.end(),
                               [&](const InstanceActor& p) { return p.actor.Get() == actor; });
  if (it == instances.end()) return false;
  pick.instance = static_cast<std::size_t>(it - instances.begin());
  vtkPolyData* poly = it->poly;
  auto* face_ids = vtkIdTypeArray::SafeDownCast(poly->GetCellData()->GetArray("face_id"));
  auto* vertex_ids = vtkIdTypeArray::SafeDownCast(poly->GetPointData()->GetArray("vertex_id"));
  if (!face_ids || !vertex_ids) return false;
  const vtkIdType cell = picker->GetCellId();
  pick.face = FaceId(static_cast<std::uint32_t>(face_ids->GetValue(cell)));
  double world[3];
  picker->GetPickPosition(world);
  pick.position = glm::vec3(world[0], world[1], world[2]);
  vtkIdType npts = 0;
  const vtkIdType* pts = nullptr;
  poly->GetCellPoints(cell, npts, pts);
  double nearest = std::numeric_limits<double>::max();
  for (vtkIdType k = 0; k < npts; ++k) {
    double p[3];
    poly->GetPoint(pts[k], p);
    const double d = std::hypot(p[0] - world[0], p[1] - world[1], p[2] - world[2]);
    if (d < nearest) {
      nearest = d;
      pick.vertex = VertexId(static_cast<std::uint32_t>(vertex_ids->GetValue(pts[k])));
    }
  }
  return true;
}

void SceneView::Impl::display_ray(int x, int y, PointerEvent& event) const {
  double near_point[4], far_point[4];
  renderer->SetDisplayPoint(x, y, 0.0);
  renderer->DisplayToWorld();
  renderer->GetWorldPoint(near_point);
  renderer->SetDisplayPoint(x, y, 1.0);
  renderer->DisplayToWorld();
  renderer->GetWorldPoint(far_point);
  for (double* p : {near_point, far_point})
    if (p[3] != 0.0)
      for (int k = 0; k < 3; ++k) p[k] /= p[3];
  const glm::vec3 a(near_point[0], near_point[1], near_point[2]), b(far_point[0], far_point[1], far_point[2]);
  event.ray_origin = a;
  event.ray_direction = glm::length(b - a) > 0.0f ? glm::normalize(b - a) : glm::vec3(0.0f, 0.0f, -1.0f);
}

SceneView::SceneView(QWidget* parent) : QWidget(parent), impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  d.widget = new QVTKOpenGLNativeWidget(this);
  d.widget->setObjectName("vtk_view");
  // Drops go to the main window, which opens the file.
  d.widget->setAcceptDrops(false);
  layout->addWidget(d.widget);
  d.widget->setRenderWindow(d.window);

  d.window->SetNumberOfLayers(3);
  d.window->AddRenderer(d.renderer);
  d.window->AddRenderer(d.tools);
  d.window->AddRenderer(d.top);
  // The tool widget between the model and the overlays: drawn over the model, while the
  // contour, path and rim lines stay crisp over the widget's translucent plane, quad or cylinder.
  d.tools->SetLayer(1);
  d.tools->InteractiveOff();
  d.tools->SetActiveCamera(d.renderer->GetActiveCamera());
  d.top->SetLayer(2);
  d.top->InteractiveOff();
  d.top->SetActiveCamera(d.renderer->GetActiveCamera());

  // A studio backdrop: dark, slightly blue gradient (Blender / ParaView users know it).
  d.renderer->GradientBackgroundOn();
  d.renderer->SetBackground(0.13, 0.14, 0.16);
  d.renderer->SetBackground2(0.34, 0.37, 0.42);
  // Smooth edges by multisampling (FXAA does not combine with the overlay layer), where a
  // graphics card draws (anti_aliasing.h); the main window applies the user's choice.
  d.window->SetMultiSamples(multisamples_for(AntiAliasing::Automatic, is_software_renderer(gl_renderer_name())));
  vtkNew<vtkLightKit> lights;
  lights->SetKeyLightIntensity(0.9);
  lights->AddLightsToRenderer(d.renderer);

  // The caption: upper left, its size fitted to the view (scene_view_caption.h).
  d.caption->GetTextProperty()->SetColor(0.93, 0.93, 0.93);
  d.caption->GetTextProperty()->SetFontFamilyToArial();
  d.caption->GetTextProperty()->ShadowOn();
  d.top->AddViewProp(d.caption);

  // Every frame (also those a widget's drag renders) keeps the tool widget and the overlays
  // inside the clipping range: they may reach beyond the model.
  d.clipping->SetClientData(&d);
  d.clipping->SetCallback([](vtkObject*, unsigned long, void* client, void*) {
    auto* impl = static_cast<Impl*>(client);
    double bounds[6], layer[6];
    impl->renderer->ComputeVisiblePropBounds(bounds);
    for (vtkRenderer* over : {impl->tools.Get(), impl->top.Get()}) {
      over->ComputeVisiblePropBounds(layer);
      if (!vtkMath::AreBoundsInitialized(layer)) continue;
      if (!vtkMath::AreBoundsInitialized(bounds)) {
        std::copy(layer, layer + 6, bounds);
        continue;
      }
      for (int k = 0; k < 3; ++k) {
        bounds[2 * k] = std::min(bounds[2 * k], layer[2 * k]);
        bounds[2 * k + 1] = std::max(bounds[2 * k + 1], layer[2 * k + 1]);
      }
    }
    if (vtkMath::AreBoundsInitialized(bounds)) impl->renderer->ResetCameraClippingRange(bounds);
  });
  d.renderer->AddObserver(vtkCommand::StartEvent, d.clipping);

  d.picker->SetTolerance(0.0005);
  d.picker->PickFromListOn();

  vtkRenderWindowInteractor* interactor = d.window->GetInteractor();
  d.style->SetDefaultRenderer(d.renderer);
  d.style->on_click = [this](int x, int y) { impl_->pick_display(x, y); };
  d.style->on_press = [this](int x, int y) {
    Impl& i = *impl_;
    if (!i.pointer_handler || !i.scene) return false;
    PointerEvent event;
    event.phase = PointerEvent::Phase::Press;
    plugins::Pick pick;
    if (i.pick_model(x, y, pick)) event.pick = pick;
    i.display_ray(x, y, event);
    return i.pointer_handler(event);
  };
  d.style->on_drag = [this](int x, int y, bool released) {
    Impl& i = *impl_;
    if (!i.pointer_handler) return;
    PointerEvent event;
    event.phase = released ? PointerEvent::Phase::Release : PointerEvent::Phase::Move;
    i.display_ray(x, y, event);
    i.pointer_handler(event);
  };
  interactor->SetInteractorStyle(d.style);

  vtkNew<vtkAxesActor> axes_actor;
  axes_actor->SetShaftTypeToCylinder();
  axes_actor->SetTotalLength(1.0, 1.0, 1.0);
  for (vtkCaptionActor2D* label : {axes_actor->GetXAxisCaptionActor2D(), axes_actor->GetYAxisCaptionActor2D(),
                                   axes_actor->GetZAxisCaptionActor2D()}) {
    label->GetCaptionTextProperty()->SetColor(0.95, 0.95, 0.95);
    label->GetCaptionTextProperty()->ShadowOff();
    label->GetCaptionTextProperty()->ItalicOff();
  }
  d.axes->SetOrientationMarker(axes_actor);
  d.axes->SetInteractor(interactor);
  d.axes->SetViewport(0.0, 0.0, 0.11, 0.17);
  d.axes->SetEnabled(1);
  d.axes->InteractiveOff();
}

SceneView::~SceneView() {
  if (impl_->tool_widget) impl_->tool_widget->Off();
}

void SceneView::Impl::add_actor(const plugins::SceneInstance& sp, std::shared_ptr<ViewPolyData> data,
                               std::vector<std::string>& notes) {
  const Model& model = *scene->model;
  InstanceActor instance;
  instance.data = std::move(data);
  instance.node = sp.node, instance.mesh = sp.mesh, instance.primitive = sp.primitive;
  instance.poly = instance.data->poly();
  instance.mapper = vtkSmartPointer<SurfaceMapper>::New();
  instance.mapper->SetInputData(instance.poly);
  instance.mapper->SetColorModeToDirectScalars();
  instance.actor = vtkSmartPointer<vtkActor>::New();
  instance.actor->SetMapper(instance.mapper);
  instance.look = instance_look(*scene, sp);
  if (instance.look.base_color_image >= 0) {
    if (instance.look.texcoord != 0) {
      notes.push_back("material '" + instance.look.name + "': base colour texture uses TEXCOORD_" +
                      std::to_string(instance.look.texcoord) + "; shown without it");
    } else if (!instance.poly->GetPointData()->GetArray("uv0")) {
      notes.push_back("material '" + instance.look.name +
                      "' has a texture but the mesh has no UVs; shown without it");
    } else {
      auto cached = textures.find(instance.look.base_color_image);
      if (cached == textures.end()) {
        vtkSmartPointer<vtkTexture> texture;
        try {
          texture = make_texture(model.images[static_cast<std::size_t>(instance.look.base_color_image)]);
        } catch (const Error& e) {
          notes.push_back(e.what());
        }
        cached = textures.emplace(instance.look.base_color_image, texture).first;
      }
      instance.texture = cached->second;
    }
  }
  use_texture_coords(instance.poly, instance.texture != nullptr);
  set_up(instance);
  renderer->AddActor(instance.actor);
  picker->AddPickList(instance.actor);
  instances.push_back(std::move(instance));
}

std::shared_ptr<const SceneView::Prepared> SceneView::prepare(const plugins::Scene& scene) {
  auto prepared = std::make_shared<Prepared>();
  for (const plugins::SceneInstance& sp : scene.instances) {
    prepared->data.push_back(instance_view_data(scene, sp));
    compute_draw_caches(*prepared->data.back());  // off the UI thread
  }
  return prepared;
}

std::vector<std::string> SceneView::set_scene(const plugins::Scene& scene, std::shared_ptr<const Prepared> prepared) {
  Impl& d = *impl_;
  if (prepared && prepared->data.size() != scene.instances.size()) prepared = nullptr;
  std::vector<std::string> notes;
  for (InstanceActor& instance : d.instances) d.renderer->RemoveActor(instance.actor);
  d.instances.clear();
  d.textures.clear();
  d.stash.clear();
  d.picker->InitializePickList();
  d.scene = &scene;
  for (const plugins::SceneInstance& sp : scene.instances)
    d.add_actor(sp, prepared ? prepared->data[d.instances.size()] : instance_view_data(scene, sp), notes);
  d.rebuild_normals();
  d.updates_due = true;
  return notes;
}

void SceneView::update_pose() {
  Impl& d = *impl_;
  if (!d.scene) return;
  for (std::size_t i = 0; i < d.instances.size() && i < d.scene->instances.size(); ++i) {
    const plugins::SceneInstance& sp = d.scene->instances[i];
    d.instances[i].data->set_positions(sp.posed(), &sp.posed_normals);
    d.instances[i].displaced = false;
  }
  d.stash.clear();  // drawn at the pose before
  d.rebuild_normals();
}

vtkPolyData* SceneView::instance_poly_data(std::size_t instance) const {
  return instance < impl_->instances.size() ? impl_->instances[instance].poly.Get() : nullptr;
}

SceneView::DataBytes SceneView::data_bytes() const {
  DataBytes all;
  auto add = [&](const std::shared_ptr<ViewPolyData>& drawn) {
    if (!drawn) return;
    const ViewPolyData::Bytes b = drawn->bytes();
    all.used += b.used, all.held += b.held, ++all.count;
  };
  for (const InstanceActor& instance : impl_->instances) add(instance.data);
  for (const auto& entry : impl_->stash) add(entry.second);
  return all;
}

void SceneView::set_instance_positions(std::size_t instance, const std::vector<glm::vec3>& positions) {
  Impl& d = *impl_;
  if (instance >= d.instances.size()) return;
  d.instances[instance].data->set_positions(positions, nullptr);
  d.instances[instance].displaced = true;
}

std::vector<glm::vec3> SceneView::instance_positions(std::size_t instance) const {
  const Impl& d = *impl_;
  if (instance >= d.instances.size() || !d.scene || instance >= d.scene->instances.size()) return {};
  std::vector<glm::vec3> out = d.scene->instances[instance].posed();
  vtkPolyData* poly = d.instances[instance].poly;
  auto* vertex_ids = vtkIdTypeArray::SafeDownCast(poly->GetPointData()->GetArray("vertex_id"));
  if (!vertex_ids) return out;
  for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i) {
    const auto v = static_cast<std::size_t>(vertex_ids->GetValue(i));
    double p[3];
    poly->GetPoint(i, p);
    if (v < out.size()) out[v] = glm::vec3(p[0], p[1], p[2]);
  }
  return out;
}

void SceneView::set_instance_colors(std::size_t instance, const plugins::InstanceColors& colors) {
  Impl& d = *impl_;
  if (instance >= d.instances.size()) return;
  InstanceActor& p = d.instances[instance];
  using Kind = plugins::InstanceColors::Kind;
  if (colors.kind == Kind::None) {
    clear_colors(p.poly);
    d.apply_look(p);
    return;
  }
  if (colors.kind == Kind::PerVertex) {
    set_vertex_colors(p.poly, colors.colors);
    p.mapper->SetScalarModeToUsePointData();
  } else {
    set_face_colors(p.poly, colors.colors);
    p.mapper->SetScalarModeToUseCellData();
  }
  p.mapper->ScalarVisibilityOn();
  p.mapper->SetColorModeToDirectScalars();
  p.actor->SetTexture(nullptr);
  p.actor->GetProperty()->SetColor(1.0, 1.0, 1.0);
  p.actor->GetProperty()->SetOpacity(1.0);
  p.actor->GetProperty()->SetSpecular(0.08);
}

void SceneView::set_overlay(Layer layer, const Overlay& overlay) {
  Impl& d = *impl_;
  OverlayProps& old = d.overlays[layer];
  for (auto& prop : old.depth_tested) d.renderer->RemoveViewProp(prop);
  for (auto& prop : old.on_top) d.top->RemoveViewProp(prop);
  old = make_overlay_props(overlay);
  for (auto& prop : old.depth_tested) d.renderer->AddViewProp(prop);
  for (auto& prop : old.on_top) d.top->AddViewProp(prop);
}

void SceneView::set_color_bar(const std::optional<ColorBar>& bar) {
  Impl& d = *impl_;
  if (d.color_bar) d.top->RemoveViewProp(d.color_bar);
  d.color_bar = bar ? make_color_bar(*bar) : nullptr;
  if (d.color_bar) d.top->AddViewProp(d.color_bar);
}

void SceneView::set_caption(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += (text.empty() ? "" : "\n") + line;
  impl_->caption->SetText(text);
}

void SceneView::set_bone_handles(std::vector<BoneHandle> handles) { impl_->bones = std::move(handles); }

void SceneView::set_display_mode(DisplayMode mode) {
  impl_->mode = mode;
  for (InstanceActor& instance : impl_->instances) impl_->apply_display_mode(instance);
}

DisplayMode SceneView::display_mode() const { return impl_->mode; }

void SceneView::set_normals_visible(bool visible) {
  impl_->show_normals = visible;
  impl_->rebuild_normals();
}

bool SceneView::normals_visible() const { return impl_->show_normals; }

void SceneView::reset_camera() {
  Impl& d = *impl_;
  vtkCamera* camera = d.renderer->GetActiveCamera();
  BoundingBox box;
  if (d.scene)
    for (const plugins::SceneInstance& instance : d.scene->instances)
      for (const glm::vec3& p : instance.posed()) box.add(p);
  if (box.empty()) {
    d.renderer->ResetCamera();
    return;
  }
  const glm::vec3 center = 0.5f * (box.min + box.max);
  // glTF is +Y up with the model facing +Z: look from the front, a little from the right and above.
  const glm::vec3 direction = glm::normalize(glm::vec3(0.45f, 0.3f, 1.0f));
  camera->SetFocalPoint(center.x, center.y, center.z);
  camera->SetPosition(center.x + direction.x, center.y + direction.y, center.z + direction.z);
  camera->SetViewUp(0.0, 1.0, 0.0);
  const double bounds[6] = {box.min.x, box.max.x, box.min.y, box.max.y, box.min.z, box.max.z};
  d.renderer->ResetCamera(bounds);
  // The bounding sphere leaves a wide margin in a wide view; use a little of it.
  const QSize size = impl_->widget->size();
  if (size.width() >= size.height()) camera->Dolly(1.08);
  d.renderer->ResetCameraClippingRange(bounds);
}

glm::vec3 SceneView::view_direction() const {
  double d[3];
  impl_->renderer->GetActiveCamera()->GetDirectionOfProjection(d);
  const glm::vec3 v(static_cast<float>(d[0]), static_cast<float>(d[1]), static_cast<float>(d[2]));
  return glm::length(v) > 0.0f ? glm::normalize(v) : glm::vec3(0.0f, 0.0f, -1.0f);
}

glm::vec3 SceneView::view_up() const {
  vtkCamera* camera = impl_->renderer->GetActiveCamera();
  double up[3], d[3];
  camera->GetViewUp(up);
  camera->GetDirectionOfProjection(d);
  glm::vec3 u(static_cast<float>(up[0]), static_cast<float>(up[1]), static_cast<float>(up[2]));
  const glm::vec3 dir = view_direction();
  u -= glm::dot(u, dir) * dir;
  return glm::length(u) > 1e-6f ? glm::normalize(u) : glm::vec3(0.0f, 1.0f, 0.0f);
}

void SceneView::set_tool_widget(vtkAbstractWidget* widget) {
  Impl& d = *impl_;
  if (d.tool_widget == widget) return;
  if (d.tool_widget) d.tool_widget->Off();
  d.tool_widget = widget;
  if (!widget) return;
  widget->SetInteractor(d.window->GetInteractor());
  // Drawn over the model, so a handle inside the model stays reachable.
  widget->SetDefaultRenderer(d.tools);
  widget->SetCurrentRenderer(d.tools);
  widget->On();
}

std::optional<glm::vec3> SceneView::surface_point_at(const QPoint& position) {
  Impl& d = *impl_;
  if (!d.scene) return std::nullopt;
  const double ratio = d.widget->devicePixelRatioF();
  const int x = static_cast<int>(std::lround(position.x() * ratio));
  const int y = static_cast<int>(std::lround((d.widget->height() - position.y() - 1) * ratio));
  if (!d.picker->Pick(x, y, 0.0, d.renderer) || d.picker->GetCellId() < 0) return std::nullopt;
  double world[3];
  d.picker->GetPickPosition(world);
  return glm::vec3(world[0], world[1], world[2]);
}

std::optional<QPoint> SceneView::cursor_position() const {
  const QPoint p = impl_->widget->mapFromGlobal(QCursor::pos());
  if (!impl_->widget->rect().contains(p)) return std::nullopt;
  return p;
}

void SceneView::frame(const glm::vec3& center, float radius) {
  vtkCamera* camera = impl_->renderer->GetActiveCamera();
  double position[3], focal[3];
  camera->GetPosition(position);
  camera->GetFocalPoint(focal);
  glm::dvec3 direction(position[0] - focal[0], position[1] - focal[1], position[2] - focal[2]);
  if (glm::length(direction) <= 0.0) direction = glm::dvec3(0.0, 0.0, 1.0);
  direction = glm::normalize(direction);
  const double half_angle = glm::radians(camera->GetViewAngle() / 2.0);
  const double distance = std::max(1e-6, static_cast<double>(radius)) / std::sin(half_angle);
  camera->SetFocalPoint(center.x, center.y, center.z);
  camera->SetPosition(center.x + distance * direction.x, center.y + distance * direction.y,
                      center.z + distance * direction.z);
  impl_->renderer->ResetCameraClippingRange();
}

void SceneView::set_render_listener(std::function<void()> listener) { impl_->render_listener = std::move(listener); }

void SceneView::set_multisamples(int samples) { impl_->window->SetMultiSamples(samples); }

int SceneView::multisamples() const { return impl_->window->GetMultiSamples(); }

void SceneView::render() {
  if (impl_->hold_renders) {  // the listener hears the render call that draws
    impl_->render_due = true;
    return;
  }
  if (impl_->render_listener) impl_->render_listener();
  const double cpu = thread_cpu_ms();
  impl_->window->Render();
  impl_->last_render_cpu_ms = thread_cpu_ms() - cpu;
  ++impl_->frames_drawn;
  impl_->widget->update();
  if (impl_->updates_due) {  // what the first build left for the first step, when idle
    impl_->updates_due = false;
    QTimer::singleShot(0, this, [this] { prepare_updates(); });
  }
}

void SceneView::warm_up() {
  QTimer::singleShot(0, this, [this] {
    if (impl_->warm_up_next()) warm_up();
  });
}

double SceneView::last_render_cpu_ms() const { return impl_->last_render_cpu_ms; }
int SceneView::frames_drawn() const { return impl_->frames_drawn; }

void SceneView::hold_renders(bool hold) {
  impl_->hold_renders = hold;
  if (hold || !impl_->render_due) return;
  impl_->render_due = false;
  render();
}

QImage SceneView::grab_view() {
  render();
  return impl_->widget->grabFramebuffer();
}

void SceneView::set_pick_handler(std::function<void(const plugins::Pick&)> handler) {
  impl_->pick_handler = std::move(handler);
}

void SceneView::set_pointer_handler(std::function<bool(const PointerEvent&)> handler) {
  impl_->pointer_handler = std::move(handler);
}

bool SceneView::pick_at(const QPoint& position) {
  const double ratio = impl_->widget->devicePixelRatioF();
  const int x = static_cast<int>(std::lround(position.x() * ratio));
  const int y = static_cast<int>(std::lround((impl_->widget->height() - position.y() - 1) * ratio));
  return impl_->pick_display(x, y);
}

QPoint SceneView::project(const glm::vec3& p) const {
  const glm::dvec2 d = impl_->to_display(p);
  const double ratio = impl_->widget->devicePixelRatioF();
  return QPoint(static_cast<int>(std::lround(d.x / ratio)),
                static_cast<int>(std::lround(impl_->widget->height() - 1 - d.y / ratio)));
}

}  // namespace deepcut::studio
