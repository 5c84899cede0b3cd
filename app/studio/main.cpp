// SPDX-License-Identifier: MIT
// deepcut-studio: the desktop app. Without arguments it opens the bundled default model; with
// --screenshot it renders one frame of the real window to a PNG and exits (headless use under
// xvfb-run). Exit codes: 0 ok, 2 bad input or usage (one line on stderr), 1 internal error.
#include <QVTKOpenGLNativeWidget.h>
#include <unistd.h>

#include <QApplication>
#include <QDir>
#include <QElapsedTimer>
#include <QFile>
#include <QFileInfo>
#include <QImageWriter>
#include <QMessageBox>
#include <QPalette>
#include <QStyleFactory>
#include <QSurfaceFormat>
#include <QWindow>
#include <fstream>
#include <iostream>
#include <new>
#include <sstream>

#include "deepcut/core/errors.h"
#include "deepcut/core/ops/operation.h"
#include "deepcut/core/process_memory.h"
#include "main_window.h"
#include "scene_view.h"
#include "studio_options.h"

namespace {

using deepcut::Error;
using deepcut::ErrorCode;
using deepcut::studio::MainWindow;
using deepcut::studio::StudioOptions;

/// A dark theme: what Blender users expect, and the model stands out against it.
void apply_theme(QApplication& app) {
  app.setStyle(QStyleFactory::create("Fusion"));
  QPalette p;
  const QColor window(48, 50, 54), base(34, 36, 39), text(220, 222, 226), accent(70, 130, 220);
  p.setColor(QPalette::Window, window);
  p.setColor(QPalette::WindowText, text);
  p.setColor(QPalette::Base, base);
  p.setColor(QPalette::AlternateBase, QColor(42, 44, 48));
  p.setColor(QPalette::ToolTipBase, base);
  p.setColor(QPalette::ToolTipText, text);
  p.setColor(QPalette::Text, text);
  p.setColor(QPalette::Button, QColor(58, 60, 65));
  p.setColor(QPalette::ButtonText, text);
  p.setColor(QPalette::BrightText, Qt::red);
  p.setColor(QPalette::Link, accent);
  p.setColor(QPalette::Highlight, accent);
  p.setColor(QPalette::HighlightedText, Qt::white);
  p.setColor(QPalette::Disabled, QPalette::Text, QColor(120, 122, 126));
  p.setColor(QPalette::Disabled, QPalette::ButtonText, QColor(120, 122, 126));
  p.setColor(QPalette::Disabled, QPalette::WindowText, QColor(120, 122, 126));
  app.setPalette(p);
}

/// Applies the view options of the command line to the window (after the model is open).
/// @throws Error{InvalidArgument} for an unknown inspector, joint, vertex or animation.
void apply_options(MainWindow& window, const StudioOptions& o) {
  std::string inspect = o.inspect;
  if (inspect.empty() && !o.joint.empty()) inspect = "weights";
  if (inspect.empty() && !o.vertex.empty()) inspect = "adjacency";
  const auto model = window.model();
  if (!o.animation.empty() && model) {
    int index = -1;
    for (std::size_t i = 0; i < model->animations.size(); ++i)
      if (model->animations[i].name == o.animation || std::to_string(i) == o.animation)
        index = static_cast<int>(i);
    if (index < 0)
      throw Error(ErrorCode::InvalidArgument, "no animation '" + o.animation + "' (the model has " +
                                                  std::to_string(model->animations.size()) + ")");
    window.set_pose(index, 0.0f);
  }
  if (!o.apply.empty()) {
    std::ifstream in(o.apply);
    if (!in) throw Error(ErrorCode::Io, o.apply + ": cannot open history file");
    std::stringstream text;
    text << in.rdbuf();
    deepcut::History history;
    try {
      history = deepcut::parse_history(text.str());
    } catch (const Error& e) {
      throw Error(e.code(), o.apply + ": " + e.what());
    }
    window.apply_history(history, o.apply);
  }
  if (o.time) window.set_pose(window.scene() ? window.scene()->animation : -1, *o.time);
  if (!inspect.empty()) window.set_inspector(inspect);
  if (!o.joint.empty()) window.set_inspector_option("joint", o.joint);
  if (!o.vertex.empty()) window.set_inspector_option("vertex", o.vertex);
  using deepcut::studio::DisplayMode;
  window.set_display_mode(o.view == "wireframe" ? DisplayMode::Wireframe
                          : o.view == "edges"   ? DisplayMode::ShadedEdges
                                                : DisplayMode::Shaded);
  window.set_normals_visible(o.normals);
  window.set_skeleton_visible(o.skeleton);
  if (o.frame && !window.frame_selected())
    throw Error(ErrorCode::InvalidArgument,
                "--frame: nothing selected (use --joint or --vertex with an inspector)");
  if (o.look_at) window.view()->frame({(*o.look_at)[0], (*o.look_at)[1], (*o.look_at)[2]}, (*o.look_at)[3]);
}

std::string model_path(const StudioOptions& o) {
  if (!o.model.empty()) return o.model;
  std::vector<std::string> searched;
  const std::string path =
      deepcut::studio::default_model_path(QApplication::applicationDirPath().toStdString(), &searched);
  if (path.empty()) {
    std::string list;
    for (const auto& s : searched) list += (list.empty() ? "" : ", ") + s;
    throw Error(ErrorCode::Io, "the default model assets/cactus.glb was not found (looked in " + list + ")");
  }
  return path;
}

int screenshot(MainWindow& window, const StudioOptions& o) {
  window.resize(o.width, o.height);
  window.load_file(QString::fromStdString(model_path(o)));
  apply_options(window, o);
  window.show();
  // Wait for the window system to map the window, then let layout and GL settle.
  QElapsedTimer clock;
  clock.start();
  while ((!window.windowHandle() || !window.windowHandle()->isExposed()) && clock.elapsed() < 10000)
    QApplication::processEvents(QEventLoop::AllEvents, 50);
  for (int i = 0; i < 5; ++i) QApplication::processEvents(QEventLoop::AllEvents, 20);
  // Frame again now that the view has its final size (the aspect ratio decides the framing).
  window.view()->reset_camera();
  if (o.frame) window.frame_selected();
  if (o.look_at) window.view()->frame({(*o.look_at)[0], (*o.look_at)[1], (*o.look_at)[2]}, (*o.look_at)[3]);
  const QImage image = window.screenshot();
  if (image.isNull())
    throw Error(ErrorCode::InvariantViolated, "screenshot: the window could not be grabbed");
  QImageWriter writer(QString::fromStdString(o.screenshot), "png");
  writer.setQuality(0);  // PNG: 0 is the strongest (lossless) compression
  if (!writer.write(image))
    throw Error(ErrorCode::Io,
                o.screenshot + ": cannot write the screenshot (" + writer.errorString().toStdString() + ")");
  std::cerr << "deepcut-studio: wrote " << o.screenshot << " (" << image.width() << "x" << image.height()
            << ")\n";
  return 0;
}

bool asks_for_help(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "-h" || std::string(argv[i]) == "--help") return true;
  return false;
}

bool has_display() {
  return !qEnvironmentVariableIsEmpty("DISPLAY") || !qEnvironmentVariableIsEmpty("WAYLAND_DISPLAY") ||
         !qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM");
}

// Qt warns on stderr when XDG_RUNTIME_DIR is unset (xvfb-run, CI); give it a private one so
// stderr keeps to the one-line messages the exit codes promise.
void give_qt_a_runtime_dir() {
  if (!qEnvironmentVariableIsEmpty("XDG_RUNTIME_DIR")) return;
  const QString dir = QDir::tempPath() + "/runtime-deepcut-" + QString::number(::getuid());
  if (QDir().mkpath(dir) &&
      QFile::setPermissions(dir, QFileDevice::ReadOwner | QFileDevice::WriteOwner | QFileDevice::ExeOwner))
    qputenv("XDG_RUNTIME_DIR", dir.toLocal8Bit());
}

// The command line's arguments after the program's name, as Qt left them.
std::vector<std::string> studio_arguments() {
  std::vector<std::string> args;
  const QStringList qt_args = QApplication::arguments();
  for (int i = 1; i < qt_args.size(); ++i) args.push_back(qt_args[i].toStdString());
  return args;
}

// Opens the model and applies the options in the shown window; a failure is reported in a dialog.
void open_with_options(MainWindow& window, const StudioOptions& options) {
  std::string path;
  try {
    path = model_path(options);
  } catch (const Error& e) {
    QMessageBox::critical(&window, "DeepCut Studio", e.what());
  }
  if (!path.empty() && window.open_file(QString::fromStdString(path))) {
    try {
      apply_options(window, options);
    } catch (const Error& e) {
      QMessageBox::critical(&window, "DeepCut Studio", e.what());
    }
  }
}

// The studio's window: a screenshot taken, or the window shown until it is closed.
int run_studio(const StudioOptions& options) {
  deepcut::studio::MainWindowOptions window_options;
  window_options.error_dialogs = options.screenshot.empty();
  MainWindow window(window_options);
  // A screenshot is one frame meant to be looked at: smooth edges unless told otherwise.
  const std::string anti_aliasing =
      options.anti_aliasing.empty() && !options.screenshot.empty() ? "on" : options.anti_aliasing;
  if (!anti_aliasing.empty())
    window.set_anti_aliasing(*deepcut::studio::parse_anti_aliasing(anti_aliasing), false);
  if (!options.screenshot.empty()) return screenshot(window, options);
  window.show();
  QApplication::processEvents();  // lay the window out, so the first framing sees the view's size
  open_with_options(window, options);
  if (!window.isVisible()) return 0;  // closed while the model was opening (the open was cancelled)
  return QApplication::exec();
}

}  // namespace

int main(int argc, char** argv) {
  deepcut::keep_freed_memory();  // an operation writes into the pages the last one freed
  // --help, and a clear message instead of Qt's abort when there is no display at all.
  if (asks_for_help(argc, argv)) {
    std::cout << deepcut::studio::studio_usage();
    return 0;
  }
  if (!has_display()) {
    std::cerr << "deepcut-studio: no display; run it under xvfb-run -a -s \"-screen 0 1600x1000x24\" "
                 "(scripts/run.sh does)\n";
    return 1;
  }
  give_qt_a_runtime_dir();
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setOrganizationName("DeepCut");
  QApplication::setApplicationName("DeepCut Studio");
  apply_theme(app);
  StudioOptions options;
  try {
    options = deepcut::studio::parse_studio_options(studio_arguments());
  } catch (const deepcut::studio::UsageError& e) {
    std::cerr << "deepcut-studio: " << e.what() << " (see deepcut-studio --help)\n";
    return 2;
  }
  try {
    return run_studio(options);
  } catch (const Error& e) {
    std::cerr << "deepcut-studio: " << e.what() << "\n";
    return e.is_input_error() ? 2 : 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "deepcut-studio: out of memory\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "deepcut-studio: internal error: " << e.what() << "\n";
    return 1;
  }
}
