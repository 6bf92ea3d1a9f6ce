// motionlod-studio: the editor's thin main.

#include "core/project.h"
#include "core/version.h"
#include "editor/main_window.h"
#include "editor/studio/scripted_run.h"
#include "editor/studio/window_fit.h"
#include "io/import_options.h"
#include "sdk/plugin_host.h"

#include <QApplication>
#include <QCommandLineParser>
#include <QDir>
#include <QFileInfo>
#include <QSettings>
#include <QSurfaceFormat>
#include <cstdio>
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
  QCommandLineOption screenshot{"screenshot",
                                "Save the window to PNG once the imports, clustering and the level's mesh are done, "
                                "print what the viewport drew (per character: level, triangles, joints), then quit.",
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
    parser.addPositionalArgument(
        "files", QString("Projects (%1) to open or files to import.").arg(mlod::kProjectSuffix), "[files...]");
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
  mlod::ScriptedRunOptions run;
  if (parser.isSet(sample))
    run.files.append({samplePath(), *mlod::parseUnitScale("cmu")});
  for (const QString& file : parser.values(open) + parser.positionalArguments())
    run.files.append({file, 0.0});
  if (parser.isSet(unit)) {
    const std::optional<double> scale = mlod::parseUnitScale(parser.value(unit).toStdString());
    if (!scale) {
      std::fprintf(stderr, "error: --unit-scale %s: not a positive number or a preset (cm, m, mm, inch, cmu)\n",
                   qPrintable(parser.value(unit)));
      return 2;
    }
    for (auto& file : run.files)
      file.unitScale = file.unitScale > 0.0 ? file.unitScale : *scale;
  }
  run.screenshot = parser.value(screenshot);
  run.joint = parser.value(joint);
  run.level = parser.value(level).toInt();
  run.crowdAgents = parser.value(crowd).toInt();

  mlod::PluginHost plugins; // File > Export…'s exporters, loaded once for the session
  plugins.loadDefault();
  mlod::MainWindow window(nullptr, &plugins);
  // A scripted screenshot at exactly 1600 x 1000 (the window is grabbed, frame excluded: the
  // docs' images keep one size); a first run at 1600 x 1000 where the screen has room for it
  // and its title bar, else as much as fits (editor/studio/window_fit.h); later runs keep the
  // size the window restored.
  if (!run.screenshot.isEmpty()) {
    window.resize(1600, 1000);
    window.show();
  } else if (!QSettings().contains("mainWindow/geometry")) {
    mlod::showFitted(&window, QSize(1600, 1000));
  } else {
    window.show();
  }
  if (run.screenshot.isEmpty())
    window.offerRecovery();

  mlod::ScriptedRun script(&window, run);
  QObject::connect(&script, &mlod::ScriptedRun::report, [](const QString& line, bool error) {
    std::fprintf(error ? stderr : stdout, "%s%s\n", error ? "error: " : "", qPrintable(line));
  });
  QObject::connect(&script, &mlod::ScriptedRun::finished, &app, [](int status) { QApplication::exit(status); });
  script.start();
  const int code = app.exec();
  return script.status() != 0 ? script.status() : code;
}
