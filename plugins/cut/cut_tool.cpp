// SPDX-License-Identifier: MIT
// The Plane tool: a cutting plane (PlaneWidget: drag its normal, origin or the plane itself)
// placed through the model's centre, mirrored with the numeric panel, its contour on the posed
// surface drawn live, applied with deepcut::apply_operation (CutOperation).
#include <QCheckBox>
#include <QComboBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QPushButton>
#include <QSignalBlocker>
#include <QWidget>
#include <glm/geometric.hpp>
#include <memory>
#include <optional>

#include "deepcut/plugins/widget_tool.h"
#include "deepcut/widgets/plane_widget.h"

namespace deepcut::plugins {
namespace {

class CutTool final : public WidgetTool<CutOperation, PlaneWidget> {
 public:
  CutTool() { write_widget(); }

  std::string id() const override { return "cut"; }
  std::string title() const override { return "Plane"; }

  QWidget* create_panel(QWidget* parent) override {
    auto* panel = new QWidget(parent);
    auto* form = new QFormLayout(panel);
    add_vec3_row(point_, form, "Point", "cut.point", op_.plane.point);
    add_vec3_row(normal_, form, "Normal", "cut.normal", op_.plane.normal);
    // ParaView's quick normals: the plane across an axis, keeping its point.
    auto* axes = new QWidget(panel);
    auto* axes_layout = new QHBoxLayout(axes);
    axes_layout->setContentsMargins(0, 0, 0, 0);
    const glm::vec3 units[3] = {{1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 1.0f}};
    const char* names[3] = {"X", "Y", "Z"};
    for (int k = 0; k < 3; ++k) {
      auto* button = new QPushButton(QString("%1 normal").arg(names[k]), axes);
      button->setObjectName(QString("cut.normal_%1").arg(QChar(names[k][0]).toLower()));
      axes_layout->addWidget(button);
      QObject::connect(button, &QPushButton::clicked, panel, [this, unit = units[k]] {
        op_.plane.normal = unit;
        refresh();
      });
    }
    form->addRow("", axes);
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
    show_panel();
    return panel;
  }

  /// Through the bounding box's centre, normal +Y (glTF up): a horizontal cut.
  void place(const Scene& scene, const ToolPlacement&) override {
    const BoundingBox box = scene_bounds(scene);
    if (box.empty()) return;
    // The plane is drawn cropped to the model's box with a margin.
    const glm::vec3 c = 0.5f * (box.min + box.max),
                    half = 0.55f * (box.max - box.min) + 0.02f * box.diagonal();
    double bounds[6] = {c.x - half.x, c.x + half.x, c.y - half.y, c.y + half.y, c.z - half.z, c.z + half.z};
    PlaneRepresentation* rep = widget_->GetPlaneRepresentation();
    rep->SetPlaceFactor(1.0);
    rep->PlaceWidget(bounds);
    op_.plane.point = c;
    op_.plane.normal = glm::vec3(0.0f, 1.0f, 0.0f);
    refresh();
  }

  Overlay preview(const Scene& scene) const override {
    Overlay overlay;
    OverlayLines contour;
    contour.endpoints = plane_contour(scene, op_.plane);
    contour.color = {1.0f, 0.85f, 0.0f};
    contour.width_px = 3.0f;
    contour.on_top = true;
    overlay.lines.push_back(std::move(contour));
    return overlay;
  }

 private:
  void read_widget() override {
    PlaneRepresentation* rep = widget_->GetPlaneRepresentation();
    double origin[3], normal[3];
    rep->GetOrigin(origin);
    rep->GetNormal(normal);
    op_.plane.point = glm::vec3(origin[0], origin[1], origin[2]);
    op_.plane.normal = glm::vec3(normal[0], normal[1], normal[2]);
  }

  void write_widget() override {
    PlaneRepresentation* rep = widget_->GetPlaneRepresentation();
    rep->SetOrigin(op_.plane.point.x, op_.plane.point.y, op_.plane.point.z);
    // A zero normal cuts nothing (the preview is empty); the widget keeps its last direction.
    if (glm::length(op_.plane.normal) > 0.0f)
      rep->SetNormal(op_.plane.normal.x, op_.plane.normal.y, op_.plane.normal.z);
  }

  void show_panel() override {
    if (!point_) return;
    point_->set(op_.plane.point);
    normal_->set(op_.plane.normal);
    const QSignalBlocker b1(keep_), b2(cap_), b3(components_);
    keep_->setCurrentIndex(keep_->findData(static_cast<int>(op_.options.keep)));
    cap_->setChecked(op_.options.cap);
    components_->setChecked(op_.options.split_components);
  }

  std::optional<Vec3Entry> point_, normal_;
  QComboBox* keep_ = nullptr;
  QCheckBox* cap_ = nullptr;
  QCheckBox* components_ = nullptr;
};

}  // namespace

std::unique_ptr<Tool> create_cut_tool() { return std::make_unique<CutTool>(); }

}  // namespace deepcut::plugins
