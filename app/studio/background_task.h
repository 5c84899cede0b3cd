// SPDX-License-Identifier: MIT
#pragma once
/// @file background_task.h
/// Long work off the UI thread: opening a model, exporting, re-running an edited history and
/// re-clustering run as a job on a worker thread while the event loop goes on (the view still
/// turns, the window still repaints). The status bar shows what runs ("Opening cactus.glb:
/// Welding"), a progress bar (one step per stage) and Cancel, once the task has run for a moment
/// (a quick one shows nothing), and follows its stages a few times a second at most: each change
/// of the status bar repaints the whole window, the 3D view included, which on a software
/// renderer takes a core for tens of milliseconds away from the job. The job names its stages through
/// `TaskProgress::stage`; each stage boundary is where Cancel takes effect: the job stops there
/// (TaskCancelled), its partial result is dropped and nothing it would have changed changes. A
/// job returns what to do with its result on the UI thread (`Deliver`), which runs only when the
/// job finished and was not cancelled; an exception from the job reaches `on_error` on the UI
/// thread. One task at a time: callers check `busy()` (and the window disables the actions that
/// would edit what a running job reads).

#include <QObject>
#include <QString>
#include <atomic>
#include <exception>
#include <functional>
#include <memory>

class QLabel;
class QProgressBar;
class QPushButton;
class QStatusBar;
class QThread;
class QTimer;

namespace deepcut::studio {

/// Thrown by `TaskProgress::stage` once Cancel was pressed: the job unwinds, dropping what it made.
struct TaskCancelled {};

/// What a running job sees: its stages and whether it was cancelled. Thread-safe.
class TaskProgress {
 public:
  /// Starts stage `name` ("Reading", "Welding", ...): the status bar shows it (at its next refresh).
  /// @throws TaskCancelled when Cancel was pressed (the stage does not start).
  void stage(const QString& name);
  bool cancelled() const { return cancelled_.load(); }

 private:
  friend class BackgroundTask;
  std::function<void(const QString&)> report_;
  std::atomic<bool> cancelled_{false};
};

class BackgroundTask : public QObject {
  Q_OBJECT

 public:
  /// What the job hands back: run on the UI thread once it finished (not when cancelled).
  using Deliver = std::function<void()>;
  using Job = std::function<Deliver(TaskProgress&)>;

  /// Shows its progress in `bar` (hidden while idle).
  BackgroundTask(QStatusBar* bar, QObject* parent);
  ~BackgroundTask() override;

  /// Runs `job` on a worker thread as "`title`: stage" with `stages` steps on the progress bar.
  /// On the UI thread afterwards: its Deliver (finished), `on_error` (it threw; the exception is
  /// rethrown for the caller to word), or `on_cancel` (Cancel). Then `finished` is emitted.
  /// @returns false (nothing runs) while another task runs.
  bool start(const QString& title, int stages, Job job, std::function<void(std::exception_ptr)> on_error,
             std::function<void()> on_cancel = {});
  /// Whether a task runs.
  bool busy() const { return running_ != nullptr; }
  /// Cancels the running task at its next stage boundary (what Cancel does).
  void cancel();
  /// Processes events until the running task has ended (its Deliver or on_error done).
  void wait();
  /// The running task's title and stage ("Opening cactus.glb: Welding"), empty while idle.
  QString text() const;

 signals:
  /// A task started (true) or ended (false): the window enables or disables its edits.
  void busy_changed(bool busy);
  /// The running task entered `stage`.
  void stage_changed(const QString& stage);
  void finished();

 private:
  struct Running;
  void show_stage(const QString& stage);
  /// Shows the running task's title, stage and progress in the status bar (a timer calls it).
  void refresh();
  void end();

  QLabel* label_ = nullptr;
  QTimer* refresh_ = nullptr;  // single shot: the first showing, then each refresh
  QProgressBar* bar_ = nullptr;
  QPushButton* cancel_ = nullptr;
  std::unique_ptr<Running> running_;
};

}  // namespace deepcut::studio
