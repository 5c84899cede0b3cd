// SPDX-License-Identifier: MIT
#pragma once
// The scene tree: node hierarchy (meshes, joints), meshes and their primitives, the drawn
// pieces, skins with their joints, animations, materials and images.

#include <QTreeWidget>

#include "deepcut/plugins/scene.h"

namespace deepcut::studio {

class SceneTree : public QTreeWidget {
  Q_OBJECT

 public:
  explicit SceneTree(QWidget* parent = nullptr);

  /// Shows `scene` (its model and pieces).
  void set_scene(const plugins::Scene& scene);

 signals:
  /// A joint node was clicked (in the hierarchy or under a skin).
  void joint_selected(int node);

 private:
  QTreeWidgetItem* add(QTreeWidgetItem* parent, const QString& name, const QString& info);
};

}  // namespace deepcut::studio
