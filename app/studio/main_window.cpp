// SPDX-License-Identifier: MIT
#include "main_window.h"

#include <QAction>
#include <QActionGroup>
#include <QApplication>
#include <QCloseEvent>
#include <QComboBox>
#include <QDir>
#include <QDockWidget>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QElapsedTimer>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QGridLayout>
#include <QLabel>
#include <QListWidget>
#include <QMenuBar>
#include <QMessageBox>
#include <QMimeData>
#include <QSettings>
#include <QStatusBar>
#include <QStyle>
#include <QTimer>
#include <QToolBar>
#include <QUndoStack>
#include <QUrl>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <new>

#include "deepcut/core/errors.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/ops/operation.h"
#include "deepcut/core/process_memory.h"
#include "deepcut/plugins/formats.h"
#include "deepcut/plugins/inspector_registry.h"
#include "inspector_host.h"
#include "morph_panel.h"
#include "operations_host.h"
#include "problems_panel.h"
#include "recent_files.h"
#include "scene_host.h"
#include "scene_tree.h"
#include "scene_view.h"
#include "timeline.h"
#include "tool_host.h"

namespace deepcut::studio {
namespace {

/// An export target: the exporter writes glTF only.
bool is_model_file(const QString& path) {
  return QStringList{"glb", "gltf"}.contains(QFileInfo(path).suffix().toLower());
}

/// A file some format plugin opens (.glb, .gltf, .obj, .ply, .stl, .off, ...).
bool is_openable_file(const QString& path) { return plugins::find_format(plugins::builtin_formats(), path.toStdString()) != nullptr; }

/// "All models (*.glb *.gltf *.obj ...);;glTF (*.glb *.gltf);;Wavefront OBJ (*.obj);;...;;All files (*)".
QString open_filters() {
  QStringList all, each;
  for (const plugins::ModelFormat& format : plugins::builtin_formats().list()) {
    QStringList patterns;
    for (const std::string& ext : format.extensions) patterns << "*." + QString::fromStdString(ext);
    all << patterns;
    each << QString::fromStdString(format.name) + " (" + patterns.join(' ') + ")";
  }
  return "All models (" + all.join(' ') + ");;" + each.join(";;") + ";;All files (*)";
}

QString thousands(std::size_t n) { return QLocale(QLocale::English).toString(static_cast<qulonglong>(n)); }

}  // namespace

double MainWindow::ms_since(const QElapsedTimer& clock) {
  return static_cast<double>(clock.nsecsElapsed()) / 1e6;
}

MainWindow::MainWindow(const MainWindowOptions& options, QWidget* parent)
    : QMainWindow(parent), options_(options) {
  setWindowTitle("DeepCut Studio");
  setObjectName("main_window");
  setAcceptDrops(true);
  setDockNestingEnabled(true);
  resize(1400, 880);
  build_hosts();
  build_docks();
  build_scene_host();
  build_menus();
  build_status_bar();
  refresh_status();
  QSettings settings;
  restoreState(settings.value("window_state").toByteArray());
}

// The view and the hosts of the inspectors, tools and operations around it.
void MainWindow::build_hosts() {
  view_ = new SceneView(this);
  setCentralWidget(view_);
  inspectors_ = new InspectorHost(view_, this);
  tools_ = new ToolHost(view_, this);
  view_->set_pick_handler([this](const plugins::Pick& pick) { scene_host_->pick(pick); });
  view_->set_pointer_handler([this](const PointerEvent& event) { return tools_->on_pointer(event); });
  connect(tools_, &ToolHost::apply_requested, this, [this] { apply_tool(); });
  connect(inspectors_, &InspectorHost::changed, this, [this] { scene_host_->refresh_inspector(); });
  connect(inspectors_, &InspectorHost::chosen, this, [this](const QString& id) { set_inspector(id.toStdString()); });
  operations_ = new OperationsHost(tools_, this);
  connect(operations_, &OperationsHost::state_changed, this, &MainWindow::show_current);
  connect(operations_, &OperationsHost::failed, this, &MainWindow::report_error);
  connect(operations_, &OperationsHost::done, this, &MainWindow::note_operation);
  connect(operations_, &OperationsHost::note, statusBar(), &QStatusBar::showMessage);
  connect(operations_, &OperationsHost::pose_requested, this, &MainWindow::set_pose);
}

// The scene host, between the view, the docks (built before), the hosts and the session.
void MainWindow::build_scene_host() {
  scene_host_ = new SceneHost(view_, tree_, timeline_, tools_, inspectors_, operations_->session(), this);
  connect(operations_, &OperationsHost::state_kept, scene_host_, &SceneHost::lend_grids);
  connect(scene_host_, &SceneHost::overlays_changed, this, &MainWindow::refresh_status);
  connect(scene_host_, &SceneHost::note, statusBar(), &QStatusBar::showMessage);
  connect(timeline_, &Timeline::pose_changed, scene_host_, &SceneHost::pose);
  scene_host_->set_morph_panel(morph_panel_);
  // After a step or a pose change the operations' posed model is rebuilt off the UI thread, and
  // an undo or redo (which edits the model it reads) waits for it.
  scene_host_->set_posed_builder([this] { return start_indexing(); });
  operations_->set_before_step([this] { finish_indexing(); });
}

// The status bar's labels and the background task, which runs the operations' and inspectors' work.
void MainWindow::build_status_bar() {
  for (QLabel** label : {&operation_label_, &time_label_, &counts_label_}) {
    *label = new QLabel(this);
    statusBar()->addPermanentWidget(*label);
  }
  operation_label_->setObjectName("status_operation");
  task_ = new BackgroundTask(statusBar(), this);
  operations_->set_task(task_);
  idle_release_ = new QTimer(this);
  idle_release_->setSingleShot(true);
  idle_release_->setInterval(kIdleReleaseMs);
  connect(idle_release_, &QTimer::timeout, this, &MainWindow::release_when_idle);
  connect(task_, &BackgroundTask::busy_changed, this, [this](bool busy) {
    set_editing_enabled(!busy);
    if (!busy) idle_release_->start();  // a task's memory too, once the studio has been idle
  });
  inspectors_->set_background_runner([this](const std::string& title, plugins::Inspector::Work work,
                                            std::function<void()> cancelled) {
    finish_indexing();
    return task_->start(
        QString::fromStdString(title), 2,
        [work = std::move(work)](TaskProgress& progress) -> BackgroundTask::Deliver {
          return work([&progress](const std::string& stage) { progress.stage(QString::fromStdString(stage)); });
        },
        [this, title](std::exception_ptr error) { report_exception(error, QString::fromStdString(title)); },
        std::move(cancelled));
  });
}

MainWindow::~MainWindow() {
  // First: a running job may read the session (a re-run), which the hosts destroyed below own.
  // The task cancels it and waits for the worker; nothing is delivered.
  delete task_;
}

void MainWindow::build_docks() {
  auto dock = [this](const QString& title, const char* name, QWidget* widget, Qt::DockWidgetArea area) {
    auto* added = new QDockWidget(title, this);
    added->setObjectName(name);
    added->setWidget(widget);
    addDockWidget(area, added);
    return added;
  };
  tree_ = new SceneTree(this);
  QDockWidget* scene_dock = dock("Scene", "scene_dock", tree_, Qt::LeftDockWidgetArea);
  problems_ = new ProblemsPanel(this);
  problems_dock_ = dock("Problems", "problems_dock", problems_, Qt::BottomDockWidgetArea);
  problems_dock_->hide();
  connect(tree_, &SceneTree::joint_selected, this, [this](int joint) {
    if (!plugins::builtin_inspectors().find("weights")) return;
    set_inspector("weights");
    plugins::Pick pick;
    pick.joint_node = joint;
    scene_host_->pick(pick);  // the inspector takes it
  });
  QDockWidget* history_dock = dock("History", "history_dock", operations_->create_panel(this), Qt::LeftDockWidgetArea);
  splitDockWidget(scene_dock, history_dock, Qt::Vertical);
  QDockWidget* inspector_dock = dock("Inspector", "inspector_dock", inspectors_->create_panel(this), Qt::RightDockWidgetArea);
  inspector_dock->setMinimumWidth(300);
  QDockWidget* tool_dock = dock("Tool", "tool_dock", tools_->create_panel(this), Qt::RightDockWidgetArea);
  splitDockWidget(inspector_dock, tool_dock, Qt::Vertical);
  morph_panel_ = new MorphPanel(this);
  QDockWidget* morph_dock = dock("Morph weights", "morph_dock", morph_panel_, Qt::LeftDockWidgetArea);
  splitDockWidget(history_dock, morph_dock, Qt::Vertical);
  resizeDocks({scene_dock, history_dock, morph_dock}, {330, 250, 200}, Qt::Vertical);
  timeline_ = new Timeline(this);
  dock("Time line", "timeline_dock", timeline_, Qt::BottomDockWidgetArea);
  resizeDocks({scene_dock, inspector_dock}, {300, 330}, Qt::Horizontal);
}

void MainWindow::build_menus() {
  QStyle* s = style();
  // File
  QMenu* file = menuBar()->addMenu("&File");
  QAction* open = file->addAction(s->standardIcon(QStyle::SP_DialogOpenButton), "&Open...", this,
                                  &MainWindow::choose_open);
  open->setShortcut(QKeySequence::Open);
  QMenu* recent = file->addMenu("Open &Recent");
  new RecentFiles(recent, [this](const QString& path) { begin_open(path); }, this);
  file->addSeparator();
  QAction* export_action = file->addAction(s->standardIcon(QStyle::SP_DialogSaveButton),
                                           "&Export .glb / .gltf...", this, &MainWindow::choose_export);
  export_action->setShortcut(QKeySequence("Ctrl+E"));
  file->addSeparator();
  edit_actions_ << open << recent->menuAction() << export_action;
  QAction* quit = file->addAction("&Quit", this, &QWidget::close);
  quit->setShortcut(QKeySequence::Quit);
  build_edit_menu();
  QAction* reset = build_view_menu();
  // Inspect: one entry per registered inspector. Tools: one per registered tool, and Apply.
  inspectors_->add_menu_actions(menuBar()->addMenu("&Inspect"));
  tools_->add_menu_actions(menuBar()->addMenu("&Tools"));

  // Animation
  QMenu* animation = menuBar()->addMenu("&Animation");
  QAction* play = animation->addAction(s->standardIcon(QStyle::SP_MediaPlay), "&Play / pause", timeline_,
                                       &Timeline::toggle_play);
  play->setShortcut(QKeySequence("Space"));
  QAction* start = animation->addAction("Go to &start", this, [this] { timeline_->set_time(0.0f); });
  start->setShortcut(QKeySequence("Shift+Left"));

  QMenu* help = menuBar()->addMenu("&Help");
  help->addAction("&About DeepCut Studio", this, [this] {
    QMessageBox::about(
        this, "About DeepCut Studio",
        "DeepCut Studio: cut, tear and drill rigged glTF models, inspect what the algorithms built, "
        "and export a rigged glTF.\n\nMouse: left drag rotates, middle drag (or Shift + left) pans, "
        "wheel zooms; click picks a vertex or a bone.");
  });
  build_toolbars(open, export_action, reset);
}

void MainWindow::build_edit_menu() {
  QStyle* s = style();
  // Edit: undo and redo follow the history (disabled while it is empty).
  QMenu* edit = menuBar()->addMenu("&Edit");
  undo_ = history()->createUndoAction(this, "&Undo");
  undo_->setShortcut(QKeySequence::Undo);
  undo_->setIcon(s->standardIcon(QStyle::SP_ArrowBack));
  redo_ = history()->createRedoAction(this, "&Redo");
  redo_->setShortcuts({QKeySequence("Ctrl+Shift+Z"), QKeySequence("Ctrl+Y")});
  redo_->setIcon(s->standardIcon(QStyle::SP_ArrowForward));
  // The menu says what would be undone ("Undo Drill (1.19, ...) r 0.35"); on the tool bar that
  // text pushed the Tools bar off the window, so the buttons say Undo / Redo and the full text
  // is their tooltip.
  undo_->setIconText("Undo");
  redo_->setIconText("Redo");
  edit->addAction(undo_);
  edit->addAction(redo_);
  edit->addSeparator();
  QAction* cancel_edit_action = edit->addAction("&Cancel operation edit", this, &MainWindow::cancel_edit);
  cancel_edit_action->setShortcut(QKeySequence(Qt::Key_Escape));
  edit_actions_ << undo_ << redo_ << cancel_edit_action;
}

void MainWindow::set_editing_enabled(bool enabled) {
  for (QAction* action : edit_actions_) action->setEnabled(enabled);
  if (enabled) {  // the undo stack's own rule
    undo_->setEnabled(history()->canUndo());
    redo_->setEnabled(history()->canRedo());
  }
  operations_list()->parentWidget()->setEnabled(enabled);  // the History panel: edit, re-run, undo view
  setAcceptDrops(enabled);
}

QAction* MainWindow::build_view_menu() {
  QStyle* s = style();
  QMenu* view = menuBar()->addMenu("&View");
  QAction* reset = view->addAction(s->standardIcon(QStyle::SP_BrowserReload), "&Reset camera", this, [this] {
    view_->reset_camera();
    view_->render();
  });
  reset->setShortcuts({QKeySequence("Home"), QKeySequence("R")});
  QAction* frame = view->addAction("&Frame selected", this, [this] {
    if (!frame_selected())
      statusBar()->showMessage("Nothing selected: pick a vertex or a joint in an inspector", 5000);
  });
  frame->setShortcuts({QKeySequence("F"), QKeySequence(".")});
  view->addSeparator();
  display_group_ = new QActionGroup(this);
  const std::pair<const char*, DisplayMode> modes[] = {{"&Shaded", DisplayMode::Shaded},
                                                       {"&Wireframe", DisplayMode::Wireframe},
                                                       {"Shaded + &edges", DisplayMode::ShadedEdges}};
  int key = 1;
  for (const auto& [text, mode] : modes) {
    QAction* action = view->addAction(text);
    action->setCheckable(true);
    action->setChecked(mode == DisplayMode::Shaded);
    action->setShortcut(QKeySequence(QString::number(key++)));
    action->setData(static_cast<int>(mode));
    display_group_->addAction(action);
    connect(action, &QAction::triggered, this, [this, m = mode] { set_display_mode(m); });
  }
  view->addSeparator();
  skeleton_action_ = view->addAction("Show s&keleton");
  skeleton_action_->setCheckable(true);
  skeleton_action_->setChecked(scene_host_->skeleton_visible());
  skeleton_action_->setShortcut(QKeySequence("K"));
  connect(skeleton_action_, &QAction::toggled, this, &MainWindow::set_skeleton_visible);
  normals_action_ = view->addAction("Show &normals");
  normals_action_->setCheckable(true);
  normals_action_->setShortcut(QKeySequence("N"));
  connect(normals_action_, &QAction::toggled, this, &MainWindow::set_normals_visible);
  build_anti_aliasing_menu(view);
  view->addSeparator();
  QMenu* panels = view->addMenu("&Panels");
  for (QDockWidget* dock : findChildren<QDockWidget*>()) panels->addAction(dock->toggleViewAction());
  return reset;
}

void MainWindow::build_anti_aliasing_menu(QMenu* view) {
  QMenu* menu = view->addMenu("&Anti-aliasing");
  const std::string& renderer = gl_renderer_name();
  const bool software = is_software_renderer(renderer);
  const QString automatic = QString("&Automatic (%1: %2)")
                                .arg(software ? "off" : "multisampling",
                                     renderer.empty() ? QString("renderer unknown") : QString::fromStdString(renderer));
  const std::pair<QString, AntiAliasing> modes[] = {{automatic, AntiAliasing::Automatic},
                                                    {QString("&Multisampling (up to %1x)").arg(kMultisamples), AntiAliasing::On},
                                                    {"O&ff", AntiAliasing::Off}};
  anti_aliasing_group_ = new QActionGroup(this);
  for (const auto& [text, mode] : modes) {
    QAction* action = menu->addAction(text);
    action->setCheckable(true);
    action->setData(static_cast<int>(mode));
    anti_aliasing_group_->addAction(action);
    connect(action, &QAction::triggered, this, [this, m = mode] { set_anti_aliasing(m); });
  }
  menu->setToolTipsVisible(true);
  menu->setToolTip("Multisampling smooths edges; on a software renderer it makes every frame several times slower");
  const auto saved = parse_anti_aliasing(QSettings().value("view/anti_aliasing").toString().toStdString());
  set_anti_aliasing(saved.value_or(AntiAliasing::Automatic), false);
}

void MainWindow::set_anti_aliasing(AntiAliasing mode, bool remember) {
  anti_aliasing_ = mode;
  for (QAction* action : anti_aliasing_group_->actions())
    action->setChecked(action->data().toInt() == static_cast<int>(mode));
  if (remember) QSettings().setValue("view/anti_aliasing", anti_aliasing_name(mode));
  const int samples = multisamples_for(mode, is_software_renderer(gl_renderer_name()));
  if (samples == view_->multisamples()) return;
  view_->set_multisamples(samples);
  view_->render();
}

void MainWindow::build_toolbars(QAction* open, QAction* export_action, QAction* reset) {
  QToolBar* tools = addToolBar("Main");
  tools->setObjectName("main_toolbar");
  tools->setToolButtonStyle(Qt::ToolButtonTextBesideIcon);
  tools->addAction(open);
  tools->addAction(export_action);
  tools->addSeparator();
  tools->addAction(undo_);
  tools->addAction(redo_);
  tools->addSeparator();
  tools->addAction(reset);
  for (QAction* action : display_group_->actions()) tools->addAction(action);
  tools->addSeparator();
  tools->addAction(skeleton_action_);
  tools->addAction(normals_action_);

  QToolBar* operation_bar = addToolBar("Tools");
  operation_bar->setObjectName("tools_toolbar");
  operation_bar->setToolButtonStyle(Qt::ToolButtonTextOnly);
  for (QAction* action : tools_->actions()) operation_bar->addAction(action);
}

QStringList MainWindow::recent_files() const { return RecentFiles::list(); }

void MainWindow::choose_open() {
  const QString dir = path_.isEmpty() ? QString() : QFileInfo(path_).absolutePath();
  const QString path = QFileDialog::getOpenFileName(this, "Open model", dir, open_filters());
  if (!path.isEmpty()) begin_open(path);
}

void MainWindow::choose_export() {
  if (!session().current()) return report_error("export: no model is open");
  const QString glb = "glTF binary (*.glb)", gltf = "glTF JSON, embedded buffers (*.gltf)";
  // Qt's own dialog (not the platform's), so it has room for the compression choice.
  QFileDialog dialog(this, "Export model", suggested_export_path(), glb + ";;" + gltf);
  dialog.setAcceptMode(QFileDialog::AcceptSave);
  dialog.setOption(QFileDialog::DontUseNativeDialog);
  auto* compression = new QComboBox(&dialog);
  compression->setObjectName("compression");
  compression->addItem("none", static_cast<int>(Compression::None));
  compression->addItem("Draco", static_cast<int>(Compression::Draco));
  compression->addItem("meshopt", static_cast<int>(Compression::Meshopt));
  compression->setCurrentIndex(compression->findData(static_cast<int>(export_compression_)));
  compression->setToolTip(
      "none: plain glTF, readable everywhere.\nDraco (KHR_draco_mesh_compression): smallest meshes; positions, "
      "normals and texture coordinates quantised.\nmeshopt (EXT_meshopt_compression): lossless.\nA compressed "
      "file needs a reader that decodes its extension.");
  if (auto* grid = qobject_cast<QGridLayout*>(dialog.layout())) {
    const int row = grid->rowCount();
    grid->addWidget(new QLabel("Compression:", &dialog), row, 0);
    grid->addWidget(compression, row, 1);
  }
  if (dialog.exec() != QDialog::Accepted || dialog.selectedFiles().isEmpty()) return;
  QString path = dialog.selectedFiles().front();
  if (!is_model_file(path)) path += dialog.selectedNameFilter() == gltf ? ".gltf" : ".glb";
  export_compression_ = static_cast<Compression>(compression->currentData().toInt());
  const QString question = problems_->export_question();
  if (!question.isEmpty() &&
      QMessageBox::question(this, "Export " + QFileInfo(path).fileName(), question) != QMessageBox::Yes)
    return;
  begin_export(path, export_compression_);
}

QString MainWindow::suggested_export_path() const {
  const QFileInfo input(path_);
  const QDir dir = path_.isEmpty() ? QDir::current() : input.absoluteDir();
  const QString base = path_.isEmpty() ? QString("model") : input.completeBaseName() + "-export";
  QString candidate = dir.absoluteFilePath(base + ".glb");
  for (int n = 2; QFileInfo::exists(candidate) || QFileInfo(candidate) == input; ++n)
    candidate = dir.absoluteFilePath(base + "-" + QString::number(n) + ".glb");
  return candidate;
}

void MainWindow::report_error(const QString& message) {
  last_error_ = message;
  statusBar()->showMessage(message, 15000);
  if (options_.error_dialogs) QMessageBox::critical(this, "DeepCut Studio", message);
}

void MainWindow::note_operation(const QString& label, double ms) {
  last_operation_ms_ = ms;
  last_operation_ = QString("%1: %2 ms").arg(label).arg(ms, 0, 'f', ms < 10.0 ? 1 : 0);
  refresh_status();
}

void MainWindow::show_current() {
  scene_host_->show_step(operations_->take_change());
  operations_->refresh_list();
  emit model_changed();
  idle_release_->start();
}

// The heap keeps what an operation frees for the next one (keep_freed_memory, main.cpp): right
// after a step that saves page faults, but over a long session the free memory of many steps'
// peaks stays resident. Once the user has paused (kIdleReleaseMs since the last step shown and
// the last task ended, e.g. the posed model a step rebuilds) it goes back to the system. The walk
// costs about 20 ms on the UI thread at a 1.7 GB heap, so not while the animation plays; the next
// operation takes fresh pages again.
void MainWindow::release_when_idle() {
  if (task_->busy()) return;  // its end starts the interval again
  if (timeline_->playing()) {
    idle_release_->start();
    return;
  }
  release_freed_memory();
}

bool MainWindow::problems_shown() const { return problems_dock_ && problems_dock_->isVisibleTo(this); }

const PosedModel* MainWindow::posed_model() const { return session().posed_model(); }
const plugins::Scene* MainWindow::scene() const { return scene_host_->scene(); }
void MainWindow::refresh_posed_model() { scene_host_->refresh_posed_model(); }

bool MainWindow::export_file(const QString& path, Compression compression) {
  if (!begin_export(path, compression)) return false;
  task_->wait();
  return export_done_;
}

bool MainWindow::begin_export(const QString& path, Compression compression) {
  finish_indexing();
  export_done_ = false;
  if (!session().current()) {
    report_error("export: no model is open");
    return false;
  }
  if (task_->busy()) {
    report_error(QFileInfo(path).fileName() + ": not exported, " + task_->text() + " is still running");
    return false;
  }
  // The worker writes the current state while edits are disabled (busy_changed), so the state
  // it reads cannot change under it and no copy is needed. It writes a hidden temporary file
  // beside the target; the Deliver renames it into place, Cancel or an error removes it: the
  // target is complete or untouched, never partial.
  const std::shared_ptr<const Model> state = session().current();
  const QFileInfo target(path);
  const QString temp = target.absoluteDir().absoluteFilePath(
      "." + target.completeBaseName() + ".exporting-" + QString::number(QCoreApplication::applicationPid()) + "." +
      target.suffix());
  auto clock = std::make_shared<QElapsedTimer>();
  clock->start();
  const QString name = target.fileName();
  BackgroundTask::Job job = [this, state, path, temp, compression, clock](TaskProgress& progress) -> BackgroundTask::Deliver {
    progress.stage("Writing");
    ExportOptions options;
    options.compression = compression;
    try {
      write_gltf(*state, temp.toStdString(), options);
    } catch (const Error& e) {  // name the target, not the temporary file
      QString message = QString::fromStdString(e.what());
      message.replace(temp, path);
      throw Error(e.code(), message.toStdString());
    }
    progress.stage("Finishing");
    return [this, path, temp, clock] { finish_export(path, temp, *clock); };
  };
  return task_->start(
      "Exporting " + name, 2, std::move(job),
      [this, name, temp](std::exception_ptr error) {
        QFile::remove(temp);
        report_exception(error, name);
      },
      [this, name, temp] {
        QFile::remove(temp);
        statusBar()->showMessage("Export of " + name + " cancelled: no file written", 8000);
      });
}

void MainWindow::finish_export(const QString& path, const QString& temp, const QElapsedTimer& clock) {
  if (std::rename(QFile::encodeName(temp).constData(), QFile::encodeName(path).constData()) != 0) {
    QFile::remove(temp);
    report_error(QFileInfo(path).fileName() + ": cannot write the file (" + QString::fromLocal8Bit(std::strerror(errno)) + ")");
    return;
  }
  export_done_ = true;
  note_operation("Export " + QFileInfo(path).fileName(), ms_since(clock));
  statusBar()->showMessage("Exported " + path, 8000);
}

void MainWindow::set_tool(const std::string& id) { tools_->set_tool(id); }
plugins::Tool* MainWindow::tool() const { return tools_->tool(); }
std::string MainWindow::tool_id() const { return tools_->tool_id(); }

bool MainWindow::apply_tool() {
  finish_indexing();
  if (task_->busy()) {
    report_error("apply: " + task_->text() + " is still running");
    return false;
  }
  const bool editing = session().editing() >= 0;
  bool applied = operations_->apply_tool();
  if (applied && editing) {  // the re-run runs off the UI thread; the event loop goes on
    task_->wait();
    applied = operations_->edit_applied();
  }
  if (applied) last_error_.clear();
  return applied;
}

void MainWindow::apply_history(const History& history, const std::string& source) {
  finish_indexing();
  if (task_->busy())
    throw Error(ErrorCode::InvalidArgument, source + ": not applied, " + task_->text().toStdString() + " is still running");
  operations_->apply_history(history, source);
}

void MainWindow::apply_operation(const QString& label, std::shared_ptr<const Model> result, double ms) {
  finish_indexing();  // the commit moves the model the worker may be reading
  operations_->commit(label, std::move(result), ms);
}

bool MainWindow::edit_operation(int index) {
  finish_indexing();
  if (task_->busy()) {
    report_error("edit: " + task_->text() + " is still running");
    return false;
  }
  return operations_->edit_operation(index);
}

void MainWindow::cancel_edit() {
  if (!task_->busy()) operations_->cancel_edit();
}
int MainWindow::editing_operation() const { return session().editing(); }
std::vector<MainWindow::OperationEntry> MainWindow::operations() const { return session().operations(); }
QListWidget* MainWindow::operations_list() const { return operations_->operations_list(); }
const session::Session& MainWindow::session() const { return operations_->session(); }
std::shared_ptr<const Model> MainWindow::model() const { return session().current(); }
QUndoStack* MainWindow::history() const { return operations_->undo_stack(); }

void MainWindow::set_inspector(const std::string& id) {
  inspectors_->set_inspector(id);
  QElapsedTimer clock;
  clock.start();
  scene_host_->refresh_inspector();
  if (inspectors_->inspector() && scene())
    note_operation("Inspect " + QString::fromStdString(inspectors_->inspector()->title()), ms_since(clock));
}

void MainWindow::set_inspector_option(const std::string& name, const std::string& value) {
  inspectors_->set_option(name, value);
  scene_host_->refresh_inspector();
}

plugins::Inspector* MainWindow::inspector() const { return inspectors_->inspector(); }
std::string MainWindow::inspector_id() const { return inspectors_->inspector_id(); }

void MainWindow::set_pose(int animation, float time) {
  if (animation != timeline_->animation()) timeline_->set_animation(animation);
  timeline_->set_time(time);
}

void MainWindow::set_display_mode(DisplayMode mode) {
  view_->set_display_mode(mode);
  for (QAction* action : display_group_->actions())
    if (action->data().toInt() == static_cast<int>(mode)) action->setChecked(true);
  view_->render();
}

bool MainWindow::frame_selected() { return scene_host_->frame_selected(); }

void MainWindow::set_skeleton_visible(bool visible) {
  if (skeleton_action_->isChecked() != visible) skeleton_action_->setChecked(visible);
  scene_host_->set_skeleton_visible(visible);
}

void MainWindow::set_normals_visible(bool visible) {
  if (normals_action_->isChecked() != visible) normals_action_->setChecked(visible);
  view_->set_normals_visible(visible);
  view_->render();
}

void MainWindow::refresh_status() {
  if (status_held_) return;
  operation_label_->setText(last_operation_);
  if (!scene()) {
    counts_label_->setText("no model");
    time_label_->setText("");
    return;
  }
  const plugins::SceneCounts counts = plugins::scene_counts(*scene());
  counts_label_->setText(
      QString("%1 vertices  %2 triangles").arg(thousands(counts.vertices), thousands(counts.triangles)));
  const int a = scene()->animation;
  const std::string name = a < 0 ? std::string() : scene()->model->animations[static_cast<std::size_t>(a)].name;
  const QString clip = a < 0 ? QString("Rest pose") : name.empty() ? QString("Animation %1").arg(a) : QString::fromStdString(name);
  time_label_->setText(QString("%1  t = %2 s").arg(clip).arg(scene()->time, 0, 'f', 3));
}

QImage MainWindow::screenshot() {
  view_->render();
  QApplication::processEvents();
  return grab().toImage();
}

void MainWindow::dragEnterEvent(QDragEnterEvent* event) {
  const QMimeData* mime = event->mimeData();
  if (mime->hasUrls() && !mime->urls().isEmpty() && is_openable_file(mime->urls().first().toLocalFile()))
    event->acceptProposedAction();
}

void MainWindow::dropEvent(QDropEvent* event) {
  const QMimeData* mime = event->mimeData();
  if (!mime->hasUrls() || mime->urls().isEmpty()) return;
  const QString path = mime->urls().first().toLocalFile();
  if (!is_openable_file(path)) return;
  event->acceptProposedAction();
  begin_open(path);
}

void MainWindow::closeEvent(QCloseEvent* event) {
  timeline_->pause();
  task_->cancel();  // a running job stops at its next stage; its result is dropped
  QSettings().setValue("window_state", saveState());
  event->accept();
}

}  // namespace deepcut::studio
