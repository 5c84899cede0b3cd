// SPDX-License-Identifier: MIT
#include "morph_panel.h"

#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QGridLayout>
#include <QGroupBox>
#include <QLabel>
#include <QScrollArea>
#include <QSlider>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>

namespace deepcut::studio {
namespace {

/// The slider covers weights 0..1 in steps of 1/kSteps; the spin box takes any weight in
/// [kMin, kMax] (glTF allows weights outside 0..1: they extrapolate a target).
constexpr int kSteps = 1000;
constexpr double kMin = -2.0, kMax = 2.0;
/// Tallest the panel insists on being (pixels): about six targets; longer lists scroll.
constexpr int kMaxMinimumHeight = 220;

int slider_position(float weight) {
  return static_cast<int>(std::lround(std::clamp(static_cast<double>(weight), 0.0, 1.0) * kSteps));
}

QString target_label(const Mesh& mesh, std::size_t target) {
  if (target < mesh.target_names.size() && !mesh.target_names[target].empty())
    return QString::fromStdString(mesh.target_names[target]);
  return QString("target %1").arg(target);
}

}  // namespace

MorphPanel::MorphPanel(QWidget* parent) : QWidget(parent) {
  auto* outer = new QVBoxLayout(this);
  outer->setContentsMargins(0, 0, 0, 0);
  scroll_ = new QScrollArea(this);
  scroll_->setWidgetResizable(true);
  scroll_->setFrameShape(QFrame::NoFrame);
  outer->addWidget(scroll_);
  body_ = new QWidget(scroll_);
  layout_ = new QVBoxLayout(body_);
  layout_->setContentsMargins(4, 4, 4, 4);
  scroll_->setWidget(body_);
  rebuild();
}

void MorphPanel::set_scene(const plugins::Scene* scene) {
  scene_ = scene;
  std::vector<int> listed;
  if (scene_) {
    const Model& model = *scene_->model;
    for (const plugins::SceneInstance& instance : scene_->instances) {
      const std::size_t count = model.meshes[static_cast<std::size_t>(instance.mesh)].target_count();
      if (count == 0 || (!listed.empty() && listed[listed.size() - 3] == instance.node)) continue;
      listed.insert(listed.end(), {instance.node, instance.mesh, static_cast<int>(count)});
    }
  }
  // A cut's pieces are new nodes named after their node ("NAME_pieceK"): they keep its weights
  // set by hand, so the pieces stay at the expression they were cut at.
  if (scene_) {
    const Model& model = *scene_->model;
    const std::map<int, std::vector<float>> held = overrides_;
    for (std::size_t n = node_count_; n < model.nodes.size(); ++n)
      for (const auto& [node, weights] : held)
        if (static_cast<std::size_t>(node) < node_count_ &&
            model.nodes[n].name.rfind(plugins::node_label(model, node) + "_piece", 0) == 0)
          overrides_[static_cast<int>(n)] = weights;
  }
  node_count_ = scene_ ? scene_->model->nodes.size() : 0;
  // Weights set by hand stay only where the node still has as many targets.
  for (auto it = overrides_.begin(); it != overrides_.end();) {
    bool kept = false;
    for (std::size_t i = 0; i < listed.size(); i += 3)
      kept = kept || (listed[i] == it->first && static_cast<std::size_t>(listed[i + 2]) == it->second.size());
    it = kept ? std::next(it) : overrides_.erase(it);
  }
  if (listed != listed_ || had_scene_ != (scene_ != nullptr)) {
    listed_ = std::move(listed);
    had_scene_ = scene_ != nullptr;
    rebuild();
  }
  show_pose();
}

void MorphPanel::rebuild() {
  groups_.clear();
  while (QLayoutItem* item = layout_->takeAt(0)) {
    if (item->widget()) delete item->widget();
    delete item;
  }
  if (listed_.empty()) {
    auto* none = new QLabel(scene_ ? "This model has no morph targets." : "No model.", body_);
    none->setObjectName("morph_none");
    layout_->addWidget(none);
  }
  for (std::size_t i = 0; i < listed_.size(); i += 3) {
    Group group;
    group.node = listed_[i];
    layout_->addWidget(make_group(group, group.rows, group.follow));
    groups_.push_back(std::move(group));
  }
  layout_->addStretch(1);
  // The dock asks for room for its groups (a few rows at least; more scroll).
  layout_->activate();
  scroll_->setMinimumHeight(std::min(layout_->minimumSize().height(), kMaxMinimumHeight));
}

QWidget* MorphPanel::make_group(const Group& group, std::vector<Row>& rows, QCheckBox*& follow) {
  const Model& model = *scene_->model;
  const int node = group.node;
  const Mesh& mesh = model.meshes[static_cast<std::size_t>(model.nodes[static_cast<std::size_t>(node)].mesh)];
  QString title = QString::fromStdString(plugins::node_label(model, node));
  if (!mesh.name.empty()) title += QString(" (mesh %1)").arg(QString::fromStdString(mesh.name));
  auto* box = new QGroupBox(title, body_);
  box->setObjectName(QString("morph_node_%1").arg(node));
  auto* grid = new QGridLayout(box);
  follow = new QCheckBox("From animation", box);
  follow->setObjectName(QString("morph_follow_%1").arg(node));
  follow->setChecked(overrides_.count(node) == 0);
  follow->setToolTip("Ticked: the weights play with the animation. Drag a slider to set them by hand.");
  grid->addWidget(follow, 0, 0, 1, 3);
  connect(follow, &QCheckBox::toggled, this, [this, node](bool on) {
    if (updating_) return;
    if (on) {
      follow_animation(node);
      return;
    }
    // Unticked: hold the weights shown now.
    std::vector<float> held = shown_weights(node, 0);
    overrides_[node] = std::move(held);
    emit weights_changed();
  });
  for (std::size_t t = 0; t < mesh.target_count(); ++t) {
    Row row;
    const int target = static_cast<int>(t);
    grid->addWidget(new QLabel(target_label(mesh, t), box), static_cast<int>(t) + 1, 0);
    row.slider = new QSlider(Qt::Horizontal, box);
    row.slider->setObjectName(QString("morph_slider_%1_%2").arg(node).arg(target));
    row.slider->setRange(0, kSteps);
    row.spin = new QDoubleSpinBox(box);
    row.spin->setObjectName(QString("morph_spin_%1_%2").arg(node).arg(target));
    row.spin->setRange(kMin, kMax);
    row.spin->setDecimals(3);
    row.spin->setSingleStep(0.05);
    grid->addWidget(row.slider, static_cast<int>(t) + 1, 1);
    grid->addWidget(row.spin, static_cast<int>(t) + 1, 2);
    connect(row.slider, &QSlider::valueChanged, this, [this, node, target](int value) {
      if (!updating_) set_weight(node, target, static_cast<float>(value) / kSteps);
    });
    connect(row.spin, qOverload<double>(&QDoubleSpinBox::valueChanged), this, [this, node, target](double value) {
      if (!updating_) set_weight(node, target, static_cast<float>(value));
    });
    rows.push_back(row);
  }
  grid->setColumnStretch(1, 1);
  return box;
}

std::vector<float> MorphPanel::shown_weights(int node, std::size_t count) const {
  const auto it = overrides_.find(node);
  std::vector<float> out = it != overrides_.end() ? it->second
                           : scene_ && scene_->posed ? scene_->posed->weights(node)
                                                     : std::vector<float>();
  const Model& model = *scene_->model;
  if (count == 0) count = model.meshes[static_cast<std::size_t>(model.nodes[static_cast<std::size_t>(node)].mesh)].target_count();
  out.resize(count, 0.0f);
  return out;
}

void MorphPanel::show_pose() {
  updating_ = true;
  for (const Group& group : groups_) {
    const std::vector<float> weights = shown_weights(group.node, group.rows.size());
    group.follow->setChecked(overrides_.count(group.node) == 0);
    for (std::size_t t = 0; t < group.rows.size(); ++t) {
      group.rows[t].slider->setValue(slider_position(weights[t]));
      group.rows[t].spin->setValue(static_cast<double>(weights[t]));
    }
  }
  updating_ = false;
}

void MorphPanel::set_weight(int node, int target, float value) {
  const auto group = std::find_if(groups_.begin(), groups_.end(), [&](const Group& g) { return g.node == node; });
  if (group == groups_.end() || target < 0 || static_cast<std::size_t>(target) >= group->rows.size()) return;
  std::vector<float> weights = shown_weights(node, group->rows.size());
  weights[static_cast<std::size_t>(target)] = std::clamp(value, static_cast<float>(kMin), static_cast<float>(kMax));
  overrides_[node] = std::move(weights);
  show_pose();
  emit weights_changed();
}

void MorphPanel::follow_animation(int node) {
  if (overrides_.erase(node) == 0) return;
  show_pose();
  emit weights_changed();
}

}  // namespace deepcut::studio
