// SPDX-License-Identifier: MIT
#pragma once
// The animation time line: choose the animation (or the rest pose), play / pause, scrub.

#include <QElapsedTimer>
#include <QString>
#include <QWidget>
#include <utility>
#include <vector>

class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QSlider;
class QTimer;
class QToolButton;

namespace deepcut::studio {

class Timeline : public QWidget {
  Q_OBJECT

 public:
  explicit Timeline(QWidget* parent = nullptr);

  /// Lists the model's animations (name, duration in seconds); selects the first one, or the
  /// rest pose when there is none, at time 0, and stops playing. Emits nothing.
  void set_animations(const std::vector<std::pair<QString, float>>& clips);

  int animation() const { return animation_; }  ///< -1: rest pose
  float time() const { return time_; }          ///< seconds
  float duration() const;
  bool playing() const { return playing_; }

  /// Selects animation `index` (-1: rest pose) and rewinds. Emits pose_changed.
  void set_animation(int index);
  /// Moves to `seconds` (clamped to the animation). Emits pose_changed.
  void set_time(float seconds);

  void play();
  void pause();
  void toggle_play();

 signals:
  void pose_changed(int animation, float time);
  void playing_changed(bool playing);

 private:
  void advance();
  void show_time();

  QComboBox* clips_ = nullptr;
  QToolButton* play_ = nullptr;
  QToolButton* rewind_ = nullptr;
  QSlider* slider_ = nullptr;
  QDoubleSpinBox* spin_ = nullptr;
  QLabel* length_ = nullptr;
  QTimer* timer_ = nullptr;
  QElapsedTimer clock_;
  std::vector<float> durations_;
  int animation_ = -1;
  float time_ = 0.0f;
  bool playing_ = false;
};

}  // namespace deepcut::studio
