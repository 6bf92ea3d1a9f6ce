// mlod_png_stats: prints "WIDTH HEIGHT COLOURS" for a PNG (COLOURS = distinct RGB values), so
// the package test can tell a real screenshot from a blank or missing one. Exit 2 if the
// file is not a readable image.

#include <QGuiApplication>
#include <QImage>
#include <QSet>

#include <cstdio>

int main(int argc, char** argv) {
  qputenv("QT_QPA_PLATFORM", "offscreen");
  QGuiApplication app(argc, argv);
  if (app.arguments().size() != 2) {
    std::fprintf(stderr, "usage: mlod_png_stats FILE.png\n");
    return 2;
  }
  const QString path = app.arguments()[1];
  const QImage image = QImage(path).convertToFormat(QImage::Format_RGB32);
  if (image.isNull()) {
    std::fprintf(stderr, "error: %s: not a readable image\n", qPrintable(path));
    return 2;
  }
  QSet<QRgb> colours;
  for (int y = 0; y < image.height(); ++y) {
    const auto* line = reinterpret_cast<const QRgb*>(image.constScanLine(y));
    for (int x = 0; x < image.width(); ++x)
      colours.insert(line[x]);
  }
  std::printf("%d %d %lld\n", image.width(), image.height(), static_cast<long long>(colours.size()));
  return 0;
}
