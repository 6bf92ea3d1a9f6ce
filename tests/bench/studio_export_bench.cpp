// The studio's export of a project, timed as an artist meets it (issue 26, item 4's goal:
// "export from the studio <= the CLI's time for the same project + 0.5 s"): the project is
// opened in a MainWindow, its assets loaded and the view's figures analysed, then File >
// Export's dialog exports the character in view with PLUGIN to OUT; printed: the seconds from
// the Export button to the dialog's result. Compare with `motionlod export PROJECT --plugin
// PLUGIN -o OUT` on the same machine in the same sitting. With `idle`, the export starts once
// the studio's own background work (the viewport's level mesh, the crowd's levels: the
// global thread pool) has stopped; without, as soon as the figures are in.
// PLUGIN `budget` times the Budget dialog's preview instead (LevelGenerator::preview(), 1 px,
// OUT levels, the project's projection), from the request to previewed(), then the preview
// asked again at 2 px (what the generator kept from the first reused).
//   QT_QPA_PLATFORM=offscreen bench_studio_export PROJECT.mlod PLUGIN OUT [idle]
//   QT_QPA_PLATFORM=offscreen bench_studio_export PROJECT.mlod budget LEVELS [idle]
// A project to time: CHARACTER with MOTION's first clip mapped onto it automatically and the
// character's levels from 1 px, 4 levels (absolute asset paths):
//   bench_studio_export --make-project CHARACTER MOTION PROJECT.mlod
// Nothing here asserts a time.

#include "core/lod/lod_set.h"
#include "core/mapping/motion_mapping.h"
#include "core/project.h"
#include "core/project_package.h"
#include "editor/document/document.h"
#include "editor/document/level_generator.h"
#include "editor/main_window.h"
#include "editor/views/export_dialog.h"
#include "io/importer.h"

#include <QApplication>
#include <QComboBox>
#include <QElapsedTimer>
#include <QEventLoop>
#include <QLineEdit>
#include <QThreadPool>
#include <QTimer>
#include <cstdio>
#include <fstream>
#include <sys/resource.h>

using namespace mlod;

namespace {

// Runs the event loop until `done` or `seconds` pass; false on the timeout.
template <typename Done> bool waitFor(Done done, int seconds) {
  QElapsedTimer timer;
  timer.start();
  while (!done()) {
    if (timer.elapsed() > seconds * 1000)
      return false;
    QEventLoop loop;
    QTimer::singleShot(10, &loop, &QEventLoop::quit);
    loop.exec();
  }
  return true;
}

// CPU seconds this process has used, every thread.
double cpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

int makeProject(const char* characterPath, const char* motionPath, const char* out) {
  const Result<Asset> character = importAsset(characterPath);
  const Result<Asset> motion = importAsset(motionPath);
  if (!character || !motion) {
    std::fprintf(stderr, "error: %s\n", (!character ? character : motion).message().c_str());
    return 2;
  }
  Project project;
  for (const char* path : {characterPath, motionPath}) {
    ProjectAsset asset;
    asset.path = path;
    project.assets.push_back(std::move(asset));
  }
  Result<MappedMotion> mapped = mapMotionAutomatically(motion->skeleton, std::span<const Clip>(motion->clips).first(1),
                                                       character->skeleton, characterPath);
  if (!mapped) {
    std::fprintf(stderr, "error: %s: %s\n", motionPath, mapped.message().c_str());
    return 2;
  }
  ProjectMapping mapping;
  mapping.motion = 1;
  mapping.character = 0;
  mapping.mapping = mapped->mapping;
  project.mappings.push_back(std::move(mapping));
  const std::vector<const Asset*> imported{&*character, &*motion};
  Result<std::vector<Clip>> clips = assignedClips(project, imported, 0);
  if (!clips) {
    std::fprintf(stderr, "error: %s\n", clips.message().c_str());
    return 2;
  }
  LodBudgetOptions options;
  options.jpc = project.jpcSettings(0, character->unitScale);
  options.clips = *clips;
  Result<LodSet> lods = LodSet::fromPixelBudget(*character, 1.0, 4, options);
  if (!lods) {
    std::fprintf(stderr, "error: %s\n", lods.message().c_str());
    return 2;
  }
  project.assets[0].lods = *lods;
  project.view.asset = 0;
  std::ofstream(out) << projectToJson(project);
  std::printf("wrote %s: %zu levels\n", out, lods->levels.size());
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  if (argc == 5 && QByteArray(argv[1]) == "--make-project")
    return makeProject(argv[2], argv[3], argv[4]);
  QApplication app(argc, argv);
  QApplication::setApplicationName("motionlod-studio-bench-export");
  if (argc != 4 && !(argc == 5 && QByteArray(argv[4]) == "idle")) {
    std::fprintf(stderr, "usage: bench_studio_export PROJECT.mlod PLUGIN OUT [idle]\n");
    return 2;
  }
  MainWindow window;
  window.resize(1400, 900);
  window.show();
  QElapsedTimer opening;
  opening.start();
  if (!window.openProject(QString::fromLocal8Bit(argv[1]))) {
    std::fprintf(stderr, "error: %s: could not be opened\n", argv[1]);
    return 2;
  }
  Document* document = window.document();
  if (!waitFor([&] { return !document->isLoading() && !document->isAnalysing() && document->analysis(); }, 600)) {
    std::fprintf(stderr, "error: %s: not loaded and analysed within 10 minutes\n", argv[1]);
    return 1;
  }
  std::printf("opened and analysed: %.2f s\n", opening.elapsed() / 1000.0);
  if (argc == 5) { // the pool idle for a second on end
    QElapsedTimer quiet;
    quiet.start();
    if (!waitFor(
            [&] {
              if (QThreadPool::globalInstance()->activeThreadCount() > 0)
                quiet.restart();
              return quiet.elapsed() > 1000;
            },
            600)) {
      std::fprintf(stderr, "error: the studio did not settle within 10 minutes\n");
      return 1;
    }
    std::printf("settled: %.2f s\n", opening.elapsed() / 1000.0);
  }

  if (QByteArray(argv[2]) == "budget") {
    LevelGenerator* generator = document->levelGenerator();
    bool previewed = false, ok = false;
    QString message;
    QObject::connect(generator, &LevelGenerator::previewed, [&](bool success, const QString& text) {
      previewed = true;
      ok = success;
      message = text;
    });
    QElapsedTimer clock;
    const double cpu = cpuSeconds();
    clock.start();
    QString error;
    if (!generator->preview(1.0, QByteArray(argv[3]).toInt(), document->lods().projection, document->lods().skinning,
                            &error)) {
      std::fprintf(stderr, "error: no preview: %s\n", qPrintable(error));
      return 1;
    }
    if (!waitFor([&] { return previewed; }, 600)) {
      std::fprintf(stderr, "error: the preview did not finish within 10 minutes\n");
      return 1;
    }
    std::printf("studio budget preview (asset %d, 1 px, %s levels): %.2f s (CPU %.2f s): %s\n",
                document->currentAsset(), argv[3], clock.elapsed() / 1000.0, cpuSeconds() - cpu, qPrintable(message));
    if (!ok)
      return 1;
    // asked again with another budget, as an artist tries a few (the search's cache reused)
    previewed = false;
    const double cpuAgain = cpuSeconds();
    clock.restart();
    if (!generator->preview(2.0, QByteArray(argv[3]).toInt(), document->lods().projection, document->lods().skinning,
                            &error) ||
        !waitFor([&] { return previewed; }, 600)) {
      std::fprintf(stderr, "error: no second preview: %s\n", qPrintable(error));
      return 1;
    }
    const LodBudgetReport& report = generator->plan().report;
    std::printf("studio budget preview again (2 px, %s levels): %.2f s (CPU %.2f s, %d joint clusterings, %d meshes "
                "built): %s\n",
                argv[3], clock.elapsed() / 1000.0, cpuSeconds() - cpuAgain, report.jointsClustered, report.meshesBuilt,
                qPrintable(message));
    return ok ? 0 : 1;
  }

  ExportDialog dialog(document, window.pluginHost(), &window);
  dialog.show();
  const int plugin = dialog.pluginCombo()->findData(QString::fromLocal8Bit(argv[2]));
  if (plugin < 0) {
    std::fprintf(stderr, "error: no exporter plugin '%s'\n", argv[2]);
    return 2;
  }
  dialog.pluginCombo()->setCurrentIndex(plugin);
  dialog.outputEdit()->setText(QString::fromLocal8Bit(argv[3]));
  bool finished = false, ok = false;
  QString message;
  QObject::connect(&dialog, &ExportDialog::exportFinished, [&](bool success, const QString& text) {
    finished = true;
    ok = success;
    message = text;
  });
  QElapsedTimer exporting;
  const double cpu = cpuSeconds();
  exporting.start();
  dialog.startExport();
  if (!waitFor([&] { return finished; }, 600)) {
    std::fprintf(stderr, "error: the export did not finish within 10 minutes\n");
    return 1;
  }
  const double seconds = exporting.elapsed() / 1000.0;
  std::printf("studio export (asset %d, %s): %.2f s (CPU %.2f s): %s\n", dialog.exportedAsset(), argv[2], seconds,
              cpuSeconds() - cpu, ok ? "ok" : qPrintable(message));
  return ok ? 0 : 1;
}
