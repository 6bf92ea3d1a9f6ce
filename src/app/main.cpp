// motionlod-studio: the editor's thin main.

#include "core/version.h"
#include "editor/main_window.h"
#include "io/import_options.h"

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
  const QCommandLineOption sample("sample", "Import the bundled sample clip (CMU mocap, in its unit) at start.");
  const QCommandLineOption unit("unit-scale", "cm per file unit for the imports, or a preset: cm, m, mm, inch, cmu.",
                                "S");
  const QCommandLineOption screenshot("screenshot", "Save the window to PNG once the imports are done, then quit.", "PNG");
  parser.addOptions({open, sample, unit, screenshot});
  parser.addPositionalArgument("files", "Files to import.", "[files...]");
  parser.process(app);

  // Each file with the unit it is imported in (0 = the window's import unit).
  QList<QPair<QString, double>> files;
  if (parser.isSet(sample))
    files.append({samplePath(), *mlod::parseUnitScale("cmu")});
  for (const QString& file : parser.values(open) + parser.positionalArguments())
    files.append({file, 0.0});

  mlod::MainWindow window;
  if (parser.isSet(unit)) {
    const std::optional<double> scale = mlod::parseUnitScale(parser.value(unit).toStdString());
    if (!scale) {
      std::fprintf(stderr, "error: --unit-scale %s: not a positive number or a preset (cm, m, mm, inch, cmu)\n",
                   qPrintable(parser.value(unit)));
      return 2;
    }
    for (auto& file : files)
      file.second = file.second > 0.0 ? file.second : *scale;
  }
  window.show();

  auto pending = std::make_shared<QList<QPair<QString, double>>>(files);
  const QString shotPath = parser.value(screenshot);
  int status = 0;
  auto next = [&window, pending, shotPath, &status]() {
    if (!pending->isEmpty()) {
      const auto [file, scale] = pending->takeFirst();
      if (scale > 0.0)
        window.importFileWithUnit(file, scale);
      else
        window.importFile(file);
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
