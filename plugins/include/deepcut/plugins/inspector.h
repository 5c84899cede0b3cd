// SPDX-License-Identifier: MIT
#pragma once
/// @file inspector.h
/// The interface of an inspector plugin. An inspector looks at the scene (model + pose) and
/// answers with data: colours for each instance's surface, an overlay, an optional colour bar and a
/// few summary lines. It owns a Qt panel with its controls. It never touches VTK objects, so it
/// can be tested without a display. Each inspector lives in its own folder under `plugins/`.

#include <cstddef>
#include <functional>
#include <glm/gtc/type_precision.hpp>
#include <optional>
#include <string>
#include <vector>

#include "deepcut/core/types.h"
#include "deepcut/plugins/scene.h"
#include "deepcut/widgets/overlay.h"

class QWidget;

namespace deepcut::plugins {

/// How an instance's surface is coloured.
struct InstanceColors {
  enum class Kind {
    None,       ///< the model's own look (material, texture)
    PerVertex,  ///< `colors` has one entry per vertex slot of the instance's mesh
    PerFace     ///< `colors` has one entry per face slot of the instance's mesh
  };
  Kind kind = Kind::None;
  std::vector<glm::u8vec3> colors;
};

/// What the user clicked in the view.
struct Pick {
  static constexpr std::size_t kNoInstance = static_cast<std::size_t>(-1);
  std::size_t instance = kNoInstance;  ///< index into Scene::instances, or kNoInstance when a bone was hit
  FaceId face;                   ///< the face under the cursor
  VertexId vertex;               ///< the vertex of that face nearest to the clicked point
  glm::vec3 position{0.0f};      ///< the clicked world position
  int joint_node = -1;           ///< the joint whose bone was clicked, or -1
};

/// A region of interest in world space (what "Frame selected" zooms to).
struct Focus {
  glm::vec3 center{0.0f};
  float radius = 1.0f;
};

/// What changed since the last `set_scene` call.
enum class SceneChange {
  Model,  ///< a new model or a new version of it (topology and attributes may differ)
  Pose    ///< only the pose (animation or time): positions moved
};

class Inspector {
 public:
  virtual ~Inspector() = default;

  /// Short name used on the command line (`--inspect ID`), e.g. "weights".
  virtual std::string id() const = 0;
  /// Title shown in menus and the panel, e.g. "Skin weights".
  virtual std::string title() const = 0;

  /// Creates the panel with the inspector's controls (Qt parent ownership). Called at most once;
  /// the inspector keeps the panel's widgets up to date from then on.
  virtual QWidget* create_panel(QWidget* parent) = 0;

  /// Gives the inspector the scene it looks at. The caller keeps `scene` alive and unchanged
  /// until the next call (or until the inspector is destroyed).
  virtual void set_scene(const Scene& scene, SceneChange change) = 0;

  /// Colours for instance `instance` of the current scene.
  virtual InstanceColors instance_colors(std::size_t instance) const = 0;
  /// What to draw over the model for the current scene and state.
  virtual Overlay overlay() const = 0;
  /// A colour bar to show beside the view, if the colours encode a continuous value.
  virtual std::optional<ColorBar> color_bar() const { return std::nullopt; }
  /// The selection to frame (picked vertex, chosen joint), if any, at the current pose.
  virtual std::optional<Focus> focus() const { return std::nullopt; }
  /// One to four short lines describing what is shown (view caption, tests, headless use).
  virtual std::vector<std::string> summary() const = 0;

  /// Reacts to a click in the view. @returns true if the inspector's state changed.
  virtual bool pick(const Pick& pick) {
    (void)pick;
    return false;
  }

  /// Sets an option by name (the command line's `--joint NAME`, `--vertex N`, ...).
  /// @throws Error{InvalidArgument} for an unknown option or a value that does not fit the scene
  ///         (the message names the option and the value).
  virtual void set_option(const std::string& name, const std::string& value);

  /// Called whenever the inspector's state changes through its panel, so the view can redraw.
  void set_changed_callback(std::function<void()> callback) { changed_ = std::move(callback); }

  /// Long work an inspector hands to the studio: run on a worker thread with `stage` (names
  /// the stage starting; throws once the user cancelled, so the work unwinds), it returns what
  /// to do with its result on the UI thread (not run when cancelled).
  using Work = std::function<std::function<void()>(const std::function<void(const std::string&)>& stage)>;
  /// Runs `title`'s work (the studio: off the UI thread, with a progress bar and Cancel, edits
  /// disabled meanwhile); `cancelled` runs on the UI thread when the user cancelled it.
  /// @returns false when it did not start (another one runs).
  using Runner = std::function<bool(const std::string& title, Work work, std::function<void()> cancelled)>;
  /// Where `run_in_background` sends work; without one (headless use) it runs at once.
  void set_background_runner(Runner runner) { runner_ = std::move(runner); }

 protected:
  void notify_changed() const {
    if (changed_) changed_();
  }
  /// Runs `work` through the runner (see Runner), or at once on this thread without one.
  bool run_in_background(const std::string& title, Work work, std::function<void()> cancelled = {}) const {
    if (runner_) return runner_(title, std::move(work), std::move(cancelled));
    work([](const std::string&) {})();
    return true;
  }

 private:
  std::function<void()> changed_;
  Runner runner_;
};

}  // namespace deepcut::plugins
