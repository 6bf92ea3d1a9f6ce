#include "editor/views/job_progress.h"

#include <algorithm>
#include <limits>

namespace mlod {

JobProgress::JobProgress(const QString& title, const QString& cancelText, QWidget* parent) : QProgressDialog(parent) {
  setWindowTitle(title);
  setCancelButtonText(cancelText.isEmpty() ? QString() : cancelText);
  // Work runs in the background and the window stays usable: the dialog never takes the
  // keyboard from it (edits and shortcuts go on while it shows).
  setAttribute(Qt::WA_ShowWithoutActivating);
  setAutoClose(false);
  setAutoReset(false);
  // note: QProgressDialog shows itself once its own timer fires (armed at construction and
  // whenever the value returns to the minimum); pushed out of reach, m_delay decides alone.
  setMinimumDuration(std::numeric_limits<int>::max());
  QProgressDialog::reset();
  hide();
  m_delay.setSingleShot(true);
  m_delay.setInterval(kShowDelayMs);
  connect(this, &QProgressDialog::canceled, &m_delay, &QTimer::stop); // the job ends soon: finish()
  connect(&m_delay, &QTimer::timeout, this, [this] {
    if (m_running)
      show();
  });
}

void JobProgress::begin(const QString& label, int maximum) {
  m_running = true;
  QProgressDialog::reset();
  setLabelText(label);
  setRange(0, std::max(0, maximum));
  setValue(0);
  m_delay.start();
}

void JobProgress::step(int done, int total) {
  if (!m_running || total <= 0)
    return;
  if (maximum() != total)
    setRange(0, total);
  setValue(std::clamp(done, 0, total));
}

void JobProgress::finish() {
  m_running = false;
  m_delay.stop();
  QProgressDialog::reset();
  hide();
}

} // namespace mlod
