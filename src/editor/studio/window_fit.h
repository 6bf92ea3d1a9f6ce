#pragma once
// The studio's first window on the screen it opens on: the size it is designed for (1600 x
// 1000), but never larger than the screen's available area with the window manager's frame
// (title bar) included. Issue 26: a 1600 x 1000 window plus its title bar overflowed a 1600 x
// 1000 screen and hid the status bar.

#include <QMargins>
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

} // namespace mlod
