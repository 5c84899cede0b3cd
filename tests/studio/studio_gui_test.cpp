// SPDX-License-Identifier: MIT
// GUI tests of the real studio window (QTest, run under xvfb-run): open models, switch
// inspectors, scrub the time line, pick in the view, undo/redo, drag and drop, export and
// validate, and keep the previous model when a file is malformed.
#include <QVTKOpenGLNativeWidget.h>

#include <QAction>
#include <QApplication>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QLabel>
#include <QMessageBox>
#include <QMimeData>
#include <QSlider>
#include <QStandardPaths>
#include <QStatusBar>
#include <QSurfaceFormat>
#include <QTimer>
#include <QToolBar>
#include <QUndoStack>
#include <QUrl>
#include <QtTest/QtTest>
#include <algorithm>
#include <cctype>
#include <functional>
#include <map>

#include "deepcut/core/io/gltf.h"
#include "deepcut/core/mesh_editor.h"
#include "deepcut/core/validate.h"
#include "deepcut/plugins/inspector_registry.h"
#include "fixtures.h"
#include "main_window.h"
#include "scene_view.h"
#include "timeline.h"
#include "studio_test_support.h"
#include "tools.h"

using deepcut::studio::MainWindow;
using deepcut::test::studio::export_bytes;
using deepcut::test::studio::kCactus;
using deepcut::test::studio::model_bytes;
using deepcut::test::studio::read_bytes;
using deepcut::test::studio::shown_window;

namespace {

/// Pixels of `image` for which `predicate(color)` holds.
int count_pixels(const QImage& image, const std::function<bool(const QColor&)>& predicate) {
  int n = 0;
  const QImage rgb = image.convertToFormat(QImage::Format_RGB32);
  for (int y = 0; y < rgb.height(); ++y)
    for (int x = 0; x < rgb.width(); ++x) n += predicate(QColor(rgb.pixel(x, y)));
  return n;
}
bool cactus_green(const QColor& c) { return c.green() > c.red() + 30 && c.green() > c.blue() + 30; }
bool heat_blue(const QColor& c) { return c.blue() > 150 && c.red() < 60 && c.green() < 90; }
bool heat_red(const QColor& c) { return c.red() > 150 && c.green() < 70 && c.blue() < 60; }

/// Accepts the next modal message box (polling for it) and stores its text in `*text`.
void accept_next_message_box(QString* text) {
  auto* timer = new QTimer;
  timer->setInterval(30);
  QObject::connect(timer, &QTimer::timeout, [timer, text] {
    if (auto* box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget())) {
      *text = box->text();
      box->accept();
      timer->stop();
      timer->deleteLater();
    }
  });
  timer->start();
}

}  // namespace

class StudioGuiTest : public QObject {
  Q_OBJECT

 private slots:
  void initTestCase() {
    QStandardPaths::setTestModeEnabled(true);
    QSettings().clear();
  }

  void opens_the_default_model_and_shows_it() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    QVERIFY(window->model());
    QCOMPARE(window->scene()->instances.size(), std::size_t(1));
    const deepcut::ModelStats stats = deepcut::compute_stats(*window->model());
    QString status;
    for (QLabel* label : window->statusBar()->findChildren<QLabel*>()) status += label->text() + " | ";
    QVERIFY2(status.contains(QLocale(QLocale::English).toString(qulonglong(stats.triangles)) + " triangles"),
             qPrintable(status));
    QVERIFY2(status.contains("Open cactus.glb"), qPrintable(status));
    QVERIFY(window->recent_files().value(0) == QFileInfo(kCactus).absoluteFilePath());
    QVERIFY(window->windowTitle().startsWith("cactus.glb"));
    const QImage image = window->view()->grab_view();
    QVERIFY2(count_pixels(image, cactus_green) > image.width() * image.height() / 50,
             "the green cactus fills the view");
    QVERIFY(!window->undo_action()->isEnabled());
    QVERIFY(!window->redo_action()->isEnabled());
  }

  void opens_every_asset_model() {
    auto window = shown_window();
    QVERIFY(window);
    for (const std::string& path : deepcut::test::asset_models()) {
      QVERIFY2(window->open_file(QString::fromStdString(path)), qPrintable(window->last_error()));
      QVERIFY(!window->scene()->instances.empty());
      QCOMPARE(window->model_path(), QString::fromStdString(path));
      for (const auto& info : deepcut::plugins::builtin_inspectors().list()) {
        window->set_inspector(info.id);
        QVERIFY(!window->inspector()->summary().empty());
      }
      window->set_inspector("none");
      window->timeline()->set_time(window->timeline()->duration() * 0.5f);
      // Something other than the backdrop is drawn in the middle of the view.
      const QImage image = window->view()->grab_view();
      const QColor corner(image.pixel(image.width() / 2, 2));
      const int drawn =
          count_pixels(image.copy(image.rect().adjusted(image.width() / 5, image.height() / 8,
                                                        -image.width() / 5, -image.height() / 8)),
                       [&](const QColor& c) {
                         return std::abs(c.red() - corner.red()) + std::abs(c.green() - corner.green()) +
                                    std::abs(c.blue() - corner.blue()) >
                                60;
                       });
      QVERIFY2(drawn > 500, qPrintable(QString::fromStdString(path)));
    }
  }

  void malformed_file_shows_the_error_and_keeps_the_previous_model() {
    auto window = shown_window(/*dialogs=*/true);
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    const auto before = window->model();
    const QString dir = QString::fromStdString(deepcut::test::temp_dir("studio-bad"));
    const QString bad = dir + "/broken.glb";
    {
      QFile file(bad);
      QVERIFY(file.open(QIODevice::WriteOnly));
      // A GLB header (magic, version 2) followed by text that is no chunk. The length comes from
      // the literal: a hand-counted 36 read past its end (found by ASan).
      static const char kBroken[] = "glTF\x02\x00\x00\x00garbage that is not a glb";
      file.write(kBroken, sizeof kBroken - 1);
    }
    QString shown;
    accept_next_message_box(&shown);
    QVERIFY(!window->open_file(bad));
    QVERIFY2(shown.contains("broken.glb"), qPrintable(shown));
    QVERIFY2(!shown.contains('\n'), "one line");
    QCOMPARE(shown, window->last_error());
    QCOMPARE(window->model(), before);
    QCOMPARE(window->model_path(), kCactus);
    QVERIFY(window->windowTitle().startsWith("cactus.glb"));

    accept_next_message_box(&shown);
    QVERIFY(!window->open_file(dir + "/missing.gltf"));
    QVERIFY2(shown.contains("missing.gltf"), qPrintable(shown));
    QCOMPARE(window->model(), before);
    const QImage image = window->view()->grab_view();
    QVERIFY(count_pixels(image, cactus_green) > image.width() * image.height() / 50);
  }

  void switching_inspectors_recolours_the_view() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    const QImage shaded = window->view()->grab_view();
    QVERIFY2(count_pixels(shaded, heat_blue) < 300, "only the axes marker is pure blue");
    auto* combo = window->findChild<QComboBox*>("inspector_combo");
    QVERIFY(combo);
    for (const auto& info : deepcut::plugins::builtin_inspectors().list()) {
      window->set_inspector(info.id);
      QCOMPARE(window->inspector_id(), info.id);
      QCOMPARE(combo->currentText().toStdString(), info.title);
      QVERIFY(!window->inspector()->summary().empty());
      const QImage image = window->view()->grab_view();
      QVERIFY2(image != shaded, info.id.c_str());
      if (info.id == "weights") {
        window->set_inspector_option("joint", "trunk_3");
        const QImage heat = window->view()->grab_view();
        QVERIFY2(count_pixels(heat, heat_blue) > 5000, "joint weight 0 is blue");
        QVERIFY2(count_pixels(heat, heat_red) > 100, "joint weight 1 is red");
        QVERIFY(window->inspector()->color_bar().has_value());
      }
      if (info.id == "clusters") {
        // The rho slider re-clusters live: a larger radius gives fewer particles.
        auto* slider = window->findChild<QSlider*>("clusters_rho_slider");
        QVERIFY(slider);
        const std::string before = window->inspector()->summary()[0];
        slider->setValue(slider->maximum());
        window->task()->wait();  // re-clustering runs off the UI thread
        const std::string after = window->inspector()->summary()[0];
        QVERIFY2(std::stoul(after) < std::stoul(before), (before + " -> " + after).c_str());
        QVERIFY(window->view()->grab_view() != image);
      }
      if (info.id == "adjacency") {
        QVERIFY(window->inspector()->summary()[0].find("3 components") != std::string::npos);
        QVERIFY(count_pixels(image, [](const QColor& c) {
                  return c.green() > 200 && c.red() < 110 && c.blue() < 150;
                }) > 200);
      }
    }
    combo->setCurrentIndex(0);
    emit combo->activated(0);
    QCOMPARE(window->inspector(), nullptr);
    QVERIFY(count_pixels(window->view()->grab_view(), cactus_green) > 0);
    QVERIFY_EXCEPTION_THROWN(window->set_inspector("nope"), deepcut::Error);
  }

  void scrubbing_the_time_line_poses_the_model_and_the_inspectors_follow() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    window->set_inspector("weights");
    window->set_inspector_option("joint", "trunk_5");
    const auto rest = window->scene()->instances[0].posed();
    auto* slider = window->findChild<QSlider*>("timeline_slider");
    QVERIFY(slider);
    slider->setValue(slider->maximum() / 4);  // a quarter of the 4 s sway
    QVERIFY(std::abs(window->scene()->time - 1.0f) < 0.01f);
    QVERIFY(std::abs(window->findChild<QDoubleSpinBox*>("timeline_time")->value() - 1.0) < 0.01);
    const auto posed = window->scene()->instances[0].posed();
    float moved = 0.0f;
    for (std::size_t v = 0; v < posed.size(); ++v) moved = std::max(moved, glm::distance(posed[v], rest[v]));
    QVERIFY2(moved > 0.05f, "the sway moves the cactus");
    // The inspector's joint marker sits on the posed joint.
    const int joint = [&] {
      for (std::size_t n = 0; n < window->model()->nodes.size(); ++n)
        if (window->model()->nodes[n].name == "trunk_5") return static_cast<int>(n);
      return -1;
    }();
    QVERIFY(joint >= 0);
    const glm::vec3 origin(window->scene()->world[static_cast<std::size_t>(joint)][3]);
    bool marker = false;
    for (const auto& points : window->inspector()->overlay().points)
      marker = marker || (points.positions.size() == 1 && glm::distance(points.positions[0], origin) < 1e-5f);
    QVERIFY(marker);
    // Rest pose and back.
    auto* clips = window->findChild<QComboBox*>("timeline_animation");
    clips->setCurrentIndex(0);
    QCOMPARE(window->scene()->animation, -1);
    const auto bind = deepcut::plugins::make_scene(window->model(), -1, 0.0f);
    for (std::size_t v = 0; v < rest.size(); ++v)
      QVERIFY(glm::distance(window->scene()->instances[0].posed()[v], bind.instances[0].posed()[v]) < 1e-5f);
    clips->setCurrentIndex(1);
    QCOMPARE(window->scene()->animation, 0);
    window->timeline()->play();
    QTest::qWait(400);
    window->timeline()->pause();
    QVERIFY(window->scene()->time > 0.0f);
  }

  void clicking_picks_vertices_and_bones() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    window->set_inspector("adjacency");
    // The front-most vertex at mid height of the trunk.
    const auto& posed = window->scene()->instances[0].posed();
    std::size_t best = 0;
    for (std::size_t v = 0; v < posed.size(); ++v)
      if (std::abs(posed[v].y - 3.0f) < 0.3f && std::abs(posed[v].x) < 0.3f && posed[v].z > posed[best].z)
        best = v;
    QVERIFY(window->view()->pick_at(window->view()->project(posed[best])));
    const auto summary = window->inspector()->summary();
    QVERIFY2(summary.size() == 3 && summary[2].rfind("Vertex ", 0) == 0, summary.back().c_str());
    // A bone: the weights inspector selects the clicked joint.
    window->set_inspector("weights");
    int joint = -1;
    for (std::size_t n = 0; n < window->model()->nodes.size(); ++n)
      if (window->model()->nodes[n].name == "arm_r_3") joint = static_cast<int>(n);
    QVERIFY(joint >= 0);
    const glm::vec3 origin(window->scene()->world[static_cast<std::size_t>(joint)][3]);
    QVERIFY(window->view()->pick_at(window->view()->project(origin)));
    QVERIFY2(window->inspector()->summary()[0].find("'arm_r_3'") != std::string::npos,
             window->inspector()->summary()[0].c_str());
  }

  void undo_and_redo_restore_model_states() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    const auto original = window->model();
    const std::string original_bytes = model_bytes(*window, "original");
    const std::size_t triangles = window->scene()->instances[0].surface->face_count();
    auto edited = std::make_shared<deepcut::Model>(*original);
    {
      deepcut::MeshEditor editor(edited->meshes[0].primitives[0].mesh);
      editor.remove_face(deepcut::FaceId(0));
      editor.remove_face(deepcut::FaceId(1));
    }
    window->apply_operation("Remove two faces", edited, 0.5);
    QCOMPARE(window->scene()->instances[0].surface->face_count(), triangles - 2);
    QVERIFY(window->undo_action()->isEnabled());
    QVERIFY(window->last_operation().startsWith("Remove two faces"));
    window->undo_action()->trigger();
    QVERIFY(model_bytes(*window, "undone") == original_bytes);
    QCOMPARE(window->scene()->instances[0].surface->face_count(), triangles);
    QVERIFY(window->redo_action()->isEnabled());
    window->redo_action()->trigger();
    QCOMPARE(window->scene()->instances[0].surface->face_count(), triangles - 2);
    QCOMPARE(window->history()->count(), 1);
    // A new file starts a new history.
    QVERIFY(window->open_file(kCactus));
    QCOMPARE(window->history()->count(), 0);
    QVERIFY(!window->undo_action()->isEnabled());
  }

  void dropping_a_model_opens_it() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    const QString fox = QStringLiteral(DEEPCUT_ASSETS_DIR "/models/Fox/Fox.glb");
    QMimeData data;
    data.setUrls({QUrl::fromLocalFile(fox)});
    const QPoint centre = window->rect().center();
    QDragEnterEvent enter(centre, Qt::CopyAction, &data, Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(window.get(), &enter);
    QVERIFY(enter.isAccepted());
    QDropEvent drop(centre, Qt::CopyAction, &data, Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(window.get(), &drop);
    window->task()->wait();  // the drop opens the file off the UI thread
    QCOMPARE(window->model_path(), fox);
    QCOMPARE(window->model()->animations.size(), std::size_t(3));
    // A static mesh (format plugin) drops in as an unrigged model: one skin with one joint.
    const QString spot = QStringLiteral(DEEPCUT_ASSETS_DIR "/models/spot/spot.obj");
    QMimeData obj;
    obj.setUrls({QUrl::fromLocalFile(spot)});
    QDragEnterEvent enter_obj(centre, Qt::CopyAction, &obj, Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(window.get(), &enter_obj);
    QVERIFY(enter_obj.isAccepted());
    QDropEvent drop_obj(centre, Qt::CopyAction, &obj, Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(window.get(), &drop_obj);
    window->task()->wait();
    QCOMPARE(window->model_path(), spot);
    QCOMPARE(window->model()->skins.size(), std::size_t(1));
    QCOMPARE(window->model()->skins[0].joints.size(), std::size_t(1));
    QVERIFY(!window->scene()->instances.empty());
    QMimeData text;
    text.setUrls({QUrl::fromLocalFile(DEEPCUT_ASSETS_DIR "/README.md")});
    QDragEnterEvent refused(centre, Qt::CopyAction, &text, Qt::LeftButton, Qt::NoModifier);
    refused.setAccepted(false);
    QApplication::sendEvent(window.get(), &refused);
    QVERIFY(!refused.isAccepted());
  }

  void export_equals_the_command_line_and_validates() {
    auto window = shown_window();
    QVERIFY(window);
    const std::string dir = deepcut::test::temp_dir("studio-export");
    for (const std::string& model :
         {kCactus.toStdString(), std::string(DEEPCUT_ASSETS_DIR "/models/CesiumMan/CesiumMan.glb")}) {
      QVERIFY(window->open_file(QString::fromStdString(model)));
      window->timeline()->set_time(0.5f);  // posing is a view: it must not change the export
      window->set_inspector("weights");
      for (const std::string ext : {".glb", ".gltf"}) {
        const std::string studio = dir + "/studio" + ext, cli = dir + "/cli" + ext;
        QVERIFY2(window->export_file(QString::fromStdString(studio)), qPrintable(window->last_error()));
        QVERIFY(window->last_operation().startsWith("Export studio"));
        const auto run = deepcut::test::run_cli("convert " + deepcut::test::quote(model) + " -o " +
                                                deepcut::test::quote(cli));
        QVERIFY2(run.exit_code == 0, run.err.c_str());
        QVERIFY2(read_bytes(studio) == read_bytes(cli),
                 (model + ext + ": studio export differs from deepcut convert").c_str());
        const auto validation = deepcut::test::validate_gltf(studio);
        QVERIFY2(validation.exit_code == 0, (validation.out + validation.err).c_str());
      }
    }
    QVERIFY(!window->export_file(QString::fromStdString(dir + "/model.obj")));
    QVERIFY(!window->last_error().isEmpty());
  }

  // The Export dialog's Compression choice writes what `deepcut convert --compress` writes.
  void export_dialog_compresses_like_the_command_line() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    const std::string dir = deepcut::test::temp_dir("studio-export-compressed");
    QAction* export_action = nullptr;
    for (QAction* a : window->findChildren<QAction*>())
      if (a->text().startsWith("&Export")) export_action = a;
    QVERIFY(export_action);
    for (const std::string codec : {"meshopt", "Draco"}) {
      const std::string studio = dir + "/studio-" + codec + ".glb", cli = dir + "/cli-" + codec + ".glb";
      bool chose = false;
      QTimer::singleShot(0, [&] {
        auto* dialog = qobject_cast<QFileDialog*>(QApplication::activeModalWidget());
        if (!dialog) return;
        auto* combo = dialog->findChild<QComboBox*>("compression");
        const int index = combo ? combo->findText(QString::fromStdString(codec)) : -1;
        if (index < 0) return dialog->reject();
        combo->setCurrentIndex(index);
        dialog->selectFile(QString::fromStdString(studio));
        chose = true;
        static_cast<QDialog*>(dialog)->accept();  // QFileDialog::accept, through the public slot
      });
      export_action->trigger();
      window->task()->wait();  // the export runs off the UI thread
      QVERIFY2(chose, "the Export dialog has no Compression choice");
      std::string lower = codec;
      std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return char(std::tolower(c)); });
      const auto run = deepcut::test::run_cli("convert " + deepcut::test::quote(kCactus.toStdString()) + " -o " +
                                              deepcut::test::quote(cli) + " --compress " + lower);
      QVERIFY2(run.exit_code == 0, run.err.c_str());
      QVERIFY2(read_bytes(studio) == read_bytes(cli), (codec + ": studio export differs from deepcut convert").c_str());
      const auto validation = deepcut::test::validate_gltf(studio);
      QVERIFY2(validation.exit_code == 0, (validation.out + validation.err).c_str());
    }
  }

  void export_never_overwrites_the_input_unless_asked() {
    auto window = shown_window();
    QVERIFY(window);
    const std::string dir = deepcut::test::temp_dir("studio-export-name");
    const QString input = QString::fromStdString(dir + "/cactus.glb");
    QVERIFY(QFile::copy(kCactus, input));
    const std::string original = read_bytes(input.toStdString());
    QVERIFY(window->open_file(input));
    // The dialog offers a new file beside the input, never the input itself.
    const QString first = window->suggested_export_path();
    QCOMPARE(QFileInfo(first).absolutePath(), QFileInfo(input).absolutePath());
    QVERIFY2(QFileInfo(first) != QFileInfo(input), qPrintable(first));
    QVERIFY(!QFileInfo::exists(first));
    QVERIFY2(window->export_file(first), qPrintable(window->last_error()));
    // An earlier export is not offered again either.
    const QString second = window->suggested_export_path();
    QVERIFY2(second != first && !QFileInfo::exists(second), qPrintable(second));
    QVERIFY(window->export_file(second));
    QVERIFY(read_bytes(input.toStdString()) == original);
    QVERIFY(read_bytes(first.toStdString()) == read_bytes(second.toStdString()));
    // Overwriting the input is possible when asked for explicitly (the dialog confirms it).
    QVERIFY(window->export_file(input));
    QVERIFY(read_bytes(input.toStdString()) == read_bytes(first.toStdString()));
  }

  void anti_aliasing_follows_the_renderer_and_the_menu() {
    using deepcut::studio::AntiAliasing;
    using deepcut::studio::is_software_renderer;
    QVERIFY(is_software_renderer("llvmpipe (LLVM 15.0.6, 256 bits)"));
    QVERIFY(is_software_renderer("Software Rasterizer"));
    QVERIFY(!is_software_renderer("NVIDIA GeForce RTX 3060/PCIe/SSE2"));
    QVERIFY(!is_software_renderer("Mesa Intel(R) UHD Graphics 620 (KBL GT2)"));
    QVERIFY(!is_software_renderer("AMD Radeon RX 6800 XT (navi21, LLVM 15.0.6, DRM 3.49, 6.1.0)"));
    const std::string renderer = deepcut::studio::gl_renderer_name();
    QVERIFY2(!renderer.empty(), "the offscreen probe names the renderer");
    const bool automatic = !is_software_renderer(renderer);
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY(window->open_file(kCactus));
    QCOMPARE(window->anti_aliasing(), AntiAliasing::Automatic);
    QCOMPARE(window->view()->multisamples() > 0, automatic);
    struct Choice {
      QString text;
      bool multisampled;
      QString saved;
    };
    std::map<bool, QImage> frames;
    for (const Choice& choice : {Choice{"Multisampling", true, "on"}, Choice{"Off", false, "off"},
                                 Choice{"Automatic", automatic, "auto"}}) {
      bool found = false;
      for (QAction* action : window->findChildren<QAction*>())
        if (action->text().remove('&').startsWith(choice.text)) {
          action->trigger();
          found = true;
        }
      QVERIFY2(found, qPrintable(choice.text));
      QCOMPARE(window->view()->multisamples() > 0, choice.multisampled);
      QCOMPARE(QSettings().value("view/anti_aliasing").toString(), choice.saved);
      const QImage frame = window->view()->grab_view();
      QVERIFY2(count_pixels(frame, cactus_green) > 1000, qPrintable(choice.text + ": the model is drawn"));
      frames[choice.multisampled] = frame;
    }
    QVERIFY2(frames[true] != frames[false], "multisampling smooths the edges");
  }

  void menus_offer_what_a_blender_or_paraview_user_expects() {
    auto window = shown_window();
    QVERIFY(window);
    QStringList texts;
    for (QAction* action : window->findChildren<QAction*>()) texts << action->text().remove('&');
    for (const char* expected :
         {"Open...", "Open Recent", "Export .glb / .gltf...", "Quit", "Undo", "Redo", "Reset camera",
          "Shaded", "Wireframe", "Shaded + edges", "Show skeleton", "Show normals", "Play / pause"})
      QVERIFY2(texts.contains(expected), expected);
    QVERIFY(window->open_file(kCactus));
    for (QAction* action : window->findChildren<QAction*>())
      if (action->text().remove('&') == "Wireframe") action->trigger();
    QCOMPARE(window->view()->display_mode(), deepcut::studio::DisplayMode::Wireframe);
    window->set_normals_visible(true);
    QVERIFY(window->view()->normals_visible());
    QVERIFY(window->view()->grab_view().isNull() == false);

    // Every tool has a key of its own, and no key means two things.
    std::map<QString, QString> owner;
    for (QAction* action : window->findChildren<QAction*>()) {
      if (action->objectName().startsWith("tool_"))
        QVERIFY2(!action->shortcut().isEmpty(), qPrintable(action->text() + " has no shortcut"));
      for (const QKeySequence& key : action->shortcuts()) {
        const QString name = key.toString();
        const auto [it, fresh] = owner.emplace(name, action->text());
        QVERIFY2(fresh, qPrintable(name + " is the shortcut of both " + it->second + " and " + action->text()));
      }
    }
    QVERIFY(owner.count("G"));

    // After an operation the Undo button does not grow with its long text ("Undo Drill (1.19,
    // ...)"), so at the default window size every tool stays on the Tools bar, none in its
    // overflow menu.
    window->set_tool("drill");
    QVERIFY(window->apply_tool());
    QVERIFY(window->undo_action()->text().size() > 30);
    window->resize(1440, 900);
    QTest::qWait(50);
    auto* bar = window->findChild<QToolBar*>("tools_toolbar");
    QVERIFY(bar);
    for (QAction* action : bar->actions()) {
      if (!action->objectName().startsWith("tool_")) continue;
      QWidget* button = bar->widgetForAction(action);
      QVERIFY2(button && button->isVisible(), qPrintable(action->text() + " is not visible on the Tools bar"));
      QVERIFY(bar->rect().contains(button->geometry()));
    }
  }
};

int main(int argc, char** argv) {
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setOrganizationName("DeepCut");
  QApplication::setApplicationName("DeepCut Studio Tests");
  StudioGuiTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "studio_gui_test.moc"
