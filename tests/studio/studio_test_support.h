// SPDX-License-Identifier: MIT
#pragma once
/// @file studio_test_support.h
/// Set-up shared by the studio GUI tests (QTest, one executable each): the default model, a
/// shown main window, exports read back as bytes, and the checks every operation session ends
/// with (undo all, redo all, validate, `deepcut apply` of the history). The check helpers record
/// QTest failures and return early: callers continue with
/// `if (QTest::currentTestFailed()) return;` where later steps depend on them.

#include <QString>
#include <QtTest/QtTest>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/ops/operation.h"
#include "main_window.h"
#include "tools.h"

namespace deepcut::test::studio {

using deepcut::studio::MainWindow;

inline const QString kCactus = QStringLiteral(DEEPCUT_ASSETS_DIR "/cactus.glb");

inline std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// A 1280x800 main window, shown and exposed (nullptr if the display never exposes it). Errors
/// go to `last_error()` only, unless `error_dialogs`.
inline std::unique_ptr<MainWindow> shown_window(bool error_dialogs = false) {
  deepcut::studio::MainWindowOptions options;
  options.error_dialogs = error_dialogs;
  auto window = std::make_unique<MainWindow>(options);
  window->resize(1280, 800);
  window->show();
  if (!QTest::qWaitForWindowExposed(window.get())) return nullptr;
  return window;
}

/// The glTF bytes of the window's model now, written as a temporary NAME.glb without going
/// through the studio (no export noted): the session edits its model in place, so a state is
/// kept by its bytes, not by holding the model.
inline std::string model_bytes(MainWindow& window, const std::string& name) {
  const std::string path = temp_dir("studio-states") + "/" + name + ".glb";
  write_gltf(*window.model(), path);
  return read_bytes(path);
}

/// Exports the window's model to DIR/NAME.glb. @returns the file's bytes ("" if the export failed).
inline std::string export_bytes(MainWindow& window, const std::string& dir, const std::string& name) {
  const std::string path = dir + "/" + name + ".glb";
  if (!window.export_file(QString::fromStdString(path))) return std::string();
  return read_bytes(path);
}

/// With `before.size()` operations applied: undoing them one by one restores the export taken
/// before each (`before[i]`), redoing all gives `final_bytes` again (exported as DIR/redo.glb),
/// and that export passes the Khronos validator.
inline void check_undo_all_redo_all(MainWindow& window, const std::string& dir, const std::vector<std::string>& before,
                                    const std::string& final_bytes) {
  for (std::size_t i = before.size(); i-- > 0;) {
    window.undo_action()->trigger();
    QVERIFY2(export_bytes(window, dir, "undo" + std::to_string(i)) == before[i],
             ("undo of operation " + std::to_string(i) + " does not restore the export").c_str());
  }
  for (std::size_t i = 0; i < before.size(); ++i) window.redo_action()->trigger();
  QVERIFY2(export_bytes(window, dir, "redo") == final_bytes, "redo all does not give the same export");
  const auto validation = validate_gltf(dir + "/redo.glb");
  QVERIFY2(validation.exit_code == 0, (validation.out + validation.err).c_str());
}

/// Writes `history` to DIR/NAME.json and runs `deepcut apply` of it on the original cactus into
/// DIR/NAME.glb. @returns the output's bytes, or "deepcut apply failed: ..." with its stderr.
inline std::string cli_apply(const History& history, const std::string& dir, const std::string& name) {
  {
    std::ofstream out(dir + "/" + name + ".json");
    out << history_to_json(history);
  }
  const auto run = run_cli("apply " + quote(kCactus.toStdString()) + " " + quote(dir + "/" + name + ".json") +
                           " -o " + quote(dir + "/" + name + ".glb"));
  if (run.exit_code != 0) return "deepcut apply failed: " + run.err;
  return read_bytes(dir + "/" + name + ".glb");
}

/// `deepcut apply` of `history` on the original cactus (DIR/history.json -> DIR/history.glb)
/// equals `studio_bytes`.
inline void check_cli_apply_equals(const History& history, const std::string& dir, const std::string& studio_bytes) {
  const std::string cli = cli_apply(history, dir, "history");
  QVERIFY2(cli.rfind("deepcut apply failed", 0) != 0, cli.c_str());
  QVERIFY2(cli == studio_bytes, "deepcut apply of the studio's history differs");
}

}  // namespace deepcut::test::studio
