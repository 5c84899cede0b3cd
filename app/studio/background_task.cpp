// SPDX-License-Identifier: MIT
#include "background_task.h"

#include <QEventLoop>
#include <QLabel>
#include <QProgressBar>
#include <QPushButton>
#include <QStatusBar>
#include <QThread>
#include <QTimer>

namespace deepcut::studio {
namespace {

// A task shows in the status bar once it has run this long, then follows its stages at most
// once per kRefreshMs (BackgroundTask's header says why).
constexpr int kShowAfterMs = 500;
constexpr int kRefreshMs = 500;

}  // namespace

void TaskProgress::stage(const QString& name) {
  if (cancelled_.load()) throw TaskCancelled{};
  if (report_) report_(name);
}

struct BackgroundTask::Running {
  QString title, stage;
  int stages = 1, done = 0;
  bool cancelling = false;  // Cancel was pressed: the status bar says so
  std::shared_ptr<TaskProgress> progress = std::make_shared<TaskProgress>();
  QThread* thread = nullptr;
  // Written by the worker before it ends, read on the UI thread after QThread::finished.
  Deliver deliver;
  std::exception_ptr error;
  bool cancelled = false;
  std::function<void(std::exception_ptr)> on_error;
  std::function<void()> on_cancel;
};

BackgroundTask::BackgroundTask(QStatusBar* bar, QObject* parent) : QObject(parent) {
  label_ = new QLabel(bar);
  label_->setObjectName("task_label");
  bar_ = new QProgressBar(bar);
  bar_->setObjectName("task_progress");
  bar_->setMaximumWidth(180);
  bar_->setTextVisible(false);
  cancel_ = new QPushButton("Cancel", bar);
  cancel_->setObjectName("task_cancel");
  cancel_->setToolTip("Stops at the next stage; the studio stays as it was");
  bar->addWidget(label_);
  bar->addWidget(bar_);
  bar->addWidget(cancel_);
  for (QWidget* w : {static_cast<QWidget*>(label_), static_cast<QWidget*>(bar_), static_cast<QWidget*>(cancel_)})
    w->hide();
  connect(cancel_, &QPushButton::clicked, this, &BackgroundTask::cancel);
  refresh_ = new QTimer(this);
  refresh_->setSingleShot(true);
  connect(refresh_, &QTimer::timeout, this, &BackgroundTask::refresh);
}

BackgroundTask::~BackgroundTask() {
  if (!running_) return;
  running_->progress->cancelled_ = true;  // the job stops at its next stage; nothing is delivered
  running_->thread->wait();
  delete running_->thread;
}

bool BackgroundTask::start(const QString& title, int stages, Job job,
                           std::function<void(std::exception_ptr)> on_error, std::function<void()> on_cancel) {
  if (running_) return false;
  running_ = std::make_unique<Running>();
  Running* run = running_.get();
  run->title = title;
  run->stages = stages < 1 ? 1 : stages;
  run->on_error = std::move(on_error);
  run->on_cancel = std::move(on_cancel);
  run->progress->report_ = [this](const QString& stage) {
    QMetaObject::invokeMethod(this, [this, stage] { show_stage(stage); }, Qt::QueuedConnection);
  };
  std::shared_ptr<TaskProgress> progress = run->progress;
  run->thread = QThread::create([run, progress, job = std::move(job)] {
    try {
      run->deliver = job(*progress);
    } catch (const TaskCancelled&) {
      run->cancelled = true;
    } catch (...) {
      run->error = std::current_exception();
    }
  });
  connect(run->thread, &QThread::finished, this, &BackgroundTask::end, Qt::QueuedConnection);
  refresh_->start(kShowAfterMs);
  emit busy_changed(true);
  run->thread->start();
  return true;
}

void BackgroundTask::show_stage(const QString& stage) {
  if (!running_) return;
  running_->stage = stage;
  ++running_->done;
  if (bar_->isVisible() && !refresh_->isActive()) refresh_->start(kRefreshMs);
  emit stage_changed(stage);
}

void BackgroundTask::refresh() {
  if (!running_) return;
  if (!bar_->isVisible()) {
    bar_->setRange(0, running_->stages);
    cancel_->setEnabled(!running_->cancelling);
    for (QWidget* w : {static_cast<QWidget*>(label_), static_cast<QWidget*>(bar_), static_cast<QWidget*>(cancel_)})
      w->show();
  }
  bar_->setValue(std::min(std::max(running_->done - 1, 0), running_->stages));
  label_->setText(running_->cancelling ? running_->title + ": cancelling" : text());
}

QString BackgroundTask::text() const {
  if (!running_) return QString();
  return running_->stage.isEmpty() ? running_->title : running_->title + ": " + running_->stage;
}

void BackgroundTask::cancel() {
  if (!running_) return;
  running_->progress->cancelled_ = true;
  running_->cancelling = true;
  cancel_->setEnabled(false);
  label_->setText(running_->title + ": cancelling");
}

void BackgroundTask::end() {
  if (!running_) return;
  running_->thread->wait();
  std::unique_ptr<Running> run = std::move(running_);
  delete run->thread;
  refresh_->stop();
  for (QWidget* w : {static_cast<QWidget*>(label_), static_cast<QWidget*>(bar_), static_cast<QWidget*>(cancel_)})
    w->hide();
  emit busy_changed(false);
  // Cancel pressed after the last stage still drops the result: the studio stays as it was.
  if (run->cancelled || run->progress->cancelled()) {
    run->deliver = nullptr;
    if (run->on_cancel) run->on_cancel();
  } else if (run->error) {
    if (run->on_error) run->on_error(run->error);
  } else if (run->deliver) {
    try {  // swapping the result in may fail too (out of memory): reported like the job's errors
      run->deliver();
    } catch (...) {
      if (run->on_error) run->on_error(std::current_exception());
    }
  }
  emit finished();
}

void BackgroundTask::wait() {
  if (!running_) return;
  QEventLoop loop;
  connect(this, &BackgroundTask::finished, &loop, &QEventLoop::quit);
  loop.exec();
}

}  // namespace deepcut::studio
