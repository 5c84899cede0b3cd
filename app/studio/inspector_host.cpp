// SPDX-License-Identifier: MIT
#include "inspector_host.h"

#include <QAction>
#include <QActionGroup>
#include <QComboBox>
#include <QLabel>
#include <QMenu>
#include <QStackedWidget>
#include <QVBoxLayout>

#include "deepcut/core/errors.h"
#include "deepcut/plugins/inspector_registry.h"
#include "scene_view.h"

namespace deepcut::studio {

InspectorHost::InspectorHost(SceneView* view, QObject* parent) : QObject(parent), view_(view) {
  for (const plugins::InspectorInfo& info : plugins::builtin_inspectors().list()) {
    inspectors_.push_back(info.create());
    inspectors_.back()->set_changed_callback([this] { emit changed(); });
  }
}

InspectorHost::~InspectorHost() = default;

void InspectorHost::set_background_runner(const plugins::Inspector::Runner& runner) {
  for (const auto& inspector : inspectors_) inspector->set_background_runner(runner);
}

QWidget* InspectorHost::create_panel(QWidget* parent) {
  auto* panel = new QWidget(parent);
  auto* layout = new QVBoxLayout(panel);
  layout->setContentsMargins(4, 4, 4, 4);
  combo_ = new QComboBox(panel);
  combo_->setObjectName("inspector_combo");
  combo_->addItem("Shaded (materials)", QString());
  stack_ = new QStackedWidget(panel);
  auto* none = new QLabel(
      "The model with its own materials and textures, posed at the time line's time.\n\n"
      "Choose an inspector above (or Inspect menu) to look at skin weights or adjacency.",
      stack_);
  none->setWordWrap(true);
  none->setAlignment(Qt::AlignTop | Qt::AlignLeft);
  none->setMargin(6);
  stack_->addWidget(none);
  for (const auto& inspector : inspectors_) {
    combo_->addItem(QString::fromStdString(inspector->title()), QString::fromStdString(inspector->id()));
    stack_->addWidget(inspector->create_panel(stack_));
  }
  layout->addWidget(combo_);
  layout->addWidget(stack_, 1);
  connect(combo_, QOverload<int>::of(&QComboBox::activated), this,
          [this](int index) { emit chosen(combo_->itemData(index).toString()); });
  return panel;
}

void InspectorHost::add_menu_actions(QMenu* menu) {
  group_ = new QActionGroup(this);
  auto add = [&](const QString& text, const std::string& id, int index) {
    QAction* action = menu->addAction(text);
    action->setCheckable(true);
    action->setChecked(id.empty());
    action->setShortcut(QKeySequence(QString("Ctrl+%1").arg(index)));
    action->setData(QString::fromStdString(id));
    group_->addAction(action);
    connect(action, &QAction::triggered, this, [this, id] { emit chosen(QString::fromStdString(id)); });
  };
  add("&Shaded (materials)", "", 0);
  for (std::size_t i = 0; i < inspectors_.size(); ++i)
    add(QString::fromStdString(inspectors_[i]->title()), inspectors_[i]->id(), static_cast<int>(i) + 1);
}

void InspectorHost::set_inspector(const std::string& id) {
  int index = -1;
  if (!id.empty() && id != "none") {
    for (std::size_t i = 0; i < inspectors_.size(); ++i)
      if (inspectors_[i]->id() == id) index = static_cast<int>(i);
    if (index < 0)
      throw Error(ErrorCode::InvalidArgument,
                  "unknown inspector '" + id + "' (known: " + plugins::builtin_inspectors().ids() + ")");
  }
  active_ = index;
  combo_->setCurrentIndex(index + 1);
  stack_->setCurrentIndex(index + 1);
  for (QAction* action : group_->actions())
    if (action->data().toString().toStdString() == (index < 0 ? std::string() : id)) action->setChecked(true);
}

void InspectorHost::set_option(const std::string& name, const std::string& value) {
  plugins::Inspector* active = inspector();
  if (!active) throw Error(ErrorCode::InvalidArgument, "option '" + name + "' needs an inspector (--inspect)");
  sync();
  active->set_option(name, value);
}

plugins::Inspector* InspectorHost::inspector() const {
  return active_ >= 0 ? inspectors_[static_cast<std::size_t>(active_)].get() : nullptr;
}

std::string InspectorHost::inspector_id() const { return inspector() ? inspector()->id() : std::string(); }

void InspectorHost::mark_stale(plugins::SceneChange change) {
  stale_.resize(inspectors_.size(), Stale::None);
  for (Stale& s : stale_)
    if (change == plugins::SceneChange::Model)
      s = Stale::Model;
    else if (s == Stale::None)
      s = Stale::Pose;
}

void InspectorHost::sync() {
  if (active_ < 0 || !scene_) return;
  stale_.resize(inspectors_.size(), Stale::Model);
  Stale& s = stale_[static_cast<std::size_t>(active_)];
  if (s != Stale::None)
    inspectors_[static_cast<std::size_t>(active_)]->set_scene(
        *scene_, s == Stale::Model ? plugins::SceneChange::Model : plugins::SceneChange::Pose);
  s = Stale::None;
}

void InspectorHost::draw_colors() {
  if (!scene_) return;
  sync();
  plugins::Inspector* active = inspector();
  for (std::size_t i = 0; i < scene_->instances.size(); ++i)
    view_->set_instance_colors(i, active ? active->instance_colors(i) : plugins::InstanceColors{});
  view_->set_color_bar(active ? active->color_bar() : std::nullopt);
}

bool InspectorHost::pick(const plugins::Pick& pick, bool& changed) {
  changed = false;
  plugins::Inspector* active = inspector();
  if (!active) return false;
  sync();
  changed = active->pick(pick);
  return true;
}

}  // namespace deepcut::studio
