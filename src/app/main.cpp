// motionlod-studio: the editor's thin main.

#include "core/project.h"
#include "core/version.h"
#include "editor/document/document.h"
#include "editor/main_window.h"
#include "editor/viewport/crowd_panel.h"
#include "io/import_options.h"

#include <QApplication>
#include <QCommandLineParser>
#include <QDir>
#include <QDockWidget>
#include <QFileInfo>
#include <QOpenGLWidget>
#include <QPainter>
#include <QPixmap>
#include <QSurfaceFormat>
#include <QTimer>
#include <cstdio>
#include <functional>
#include <string_view>

namespace {
// The bundled sample: installed beside the executable, or the source tree's copy.
QString samplePath() {
  const QString installed = QDir(QCoreApplication::applicationDirPath()).filePath(MLOD_SAMPLE_RELPATH);
  return QFileInfo::exists(installed) ? QDir::cleanPath(installed) : QString(MLOD_SAMPLE_SOURCE);
}

// The command line, for the studio and for --help / --version without a display.
struct StudioOptions {
  QCommandLineOption open{"open", "Import FILE at start.", "FILE"};
  QCommandLineOption sample{"sample", "Import the bundled sample clip (CMU mocap, in its unit) at start."};
  QCommandLineOption unit{"unit-scale", "cm per file unit for the imports, or a preset: cm, m, mm, inch, cmu.", "S"};
  QCommandLineOption screenshot{"screenshot", "Save the window to PNG once the imports and clustering are done, then quit.",
                                "PNG"};
  QCommandLineOption joint{"joint", "Select joint NAME once loaded (for --screenshot).", "NAME"};
  QCommandLineOption level{"level", "Show LOD level N once loaded (for --screenshot).", "N"};
  QCommandLineOption crowd{"crowd",
                           "With --screenshot: show the Crowd dock with N agents (tinted by level), render 120 "
                           "frames and print its figures (agents per level, joints, vertices, pose CPU ms, fps).",
                           "N"};

  void describe(QCommandLineParser& parser) const {
    parser.setApplicationDescription("Motion LOD Studio: motion level-of-detail authoring for crowds");
    parser.addHelpOption();
    parser.addVersionOption();
    parser.addOptions({open, sample, unit, screenshot, joint, level, crowd});
    parser.addPositionalArgument("files", "Projects (.mlod) to open or files to import.", "[files...]");
  }
};

void nameApplication() {
  QCoreApplication::setOrganizationName("MotionLOD");
  QCoreApplication::setApplicationName("Motion LOD Studio");
  QCoreApplication::setApplicationVersion(mlod::kVersion);
}

// --help and --version print and quit: they need no display, so they are answered before
// the GUI application (which aborts without one) exists.
bool asksForHelpOrVersion(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view argument = argv[i];
    if (argument == "-h" || argument == "--help" || argument == "--help-all" || argument == "-v" ||
        argument == "--version")
      return true;
  }
  return false;
}
} // namespace

int main(int argc, char** argv) {
  const StudioOptions options;
  if (asksForHelpOrVersion(argc, argv)) {
    QCoreApplication core(argc, argv);
    nameApplication();
    QCommandLineParser parser;
    options.describe(parser);
    parser.process(core); // prints and exits
    return 0;
  }
  // The 3D views draw with OpenGL 3.3 core (editor/viewport/); set before the application.
  QSurfaceFormat format;
  format.setVersion(3, 3);
  format.setProfile(QSurfaceFormat::CoreProfile);
  format.setDepthBufferSize(24);
  QSurfaceFormat::setDefaultFormat(format);
  QApplication app(argc, argv);
  nameApplication();

  QCommandLineParser parser;
  options.describe(parser);
  parser.process(app);
  const auto& [open, sample, unit, screenshot, joint, level, crowd] = options;

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
  const int crowdAgents = parser.value(crowd).toInt();
  auto shotStarted = std::make_shared<bool>(false);
  std::function<void()> next; // imports and opens each file in turn, then the screenshot
  next = [&next, &window, pending, shotPath, jointName, levelIndex, crowdAgents, shotStarted, &status]() {
    if (!pending->isEmpty()) {
      const auto [file, scale] = pending->takeFirst();
      if (file.endsWith(".mlod")) {
        if (window.openProject(file))
          return; // projectOpened() calls next
        // Refused (the window says why): a scripted run goes on, and ends with status 2.
        const mlod::Result<mlod::Project> probe =
            mlod::loadProjectFile(QFileInfo(file).absoluteFilePath().toStdString());
        std::fprintf(stderr, "error: %s: %s\n", qPrintable(file),
                     probe ? "the project was not opened" : probe.message().c_str());
        status = 2;
        QTimer::singleShot(0, &window, next);
        return;
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
    if (!shotPath.isEmpty() && !*shotStarted) {
      *shotStarted = true;
      auto shoot = [&window, shotPath, &status] {
        QPixmap shot = window.grab();
        { // the 3D views as they render (overlay text included), over what the window grab gave
          QPainter painter(&shot);
          for (QOpenGLWidget* view : window.findChildren<QOpenGLWidget*>())
            if (view->isVisible())
              painter.drawImage(QRect(view->mapTo(&window, QPoint(0, 0)), view->size()), view->grabFramebuffer());
        }
        const bool saved = shot.save(shotPath, "PNG");
        std::fprintf(saved ? stdout : stderr, "%s %s\n", saved ? "screenshot:" : "error: cannot write",
                     qPrintable(shotPath));
        status = saved ? status : 1;
        QApplication::exit(status);
      };
      auto* crowdPanel = window.findChild<mlod::CrowdPanel*>("crowdPanel");
      if (crowdAgents > 0 && crowdPanel) {
        crowdPanel->setAgentCount(crowdAgents);
        QObject::connect(crowdPanel, &mlod::CrowdPanel::levelsReady, &window,
                         [crowdPanel, shoot, &status](bool ok, const QString& why) {
                           if (!ok) { // nothing to measure: the picture says why
                             std::fprintf(stderr, "error: crowd: %s\n", qPrintable(why));
                             status = 1;
                             shoot();
                             return;
                           }
                           crowdPanel->measure(120);
                         });
        QObject::connect(crowdPanel, &mlod::CrowdPanel::measured, &window, [crowdPanel, shoot](double poseMs, double fps) {
          for (const QString& line : crowdPanel->overlayLines())
            std::printf("crowd: %s\n", qPrintable(line));
          std::printf("crowd: mean over 120 frames: pose evaluation %.3f ms CPU per frame, %.1f fps\n", poseMs, fps);
          shoot();
        });
        QDockWidget* dock = window.findChild<QDockWidget*>("crowdDock");
        dock->raise();
        window.resizeDocks({dock}, {620}, Qt::Vertical);
        return;
      }
      // the character view, given time to render
      if (auto* dock = window.findChild<QDockWidget*>("viewportDock")) {
        dock->raise();
        window.resizeDocks({dock}, {620}, Qt::Vertical);
      }
      QTimer::singleShot(500, &window, shoot);
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
