// SPDX-License-Identifier: MIT
#pragma once
/// @file recent_files.h
/// File > Open Recent: the files last opened, newest first (at most 10), kept in QSettings
/// under "recent_files".

#include <QObject>
#include <QString>
#include <QStringList>
#include <functional>

class QMenu;

namespace deepcut::studio {

class RecentFiles : public QObject {
  Q_OBJECT

 public:
  /// Fills `menu` each time it opens; choosing an entry calls `open` with its path.
  RecentFiles(QMenu* menu, std::function<void(const QString&)> open, QObject* parent);

  /// The remembered files (absolute paths), newest first.
  static QStringList list();
  /// Puts `path` first.
  static void remember(const QString& path);

 private:
  void refresh();

  QMenu* menu_;
  std::function<void(const QString&)> open_;
};

}  // namespace deepcut::studio
