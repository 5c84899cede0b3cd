// SPDX-License-Identifier: MIT
// GUI tests of the Morph weights panel (QTest under xvfb-run), on AnimatedMorphCube, whose only
// clip animates morph weights:
//  - the time line plays the clip: the drawn cube and the panel's sliders move;
//  - dragging a slider sets that node's weights by hand: the drawn positions move by exactly the
//    weight change times the target's deltas (through the node's transform), the time line no
//    longer changes them, and "From animation" gives them back to the clip;
//  - with target 0 set to 1 by hand (the cube squashed), a cut through the lower half of the cube
//    at rest misses; one through the squashed cube hits: every piece lies on one side of the
//    plane at the weights set by hand, the rim on it (and off it at the animation's weights); the
//    history records the weights, and `deepcut apply` of it makes the same bytes;
//  - a model without targets gets one line saying so.
#include <QVTKOpenGLNativeWidget.h>

#include <QAction>
#include <QApplication>
#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QLabel>
#include <QSlider>
#include <QSurfaceFormat>
#include <QtTest/QtTest>
#include <algorithm>
#include <fstream>

#include "deepcut/core/attributes.h"
#include "deepcut/core/ops/operation.h"
#include "deepcut/plugins/tool.h"
#include "main_window.h"
#include "morph_panel.h"
#include "scene_view.h"
#include "studio_test_support.h"
#include "timeline.h"
#include "tools.h"

using deepcut::studio::MainWindow;
using deepcut::studio::MorphPanel;
using deepcut::test::studio::read_bytes;
using deepcut::test::studio::shown_window;

namespace {

const QString kCube = QStringLiteral(DEEPCUT_ASSETS_DIR "/models/AnimatedMorphCube/AnimatedMorphCube.gltf");

std::vector<glm::vec3> drawn(const MainWindow& window) { return window.scene()->instances[0].posed(); }

float largest_change(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  float largest = 0.0f;
  for (std::size_t v = 0; v < a.size() && v < b.size(); ++v) largest = std::max(largest, glm::length(a[v] - b[v]));
  return largest;
}

template <typename T>
T* child(const MainWindow& window, const QString& name) {
  T* found = window.findChild<T*>(name);
  if (!found) qWarning("no widget named %s", qPrintable(name));
  return found;
}

}  // namespace

class StudioMorphTest : public QObject {
  Q_OBJECT

 private slots:
  void the_time_line_plays_the_weights_and_a_slider_sets_them_by_hand() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY2(window->open_file(kCube), qPrintable(window->last_error()));
    auto* panel = window->findChild<MorphPanel*>();
    QVERIFY(panel);
    QCOMPARE(panel->group_count(), 1);
    const int node = window->scene()->instances[0].node;
    auto* slider = child<QSlider>(*window, QString("morph_slider_%1_0").arg(node));
    auto* spin = child<QDoubleSpinBox>(*window, QString("morph_spin_%1_0").arg(node));
    auto* follow = child<QCheckBox>(*window, QString("morph_follow_%1").arg(node));
    QVERIFY(slider && spin && follow && child<QSlider>(*window, QString("morph_slider_%1_1").arg(node)));
    QVERIFY(follow->isChecked());
    const float size = window->scene()->size;

    // The clip animates only weights: the time line moves the drawn cube and the sliders.
    QCOMPARE(window->timeline()->animation(), 0);
    window->timeline()->set_time(1.0f);
    const std::vector<glm::vec3> at_1 = drawn(*window);
    QVERIFY(std::abs(spin->value() - window->scene()->posed->weights(node)[0]) < 1e-3);
    window->timeline()->set_time(2.5f);
    QVERIFY2(largest_change(at_1, drawn(*window)) > 1e-3f * size, "the weight clip does not move the cube");
    QVERIFY(std::abs(spin->value() - window->scene()->posed->weights(node)[0]) < 1e-3);
    QVERIFY(largest_change(window->view()->instance_positions(0), drawn(*window)) <= 1e-6f * size);

    // A slider sets target 0 by hand: the cube moves by the weight change times its deltas.
    const std::vector<float> before_weights = window->scene()->posed->weights(node);
    const std::vector<glm::vec3> before = drawn(*window);
    slider->setValue(slider->maximum());
    QVERIFY(!follow->isChecked());
    QCOMPARE(panel->overrides().at(node), (std::vector<float>{1.0f, before_weights[1]}));
    QCOMPARE(window->scene()->posed->weights(node), panel->overrides().at(node));
    const deepcut::SurfaceMesh& mesh = *window->scene()->instances[0].surface;
    const auto& delta = mesh.vertex_attrs().get<glm::vec3>(deepcut::attr::morph_position_name(0)).data();
    const glm::mat3 linear(window->scene()->world[static_cast<std::size_t>(node)]);
    const std::vector<glm::vec3> after = drawn(*window);
    float off = 0.0f;
    for (std::size_t v = 0; v < after.size(); ++v)
      off = std::max(off, glm::length(after[v] - (before[v] + linear * ((1.0f - before_weights[0]) * delta[v]))));
    QVERIFY2(off <= 1e-5f * size, qPrintable(QString("drawn positions off the expected delta by %1").arg(off)));
    QVERIFY(largest_change(window->view()->instance_positions(0), after) <= 1e-6f * size);

    // Set by hand: the time line no longer moves them; "From animation" gives them back.
    window->timeline()->set_time(1.0f);
    QCOMPARE(window->scene()->posed->weights(node)[0], 1.0f);
    QCOMPARE(spin->value(), 1.0);
    follow->setChecked(true);
    QVERIFY(panel->overrides().empty());
    QVERIFY(largest_change(at_1, drawn(*window)) <= 1e-6f * size);
    save_shot(*window, "morph_panel");
  }

  void a_cut_is_made_at_the_weights_set_by_hand() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY2(window->open_file(kCube), qPrintable(window->last_error()));
    const int node = window->scene()->instances[0].node;
    auto* panel = window->findChild<MorphPanel*>();
    QVERIFY(panel);
    window->timeline()->set_time(0.0f);
    // Target 0 squashes the cube: its bottom (local y = -0.01) rises to y = 0.0089.
    panel->set_weight(node, 0, 1.0f);
    panel->set_weight(node, 1, 0.0f);
    const std::map<int, std::vector<float>> hand = {{node, {1.0f, 0.0f}}};
    QCOMPARE(panel->overrides(), hand);
    const glm::mat4 world = window->scene()->world[static_cast<std::size_t>(node)];
    const glm::vec3 normal = glm::normalize(glm::transpose(glm::inverse(glm::mat3(world))) * glm::vec3(0, 1, 0));
    window->set_tool("cut");
    auto cut_at = [&](float local_y) {
      deepcut::CutOperation cut = std::get<deepcut::CutOperation>(window->tool()->parameters());
      cut.plane = {glm::vec3(world * glm::vec4(0.0f, local_y, 0.0f, 1.0f)), normal};
      cut.options.keep = deepcut::CutKeep::Both;
      cut.options.cap = false;
      cut.options.split_components = false;
      window->tool()->set_parameters(cut);
      return cut.plane.point;
    };
    // Across the cube at rest, below the squashed cube: the cut misses.
    cut_at(-0.005f);
    QVERIFY2(!window->apply_tool(), "the plane misses the squashed cube");
    const glm::vec3 point = cut_at(0.0095f);
    QVERIFY2(window->apply_tool(), qPrintable(window->last_error()));
    const auto entries = window->operations();
    QCOMPARE(entries.size(), std::size_t(1));
    QCOMPARE(entries[0].operation.weights, hand);

    // Drawn at the weights set by hand (the pieces keep them): each piece lies on one side of
    // the plane, and the rim is on it; at the animation's weights the rim is off the plane.
    const auto* scene = window->scene();
    QVERIFY(scene->instances.size() >= 2);
    const float eps = 1e-5f * scene->size;
    const deepcut::PosedModel by_animation = deepcut::PosedModel::build(*scene->model, deepcut::PoseKey(0, 0.0f));
    std::size_t on_plane = 0;
    float off_by_animation = 0.0f;
    for (const auto& instance : scene->instances) {
      QCOMPARE(scene->posed->weights(instance.node), hand.at(node));
      const auto& other = by_animation.find(instance.node, instance.primitive)->posed;
      float lo = 0.0f, hi = 0.0f;
      std::vector<char> seen(instance.posed().size(), 0);
      instance.surface->for_each_face([&](deepcut::FaceId, const deepcut::Triangle& t) {
        for (int k = 0; k < 3; ++k) {
          if (seen[t[k].index]) continue;
          seen[t[k].index] = 1;
          const float d = glm::dot(instance.posed()[t[k].index] - point, normal);
          lo = std::min(lo, d);
          hi = std::max(hi, d);
          if (std::abs(d) > eps) continue;
          ++on_plane;
          off_by_animation = std::max(off_by_animation, std::abs(glm::dot(other[t[k].index] - point, normal)));
        }
      });
      QVERIFY2(lo >= -eps || hi <= eps, qPrintable(QString("a piece straddles the plane (%1 .. %2)").arg(lo).arg(hi)));
    }
    QVERIFY2(on_plane >= 3, "the rim lies on the plane at the weights set by hand");
    QVERIFY2(off_by_animation > 1e-3f * scene->size, "the rim is where the weights set by hand put it");

    // The history replays exactly on the command line.
    const std::string dir = deepcut::test::temp_dir("studio-morph-cut");
    const std::string studio = dir + "/studio.glb";
    QVERIFY(window->export_file(QString::fromStdString(studio)));
    deepcut::History history;
    history.operations.push_back(entries[0].operation);
    {
      std::ofstream out(dir + "/history.json");
      out << deepcut::history_to_json(history);
    }
    const auto run = deepcut::test::run_cli("apply " + deepcut::test::quote(kCube.toStdString()) + " " +
                                            deepcut::test::quote(dir + "/history.json") + " -o " +
                                            deepcut::test::quote(dir + "/cli.glb"));
    QVERIFY2(run.exit_code == 0, run.err.c_str());
    QVERIFY2(read_bytes(dir + "/cli.glb") == read_bytes(studio), "deepcut apply of the history differs");
    const auto validation = deepcut::test::validate_gltf(studio);
    QVERIFY2(validation.exit_code == 0, (validation.out + validation.err).c_str());
  }

  void a_model_without_targets_says_so_in_one_line() {
    auto window = shown_window();
    QVERIFY(window);
    QVERIFY2(window->open_file(QStringLiteral(DEEPCUT_ASSETS_DIR "/models/SimpleSkin/SimpleSkin.gltf")),
             qPrintable(window->last_error()));
    auto* panel = window->findChild<MorphPanel*>();
    QVERIFY(panel);
    QCOMPARE(panel->group_count(), 0);
    auto* none = child<QLabel>(*window, "morph_none");
    QVERIFY(none);
    QCOMPARE(none->text(), QString("This model has no morph targets."));
  }

 private:
  static void save_shot(MainWindow& window, const std::string& name) {
    const std::string dir = deepcut::test::temp_dir("studio-morph-shots");
    window.screenshot().save(QString::fromStdString(dir + "/" + name + ".png"));
  }
};

int main(int argc, char** argv) {
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setOrganizationName("DeepCut");
  QApplication::setApplicationName("DeepCut Studio Morph Tests");
  StudioMorphTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "morph_gui_test.moc"
