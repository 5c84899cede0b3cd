// SPDX-License-Identifier: MIT
#include "scene_host.h"

#include <QTimer>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <ctime>

#include "inspector_host.h"
#include "morph_panel.h"
#include "scene_tree.h"
#include "scene_view.h"
#include "thread_cpu_time.h"
#include "timeline.h"
#include "tool_host.h"

namespace deepcut::studio {
namespace {

/// `posed` when every instance has its grid, else nullptr (one lent to a cut has none:
/// OperationsHost::lend_scene_pose).
const PosedModel* with_grids(const PosedModel* posed) {
  if (!posed) return nullptr;
  for (const auto& entry : posed->instances())
    if (entry.second.gridless) return nullptr;
  return posed;
}

}  // namespace

SceneHost::SceneHost(SceneView* view, SceneTree* tree, Timeline* timeline, ToolHost* tools,
                     InspectorHost* inspectors, session::Session& session, QObject* parent)
    : QObject(parent),
      view_(view),
      tree_(tree),
      timeline_(timeline),
      tools_(tools),
      inspectors_(inspectors),
      session_(session) {
  // The session's posed model changes: the scene gives back the grids it lent.
  session_.set_posed_model_listener([this] { tools_->lend_grids(nullptr, nullptr); });
  posed_timer_ = new QTimer(this);
  posed_timer_->setSingleShot(true);
  posed_timer_->setInterval(300);
  connect(posed_timer_, &QTimer::timeout, this, [this] {
    if (timeline_->playing()) return;  // playing: re-posing every frame; the next stop rebuilds
    rebuild_posed_model();
  });
}

SceneHost::~SceneHost() = default;

std::vector<std::string> SceneHost::show_opened(plugins::Scene scene, const QString& title,
                                               std::shared_ptr<const SceneView::Prepared> prepared) {
  if (!scene_) {
    scene_ = std::make_unique<plugins::Scene>();
    tools_->set_scene(scene_.get());
    inspectors_->set_scene(scene_.get());
  }
  *scene_ = std::move(scene);
  // The session edits a model of its own (a copy of the one the scene was built from, when the
  // scene holds it too): the scene draws that one, as a step that changed nothing.
  if (session_.current() && session_.current() != scene_->model)
    plugins::follow_scene(*scene_, session_.current(), ModelChange{});
  title_ = title;
  if (morph_) {  // a new model: its weights follow the animation
    morph_->set_scene(nullptr);
    morph_->set_scene(scene_.get());
  }
  // The operations' posed model comes after the first frame (adopt_posed_model); an operation
  // made before builds it.
  posed_timer_->stop();
  std::vector<std::string> notes = present(std::move(prepared));
  refresh_inspector();
  view_->reset_camera();
  tools_->forget_pick();
  tools_->place_on_new_scene();
  view_->render();
  return notes;
}

void SceneHost::adopt_normals(std::vector<std::vector<glm::vec3>> normals, const Model* built_for,
                              const PoseKey& key) {
  if (!scene_ || scene_->model.get() != built_for || !(pose_key() == key) ||
      normals.size() != scene_->instances.size())
    return;
  for (std::size_t i = 0; i < normals.size(); ++i) {
    plugins::SceneInstance& instance = scene_->instances[i];
    if (instance.posed_normals.empty() && normals[i].size() == 3 * instance.surface->face_slots())
      instance.posed_normals = std::move(normals[i]);
  }
}

void SceneHost::complete_normals() {
  if (!scene_) return;
  for (plugins::SceneInstance& instance : scene_->instances)
    if (instance.posed_normals.empty() && instance.pose)
      instance.posed_normals = instance.pose->corner_normals(*instance.surface);
}

PoseKey SceneHost::pose_key() const { return PoseKey(scene_->animation, scene_->time, scene_->weights); }

void SceneHost::adopt_posed_model(std::unique_ptr<PosedModel> posed, const Model* built_for, std::uint64_t version) {
  if (!scene_ || !posed || !posed->matches(pose_key())) return;  // posed again meanwhile: the timer rebuilds
  if (!session_.adopt_posed_model(std::move(posed), built_for, version)) return;
  // The previews follow the grids from the next pointer move: with them or by a scan of every
  // posed triangle they draw the same lines, so the one shown stays (redrawing it costs a frame).
  lend_grids();
}

std::vector<std::string> SceneHost::present(std::shared_ptr<const SceneView::Prepared> prepared) {
  skeleton_drawn_ = false;  // a new scene: its skeleton is drawn anew
  lend_grids();
  std::vector<std::string> notes = view_->set_scene(*scene_, std::move(prepared));
  tools_->scene_redrawn();
  tree_->set_scene(*scene_);
  inspectors_->mark_stale(plugins::SceneChange::Model);
  return notes;
}

void SceneHost::show_current() {
  const std::shared_ptr<const Model>& model = session_.current();
  int animation = timeline_->animation();
  if (animation >= static_cast<int>(model->animations.size())) animation = model->animations.empty() ? -1 : 0;
  *scene_ = plugins::make_scene(model, PoseKey(animation, timeline_->time(), scene_->weights));
  sync_morph_panel();
  present();
  tools_->update_preview();
  refresh_inspector();  // draws the step's one frame
  // Undo, redo or an edit: the posed model describes another state; a cut dropped it (its
  // pieces are new meshes). Rebuild it when idle.
  if (!session_.posed_model()) posed_timer_->start();
}

bool SceneHost::sync_morph_panel() {
  if (!morph_) return false;
  morph_->set_scene(scene_.get());  // drops weights set for nodes that no longer morph alike
  bool posed = false;
  if (morph_->overrides() != scene_->weights) {
    scene_->weights = morph_->overrides();
    plugins::pose_scene(*scene_, scene_->animation, scene_->time);
    posed = true;
  }
  morph_->show_pose();
  return posed;
}

void SceneHost::show_step(const ModelChange& change) {
  // DEEPCUT_VIEW_REBUILD=1: every step builds the scene again (the studio benchmark's reference).
  const char* rebuild = std::getenv("DEEPCUT_VIEW_REBUILD");
  const bool follow = !(rebuild && std::strcmp(rebuild, "1") == 0);
  using Clock = std::chrono::steady_clock;
  auto cpu_ms = [] { return 1e3 * static_cast<double>(std::clock()) / CLOCKS_PER_SEC; };
  const auto t0 = Clock::now();
  const double c0 = cpu_ms();
  const long f0 = process_minor_faults();
  if (!scene_ || !session_.current() || !follow || !plugins::follow_scene(*scene_, session_.current(), change)) {
    step_timing_ = {};
    if (scene_) show_current();
    return;
  }
  const auto t1 = Clock::now();
  const double c1 = cpu_ms();
  const long f1 = process_minor_faults();
  view_->update_scene(change);
  step_timing_.scene_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
  step_timing_.view_ms = std::chrono::duration<double, std::milli>(Clock::now() - t1).count();
  step_timing_.scene_cpu_ms = c1 - c0;
  step_timing_.view_cpu_ms = cpu_ms() - c1;
  step_timing_.faults_at_start = f0;
  step_timing_.scene_faults = f1 - f0;
  step_timing_.view_faults = process_minor_faults() - f1;
  // A structural step may add or drop nodes that morph: the panel follows (re-posing the
  // scene when the weights set by hand change).
  if (change.structure && sync_morph_panel()) view_->update_pose();
  lend_grids();
  tools_->scene_redrawn();
  tree_->set_scene(*scene_);
  inspectors_->mark_stale(plugins::SceneChange::Model);
  tools_->update_preview();
  draw_frame();  // the step's one frame
  if (change.structure) QTimer::singleShot(0, view_, [view = view_] { view->prepare_updates(); });
  if (!session_.posed_model()) posed_timer_->start();
}

void SceneHost::pose(int animation, float time) {
  if (!scene_) return;
  posed_timer_->start();                 // the operations' posed model follows once the pose stays put
  tools_->lend_grids(nullptr, nullptr);  // its grids are filed at the previous pose
  plugins::pose_scene(*scene_, animation, time);
  if (morph_) morph_->show_pose();
  view_->update_pose();
  tools_->scene_redrawn();
  tools_->show_displacement();
  inspectors_->mark_stale(plugins::SceneChange::Pose);
  inspectors_->sync();
  tools_->update_preview();
  draw_overlays();
  view_->render();
  emit overlays_changed();
}

void SceneHost::rebuild_posed_model() {
  // While a past operation is edited the posed model describes the edit's base, which the
  // session keeps apart from the live model: it is brought up to date in place.
  if (!posed_builder_ || session_.editing() >= 0) return refresh_posed_model();
  if (!session_.current() || !scene_) return;
  const PosedModel* posed = with_grids(session_.posed_model());
  if (posed && posed->matches(pose_key())) return;  // it followed the step
  if (!posed_builder_()) posed_timer_->start();      // another task runs: ask again once idle
}

void SceneHost::refresh_posed_model() {
  if (!session_.current() || !scene_) return;
  if (!session_.refresh_posed_model(PoseKey(scene_->animation, scene_->time, scene_->weights))) return;
  // As adopt_posed_model: the previews follow the grids from the next pointer move (they draw
  // the same lines with or without them), so the one shown stays.
  lend_grids();
}

void SceneHost::set_morph_panel(MorphPanel* panel) {
  morph_ = panel;
  morph_->set_scene(scene_.get());
  connect(morph_, &MorphPanel::weights_changed, this, [this] {
    if (!scene_) return;
    scene_->weights = morph_->overrides();
    pose(scene_->animation, scene_->time);
  });
}

void SceneHost::lend_grids() {
  const PosedModel* posed = session_.posed_model();
  // One without grids (lent to a cut that missed) is built again with them once idle.
  if (posed && !with_grids(posed)) posed_timer_->start();
  tools_->lend_grids(session_.current(), with_grids(posed));
}

void SceneHost::refresh_inspector() {
  if (!scene_) return;
  draw_frame();
}

void SceneHost::draw_frame() {
  inspectors_->draw_colors();
  draw_overlays();
  view_->render();
  emit overlays_changed();  // the status bar follows once the frame is asked for
}

void SceneHost::refresh_overlays() {
  if (!scene_) return;
  draw_overlays();
  emit overlays_changed();
}

void SceneHost::draw_overlays() {
  const Model& model = *scene_->model;
  const bool skeleton = show_skeleton_ && !model.skins.empty();
  std::vector<BoneHandle> handles;
  if (skeleton) {
    auto origin = [&](int node) { return glm::vec3(scene_->world[static_cast<std::size_t>(node)][3]); };
    for (int j : plugins::joint_nodes(model)) handles.push_back({j, origin(j), origin(j)});
    for (const auto& [parent, child] : plugins::skeleton_bones(model))
      handles.push_back({parent, origin(parent), origin(child)});
  }
  // The skeleton overlay draws the joints and bones the handles hold: the same handles, the same
  // overlay, already drawn (a step that leaves the joints where they were).
  auto same = [](const BoneHandle& a, const BoneHandle& b) { return a.joint == b.joint && a.head == b.head && a.tail == b.tail; };
  if (!skeleton_drawn_ || !std::equal(handles.begin(), handles.end(), drawn_bones_.begin(), drawn_bones_.end(), same)) {
    view_->set_overlay(SceneView::Layer::Skeleton, skeleton ? plugins::skeleton_overlay(*scene_) : Overlay{});
    drawn_bones_ = handles;
    skeleton_drawn_ = true;
    view_->set_bone_handles(std::move(handles));
  }
  plugins::Inspector* active = inspectors_->inspector();
  view_->set_overlay(SceneView::Layer::Inspector, active ? active->overlay() : Overlay{});
  std::vector<std::string> caption = {title_.toStdString() + "  |  " +
                                      (active ? active->title() : std::string("Materials"))};
  if (active)
    for (const std::string& line : active->summary()) caption.push_back(line);
  view_->set_caption(caption);
}

void SceneHost::set_skeleton_visible(bool visible) {
  show_skeleton_ = visible;
  refresh_overlays();
  view_->render();
}

bool SceneHost::frame_selected() {
  const plugins::Inspector* active = inspectors_->inspector();
  const auto focus = active ? active->focus() : std::nullopt;
  if (!focus) return false;
  view_->frame(focus->center, focus->radius);
  view_->render();
  return true;
}

void SceneHost::pick(const plugins::Pick& pick) {
  if (!scene_) return;
  tools_->note_pick(pick);
  bool changed = false;
  if (inspectors_->pick(pick, changed)) {
    if (changed) refresh_inspector();
    return;
  }
  if (pick.joint_node >= 0)
    emit note(QString("Joint %1 (Inspect > Skin weights shows its weights)")
                  .arg(QString::fromStdString(plugins::node_label(*scene_->model, pick.joint_node))),
              8000);
  else if (pick.instance < scene_->instances.size())
    emit note(QString("Instance %1, vertex %2, face %3")
                  .arg(pick.instance)
                  .arg(pick.vertex.index)
                  .arg(pick.face.index),
              8000);
}

}  // namespace deepcut::studio
