#pragma once
// The one current time every 3D view follows (the character view, the crowd, the status
// bar, the per-frame chart), and the timeline that drives it: play/pause (Space), scrub,
// step a frame (← → or , .), first and last frame (Home End), a typed frame number, loop,
// speed, time.

#include <QElapsedTimer>
#include <QObject>
#include <QTimer>
#include <QWidget>

class QCheckBox;
class QDoubleSpinBox;
class QLabel;
class QSlider;
class QSpinBox;
class QToolButton;

namespace mlod {

class Playback : public QObject {
  Q_OBJECT
public:
  explicit Playback(QObject* parent = nullptr);

  // The clip in view: frames at `fps`; a clip of one frame (or none) does not play.
  void setClip(int frameCount, double fps);
  int frameCount() const { return m_frames; }
  double fps() const { return m_fps; }
  double duration() const { return m_frames > 1 ? (m_frames - 1) / m_fps : 0.0; }

  double seconds() const { return m_seconds; }
  double framePosition() const { return m_seconds * m_fps; }
  int frame() const; // the nearest frame
  void setSeconds(double seconds);
  void setFrame(int frame) { setSeconds(frame / m_fps); }
  // Stops and moves `frames` frames (negative: back), within the clip.
  void stepFrames(int frames);
  void goToFirstFrame() { stepFrames(-frame()); }
  void goToLastFrame() { stepFrames(m_frames - 1 - frame()); }
  // Advances by `seconds` x speed, wrapping (loop) or stopping at the end.
  void advance(double seconds);

  bool isPlaying() const { return m_timer.isActive(); }
  void setPlaying(bool playing);
  void togglePlaying() { setPlaying(!isPlaying()); }
  bool loops() const { return m_loop; }
  void setLoop(bool loop);
  double speed() const { return m_speed; }
  void setSpeed(double speed); // (0, 10]

signals:
  void timeChanged(double seconds);
  void playingChanged(bool playing);
  void clipChanged();

private:
  void tick();

  int m_frames = 0;
  double m_fps = 30.0;
  double m_seconds = 0.0;
  bool m_loop = true;
  double m_speed = 1.0;
  QTimer m_timer;
  QElapsedTimer m_clock;
};

class TimelineWidget : public QWidget {
  Q_OBJECT
public:
  explicit TimelineWidget(Playback* playback, QWidget* parent = nullptr);

  QSlider* slider() const { return m_slider; }
  QSpinBox* frameBox() const { return m_frameBox; }
  // The timeline's keys (← → , . Home End) wherever the focus is inside `scope` (the panel
  // that holds this timeline and its view).
  void addKeys(QWidget* scope);
  QToolButton* playButton() const { return m_play; }
  QString frameText() const;

private:
  void refresh();

  Playback* m_playback = nullptr;
  QToolButton* m_play = nullptr;
  QSlider* m_slider = nullptr;
  QSpinBox* m_frameBox = nullptr;
  QCheckBox* m_loop = nullptr;
  QDoubleSpinBox* m_speed = nullptr;
  QLabel* m_label = nullptr;
};

} // namespace mlod
