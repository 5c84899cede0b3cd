// SPDX-License-Identifier: MIT
#pragma once
/// @file morph_panel.h
/// The Morph weights dock: one group per drawn node whose mesh has morph targets, a slider and a
/// spin box per target (named by the mesh's `target_names`, else "target N"). A node's weights
/// follow the animation (the sliders move as the time line plays) until the designer drags one of
/// its sliders: its weights are then set by hand (PoseKey::weights) until "From animation" is
/// ticked again. The drawn pose and the operations use the same weights, so a cut is made at the
/// expression shown. See docs/studio.md.

#include <QString>
#include <QWidget>
#include <map>
#include <vector>

#include "deepcut/plugins/scene.h"

class QCheckBox;
class QDoubleSpinBox;
class QScrollArea;
class QSlider;
class QVBoxLayout;

namespace deepcut::studio {

class MorphPanel : public QWidget {
  Q_OBJECT

 public:
  explicit MorphPanel(QWidget* parent = nullptr);

  /// Lists the morphing nodes of `scene` (nullptr: none). Weights set by hand stay for nodes that
  /// still draw a mesh with as many targets, and pass to the pieces a cut made of them (new nodes
  /// named "NODE_pieceK"); the others follow the animation again.
  void set_scene(const plugins::Scene* scene);
  /// Shows the scene's weights at its pose on the sliders (no signal).
  void show_pose();

  /// Weights set by hand, per node: what the scene's and the operations' pose use.
  const std::map<int, std::vector<float>>& overrides() const { return overrides_; }
  /// Sets weight `target` of `node` by hand, as dragging its slider does. Emits weights_changed.
  void set_weight(int node, int target, float value);
  /// Lets `node`'s weights follow the animation again. Emits weights_changed.
  void follow_animation(int node);

  /// Number of listed nodes (0: the panel's one line says the model has no morph targets).
  int group_count() const { return static_cast<int>(groups_.size()); }

 signals:
  /// The weights set by hand changed (`overrides()`).
  void weights_changed();

 private:
  struct Row {
    QSlider* slider = nullptr;
    QDoubleSpinBox* spin = nullptr;
  };
  struct Group {
    int node = -1;
    QCheckBox* follow = nullptr;
    std::vector<Row> rows;
  };

  void rebuild();
  QWidget* make_group(const Group& group, std::vector<Row>& rows, QCheckBox*& follow);
  /// The node's weights as shown: set by hand, else the pose's.
  std::vector<float> shown_weights(int node, std::size_t count) const;

  const plugins::Scene* scene_ = nullptr;
  QScrollArea* scroll_ = nullptr;
  QWidget* body_ = nullptr;  // rebuilt with the list of nodes
  QVBoxLayout* layout_ = nullptr;
  std::vector<Group> groups_;
  std::vector<int> listed_;  // nodes and target counts the groups were built for, to rebuild only on change
  std::map<int, std::vector<float>> overrides_;
  std::size_t node_count_ = 0;  // nodes of the model last shown (later ones are new: a cut's pieces)
  bool had_scene_ = false;  // whether the groups were built for a scene (else: "No model.")
  bool updating_ = false;  // programmatic value changes: no signals
};

}  // namespace deepcut::studio
