// SPDX-License-Identifier: MIT
#include "timeline.h"

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QSignalBlocker>
#include <QSlider>
#include <QStyle>
#include <QTimer>
#include <QToolButton>
#include <algorithm>
#include <cmath>

namespace deepcut::studio {

namespace {
constexpr int kSliderSteps = 1000;  // slider resolution over one animation
}

Timeline::Timeline(QWidget* parent) : QWidget(parent) {
  auto* layout = new QHBoxLayout(this);
  layout->setContentsMargins(6, 4, 6, 4);
  clips_ = new QComboBox(this);
  clips_->setObjectName("timeline_animation");
  clips_->setMinimumWidth(160);
  clips_->setToolTip("Animation");
  rewind_ = new QToolButton(this);
  rewind_->setIcon(style()->standardIcon(QStyle::SP_MediaSkipBackward));
  rewind_->setToolTip("Go to the start");
  play_ = new QToolButton(this);
  play_->setObjectName("timeline_play");
  play_->setIcon(style()->standardIcon(QStyle::SP_MediaPlay));
  play_->setToolTip("Play / pause (Space)");
  slider_ = new QSlider(Qt::Horizontal, this);
  slider_->setObjectName("timeline_slider");
  slider_->setRange(0, kSliderSteps);
  slider_->setToolTip("Drag to scrub");
  spin_ = new QDoubleSpinBox(this);
  spin_->setObjectName("timeline_time");
  spin_->setDecimals(3);
  spin_->setSingleStep(1.0 / 30.0);
  spin_->setSuffix(" s");
  spin_->setKeyboardTracking(false);
  length_ = new QLabel(this);
  layout->addWidget(clips_);
  layout->addWidget(rewind_);
  layout->addWidget(play_);
  layout->addWidget(slider_, 1);
  layout->addWidget(spin_);
  layout->addWidget(length_);

  timer_ = new QTimer(this);
  timer_->setInterval(33);
  connect(timer_, &QTimer::timeout, this, &Timeline::advance);
  connect(play_, &QToolButton::clicked, this, &Timeline::toggle_play);
  connect(rewind_, &QToolButton::clicked, this, [this] { set_time(0.0f); });
  connect(clips_, QOverload<int>::of(&QComboBox::currentIndexChanged), this,
          [this](int index) { set_animation(index - 1); });
  connect(slider_, &QSlider::valueChanged, this,
          [this](int value) { set_time(duration() * static_cast<float>(value) / kSliderSteps); });
  connect(spin_, QOverload<double>::of(&QDoubleSpinBox::valueChanged), this,
          [this](double value) { set_time(static_cast<float>(value)); });
  set_animations({});
}

float Timeline::duration() const {
  return animation_ >= 0 && animation_ < static_cast<int>(durations_.size())
             ? durations_[static_cast<std::size_t>(animation_)]
             : 0.0f;
}

void Timeline::set_animations(const std::vector<std::pair<QString, float>>& clips) {
  pause();
  durations_.clear();
  const QSignalBlocker block(clips_);
  clips_->clear();
  clips_->addItem("Rest pose");
  for (std::size_t i = 0; i < clips.size(); ++i) {
    const QString name = clips[i].first.isEmpty() ? QString("Animation %1").arg(i) : clips[i].first;
    clips_->addItem(QString("%1 (%2 s)").arg(name).arg(clips[i].second, 0, 'f', 2));
    durations_.push_back(clips[i].second);
  }
  animation_ = clips.empty() ? -1 : 0;
  clips_->setCurrentIndex(animation_ + 1);
  time_ = 0.0f;
  show_time();
}

void Timeline::set_animation(int index) {
  index = std::clamp(index, -1, static_cast<int>(durations_.size()) - 1);
  animation_ = index;
  {
    const QSignalBlocker block(clips_);
    clips_->setCurrentIndex(index + 1);
  }
  time_ = 0.0f;
  if (animation_ < 0) pause();
  show_time();
  emit pose_changed(animation_, time_);
}

void Timeline::set_time(float seconds) {
  const float t = std::clamp(std::isfinite(seconds) ? seconds : 0.0f, 0.0f, duration());
  if (t == time_) {
    show_time();
    return;
  }
  time_ = t;
  show_time();
  emit pose_changed(animation_, time_);
}

void Timeline::play() {
  if (playing_ || duration() <= 0.0f) return;
  playing_ = true;
  clock_.start();
  timer_->start();
  play_->setIcon(style()->standardIcon(QStyle::SP_MediaPause));
  emit playing_changed(true);
}

void Timeline::pause() {
  if (!playing_) return;
  playing_ = false;
  timer_->stop();
  play_->setIcon(style()->standardIcon(QStyle::SP_MediaPlay));
  emit playing_changed(false);
}

void Timeline::toggle_play() { playing_ ? pause() : play(); }

void Timeline::advance() {
  const float d = duration();
  if (d <= 0.0f) return pause();
  const float step = static_cast<float>(clock_.restart()) / 1000.0f;
  float t = time_ + step;
  if (t > d) t = std::fmod(t, d);  // loop
  time_ = t;
  show_time();
  emit pose_changed(animation_, time_);
}

void Timeline::show_time() {
  const float d = duration();
  const QSignalBlocker a(slider_), b(spin_);
  slider_->setEnabled(d > 0.0f);
  spin_->setEnabled(d > 0.0f);
  play_->setEnabled(d > 0.0f);
  rewind_->setEnabled(d > 0.0f);
  spin_->setRange(0.0, d);
  spin_->setValue(time_);
  slider_->setValue(d > 0.0f ? static_cast<int>(std::lround(time_ / d * kSliderSteps)) : 0);
  length_->setText(QString("/ %1 s").arg(d, 0, 'f', 2));
}

}  // namespace deepcut::studio
