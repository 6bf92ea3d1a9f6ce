// motionlod-studio: the editor's thin main.

#include "core/version.h"
#include "editor/document/document.h"
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
  const QCommandLineOption screenshot("screenshot",
                                      "Save the window to PNG once the imports and clustering are done, then quit.", "PNG");
  const QCommandLineOption joint("joint", "Select joint NAME once loaded (for --screenshot).", "NAME");
  const QCommandLineOption level("level", "Show LOD level N once loaded (for --screenshot).", "N");
  parser.addOptions({open, sample, unit, screenshot, joint, level});
  parser.addPositionalArgument("files", "Projects (.mlod) to open or files to import.", "[files...]");
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
  window.resize(1600, 1000);
  window.show();
  if (!parser.isSet(screenshot))
    window.offerRecovery();

  auto pending = std::make_shared<QList<QPair<QString, double>>>(files);
  const QString shotPath = parser.value(screenshot);
  int status = 0;
  const QString jointName = parser.value(joint);
  const int levelIndex = parser.value(level).toInt();
  auto next = [&window, pending, shotPath, jointName, levelIndex, &status]() {
    if (!pending->isEmpty()) {
      const auto [file, scale] = pending->takeFirst();
      if (file.endsWith(".mlod")) {
        if (!window.openProject(file))
          status = 2;
        return; // projectOpened() calls next
      }
      if (scale > 0.0)
        window.importFileWithUnit(file, scale);
      else
        window.importFile(file);
      return;
    }
    mlod::Document* document = window.document();
    if (!jointName.isEmpty() && document->currentAssetPtr() && document->currentJoint() < 0)
      document->setCurrentJoint(document->currentAssetPtr()->skeleton.find(jointName.toStdString()));
    if (levelIndex > 0)
      document->setCurrentLevel(levelIndex);
    if (document->isAnalysing() || document->isLoading())
      return; // analysisFinished() or projectOpened() calls next
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
  QObject::connect(window.document(), &mlod::Document::projectOpened, &window,
                   [&](bool, const QString&) { QTimer::singleShot(0, &window, next); });
  QObject::connect(window.document(), &mlod::Document::analysisFinished, &window, [&](bool, const QString&) {
    if (pending->isEmpty())
      QTimer::singleShot(0, &window, next);
  });
  QTimer::singleShot(0, &window, next);
  const int code = app.exec();
  return status != 0 ? status : code;
}
