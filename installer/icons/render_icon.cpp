// mlod_render_icon: renders the studio's SVG icon to the hicolor PNG sizes at build time,
// so the SVG stays the only source. Usage: mlod_render_icon ICON.svg OUTDIR NAME SIZE...
// writes OUTDIR/<SIZE>x<SIZE>/apps/NAME.png for each size.

#include <QDir>
#include <QGuiApplication>
#include <QImage>
#include <QPainter>
#include <QSvgRenderer>

#include <cstdio>

int main(int argc, char** argv) {
  // No display is needed to paint into a QImage.
  qputenv("QT_QPA_PLATFORM", "offscreen");
  QGuiApplication app(argc, argv);
  const QStringList args = app.arguments();
  if (args.size() < 5) {
    std::fprintf(stderr, "usage: mlod_render_icon ICON.svg OUTDIR NAME SIZE...\n");
    return 2;
  }
  QSvgRenderer renderer(args[1]);
  if (!renderer.isValid()) {
    std::fprintf(stderr, "error: %s: not a valid SVG\n", qPrintable(args[1]));
    return 2;
  }
  for (qsizetype i = 4; i < args.size(); ++i) {
    bool ok = false;
    const int size = args[i].toInt(&ok);
    if (!ok || size <= 0 || size > 4096) {
      std::fprintf(stderr, "error: %s: not a size in pixels\n", qPrintable(args[i]));
      return 2;
    }
    QImage image(size, size, QImage::Format_ARGB32_Premultiplied);
    image.fill(Qt::transparent);
    QPainter painter(&image);
    painter.setRenderHint(QPainter::Antialiasing);
    renderer.render(&painter);
    painter.end();
    const QString dir = QStringLiteral("%1/%2x%2/apps").arg(args[2]).arg(size);
    const QString file = QStringLiteral("%1/%2.png").arg(dir, args[3]);
    if (!QDir().mkpath(dir) || !image.save(file, "PNG")) {
      std::fprintf(stderr, "error: %s: cannot write\n", qPrintable(file));
      return 1;
    }
  }
  return 0;
}
