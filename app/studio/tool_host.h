// SPDX-License-Identifier: MIT
#pragma once
/// @file tool_host.h
/// Hosts the operation tools (plugins/include/deepcut/plugins/tool.h) in the studio: the Tool
/// panel (the active tool's parameters, Apply, a banner), the Tools menu entries, choosing and
/// placing a tool, its live preview, left drags offered to it, and the motion of a tool that
/// moves the drawn model on its own (the Poke's soft body). See docs/studio.md.

#include <QElapsedTimer>
#include <QObject>
#include <QString>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deepcut/core/posed_model.h"
#include "deepcut/plugins/scene.h"
#include "deepcut/plugins/tool.h"

class QAction;
class QActionGroup;
class QLabel;
class QMenu;
class QPushButton;
class QStackedWidget;
class QTimer;
class QWidget;

namespace deepcut::studio {

struct PointerEvent;
class SceneView;

class ToolHost : public QObject {
  Q_OBJECT

 public:
  /// Creates every registered tool that the studio can host.
  ToolHost(SceneView* view, QObject* parent);
  ~ToolHost() override;

  /// The Tool panel: banner (hidden until set), the tools' panels, Apply.
  QWidget* create_panel(QWidget* parent);
  /// One checkable entry per tool (at most one active), then Apply (Enter).
  void add_menu_actions(QMenu* menu);
  /// The tool entries and Apply, for a tool bar.
  QList<QAction*> actions() const;

  /// The scene the tools work on (the window's, kept at one address), or nullptr.
  void set_scene(plugins::Scene* scene) { scene_ = scene; }
  plugins::Scene* scene() const { return scene_; }

  /// Chooses tool `id` ("" or "none": no tool), placed on the scene. See MainWindow::set_tool.
  /// @throws Error{InvalidArgument} for an unknown id.
  void set_tool(const std::string& id);
  plugins::Tool* tool() const;
  std::string tool_id() const;
  /// Places the active tool on a new scene (a model was opened) and shows its widget.
  void place_on_new_scene();

  /// Draws the active tool's preview.
  void refresh_preview();
  /// Sets the active tool's preview without drawing a frame: a caller that draws one anyway (a
  /// step shown, a pose) draws it with the rest, so a step costs one frame, not two.
  void update_preview();
  /// The scene was drawn anew at its posed positions (a new state or pose).
  void scene_redrawn() { displaced_ = false; }
  /// Draws the pieces where the active tool displaces them (or as posed).
  void show_displacement();

  /// A click on the model: the surface point tools are placed at when the cursor is elsewhere.
  void note_pick(const plugins::Pick& pick);
  void forget_pick() { last_surface_click_.reset(); }
  /// A left drag in the view, offered to the active tool. @returns true when it took it.
  bool on_pointer(const PointerEvent& event);

  /// Lends the scene's instances the grids of `posed` where it describes them bit for bit (the
  /// previews then visit only the cells they cross), or takes them back (nullptr). The positions
  /// are compared in full the first time a pair of arrays (the posed model's, the scene's) is
  /// lent; after that both follow the same steps, each as a fresh build would, so only their
  /// sizes are compared: O(instances) on the way from Apply to the frame.
  void lend_grids(const std::shared_ptr<const Model>& model, const PosedModel* posed);

  /// Shows `text` above the tool's panel ("" hides it) and names the Apply button.
  void set_banner(const QString& text, const QString& apply_text);

 signals:
  /// Apply (button or Enter).
  void apply_requested();

 private:
  /// Camera and surface point for placing a tool (see MainWindow::set_tool).
  plugins::ToolPlacement placement();
  /// One tick of the active tool's own motion, then the view follows.
  void step();

  SceneView* view_;
  plugins::Scene* scene_ = nullptr;
  std::vector<std::unique_ptr<plugins::Tool>> tools_;  // in registry order
  int active_ = -1;                                    // index into tools_
  std::optional<glm::vec3> last_surface_click_;        // posed world point of the last click on the model
  QTimer* timer_ = nullptr;                            // steps a tool that moves
  QElapsedTimer clock_;                                // since the last step
  bool displaced_ = false;                             // the view shows displaced positions
  // Per instance (node, primitive): the posed model's and the scene's positions found equal,
  // for the model and pose they were compared at (another one: compared again).
  std::map<std::pair<int, int>, std::pair<const glm::vec3*, const glm::vec3*>> same_positions_;
  const Model* same_model_ = nullptr;
  PoseKey same_key_;
  QStackedWidget* stack_ = nullptr;
  QLabel* banner_ = nullptr;
  QPushButton* apply_button_ = nullptr;
  QActionGroup* group_ = nullptr;
  QAction* apply_action_ = nullptr;
};

}  // namespace deepcut::studio
