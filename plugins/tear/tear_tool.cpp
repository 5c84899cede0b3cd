// SPDX-License-Identifier: MIT
// The Scalpel tool: a blade (handle, tip) at a start and an end pose; the swept quad is what
// tears. The tear path (quad against the posed triangles) is drawn live; applied with
// deepcut::apply_operation (TearOperation).
#include <QDoubleSpinBox>
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

class TearTool final : public Tool {
 public:
  std::string id() const override { return "tear"; }
  std::string title() const override { return "Scalpel"; }

  QWidget* create_panel(QWidget* parent) override {
    auto* panel = new QWidget(parent);
    auto* form = new QFormLayout(panel);
    start_handle_.emplace(form, "Start handle", "tear.start.handle", [this] {
      op_.start.handle = start_handle_->value();
      notify_changed();
    });
    start_tip_.emplace(form, "Start tip", "tear.start.tip", [this] {
      op_.start.tip = start_tip_->value();
      notify_changed();
    });
    end_handle_.emplace(form, "End handle", "tear.end.handle", [this] {
      op_.end.handle = end_handle_->value();
      notify_changed();
    });
    end_tip_.emplace(form, "End tip", "tear.end.tip", [this] {
      op_.end.tip = end_tip_->value();
      notify_changed();
    });
    width_ = make_number(panel, "tear.width", -1.0, 1e6);
    width_->setSpecialValueText("auto (5% of the blade)");
    width_->setToolTip("Opening width in model units; auto: 5% of the mean blade length; 0: no gap");
    form->addRow("Opening width", width_);
    QObject::connect(width_, QOverload<double>::of(&QDoubleSpinBox::valueChanged), panel, [this](double w) {
      op_.options.width = static_cast<float>(w);
      notify_changed();
    });
    show();
    return panel;
  }

  /// The blade points along the view direction from in front of the model to its centre and
  /// sweeps down across the model's front.
  void place(const Scene& scene, const glm::vec3& view_direction) override {
    const BoundingBox box = scene_bounds(scene);
    if (box.empty()) return;
    const glm::vec3 c = 0.5f * (box.min + box.max), extent = box.max - box.min;
    const glm::vec3 d = view_direction;
    glm::vec3 up = glm::vec3(0.0f, 1.0f, 0.0f) - d.y * d;
    up = glm::length(up) > 1e-3f ? glm::normalize(up) : glm::vec3(0.0f, 0.0f, 1.0f);
    const float depth = 0.5f * glm::dot(glm::abs(d), extent);
    const float height = 0.5f * glm::dot(glm::abs(up), extent);
    const glm::vec3 handle = c - 1.5f * depth * d, tip = c;
    op_.start = {handle + 0.3f * height * up, tip + 0.3f * height * up};
    op_.end = {handle - 0.3f * height * up, tip - 0.3f * height * up};
    show();
    notify_changed();
  }

  OperationParams parameters() const override { return op_; }

  void set_parameters(const OperationParams& params) override {
    const auto* tear = std::get_if<TearOperation>(&params);
    if (!tear) throw Error(ErrorCode::InvalidArgument, "the Scalpel tool takes tear parameters");
    op_ = *tear;
    show();
    notify_changed();
  }

  Overlay preview(const Scene& scene) const override {
    Overlay overlay;
    OverlayLines path, quad;
    try {
      for (const auto& tri : swept_quad_triangles(op_.start, op_.end)) {
        const std::vector<glm::vec3> part = triangle_contour(scene, tri);
        path.endpoints.insert(path.endpoints.end(), part.begin(), part.end());
      }
    } catch (const Error&) {
      // A degenerate sweep tears nothing: only the blades are drawn.
    }
    path.color = {1.0f, 0.2f, 0.2f};
    path.width_px = 3.0f;
    path.on_top = true;
    overlay.lines.push_back(std::move(path));
    const glm::vec3 outline[4] = {op_.start.handle, op_.start.tip, op_.end.tip, op_.end.handle};
    for (int k = 0; k < 4; ++k) {
      quad.endpoints.push_back(outline[k]);
      quad.endpoints.push_back(outline[(k + 1) % 4]);
    }
    quad.color = {0.9f, 0.9f, 0.9f};
    overlay.lines.push_back(std::move(quad));
    OverlayPoints handles, tips;
    handles.positions = {op_.start.handle, op_.end.handle};
    handles.color = {0.3f, 0.7f, 1.0f};
    handles.size_px = 10.0f;
    handles.on_top = true;
    tips.positions = {op_.start.tip, op_.end.tip};
    tips.color = {1.0f, 0.4f, 0.2f};
    tips.size_px = 10.0f;
    tips.on_top = true;
    overlay.points.push_back(std::move(handles));
    overlay.points.push_back(std::move(tips));
    return overlay;
  }

 private:
  void show() {
    if (!start_handle_) return;
    start_handle_->set(op_.start.handle);
    start_tip_->set(op_.start.tip);
    end_handle_->set(op_.end.handle);
    end_tip_->set(op_.end.tip);
    const QSignalBlocker block(width_);
    width_->setValue(static_cast<double>(op_.options.width));
  }

  TearOperation op_;
  std::optional<Vec3Entry> start_handle_, start_tip_, end_handle_, end_tip_;
  QDoubleSpinBox* width_ = nullptr;
};

}  // namespace

void register_tear(ToolRegistry& registry) {
  registry.add({"tear", "Scalpel", [] { return std::make_unique<TearTool>(); }});
}

}  // namespace deepcut::plugins
