// SPDX-License-Identifier: MIT
#pragma once
// The 3D view of the studio: a QVTKOpenGLNativeWidget showing every instance of the scene posed,
// with its material (base colour and texture) or an inspector's colours, overlays (skeleton,
// normals, the inspector's markers and edges), a colour bar and a caption. VTK stays inside
// scene_view*.cpp and scene_view_impl.h; this header is cheap to include.

#include <QImage>
#include <QWidget>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deepcut/plugins/inspector.h"
#include "deepcut/plugins/scene.h"
#include "deepcut/widgets/overlay.h"

class vtkAbstractWidget;
class vtkPolyData;

namespace deepcut::studio {

enum class DisplayMode { Shaded, Wireframe, ShadedEdges };

/// A clickable part of the skeleton in world space: the bone of `joint` from `head` to `tail`
/// (head == tail for a joint marker alone).
struct BoneHandle {
  int joint = -1;
  glm::vec3 head{0.0f}, tail{0.0f};
};

/// A left-button drag the view offers to the active tool before the camera gets it.
struct PointerEvent {
  enum class Phase { Press, Move, Release };
  Phase phase = Phase::Press;
  std::optional<plugins::Pick> pick;  ///< Press: the model under the cursor (none: missed it)
  glm::vec3 ray_origin{0.0f};         ///< the cursor's ray, world space
  glm::vec3 ray_direction{0.0f, 0.0f, -1.0f};
};

class SceneView : public QWidget {
 public:
  explicit SceneView(QWidget* parent = nullptr);
  ~SceneView() override;

  /// The VTK data of a scene's instances (ViewPolyData, laid out by slot: the full build
  /// `set_scene` makes without it, which then follows each step): what drawing a new scene
  /// costs besides the frame. Made by `prepare` on any thread (a worker
  /// opening a model), taken by `set_scene`.
  struct Prepared;
  /// Builds the VTK data of every instance of `scene` at its pose. Touches no view: safe off
  /// the UI thread while `scene` does not change.
  static std::shared_ptr<const Prepared> prepare(const plugins::Scene& scene);

  /// Builds the actors of a new scene (decodes textures), from `prepared` (made by `prepare`
  /// of this scene) when given. The scene must outlive the next call.
  /// @returns notes about what could not be shown as the file asks (e.g. an image that does not
  ///          decode), one line each.
  std::vector<std::string> set_scene(const plugins::Scene& scene, std::shared_ptr<const Prepared> prepared = nullptr);
  /// While held, `render` only notes that a frame is due; releasing the hold draws it once
  /// (a swap-in whose steps each ask for a frame draws one).
  void hold_renders(bool hold);
  /// Moves every actor (and the normals, when shown) to the scene's current pose.
  void update_pose();
  /// Follows one step on the shown scene, already followed (`plugins::follow_scene`): only the
  /// points and cells `change` touched are rewritten (ViewPolyData::update). O(change). A mapped
  /// structural step lists the actors again: an instance the scene kept or took back from its
  /// stash (Scene::origins) keeps its drawn data, every other is built; the data of instances
  /// that left (Scene::departed) is kept until the next structural step (or pose), for an undo or
  /// redo that brings them back. @pre an unmapped structural change is shown with `set_scene`.
  void update_scene(const ModelChange& change);
  /// Builds what the data of the instances a structural step made, or a new scene's, left for
  /// later (the corner lists they get only before their first update:
  /// ViewPolyData::prepare_updates): when idle after the step's frame (a new scene's: after its
  /// first frame, by itself).
  void prepare_updates();
  /// The drawn data of instance `instance` (nullptr for an unknown one): what tests and the
  /// studio benchmark compare with a fresh build.
  vtkPolyData* instance_poly_data(std::size_t instance) const;
  /// The memory of the view's own data (ViewPolyData::bytes over the instances drawn and the
  /// data set aside for an undo; `count`: how many data): what the studio benchmark reports
  /// beside the model's ("view_bytes").
  struct DataBytes {
    std::size_t used = 0, held = 0, count = 0;
  };
  DataBytes data_bytes() const;
  /// Draws instance `instance` at `positions` (world, one per vertex slot of its mesh) instead of its
  /// posed positions, until the next `update_pose` or `set_scene`.
  void set_instance_positions(std::size_t instance, const std::vector<glm::vec3>& positions);
  /// The world positions instance `instance` is drawn at, one per vertex slot (slots that are not
  /// drawn keep the posed position). Empty for an unknown instance.
  std::vector<glm::vec3> instance_positions(std::size_t instance) const;

  /// Colours instance `instance` (Kind::None restores its material look).
  void set_instance_colors(std::size_t instance, const plugins::InstanceColors& colors);
  /// Layers of overlays, replaced independently.
  enum class Layer { Skeleton, Inspector, Tool };
  void set_overlay(Layer layer, const Overlay& overlay);
  void set_color_bar(const std::optional<ColorBar>& bar);
  /// Text in the upper left corner of the view.
  void set_caption(const std::vector<std::string>& lines);
  /// Skeleton parts that a click can hit (empty: bones are not pickable).
  void set_bone_handles(std::vector<BoneHandle> handles);

  void set_display_mode(DisplayMode mode);
  DisplayMode display_mode() const;
  void set_normals_visible(bool visible);
  bool normals_visible() const;

  /// Frames the whole scene (current pose) from a three-quarter front view.
  void reset_camera();
  /// Zooms to a sphere (world space) keeping the view direction.
  void frame(const glm::vec3& center, float radius);
  /// The camera's direction of projection (world space, unit length).
  glm::vec3 view_direction() const;
  /// Renders now.
  void render();
  /// Compiles what a model's first frame draws with: the shaders of an untextured and of a
  /// textured surface, set up as a scene instance's, each by drawing one small triangle alone in
  /// a frame that is never shown, one per turn of the event loop from the next on (the caller
  /// returns at once). Once per view; what is left waits for a view that can draw. The studio
  /// asks for it while a worker reads a file (the UI thread is idle then): the first frame of
  /// the open then costs about what a later frame costs.
  void warm_up();
  /// Samples per pixel for anti-aliasing (0: none), from the next frame on.
  void set_multisamples(int samples);
  int multisamples() const;
  /// Called at the start of every `render` (nullptr: none): the studio benchmark times the work
  /// between an action and the render call with it.
  void set_render_listener(std::function<void()> listener);
  /// CPU time the UI thread spent in the last frame's drawing, in ms (the renderer's own
  /// threads not counted where the platform has a thread CPU clock; else the process's CPU
  /// time). Public because the studio benchmark, which drives the real main window, reports it
  /// beside wall times on a loaded machine; the studio itself does not read it.
  double last_render_cpu_ms() const;
  /// How many frames `render` drew so far.
  int frames_drawn() const;
  /// The rendered view as an image (renders first).
  QImage grab_view();

  /// The camera's up direction (world space, unit length, across the view direction).
  glm::vec3 view_up() const;

  /// Shows `widget` (a tool's VTK widget; nullptr: none) over the model and lets it take the
  /// mouse: it gets the view's interactor and a renderer layered between the model and the
  /// overlays, and is enabled; the previous widget is disabled. The caller keeps the widget
  /// alive while it is shown.
  void set_tool_widget(vtkAbstractWidget* widget);

  /// The model's surface point under widget coordinates `position` (logical pixels, origin top
  /// left), without reporting a pick; nullopt when no instance is there.
  std::optional<glm::vec3> surface_point_at(const QPoint& position);
  /// Widget coordinates of the mouse cursor when it is over the view, else nullopt.
  std::optional<QPoint> cursor_position() const;

  /// Called when the user clicks (press and release without dragging) on an instance or a bone.
  void set_pick_handler(std::function<void(const plugins::Pick&)> handler);
  /// Called on a left press (with what is under the cursor), and, when it returned true for the
  /// press, on every move and on the release; the camera does not move during such a drag.
  void set_pointer_handler(std::function<bool(const PointerEvent&)> handler);
  /// Picks at widget coordinates (logical pixels, origin top left), as a click there would.
  /// @returns false when nothing was hit.
  bool pick_at(const QPoint& position);
  /// Where world point `p` appears in the widget (logical pixels, origin top left).
  QPoint project(const glm::vec3& p) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace deepcut::studio
