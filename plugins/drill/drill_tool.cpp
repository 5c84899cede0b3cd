// SPDX-License-Identifier: MIT
// The Drill tool: a finite cylinder from axis end A to B with a radius (DrillWidget: drag the
// ends, the radius handle or the whole cylinder), placed along the view direction through the
// picked point or the model's centre, mirrored with the numeric panel. The rims (cylinder
// against the posed triangles) are drawn live; applied with deepcut::apply_operation
// (DrillOperation).
#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QSignalBlocker>
#include <QSpinBox>
#include <QWidget>
#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <memory>
#include <optional>

#include "deepcut/plugins/widget_tool.h"
#include "deepcut/widgets/drill_widget.h"

namespace deepcut::plugins {
namespace {

constexpr int kPreviewSides = 48;
constexpr float kPi = 3.14159265358979f;

class DrillTool final : public WidgetTool<DrillOperation, DrillWidget> {
 public:
  DrillTool() { write_widget(); }

  std::string id() const override { return "drill"; }
  std::string title() const override { return "Drill"; }

  QWidget* create_panel(QWidget* parent) override {
    auto* panel = new QWidget(parent);
    auto* form = new QFormLayout(panel);
    add_vec3_row(a_, form, "Axis end A", "drill.a", op_.cylinder.a);
    add_vec3_row(b_, form, "Axis end B", "drill.b", op_.cylinder.b);
    radius_ = make_number(panel, "drill.radius", 0.0, 1e6);
    form->addRow("Radius", radius_);
    QObject::connect(radius_, QOverload<double>::of(&QDoubleSpinBox::valueChanged), panel, [this](double r) {
      op_.cylinder.radius = static_cast<float>(r);
      write_widget();
      notify_changed();
    });
    rim_edges_ = new QSpinBox(panel);
    rim_edges_->setObjectName("drill.min_rim_edges");
    rim_edges_->setRange(DrillOptions::kMinRimEdgesMin, DrillOptions::kMinRimEdgesMax);
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
    show_panel();
    return panel;
  }

  /// Along the view direction through the surface point (else the box's centre): A in front
  /// of the model, B beyond its far side, so the hole goes through every layer behind the point.
  void place(const Scene& scene, const ToolPlacement& placement) override {
    const BoundingBox box = scene_bounds(scene);
    if (box.empty()) return;
    const glm::vec3 d = placement.view_direction;
    const glm::vec3 through = placement.point ? *placement.point : 0.5f * (box.min + box.max);
    // How far the box reaches in front of and behind `through` along d.
    float front = 0.0f, back = 0.0f;
    for (int k = 0; k < 8; ++k) {
      const glm::vec3 corner((k & 1) ? box.max.x : box.min.x, (k & 2) ? box.max.y : box.min.y,
                             (k & 4) ? box.max.z : box.min.z);
      const float t = glm::dot(corner - through, d);
      front = std::min(front, t);
      back = std::max(back, t);
    }
    const float margin = 0.05f * box.diagonal();
    op_.cylinder.a = through + (front - margin) * d;
    op_.cylinder.b = through + (back + margin) * d;
    op_.cylinder.radius = 0.03f * box.diagonal();
    refresh();
  }

  /// The rims: the cylinder's side (a prism of thin triangles) against the posed surface.
  Overlay preview(const Scene& scene) const override {
    Overlay overlay;
    const glm::vec3 a = op_.cylinder.a, b = op_.cylinder.b;
    const float r = op_.cylinder.radius;
    OverlayLines rim;
    rim.color = {0.2f, 1.0f, 0.4f};
    rim.width_px = 3.0f;
    rim.on_top = true;
    const float length = glm::length(b - a);
    if (length > 0.0f && r > 0.0f) {
      const glm::vec3 w = (b - a) / length;
      const glm::vec3 helper = std::abs(w.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
      const glm::vec3 u = glm::normalize(glm::cross(w, helper)), v = glm::cross(w, u);
      auto ring = [&](int k) {
        const float t = 2.0f * kPi * static_cast<float>(k) / kPreviewSides;
        return r * (std::cos(t) * u + std::sin(t) * v);
      };
      for (int k = 0; k < kPreviewSides; ++k) {
        const glm::vec3 p = ring(k), q = ring(k + 1);
        for (const std::array<glm::vec3, 3>& tri :
             {std::array<glm::vec3, 3>{a + p, b + p, b + q}, std::array<glm::vec3, 3>{a + p, b + q, a + q}}) {
          const std::vector<glm::vec3> part = triangle_contour(scene, tri);
          rim.endpoints.insert(rim.endpoints.end(), part.begin(), part.end());
        }
      }
    }
    overlay.lines.push_back(std::move(rim));
    return overlay;
  }

 private:
  void read_widget() override {
    DrillRepresentation* rep = widget_->GetDrillRepresentation();
    auto point = [](const double* p) { return glm::vec3(p[0], p[1], p[2]); };
    op_.cylinder.a = point(rep->GetEndA());
    op_.cylinder.b = point(rep->GetEndB());
    op_.cylinder.radius = static_cast<float>(rep->GetRadius());
  }

  void write_widget() override {
    DrillRepresentation* rep = widget_->GetDrillRepresentation();
    const double a[3] = {op_.cylinder.a.x, op_.cylinder.a.y, op_.cylinder.a.z};
    const double b[3] = {op_.cylinder.b.x, op_.cylinder.b.y, op_.cylinder.b.z};
    rep->SetEndA(a);
    rep->SetEndB(b);
    rep->SetRadius(op_.cylinder.radius);
  }

  void show_panel() override {
    if (!a_) return;
    a_->set(op_.cylinder.a);
    b_->set(op_.cylinder.b);
    const QSignalBlocker b1(radius_), b2(rim_edges_), b3(wall_);
    radius_->setValue(static_cast<double>(op_.cylinder.radius));
    rim_edges_->setValue(op_.options.min_rim_edges);
    wall_->setChecked(op_.options.wall);
  }

  std::optional<Vec3Entry> a_, b_;
  QDoubleSpinBox* radius_ = nullptr;
  QSpinBox* rim_edges_ = nullptr;
  QCheckBox* wall_ = nullptr;
};

}  // namespace

std::unique_ptr<Tool> create_drill_tool() { return std::make_unique<DrillTool>(); }

}  // namespace deepcut::plugins
