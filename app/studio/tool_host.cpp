// SPDX-License-Identifier: MIT
#include "tool_host.h"

#include <QAction>
#include <QActionGroup>
#include <QLabel>
#include <QMenu>
#include <QPushButton>
#include <QStackedWidget>
#include <QStyle>
#include <QTimer>
#include <QVBoxLayout>
#include <algorithm>

#include "deepcut/core/errors.h"
#include "deepcut/plugins/tool_registry.h"
#include "scene_view.h"

namespace deepcut::studio {

ToolHost::ToolHost(SceneView* view, QObject* parent) : QObject(parent), view_(view) {
  timer_ = new QTimer(this);
  timer_->setInterval(16);
  connect(timer_, &QTimer::timeout, this, &ToolHost::step);
  for (const plugins::ToolInfo& info : plugins::builtin_tools().list()) {
    if (!info.create) continue;  // a command-line-only entry
    tools_.push_back(info.create());
    tools_.back()->set_changed_callback([this] { refresh_preview(); });
  }
}

ToolHost::~ToolHost() = default;

QWidget* ToolHost::create_panel(QWidget* parent) {
  auto* panel = new QWidget(parent);
  auto* layout = new QVBoxLayout(panel);
  layout->setContentsMargins(4, 4, 4, 4);
  banner_ = new QLabel(panel);
  banner_->setObjectName("edit_banner");
  banner_->setWordWrap(true);
  banner_->setStyleSheet("QLabel { background: #5a4a1e; color: #ffe9a8; padding: 4px; }");
  banner_->hide();
  layout->addWidget(banner_);
  stack_ = new QStackedWidget(panel);
  auto* no_tool = new QLabel(
      "Choose Plane, Scalpel or Drill on the Tools bar: the tool places itself on the model and its "
      "contour, tear path or rims are drawn live. Edit the numbers here, then Apply (Enter). "
      "With Poke, drag on the model to pull it as a soft body.",
      stack_);
  no_tool->setWordWrap(true);
  no_tool->setAlignment(Qt::AlignTop | Qt::AlignLeft);
  no_tool->setMargin(6);
  stack_->addWidget(no_tool);
  for (const auto& tool : tools_) stack_->addWidget(tool->create_panel(stack_));
  apply_button_ = new QPushButton("Apply (Enter)", panel);
  apply_button_->setObjectName("apply_button");
  apply_button_->setEnabled(false);
  connect(apply_button_, &QPushButton::clicked, this, &ToolHost::apply_requested);
  layout->addWidget(stack_, 1);
  layout->addWidget(apply_button_);
  return panel;
}

void ToolHost::add_menu_actions(QMenu* menu) {
  group_ = new QActionGroup(this);
  group_->setExclusionPolicy(QActionGroup::ExclusionPolicy::ExclusiveOptional);
  for (const auto& tool : tools_) {
    QAction* action = menu->addAction(QString::fromStdString(tool->title()));
    action->setObjectName(QString::fromStdString("tool_" + tool->id()));
    const plugins::ToolInfo* info = plugins::builtin_tools().find(tool->id());
    const std::string shortcut = info ? info->shortcut : std::string();
    if (!shortcut.empty()) action->setShortcut(QKeySequence(QString::fromStdString(shortcut)));
    action->setCheckable(true);
    action->setData(QString::fromStdString(tool->id()));
    group_->addAction(action);
    connect(action, &QAction::triggered, this,
            [this, action, id = tool->id()](bool on) { set_tool(on || action->isChecked() ? id : std::string()); });
  }
  menu->addSeparator();
  apply_action_ = menu->addAction(menu->style()->standardIcon(QStyle::SP_DialogApplyButton), "&Apply tool", this,
                                  &ToolHost::apply_requested);
  apply_action_->setObjectName("apply_tool");
  apply_action_->setShortcuts({QKeySequence(Qt::Key_Return), QKeySequence(Qt::Key_Enter)});
  apply_action_->setEnabled(false);
}

QList<QAction*> ToolHost::actions() const { return group_->actions() << apply_action_; }

void ToolHost::set_tool(const std::string& id) {
  int index = -1;
  if (!id.empty() && id != "none") {
    for (std::size_t i = 0; i < tools_.size(); ++i)
      if (tools_[i]->id() == id) index = static_cast<int>(i);
    if (index < 0)
      throw Error(ErrorCode::InvalidArgument,
                  "unknown tool '" + id + "' (known: " + plugins::builtin_tools().ids() + ")");
  }
  if (plugins::Tool* previous = tool(); previous && scene_) previous->release(*scene_);
  active_ = index;
  timer_->stop();
  show_displacement();  // back to the posed model
  stack_->setCurrentIndex(index + 1);
  for (QAction* action : group_->actions())
    action->setChecked(index >= 0 && action->data().toString().toStdString() == id);
  const bool operation = index >= 0 && tools_[static_cast<std::size_t>(index)]->makes_operation();
  apply_button_->setEnabled(operation);
  apply_action_->setEnabled(operation);
  plugins::Tool* chosen = tool();
  if (chosen && scene_) chosen->place(*scene_, placement());
  view_->set_tool_widget(chosen && scene_ ? chosen->widget() : nullptr);
  refresh_preview();
  view_->render();
}

void ToolHost::place_on_new_scene() {
  if (plugins::Tool* active = tool(); active && scene_) {
    active->place(*scene_, placement());
    view_->set_tool_widget(active->widget());
  }
  refresh_preview();
}

plugins::ToolPlacement ToolHost::placement() {
  plugins::ToolPlacement placement;
  placement.view_direction = view_->view_direction();
  placement.view_up = view_->view_up();
  if (const std::optional<QPoint> cursor = view_->cursor_position())
    placement.point = view_->surface_point_at(*cursor);
  if (!placement.point) placement.point = last_surface_click_;
  return placement;
}

plugins::Tool* ToolHost::tool() const {
  return active_ >= 0 ? tools_[static_cast<std::size_t>(active_)].get() : nullptr;
}

std::string ToolHost::tool_id() const { return tool() ? tool()->id() : std::string(); }

void ToolHost::refresh_preview() {
  update_preview();
  view_->render();
}

void ToolHost::update_preview() {
  plugins::Tool* active = tool();
  view_->set_overlay(SceneView::Layer::Tool, active && scene_ ? active->preview(*scene_) : Overlay{});
}

void ToolHost::set_banner(const QString& text, const QString& apply_text) {
  banner_->setVisible(!text.isEmpty());
  if (!text.isEmpty()) banner_->setText(text);
  apply_button_->setText(apply_text);
}

void ToolHost::note_pick(const plugins::Pick& pick) {
  if (scene_ && pick.joint_node < 0 && pick.instance < scene_->instances.size())
    last_surface_click_ = pick.position;
}

bool ToolHost::on_pointer(const PointerEvent& event) {
  plugins::Tool* active = tool();
  if (!active || !scene_) return false;
  plugins::ToolPointer pointer;
  pointer.ray_origin = event.ray_origin;
  pointer.ray_direction = event.ray_direction;
  pointer.view_direction = view_->view_direction();
  switch (event.phase) {
    case PointerEvent::Phase::Press:
      if (!event.pick || !active->press(*scene_, *event.pick, pointer)) return false;
      break;
    case PointerEvent::Phase::Move:
      active->move(*scene_, pointer);
      break;
    case PointerEvent::Phase::Release:
      active->release(*scene_);
      break;
  }
  if (!timer_->isActive()) {
    clock_.start();
    timer_->start();
  }
  step();
  return true;
}

void ToolHost::step() {
  plugins::Tool* active = tool();
  if (!active || !scene_) {
    timer_->stop();
    return;
  }
  // Real time since the last step, capped so a stalled event loop does not jump.
  const float dt = std::min(0.05f, static_cast<float>(clock_.restart()) / 1000.0f);
  const bool moving = active->step(*scene_, dt);
  show_displacement();
  if (!moving) timer_->stop();
  view_->render();
}

void ToolHost::show_displacement() {
  if (!scene_) return;
  plugins::Tool* active = tool();
  std::vector<glm::vec3> positions;
  bool displaced = false;
  for (std::size_t i = 0; i < scene_->instances.size(); ++i)
    if (active && active->displaced_positions(*scene_, i, positions)) {
      view_->set_instance_positions(i, positions);
      displaced = true;
    }
  // Settled (or another tool): draw the posed model again, once.
  if (!displaced && displaced_)
    for (std::size_t i = 0; i < scene_->instances.size(); ++i)
      view_->set_instance_positions(i, scene_->instances[i].posed());
  displaced_ = displaced;
}

void ToolHost::lend_grids(const std::shared_ptr<const Model>& model, const PosedModel* posed) {
  if (!scene_) return;
  for (plugins::SceneInstance& instance : scene_->instances) instance.grid = nullptr;
  const PoseKey key(scene_->animation, scene_->time, scene_->weights);
  if (!posed || scene_->model != model || !posed->matches(key)) return;
  if (same_model_ != model.get() || !(same_key_ == key)) {
    same_positions_.clear();
    same_model_ = model.get();
    same_key_ = key;
  }
  for (plugins::SceneInstance& instance : scene_->instances) {
    const PosedMesh* mesh = posed->find(instance.node, instance.primitive);
    // The grid is filed at the posed model's positions: lend it only where they are the
    // scene's, bit for bit (both pose with the same skinning; this guards the assumption).
    if (!mesh || mesh->mesh != instance.mesh || mesh->posed.size() != instance.posed().size()) continue;
    const std::pair<const glm::vec3*, const glm::vec3*> arrays(mesh->posed.data(), instance.posed().data());
    auto& same = same_positions_[{instance.node, instance.primitive}];
    if (same != arrays) {
      if (!std::equal(mesh->posed.begin(), mesh->posed.end(), instance.posed().begin())) continue;
      same = arrays;
    }
    instance.grid = &mesh->grid;
  }
}

}  // namespace deepcut::studio
