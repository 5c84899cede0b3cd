// SPDX-License-Identifier: MIT
#pragma once
/// @file tool.h
/// Operation tools (Plane cut, Scalpel tear, Drill): each plugin folder `plugins/NAME/` holds a
/// tool's parameters, its numeric panel, its interactive 3D widget (a widgets/ VTK pair), its
/// placement on the model and its live preview, and defines
/// `std::unique_ptr<Tool> deepcut::plugins::create_NAME_tool()`, which the registry
/// (tool_registry.h) lists. The studio applies a tool's parameters with
/// `deepcut::apply_operation`, exactly as `deepcut apply` does. A tool that acts on the model
/// directly instead (the soft-body Poke) makes no operation and takes the mouse and a clock
/// (`press` / `move` / `release`, `step`, `displaced_positions`).

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deepcut/core/ops/operation.h"
#include "deepcut/plugins/inspector.h"
#include "deepcut/plugins/scene.h"
#include "deepcut/plugins/tool_registry.h"
#include "deepcut/widgets/overlay.h"

class QWidget;
class vtkAbstractWidget;

namespace deepcut::plugins {

/// Where the studio asks a tool to place itself: the camera and, when there is one, the point
/// of the model's surface the user means (under the cursor, else the last clicked point).
struct ToolPlacement {
  glm::vec3 view_direction{0.0f, 0.0f, -1.0f};  ///< camera direction of projection (unit)
  glm::vec3 view_up{0.0f, 1.0f, 0.0f};          ///< camera up (unit, across view_direction)
  std::optional<glm::vec3> point;               ///< a surface point (posed world space), if any
};

/// Where the cursor is, for tools that take the mouse: its ray through the view (world space).
struct ToolPointer {
  glm::vec3 ray_origin{0.0f};
  glm::vec3 ray_direction{0.0f, 0.0f, -1.0f};   ///< unit length, into the scene
  glm::vec3 view_direction{0.0f, 0.0f, -1.0f};  ///< the camera's direction of projection
};

/// One operation tool. Parameters live in the tool; its panel, its widget and `set_parameters`
/// all change them and mirror each other (a drag updates the panel's numbers, a typed number
/// moves the widget; showing a value is never an edit, so nothing loops), and every change calls
/// the changed callback (the studio redraws the preview).
class Tool {
 public:
  virtual ~Tool() = default;
  /// Command-line and history name of the operation ("cut", "tear", "drill").
  virtual std::string id() const = 0;
  /// Tool bar text ("Plane", "Scalpel", "Drill").
  virtual std::string title() const = 0;
  /// Builds the numeric parameter panel (owned by `parent`). Called once.
  virtual QWidget* create_panel(QWidget* parent) = 0;
  /// Places the tool sensibly on `scene` (posed world positions) and refreshes the panel and
  /// the widget.
  virtual void place(const Scene& scene, const ToolPlacement& placement) = 0;
  /// The tool's interactive 3D widget, owned by the tool (nullptr: numbers only). The studio
  /// gives it the view's interactor and a renderer drawn over the model and enables it while
  /// the tool is chosen; the tool observes its InteractionEvent.
  virtual vtkAbstractWidget* widget() { return nullptr; }
  /// The operation the tool would apply now.
  virtual OperationParams parameters() const = 0;
  /// Sets the parameters (and the panel). @throws Error{InvalidArgument} for another tool's type.
  virtual void set_parameters(const OperationParams& params) = 0;
  /// What applying would touch on the posed scene (contour, path, rim), as world-space lines
  /// (the first line set) and markers; the tool itself is drawn by its widget.
  virtual Overlay preview(const Scene& scene) const = 0;

  /// False for a tool that makes no operation (no Apply, no history entry); its `parameters`
  /// and `set_parameters` throw Error{InvalidArgument}.
  virtual bool makes_operation() const { return true; }
  /// The left button went down on the model at `pick`. @returns true to take the drag: the
  /// camera stays still and `move` / `release` follow until the button goes up.
  virtual bool press(const Scene& scene, const Pick& pick, const ToolPointer& pointer) {
    (void)scene, (void)pick, (void)pointer;
    return false;
  }
  virtual void move(const Scene& scene, const ToolPointer& pointer) { (void)scene, (void)pointer; }
  virtual void release(const Scene& scene) { (void)scene; }
  /// Advances the tool's own motion by `dt` seconds (the studio calls it from a timer, also
  /// while the animation plays). @returns true while anything still moves.
  virtual bool step(const Scene& scene, float dt) {
    (void)scene, (void)dt;
    return false;
  }
  /// The positions to draw piece `piece` at instead of its posed ones (one per vertex slot).
  /// @returns false when the piece is drawn as posed.
  virtual bool displaced_positions(const Scene& scene, std::size_t piece, std::vector<glm::vec3>& out) const {
    (void)scene, (void)piece, (void)out;
    return false;
  }

  void set_changed_callback(std::function<void()> callback) { changed_ = std::move(callback); }

 protected:
  void notify_changed() const {
    if (changed_) changed_();
  }

 private:
  std::function<void()> changed_;
};

/// Creates the interactive tool `id` of `registry`.
/// @throws Error{InvalidArgument} naming the known ids if `id` is unknown or has no factory.
std::unique_ptr<Tool> create_tool(const ToolRegistry& registry, const std::string& id);

/// Segments where the triangles of `scene` meet `plane` (the cut contour), world space.
std::vector<glm::vec3> plane_contour(const Scene& scene, const Plane& plane);

/// Segments where the triangles of `scene` meet the triangle `tri` (world space).
std::vector<glm::vec3> triangle_contour(const Scene& scene, const std::array<glm::vec3, 3>& tri);

/// The world-space bounding box of the scene's posed positions.
BoundingBox scene_bounds(const Scene& scene);

}  // namespace deepcut::plugins
