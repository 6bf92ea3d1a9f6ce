#include "editor/viewport/playback.h"

#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QHBoxLayout>
#include <QSpinBox>
#include <QShortcut>
#include <QLabel>
#include <QSignalBlocker>
#include <QSlider>
#include <QStyle>
#include <QToolButton>

#include <algorithm>
#include <cmath>

namespace mlod {

Playback::Playback(QObject* parent) : QObject(parent) {
  m_timer.setInterval(16);
  m_timer.setTimerType(Qt::PreciseTimer);
  connect(&m_timer, &QTimer::timeout, this, &Playback::tick);
}

void Playback::setClip(int frameCount, double fps) {
  m_frames = std::max(0, frameCount);
  m_fps = std::isfinite(fps) && fps > 0.0 ? fps : 30.0;
  if (m_frames < 2)
    setPlaying(false);
  m_seconds = std::clamp(m_seconds, 0.0, duration());
  emit clipChanged();
  emit timeChanged(m_seconds);
}

int Playback::frame() const {
  return std::clamp(static_cast<int>(std::lround(framePosition())), 0, std::max(0, m_frames - 1));
}

void Playback::setSeconds(double seconds) {
  const double clamped = std::isfinite(seconds) ? std::clamp(seconds, 0.0, duration()) : 0.0;
  if (clamped == m_seconds)
    return;
  m_seconds = clamped;
  emit timeChanged(m_seconds);
}

void Playback::advance(double seconds) {
  const double d = duration();
  if (d <= 0.0)
    return;
  double t = m_seconds + seconds * m_speed;
  if (t > d) {
    if (m_loop) {
      t = std::fmod(t, d);
    } else {
      t = d;
      setPlaying(false);
    }
  }
  m_seconds = t;
  emit timeChanged(m_seconds);
}

void Playback::setPlaying(bool playing) {
  if (playing == isPlaying() || (playing && m_frames < 2))
    return;
  if (playing) {
    if (!m_loop && m_seconds >= duration())
      m_seconds = 0.0;
    m_clock.start();
    m_timer.start();
  } else {
    m_timer.stop();
  }
  emit playingChanged(playing);
}

void Playback::setLoop(bool loop) { m_loop = loop; }

void Playback::stepFrames(int frames) {
  setPlaying(false);
  setFrame(std::clamp(frame() + frames, 0, std::max(0, m_frames - 1)));
}

void Playback::setSpeed(double speed) { m_speed = std::isfinite(speed) ? std::clamp(speed, 0.01, 10.0) : 1.0; }

void Playback::tick() {
  // real time since the last tick, so playback keeps the clip's speed when frames are slow
  const double elapsed = std::min(0.25, m_clock.restart() / 1000.0);
  advance(elapsed);
}

TimelineWidget::TimelineWidget(Playback* playback, QWidget* parent) : QWidget(parent), m_playback(playback) {
  auto* layout = new QHBoxLayout(this);
  layout->setContentsMargins(4, 2, 4, 2);
  m_play = new QToolButton;
  m_play->setObjectName("playButton");
  m_play->setToolTip(tr("Play / pause (Space)"));
  m_play->setIcon(style()->standardIcon(QStyle::SP_MediaPlay));
  m_play->setAutoRaise(true);
  m_slider = new QSlider(Qt::Horizontal);
  m_slider->setObjectName("timelineSlider");
  m_slider->setToolTip(tr("Scrub: the current frame of every 3D view"));
  m_loop = new QCheckBox(tr("Loop"));
  m_loop->setChecked(playback->loops());
  m_loop->setToolTip(tr("Wrap to the first frame at the end"));
  m_speed = new QDoubleSpinBox;
  m_speed->setObjectName("speedBox");
  m_speed->setRange(0.05, 4.0);
  m_speed->setSingleStep(0.25);
  m_speed->setDecimals(2);
  m_speed->setSuffix(QStringLiteral("×"));
  m_speed->setValue(playback->speed());
  m_speed->setToolTip(tr("Playback speed"));
  m_frameBox = new QSpinBox;
  m_frameBox->setObjectName("frameBox");
  m_frameBox->setKeyboardTracking(false); // a typed number applies on Enter, not digit by digit
  m_frameBox->setToolTip(tr("The current frame: type a frame number and press Enter (← → or , . step, Home End)"));
  m_label = new QLabel;
  m_label->setObjectName("frameLabel");
  m_label->setMinimumWidth(120);
  m_label->setToolTip(tr("Last frame · time in seconds"));
  layout->addWidget(m_play);
  layout->addWidget(m_slider, 1);
  layout->addWidget(m_frameBox);
  layout->addWidget(m_label);
  layout->addWidget(m_loop);
  layout->addWidget(m_speed);

  connect(m_play, &QToolButton::clicked, playback, &Playback::togglePlaying);
  connect(m_slider, &QSlider::valueChanged, playback, [playback](int frame) {
    if (frame != playback->frame())
      playback->setFrame(frame);
  });
  connect(m_slider, &QSlider::sliderPressed, playback, [playback] { playback->setPlaying(false); });
  connect(m_frameBox, &QSpinBox::valueChanged, playback, [playback](int frame) {
    if (frame != playback->frame()) {
      playback->setPlaying(false);
      playback->setFrame(frame);
    }
  });
  connect(m_loop, &QCheckBox::toggled, playback, &Playback::setLoop);
  connect(m_speed, &QDoubleSpinBox::valueChanged, playback, &Playback::setSpeed);
  connect(playback, &Playback::timeChanged, this, &TimelineWidget::refresh);
  connect(playback, &Playback::clipChanged, this, &TimelineWidget::refresh);
  connect(playback, &Playback::playingChanged, this, [this](bool playing) {
    m_play->setIcon(style()->standardIcon(playing ? QStyle::SP_MediaPause : QStyle::SP_MediaPlay));
  });
  refresh();
}

QString TimelineWidget::frameText() const {
  if (m_playback->frameCount() < 1)
    return tr("no clip");
  return tr("frame %1 / %2 · %3 s")
      .arg(m_playback->frame())
      .arg(m_playback->frameCount() - 1)
      .arg(m_playback->seconds(), 0, 'f', 3);
}

void TimelineWidget::addKeys(QWidget* scope) {
  const auto key = [&](QKeySequence sequence, auto&& slot) {
    auto* shortcut = new QShortcut(sequence, scope);
    shortcut->setContext(Qt::WidgetWithChildrenShortcut);
    connect(shortcut, &QShortcut::activated, m_playback, slot);
  };
  Playback* playback = m_playback;
  key(QKeySequence(Qt::Key_Right), [playback] { playback->stepFrames(1); });
  key(QKeySequence(Qt::Key_Period), [playback] { playback->stepFrames(1); });
  key(QKeySequence(Qt::Key_Left), [playback] { playback->stepFrames(-1); });
  key(QKeySequence(Qt::Key_Comma), [playback] { playback->stepFrames(-1); });
  key(QKeySequence(Qt::Key_Home), [playback] { playback->goToFirstFrame(); });
  key(QKeySequence(Qt::Key_End), [playback] { playback->goToLastFrame(); });
}

void TimelineWidget::refresh() {
  const int last = std::max(0, m_playback->frameCount() - 1);
  {
    const QSignalBlocker block(m_slider);
    m_slider->setRange(0, last);
    m_slider->setValue(m_playback->frame());
    m_slider->setEnabled(m_playback->frameCount() > 1);
  }
  {
    const QSignalBlocker block(m_frameBox);
    m_frameBox->setRange(0, last);
    m_frameBox->setValue(m_playback->frame());
    m_frameBox->setEnabled(m_playback->frameCount() > 1);
  }
  m_play->setEnabled(m_playback->frameCount() > 1);
  m_label->setText(m_playback->frameCount() < 1 ? tr("no clip")
                                                : tr("/ %1 · %2 s").arg(last).arg(m_playback->seconds(), 0, 'f', 3));
}

} // namespace mlod
