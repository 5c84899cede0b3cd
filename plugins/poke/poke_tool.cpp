// SPDX-License-Identifier: MIT
// The Poke tool: click-drag on the model pulls the soft-body particles near the picked point
// (core/softbody), the mesh follows live, and on release it springs back, damped; a click
// without dragging gives the surface a push into the view. The displacement is layered on the
// skinned pose (displacements live in the current pose's world frame), so poking works while the
// animation plays. It never changes the model: no operation, no history entry.
#include <QDoubleSpinBox>
#include <QElapsedTimer>
#include <QFormLayout>
#include <QLabel>
#include <QPointer>
#include <QSignalBlocker>
#include <QVBoxLayout>
#include <QWidget>
#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <memory>

#include "deepcut/core/errors.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/core/softbody/clustering.h"
#include "deepcut/core/softbody/simulation.h"
#include "deepcut/plugins/tool.h"
#include "deepcut/plugins/tool_panel.h"

namespace deepcut::plugins {
namespace {

constexpr float kDefaultRhoFraction = 0.07f;     // particle radius, of the model size (as the clusters inspector)
constexpr float kDefaultReachFraction = 0.12f;   // radius of influence, of the model size
constexpr float kRestFraction = 1e-5f;           // displacements below this (of the size) are at rest
constexpr float kClickSpeedFraction = 0.5f;      // a click pushes at half the model size per second

/// The soft body of one scene piece.
struct PieceBody {
  Clusters clusters;
  SoftBodyState state;
};

class PokeTool final : public Tool {
 public:
  std::string id() const override { return "poke"; }
  std::string title() const override { return "Poke"; }
  bool makes_operation() const override { return false; }

  QWidget* create_panel(QWidget* parent) override {
    auto* panel = new QWidget(parent);
    auto* layout = new QVBoxLayout(panel);
    layout->setContentsMargins(0, 0, 0, 0);
    auto* hint = new QLabel(
        "Drag on the model to pull it; release and it springs back. A click pushes it. Works while "
        "the animation plays; the model itself never changes.",
        panel);
    hint->setWordWrap(true);
    layout->addWidget(hint);
    auto* form = new QFormLayout();
    layout->addLayout(form);
    const auto number = [&](const char* name, const char* label, double min, double max, auto on_edit) {
      QDoubleSpinBox* spin = make_number(panel, name, min, max);
      form->addRow(label, spin);
      QObject::connect(spin, QOverload<double>::of(&QDoubleSpinBox::valueChanged), panel, on_edit);
      return spin;
    };
    reach_ = number("poke.radius", "Radius of influence", 1e-6, 1e6, [this](double v) {
      reach_value_ = static_cast<float>(v);
      notify_changed();
    });
    rho_ = number("poke.rho", "Particle radius (rho)", 1e-6, 1e6, [this](double v) {
      rho_value_ = static_cast<float>(v);
      model_.reset();  // re-cluster when the scene is seen next (the preview follows at once)
      notify_changed();
    });
    stiffness_ = number("poke.stiffness", "Stiffness", 0.0, 1e6, [this](double v) {
      options_.stiffness = static_cast<float>(v);
      notify_changed();
    });
    damping_ = number("poke.damping", "Damping", 0.0, 1e6, [this](double v) {
      options_.damping = static_cast<float>(v);
      notify_changed();
    });
    status_ = new QLabel(panel);
    status_->setObjectName("poke.status");
    status_->setWordWrap(true);
    layout->addWidget(status_);
    layout->addStretch(1);
    show();
    return panel;
  }

  void place(const Scene& scene, const ToolPlacement& placement) override {
    (void)placement;
    // Defaults relative to the model, kept while the user's values still fit it.
    if (!(rho_value_ > 0.0f) || rho_value_ > scene.size) {
      rho_value_ = kDefaultRhoFraction * scene.size;
      model_.reset();
    }
    if (!(reach_value_ > 0.0f) || reach_value_ > scene.size) reach_value_ = kDefaultReachFraction * scene.size;
    ensure(scene);
    show();
    notify_changed();
  }

  OperationParams parameters() const override {
    throw Error(ErrorCode::InvalidArgument, "the Poke tool makes no operation (it never changes the model)");
  }
  void set_parameters(const OperationParams& params) override {
    (void)params;
    throw Error(ErrorCode::InvalidArgument, "the Poke tool takes no operation parameters");
  }

  Overlay preview(const Scene& scene) const override {
    ensure(scene);
    Overlay overlay;
    if (!dragging_) return overlay;
    // The grab point, where it is pulled to, and the reach in the view plane.
    OverlayPoints marks;
    marks.positions = {grab_, target_};
    marks.color = {1.0f, 0.45f, 0.1f};
    marks.size_px = 10.0f;
    marks.on_top = true;
    overlay.points.push_back(std::move(marks));
    OverlayLines lines;
    lines.endpoints = {grab_, target_};
    const glm::vec3 helper = std::abs(normal_.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    const glm::vec3 u = glm::normalize(glm::cross(normal_, helper)), v = glm::cross(normal_, u);
    constexpr int kSegments = 48;
    for (int k = 0; k < kSegments; ++k) {
      const float a0 = 6.2831853f * static_cast<float>(k) / kSegments;
      const float a1 = 6.2831853f * static_cast<float>(k + 1) / kSegments;
      lines.endpoints.push_back(grab_ + reach_value_ * (std::cos(a0) * u + std::sin(a0) * v));
      lines.endpoints.push_back(grab_ + reach_value_ * (std::cos(a1) * u + std::sin(a1) * v));
    }
    lines.color = {1.0f, 0.45f, 0.1f};
    lines.width_px = 2.0f;
    lines.on_top = true;
    overlay.lines.push_back(std::move(lines));
    return overlay;
  }

  bool press(const Scene& scene, const Pick& pick, const ToolPointer& pointer) override {
    if (pick.piece == Pick::kNoPiece || pick.piece >= scene.pieces.size()) return false;
    ensure(scene);
    if (bodies_.size() != scene.pieces.size()) return false;  // clustering failed (reported)
    grab_ = target_ = pick.position;
    normal_ = glm::length(pointer.view_direction) > 0.0f ? glm::normalize(pointer.view_direction)
                                                         : glm::vec3(0.0f, 0.0f, -1.0f);
    dragging_ = true;
    moved_ = false;
    pull(scene);
    show_status();
    notify_changed();
    return true;
  }

  void move(const Scene& scene, const ToolPointer& pointer) override {
    if (!dragging_) return;
    // Follow the cursor in the plane through the grab point facing the camera.
    const float denom = glm::dot(pointer.ray_direction, normal_);
    if (std::abs(denom) < 1e-6f) return;
    const float t = glm::dot(grab_ - pointer.ray_origin, normal_) / denom;
    const glm::vec3 target = pointer.ray_origin + t * pointer.ray_direction;
    if (!std::isfinite(target.x) || !std::isfinite(target.y) || !std::isfinite(target.z)) return;
    target_ = target;
    moved_ = true;
    pull(scene);
    show_status();
    notify_changed();
  }

  void release(const Scene& scene) override {
    if (!dragging_) return;
    dragging_ = false;
    moving_ = true;
    for (PieceBody& body : bodies_) release_drag(body.state);
    if (!moved_ && bodies_.size() == scene.pieces.size()) {
      // A click: push the surface into the view.
      const glm::vec3 impulse = normal_ * (kClickSpeedFraction * scene.size * options_.mass);
      grabbed_ = 0;
      for (std::size_t i = 0; i < bodies_.size(); ++i)
        grabbed_ += poke(bodies_[i].state, bodies_[i].clusters, scene.pieces[i].posed(), grab_, impulse,
                         reach_value_, options_);
    }
    show_status();
    notify_changed();
  }

  bool step(const Scene& scene, float dt) override {
    if (bodies_.empty() || model_ != scene.model || (!dragging_ && !moving_)) return false;
    const float rest = kRestFraction * scene.size;
    float largest = 0.0f;
    for (PieceBody& body : bodies_) {
      step_soft_body(body.state, dt, options_);
      for (std::size_t p = 0; p < body.state.displacement.size(); ++p) {
        largest = std::max(largest, glm::length(body.state.displacement[p]));
        // A particle still moving fast will travel: count its speed over a tenth of a second.
        largest = std::max(largest, 0.1f * glm::length(body.state.velocity[p]));
      }
    }
    if (!dragging_ && largest < rest) {
      // Settled: back to exactly the skinned pose.
      for (PieceBody& body : bodies_) body.state = make_soft_body(body.clusters);
      moving_ = false;
      show_status();
    }
    return dragging_ || moving_;
  }

  bool displaced_positions(const Scene& scene, std::size_t piece, std::vector<glm::vec3>& out) const override {
    if ((!dragging_ && !moving_) || model_ != scene.model || piece >= bodies_.size() ||
        piece >= scene.pieces.size())
      return false;
    const PieceBody& body = bodies_[piece];
    if (body.clusters.vertex_count() != scene.pieces[piece].posed().size()) return false;
    deformed_positions(body.state, body.clusters, scene.pieces[piece].posed(), out);
    return true;
  }

 private:
  /// Clusters every piece of the scene's model with the current rho, unless that is done.
  /// (A cache over the scene: whoever sees the scene first builds it, the preview included.)
  void ensure(const Scene& scene) const {
    if (model_ == scene.model && bodies_.size() == scene.pieces.size()) return;
    bodies_.clear();
    dragging_ = moving_ = false;
    model_ = scene.model;
    error_.clear();
    if (!model_ || !(rho_value_ > 0.0f)) return;
    QElapsedTimer clock;
    clock.start();
    try {
      const Model& model = *model_;
      const PosedModel rest = PosedModel::build(model, -1, 0.0f, PoseDetail::Positions);
      ClusterOptions options;
      options.radius = rho_value_;
      for (const SceneInstance& piece : scene.pieces) {
        PieceBody body;
        // Rest-pose world positions: rho is measured in the units the user sees.
        body.clusters =
            Clusters::build(*piece.surface, rest.find(piece.node, piece.primitive)->posed, options);
        body.state = make_soft_body(body.clusters);
        bodies_.push_back(std::move(body));
      }
    } catch (const Error& e) {
      bodies_.clear();
      error_ = e.what();
    }
    cluster_ms_ = static_cast<double>(clock.nsecsElapsed()) / 1e6;
    show_status();
  }

  /// Pulls the particles within reach of the grab point towards the cursor, on every piece.
  void pull(const Scene& scene) {
    grabbed_ = 0;
    for (std::size_t i = 0; i < bodies_.size() && i < scene.pieces.size(); ++i)
      grabbed_ += drag(bodies_[i].state, bodies_[i].clusters, scene.pieces[i].posed(), grab_, target_, reach_value_);
  }

  void show() {
    if (!reach_) return;
    const QSignalBlocker b1(reach_), b2(rho_), b3(stiffness_), b4(damping_);
    reach_->setValue(static_cast<double>(reach_value_));
    rho_->setValue(static_cast<double>(rho_value_));
    stiffness_->setValue(static_cast<double>(options_.stiffness));
    damping_->setValue(static_cast<double>(options_.damping));
    show_status();
  }

  void show_status() const {
    if (!status_) return;
    if (!error_.empty()) {
      status_->setText(QString::fromStdString("Cannot cluster: " + error_));
      return;
    }
    std::size_t particles = 0;
    for (const PieceBody& body : bodies_) particles += body.clusters.particle_count();
    QString text = QString("%1 particles (rho %2), clustered in %3 ms")
                       .arg(particles)
                       .arg(static_cast<double>(rho_value_), 0, 'g', 3)
                       .arg(cluster_ms_, 0, 'f', 0);
    if (dragging_) text += QString("\nPulling %1 particles").arg(grabbed_);
    else if (moving_) text += "\nSpringing back";
    status_->setText(text);
  }

  SoftBodyOptions options_;
  float rho_value_ = 0.0f, reach_value_ = 0.0f;  // world units; 0 until placed on a model
  // The soft body of the scene's model (a cache: see ensure()).
  mutable std::shared_ptr<const Model> model_;
  mutable std::vector<PieceBody> bodies_;
  mutable double cluster_ms_ = 0.0;
  mutable std::string error_;
  mutable bool dragging_ = false, moving_ = false;
  bool moved_ = false;
  std::size_t grabbed_ = 0;
  glm::vec3 grab_{0.0f}, target_{0.0f}, normal_{0.0f, 0.0f, -1.0f};

  QPointer<QDoubleSpinBox> reach_, rho_, stiffness_, damping_;
  QPointer<QLabel> status_;
};

}  // namespace

std::unique_ptr<Tool> create_poke_tool() { return std::make_unique<PokeTool>(); }

}  // namespace deepcut::plugins
