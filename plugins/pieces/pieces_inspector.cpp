// SPDX-License-Identifier: MIT
// Pieces inspector: what a cut made. Every drawn instance (node x primitive; a cut's pieces, its
// sides and connected components, are instances of their own) gets its own colour; faces an
// operation created (cut caps, drill walls: f:cut_surface) are drawn darker, so caps and walls
// stand out from the old surface.
#include <QLabel>
#include <QPointer>
#include <QVBoxLayout>
#include <QWidget>
#include <cstdint>

#include "deepcut/core/attributes.h"
#include "deepcut/plugins/colors.h"
#include "deepcut/plugins/inspector_registry.h"

namespace deepcut::plugins {
namespace {

constexpr float kCreatedShade = 0.55f;  // brightness of faces an operation created

class PiecesInspector final : public Inspector {
 public:
  std::string id() const override { return "pieces"; }
  std::string title() const override { return "Pieces"; }

  QWidget* create_panel(QWidget* parent) override {
    auto* panel = new QWidget(parent);
    auto* layout = new QVBoxLayout(panel);
    auto* hint = new QLabel(
        "Each drawn instance in its own colour (a cut's pieces, its sides and components, are separate "
        "instances); surface an operation created (caps, drill walls) is drawn darker.",
        panel);
    hint->setWordWrap(true);
    layout->addWidget(hint);
    list_ = new QLabel(panel);
    list_->setObjectName("pieces.list");
    list_->setWordWrap(true);
    list_->setAlignment(Qt::AlignTop | Qt::AlignLeft);
    list_->setTextInteractionFlags(Qt::TextSelectableByMouse);
    layout->addWidget(list_, 1);
    refresh_panel();
    return panel;
  }

  void set_scene(const Scene& scene, SceneChange change) override {
    scene_ = &scene;
    if (change == SceneChange::Model) refresh_panel();
  }

  InstanceColors instance_colors(std::size_t instance) const override {
    InstanceColors out;
    if (!scene_ || instance >= scene_->instances.size()) return out;
    const SurfaceMesh& mesh = *scene_->instances[instance].surface;
    const glm::vec3 base = category_color(instance);
    out.kind = InstanceColors::Kind::PerFace;
    out.colors.assign(mesh.face_slots(), to_rgb8(base));
    if (const auto* created = mesh.face_attrs().find<std::uint8_t>(attr::kCutSurface)) {
      const glm::u8vec3 dark = to_rgb8(kCreatedShade * base);
      for (std::size_t f = 0; f < mesh.face_slots() && f < created->size(); ++f)
        if ((*created)[f] != 0) out.colors[f] = dark;
    }
    return out;
  }

  Overlay overlay() const override { return {}; }

  std::vector<std::string> summary() const override {
    if (!scene_) return {};
    const SceneCounts counts = scene_counts(*scene_);
    return {std::to_string(scene_->instances.size()) +
            (scene_->instances.size() == 1 ? " instance, " : " instances, ") +
            std::to_string(counts.triangles) + " triangles"};
  }

 private:
  void refresh_panel() {
    if (!list_) return;
    if (!scene_) {
      list_->setText("No model.");
      return;
    }
    QString text;
    for (std::size_t i = 0; i < scene_->instances.size(); ++i) {
      const SceneInstance& instance = scene_->instances[i];
      const glm::u8vec3 c = to_rgb8(category_color(i));
      std::size_t created = 0;
      if (const auto* flags = instance.surface->face_attrs().find<std::uint8_t>(attr::kCutSurface))
        instance.surface->for_each_face([&](FaceId f, const Triangle&) {
          if (f.index < flags->size() && (*flags)[f.index] != 0) ++created;
        });
      text += QString("<span style='color:rgb(%1,%2,%3)'>&#9632;</span> %4: %5 triangles%6<br>")
                  .arg(c.r)
                  .arg(c.g)
                  .arg(c.b)
                  .arg(QString::fromStdString(node_label(*scene_->model, instance.node)).toHtmlEscaped())
                  .arg(instance.surface->face_count())
                  .arg(created ? QString(" (%1 made by operations)").arg(created) : QString());
    }
    list_->setText(text);
  }

  const Scene* scene_ = nullptr;
  QPointer<QLabel> list_;
};

}  // namespace

void register_pieces(InspectorRegistry& registry) {
  registry.add({"pieces", "Pieces", [] { return std::make_unique<PiecesInspector>(); }});
}

}  // namespace deepcut::plugins
