// SPDX-License-Identifier: MIT
#include "main_window.h"

#include <QAction>
#include <QActionGroup>
#include <QApplication>
#include <QCloseEvent>
#include <QColor>
#include <QComboBox>
#include <QDockWidget>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QElapsedTimer>
#include <QFileDialog>
#include <QDir>
#include <QFileInfo>
#include <QFont>
#include <QHBoxLayout>
#include <QLabel>
#include <QListWidget>
#include <QMenuBar>
#include <QMessageBox>
#include <QMimeData>
#include <QPushButton>
#include <QSettings>
#include <QStackedWidget>
#include <QStatusBar>
#include <QStyle>
#include <QTimer>
#include <QToolBar>
#include <QUndoStack>
#include <QUndoView>
#include <QUrl>
#include <QVBoxLayout>
#include <algorithm>
#include <new>

#include "deepcut/core/errors.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/ops/operation.h"
#include "deepcut/plugins/formats.h"
#include "deepcut/plugins/inspector_registry.h"
#include "scene_tree.h"
#include "scene_view.h"
#include "timeline.h"

namespace deepcut::studio {
namespace {

constexpr int kMaxRecent = 10;
const char* kRecentKey = "recent_files";

/// One undoable change of model state: the snapshots before and after.
class ModelCommand : public QUndoCommand {
 public:
  ModelCommand(MainWindow* window, const QString& label, std::shared_ptr<const Model> before,
               std::shared_ptr<const Model> after)
      : QUndoCommand(label), window_(window), before_(std::move(before)), after_(std::move(after)) {}
  void undo() override { window_->show_model(before_); }
  void redo() override { window_->show_model(after_); }

 private:
  MainWindow* window_;
  std::shared_ptr<const Model> before_, after_;
};

/// An export target: the exporter writes glTF only.
bool is_model_file(const QString& path) {
  const QString suffix = QFileInfo(path).suffix().toLower();
  return suffix == "glb" || suffix == "gltf";
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

QString vec(const glm::vec3& v) { return QString("(%1, %2, %3)").arg(v.x, 0, 'g', 4).arg(v.y, 0, 'g', 4).arg(v.z, 0, 'g', 4); }

/// The history entry's text: operation type, its main parameters and the pose time.
QString operation_label(const Operation& op) {
  QString text;
  if (const auto* cut = std::get_if<CutOperation>(&op.params))
    text = "Cut  point " + vec(cut->plane.point) + " normal " + vec(cut->plane.normal) +
           (cut->options.cap ? "  cap" : "") + (cut->options.split_components ? "  components" : "") +
           (cut->options.keep == CutKeep::Positive ? "  keep +" : cut->options.keep == CutKeep::Negative ? "  keep -" : "");
  else if (const auto* tear = std::get_if<TearOperation>(&op.params))
    text = "Tear  " + vec(tear->start.tip) + " to " + vec(tear->end.tip) +
           QString("  width %1").arg(tear->options.width, 0, 'g', 4);
  else if (const auto* drill = std::get_if<DrillOperation>(&op.params))
    text = "Drill  " + vec(drill->cylinder.a) + " to " + vec(drill->cylinder.b) +
           QString("  r %1").arg(drill->cylinder.radius, 0, 'g', 4) + (drill->options.wall ? "  wall" : "");
  return text + (op.animation < 0 ? QString("  @ rest") : QString("  @ anim %1 t = %2 s").arg(op.animation).arg(op.time, 0, 'f', 3));
}

QString thousands(std::size_t n) { return QLocale(QLocale::English).toString(static_cast<qulonglong>(n)); }

}  // namespace

MainWindow::MainWindow(const MainWindowOptions& options, QWidget* parent)
    : QMainWindow(parent), options_(options) {
  setWindowTitle("DeepCut Studio");
  setObjectName("main_window");
  setAcceptDrops(true);
  setDockNestingEnabled(true);
  resize(1400, 880);

  view_ = new SceneView(this);
  setCentralWidget(view_);
  view_->set_pick_handler([this](const plugins::Pick& pick) { on_pick(pick); });
  view_->set_pointer_handler([this](const PointerEvent& event) { return on_pointer(event); });
  tool_timer_ = new QTimer(this);
  tool_timer_->setInterval(16);
  connect(tool_timer_, &QTimer::timeout, this, &MainWindow::step_tool);
  index_timer_ = new QTimer(this);
  index_timer_->setSingleShot(true);
  index_timer_->setInterval(300);
  connect(index_timer_, &QTimer::timeout, this, [this] {
    if (timeline_->playing()) return;  // playing: re-posing every frame; the next stop rebuilds
    refresh_operation_index();
  });

  history_ = new QUndoStack(this);
  for (const plugins::InspectorInfo& info : plugins::builtin_inspectors().list()) {
    inspectors_.push_back(info.create());
    inspectors_.back()->set_changed_callback([this] { refresh_inspector(); });
  }
  for (const plugins::ToolInfo& info : plugins::builtin_tools().list()) {
    if (!info.create) continue;  // a command-line-only entry
    tools_.push_back(info.create());
    tools_.back()->set_changed_callback([this] { refresh_tool_preview(); });
  }
  build_docks();
  build_menus();

  counts_label_ = new QLabel(this);
  time_label_ = new QLabel(this);
  operation_label_ = new QLabel(this);
  operation_label_->setObjectName("status_operation");
  statusBar()->addPermanentWidget(operation_label_);
  statusBar()->addPermanentWidget(time_label_);
  statusBar()->addPermanentWidget(counts_label_);
  refresh_status();

  QSettings settings;
  restoreState(settings.value("window_state").toByteArray());
}

MainWindow::~MainWindow() = default;

void MainWindow::build_docks() {
  tree_ = new SceneTree(this);
  auto* scene_dock = new QDockWidget("Scene", this);
  scene_dock->setObjectName("scene_dock");
  scene_dock->setWidget(tree_);
  addDockWidget(Qt::LeftDockWidgetArea, scene_dock);
  connect(tree_, &SceneTree::joint_selected, this, [this](int joint) {
    if (!plugins::builtin_inspectors().find("weights")) return;
    set_inspector("weights");
    plugins::Pick pick;
    pick.joint_node = joint;
    sync_active_inspector();
    if (inspector()->pick(pick)) refresh_inspector();
  });

  // History: the operations of the current state (edit one: the later ones re-run) above the
  // undo stack (click an entry to go back).
  auto* history_dock = new QDockWidget("History", this);
  history_dock->setObjectName("history_dock");
  auto* history_panel = new QWidget(history_dock);
  auto* history_layout = new QVBoxLayout(history_panel);
  history_layout->setContentsMargins(4, 4, 4, 4);
  history_layout->addWidget(new QLabel("Operations (double-click to edit; later ones re-run)", history_panel));
  operations_list_ = new QListWidget(history_panel);
  operations_list_->setObjectName("operations_list");
  history_layout->addWidget(operations_list_, 1);
  auto* edit_row = new QHBoxLayout();
  edit_button_ = new QPushButton("Edit operation", history_panel);
  edit_button_->setObjectName("edit_operation");
  edit_button_->setEnabled(false);
  cancel_edit_button_ = new QPushButton("Cancel edit", history_panel);
  cancel_edit_button_->setObjectName("cancel_edit");
  cancel_edit_button_->setEnabled(false);
  edit_row->addWidget(edit_button_);
  edit_row->addWidget(cancel_edit_button_);
  history_layout->addLayout(edit_row);
  connect(operations_list_, &QListWidget::currentRowChanged, this,
          [this](int row) { edit_button_->setEnabled(row >= 0 && editing_.index < 0); });
  connect(operations_list_, &QListWidget::itemDoubleClicked, this,
          [this](QListWidgetItem* item) { edit_operation(operations_list_->row(item)); });
  connect(edit_button_, &QPushButton::clicked, this, [this] { edit_operation(operations_list_->currentRow()); });
  connect(cancel_edit_button_, &QPushButton::clicked, this, &MainWindow::cancel_edit);
  history_layout->addWidget(new QLabel("Undo history (click to go back)", history_panel));
  auto* undo_view = new QUndoView(history_, history_panel);
  undo_view->setEmptyLabel("Opened model");
  history_layout->addWidget(undo_view, 1);
  history_dock->setWidget(history_panel);
  addDockWidget(Qt::LeftDockWidgetArea, history_dock);
  splitDockWidget(scene_dock, history_dock, Qt::Vertical);
  resizeDocks({scene_dock, history_dock}, {480, 300}, Qt::Vertical);

  auto* inspector_dock = new QDockWidget("Inspector", this);
  inspector_dock->setObjectName("inspector_dock");
  auto* panel = new QWidget(inspector_dock);
  auto* layout = new QVBoxLayout(panel);
  layout->setContentsMargins(4, 4, 4, 4);
  inspector_combo_ = new QComboBox(panel);
  inspector_combo_->setObjectName("inspector_combo");
  inspector_combo_->addItem("Shaded (materials)", QString());
  inspector_stack_ = new QStackedWidget(panel);
  auto* none = new QLabel(
      "The model with its own materials and textures, posed at the time line's time.\n\n"
      "Choose an inspector above (or Inspect menu) to look at skin weights or adjacency.",
      inspector_stack_);
  none->setWordWrap(true);
  none->setAlignment(Qt::AlignTop | Qt::AlignLeft);
  none->setMargin(6);
  inspector_stack_->addWidget(none);
  for (const auto& inspector : inspectors_) {
    inspector_combo_->addItem(QString::fromStdString(inspector->title()),
                              QString::fromStdString(inspector->id()));
    inspector_stack_->addWidget(inspector->create_panel(inspector_stack_));
  }
  layout->addWidget(inspector_combo_);
  layout->addWidget(inspector_stack_, 1);
  inspector_dock->setWidget(panel);
  inspector_dock->setMinimumWidth(300);
  addDockWidget(Qt::RightDockWidgetArea, inspector_dock);
  connect(inspector_combo_, QOverload<int>::of(&QComboBox::activated), this,
          [this](int index) { set_inspector(inspector_combo_->itemData(index).toString().toStdString()); });

  auto* tool_dock = new QDockWidget("Tool", this);
  tool_dock->setObjectName("tool_dock");
  auto* tool_panel = new QWidget(tool_dock);
  auto* tool_layout = new QVBoxLayout(tool_panel);
  tool_layout->setContentsMargins(4, 4, 4, 4);
  edit_banner_ = new QLabel(tool_panel);
  edit_banner_->setObjectName("edit_banner");
  edit_banner_->setWordWrap(true);
  edit_banner_->setStyleSheet("QLabel { background: #5a4a1e; color: #ffe9a8; padding: 4px; }");
  edit_banner_->hide();
  tool_layout->addWidget(edit_banner_);
  tool_stack_ = new QStackedWidget(tool_panel);
  auto* no_tool = new QLabel(
      "Choose Plane, Scalpel or Drill on the Tools bar: the tool places itself on the model and its "
      "contour, tear path or rims are drawn live. Edit the numbers here, then Apply (Enter). "
      "With Poke, drag on the model to pull it as a soft body.",
      tool_stack_);
  no_tool->setWordWrap(true);
  no_tool->setAlignment(Qt::AlignTop | Qt::AlignLeft);
  no_tool->setMargin(6);
  tool_stack_->addWidget(no_tool);
  for (const auto& tool : tools_) tool_stack_->addWidget(tool->create_panel(tool_stack_));
  apply_button_ = new QPushButton("Apply (Enter)", tool_panel);
  apply_button_->setObjectName("apply_button");
  apply_button_->setEnabled(false);
  connect(apply_button_, &QPushButton::clicked, this, [this] { apply_tool(); });
  tool_layout->addWidget(tool_stack_, 1);
  tool_layout->addWidget(apply_button_);
  tool_dock->setWidget(tool_panel);
  addDockWidget(Qt::RightDockWidgetArea, tool_dock);
  splitDockWidget(inspector_dock, tool_dock, Qt::Vertical);

  timeline_ = new Timeline(this);
  auto* timeline_dock = new QDockWidget("Time line", this);
  timeline_dock->setObjectName("timeline_dock");
  timeline_dock->setWidget(timeline_);
  addDockWidget(Qt::BottomDockWidgetArea, timeline_dock);
  connect(timeline_, &Timeline::pose_changed, this, &MainWindow::on_pose_changed);
  resizeDocks({scene_dock, inspector_dock}, {300, 330}, Qt::Horizontal);
}

void MainWindow::build_menus() {
  QStyle* s = style();
  // File
  QMenu* file = menuBar()->addMenu("&File");
  QAction* open = file->addAction(s->standardIcon(QStyle::SP_DialogOpenButton), "&Open...", this,
                                  &MainWindow::choose_open);
  open->setShortcut(QKeySequence::Open);
  recent_menu_ = file->addMenu("Open &Recent");
  connect(recent_menu_, &QMenu::aboutToShow, this, &MainWindow::refresh_recent_menu);
  file->addSeparator();
  QAction* export_action = file->addAction(s->standardIcon(QStyle::SP_DialogSaveButton),
                                           "&Export .glb / .gltf...", this, &MainWindow::choose_export);
  export_action->setShortcut(QKeySequence("Ctrl+E"));
  file->addSeparator();
  QAction* quit = file->addAction("&Quit", this, &QWidget::close);
  quit->setShortcut(QKeySequence::Quit);

  // Edit: undo and redo follow the history (disabled while it is empty).
  QMenu* edit = menuBar()->addMenu("&Edit");
  undo_ = history_->createUndoAction(this, "&Undo");
  undo_->setShortcut(QKeySequence::Undo);
  undo_->setIcon(s->standardIcon(QStyle::SP_ArrowBack));
  redo_ = history_->createRedoAction(this, "&Redo");
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

  // View
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
  skeleton_action_->setChecked(show_skeleton_);
  skeleton_action_->setShortcut(QKeySequence("K"));
  connect(skeleton_action_, &QAction::toggled, this, &MainWindow::set_skeleton_visible);
  normals_action_ = view->addAction("Show &normals");
  normals_action_->setCheckable(true);
  normals_action_->setShortcut(QKeySequence("N"));
  connect(normals_action_, &QAction::toggled, this, &MainWindow::set_normals_visible);
  view->addSeparator();
  QMenu* panels = view->addMenu("&Panels");
  for (QDockWidget* dock : findChildren<QDockWidget*>()) panels->addAction(dock->toggleViewAction());

  // Inspect: one entry per registered inspector.
  QMenu* inspect = menuBar()->addMenu("&Inspect");
  inspect_group_ = new QActionGroup(this);
  auto add_mode = [&](const QString& text, const std::string& id, int index) {
    QAction* action = inspect->addAction(text);
    action->setCheckable(true);
    action->setChecked(id.empty());
    action->setShortcut(QKeySequence(QString("Ctrl+%1").arg(index)));
    action->setData(QString::fromStdString(id));
    inspect_group_->addAction(action);
    connect(action, &QAction::triggered, this, [this, id] { set_inspector(id); });
  };
  add_mode("&Shaded (materials)", "", 0);
  for (std::size_t i = 0; i < inspectors_.size(); ++i)
    add_mode(QString::fromStdString(inspectors_[i]->title()), inspectors_[i]->id(), static_cast<int>(i) + 1);

  // Tools: one checkable entry per registered tool (at most one active), and Apply.
  QMenu* tools_menu = menuBar()->addMenu("&Tools");
  tool_group_ = new QActionGroup(this);
  tool_group_->setExclusionPolicy(QActionGroup::ExclusionPolicy::ExclusiveOptional);
  for (std::size_t i = 0; i < tools_.size(); ++i) {
    const auto& tool = tools_[i];
    QAction* action = tools_menu->addAction(QString::fromStdString(tool->title()));
    action->setObjectName(QString::fromStdString("tool_" + tool->id()));
    const plugins::ToolInfo* info = plugins::builtin_tools().find(tool->id());
    const std::string shortcut = info ? info->shortcut : std::string();
    if (!shortcut.empty()) action->setShortcut(QKeySequence(QString::fromStdString(shortcut)));
    action->setCheckable(true);
    action->setData(QString::fromStdString(tool->id()));
    tool_group_->addAction(action);
    connect(action, &QAction::triggered, this,
            [this, action, id = tool->id()](bool on) { set_tool(on || action->isChecked() ? id : std::string()); });
  }
  tools_menu->addSeparator();
  apply_action_ = tools_menu->addAction(s->standardIcon(QStyle::SP_DialogApplyButton), "&Apply tool", this,
                                        [this] { apply_tool(); });
  apply_action_->setObjectName("apply_tool");
  apply_action_->setShortcuts({QKeySequence(Qt::Key_Return), QKeySequence(Qt::Key_Enter)});
  apply_action_->setEnabled(false);

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
  for (QAction* action : tool_group_->actions()) operation_bar->addAction(action);
  operation_bar->addAction(apply_action_);
}

QStringList MainWindow::recent_files() const { return QSettings().value(kRecentKey).toStringList(); }

void MainWindow::remember_recent(const QString& path) {
  QSettings settings;
  QStringList list = settings.value(kRecentKey).toStringList();
  const QString absolute = QFileInfo(path).absoluteFilePath();
  list.removeAll(absolute);
  list.prepend(absolute);
  while (list.size() > kMaxRecent) list.removeLast();
  settings.setValue(kRecentKey, list);
}

void MainWindow::refresh_recent_menu() {
  recent_menu_->clear();
  const QStringList list = recent_files();
  for (const QString& path : list) {
    QAction* action =
        recent_menu_->addAction(QFileInfo(path).fileName(), this, [this, path] { open_file(path); });
    action->setToolTip(path);
    action->setEnabled(QFileInfo::exists(path));
  }
  if (list.isEmpty()) recent_menu_->addAction("(none)")->setEnabled(false);
  recent_menu_->addSeparator();
  recent_menu_->addAction("Clear list", this, [] { QSettings().remove(kRecentKey); });
}

void MainWindow::choose_open() {
  const QString dir = path_.isEmpty() ? QString() : QFileInfo(path_).absolutePath();
  const QString path =
      QFileDialog::getOpenFileName(this, "Open model", dir, open_filters());
  if (!path.isEmpty()) open_file(path);
}

void MainWindow::choose_export() {
  if (!model_) return report_error("export: no model is open");
  const QString glb = "glTF binary (*.glb)", gltf = "glTF JSON, embedded buffers (*.gltf)";
  QString filter = glb;
  QString path =
      QFileDialog::getSaveFileName(this, "Export model", suggested_export_path(), glb + ";;" + gltf, &filter);
  if (path.isEmpty()) return;
  if (!is_model_file(path)) path += filter == gltf ? ".gltf" : ".glb";
  export_file(path);
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
  last_operation_ = QString("%1: %2 ms").arg(label).arg(ms, 0, 'f', ms < 10.0 ? 1 : 0);
  refresh_status();
}

bool MainWindow::open_file(const QString& path) {
  try {
    load_file(path);
    return true;
  } catch (const Error& e) {
    report_error(QString::fromStdString(e.what()));
  } catch (const std::bad_alloc&) {
    report_error(QFileInfo(path).fileName() + ": out of memory");
  } catch (const std::exception& e) {
    report_error(QFileInfo(path).fileName() + ": internal error: " + e.what());
  }
  return false;
}

void MainWindow::load_file(const QString& path) {
  QElapsedTimer clock;
  clock.start();
  Model loaded = plugins::read_model(path.toStdString());
  reserve_for_operations(loaded);  // room to grow, kept by every snapshot copied from it
  auto model = std::make_shared<const Model>(std::move(loaded));
  // Build the new scene before touching the current state, so a failure keeps the old model.
  const int animation = model->animations.empty() ? -1 : 0;
  plugins::Scene scene = plugins::make_scene(model, animation, 0.0f);
  // The operations' preprocessing, once per model (and pose): every drill and tear updates it.
  auto index = std::make_unique<PosedModel>(PosedModel::build(*model, animation, 0.0f));
  std::vector<std::pair<QString, float>> clips;
  for (const Animation& a : model->animations)
    clips.emplace_back(QString::fromStdString(a.name), a.duration());

  path_ = path;
  editing_ = {};
  history_->clear();
  original_ = model;
  opened_operations_ = model_history(*model).operations.size();
  reruns_.clear();
  timeline_->set_animations(clips);
  model_ = model;
  detach_index();
  index_ = std::move(index);
  index_state_ = model;
  index_timer_->stop();
  if (!scene_) scene_ = std::make_unique<plugins::Scene>();
  *scene_ = std::move(scene);
  attach_index();
  const std::vector<std::string> notes = view_->set_scene(*scene_);
  tool_displaced_ = false;
  tree_->set_scene(*scene_);
  mark_inspectors_stale(plugins::SceneChange::Model);
  refresh_inspector();
  view_->reset_camera();
  last_surface_click_.reset();
  if (plugins::Tool* active_tool = tool()) {
    active_tool->place(*scene_, tool_placement());
    view_->set_tool_widget(active_tool->widget());
  }
  refresh_tool_preview();
  view_->render();
  remember_recent(path);
  setWindowTitle(QFileInfo(path).fileName() + " - DeepCut Studio");
  last_error_.clear();
  note_operation("Open " + QFileInfo(path).fileName(), static_cast<double>(clock.nsecsElapsed()) / 1e6);
  refresh_operations();
  if (!notes.empty()) statusBar()->showMessage(QString::fromStdString(notes.front()), 15000);
  emit model_changed();
}

void MainWindow::show_model(std::shared_ptr<const Model> model) {
  if (!model) return;
  // Undo, redo or a click in the undo history while editing an operation: the edit is dropped.
  if (editing_.index >= 0 && !entering_edit_) editing_ = {};
  int animation = timeline_->animation();
  if (animation >= static_cast<int>(model->animations.size())) animation = model->animations.empty() ? -1 : 0;
  model_ = std::move(model);
  *scene_ = plugins::make_scene(model_, animation, timeline_->time());
  if (index_state_.lock() == model_) attach_index();
  view_->set_scene(*scene_);
  tool_displaced_ = false;
  tree_->set_scene(*scene_);
  mark_inspectors_stale(plugins::SceneChange::Model);
  refresh_tool_preview();
  refresh_inspector();
  refresh_operations();
  // Undo, redo or an edit: the preprocessing describes another state; a cut dropped it (its
  // pieces are new meshes). Rebuild it when idle.
  if (index_state_.lock() != model_ || !index_ || !index_->valid()) index_timer_->start();
  emit model_changed();
}

const PosedModel* MainWindow::operation_index() const {
  if (!index_ || !model_ || index_state_.lock() != model_ || !index_->valid()) return nullptr;
  return index_.get();
}

void MainWindow::refresh_operation_index() {
  if (!model_ || !scene_) return;
  try {
    index_for(model_)->prepare(*model_, scene_->animation, scene_->time);
    attach_index();
    refresh_tool_preview();
  } catch (const Error&) {
    index_state_.reset();  // the next operation builds it (and reports what is wrong)
  } catch (const std::bad_alloc&) {
    index_.reset();
    index_state_.reset();
  }
}

void MainWindow::detach_index() {
  if (!scene_) return;
  for (plugins::ScenePiece& piece : scene_->pieces) piece.grid = nullptr;
}

void MainWindow::attach_index() {
  detach_index();
  const PosedModel* index = operation_index();
  if (!index || !scene_ || scene_->model != model_ || !index->matches(scene_->animation, scene_->time)) return;
  for (plugins::ScenePiece& piece : scene_->pieces) {
    const PosedMesh* inst = index->find(piece.node, piece.primitive);
    // The grid is filed at the index's posed positions: attach it only where they are the
    // scene's, bit for bit (both pose with the same skinning; this guards the assumption).
    if (inst && inst->mesh == piece.mesh && inst->posed.size() == piece.posed.size() &&
        std::equal(inst->posed.begin(), inst->posed.end(), piece.posed.begin()))
      piece.grid = &inst->grid;
  }
}

PosedModel* MainWindow::index_for(const std::shared_ptr<const Model>& state) {
  detach_index();
  if (!index_) index_ = std::make_unique<PosedModel>();
  if (index_state_.lock() != state) {
    index_->invalidate();  // free the old one before building the new one
    *index_ = PosedModel::build(*state, scene_->animation, scene_->time);
    index_state_ = state;
  }
  return index_.get();
}

bool MainWindow::export_file(const QString& path) {
  if (!model_) {
    report_error("export: no model is open");
    return false;
  }
  QElapsedTimer clock;
  clock.start();
  try {
    write_gltf(*model_, path.toStdString());
  } catch (const Error& e) {
    report_error(QString::fromStdString(e.what()));
    return false;
  } catch (const std::exception& e) {
    report_error(QFileInfo(path).fileName() + ": internal error: " + e.what());
    return false;
  }
  note_operation("Export " + QFileInfo(path).fileName(), static_cast<double>(clock.nsecsElapsed()) / 1e6);
  statusBar()->showMessage("Exported " + path, 8000);
  return true;
}

void MainWindow::apply_operation(const QString& label, std::shared_ptr<const Model> result, double ms) {
  if (!model_ || !result) return;
  history_->push(new ModelCommand(this, label, model_, std::move(result)));
  note_operation(label, ms);
}

void MainWindow::set_tool(const std::string& id) {
  int index = -1;
  if (!id.empty() && id != "none") {
    for (std::size_t i = 0; i < tools_.size(); ++i)
      if (tools_[i]->id() == id) index = static_cast<int>(i);
    if (index < 0)
      throw Error(ErrorCode::InvalidArgument,
                  "unknown tool '" + id + "' (known: " + plugins::builtin_tools().ids() + ")");
  }
  if (plugins::Tool* previous = tool(); previous && scene_) previous->release(*scene_);
  active_tool_ = index;
  tool_timer_->stop();
  show_tool_displacement();  // back to the posed model
  tool_stack_->setCurrentIndex(index + 1);
  for (QAction* action : tool_group_->actions())
    action->setChecked(index >= 0 && action->data().toString().toStdString() == id);
  const bool operation = index >= 0 && tools_[static_cast<std::size_t>(index)]->makes_operation();
  apply_button_->setEnabled(operation);
  apply_action_->setEnabled(operation);
  plugins::Tool* chosen = tool();
  if (chosen && scene_) chosen->place(*scene_, tool_placement());
  view_->set_tool_widget(chosen && scene_ ? chosen->widget() : nullptr);
  refresh_tool_preview();
  view_->render();
}

plugins::ToolPlacement MainWindow::tool_placement() {
  plugins::ToolPlacement placement;
  placement.view_direction = view_->view_direction();
  placement.view_up = view_->view_up();
  if (const std::optional<QPoint> cursor = view_->cursor_position())
    placement.point = view_->surface_point_at(*cursor);
  if (!placement.point) placement.point = last_surface_click_;
  return placement;
}

plugins::Tool* MainWindow::tool() const {
  return active_tool_ >= 0 ? tools_[static_cast<std::size_t>(active_tool_)].get() : nullptr;
}

std::string MainWindow::tool_id() const { return tool() ? tool()->id() : std::string(); }

void MainWindow::refresh_tool_preview() {
  plugins::Tool* active_tool = tool();
  view_->set_overlay(SceneView::Layer::Tool, active_tool && scene_ ? active_tool->preview(*scene_) : Overlay{});
  view_->render();
}

bool MainWindow::apply_tool() {
  plugins::Tool* active_tool = tool();
  if (!model_ || !scene_) {
    report_error("apply: no model is open");
    return false;
  }
  if (!active_tool || !active_tool->makes_operation()) {
    report_error("apply: no operation tool is chosen (Tools: Plane, Scalpel or Drill)");
    return false;
  }
  if (editing_.index >= 0) return apply_edit();
  Operation op;
  op.params = active_tool->parameters();
  op.animation = scene_->animation;
  op.time = scene_->time;
  QElapsedTimer clock;
  clock.start();
  try {
    auto result = std::make_shared<Model>(*model_);
    // The operation follows and updates the preprocessing, which then describes `result` (a
    // miss leaves both as they were; a failure leaves the index for a rebuild).
    PosedModel* index = index_for(model_);
    index_state_.reset();
    const OperationResult report = deepcut::apply_operation(*result, op, index);
    index_state_ = report.status == OpStatus::Ok ? std::shared_ptr<const Model>(result) : model_;
    if (report.status != OpStatus::Ok) {
      attach_index();  // a miss changed nothing: the index still describes the shown model
      report_error(QString::fromStdString(active_tool->title()) + ": the tool misses the model (nothing changed)");
      return false;
    }
    // A state made by an edit keeps its skipped operations listed after a new one.
    if (const auto* entries = rerun_entries(model_.get())) {
      std::vector<OperationEntry> next = *entries;
      next.push_back({op, OpStatus::Ok, {}});
      reruns_.emplace_back(result, std::move(next));
    }
    apply_operation(operation_label(op), std::move(result), static_cast<double>(clock.nsecsElapsed()) / 1e6);
  } catch (const Error& e) {
    report_error(QString::fromStdString(active_tool->title() + ": " + e.what()));
    return false;
  } catch (const std::bad_alloc&) {
    report_error(QString::fromStdString(active_tool->title()) + ": out of memory");
    return false;
  } catch (const std::exception& e) {  // a defect in an operation: reported, never a crash
    index_state_.reset();                // the index may have followed part of the operation
    report_error(QString::fromStdString(active_tool->title() + ": internal error: " + e.what()));
    return false;
  }
  last_error_.clear();
  return true;
}

void MainWindow::apply_history(const History& history, const std::string& source) {
  if (!model_) throw Error(ErrorCode::InvalidArgument, source + ": no model is open");
  // Run all first, so a bad operation leaves the history as it was.
  struct Applied {
    QString label;
    std::shared_ptr<const Model> model;
    double ms = 0.0;
  };
  std::vector<Applied> states;
  std::shared_ptr<const Model> state = model_;
  for (std::size_t i = 0; i < history.operations.size(); ++i) {
    const Operation& op = history.operations[i];
    QElapsedTimer clock;
    clock.start();
    auto next = std::make_shared<Model>(*state);
    PosedModel* index = index_for(state);
    index_state_.reset();
    try {
      if (deepcut::apply_operation(*next, op, index).status != OpStatus::Ok) {
        index_state_ = state;
        continue;
      }
    } catch (const Error& e) {
      throw Error(e.code(), source + ": operation " + std::to_string(i) + ": " + e.what());
    }
    index_state_ = next;
    state = next;
    states.push_back({operation_label(op), state, static_cast<double>(clock.nsecsElapsed()) / 1e6});
  }
  for (auto& applied : states) apply_operation(applied.label, applied.model, applied.ms);
}

const std::vector<MainWindow::OperationEntry>* MainWindow::rerun_entries(const Model* model) const {
  for (const auto& [state, entries] : reruns_)
    if (const auto alive = state.lock(); alive && alive.get() == model) return &entries;
  return nullptr;
}

std::vector<MainWindow::OperationEntry> MainWindow::operations() const {
  if (editing_.index >= 0) return editing_.entries;
  if (!model_) return {};
  if (const auto* entries = rerun_entries(model_.get())) return *entries;
  std::vector<OperationEntry> out;
  const History history = model_history(*model_);
  for (std::size_t i = opened_operations_; i < history.operations.size(); ++i)
    out.push_back({history.operations[i], OpStatus::Ok, {}});
  return out;
}

void MainWindow::refresh_operations() {
  // Forget the lists of states no command holds any more.
  reruns_.erase(std::remove_if(reruns_.begin(), reruns_.end(), [](const auto& r) { return r.first.expired(); }),
                reruns_.end());
  const std::vector<OperationEntry> entries = operations();
  const int row = operations_list_->currentRow();
  operations_list_->clear();
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const OperationEntry& entry = entries[i];
    QString text = QString("%1. %2").arg(i + 1).arg(operation_label(entry.operation));
    auto* item = new QListWidgetItem(operations_list_);
    if (!entry.applied()) {
      const QString why = entry.error.empty() ? QString("no longer applies (%1)").arg(to_string(entry.status))
                                              : QString("failed: %1").arg(QString::fromStdString(entry.error));
      text = QString::fromUtf8("✗ ") + text + "  - " + why + ", skipped";
      item->setForeground(QColor(255, 120, 110));
      item->setToolTip("After the last edit this operation " + why + "; it was skipped. Edit it to fix it.");
    }
    if (static_cast<int>(i) == editing_.index) {
      QFont font = item->font();
      font.setBold(true);
      item->setFont(font);
      text = QString::fromUtf8("✎ ") + text;
    }
    item->setText(text);
  }
  if (row >= 0 && row < operations_list_->count()) operations_list_->setCurrentRow(row);
  edit_button_->setEnabled(editing_.index < 0 && operations_list_->currentRow() >= 0);
  cancel_edit_button_->setEnabled(editing_.index >= 0);
  const bool editing = editing_.index >= 0;
  edit_banner_->setVisible(editing);
  if (editing)
    edit_banner_->setText(QString("Editing operation %1 of %2 (the model as it was before it). Apply re-runs "
                                  "it and the %3 after it as one undoable step; Esc cancels.")
                              .arg(editing_.index + 1)
                              .arg(entries.size())
                              .arg(static_cast<int>(entries.size()) - editing_.index - 1));
  apply_button_->setText(editing ? "Re-run from here (Enter)" : "Apply (Enter)");
}

namespace {

std::string tool_of(const Operation& op) {
  if (std::holds_alternative<CutOperation>(op.params)) return "cut";
  if (std::holds_alternative<TearOperation>(op.params)) return "tear";
  return "drill";
}

/// Applies `entry` to `model` as `deepcut apply` would, noting whether it applied.
/// `index` (the preprocessing describing `model`, or nullptr) follows the operation; after a
/// failure it is invalidated, so the next operation rebuilds it.
void run_entry(Model& model, MainWindow::OperationEntry& entry, PosedModel* index) {
  entry.error.clear();
  try {
    entry.status = deepcut::apply_operation(model, entry.operation, index).status;
  } catch (const Error& e) {
    entry.status = OpStatus::Ok;
    entry.error = e.what();
    if (index) index->invalidate();
  } catch (const std::bad_alloc&) {
    if (index) index->invalidate();
    throw;  // the caller reports it
  } catch (const std::exception& e) {  // a defect in an operation: reported, never a crash
    entry.status = OpStatus::Ok;
    entry.error = std::string("internal error: ") + e.what();
    if (index) index->invalidate();
  }
}

}  // namespace

bool MainWindow::edit_operation(int index) {
  if (editing_.index >= 0) cancel_edit();
  const std::vector<OperationEntry> entries = operations();
  if (!model_ || !original_ || index < 0 || index >= static_cast<int>(entries.size())) {
    report_error(QString("edit: there is no operation %1 to edit").arg(index + 1));
    return false;
  }
  QElapsedTimer clock;
  clock.start();
  // The state before the operation: the opened model and the operations before it, re-run.
  auto base = std::make_shared<Model>(*original_);
  std::vector<OperationEntry> replayed = entries;
  try {
    PosedModel* model_index = index < 1 ? nullptr : index_for(original_);
    if (model_index) index_state_.reset();  // it follows `base` from here on
    for (int i = 0; i < index; ++i) run_entry(*base, replayed[static_cast<std::size_t>(i)], model_index);
    if (model_index) index_state_ = std::shared_ptr<const Model>(base);
  } catch (const std::bad_alloc&) {
    report_error("edit: out of memory");
    return false;
  }
  const OperationEntry& edited = entries[static_cast<std::size_t>(index)];
  editing_ = {index, model_, entries};
  entering_edit_ = true;
  show_model(base);
  entering_edit_ = false;
  // Its tool with its parameters, at its pose.
  if (edited.operation.animation < static_cast<int>(model_->animations.size()))
    set_pose(edited.operation.animation, edited.operation.time);
  set_tool(tool_of(edited.operation));
  tool()->set_parameters(edited.operation.params);
  refresh_operations();
  operations_list_->setCurrentRow(index);
  note_operation(QString("Edit operation %1").arg(index + 1), static_cast<double>(clock.nsecsElapsed()) / 1e6);
  return true;
}

void MainWindow::cancel_edit() {
  if (editing_.index < 0) return;
  const std::shared_ptr<const Model> current = editing_.current;
  editing_ = {};
  show_model(current);
  statusBar()->showMessage("Edit cancelled: the history is unchanged", 5000);
}

bool MainWindow::apply_edit() {
  plugins::Tool* active_tool = tool();
  const int index = editing_.index;
  std::vector<OperationEntry> entries = editing_.entries;
  OperationEntry& edited = entries[static_cast<std::size_t>(index)];
  edited.operation.params = active_tool->parameters();
  edited.operation.animation = scene_->animation;
  edited.operation.time = scene_->time;
  QElapsedTimer clock;
  clock.start();
  auto result = std::make_shared<Model>(*model_);  // the state before the edited operation
  PosedModel* model_index = nullptr;
  try {
    model_index = index_for(model_);
    index_state_.reset();  // it follows `result` from here on
    run_entry(*result, edited, model_index);
  } catch (const std::bad_alloc&) {
    report_error(QString::fromStdString(active_tool->title()) + ": out of memory");
    return false;
  }
  if (!edited.error.empty()) {
    report_error(QString::fromStdString(active_tool->title() + ": " + edited.error));
    return false;
  }
  if (edited.status != OpStatus::Ok) {
    report_error(QString::fromStdString(active_tool->title()) + ": the edited operation misses the model (nothing changed)");
    return false;
  }
  std::size_t skipped = 0;
  try {
    for (std::size_t i = static_cast<std::size_t>(index) + 1; i < entries.size(); ++i) {
      run_entry(*result, entries[i], model_index);
      if (!entries[i].applied()) ++skipped;
    }
  } catch (const std::bad_alloc&) {
    report_error("edit: out of memory while re-running the history");
    return false;
  }
  const std::shared_ptr<const Model> before = editing_.current;
  const QString label = QString("Edit %1: %2").arg(index + 1).arg(operation_label(edited.operation));
  std::shared_ptr<const Model> after = result;
  index_state_ = after;
  reruns_.emplace_back(after, entries);
  editing_ = {};
  history_->push(new ModelCommand(this, label, before, std::move(after)));
  note_operation(label, static_cast<double>(clock.nsecsElapsed()) / 1e6);
  last_error_.clear();
  operations_list_->setCurrentRow(index);
  if (skipped > 0)
    statusBar()->showMessage(QString("%1 later operation%2 no longer appl%3 and %4 skipped (marked in History)")
                                 .arg(skipped)
                                 .arg(skipped == 1 ? "" : "s")
                                 .arg(skipped == 1 ? "ies" : "y")
                                 .arg(skipped == 1 ? "was" : "were"),
                             15000);
  return true;
}

void MainWindow::set_inspector(const std::string& id) {
  int index = -1;
  if (!id.empty() && id != "none") {
    for (std::size_t i = 0; i < inspectors_.size(); ++i)
      if (inspectors_[i]->id() == id) index = static_cast<int>(i);
    if (index < 0)
      throw Error(ErrorCode::InvalidArgument,
                  "unknown inspector '" + id + "' (known: " + plugins::builtin_inspectors().ids() + ")");
  }
  active_ = index;
  inspector_combo_->setCurrentIndex(index + 1);
  inspector_stack_->setCurrentIndex(index + 1);
  for (QAction* action : inspect_group_->actions())
    if (action->data().toString().toStdString() == (index < 0 ? std::string() : id)) action->setChecked(true);
  QElapsedTimer clock;
  clock.start();
  refresh_inspector();
  if (index >= 0 && scene_)
    note_operation("Inspect " + QString::fromStdString(inspectors_[static_cast<std::size_t>(index)]->title()),
                   static_cast<double>(clock.nsecsElapsed()) / 1e6);
}

void MainWindow::set_inspector_option(const std::string& name, const std::string& value) {
  plugins::Inspector* active = inspector();
  if (!active)
    throw Error(ErrorCode::InvalidArgument, "option '" + name + "' needs an inspector (--inspect)");
  sync_active_inspector();
  active->set_option(name, value);
  refresh_inspector();
}

plugins::Inspector* MainWindow::inspector() const {
  return active_ >= 0 ? inspectors_[static_cast<std::size_t>(active_)].get() : nullptr;
}

std::string MainWindow::inspector_id() const { return inspector() ? inspector()->id() : std::string(); }

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

bool MainWindow::frame_selected() {
  const plugins::Inspector* active = inspector();
  const auto focus = active ? active->focus() : std::nullopt;
  if (!focus) return false;
  view_->frame(focus->center, focus->radius);
  view_->render();
  return true;
}

void MainWindow::set_skeleton_visible(bool visible) {
  show_skeleton_ = visible;
  if (skeleton_action_->isChecked() != visible) skeleton_action_->setChecked(visible);
  refresh_overlays();
  view_->render();
}

void MainWindow::set_normals_visible(bool visible) {
  if (normals_action_->isChecked() != visible) normals_action_->setChecked(visible);
  view_->set_normals_visible(visible);
  view_->render();
}

void MainWindow::mark_inspectors_stale(plugins::SceneChange change) {
  stale_.resize(inspectors_.size(), Stale::None);
  for (Stale& s : stale_)
    if (change == plugins::SceneChange::Model)
      s = Stale::Model;
    else if (s == Stale::None)
      s = Stale::Pose;
}

void MainWindow::sync_active_inspector() {
  if (active_ < 0 || !scene_) return;
  stale_.resize(inspectors_.size(), Stale::Model);
  Stale& s = stale_[static_cast<std::size_t>(active_)];
  if (s != Stale::None)
    inspectors_[static_cast<std::size_t>(active_)]->set_scene(
        *scene_, s == Stale::Model ? plugins::SceneChange::Model : plugins::SceneChange::Pose);
  s = Stale::None;
}

void MainWindow::refresh_inspector() {
  if (!scene_) return;
  sync_active_inspector();
  plugins::Inspector* active = inspector();
  for (std::size_t i = 0; i < scene_->pieces.size(); ++i)
    view_->set_piece_colors(i, active ? active->piece_colors(i) : plugins::PieceColors{});
  view_->set_color_bar(active ? active->color_bar() : std::nullopt);
  refresh_overlays();
  view_->render();
}

void MainWindow::refresh_overlays() {
  if (!scene_) return;
  const Model& model = *scene_->model;
  const bool skeleton = show_skeleton_ && !model.skins.empty();
  view_->set_overlay(SceneView::Layer::Skeleton, skeleton ? plugins::skeleton_overlay(*scene_) : Overlay{});
  std::vector<BoneHandle> handles;
  if (skeleton) {
    auto origin = [&](int node) { return glm::vec3(scene_->world[static_cast<std::size_t>(node)][3]); };
    for (int j : plugins::joint_nodes(model)) handles.push_back({j, origin(j), origin(j)});
    for (const auto& [parent, child] : plugins::skeleton_bones(model))
      handles.push_back({parent, origin(parent), origin(child)});
  }
  view_->set_bone_handles(std::move(handles));
  plugins::Inspector* active = inspector();
  view_->set_overlay(SceneView::Layer::Inspector, active ? active->overlay() : Overlay{});
  std::vector<std::string> caption = {QFileInfo(path_).fileName().toStdString() + "  |  " +
                                      (active ? active->title() : std::string("Materials"))};
  if (active)
    for (const std::string& line : active->summary()) caption.push_back(line);
  view_->set_caption(caption);
  refresh_status();
}

void MainWindow::refresh_status() {
  if (!scene_) {
    counts_label_->setText("no model");
    time_label_->setText("");
    operation_label_->setText(last_operation_);
    return;
  }
  const plugins::SceneCounts counts = plugins::scene_counts(*scene_);
  counts_label_->setText(
      QString("%1 vertices  %2 triangles").arg(thousands(counts.vertices), thousands(counts.triangles)));
  const int a = scene_->animation;
  const QString clip =
      a < 0 ? QString("Rest pose")
            : (scene_->model->animations[static_cast<std::size_t>(a)].name.empty()
                   ? QString("Animation %1").arg(a)
                   : QString::fromStdString(scene_->model->animations[static_cast<std::size_t>(a)].name));
  time_label_->setText(QString("%1  t = %2 s").arg(clip).arg(scene_->time, 0, 'f', 3));
  operation_label_->setText(last_operation_);
}

void MainWindow::on_pose_changed(int animation, float time) {
  if (!scene_) return;
  index_timer_->start();  // the operations' preprocessing follows once the pose stays put
  detach_index();         // its grids are filed at the previous pose
  plugins::pose_scene(*scene_, animation, time);
  view_->update_pose();
  tool_displaced_ = false;
  show_tool_displacement();
  mark_inspectors_stale(plugins::SceneChange::Pose);
  sync_active_inspector();
  refresh_tool_preview();
  refresh_overlays();
  view_->render();
}

bool MainWindow::on_pointer(const PointerEvent& event) {
  plugins::Tool* active_tool = tool();
  if (!active_tool || !scene_) return false;
  plugins::ToolPointer pointer;
  pointer.ray_origin = event.ray_origin;
  pointer.ray_direction = event.ray_direction;
  pointer.view_direction = view_->view_direction();
  switch (event.phase) {
    case PointerEvent::Phase::Press:
      if (!event.pick || !active_tool->press(*scene_, *event.pick, pointer)) return false;
      break;
    case PointerEvent::Phase::Move:
      active_tool->move(*scene_, pointer);
      break;
    case PointerEvent::Phase::Release:
      active_tool->release(*scene_);
      break;
  }
  if (!tool_timer_->isActive()) {
    tool_clock_.start();
    tool_timer_->start();
  }
  step_tool();
  return true;
}

void MainWindow::step_tool() {
  plugins::Tool* active_tool = tool();
  if (!active_tool || !scene_) {
    tool_timer_->stop();
    return;
  }
  // Real time since the last step, capped so a stalled event loop does not jump.
  const float dt = std::min(0.05f, static_cast<float>(tool_clock_.restart()) / 1000.0f);
  const bool moving = active_tool->step(*scene_, dt);
  show_tool_displacement();
  if (!moving) tool_timer_->stop();
  view_->render();
}

void MainWindow::show_tool_displacement() {
  if (!scene_) return;
  plugins::Tool* active_tool = tool();
  std::vector<glm::vec3> positions;
  bool displaced = false;
  for (std::size_t i = 0; i < scene_->pieces.size(); ++i)
    if (active_tool && active_tool->displaced_positions(*scene_, i, positions)) {
      view_->set_piece_positions(i, positions);
      displaced = true;
    }
  // Settled (or another tool): draw the posed model again, once.
  if (!displaced && tool_displaced_)
    for (std::size_t i = 0; i < scene_->pieces.size(); ++i) view_->set_piece_positions(i, scene_->pieces[i].posed);
  tool_displaced_ = displaced;
}

void MainWindow::on_pick(const plugins::Pick& pick) {
  if (!scene_) return;
  if (pick.joint_node < 0 && pick.piece < scene_->pieces.size()) last_surface_click_ = pick.position;
  if (plugins::Inspector* active = inspector()) {
    sync_active_inspector();
    if (active->pick(pick)) refresh_inspector();
    return;
  }
  if (pick.joint_node >= 0)
    statusBar()->showMessage(
        QString("Joint %1 (Inspect > Skin weights shows its weights)")
            .arg(QString::fromStdString(plugins::node_label(*scene_->model, pick.joint_node))),
        8000);
  else if (pick.piece < scene_->pieces.size())
    statusBar()->showMessage(
        QString("Piece %1, vertex %2, face %3").arg(pick.piece).arg(pick.vertex.index).arg(pick.face.index),
        8000);
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
  open_file(path);
}

void MainWindow::closeEvent(QCloseEvent* event) {
  timeline_->pause();
  QSettings().setValue("window_state", saveState());
  event->accept();
}

}  // namespace deepcut::studio
