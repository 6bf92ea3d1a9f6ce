#pragma once
// Conditions the UI tests wait on instead of fixed waits: a fixed qWait() guesses how fast
// the event loop is, and a loaded machine makes that guess wrong.

#include <QCoreApplication>
#include <QEvent>
#include <QObject>
#include <QPointer>
#include <QTest>
#include <QTimer>
#include <QWidget>

namespace mlod::test {

// Counts the Show events a widget gets from its construction on: a dialog that showed for a
// moment and hid again is seen, where isVisible() at one instant would miss it. The widget
// may go first (a dialog deleted on close).
class ShowCounter : public QObject {
public:
  explicit ShowCounter(QWidget* watched) : m_watched(watched) { watched->installEventFilter(this); }
  ~ShowCounter() override {
    if (m_watched)
      m_watched->removeEventFilter(this);
  }
  ShowCounter(const ShowCounter&) = delete;
  ShowCounter& operator=(const ShowCounter&) = delete;
  int count() const { return m_shows; }

protected:
  bool eventFilter(QObject* object, QEvent* event) override {
    if (object == m_watched && event->type() == QEvent::Show)
      ++m_shows;
    return false;
  }

private:
  QPointer<QWidget> m_watched;
  int m_shows = 0;
};

// Runs the event loop until a precise timer of `intervalMs` + 100 ms, started now, fires.
// Qt fires due timers in the order they expire, so by then every timer of at most
// `intervalMs` armed before this call has fired (a coarse one may be late by 5%: the 100 ms
// cover it): "nothing shows later" is checked against the timers, however slow the loop.
inline bool timersOfAtMostHaveFired(int intervalMs) {
  QObject context; // stops the timer if the wait gives up
  bool fired = false;
  QTimer::singleShot(intervalMs + 100, Qt::PreciseTimer, &context, [&fired] { fired = true; });
  return QTest::qWaitFor([&fired] { return fired; }, 60000 + intervalMs);
}

// Runs the event loop until `fingerprint()` (sizes, section widths, rectangles: what a
// check reads) is the same before and after a pass that had work to do: layouts, delayed
// item layouts and resizes are done. False when it still changes after `timeoutMs`.
template <typename Fingerprint>
bool settles(Fingerprint fingerprint, int timeoutMs = 10000) {
  auto last = fingerprint();
  int stablePasses = 0;
  return QTest::qWaitFor(
      [&] {
        QCoreApplication::sendPostedEvents(nullptr, QEvent::LayoutRequest);
        QCoreApplication::processEvents();
        const auto now = fingerprint();
        stablePasses = now == last ? stablePasses + 1 : 0;
        last = now;
        return stablePasses >= 2;
      },
      timeoutMs);
}

} // namespace mlod::test
