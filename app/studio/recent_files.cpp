// SPDX-License-Identifier: MIT
#include "recent_files.h"

#include <QAction>
#include <QFileInfo>
#include <QMenu>
#include <QSettings>

namespace deepcut::studio {
namespace {

constexpr int kMaxRecent = 10;
const char* kRecentKey = "recent_files";

}  // namespace

RecentFiles::RecentFiles(QMenu* menu, std::function<void(const QString&)> open, QObject* parent)
    : QObject(parent), menu_(menu), open_(std::move(open)) {
  connect(menu_, &QMenu::aboutToShow, this, &RecentFiles::refresh);
}

QStringList RecentFiles::list() { return QSettings().value(kRecentKey).toStringList(); }

void RecentFiles::remember(const QString& path) {
  QSettings settings;
  QStringList files = settings.value(kRecentKey).toStringList();
  const QString absolute = QFileInfo(path).absoluteFilePath();
  files.removeAll(absolute);
  files.prepend(absolute);
  while (files.size() > kMaxRecent) files.removeLast();
  settings.setValue(kRecentKey, files);
}

void RecentFiles::refresh() {
  menu_->clear();
  const QStringList files = list();
  for (const QString& path : files) {
    QAction* action = menu_->addAction(QFileInfo(path).fileName(), this, [this, path] { open_(path); });
    action->setToolTip(path);
    action->setEnabled(QFileInfo::exists(path));
  }
  if (files.isEmpty()) menu_->addAction("(none)")->setEnabled(false);
  menu_->addSeparator();
  menu_->addAction("Clear list", this, [] { QSettings().remove(kRecentKey); });
}

}  // namespace deepcut::studio
