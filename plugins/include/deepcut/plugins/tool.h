// SPDX-License-Identifier: MIT
#pragma once
/// @file tool.h
/// Operation tools (Plane cut, Scalpel tear, Drill): each plugin folder `plugins/NAME/` holds a
/// tool's parameters, its numeric panel, its placement on the model and its live preview, and
/// defines `void deepcut::plugins::register_NAME(ToolRegistry&)`. The build list
/// `DEEPCUT_TOOL_PLUGINS` in `plugins/CMakeLists.txt` generates `builtin_tools()`. The studio
/// applies a tool's parameters with `deepcut::apply_operation`, exactly as `deepcut apply` does.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "deepcut/core/ops/history.h"
#include "deepcut/plugins/scene.h"
#include "deepcut/widgets/overlay.h"

class QWidget;

namespace deepcut::plugins {

/// One operation tool. Parameters live in the tool; its panel and `set_parameters` both change
/// them, and every change calls the changed callback (the studio redraws the preview).
class Tool {
 public:
  virtual ~Tool() = default;
  /// Command-line and history name of the operation ("cut", "tear", "drill").
  virtual std::string id() const = 0;
  /// Tool bar text ("Plane", "Scalpel", "Drill").
  virtual std::string title() const = 0;
  /// Builds the numeric parameter panel (owned by `parent`). Called once.
  virtual QWidget* create_panel(QWidget* parent) = 0;
  /// Places the tool sensibly on `scene` (posed world positions) and refreshes the panel.
  /// @param view_direction  the camera's direction of projection (world space, unit length).
  virtual void place(const Scene& scene, const glm::vec3& view_direction) = 0;
  /// The operation the tool would apply now.
  virtual OperationParams parameters() const = 0;
  /// Sets the parameters (and the panel). @throws Error{InvalidArgument} for another tool's type.
  virtual void set_parameters(const OperationParams& params) = 0;
  /// What applying would touch on the posed scene (contour, path, rim) plus the tool itself,
  /// as world-space lines and markers.
  virtual Overlay preview(const Scene& scene) const = 0;

  void set_changed_callback(std::function<void()> callback) { changed_ = std::move(callback); }

 protected:
  void notify_changed() const {
    if (changed_) changed_();
  }

 private:
  std::function<void()> changed_;
};

struct ToolInfo {
  std::string id;     ///< operation name, unique
  std::string title;  ///< tool bar text
  std::function<std::unique_ptr<Tool>()> create;
};

class ToolRegistry {
 public:
  /// @throws Error{InvalidArgument} if the id is empty, taken, or `create` is empty.
  void add(ToolInfo info);
  const std::vector<ToolInfo>& list() const { return infos_; }
  /// @returns the entry with `id`, or nullptr.
  const ToolInfo* find(const std::string& id) const;
  /// @throws Error{InvalidArgument} naming the known ids if `id` is unknown.
  std::unique_ptr<Tool> create(const std::string& id) const;
  /// The ids, comma separated ("cut, tear, drill").
  std::string ids() const;

 private:
  std::vector<ToolInfo> infos_;
};

/// The tools built into this program, in build-list order.
const ToolRegistry& builtin_tools();

/// Segments where the triangles of `scene` meet `plane` (the cut contour), world space.
std::vector<glm::vec3> plane_contour(const Scene& scene, const Plane& plane);

/// Segments where the triangles of `scene` meet the triangle `tri` (world space).
std::vector<glm::vec3> triangle_contour(const Scene& scene, const std::array<glm::vec3, 3>& tri);

/// The world-space bounding box of the scene's posed positions.
BoundingBox scene_bounds(const Scene& scene);

}  // namespace deepcut::plugins
