// SPDX-License-Identifier: MIT
// The Drill tool: a finite cylinder from axis end A to B with a radius, placed along the view
// direction through the model's centre. The rims (cylinder against the posed triangles) are
// drawn live; applied with deepcut::apply_operation (DrillOperation).
#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QSignalBlocker>
#include <QSpinBox>
#include <QWidget>
#include <cmath>
#include <glm/geometric.hpp>
#include <memory>
#include <optional>

#include "deepcut/core/errors.h"
#include "deepcut/plugins/tool.h"
#include "deepcut/plugins/tool_panel.h"

namespace deepcut::plugins {
namespace {

constexpr int kPreviewSides = 48;
constexpr float kPi = 3.14159265358979f;

class DrillTool final : public Tool {
 public:
  std::string id() const override { return "drill"; }
  std::string title() const override { return "Drill"; }

  QWidget* create_panel(QWidget* parent) override {
    auto* panel = new QWidget(parent);
    auto* form = new QFormLayout(panel);
    a_.emplace(form, "Axis end A", "drill.a", [this] {
      op_.cylinder.a = a_->value();
      notify_changed();
    });
    b_.emplace(form, "Axis end B", "drill.b", [this] {
      op_.cylinder.b = b_->value();
      notify_changed();
    });
    radius_ = make_number(panel, "drill.radius", 0.0, 1e6);
    form->addRow("Radius", radius_);
    QObject::connect(radius_, QOverload<double>::of(&QDoubleSpinBox::valueChanged), panel, [this](double r) {
      op_.cylinder.radius = static_cast<float>(r);
      notify_changed();
    });
    rim_edges_ = new QSpinBox(panel);
    rim_edges_->setObjectName("drill.min_rim_edges");
    rim_edges_->setRange(3, 4096);
    rim_edges_->setKeyboardTracking(false);
    form->addRow("Min rim edges", rim_edges_);
    QObject::connect(rim_edges_, QOverload<int>::of(&QSpinBox::valueChanged), panel, [this](int n) {
      op_.options.min_rim_edges = n;
      notify_changed();
    });
    wall_ = new QCheckBox("Line the hole with a wall", panel);
    wall_->setObjectName("drill.wall");
    form->addRow(wall_);
    QObject::connect(wall_, &QCheckBox::toggled, panel, [this](bool on) {
      op_.options.wall = on;
      notify_changed();
    });
    show();
    return panel;
  }

  void place(const Scene& scene, const glm::vec3& view_direction) override {
    const BoundingBox box = scene_bounds(scene);
    if (box.empty()) return;
    const glm::vec3 c = 0.5f * (box.min + box.max);
    const float reach = 0.6f * box.diagonal();
    op_.cylinder.a = c - reach * view_direction;
    op_.cylinder.b = c + reach * view_direction;
    op_.cylinder.radius = 0.03f * box.diagonal();
    show();
    notify_changed();
  }

  OperationParams parameters() const override { return op_; }

  void set_parameters(const OperationParams& params) override {
    const auto* drill = std::get_if<DrillOperation>(&params);
    if (!drill) throw Error(ErrorCode::InvalidArgument, "the Drill tool takes drill parameters");
    op_ = *drill;
    show();
    notify_changed();
  }

  Overlay preview(const Scene& scene) const override {
    Overlay overlay;
    const glm::vec3 a = op_.cylinder.a, b = op_.cylinder.b;
    const float r = op_.cylinder.radius;
    OverlayLines axis;
    axis.endpoints = {a, b};
    axis.color = {0.3f, 0.7f, 1.0f};
    OverlayPoints ends;
    ends.positions = {a, b};
    ends.color = {0.3f, 0.7f, 1.0f};
    ends.size_px = 10.0f;
    ends.on_top = true;
    const float length = glm::length(b - a);
    if (length > 0.0f && r > 0.0f) {
      const glm::vec3 w = (b - a) / length;
      const glm::vec3 helper = std::abs(w.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
      const glm::vec3 u = glm::normalize(glm::cross(w, helper)), v = glm::cross(w, u);
      auto ring = [&](int k) {
        const float t = 2.0f * kPi * static_cast<float>(k) / kPreviewSides;
        return r * (std::cos(t) * u + std::sin(t) * v);
      };
      // The rim: the cylinder's side (as a prism of thin triangles) against the posed surface.
      OverlayLines rim, outline;
      for (int k = 0; k < kPreviewSides; ++k) {
        const glm::vec3 p = ring(k), q = ring(k + 1);
        for (const std::array<glm::vec3, 3>& tri :
             {std::array<glm::vec3, 3>{a + p, b + p, b + q}, std::array<glm::vec3, 3>{a + p, b + q, a + q}}) {
          const std::vector<glm::vec3> part = triangle_contour(scene, tri);
          rim.endpoints.insert(rim.endpoints.end(), part.begin(), part.end());
        }
        for (const glm::vec3& end : {a, b}) {
          outline.endpoints.push_back(end + p);
          outline.endpoints.push_back(end + q);
        }
      }
      rim.color = {0.2f, 1.0f, 0.4f};
      rim.width_px = 3.0f;
      rim.on_top = true;
      outline.color = {0.3f, 0.7f, 1.0f};
      overlay.lines.push_back(std::move(rim));
      overlay.lines.push_back(std::move(outline));
      OverlayPoints radius_handle;
      radius_handle.positions = {a + ring(0)};
      radius_handle.color = {1.0f, 0.8f, 0.2f};
      radius_handle.size_px = 9.0f;
      radius_handle.on_top = true;
      overlay.points.push_back(std::move(radius_handle));
    }
    overlay.lines.push_back(std::move(axis));
    overlay.points.push_back(std::move(ends));
    return overlay;
  }

 private:
  void show() {
    if (!a_) return;
    a_->set(op_.cylinder.a);
    b_->set(op_.cylinder.b);
    const QSignalBlocker b1(radius_), b2(rim_edges_), b3(wall_);
    radius_->setValue(static_cast<double>(op_.cylinder.radius));
    rim_edges_->setValue(op_.options.min_rim_edges);
    wall_->setChecked(op_.options.wall);
  }

  DrillOperation op_;
  std::optional<Vec3Entry> a_, b_;
  QDoubleSpinBox* radius_ = nullptr;
  QSpinBox* rim_edges_ = nullptr;
  QCheckBox* wall_ = nullptr;
};

}  // namespace

void register_drill(ToolRegistry& registry) {
  registry.add({"drill", "Drill", [] { return std::make_unique<DrillTool>(); }});
}

}  // namespace deepcut::plugins
