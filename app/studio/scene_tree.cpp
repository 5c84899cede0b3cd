// SPDX-License-Identifier: MIT
#include "scene_tree.h"

#include <QHeaderView>
#include <functional>
#include <set>

namespace deepcut::studio {
namespace {

constexpr int kJointRole = Qt::UserRole + 1;  // node index of a joint item

QString clip_name(const Animation& animation, std::size_t i) {
  return animation.name.empty() ? QString("Animation %1").arg(i) : QString::fromStdString(animation.name);
}

}  // namespace

SceneTree::SceneTree(QWidget* parent) : QTreeWidget(parent) {
  setObjectName("scene_tree");
  setHeaderLabels({"Name", "Details"});
  header()->setStretchLastSection(true);
  header()->setSectionResizeMode(0, QHeaderView::ResizeToContents);
  setUniformRowHeights(true);
  setAlternatingRowColors(true);
  connect(this, &QTreeWidget::itemClicked, this, [this](QTreeWidgetItem* item, int) {
    const QVariant joint = item->data(0, kJointRole);
    if (joint.isValid()) emit joint_selected(joint.toInt());
  });
}

QTreeWidgetItem* SceneTree::add(QTreeWidgetItem* parent, const QString& name, const QString& info) {
  auto* item = new QTreeWidgetItem({name, info});
  if (parent)
    parent->addChild(item);
  else
    addTopLevelItem(item);
  return item;
}

void SceneTree::set_scene(const plugins::Scene& scene) {
  clear();
  const Model& model = *scene.model;
  std::set<int> joints;
  for (int j : plugins::joint_nodes(model)) joints.insert(j);
  auto label = [&](int node) { return QString::fromStdString(plugins::node_label(model, node)); };

  QTreeWidgetItem* nodes = add(nullptr, "Nodes", QString("%1").arg(model.nodes.size()));
  std::set<int> shown;
  std::function<void(QTreeWidgetItem*, int)> add_node = [&](QTreeWidgetItem* parent, int n) {
    if (n < 0 || n >= static_cast<int>(model.nodes.size()) || !shown.insert(n).second) return;
    const Node& node = model.nodes[static_cast<std::size_t>(n)];
    QStringList info;
    if (joints.count(n)) info << "joint";
    if (node.mesh >= 0) info << QString("mesh %1").arg(node.mesh);
    if (node.skin >= 0) info << QString("skin %1").arg(node.skin);
    if (node.camera >= 0) info << "camera";
    QTreeWidgetItem* item = add(parent, label(n), info.join(", "));
    if (joints.count(n)) item->setData(0, kJointRole, n);
    for (int child : node.children) add_node(item, child);
  };
  for (int root : model.root_nodes()) add_node(nodes, root);
  for (int n = 0; n < static_cast<int>(model.nodes.size()); ++n)
    add_node(nodes, n);  // nodes outside the scene
  nodes->setExpanded(true);
  for (int i = 0; i < nodes->childCount(); ++i) nodes->child(i)->setExpanded(true);

  QTreeWidgetItem* meshes = add(nullptr, "Meshes", QString("%1").arg(model.meshes.size()));
  for (std::size_t m = 0; m < model.meshes.size(); ++m) {
    const Mesh& mesh = model.meshes[m];
    QTreeWidgetItem* item =
        add(meshes, mesh.name.empty() ? QString("mesh %1").arg(m) : QString::fromStdString(mesh.name),
            QString("%1 primitives").arg(mesh.primitives.size()));
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      const SurfaceMesh& s = mesh.primitives[p].mesh;
      add(item, QString("primitive %1").arg(p),
          QString("%1 vertices, %2 triangles, material %3")
              .arg(s.vertex_count())
              .arg(s.face_count())
              .arg(mesh.primitives[p].material));
    }
  }
  meshes->setExpanded(true);

  QTreeWidgetItem* instances = add(nullptr, "Instances", QString("%1 drawn").arg(scene.instances.size()));
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const plugins::SceneInstance& instance = scene.instances[i];
    add(instances, QString("instance %1: %2").arg(i).arg(label(instance.node)),
        QString("mesh %1 / primitive %2, %3 triangles%4")
            .arg(instance.mesh)
            .arg(instance.primitive)
            .arg(instance.surface->face_count())
            .arg(instance.skin >= 0 ? QString(", skinned (skin %1)").arg(instance.skin) : QString()));
  }

  QTreeWidgetItem* skins = add(nullptr, "Skins", QString("%1").arg(model.skins.size()));
  for (std::size_t s = 0; s < model.skins.size(); ++s) {
    const Skin& skin = model.skins[s];
    QTreeWidgetItem* item =
        add(skins, skin.name.empty() ? QString("skin %1").arg(s) : QString::fromStdString(skin.name),
            QString("%1 joints").arg(skin.joints.size()));
    for (std::size_t j = 0; j < skin.joints.size(); ++j) {
      QTreeWidgetItem* joint =
          add(item, label(skin.joints[j]), QString("joint %1, node %2").arg(j).arg(skin.joints[j]));
      joint->setData(0, kJointRole, skin.joints[j]);
    }
  }

  QTreeWidgetItem* animations = add(nullptr, "Animations", QString("%1").arg(model.animations.size()));
  for (std::size_t a = 0; a < model.animations.size(); ++a)
    add(animations, clip_name(model.animations[a], a),
        QString("%1 s, %2 channels")
            .arg(model.animations[a].duration(), 0, 'f', 2)
            .arg(model.animations[a].channels.size()));

  QTreeWidgetItem* materials = add(nullptr, "Materials", QString("%1").arg(model.materials.size()));
  for (std::size_t m = 0; m < model.materials.size(); ++m)
    add(materials,
        model.materials[m].name.empty() ? QString("material %1").arg(m)
                                        : QString::fromStdString(model.materials[m].name),
        "");
  QTreeWidgetItem* images = add(nullptr, "Images", QString("%1").arg(model.images.size()));
  for (std::size_t i = 0; i < model.images.size(); ++i)
    add(images,
        model.images[i].name.empty() ? QString("image %1").arg(i)
                                     : QString::fromStdString(model.images[i].name),
        QString("%1, %2 KB")
            .arg(QString::fromStdString(model.images[i].mime_type))
            .arg(model.images[i].data.size() / 1024));
}

}  // namespace deepcut::studio
