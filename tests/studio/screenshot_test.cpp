// SPDX-License-Identifier: MIT
// `deepcut-studio --screenshot` as a user runs it (under xvfb-run): exit codes, and the content
// of the picture (model pixels against the backdrop, heat-map colours in weights mode, edge and
// highlight colours in adjacency mode), never byte equality.
#include <QDir>
#include <QImage>
#include <QtTest/QtTest>
#include <functional>
#include <map>
#include <set>

#include "tools.h"

namespace {

using deepcut::test::quote;
using deepcut::test::RunResult;

RunResult run_studio(const std::string& args) {
  return deepcut::test::run_command(quote(DEEPCUT_STUDIO) + " " + args);
}

/// The middle of the 3D view in a default-size window (the docks take the sides).
QImage view_middle(const QImage& shot) {
  return shot
      .copy(QRect(shot.width() * 27 / 100, shot.height() * 10 / 100, shot.width() * 40 / 100,
                  shot.height() * 75 / 100))
      .convertToFormat(QImage::Format_RGB32);
}

int count_pixels(const QImage& image, const std::function<bool(const QColor&)>& predicate) {
  int n = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) n += predicate(QColor(image.pixel(x, y)));
  return n;
}

/// Pixels that differ from the backdrop: the backdrop is a vertical gradient, so each row is
/// compared with its own left-most pixel (left of the model).
int model_pixels(const QImage& image) {
  int n = 0;
  for (int y = 0; y < image.height(); ++y) {
    const QColor backdrop(image.pixel(0, y));
    for (int x = 0; x < image.width(); ++x) {
      const QColor c(image.pixel(x, y));
      n += std::abs(c.red() - backdrop.red()) + std::abs(c.green() - backdrop.green()) +
               std::abs(c.blue() - backdrop.blue()) >
           40;
    }
  }
  return n;
}

bool heat_blue(const QColor& c) { return c.blue() > 150 && c.red() < 60 && c.green() < 90; }
bool heat_high(const QColor& c) {
  return c.red() > 170 && c.green() < 200 && c.blue() < 60;
}  // orange to red
bool heat_middle(const QColor& c) { return c.green() > 150 && c.blue() < 80; }  // green to yellow

}  // namespace

class ScreenshotTest : public QObject {
  Q_OBJECT

  std::string dir_;

  QImage shoot(const std::string& name, const std::string& args) {
    const std::string out = dir_ + "/" + name + ".png";
    const RunResult r = run_studio("--screenshot " + quote(out) + " " + args);
    if (r.exit_code != 0) {
      qWarning("deepcut-studio exited %d: %s", r.exit_code, r.err.c_str());
      return QImage();
    }
    return QImage(QString::fromStdString(out));
  }

 private slots:
  void initTestCase() { dir_ = deepcut::test::temp_dir("studio-shots"); }

  void default_model_without_arguments() {
    const QImage shot = shoot("default", "");
    QVERIFY(!shot.isNull());
    QCOMPARE(shot.size(), QSize(1440, 900));
    const QImage middle = view_middle(shot);
    const int model = model_pixels(middle);
    QVERIFY2(model > middle.width() * middle.height() / 10,
             qPrintable(QString("only %1 model pixels").arg(model)));
    QVERIFY2(count_pixels(middle,
                          [](const QColor& c) {
                            return c.green() > c.red() + 30 && c.green() > c.blue() + 30;
                          }) > 20000,
             "the cactus is green");
    QCOMPARE(count_pixels(middle, heat_blue), 0);
  }

  void weights_mode_shows_a_heat_map() {
    const QImage shot = shoot("weights", "--inspect weights --joint trunk_3 --time 1");
    QVERIFY(!shot.isNull());
    const QImage middle = view_middle(shot);
    QVERIFY2(count_pixels(middle, heat_blue) > 10000, "weight 0 is blue");
    QVERIFY2(count_pixels(middle, heat_high) > 1000, "weights near 1 at the joint are orange to red");
    QVERIFY2(count_pixels(middle, heat_middle) > 1000, "blends are green to yellow");
  }

  void adjacency_mode_shows_edges_components_and_the_picked_ring() {
    const QImage shot = shoot("adjacency", "--inspect adjacency --vertex 4049 --frame --view edges");
    QVERIFY(!shot.isNull());
    const QImage middle = view_middle(shot);
    QVERIFY2(
        count_pixels(
            middle, [](const QColor& c) { return c.green() > 200 && c.red() < 110 && c.blue() < 150; }) > 300,
        "seam edges are bright green");
    QVERIFY2(count_pixels(middle,
                          [](const QColor& c) {
                            return c.red() > 150 && c.red() > c.green() + 50 && c.green() > 70 &&
                                   c.blue() < 45;
                          }) > 800,
             "the picked vertex's faces, framed, are orange");
  }

  void clusters_mode_colours_particles() {
    const QImage shot = shoot("clusters", "--inspect clusters --time 2");
    QVERIFY(!shot.isNull());
    const QImage middle = view_middle(shot);
    // Many particles, many hues: count the distinct coarse hues of saturated pixels.
    std::set<int> hues;
    for (int y = 0; y < middle.height(); ++y)
      for (int x = 0; x < middle.width(); ++x) {
        const QColor c(middle.pixel(x, y));
        if (c.hsvSaturation() > 120 && c.value() > 120) hues.insert(c.hsvHue() / 15);
      }
    QVERIFY2(hues.size() >= 12, qPrintable(QString("%1 hue bins").arg(hues.size())));
    QVERIFY(model_pixels(middle) > middle.width() * middle.height() / 10);
  }

  void applied_history_shows_pieces_slit_and_hole() {
    const std::string histories = DEEPCUT_SOURCE_DIR "/tests/data/histories/";
    // The cut's two pieces, each in its own colour (the pieces inspector), the caps darker.
    const QImage pieces = shoot("cut_pieces", "--apply " + quote(histories + "cut_pieces.json") + " --inspect pieces");
    QVERIFY(!pieces.isNull());
    const QImage middle = view_middle(pieces);
    std::set<int> hues;
    std::map<int, int> hue_pixels;
    for (int y = 0; y < middle.height(); ++y)
      for (int x = 0; x < middle.width(); ++x) {
        const QColor c(middle.pixel(x, y));
        if (c.hsvSaturation() > 100 && c.value() > 90) ++hue_pixels[c.hsvHue() / 20];
      }
    for (const auto& [bin, n] : hue_pixels)
      if (n > 5000) hues.insert(bin);
    QVERIFY2(hues.size() >= 2, qPrintable(QString("%1 large hue areas: the pieces are not told apart").arg(hues.size())));
    // The slit, zoomed in with the adjacency inspector: its lips are boundary edges (blue); the
    // cactus has none before the tear.
    const std::string slit_args = "--look-at 0.41,4,0.95,1.3 --no-skeleton --inspect adjacency";
    const QImage slit = shoot("tear_slit", "--apply " + quote(histories + "tear_slit.json") + " " + slit_args);
    const QImage whole = shoot("tear_none", slit_args);
    QVERIFY(!slit.isNull() && !whole.isNull());
    const auto boundary_blue = [](const QColor& c) {
      return c.blue() > 200 && c.red() < 90 && c.green() > 100 && c.green() < 190;
    };
    const int lips = count_pixels(view_middle(slit), boundary_blue), none = count_pixels(view_middle(whole), boundary_blue);
    // (Both include the inspector's blue legend swatch at the crop's edge.)
    QVERIFY2(lips > none + 150, qPrintable(QString("boundary pixels: %1 torn, %2 whole").arg(lips).arg(none)));
    // The hole, zoomed in: the backdrop shows through it.
    const std::string hole_args = "--look-at 0,7,0,1.2 --no-skeleton";
    const QImage hole = shoot("drill_hole", "--apply " + quote(histories + "drill_hole.json") + " " + hole_args);
    const QImage solid = shoot("drill_none", hole_args);
    QVERIFY(!hole.isNull() && !solid.isNull());
    QVERIFY2(model_pixels(view_middle(hole)) < model_pixels(view_middle(solid)) - 2000,
             "the drilled trunk shows the backdrop through its hole");
  }

  void a_bad_history_exits_2_with_one_line() {
    const std::string out = dir_ + "/never.png";
    const std::string bad = dir_ + "/bad_history.json";
    {
      QFile file(QString::fromStdString(bad));
      QVERIFY(file.open(QIODevice::WriteOnly));
      file.write("{\"operations\": [{\"op\": \"saw\"}]}");
    }
    for (const std::string& args : {"--apply " + quote(bad), "--apply " + quote(dir_ + "/missing.json"),
                                     std::string("--look-at 1,2,3"), std::string("--look-at 0,0,0,-1")}) {
      const RunResult r = run_studio("--screenshot " + quote(out) + " " + args);
      QVERIFY2(r.exit_code == 2, (args + ": exit " + std::to_string(r.exit_code)).c_str());
      QVERIFY2(std::count(r.err.begin(), r.err.end(), '\n') == 1, (args + ": " + r.err).c_str());
    }
    QVERIFY(!QFile::exists(QString::fromStdString(out)));
  }

  void textured_model_is_drawn() {
    const QImage shot =
        shoot("cesium", quote(DEEPCUT_ASSETS_DIR "/models/CesiumMan/CesiumMan.glb") + " --time 0.5");
    QVERIFY(!shot.isNull());
    const QImage middle = view_middle(shot);
    QVERIFY2(model_pixels(middle) > middle.width() * middle.height() / 30, "CesiumMan is in view");
  }

  void unreadable_model_exits_2_with_one_line() {
    const std::string bad = dir_ + "/bad.gltf";
    {
      QFile file(QString::fromStdString(bad));
      QVERIFY(file.open(QIODevice::WriteOnly));
      file.write("{\"asset\": ");
    }
    const std::string out = dir_ + "/never.png";
    RunResult r = run_studio("--screenshot " + quote(out) + " " + quote(bad));
    QCOMPARE(r.exit_code, 2);
    QVERIFY2(r.err.find("bad.gltf") != std::string::npos, r.err.c_str());
    QCOMPARE(std::count(r.err.begin(), r.err.end(), '\n'), 1l);
    QVERIFY(!QFile::exists(QString::fromStdString(out)));

    r = run_studio("--screenshot " + quote(out) + " " + quote(dir_ + "/missing.glb"));
    QCOMPARE(r.exit_code, 2);
    QVERIFY2(r.err.find("missing.glb") != std::string::npos, r.err.c_str());
  }

  void bad_options_exit_2() {
    const std::string out = dir_ + "/never.png";
    for (const std::string& args :
         {std::string("--inspect nope"), std::string("--joint nobody"), std::string("--time soon"),
          std::string("--vertex 99999999"), std::string("--frobnicate"), std::string("--frame"),
          std::string("--inspect clusters --frame"), std::string("--anti-aliasing sometimes")}) {
      const RunResult r = run_studio("--screenshot " + quote(out) + " " + args);
      QVERIFY2(r.exit_code == 2, (args + ": exit " + std::to_string(r.exit_code)).c_str());
      QVERIFY2(std::count(r.err.begin(), r.err.end(), '\n') == 1, (args + ": " + r.err).c_str());
    }
    QVERIFY(!QFile::exists(QString::fromStdString(out)));
  }

  void bad_input_catalogue_exits_0_or_2() {
    // Every hostile file of tests/data/bad: either refused with one line (2) or shown (0),
    // never a crash, with the weights inspector (the most skin-dependent view) active.
    const QDir dir(DEEPCUT_SOURCE_DIR "/tests/data/bad");
    const QStringList files = dir.entryList({"*.gltf", "*.glb"}, QDir::Files, QDir::Name);
    QVERIFY2(files.size() > 20, "the bad-input catalogue is there");
    const std::string out = dir_ + "/bad.png";
    for (const QString& name : files) {
      const std::string path = dir.filePath(name).toStdString();
      const RunResult r =
          run_studio("--size 640x480 --screenshot " + quote(out) + " --inspect weights " + quote(path));
      QVERIFY2(r.exit_code == 0 || r.exit_code == 2,
               (path + ": exit " + std::to_string(r.exit_code) + ": " + r.err).c_str());
      if (r.exit_code == 2) {
        QVERIFY2(std::count(r.err.begin(), r.err.end(), '\n') == 1, (path + ": " + r.err).c_str());
        QVERIFY2(r.err.find(name.toStdString()) != std::string::npos, (path + ": " + r.err).c_str());
      }
    }
  }

  void default_model_from_an_out_of_tree_build() {
    // A copy of the program far from any assets/ folder still opens the source tree's cactus.
    const std::string bin = dir_ + "/elsewhere/bin";
    QVERIFY(QDir().mkpath(QString::fromStdString(bin)));
    const std::string copy = bin + "/deepcut-studio";
    QFile::remove(QString::fromStdString(copy));
    QVERIFY(QFile::copy(DEEPCUT_STUDIO, QString::fromStdString(copy)));
    const std::string out = dir_ + "/elsewhere.png";
    const RunResult r = deepcut::test::run_command(quote(copy) + " --size 640x480 --screenshot " + quote(out));
    QVERIFY2(r.exit_code == 0, r.err.c_str());
    QVERIFY(!QImage(QString::fromStdString(out)).isNull());
  }

  void help_without_a_display() {
    const RunResult r =
        deepcut::test::run_command("env -u DISPLAY -u WAYLAND_DISPLAY -u QT_QPA_PLATFORM " + quote(DEEPCUT_STUDIO) + " --help");
    QCOMPARE(r.exit_code, 0);
    QVERIFY2(r.out.find("deepcut-studio") != std::string::npos, r.out.c_str());
  }
};

QTEST_GUILESS_MAIN(ScreenshotTest)

#include "screenshot_test.moc"
