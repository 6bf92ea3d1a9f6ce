#pragma once
// The studio's first window on the screen it opens on: the size it is designed for (1600 x
// 1000), but never larger than the screen's available area with the window manager's frame
// (title bar) included. Issue 26: a 1600 x 1000 window plus its title bar overflowed a 1600 x
// 1000 screen and hid the status bar.

#include <QMargins>
#include <QPoint>
#include <QRect>
#include <QSize>

class QWidget;

namespace mlod {

// The geometry to give a window (frame excluded, as QWidget::setGeometry() takes it) of
// `wanted` size on a screen whose available area (QScreen::availableGeometry()) is
// `available`, the window system adding `frame` around it: `wanted`, shrunk where the framed
// window would not fit, then centred so that the frame lies inside `available`.
QRect firstWindowGeometry(QSize wanted, const QRect& available, const QMargins& frame);

// Shows `window` at firstWindowGeometry() on its screen. Until the window system tells the
// frame (once the window is shown), it is taken as a title bar of the style's height; when the
// real frame does not fit, the window is fitted again with it.
void showFitted(QWidget* window, QSize wanted);

// Where to put a dialog whose frame is `dialog` big on a screen's available area `available`
// so that it hides as little as it can of `keep` (the 3D view the dialog's work is about);
// `preferred` is where the window system would put it (centred on its parent). Returns the
// frame's top-left: beside `keep` where the room is, else the position within `available`
// that covers the fewest of its pixels, the one nearest `preferred` among equals. Issue 26
// (item 7): the Budget dialog, centred on the main window, sat exactly over the viewport (the
// central widget) and the artist saw no character while choosing the budget.
QPoint placeBeside(QSize dialog, const QRect& keep, const QRect& available, const QPoint& preferred);

// Moves the shown top-level `dialog` to placeBeside() `keep` (a widget on screen) on its
// screen.
void moveBeside(QWidget* dialog, const QWidget* keep);

} // namespace mlod
