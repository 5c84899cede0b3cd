// SPDX-License-Identifier: MIT
// MainWindow's open: a file read, posed and built for the view off the UI thread, swapped in,
// drawn, then indexed for the operations in the background.
#include <QDockWidget>
#include <QElapsedTimer>
#include <QFileInfo>
#include <QMetaObject>
#include <QStatusBar>
#include <QString>
#include <QStringList>
#include <memory>
#include <utility>
#include <vector>

#include "deepcut/core/errors.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/process_memory.h"
#include "deepcut/plugins/formats.h"
#include "main_window.h"
#include "operations_host.h"
#include "problems_panel.h"
#include "recent_files.h"
#include "scene_host.h"
#include "scene_view.h"
#include "timeline.h"
#include "tool_host.h"

namespace deepcut::studio {

bool MainWindow::open_file(const QString& path) {
  if (!begin_open(path)) return false;
  task_->wait();
  draw_first_frame();
  task_->wait();  // the operations' posed model, built after the first frame
  scene_host_->complete_normals();  // (what the index job did not make)
  return open_done_;
}

bool MainWindow::begin_open(const QString& path) {
  finish_indexing();
  if (task_->busy()) {
    report_error(QFileInfo(path).fileName() + ": not opened, " + task_->text() + " is still running");
    return false;
  }
  open_done_ = false;
  auto clock = std::make_shared<QElapsedTimer>();
  clock->start();
  view_->warm_up();  // the shaders compile while the worker reads (the UI thread waits then)
  const QString name = QFileInfo(path).fileName();
  return task_->start(
      "Opening " + name, 5, open_job(path, clock),
      [this, name](std::exception_ptr error) {
        view_->hold_renders(false);  // a swap-in that failed half-way still draws
        refresh_status();
        report_exception(error, name);
      },
      [this, name] { statusBar()->showMessage("Opening " + name + " cancelled: nothing changed", 8000); });
}

void MainWindow::report_exception(std::exception_ptr error, const QString& file) {
  try {
    std::rethrow_exception(error);
  } catch (const Error& e) {
    report_error(QString::fromStdString(e.what()));
  } catch (const std::bad_alloc&) {
    report_error(file + ": out of memory");
  } catch (const std::exception& e) {
    report_error(file + ": internal error: " + e.what());
  }
}

void MainWindow::load_file(const QString& path) {
  auto clock = std::make_shared<QElapsedTimer>();
  clock->start();
  TaskProgress progress;  // on this thread: no Cancel
  open_job(path, clock)(progress)();
  first_frame_pending_ = false;
  draw_frame_and_index(false);
}

BackgroundTask::Job MainWindow::open_job(const QString& path, std::shared_ptr<QElapsedTimer> clock) {
  // Off the UI thread: everything that does not touch the window or the session. The window
  // changes only in the Deliver, so a failure or Cancel keeps the old model.
  return [this, path, clock](TaskProgress& progress) -> BackgroundTask::Deliver {
    auto opened = std::make_shared<OpenedModel>();
    progress.stage("Reading");
    Model loaded = plugins::read_model(path.toStdString());
    opened->timing.read_ms = ms_since(*clock);
    progress.stage("Preparing");
    reserve_for_operations(loaded);  // room to grow: the first operations do not reallocate
    opened->model = std::make_shared<const Model>(std::move(loaded));
    progress.stage("Posing");
    const int animation = opened->model->animations.empty() ? -1 : 0;
    // Without the corner normals: the view poses one per drawn point for the first frame, and
    // the scene gets them after it (SceneHost::complete_normals).
    opened->scene = plugins::make_scene(opened->model, animation, 0.0f, /*with_normals=*/false);
    opened->timing.posed_ms = ms_since(*clock);
    progress.stage("Building the view");
    opened->drawn = SceneView::prepare(opened->scene);
    opened->timing.prepared_ms = ms_since(*clock);
    progress.stage("Drawing");
    return [this, path, clock, opened] { show_opened(path, std::move(*opened), *clock); };
  };
}

void MainWindow::show_opened(const QString& path, OpenedModel opened, const QElapsedTimer& clock) {
  open_timing_ = opened.timing;
  open_timing_.delivered_ms = ms_since(clock);
  std::vector<std::pair<QString, float>> clips;
  for (const Animation& a : opened.model->animations)
    clips.emplace_back(QString::fromStdString(a.name), a.duration());
  // The swap-in: every step below may ask for a frame; the view draws one, at the end. The
  // status bar and the recent files follow that frame (draw_frame_and_index).
  view_->hold_renders(true);
  status_held_ = true;
  struct Release {
    bool& held;
    ~Release() { held = false; }
  } release{status_held_};
  path_ = path;
  open_done_ = true;
  operations_->open(opened.model, nullptr);  // the scene draws the live model; posed after the first frame
  timeline_->set_animations(clips);
  const std::vector<std::string> notes =
      scene_host_->show_opened(std::move(opened.scene), QFileInfo(path).fileName(), std::move(opened.drawn));
  setWindowTitle(QFileInfo(path).fileName() + " - DeepCut Studio");
  last_error_.clear();
  operations_->refresh_list();
  // What reading repaired or dropped: the Problems panel lists it, the status bar points at it.
  problems_->set_problems(QFileInfo(path).fileName(), opened.model->import_problems);
  problems_dock_->setVisible(!problems_->lines().isEmpty());
  QStringList status;
  if (!notes.empty()) status << QString::fromStdString(notes.front());
  if (!problems_->summary().isEmpty()) status << problems_->summary();
  if (!status.isEmpty()) statusBar()->showMessage(status.join("; "), 15000);
  open_timing_.swap_ms = ms_since(clock) - open_timing_.delivered_ms;
  emit model_changed();
  // The first frame in the next turn of the event loop: what is queued runs between the two. Posted, not
  // a zero timer: it runs before the swap-in's repaint requests (low priority), so one repaint shows all.
  open_clock_ = clock;
  first_frame_pending_ = true;
  QMetaObject::invokeMethod(this, &MainWindow::draw_first_frame, Qt::QueuedConnection);
}

void MainWindow::draw_first_frame() {
  if (!first_frame_pending_) return;
  first_frame_pending_ = false;
  draw_frame_and_index(true);
}

void MainWindow::draw_frame_and_index(bool in_background) {
  open_timing_.frame_begin = std::chrono::steady_clock::now();
  view_->hold_renders(false);
  open_timing_.frame_end = std::chrono::steady_clock::now();
  open_timing_.first_frame_ms =
      std::chrono::duration<double, std::milli>(open_timing_.frame_end - open_timing_.frame_begin).count();
  open_timing_.total_ms = ms_since(open_clock_);
  RecentFiles::remember(path_);
  note_operation("Open " + QFileInfo(path_).fileName(), open_timing_.total_ms);
  // Then the operations' posed model (positions again, with the grids the tools search), off
  // the UI thread while edits wait for it: an operation never finds a half-built one.
  if (in_background) {
    start_indexing();
  } else if (session().current() && scene()) {
    TaskProgress progress;
    index_job(session().current(), scene_host_->pose_key())(progress)();
    scene_host_->complete_normals();  // (what the index job did not make)
  }
}

bool MainWindow::start_indexing() {
  const std::shared_ptr<const Model> model = session().current();
  if (!model || !scene()) return true;  // nothing to index
  if (task_->busy()) return false;
  const QString name = QFileInfo(path_).fileName();
  indexing_ = task_->start(
      "Indexing " + name, 1, index_job(model, scene_host_->pose_key()),
      [this, name](std::exception_ptr error) {
        indexing_ = false;
        report_exception(error, name);
      },
      [this] { indexing_ = false; });  // the first operation builds it
  return indexing_;
}

void MainWindow::finish_indexing() {
  if (indexing_) task_->wait();
}

BackgroundTask::Job MainWindow::index_job(std::shared_ptr<const Model> model, const PoseKey& key) {
  const std::uint64_t version = session().state_version();
  // The scene's instances without corner normals (an open's scene: its first frame posed a
  // normal per drawn point only), as (node, primitive), else (-1, -1): this posed model (the
  // same pose: the same bits) makes theirs too, handed to the scene with it.
  std::vector<std::pair<int, int>> bare;
  if (scene() && scene()->model == model)
    for (const plugins::SceneInstance& i : scene()->instances)
      bare.push_back(i.posed_normals.empty() ? std::pair(i.node, i.primitive) : std::pair(-1, -1));
  return [this, model, key, version, bare](TaskProgress& progress) -> BackgroundTask::Deliver {
    progress.stage("Indexing");
    auto posed = std::make_shared<std::unique_ptr<PosedModel>>(
        std::make_unique<PosedModel>(PosedModel::build(*model, key, PoseDetail::Full)));
    auto normals = std::make_shared<std::vector<std::vector<glm::vec3>>>(bare.size());
    for (std::size_t i = 0; i < bare.size(); ++i)
      if (const PosedMesh* pose = (*posed)->find(bare[i].first, bare[i].second))
        (*normals)[i] = pose->corner_normals(model->meshes[static_cast<std::size_t>(pose->mesh)]
                                                 .primitives[static_cast<std::size_t>(pose->primitive)]
                                                 .mesh);
    return [this, model, key, posed, normals, version] {
      indexing_ = false;
      scene_host_->adopt_normals(std::move(*normals), model.get(), key);
      scene_host_->adopt_posed_model(std::move(*posed), model.get(), version);
      release_freed_memory();  // the open is over: what the last model held and this one did not reuse
    };
  };
}

}  // namespace deepcut::studio
