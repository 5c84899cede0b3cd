// SPDX-License-Identifier: MIT
// Adjacency inspector: what the operations rely on. Click a vertex to see its one-ring
// (neighbour vertices and faces); boundary, non-manifold and seam edges are drawn in their own
// colours; faces are tinted by connected component.
#include <QCheckBox>
#include <QGridLayout>
#include <QLabel>
#include <QPixmap>
#include <QPointer>
#include <QSignalBlocker>
#include <QVBoxLayout>
#include <algorithm>
#include <set>
#include <sstream>

#include "deepcut/core/adjacency.h"
#include "deepcut/core/errors.h"
#include "deepcut/plugins/colors.h"
#include "deepcut/plugins/inspector_registry.h"

namespace deepcut::plugins {
namespace {

struct PieceTopology {
  Adjacency adjacency;
  std::vector<Edge> boundary, nonmanifold, seams;
  std::vector<std::uint32_t> component;  // per vertex
  std::size_t components = 0;
  std::size_t vertices = 0;  // referenced
};

class AdjacencyInspector final : public Inspector {
 public:
  std::string id() const override { return "adjacency"; }
  std::string title() const override { return "Adjacency"; }

  QWidget* create_panel(QWidget* parent) override;
  void set_scene(const Scene& scene, SceneChange change) override;
  PieceColors piece_colors(std::size_t piece) const override;
  Overlay overlay() const override;
  std::vector<std::string> summary() const override;
  std::optional<Focus> focus() const override;
  bool pick(const Pick& pick) override;
  void set_option(const std::string& name, const std::string& value) override;

 private:
  bool has_pick() const { return scene_ && picked_piece_ < topology_.size(); }
  std::size_t total(std::vector<Edge> PieceTopology::*edges) const {
    std::size_t n = 0;
    for (const PieceTopology& t : topology_) n += (t.*edges).size();
    return n;
  }
  void refresh_panel();

  const Scene* scene_ = nullptr;
  std::vector<PieceTopology> topology_;
  std::size_t component_total_ = 0, edge_total_ = 0;
  std::size_t picked_piece_ = Pick::kNoPiece;
  VertexId picked_vertex_;
  bool show_boundary_ = true, show_nonmanifold_ = true, show_seams_ = true, tint_components_ = true;

  QPointer<QLabel> counts_, picked_label_;
  QPointer<QCheckBox> boundary_box_, nonmanifold_box_, seam_box_, component_box_;
};

void AdjacencyInspector::set_scene(const Scene& scene, SceneChange change) {
  scene_ = &scene;
  if (change == SceneChange::Pose) return;
  topology_.clear();
  component_total_ = edge_total_ = 0;
  picked_piece_ = Pick::kNoPiece;
  for (const SceneInstance& piece : scene.pieces) {
    PieceTopology t;
    t.adjacency = Adjacency::build(*piece.surface);
    t.boundary = t.adjacency.boundary_edges();
    t.nonmanifold = t.adjacency.nonmanifold_edges();
    t.seams = t.adjacency.seam_edges(*piece.surface);
    t.component = t.adjacency.vertex_components(&t.components);
    for (std::uint32_t c : t.component) t.vertices += c != kInvalidIndex;
    component_total_ += t.components;
    edge_total_ += t.adjacency.edge_count();
    topology_.push_back(std::move(t));
  }
  refresh_panel();
}

PieceColors AdjacencyInspector::piece_colors(std::size_t piece) const {
  PieceColors out;
  if (!scene_ || piece >= topology_.size()) return out;
  const SurfaceMesh& mesh = *scene_->pieces[piece].surface;
  const PieceTopology& t = topology_[piece];
  out.kind = PieceColors::Kind::PerFace;
  out.colors.assign(mesh.face_slots(), to_rgb8(palette::kNeutral));
  // Offset the component numbering per piece so pieces differ too.
  std::size_t offset = 0;
  for (std::size_t i = 0; i < piece; ++i) offset += topology_[i].components;
  if (tint_components_)
    mesh.for_each_face([&](FaceId f, const Triangle& tri) {
      const std::uint32_t c = t.component[tri[0].index];
      // Start three hues in, away from the orange of the one-ring highlight.
      out.colors[f.index] = to_rgb8(pastel(category_color(offset + c + 3), 0.5f));
    });
  if (has_pick() && picked_piece_ == piece)
    for (FaceId f : t.adjacency.vertex_faces(picked_vertex_))
      out.colors[f.index] = to_rgb8(palette::kHighlight);
  return out;
}

Overlay AdjacencyInspector::overlay() const {
  Overlay overlay;
  if (!scene_) return overlay;
  auto add_edges = [&](std::vector<Edge> PieceTopology::*edges, const glm::vec3& color, float width) {
    OverlayLines lines;
    lines.color = color;
    lines.width_px = width;
    for (std::size_t i = 0; i < topology_.size(); ++i)
      for (const Edge& e : topology_[i].*edges) {
        lines.endpoints.push_back(scene_->pieces[i].posed()[e.a.index]);
        lines.endpoints.push_back(scene_->pieces[i].posed()[e.b.index]);
      }
    if (!lines.endpoints.empty()) overlay.lines.push_back(std::move(lines));
  };
  if (show_seams_) add_edges(&PieceTopology::seams, palette::kSeam, 2.0f);
  if (show_boundary_) add_edges(&PieceTopology::boundary, palette::kBoundary, 3.0f);
  if (show_nonmanifold_) add_edges(&PieceTopology::nonmanifold, palette::kNonManifold, 4.0f);
  if (has_pick()) {
    const auto& posed = scene_->pieces[picked_piece_].posed();
    const glm::vec3 center = posed[picked_vertex_.index];
    OverlayLines spokes;
    spokes.color = palette::kHighlight;
    spokes.width_px = 3.0f;
    spokes.on_top = true;
    OverlayPoints ring;
    ring.color = glm::vec3(1.0f, 0.9f, 0.2f);
    ring.size_px = 10.0f;
    ring.on_top = true;
    for (VertexId n : topology_[picked_piece_].adjacency.vertex_neighbors(picked_vertex_)) {
      spokes.endpoints.push_back(center);
      spokes.endpoints.push_back(posed[n.index]);
      ring.positions.push_back(posed[n.index]);
    }
    OverlayPoints picked;
    picked.positions = {center};
    picked.color = palette::kPicked;
    picked.size_px = 15.0f;
    picked.on_top = true;
    overlay.lines.push_back(std::move(spokes));
    overlay.points.push_back(std::move(ring));
    overlay.points.push_back(std::move(picked));
  }
  return overlay;
}

std::vector<std::string> AdjacencyInspector::summary() const {
  std::vector<std::string> lines;
  if (!scene_) return lines;
  std::size_t vertices = 0, faces = 0;
  for (std::size_t i = 0; i < topology_.size(); ++i) {
    vertices += topology_[i].vertices;
    faces += scene_->pieces[i].surface->face_count();
  }
  std::ostringstream a, b;
  a << vertices << " vertices, " << edge_total_ << " edges, " << faces << " faces; " << component_total_
    << (component_total_ == 1 ? " component" : " components");
  b << total(&PieceTopology::boundary) << " boundary, " << total(&PieceTopology::nonmanifold)
    << " non-manifold, " << total(&PieceTopology::seams) << " seam edges";
  lines.push_back(a.str());
  lines.push_back(b.str());
  if (has_pick()) {
    const Adjacency& adj = topology_[picked_piece_].adjacency;
    const auto neighbours = adj.vertex_neighbors(picked_vertex_);
    std::size_t open = 0;
    for (VertexId n : neighbours) open += adj.edge_faces(picked_vertex_, n).size() != 2;
    std::ostringstream c;
    c << "Vertex " << picked_vertex_.index << ": " << neighbours.size() << " neighbour vertices, "
      << adj.vertex_faces(picked_vertex_).size() << " faces"
      << (open ? ", on a boundary or non-manifold edge" : "");
    lines.push_back(c.str());
  }
  return lines;
}

std::optional<Focus> AdjacencyInspector::focus() const {
  if (!has_pick()) return std::nullopt;
  const auto& posed = scene_->pieces[picked_piece_].posed();
  const glm::vec3 center = posed[picked_vertex_.index];
  float reach = 0.0f;
  for (VertexId n : topology_[picked_piece_].adjacency.vertex_neighbors(picked_vertex_))
    reach = std::max(reach, glm::distance(center, posed[n.index]));
  return Focus{center, reach > 0.0f ? 7.0f * reach : 0.05f * scene_->size};
}

bool AdjacencyInspector::pick(const Pick& pick) {
  if (!scene_ || pick.piece >= topology_.size() || !pick.vertex.valid() ||
      pick.vertex.index >= topology_[pick.piece].adjacency.vertex_count())
    return false;
  picked_piece_ = pick.piece;
  picked_vertex_ = pick.vertex;
  refresh_panel();
  return true;
}

void AdjacencyInspector::set_option(const std::string& name, const std::string& value) {
  if (name == "vertex") {
    std::size_t used = 0;
    unsigned long index = 0;
    try {
      index = std::stoul(value, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != value.size() || value.empty())
      throw Error(ErrorCode::InvalidArgument,
                  "adjacency: vertex must be a vertex number, not '" + value + "'");
    if (!scene_ || topology_.empty() || index >= topology_[0].adjacency.vertex_count() ||
        topology_[0].adjacency.vertex_faces(VertexId(static_cast<std::uint32_t>(index))).empty())
      throw Error(ErrorCode::InvalidArgument,
                  "adjacency: vertex " + value + " is not a vertex of the first mesh");
    picked_piece_ = 0;
    picked_vertex_ = VertexId(static_cast<std::uint32_t>(index));
    refresh_panel();
    return;
  }
  Inspector::set_option(name, value);
}

QCheckBox* edge_box(const QString& text, const glm::vec3& color, QWidget* parent) {
  auto* box = new QCheckBox(text, parent);
  QPixmap pixmap(14, 14);
  pixmap.fill(QColor::fromRgbF(color.r, color.g, color.b));
  box->setIcon(QIcon(pixmap));
  box->setChecked(true);
  return box;
}

QWidget* AdjacencyInspector::create_panel(QWidget* parent) {
  auto* panel = new QWidget(parent);
  auto* layout = new QVBoxLayout(panel);
  layout->setContentsMargins(6, 6, 6, 6);
  auto* hint =
      new QLabel("Click a vertex in the view: its one-ring faces turn orange, its neighbours yellow.", panel);
  hint->setWordWrap(true);
  layout->addWidget(hint);
  boundary_box_ = edge_box("Boundary edges", palette::kBoundary, panel);
  nonmanifold_box_ = edge_box("Non-manifold edges", palette::kNonManifold, panel);
  seam_box_ = edge_box("Seam edges (UV / normal)", palette::kSeam, panel);
  component_box_ = new QCheckBox("Tint faces by component", panel);
  component_box_->setChecked(true);
  for (QCheckBox* box :
       {boundary_box_.data(), nonmanifold_box_.data(), seam_box_.data(), component_box_.data()})
    layout->addWidget(box);
  counts_ = new QLabel(panel);
  counts_->setWordWrap(true);
  counts_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  picked_label_ = new QLabel(panel);
  picked_label_->setWordWrap(true);
  picked_label_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  layout->addWidget(counts_);
  layout->addWidget(picked_label_);
  layout->addStretch(1);
  auto bind = [this, panel](QCheckBox* box, bool* flag) {
    QObject::connect(box, &QCheckBox::toggled, panel, [this, flag](bool on) {
      *flag = on;
      notify_changed();
    });
  };
  bind(boundary_box_, &show_boundary_);
  bind(nonmanifold_box_, &show_nonmanifold_);
  bind(seam_box_, &show_seams_);
  bind(component_box_, &tint_components_);
  refresh_panel();
  return panel;
}

void AdjacencyInspector::refresh_panel() {
  if (!counts_) return;
  const auto lines = summary();
  QString text;
  for (std::size_t i = 0; i < lines.size() && i < 2; ++i) text += QString::fromStdString(lines[i]) + "\n";
  if (scene_ && topology_.size() > 1) {
    for (std::size_t i = 0; i < topology_.size(); ++i)
      text += QString("  piece %1 (%2): %3 components\n")
                  .arg(i)
                  .arg(QString::fromStdString(node_label(*scene_->model, scene_->pieces[i].node)))
                  .arg(topology_[i].components);
  }
  counts_->setText(text.trimmed());
  {
    const QSignalBlocker a(boundary_box_.data()), b(nonmanifold_box_.data()), c(seam_box_.data());
    boundary_box_->setText(QString("Boundary edges (%1)").arg(total(&PieceTopology::boundary)));
    nonmanifold_box_->setText(QString("Non-manifold edges (%1)").arg(total(&PieceTopology::nonmanifold)));
    seam_box_->setText(QString("Seam edges, UV / normal (%1)").arg(total(&PieceTopology::seams)));
  }
  picked_label_->setText(lines.size() > 2 ? QString::fromStdString(lines[2]) : QString("No vertex picked."));
}

}  // namespace

void register_adjacency(InspectorRegistry& registry) {
  registry.add({"adjacency", "Adjacency", [] { return std::make_unique<AdjacencyInspector>(); }});
}

}  // namespace deepcut::plugins
