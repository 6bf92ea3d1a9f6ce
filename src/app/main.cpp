// motionlod-studio: the editor's thin main.

#include "core/version.h"
#include "editor/main_window.h"

#include <QApplication>
#include <QCommandLineParser>
#include <QDir>
#include <QFileInfo>
#include <QTimer>

#include <cstdio>

namespace {
// The bundled sample: installed beside the executable, or the source tree's copy.
QString samplePath() {
  const QString installed = QDir(QCoreApplication::applicationDirPath()).filePath(MLOD_SAMPLE_RELPATH);
  return QFileInfo::exists(installed) ? QDir::cleanPath(installed) : QString(MLOD_SAMPLE_SOURCE);
}
} // namespace

int main(int argc, char** argv) {
  QApplication app(argc, argv);
  QApplication::setOrganizationName("MotionLOD");
  QApplication::setApplicationName("Motion LOD Studio");
  QApplication::setApplicationVersion(mlod::kVersion);

  QCommandLineParser parser;
  parser.setApplicationDescription("Motion LOD Studio: motion level-of-detail authoring for crowds");
  parser.addHelpOption();
  parser.addVersionOption();
  const QCommandLineOption open("open", "Import FILE at start.", "FILE");
  const QCommandLineOption sample("sample", "Import the bundled sample clip at start.");
  const QCommandLineOption screenshot("screenshot", "Save the window to PNG once the imports are done, then quit.", "PNG");
  parser.addOptions({open, sample, screenshot});
  parser.addPositionalArgument("files", "Files to import.", "[files...]");
  parser.process(app);

  QStringList files = parser.values(open) + parser.positionalArguments();
  if (parser.isSet(sample))
    files.prepend(samplePath());

  mlod::MainWindow window;
  window.show();

  auto pending = std::make_shared<QStringList>(files);
  const QString shotPath = parser.value(screenshot);
  int status = 0;
  auto next = [&window, pending, shotPath, &status]() {
    if (!pending->isEmpty()) {
      window.importFile(pending->takeFirst());
      return;
    }
    if (!shotPath.isEmpty()) {
      const bool saved = window.grab().save(shotPath, "PNG");
      std::fprintf(saved ? stdout : stderr, "%s %s\n", saved ? "screenshot:" : "error: cannot write",
                   qPrintable(shotPath));
      status = saved ? status : 1;
      QApplication::exit(status);
    }
  };
  QObject::connect(&window, &mlod::MainWindow::importFinished, &window,
                   [&](bool ok, const QString&, const QString&) {
                     if (!ok)
                       status = 2;
                     QTimer::singleShot(0, &window, next);
                   });
  QTimer::singleShot(0, &window, next);
  const int code = app.exec();
  return status != 0 ? status : code;
}
