// SPDX-License-Identifier: MIT
// The Plane tool: a cutting plane placed through the model's centre, its contour on the posed
// surface drawn live, applied with deepcut::apply_operation (CutOperation).
#include <QCheckBox>
#include <QComboBox>
#include <QFormLayout>
#include <QSignalBlocker>
#include <QWidget>
#include <glm/geometric.hpp>
#include <memory>
#include <optional>

#include "deepcut/core/errors.h"
#include "deepcut/plugins/tool.h"
#include "deepcut/plugins/tool_panel.h"

namespace deepcut::plugins {
namespace {

class CutTool final : public Tool {
 public:
  std::string id() const override { return "cut"; }
  std::string title() const override { return "Plane"; }

  QWidget* create_panel(QWidget* parent) override {
    auto* panel = new QWidget(parent);
    auto* form = new QFormLayout(panel);
    point_.emplace(form, "Point", "cut.point", [this] {
      op_.plane.point = point_->value();
      notify_changed();
    });
    normal_.emplace(form, "Normal", "cut.normal", [this] {
      op_.plane.normal = normal_->value();
      notify_changed();
    });
    keep_ = new QComboBox(panel);
    keep_->setObjectName("cut.keep");
    keep_->addItem("Both sides", static_cast<int>(CutKeep::Both));
    keep_->addItem("Positive side", static_cast<int>(CutKeep::Positive));
    keep_->addItem("Negative side", static_cast<int>(CutKeep::Negative));
    form->addRow("Keep", keep_);
    QObject::connect(keep_, QOverload<int>::of(&QComboBox::currentIndexChanged), panel, [this](int index) {
      op_.options.keep = static_cast<CutKeep>(keep_->itemData(index).toInt());
      notify_changed();
    });
    cap_ = new QCheckBox("Close rims with caps", panel);
    cap_->setObjectName("cut.cap");
    form->addRow(cap_);
    QObject::connect(cap_, &QCheckBox::toggled, panel, [this](bool on) {
      op_.options.cap = on;
      notify_changed();
    });
    components_ = new QCheckBox("Split into connected components", panel);
    components_->setObjectName("cut.components");
    form->addRow(components_);
    QObject::connect(components_, &QCheckBox::toggled, panel, [this](bool on) {
      op_.options.split_components = on;
      notify_changed();
    });
    show();
    return panel;
  }

  void place(const Scene& scene, const glm::vec3& view_direction) override {
    (void)view_direction;
    const BoundingBox box = scene_bounds(scene);
    if (box.empty()) return;
    op_.plane.point = 0.5f * (box.min + box.max);
    op_.plane.normal = glm::vec3(0.0f, 1.0f, 0.0f);
    show();
    notify_changed();
  }

  OperationParams parameters() const override { return op_; }

  void set_parameters(const OperationParams& params) override {
    const auto* cut = std::get_if<CutOperation>(&params);
    if (!cut) throw Error(ErrorCode::InvalidArgument, "the Plane tool takes cut parameters");
    op_ = *cut;
    show();
    notify_changed();
  }

  Overlay preview(const Scene& scene) const override {
    Overlay overlay;
    OverlayLines contour;
    contour.endpoints = plane_contour(scene, op_.plane);
    contour.color = {1.0f, 0.85f, 0.0f};
    contour.width_px = 3.0f;
    contour.on_top = true;
    overlay.lines.push_back(std::move(contour));
    // The plane itself: a square outline through the point and the normal as a short stroke.
    const float len = glm::length(op_.plane.normal);
    if (len > 0.0f) {
      const glm::vec3 n = op_.plane.normal / len;
      const glm::vec3 helper = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
      const glm::vec3 u = glm::normalize(glm::cross(n, helper)), v = glm::cross(n, u);
      const float r = 0.6f * scene.size;
      const glm::vec3 c = op_.plane.point;
      const glm::vec3 corners[4] = {c + r * (u + v), c + r * (-u + v), c + r * (-u - v), c + r * (u - v)};
      OverlayLines frame;
      for (int k = 0; k < 4; ++k) {
        frame.endpoints.push_back(corners[k]);
        frame.endpoints.push_back(corners[(k + 1) % 4]);
      }
      frame.endpoints.push_back(c);
      frame.endpoints.push_back(c + 0.2f * scene.size * n);
      frame.color = {0.3f, 0.7f, 1.0f};
      overlay.lines.push_back(std::move(frame));
      OverlayPoints handle;
      handle.positions = {c};
      handle.color = {0.3f, 0.7f, 1.0f};
      handle.size_px = 10.0f;
      handle.on_top = true;
      overlay.points.push_back(std::move(handle));
    }
    return overlay;
  }

 private:
  void show() {
    if (!point_) return;
    point_->set(op_.plane.point);
    normal_->set(op_.plane.normal);
    const QSignalBlocker b1(keep_), b2(cap_), b3(components_);
    keep_->setCurrentIndex(keep_->findData(static_cast<int>(op_.options.keep)));
    cap_->setChecked(op_.options.cap);
    components_->setChecked(op_.options.split_components);
  }

  CutOperation op_;
  std::optional<Vec3Entry> point_, normal_;
  QComboBox* keep_ = nullptr;
  QCheckBox* cap_ = nullptr;
  QCheckBox* components_ = nullptr;
};

}  // namespace

void register_cut(ToolRegistry& registry) {
  registry.add({"cut", "Plane", [] { return std::make_unique<CutTool>(); }});
}

}  // namespace deepcut::plugins
