// SPDX-License-Identifier: MIT
// GUI test of the Problems panel (QTest under xvfb-run): opening a file whose reading repaired
// something shows the panel with one row per kind (the lines `deepcut` prints on stderr), the
// status bar points at it and the export asks with the same list; opening a clean model clears
// and hides it.
#include <QVTKOpenGLNativeWidget.h>

#include <QAction>
#include <QApplication>
#include <QListWidget>
#include <QStatusBar>
#include <QSurfaceFormat>
#include <QtTest/QtTest>

#include "main_window.h"
#include "problems_panel.h"
#include "studio_test_support.h"

namespace {

using deepcut::studio::MainWindow;

const QString kRepaired = QStringLiteral(DEEPCUT_SOURCE_DIR "/tests/data/bad/joint_past_skin.gltf");

class StudioProblemsTest : public QObject {
  Q_OBJECT

 private slots:
  void opening_a_repaired_file_lists_each_repair_and_the_export_asks() {
    auto window = deepcut::test::studio::shown_window();
    QVERIFY(window);
    QVERIFY2(window->open_file(kRepaired), qPrintable(window->last_error()));
    auto* panel = window->problems_panel();
    QVERIFY(window->problems_shown());

    // The rows are what `deepcut convert` prints on stderr for the same file, kind by kind.
    const auto cli = deepcut::test::run_cli("convert " + deepcut::test::quote(kRepaired.toStdString()) + " -o " +
                                            deepcut::test::quote(deepcut::test::temp_dir("problems-gui") + "/o.glb"));
    QCOMPARE(cli.exit_code, 0);
    QStringList printed;
    for (const QString& line : QString::fromStdString(cli.err).split('\n', Qt::SkipEmptyParts))
      if (line.endsWith(']')) printed << line.section(": ", 2);
    QCOMPARE(panel->lines(), printed);
    QCOMPARE(panel->lines().size(), 2);
    QVERIFY(panel->lines().filter("[joints-past-skin]").size() == 1);
    QVERIFY(panel->lines().filter("[weights-normalised]").size() == 1);
    auto* list = panel->findChild<QListWidget*>("problems_list");
    QVERIFY(list);
    QCOMPARE(list->count(), 2);

    QVERIFY2(window->statusBar()->currentMessage().contains("Problems panel"),
             qPrintable(window->statusBar()->currentMessage()));
    const QString question = panel->export_question();
    for (const QString& line : panel->lines()) QVERIFY2(question.contains(line), qPrintable(question));

    // A clean model clears the list and hides the panel; nothing to ask before exporting it.
    QVERIFY(window->open_file(deepcut::test::studio::kCactus));
    QVERIFY(panel->lines().isEmpty());
    QVERIFY(panel->export_question().isEmpty());
    QVERIFY(!window->problems_shown());
  }
};

}  // namespace

int main(int argc, char** argv) {
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setOrganizationName("DeepCut");
  QApplication::setApplicationName("DeepCut Studio Problems Tests");
  StudioProblemsTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "problems_gui_test.moc"
