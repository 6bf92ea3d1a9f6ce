#pragma once
// The progress dialog of one background job (import, clustering, level generation): it
// shows only while the job runs and only once it has run kShowDelayMs, so quick work never
// flashes a dialog, and it hides the moment the job ends. QProgressDialog alone does
// neither reliably: its construction arms a timer that shows it later whatever happened
// meanwhile, and reset() does not hide it without autoClose.

#include <QProgressDialog>
#include <QTimer>

namespace mlod {

class JobProgress : public QProgressDialog {
  Q_OBJECT
public:
  static constexpr int kShowDelayMs = 300;

  // `cancelText` empty: no cancel button.
  JobProgress(const QString& title, const QString& cancelText, QWidget* parent);

  // A job starts: `maximum` 0 is a busy bar with no fraction; otherwise steps 0..maximum
  // shown as a percentage. The dialog appears after kShowDelayMs if the job still runs.
  void begin(const QString& label, int maximum = 0);
  // `done` of `total` steps (total > 0): the bar becomes a percentage.
  void step(int done, int total);
  // The job ended (succeeded, failed or was cancelled): hidden at once, nothing pending.
  void finish();
  bool isRunning() const { return m_running; }

private:
  QTimer m_delay;
  bool m_running = false;
};

} // namespace mlod
