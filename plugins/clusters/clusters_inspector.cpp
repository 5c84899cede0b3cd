// SPDX-License-Identifier: MIT
// Particle clusters inspector: the soft-body particles (core/softbody/clustering.h) of every
// instance. Vertices are coloured by the particle that holds them most strongly, particle centres
// and their radius spheres follow the pose, and the rho slider re-clusters live (in the studio off
// the UI thread: a 1M-triangle model takes a second or more; the clusters shown change only when
// the new ones are ready, and Cancel keeps them).
#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QElapsedTimer>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QPointer>
#include <QSignalBlocker>
#include <QSlider>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <string>

#include "deepcut/core/errors.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/core/softbody/clustering.h"
#include "deepcut/core/softbody/simulation.h"
#include "deepcut/plugins/colors.h"
#include "deepcut/plugins/inspector_registry.h"

namespace deepcut::plugins {
namespace {

constexpr int kSliderSteps = 400;
constexpr float kMinRhoFraction = 0.01f, kMaxRhoFraction = 0.25f;  // of the model size
constexpr float kDefaultRhoFraction = 0.07f;

struct InstanceClusters {
  Clusters clusters;
  std::vector<glm::vec3> rest;  // rest-pose world positions (what rho is measured in)
  std::uint32_t first_id = 0;   // particle numbering across instances (for colours)
};

/// One drawn instance as clustering reads it: its mesh (owned by the scene's model) and where
/// its rest pose is.
struct ClusterInput {
  int node = -1, primitive = -1;
  const SurfaceMesh* surface = nullptr;
};

/// The particles of every instance of `model` at radius `rho`, numbered across instances.
/// Reads `model` only: safe off the UI thread while nothing edits it.
std::vector<InstanceClusters> cluster_instances(const Model& model, const std::vector<ClusterInput>& inputs, float rho) {
  const PosedModel rest = PosedModel::build(model, -1, 0.0f, PoseDetail::Positions);
  std::vector<InstanceClusters> out;
  std::uint32_t next_id = 0;
  ClusterOptions options;
  options.radius = rho;
  for (const ClusterInput& input : inputs) {
    InstanceClusters pc;
    pc.rest = rest.find(input.node, input.primitive)->posed;
    pc.clusters = Clusters::build(*input.surface, pc.rest, options);
    pc.first_id = next_id;
    next_id += static_cast<std::uint32_t>(pc.clusters.particle_slots());
    out.push_back(std::move(pc));
  }
  return out;
}

class ClustersInspector final : public Inspector {
 public:
  std::string id() const override { return "clusters"; }
  std::string title() const override { return "Particle clusters"; }

  QWidget* create_panel(QWidget* parent) override;
  void set_scene(const Scene& scene, SceneChange change) override;
  InstanceColors instance_colors(std::size_t instance) const override;
  Overlay overlay() const override;
  std::vector<std::string> summary() const override;
  std::optional<Focus> focus() const override;
  bool pick(const Pick& pick) override;
  void set_option(const std::string& name, const std::string& value) override;

 private:
  void recluster();
  /// Re-clusters at `rho` through the studio's background runner (the panel's controls).
  void recluster_in_background(float rho);
  /// The scene's instances as clustering reads them.
  std::vector<ClusterInput> inputs() const;
  /// Shows the clusters just made (`ms` to make them).
  void take_clusters(double ms);
  void refresh_panel();
  float slider_to_rho(int value) const;
  int rho_to_slider(float rho) const;
  std::uint32_t dominant_particle(std::size_t instance, VertexId v) const;

  const Scene* scene_ = nullptr;
  float rho_ = 0.0f;  // 0: not chosen yet (a default relative to the model is used)
  std::vector<InstanceClusters> instances_;
  double cluster_ms_ = 0.0;
  bool show_spheres_ = true;
  std::size_t picked_instance_ = Pick::kNoInstance;
  std::uint32_t picked_particle_ = kInvalidIndex;

  QPointer<QSlider> slider_;
  QPointer<QDoubleSpinBox> spin_;
  QPointer<QLabel> counts_, picked_label_;
  QPointer<QCheckBox> spheres_box_;
};

float ClustersInspector::slider_to_rho(int value) const {
  const float size = scene_ ? scene_->size : 1.0f;
  const float t = static_cast<float>(value) / kSliderSteps;
  return size * kMinRhoFraction * std::pow(kMaxRhoFraction / kMinRhoFraction, t);
}

int ClustersInspector::rho_to_slider(float rho) const {
  const float size = scene_ ? scene_->size : 1.0f;
  const float t = std::log(rho / (size * kMinRhoFraction)) / std::log(kMaxRhoFraction / kMinRhoFraction);
  return std::clamp(static_cast<int>(std::lround(t * kSliderSteps)), 0, kSliderSteps);
}

void ClustersInspector::set_scene(const Scene& scene, SceneChange change) {
  scene_ = &scene;
  if (change == SceneChange::Pose) return;
  if (rho_ <= 0.0f || rho_ > scene.size) rho_ = kDefaultRhoFraction * scene.size;
  picked_instance_ = Pick::kNoInstance;
  recluster();
}

std::vector<ClusterInput> ClustersInspector::inputs() const {
  std::vector<ClusterInput> out;
  for (const SceneInstance& instance : scene_->instances) out.push_back({instance.node, instance.primitive, instance.surface});
  return out;
}

void ClustersInspector::recluster() {
  instances_.clear();
  if (!scene_) return;
  QElapsedTimer clock;
  clock.start();
  instances_ = cluster_instances(*scene_->model, inputs(), rho_);
  take_clusters(static_cast<double>(clock.nsecsElapsed()) / 1e6);
}

void ClustersInspector::take_clusters(double ms) {
  cluster_ms_ = ms;
  if (picked_instance_ < instances_.size() &&
      picked_particle_ >= instances_[picked_instance_].clusters.particle_slots())
    picked_instance_ = Pick::kNoInstance;
  refresh_panel();
}

void ClustersInspector::recluster_in_background(float rho) {
  if (!scene_) return;
  // The new clusters replace the shown ones when ready; until then (and after Cancel, or when
  // another task runs) rho and the colours stay as they are.
  std::shared_ptr<const Model> model = scene_->model;
  const std::vector<ClusterInput> in = inputs();
  std::ostringstream title;
  title << "Re-clustering at rho " << rho;
  const bool started = run_in_background(
      title.str(),
      [this, model, in, rho](const std::function<void(const std::string&)>& stage) -> std::function<void()> {
        stage("Clustering");
        QElapsedTimer clock;
        clock.start();
        auto made = std::make_shared<std::vector<InstanceClusters>>(cluster_instances(*model, in, rho));
        const double ms = static_cast<double>(clock.nsecsElapsed()) / 1e6;
        stage("Colouring");
        return [this, model, made, rho, ms] {
          if (!scene_ || scene_->model != model) return;  // the scene changed meanwhile
          rho_ = rho;
          instances_ = std::move(*made);
          take_clusters(ms);
          notify_changed();
        };
      },
      [this] { refresh_panel(); });
  if (!started) refresh_panel();
}

std::uint32_t ClustersInspector::dominant_particle(std::size_t instance, VertexId v) const {
  const Clusters& c = instances_[instance].clusters;
  if (v.index >= c.vertex_count()) return kInvalidIndex;
  std::uint32_t best = kInvalidIndex;
  float weight = -1.0f;
  for (const Influence& influence : c.influences(v))
    if (influence.weight > weight) {
      weight = influence.weight;
      best = influence.particle;
    }
  return best;
}

InstanceColors ClustersInspector::instance_colors(std::size_t instance) const {
  InstanceColors out;
  if (!scene_ || instance >= instances_.size()) return out;
  const SurfaceMesh& mesh = *scene_->instances[instance].surface;
  out.kind = InstanceColors::Kind::PerVertex;
  out.colors.assign(mesh.vertex_count(), to_rgb8(palette::kNeutral));
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    const std::uint32_t p = dominant_particle(instance, VertexId(v));
    if (p == kInvalidIndex) continue;
    glm::vec3 c = category_color(instances_[instance].first_id + p);
    if (picked_instance_ == instance && picked_particle_ != kInvalidIndex && p != picked_particle_)
      c = pastel(c, 0.6f);
    out.colors[v] = to_rgb8(c);
  }
  return out;
}

Overlay ClustersInspector::overlay() const {
  Overlay overlay;
  if (!scene_) return overlay;
  OverlayPoints centres;
  centres.color = glm::vec3(0.08f, 0.08f, 0.1f);
  centres.size_px = 6.0f;
  centres.on_top = true;
  OverlaySpheres spheres;
  spheres.opacity = 0.12f;
  for (std::size_t i = 0; i < instances_.size(); ++i) {
    const Clusters& c = instances_[i].clusters;
    const std::vector<glm::vec3> posed = posed_particle_centres(c, scene_->instances[i].posed());
    for (std::uint32_t p = 0; p < c.particle_slots(); ++p) {
      if (c.members(p).empty()) continue;
      centres.positions.push_back(posed[p]);
      spheres.centers.push_back(posed[p]);
      spheres.radii.push_back(c.radius());
      spheres.colors.push_back(category_color(instances_[i].first_id + p));
    }
  }
  overlay.points.push_back(std::move(centres));
  if (show_spheres_) overlay.spheres.push_back(std::move(spheres));
  if (picked_instance_ < instances_.size() && picked_particle_ != kInvalidIndex) {
    const Clusters& c = instances_[picked_instance_].clusters;
    const auto& posed = scene_->instances[picked_instance_].posed();
    OverlayPoints members;
    members.color = palette::kPicked;
    members.size_px = 6.0f;
    for (std::uint32_t v : c.members(picked_particle_)) members.positions.push_back(posed[v]);
    overlay.points.push_back(std::move(members));
    OverlaySpheres sphere;
    sphere.centers = {posed_particle_centres(c, posed)[picked_particle_]};
    sphere.radii = {c.radius()};
    sphere.color = palette::kPicked;
    sphere.opacity = 0.3f;
    overlay.spheres.push_back(std::move(sphere));
  }
  return overlay;
}

std::vector<std::string> ClustersInspector::summary() const {
  std::vector<std::string> lines;
  if (!scene_) return lines;
  std::size_t particles = 0, min_members = 0, max_members = 0, memberships = 0, covered = 0, uncovered = 0;
  bool first = true;
  for (std::size_t i = 0; i < instances_.size(); ++i) {
    const ClusterStats s = cluster_stats(instances_[i].clusters, *scene_->instances[i].surface);
    if (s.particles == 0) continue;
    min_members = first ? s.min_vertices : std::min(min_members, s.min_vertices);
    max_members = std::max(max_members, s.max_vertices);
    first = false;
    particles += s.particles;
    memberships += s.memberships;
    covered += s.covered_vertices;
    uncovered += s.uncovered_vertices;
  }
  std::ostringstream a, b;
  a.precision(3);
  a << particles << " particles at rho " << rho_ << " (clustered in "
    << static_cast<long>(std::lround(cluster_ms_)) << " ms)";
  b.precision(3);
  b << "vertices per particle " << min_members << " to " << max_members << ", mean "
    << (particles ? static_cast<double>(memberships) / static_cast<double>(particles) : 0.0) << "; "
    << covered << " vertices covered"
    << (uncovered ? ", " + std::to_string(uncovered) + " not covered" : std::string());
  lines.push_back(a.str());
  lines.push_back(b.str());
  if (picked_instance_ < instances_.size() && picked_particle_ != kInvalidIndex)
    lines.push_back("Particle " + std::to_string(picked_particle_) + ": " +
                    std::to_string(instances_[picked_instance_].clusters.members(picked_particle_).size()) +
                    " vertices");
  return lines;
}

std::optional<Focus> ClustersInspector::focus() const {
  if (!scene_ || picked_instance_ >= instances_.size() || picked_particle_ == kInvalidIndex)
    return std::nullopt;
  const Clusters& c = instances_[picked_instance_].clusters;
  return Focus{posed_particle_centres(c, scene_->instances[picked_instance_].posed())[picked_particle_],
               2.0f * c.radius()};
}

bool ClustersInspector::pick(const Pick& pick) {
  if (!scene_ || pick.instance >= instances_.size() || !pick.vertex.valid()) return false;
  const std::uint32_t p = dominant_particle(pick.instance, pick.vertex);
  if (p == kInvalidIndex) return false;
  picked_instance_ = pick.instance;
  picked_particle_ = p;
  refresh_panel();
  return true;
}

void ClustersInspector::set_option(const std::string& name, const std::string& value) {
  if (name == "rho") {
    std::size_t used = 0;
    float rho = 0.0f;
    try {
      rho = std::stof(value, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != value.size() || value.empty() || !std::isfinite(rho) || rho <= 0.0f)
      throw Error(ErrorCode::InvalidArgument, "clusters: rho must be a positive number, not '" + value + "'");
    rho_ = rho;
    recluster();
    return;
  }
  Inspector::set_option(name, value);
}

QWidget* ClustersInspector::create_panel(QWidget* parent) {
  auto* panel = new QWidget(parent);
  auto* layout = new QVBoxLayout(panel);
  layout->setContentsMargins(6, 6, 6, 6);
  auto* hint = new QLabel(
      "Soft-body particles: every vertex within rho of a particle's seed belongs to it. Drag rho to "
      "re-cluster; "
      "click the surface to see one particle.",
      panel);
  hint->setWordWrap(true);
  layout->addWidget(hint);
  auto* row = new QHBoxLayout;
  row->addWidget(new QLabel("rho", panel));
  slider_ = new QSlider(Qt::Horizontal, panel);
  slider_->setObjectName("clusters_rho_slider");
  slider_->setRange(0, kSliderSteps);
  slider_->setToolTip("Particle radius (logarithmic scale)");
  spin_ = new QDoubleSpinBox(panel);
  spin_->setObjectName("clusters_rho");
  spin_->setDecimals(3);
  spin_->setKeyboardTracking(false);
  spin_->setRange(0.001, 1e6);
  row->addWidget(slider_, 1);
  row->addWidget(spin_);
  layout->addLayout(row);
  spheres_box_ = new QCheckBox("Show particle radius spheres", panel);
  spheres_box_->setChecked(show_spheres_);
  layout->addWidget(spheres_box_);
  counts_ = new QLabel(panel);
  counts_->setWordWrap(true);
  counts_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  picked_label_ = new QLabel(panel);
  picked_label_->setWordWrap(true);
  layout->addWidget(counts_);
  layout->addWidget(picked_label_);
  layout->addStretch(1);

  QObject::connect(slider_, &QSlider::valueChanged, panel,
                   [this](int value) { recluster_in_background(slider_to_rho(value)); });
  QObject::connect(spin_, QOverload<double>::of(&QDoubleSpinBox::valueChanged), panel, [this](double value) {
    if (value > 0.0) recluster_in_background(static_cast<float>(value));
  });
  QObject::connect(spheres_box_, &QCheckBox::toggled, panel, [this](bool on) {
    show_spheres_ = on;
    notify_changed();
  });
  refresh_panel();
  return panel;
}

void ClustersInspector::refresh_panel() {
  if (!counts_) return;
  {
    const QSignalBlocker a(slider_.data()), b(spin_.data());
    slider_->setValue(rho_to_slider(rho_ > 0.0f ? rho_ : 1.0f));
    spin_->setValue(rho_);
  }
  const auto lines = summary();
  QString text;
  for (std::size_t i = 0; i < lines.size() && i < 2; ++i) text += QString::fromStdString(lines[i]) + "\n";
  counts_->setText(text.trimmed());
  picked_label_->setText(lines.size() > 2 ? QString::fromStdString(lines[2])
                                          : QString("No particle picked."));
}

}  // namespace

void register_clusters(InspectorRegistry& registry) {
  registry.add({"clusters", "Particle clusters", [] { return std::make_unique<ClustersInspector>(); }});
}

}  // namespace deepcut::plugins
