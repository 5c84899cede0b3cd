// SPDX-License-Identifier: MIT
#pragma once
/// @file scene_host.h
/// The drawn state: the Scene (plugins/include/deepcut/plugins/scene.h) of the session's current
/// state at the time line's pose, handed to the view, the scene tree and the tool and inspector
/// hosts; the session's posed model lent to it (its grids) and rebuilt once the pose settles;
/// the overlays drawn over it (skeleton, inspector, caption) and clicks on it. See
/// docs/studio.md.

#include <QObject>
#include <QString>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "deepcut/plugins/inspector.h"
#include "deepcut/plugins/scene.h"
#include "scene_view.h"
#include "session.h"

class QTimer;

namespace deepcut::studio {

class InspectorHost;
class MorphPanel;
class SceneTree;
class Timeline;
class ToolHost;

class SceneHost : public QObject {
  Q_OBJECT

 public:
  SceneHost(SceneView* view, SceneTree* tree, Timeline* timeline, ToolHost* tools, InspectorHost* inspectors,
            session::Session& session, QObject* parent);
  ~SceneHost() override;

  /// The drawn scene (null before the first model).
  const plugins::Scene* scene() const { return scene_.get(); }
  /// Shows `scene`, the session's newly opened state, named `title` in the caption; the camera
  /// frames it; `prepared` (SceneView::prepare of `scene`, or null) is its VTK data. @returns
  /// the view's notes on what it cannot draw.
  std::vector<std::string> show_opened(plugins::Scene scene, const QString& title,
                                       std::shared_ptr<const SceneView::Prepared> prepared = nullptr);
  /// Gives every instance without corner normals (a scene opened without them: its first frame
  /// posed a normal per drawn point only) the corner normals of its pose, which the scene's
  /// followers use from the first step: `normals` (one array per instance, made off the UI
  /// thread after that frame) when the scene still shows `built_for` at `key`, each where it
  /// holds the instance's corners. Nothing otherwise (a step or a new pose made them).
  void adopt_normals(std::vector<std::vector<glm::vec3>> normals, const Model* built_for, const PoseKey& key);
  /// The same, the corner normals made here (what adopt_normals did not give). Nothing to do
  /// otherwise.
  void complete_normals();
  /// The pose the scene is drawn at (animation, time, morph weights set by hand). @pre scene().
  PoseKey pose_key() const;
  /// The operations' posed model of the state just opened, built off the UI thread after its
  /// first frame (show_opened leaves the session without one: building it, grids included,
  /// would delay that frame): the session takes it when it describes the current state
  /// (`built_for`, no step since) at the scene's pose, and the tools get its grids.
  void adopt_posed_model(std::unique_ptr<PosedModel> posed, const Model* built_for, std::uint64_t version);
  /// How the operations' posed model is rebuilt once a step or the pose settles: `start` begins
  /// building it off the UI thread (handed back through adopt_posed_model) and returns whether
  /// it could start now (else the scene asks again later). Without one it is rebuilt in place.
  void set_posed_builder(std::function<bool()> start) { posed_builder_ = std::move(start); }
  /// Shows the session's current state at the time line's pose (after an undo step or an edit),
  /// in one frame.
  void show_current();
  /// Shows the session's current state after one step from the shown state (an operation, its
  /// undo or redo) that `change` describes: the scene, its VTK data, the tree and the inspectors
  /// follow it in O(change) (a mapped structural step, such as a cut and its undo and redo: in
  /// O(what it made), keeping what it kept); an unmapped structural change (or one that does not
  /// start at the shown state) is shown as `show_current` does, and so is every step while the environment
  /// variable DEEPCUT_VIEW_REBUILD is 1 (the studio benchmark's reference). One step draws one
  /// frame (the tool's preview, the inspector's colours and the overlays all in it).
  void show_step(const ModelChange& change);
  /// Where the last `show_step` that followed its step spent its time before the frame, in ms:
  /// the scene (posed meshes, corner normals) and the view's VTK data, wall clock and the
  /// process's CPU time (every thread of the pool; steadier on a loaded machine), and the
  /// process's minor page faults: at the step's start (before the scene follows it: what came
  /// before, the operation and its undo record, is counted from there), in the scene, in the view.
  struct StepTiming {
    double scene_ms = 0.0, view_ms = 0.0;
    double scene_cpu_ms = 0.0, view_cpu_ms = 0.0;
    long faults_at_start = 0, scene_faults = 0, view_faults = 0;
  };
  StepTiming last_step_timing() const { return step_timing_; }
  /// Poses the scene at `time` of `animation` (the time line moved), at the morph weights set by
  /// hand.
  void pose(int animation, float time);
  /// Shows the morph weights in `panel` and poses the scene (and the operations) at the weights
  /// set there by hand.
  void set_morph_panel(MorphPanel* panel);

  /// Brings the session's posed model up to date for the shown state and pose now (else done
  /// once the pose stays put for a moment), and lends the scene its grids.
  void refresh_posed_model();
  /// What the idle timer runs: nothing when the posed model already describes the shown state
  /// and pose, else the posed builder (set_posed_builder), else refresh_posed_model.
  void rebuild_posed_model();
  /// Lends the scene the posed model's grids when it describes the shown state and pose and has
  /// them (one lent to a cut has none: it is built again once idle).
  void lend_grids();

  /// Redraws the active inspector's colours and every overlay.
  void refresh_inspector();
  /// Redraws the skeleton, the inspector's overlay and the caption.
  void refresh_overlays();
  void set_skeleton_visible(bool visible);
  bool skeleton_visible() const { return show_skeleton_; }
  /// Zooms the view to the active inspector's selection. @returns false when there is none.
  bool frame_selected();
  /// A click on the model or a bone: the tools note it, the active inspector takes it, else the
  /// status bar names what was hit.
  void pick(const plugins::Pick& pick);

 signals:
  /// The overlays were drawn (counts, pose or caption may have changed).
  void overlays_changed();
  /// A passing note for the status bar.
  void note(const QString& text, int timeout_ms);

 private:
  /// Shows the scene's morph weights in the panel, dropping weights set by hand for nodes that no
  /// longer morph alike. @returns true when that re-posed the scene.
  bool sync_morph_panel();
  /// Sets the skeleton (unless its joints and bones are where they were last drawn), the
  /// inspector's overlay and the caption (refresh_overlays without the signal: a caller drawing
  /// a frame signals after asking for it).
  void draw_overlays();
  /// The inspector's colours, the overlays, one frame, then the signal (refresh_inspector, and a
  /// step's one frame).
  void draw_frame();
  /// Hands the scene to the view, the tree and the hosts. @returns the view's notes.
  std::vector<std::string> present(std::shared_ptr<const SceneView::Prepared> prepared = nullptr);

  SceneView* view_;
  SceneTree* tree_;
  Timeline* timeline_;
  ToolHost* tools_;
  InspectorHost* inspectors_;
  MorphPanel* morph_ = nullptr;
  session::Session& session_;
  std::unique_ptr<plugins::Scene> scene_;  // created once, then kept at one address
  std::function<bool()> posed_builder_;   // set_posed_builder
  QTimer* posed_timer_ = nullptr;          // rebuilds the posed model once the pose or state settles
  QString title_;
  bool show_skeleton_ = true;
  std::vector<BoneHandle> drawn_bones_;  // the skeleton's joints and bones as drawn
  StepTiming step_timing_;
  bool skeleton_drawn_ = false;           // false: a new scene, the skeleton not drawn yet
};

}  // namespace deepcut::studio
