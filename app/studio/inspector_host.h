// SPDX-License-Identifier: MIT
#pragma once
/// @file inspector_host.h
/// Hosts the inspectors (plugins/include/deepcut/plugins/inspector.h) in the studio: the
/// Inspector panel and the Inspect menu entries, the active inspector, what each inspector has
/// not yet seen of the scene (inspectors see it lazily: only the active one is kept current),
/// its colours and overlay on the view, and picks routed to it. See docs/studio.md.

#include <QObject>
#include <QString>
#include <memory>
#include <string>
#include <vector>

#include "deepcut/plugins/inspector.h"
#include "deepcut/plugins/scene.h"

class QActionGroup;
class QComboBox;
class QMenu;
class QStackedWidget;
class QWidget;

namespace deepcut::studio {

class SceneView;

class InspectorHost : public QObject {
  Q_OBJECT

 public:
  /// Creates every registered inspector.
  InspectorHost(SceneView* view, QObject* parent);
  ~InspectorHost() override;

  /// The Inspector panel: a chooser above the active inspector's panel.
  QWidget* create_panel(QWidget* parent);
  /// "Shaded (materials)" and one checkable entry per inspector (Ctrl+0, Ctrl+1, ...).
  void add_menu_actions(QMenu* menu);

  /// Gives every inspector `runner` for its long work (re-clustering): the window's
  /// BackgroundTask.
  void set_background_runner(const plugins::Inspector::Runner& runner);
  /// The scene the inspectors look at (the window's, kept at one address), or nullptr.
  void set_scene(const plugins::Scene* scene) { scene_ = scene; }

  /// Activates inspector `id` ("" or "none": the model's own look) in the panel and the menu.
  /// @throws Error{InvalidArgument} for an unknown id.
  void set_inspector(const std::string& id);
  plugins::Inspector* inspector() const;
  std::string inspector_id() const;
  /// Passes an option to the active inspector. @throws Error{InvalidArgument} (see Inspector).
  void set_option(const std::string& name, const std::string& value);

  /// The scene changed (`change`): every inspector sees it when it is next active.
  void mark_stale(plugins::SceneChange change);
  /// Shows the active inspector what changed since it last looked.
  void sync();
  /// Draws the active inspector's colours and colour bar on the view (its overlay is the
  /// window's to draw with the others).
  void draw_colors();
  /// Offers a click to the active inspector. @returns false when there is none; `changed` says
  /// whether it took the pick (then draw again).
  bool pick(const plugins::Pick& pick, bool& changed);

 signals:
  /// The user chose inspector `id` (panel or menu).
  void chosen(const QString& id);
  /// The active inspector changed what it shows.
  void changed();

 private:
  enum class Stale { None, Pose, Model };

  SceneView* view_;
  const plugins::Scene* scene_ = nullptr;
  std::vector<std::unique_ptr<plugins::Inspector>> inspectors_;  // in registry order
  int active_ = -1;                                              // index into inspectors_
  std::vector<Stale> stale_;  // per inspector: what changed since it last saw the scene
  QComboBox* combo_ = nullptr;
  QStackedWidget* stack_ = nullptr;
  QActionGroup* group_ = nullptr;
};

}  // namespace deepcut::studio
