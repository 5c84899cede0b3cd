// SPDX-License-Identifier: MIT
// The Scalpel tool: a blade (handle, tip) at a start and an end pose; the swept quad is what
// tears. ScalpelWidget drags the points, the blades and the whole scalpel, mirrored with the
// numeric panel; the tear path (quad against the posed triangles) is drawn live; applied with
// deepcut::apply_operation (TearOperation).
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QSignalBlocker>
#include <QWidget>
#include <glm/geometric.hpp>
#include <memory>
#include <optional>

#include "deepcut/core/errors.h"
#include "deepcut/plugins/widget_tool.h"
#include "deepcut/widgets/scalpel_widget.h"

namespace deepcut::plugins {
namespace {

class TearTool final : public WidgetTool<TearOperation, ScalpelWidget> {
 public:
  TearTool() { write_widget(); }

  std::string id() const override { return "tear"; }
  std::string title() const override { return "Scalpel"; }

  QWidget* create_panel(QWidget* parent) override {
    auto* panel = new QWidget(parent);
    auto* form = new QFormLayout(panel);
    add_vec3_row(start_handle_, form, "Start handle", "tear.start.handle", op_.start.handle);
    add_vec3_row(start_tip_, form, "Start tip", "tear.start.tip", op_.start.tip);
    add_vec3_row(end_handle_, form, "End handle", "tear.end.handle", op_.end.handle);
    add_vec3_row(end_tip_, form, "End tip", "tear.end.tip", op_.end.tip);
    width_ = make_number(panel, "tear.width", -1.0, 1e6);
    width_->setSpecialValueText("auto (5% of the blade)");
    width_->setToolTip("Opening width in model units; auto: 5% of the mean blade length; 0: no gap");
    form->addRow("Opening width", width_);
    QObject::connect(width_, QOverload<double>::of(&QDoubleSpinBox::valueChanged), panel, [this](double w) {
      op_.options.width = static_cast<float>(w);
      notify_changed();
    });
    show_panel();
    return panel;
  }

  /// At a surface point: the blade points along the view direction, from in front of the point
  /// into the surface, and sweeps down the screen across it. Without a point: from in front of
  /// the model to its centre, sweeping down across the model's front.
  void place(const Scene& scene, const ToolPlacement& placement) override {
    const BoundingBox box = scene_bounds(scene);
    if (box.empty()) return;
    const glm::vec3 d = placement.view_direction;
    if (placement.point) {
      const glm::vec3 p = *placement.point, up = placement.view_up;
      const float size = box.diagonal(), outside = 0.08f * size, inside = 0.04f * size, sweep = 0.08f * size;
      op_.start = {p - outside * d + sweep * up, p + inside * d + sweep * up};
      op_.end = {p - outside * d - sweep * up, p + inside * d - sweep * up};
      refresh();
      return;
    }
    const glm::vec3 c = 0.5f * (box.min + box.max), extent = box.max - box.min;
    glm::vec3 up = glm::vec3(0.0f, 1.0f, 0.0f) - d.y * d;
    up = glm::length(up) > 1e-3f ? glm::normalize(up) : glm::vec3(0.0f, 0.0f, 1.0f);
    const float depth = 0.5f * glm::dot(glm::abs(d), extent);
    const float height = 0.5f * glm::dot(glm::abs(up), extent);
    const glm::vec3 handle = c - 1.5f * depth * d, tip = c;
    op_.start = {handle + 0.3f * height * up, tip + 0.3f * height * up};
    op_.end = {handle - 0.3f * height * up, tip - 0.3f * height * up};
    refresh();
  }

  Overlay preview(const Scene& scene) const override {
    Overlay overlay;
    OverlayLines path;
    try {
      for (const auto& tri : swept_quad_triangles(op_.start, op_.end)) {
        const std::vector<glm::vec3> part = triangle_contour(scene, tri);
        path.endpoints.insert(path.endpoints.end(), part.begin(), part.end());
      }
    } catch (const Error&) {
      // A degenerate sweep tears nothing: no path (the widget still shows the blades).
    }
    path.color = {1.0f, 0.2f, 0.2f};
    path.width_px = 3.0f;
    path.on_top = true;
    overlay.lines.push_back(std::move(path));
    return overlay;
  }

 private:
  void read_widget() override {
    ScalpelRepresentation* rep = widget_->GetScalpelRepresentation();
    auto point = [](const double* p) { return glm::vec3(p[0], p[1], p[2]); };
    op_.start = {point(rep->GetStartHandle()), point(rep->GetStartTip())};
    op_.end = {point(rep->GetEndHandle()), point(rep->GetEndTip())};
  }

  void write_widget() override {
    ScalpelRepresentation* rep = widget_->GetScalpelRepresentation();
    auto set = [](const glm::vec3& p, double out[3]) { out[0] = p.x, out[1] = p.y, out[2] = p.z; };
    double p[3];
    set(op_.start.handle, p);
    rep->SetStartHandle(p);
    set(op_.start.tip, p);
    rep->SetStartTip(p);
    set(op_.end.handle, p);
    rep->SetEndHandle(p);
    set(op_.end.tip, p);
    rep->SetEndTip(p);
  }

  void show_panel() override {
    if (!start_handle_) return;
    start_handle_->set(op_.start.handle);
    start_tip_->set(op_.start.tip);
    end_handle_->set(op_.end.handle);
    end_tip_->set(op_.end.tip);
    const QSignalBlocker block(width_);
    width_->setValue(static_cast<double>(op_.options.width));
  }

  std::optional<Vec3Entry> start_handle_, start_tip_, end_handle_, end_tip_;
  QDoubleSpinBox* width_ = nullptr;
};

}  // namespace

std::unique_ptr<Tool> create_tear_tool() { return std::make_unique<TearTool>(); }

}  // namespace deepcut::plugins
