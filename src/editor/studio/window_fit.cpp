#include "editor/studio/window_fit.h"

#include <QEvent>
#include <QGuiApplication>
#include <QScreen>
#include <QStyle>
#include <QTimer>
#include <QWidget>
#include <QWindow>

#include <algorithm>
#include <cstdint>
#include <limits>

namespace mlod {

QRect firstWindowGeometry(QSize wanted, const QRect& available, const QMargins& frame) {
  const QSize room(available.width() - frame.left() - frame.right(), available.height() - frame.top() - frame.bottom());
  const QSize size = wanted.boundedTo(room).expandedTo(QSize(1, 1));
  const QPoint framedTopLeft(available.left() + std::max(0, (room.width() - size.width()) / 2),
                             available.top() + std::max(0, (room.height() - size.height()) / 2));
  return QRect(framedTopLeft + QPoint(frame.left(), frame.top()), size);
}

namespace {

QMargins frameOf(const QWidget* window) {
  return QMargins(window->geometry().left() - window->frameGeometry().left(),
                  window->geometry().top() - window->frameGeometry().top(),
                  window->frameGeometry().right() - window->geometry().right(),
                  window->frameGeometry().bottom() - window->geometry().bottom());
}

// Fits the window again once its real frame is known: the window manager tells it after the
// window is mapped (a move or resize follows), so this watches those for a few seconds. A
// child of the window: it goes with it.
class RefitOnFrame : public QObject {
public:
  RefitOnFrame(QWidget* window, QSize wanted) : QObject(window), m_window(window), m_wanted(wanted) {
    window->installEventFilter(this);
    QTimer::singleShot(5000, this, [this] { deleteLater(); });
  }

  bool eventFilter(QObject* watched, QEvent* event) override {
    if (watched == m_window && (event->type() == QEvent::Move || event->type() == QEvent::Resize))
      QTimer::singleShot(0, this, [this] { refit(); });
    return false;
  }

  void refit() {
    if (m_window->isMaximized() || m_window->isFullScreen())
      return;
    const QScreen* screen = m_window->screen();
    if (!screen)
      return;
    const QRect available = screen->availableGeometry();
    if (available.contains(m_window->frameGeometry()))
      return;
    m_window->setGeometry(firstWindowGeometry(m_wanted, available, frameOf(m_window)));
  }

private:
  QWidget* m_window; // the parent: it outlives this
  QSize m_wanted;
};

} // namespace

void showFitted(QWidget* window, QSize wanted) {
  const QScreen* screen = window->screen() ? window->screen() : QGuiApplication::primaryScreen();
  if (!screen) {
    window->resize(wanted);
    window->show();
    return;
  }
  window->winId(); // the native window: some window systems tell its frame before it is shown
  QMargins frame = window->windowHandle() ? window->windowHandle()->frameMargins() : QMargins();
  if (frame.isNull()) // a title bar, until told
    frame.setTop(window->style()->pixelMetric(QStyle::PM_TitleBarHeight, nullptr, window));
  window->setGeometry(firstWindowGeometry(wanted, screen->availableGeometry(), frame));
  window->show();
  auto* refit = new RefitOnFrame(window, wanted);
  QTimer::singleShot(0, refit, [refit] { refit->refit(); }); // where no move or resize follows the show
}

QPoint placeBeside(QSize dialog, const QRect& keep, const QRect& available, const QPoint& preferred) {
  const int w = dialog.width(), h = dialog.height();
  // Candidates: flush against each side of `keep`, against each edge of the screen, and the
  // preferred place; each then pulled inside the screen (its top-left first where it is too big).
  const int xs[] = {keep.right() + 1, keep.left() - w, available.left(), available.right() + 1 - w, preferred.x()};
  const int ys[] = {preferred.y(), keep.top(), keep.bottom() + 1, keep.top() - h, available.top(),
                    available.bottom() + 1 - h};
  QPoint best = preferred;
  std::int64_t bestHidden = std::numeric_limits<std::int64_t>::max();
  std::int64_t bestDistance = 0;
  for (const int x : xs)
    for (const int y : ys) {
      const QPoint at(std::max(available.left(), std::min(x, available.right() + 1 - w)),
                      std::max(available.top(), std::min(y, available.bottom() + 1 - h)));
      const QRect hidden = QRect(at, dialog).intersected(keep);
      const std::int64_t area = hidden.isEmpty() ? 0 : std::int64_t(hidden.width()) * hidden.height();
      const QPoint d = at - preferred;
      const std::int64_t distance = std::int64_t(d.x()) * d.x() + std::int64_t(d.y()) * d.y();
      if (area < bestHidden || (area == bestHidden && distance < bestDistance)) {
        best = at;
        bestHidden = area;
        bestDistance = distance;
      }
    }
  return best;
}

void moveBeside(QWidget* dialog, const QWidget* keep) {
  const QScreen* screen = dialog->screen() ? dialog->screen() : QGuiApplication::primaryScreen();
  if (!screen || !keep->isVisible())
    return;
  const QRect view(keep->mapToGlobal(QPoint(0, 0)), keep->size());
  const QRect frame = dialog->frameGeometry();
  dialog->move(placeBeside(frame.size(), view, screen->availableGeometry(), frame.topLeft()));
}

} // namespace mlod
