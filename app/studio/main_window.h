// SPDX-License-Identifier: MIT
#pragma once
// The studio's main window: menus (File, Edit, View, Inspect, Tools, Animation, Help), tool bars,
// docks, dialogs, drag and drop and the status bar. The model states, operations and undo steps
// are the Session's (app/session/session.h), applied and edited through operations_host.h; the
// drawn scene is scene_host.h's; tools and inspectors live in tool_host.h and inspector_host.h.

#include <QList>
#include <QElapsedTimer>
#include <QMainWindow>
#include <QString>
#include <QStringList>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/model.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/plugins/inspector.h"
#include "deepcut/plugins/scene.h"
#include "deepcut/plugins/tool.h"
#include "anti_aliasing.h"
#include "background_task.h"
#include "scene_view.h"
#include "session.h"

class QAction;
class QDockWidget;
class QActionGroup;
class QLabel;
class QTimer;
class QListWidget;
class QUndoStack;

namespace deepcut::studio {

class InspectorHost;
class OperationsHost;
class ProblemsPanel;
class SceneHost;
class SceneTree;
class SceneView;
class Timeline;
class MorphPanel;
class ToolHost;
enum class DisplayMode;

/// Where recent files and window layout are remembered, and whether errors open dialogs.
struct MainWindowOptions {
  /// Show errors in a modal dialog (default on). Off: errors only reach `last_error()` and the
  /// status bar (headless screenshots).
  bool error_dialogs = true;
};

class MainWindow : public QMainWindow {
  Q_OBJECT

 public:
  /// How long the studio waits after the last step shown and the last task's end before it
  /// hands the heap's free memory back to the system (release_when_idle).
  static constexpr int kIdleReleaseMs = 2000;

  explicit MainWindow(const MainWindowOptions& options = {}, QWidget* parent = nullptr);
  ~MainWindow() override;

  /// Reads `path` and shows it (the history starts anew). On failure the current model stays,
  /// the one-line message is shown (dialog) and kept in `last_error()`.
  /// @returns true when the model was opened.
  /// Reading, welding, posing and the view's data are made off the UI thread (background_task.h)
  /// while this waits, processing events; Cancel leaves everything as it was (returns false).
  /// After the first frame the operations' posed model (grids included) is built off the UI
  /// thread too ("Indexing"); this returns once it is.
  bool open_file(const QString& path);
  /// Starts opening `path` off the UI thread and returns at once (what File > Open, a drop and
  /// a recent file do); the model is shown when it is ready, errors are reported like
  /// open_file's. @returns false (reported) while another task runs.
  bool begin_open(const QString& path);
  /// Like `open_file` but lets the error propagate instead of reporting it.
  /// @throws Error from read_gltf (Io, InvalidInput).
  void load_file(const QString& path);
  /// Writes the current model state with `write_gltf` (.glb or .gltf by extension), exactly as
  /// `deepcut convert` would write it, compressed as `deepcut convert --compress` would.
  /// @returns true on success; errors are reported like open_file's.
  /// Writes off the UI thread (edits are disabled meanwhile) while this waits, processing
  /// events; the file appears complete when it succeeds, else (error, Cancel) stays as it was.
  bool export_file(const QString& path, Compression compression = Compression::None);
  /// Starts the export and returns at once (the Export dialog). @returns false (reported)
  /// when nothing is open or another task runs.
  bool begin_export(const QString& path, Compression compression = Compression::None);
  /// The long work running off the UI thread (open, export, re-run, re-cluster) and its
  /// progress bar and Cancel in the status bar.
  BackgroundTask* task() const { return task_; }
  /// Where the last open's time went (ms from the click): until the worker's result arrived,
  /// swapping it in on the UI thread, drawing the first frame, and the whole (open to first frame).
  /// `frame_begin` and `frame_end` (steady clock) bound the first frame's drawing. On the
  /// worker, ms from the click: the file read and welded, the scene posed, the view's data built.
  struct OpenTiming {
    double delivered_ms = 0.0, swap_ms = 0.0, first_frame_ms = 0.0, total_ms = 0.0;
    double read_ms = 0.0, posed_ms = 0.0, prepared_ms = 0.0;
    std::chrono::steady_clock::time_point frame_begin, frame_end;
  };
  OpenTiming last_open_timing() const { return open_timing_; }
  /// What the Export dialog offers: `<model>-export.glb` in the model's folder (`model.glb` in
  /// the working folder when nothing was opened from a file), numbered `-export-2`, `-export-3`...
  /// past files that exist, so accepting the dialog never overwrites the input or an earlier
  /// export unless the user picks that file (and confirms the overwrite).
  QString suggested_export_path() const;

  /// Replaces the model by `result` of an operation named `label` that took `ms`, undoably.
  void apply_operation(const QString& label, std::shared_ptr<const Model> result, double ms);

  /// Chooses operation tool `id` ("cut", "tear", "drill"; "" or "none": no tool). The tool
  /// places itself on the model (current pose and view; at the surface point under the mouse
  /// cursor, else at the last clicked surface point), its widget appears in the view and its
  /// preview is drawn.
  /// @throws Error{InvalidArgument} for an unknown id.
  void set_tool(const std::string& id);
  /// The active tool, or nullptr.
  plugins::Tool* tool() const;
  std::string tool_id() const;
  /// Runs the operations of `history` on the current model as `deepcut apply` would, each one an
  /// undoable history entry (one that misses the model changes nothing and makes none).
  /// @throws Error naming `source` and the operation index when one is invalid (nothing changes).
  void apply_history(const History& history, const std::string& source);
  /// Applies the active tool's parameters at the current pose (animation and time) through
  /// `deepcut::apply_operation`, undoably; the history entry names type, parameters and time.
  /// Errors and a tool that misses the model are reported like open_file's. While editing a
  /// past operation the re-run runs off the UI thread (progress, Cancel) while this waits,
  /// processing events. @returns true when the model changed.
  bool apply_tool();

  /// One operation made since the model was opened, as it last ran (session.h).
  using OperationEntry = session::OperationEntry;
  /// The operations of the current state since the model was opened (the Operations list):
  /// what `deepcut apply` of them on the opened file reproduces.
  std::vector<OperationEntry> operations() const;
  /// Starts editing operation `index` of `operations()`: the model is shown as it was before it,
  /// its tool is chosen with its parameters and pose, and Apply re-runs it with the panel's
  /// parameters and then every later operation, as one undoable step (an operation that no
  /// longer applies is skipped and marked). @returns false (reported) for a bad index.
  bool edit_operation(int index);
  /// Leaves editing without changing anything.
  void cancel_edit();
  /// The operation being edited, or -1.
  int editing_operation() const;
  QListWidget* operations_list() const;

  /// Activates inspector `id` ("" or "none": the model's own look).
  /// @throws Error{InvalidArgument} for an unknown id.
  void set_inspector(const std::string& id);
  /// Passes an option to the active inspector. @throws Error{InvalidArgument} (see Inspector).
  void set_inspector_option(const std::string& name, const std::string& value);
  /// The active inspector, or nullptr.
  plugins::Inspector* inspector() const;
  std::string inspector_id() const;

  /// Poses the model: animation `animation` (-1 rest pose) at `time` seconds (clamped).
  void set_pose(int animation, float time);

  void set_display_mode(DisplayMode mode);
  /// Chooses the view's anti-aliasing (anti_aliasing.h) and draws a frame; `remember` keeps the
  /// choice for the next sessions (the View menu does; `--anti-aliasing` does not).
  void set_anti_aliasing(AntiAliasing mode, bool remember = true);
  AntiAliasing anti_aliasing() const { return anti_aliasing_; }
  /// Zooms the view to the active inspector's selection (picked vertex, chosen joint).
  /// @returns false when there is nothing selected.
  bool frame_selected();
  void set_skeleton_visible(bool visible);
  void set_normals_visible(bool visible);

  /// The current model state (null before the first successful open).
  std::shared_ptr<const Model> model() const;
  /// The model states, operations and undo steps shown.
  const session::Session& session() const;
  const plugins::Scene* scene() const;
  QString model_path() const { return path_; }
  QString last_error() const { return last_error_; }
  QString last_operation() const { return last_operation_; }
  /// How long the last operation took (the session's apply, its undo record included), in ms.
  double last_operation_ms() const { return last_operation_ms_; }
  /// The scene's host (the benchmark reads where a step's time went: SceneHost::StepTiming).
  const SceneHost* scene_host() const { return scene_host_; }
  QStringList recent_files() const;

  SceneView* view() const { return view_; }
  Timeline* timeline() const { return timeline_; }
  SceneTree* scene_tree() const { return tree_; }
  /// The Problems panel (what reading the open model repaired or dropped).
  ProblemsPanel* problems_panel() const { return problems_; }
  /// Whether the Problems panel is shown (it is when the opened model had problems).
  bool problems_shown() const;
  QUndoStack* history() const;
  QAction* undo_action() const { return undo_; }
  QAction* redo_action() const { return redo_; }

  /// Renders the view and grabs the whole window (view included) as an image.
  QImage screenshot();

  /// The operations' preprocessing (posed_model.h) when it describes the current model, else
  /// nullptr. Built when a model is opened, kept up to date by every drill and tear the studio
  /// applies, and rebuilt shortly after the pose stops changing or the state changes otherwise
  /// (undo, redo, an edit, a cut), or at the next operation, whichever comes first.
  const PosedModel* posed_model() const;
  /// Brings the preprocessing up to date for the current model and pose now (what the studio
  /// does once the pose stays put for a moment).
  void refresh_posed_model();

 signals:
  void model_changed();

 protected:
  void dragEnterEvent(QDragEnterEvent* event) override;
  void dropEvent(QDropEvent* event) override;
  void closeEvent(QCloseEvent* event) override;

 private:
  /// Milliseconds since `clock` started.
  static double ms_since(const QElapsedTimer& clock);
  void build_hosts();
  void build_docks();
  void build_scene_host();
  void build_menus();
  void build_status_bar();
  void build_edit_menu();
  /// @returns Reset camera (the tool bar shows it).
  QAction* build_view_menu();
  void build_anti_aliasing_menu(QMenu* view);
  void build_toolbars(QAction* open, QAction* export_action, QAction* reset);
  void report_error(const QString& message);
  void note_operation(const QString& label, double ms);
  /// Shows the session's current state (after an undo step, an edit, a cancelled edit).
  void show_current();
  /// Hands the heap's free memory back to the system once the studio has been idle for a while
  /// (idle_release_): see release_when_idle.
  void release_when_idle();
  void refresh_status();
  void choose_open();
  void choose_export();
  /// What opening a file makes off the UI thread before anything visible changes.
  struct OpenedModel {
    std::shared_ptr<const Model> model;  // the session takes it over: the scene draws the live model
    plugins::Scene scene;
    std::shared_ptr<const SceneView::Prepared> drawn;  // the scene's VTK data
    OpenTiming timing;  // the worker's marks
  };
  BackgroundTask::Job open_job(const QString& path, std::shared_ptr<QElapsedTimer> clock);
  /// Swaps the opened model in and draws its first frame (UI thread).
  void show_opened(const QString& path, OpenedModel opened, const QElapsedTimer& clock);
  /// Draws the opened model's first frame (held during the swap-in) unless it was drawn.
  void draw_first_frame();
  /// Draws the first frame, then builds the operations' posed model (index_job) on the worker
  /// (`in_background`) or here.
  void draw_frame_and_index(bool in_background);
  /// Starts index_job of the current state at the scene's pose on the worker. @returns false
  /// when another task runs (nothing started), true otherwise.
  bool start_indexing();
  /// Builds the posed model of `model` (the current state: just opened, after a structural step
  /// or at a new pose) at `key` with its grids, for the session to adopt
  /// (SceneHost::adopt_posed_model) while the state stays as it was.
  BackgroundTask::Job index_job(std::shared_ptr<const Model> model, const PoseKey& key);
  /// Waits for index_job when it runs: what is asked right after an open (opening another file,
  /// applying an operation or a history, editing a past one, exporting, a background inspector
  /// job) waits for the posed model, a moment, instead of being refused as while other tasks run.
  void finish_indexing();
  void finish_export(const QString& path, const QString& temp, const QElapsedTimer& clock);
  /// Reports what a job threw, as open_file does (`file` names the file when the error does not).
  void report_exception(std::exception_ptr error, const QString& file);
  /// Disables (busy) or enables again what would edit the session while a task reads it.
  void set_editing_enabled(bool enabled);

  MainWindowOptions options_;
  QString path_, last_error_, last_operation_;
  double last_operation_ms_ = 0.0;
  Compression export_compression_ = Compression::None;  // the Export dialog's last choice

  SceneView* view_ = nullptr;
  SceneTree* tree_ = nullptr;
  ProblemsPanel* problems_ = nullptr;
  QDockWidget* problems_dock_ = nullptr;
  Timeline* timeline_ = nullptr;
  MorphPanel* morph_panel_ = nullptr;
  ToolHost* tools_ = nullptr;
  InspectorHost* inspectors_ = nullptr;
  OperationsHost* operations_ = nullptr;
  SceneHost* scene_host_ = nullptr;
  QAction* undo_ = nullptr;
  QAction* redo_ = nullptr;
  QAction* skeleton_action_ = nullptr;
  QAction* normals_action_ = nullptr;
  QActionGroup* display_group_ = nullptr;
  QActionGroup* anti_aliasing_group_ = nullptr;
  AntiAliasing anti_aliasing_ = AntiAliasing::Automatic;
  QLabel* counts_label_ = nullptr;
  QLabel* time_label_ = nullptr;
  QLabel* operation_label_ = nullptr;
  BackgroundTask* task_ = nullptr;
  QTimer* idle_release_ = nullptr;  // restarted by every step shown and every task's end
  QList<QAction*> edit_actions_;  // disabled while a task runs
  bool open_done_ = false, export_done_ = false;  // the last open / export succeeded
  OpenTiming open_timing_;
  QElapsedTimer open_clock_;  // since the last open started
  bool first_frame_pending_ = false;
  bool status_held_ =
      false;               // the swap-in: the status bar follows the first frame (its counts scan the model)
  bool indexing_ = false;  // index_job runs
};

}  // namespace deepcut::studio
