// SPDX-License-Identifier: MIT
// Skin weights inspector: pick a joint (list, or click its bone) to see a heat map of its
// weights, or colour every vertex by the joint that moves it most; vertices whose weights do not
// sum to one are flagged.
#include <QButtonGroup>
#include <QCheckBox>
#include <QLabel>
#include <QLinearGradient>
#include <QPainter>
#include <QPixmap>
#include <QPointer>
#include <QRadioButton>
#include <QSignalBlocker>
#include <QTreeWidget>
#include <QTreeWidgetItemIterator>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "deepcut/core/attributes.h"
#include "deepcut/core/errors.h"
#include "deepcut/plugins/colors.h"
#include "deepcut/plugins/inspector_registry.h"

namespace deepcut::plugins {
namespace {

constexpr float kSumTolerance = 1e-3f;

/// The skin weights of one vertex, as (joint node, weight) with repeated joints summed.
using VertexWeights = std::map<int, float>;

// The legend's ramp from weight 0 to 1.
QPixmap weight_ramp_pixmap() {
  QPixmap ramp(220, 14);
  QPainter painter(&ramp);
  QLinearGradient gradient(0, 0, 220, 0);
  const auto stops = weight_ramp();
  for (std::size_t i = 0; i < stops.size(); ++i)
    gradient.setColorAt(static_cast<double>(i) / (stops.size() - 1),
                        QColor::fromRgbF(stops[i].r, stops[i].g, stops[i].b));
  painter.fillRect(ramp.rect(), gradient);
  painter.end();
  return ramp;
}

class WeightsInspector final : public Inspector {
 public:
  enum class Mode { JointWeight, DominantJoint };

  std::string id() const override { return "weights"; }
  std::string title() const override { return "Skin weights"; }

  QWidget* create_panel(QWidget* parent) override;
  void set_scene(const Scene& scene, SceneChange change) override;
  InstanceColors instance_colors(std::size_t instance) const override;
  Overlay overlay() const override;
  std::optional<ColorBar> color_bar() const override;
  std::optional<Focus> focus() const override;
  std::vector<std::string> summary() const override;
  bool pick(const Pick& pick) override;
  void set_option(const std::string& name, const std::string& value) override;

 private:
  VertexWeights weights_of(std::size_t instance, VertexId v) const;
  float weight_of(std::size_t instance, VertexId v, int joint) const;
  void select_joint(int joint);
  void set_mode(Mode mode);
  void refresh_panel();
  void rebuild_joint_tree();
  QString picked_text() const;
  std::string joint_name(int joint) const {
    return scene_ ? node_label(*scene_->model, joint) : std::string();
  }

  const Scene* scene_ = nullptr;
  std::vector<int> joints_;  // joint nodes, skin order
  int joint_ = -1;           // selected joint node
  Mode mode_ = Mode::JointWeight;
  std::vector<std::vector<VertexId>> unnormalised_;  // per instance
  std::size_t influenced_ = 0;                       // vertices with weight > 0 for joint_
  float max_weight_ = 0.0f;
  std::size_t picked_instance_ = Pick::kNoInstance;
  VertexId picked_vertex_;
  bool tree_stale_ = true;  // the joint list changed since the panel last showed it

  QPointer<QTreeWidget> tree_;
  QPointer<QLabel> stats_, flags_, picked_label_, legend_;
  QPointer<QRadioButton> joint_mode_, dominant_mode_;
};

VertexWeights WeightsInspector::weights_of(std::size_t instance, VertexId v) const {
  VertexWeights out;
  const SceneInstance& p = scene_->instances[instance];
  if (p.skin < 0) return out;
  const auto& joints = scene_->model->skins[static_cast<std::size_t>(p.skin)].joints;
  const AttributeSet& va = p.surface->vertex_attrs();
  const std::pair<const char*, const char*> sets[2] = {{attr::kJoints0, attr::kWeights0},
                                                       {attr::kJoints1, attr::kWeights1}};
  for (const auto& [jname, wname] : sets) {
    const auto* j = va.find<glm::u16vec4>(jname);
    const auto* w = va.find<glm::vec4>(wname);
    if (!j || !w) continue;
    for (int k = 0; k < 4; ++k) {
      const float weight = (*w)[v.index][k];
      const std::size_t slot = (*j)[v.index][k];
      if (weight != 0.0f && slot < joints.size()) out[joints[slot]] += weight;
    }
  }
  return out;
}

float WeightsInspector::weight_of(std::size_t instance, VertexId v, int joint) const {
  const VertexWeights w = weights_of(instance, v);
  const auto it = w.find(joint);
  return it == w.end() ? 0.0f : it->second;
}

void WeightsInspector::set_scene(const Scene& scene, SceneChange change) {
  scene_ = &scene;
  if (change == SceneChange::Pose) return;
  joints_ = joint_nodes(*scene.model);
  tree_stale_ = true;
  if (std::find(joints_.begin(), joints_.end(), joint_) == joints_.end()) joint_ = -1;
  picked_instance_ = Pick::kNoInstance;
  unnormalised_.assign(scene.instances.size(), {});
  std::map<int, std::size_t> influence;  // vertices influenced per joint, to choose a default
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const SceneInstance& instance = scene.instances[i];
    if (instance.skin < 0) continue;
    const auto* w0 = instance.surface->vertex_attrs().find<glm::vec4>(attr::kWeights0);
    if (!w0) continue;
    const auto* w1 = instance.surface->vertex_attrs().find<glm::vec4>(attr::kWeights1);
    std::vector<char> used(instance.surface->vertex_count(), 0);
    instance.surface->for_each_face([&](FaceId, const Triangle& t) {
      for (VertexId v : t) used[v.index] = 1;
    });
    for (std::uint32_t v = 0; v < used.size(); ++v) {
      if (!used[v]) continue;
      const glm::vec4& a = (*w0)[v];
      float sum = a.x + a.y + a.z + a.w;
      bool negative = glm::any(glm::lessThan(a, glm::vec4(0.0f)));
      if (w1) {
        const glm::vec4& b = (*w1)[v];
        sum += b.x + b.y + b.z + b.w;
        negative = negative || glm::any(glm::lessThan(b, glm::vec4(0.0f)));
      }
      if (!(std::fabs(sum - 1.0f) <= kSumTolerance) || negative) unnormalised_[i].push_back(VertexId(v));
      for (const auto& [joint, weight] : weights_of(i, VertexId(v)))
        if (weight > 0.0f) ++influence[joint];
    }
  }
  if (joint_ < 0 && !joints_.empty()) {
    // Default: the joint that moves the most vertices, so the first view shows something.
    joint_ = joints_.front();
    std::size_t best = 0;
    for (int j : joints_)
      if (influence[j] > best) best = influence[j], joint_ = j;
  }
  select_joint(joint_);
}

void WeightsInspector::select_joint(int joint) {
  joint_ = joint;
  influenced_ = 0;
  max_weight_ = 0.0f;
  if (scene_ && joint_ >= 0) {
    for (std::size_t i = 0; i < scene_->instances.size(); ++i) {
      const SurfaceMesh& mesh = *scene_->instances[i].surface;
      std::vector<char> used(mesh.vertex_count(), 0);
      mesh.for_each_face([&](FaceId, const Triangle& t) {
        for (VertexId v : t) used[v.index] = 1;
      });
      for (std::uint32_t v = 0; v < used.size(); ++v) {
        if (!used[v]) continue;
        const float w = weight_of(i, VertexId(v), joint_);
        if (w > 0.0f) ++influenced_;
        max_weight_ = std::max(max_weight_, w);
      }
    }
  }
  refresh_panel();
}

void WeightsInspector::set_mode(Mode mode) {
  mode_ = mode;
  refresh_panel();
}

InstanceColors WeightsInspector::instance_colors(std::size_t instance) const {
  InstanceColors out;
  if (!scene_ || instance >= scene_->instances.size()) return out;
  const SceneInstance& p = scene_->instances[instance];
  out.kind = InstanceColors::Kind::PerVertex;
  out.colors.assign(p.surface->vertex_count(), to_rgb8(palette::kUnskinned));
  if (p.skin < 0 || !p.surface->vertex_attrs().contains(attr::kWeights0)) return out;
  std::map<int, std::size_t> joint_index;
  for (std::size_t i = 0; i < joints_.size(); ++i) joint_index[joints_[i]] = i;
  for (std::uint32_t v = 0; v < out.colors.size(); ++v) {
    const VertexWeights w = weights_of(instance, VertexId(v));
    if (mode_ == Mode::JointWeight) {
      const auto it = w.find(joint_);
      out.colors[v] = to_rgb8(weight_color(it == w.end() ? 0.0f : it->second));
    } else if (!w.empty()) {
      const auto best = std::max_element(w.begin(), w.end(),
                                         [](const auto& a, const auto& b) { return a.second < b.second; });
      out.colors[v] = to_rgb8(category_color(joint_index[best->first]));
    }
  }
  return out;
}

Overlay WeightsInspector::overlay() const {
  Overlay overlay;
  if (!scene_) return overlay;
  if (joint_ >= 0) {
    // The chosen joint and its bones, over everything.
    auto origin = [&](int node) { return glm::vec3(scene_->world[static_cast<std::size_t>(node)][3]); };
    OverlayLines bones;
    bones.color = palette::kHighlight;
    bones.width_px = 5.0f;
    bones.on_top = true;
    for (const auto& [parent, child] : skeleton_bones(*scene_->model))
      if (parent == joint_ || child == joint_) {
        bones.endpoints.push_back(origin(parent));
        bones.endpoints.push_back(origin(child));
      }
    OverlayPoints marker;
    marker.positions = {origin(joint_)};
    marker.color = palette::kHighlight;
    marker.size_px = 15.0f;
    marker.on_top = true;
    overlay.lines.push_back(std::move(bones));
    overlay.points.push_back(std::move(marker));
  }
  OverlayPoints flagged;
  flagged.color = palette::kFlagged;
  flagged.size_px = 9.0f;
  flagged.on_top = true;
  for (std::size_t i = 0; i < unnormalised_.size(); ++i)
    for (VertexId v : unnormalised_[i]) flagged.positions.push_back(scene_->instances[i].posed()[v.index]);
  if (!flagged.positions.empty()) overlay.points.push_back(std::move(flagged));
  if (picked_instance_ < scene_->instances.size()) {
    OverlayPoints picked;
    picked.positions = {scene_->instances[picked_instance_].posed()[picked_vertex_.index]};
    picked.color = palette::kPicked;
    picked.size_px = 12.0f;
    picked.on_top = true;
    overlay.points.push_back(std::move(picked));
  }
  return overlay;
}

std::optional<ColorBar> WeightsInspector::color_bar() const {
  if (mode_ != Mode::JointWeight || joint_ < 0) return std::nullopt;
  return ColorBar{"Weight", weight_ramp(), 0.0f, 1.0f};
}

std::optional<Focus> WeightsInspector::focus() const {
  if (!scene_ || joint_ < 0) return std::nullopt;
  const auto origin = [&](int node) { return glm::vec3(scene_->world[static_cast<std::size_t>(node)][3]); };
  const glm::vec3 center = origin(joint_);
  float reach = 0.0f;
  for (const auto& [parent, child] : skeleton_bones(*scene_->model))
    if (parent == joint_ || child == joint_)
      reach = std::max(reach, glm::distance(origin(parent), origin(child)));
  return Focus{center, std::max(1.5f * reach, 0.1f * scene_->size)};
}

std::vector<std::string> WeightsInspector::summary() const {
  std::vector<std::string> lines;
  if (!scene_) return lines;
  std::size_t flagged = 0;
  for (const auto& list : unnormalised_) flagged += list.size();
  if (joints_.empty()) {
    lines.push_back("Skin weights: the model has no skin");
  } else if (mode_ == Mode::JointWeight) {
    std::ostringstream s;
    s << "Skin weights of joint '" << joint_name(joint_) << "': " << influenced_ << " vertices, max "
      << std::fixed;
    s.precision(2);
    s << max_weight_;
    lines.push_back(s.str());
  } else {
    lines.push_back("Dominant joint of each vertex (" + std::to_string(joints_.size()) + " joints)");
  }
  lines.push_back(flagged == 0
                      ? std::string("All weights normalised")
                      : std::to_string(flagged) + " vertices with weights not summing to 1 (magenta)");
  return lines;
}

bool WeightsInspector::pick(const Pick& pick) {
  if (!scene_) return false;
  if (pick.joint_node >= 0) {
    if (std::find(joints_.begin(), joints_.end(), pick.joint_node) == joints_.end()) return false;
    mode_ = Mode::JointWeight;
    select_joint(pick.joint_node);
    return true;
  }
  if (pick.instance >= scene_->instances.size() || !pick.vertex.valid() ||
      pick.vertex.index >= scene_->instances[pick.instance].surface->vertex_count())
    return false;
  picked_instance_ = pick.instance;
  picked_vertex_ = pick.vertex;
  refresh_panel();
  return true;
}

void WeightsInspector::set_option(const std::string& name, const std::string& value) {
  if (name == "joint") {
    if (!scene_)
      throw Error(ErrorCode::InvalidArgument, "weights: no model to choose joint '" + value + "' from");
    for (int j : joints_)
      if (node_label(*scene_->model, j) == value) {
        mode_ = Mode::JointWeight;
        select_joint(j);
        return;
      }
    std::string known;
    for (std::size_t i = 0; i < joints_.size() && i < 8; ++i)
      known += (i ? ", " : "") + joint_name(joints_[i]);
    if (joints_.size() > 8) known += ", ...";
    throw Error(ErrorCode::InvalidArgument,
                "weights: unknown joint '" + value + "'" +
                    (joints_.empty() ? " (the model has no skin)" : " (joints: " + known + ")"));
  }
  if (name == "mode") {
    if (value == "joint") return set_mode(Mode::JointWeight);
    if (value == "dominant") return set_mode(Mode::DominantJoint);
    throw Error(ErrorCode::InvalidArgument,
                "weights: mode must be 'joint' or 'dominant', not '" + value + "'");
  }
  Inspector::set_option(name, value);
}

QPixmap swatch(const glm::vec3& c) {
  QPixmap pixmap(12, 12);
  pixmap.fill(QColor::fromRgbF(c.r, c.g, c.b));
  return pixmap;
}

QWidget* WeightsInspector::create_panel(QWidget* parent) {
  auto* panel = new QWidget(parent);
  auto* layout = new QVBoxLayout(panel);
  layout->setContentsMargins(6, 6, 6, 6);
  joint_mode_ = new QRadioButton("Weight of the selected joint", panel);
  dominant_mode_ = new QRadioButton("Dominant joint per vertex", panel);
  auto* group = new QButtonGroup(panel);
  group->addButton(joint_mode_);
  group->addButton(dominant_mode_);
  layout->addWidget(joint_mode_);
  layout->addWidget(dominant_mode_);
  legend_ = new QLabel(panel);
  layout->addWidget(legend_);
  tree_ = new QTreeWidget(panel);
  tree_->setHeaderLabels({"Joint (colour: dominant-joint mode)"});
  tree_->setRootIsDecorated(true);
  tree_->setUniformRowHeights(true);
  tree_->setObjectName("weights_joint_tree");
  layout->addWidget(tree_, 1);
  stats_ = new QLabel(panel);
  stats_->setWordWrap(true);
  flags_ = new QLabel(panel);
  flags_->setWordWrap(true);
  picked_label_ = new QLabel(panel);
  picked_label_->setWordWrap(true);
  picked_label_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  layout->addWidget(stats_);
  layout->addWidget(flags_);
  layout->addWidget(picked_label_);

  QObject::connect(joint_mode_, &QRadioButton::toggled, panel, [this](bool on) {
    if (on && mode_ != Mode::JointWeight) {
      set_mode(Mode::JointWeight);
      notify_changed();
    }
  });
  QObject::connect(dominant_mode_, &QRadioButton::toggled, panel, [this](bool on) {
    if (on && mode_ != Mode::DominantJoint) {
      set_mode(Mode::DominantJoint);
      notify_changed();
    }
  });
  QObject::connect(tree_, &QTreeWidget::currentItemChanged, panel,
                   [this](QTreeWidgetItem* item, QTreeWidgetItem*) {
                     if (!item) return;
                     const int joint = item->data(0, Qt::UserRole).toInt();
                     if (joint == joint_ && mode_ == Mode::JointWeight) return;
                     mode_ = Mode::JointWeight;
                     select_joint(joint);
                     notify_changed();
                   });
  refresh_panel();
  return panel;
}

void WeightsInspector::refresh_panel() {
  if (!tree_) return;
  const QSignalBlocker block_tree(tree_.data());
  const QSignalBlocker block_a(joint_mode_.data());
  const QSignalBlocker block_b(dominant_mode_.data());
  joint_mode_->setChecked(mode_ == Mode::JointWeight);
  dominant_mode_->setChecked(mode_ == Mode::DominantJoint);
  if (tree_stale_) rebuild_joint_tree();
  for (QTreeWidgetItemIterator it(tree_); *it; ++it)
    if ((*it)->data(0, Qt::UserRole).toInt() == joint_) {
      tree_->setCurrentItem(*it);
      tree_->scrollToItem(*it);
    }
  // Legend: the ramp, or a note that the joint colours are the swatches in the list.
  if (mode_ == Mode::JointWeight) {
    legend_->setPixmap(weight_ramp_pixmap());
    legend_->setToolTip("weight 0 (blue) to 1 (red)");
  } else {
    legend_->setText("Colour = joint with the largest weight (swatches below)");
  }
  const auto lines = summary();
  stats_->setText(lines.empty() ? QString() : QString::fromStdString(lines[0]));
  flags_->setText(lines.size() > 1 ? QString::fromStdString(lines[1]) : QString());
  flags_->setStyleSheet(lines.size() > 1 && lines[1].rfind("All", 0) != 0 ? "color: #ff40d0;" : "");
  picked_label_->setText(picked_text());
}

// The joint hierarchy, rebuilt when the joints changed.
void WeightsInspector::rebuild_joint_tree() {
  tree_stale_ = false;
  tree_->clear();
  std::map<int, QTreeWidgetItem*> items;
  std::map<int, int> parent_of;
  if (scene_)
    for (const auto& [parent, child] : skeleton_bones(*scene_->model)) parent_of[child] = parent;
  // Skin order lists parents before children in practice; attach children whose parent comes
  // later in a second pass.
  for (std::size_t i = 0; i < joints_.size(); ++i) {
    auto* item =
        new QTreeWidgetItem({QString::fromStdString(joint_name(joints_[i])), QString::number(joints_[i])});
    item->setData(0, Qt::UserRole, joints_[i]);
    item->setIcon(0, QIcon(swatch(category_color(i))));
    items[joints_[i]] = item;
  }
  for (int j : joints_) {
    const auto p = parent_of.find(j);
    if (p != parent_of.end() && items.count(p->second))
      items[p->second]->addChild(items[j]);
    else
      tree_->addTopLevelItem(items[j]);
  }
  tree_->expandAll();
}

// The picked vertex's weights, or how to pick one.
QString WeightsInspector::picked_text() const {
  if (!scene_ || picked_instance_ >= scene_->instances.size())
    return "Click a bone to choose its joint; click the surface to read a vertex's weights.";
  QString text = QString("Vertex %1:").arg(picked_vertex_.index);
  const VertexWeights w = weights_of(picked_instance_, picked_vertex_);
  float sum = 0.0f;
  for (const auto& [joint, weight] : w) {
    text += QString(" %1 %2").arg(QString::fromStdString(joint_name(joint))).arg(weight, 0, 'f', 3);
    sum += weight;
  }
  text += QString(" (sum %1)").arg(sum, 0, 'f', 3);
  return text;
}

}  // namespace

void register_weights(InspectorRegistry& registry) {
  registry.add({"weights", "Skin weights", [] { return std::make_unique<WeightsInspector>(); }});
}

}  // namespace deepcut::plugins
