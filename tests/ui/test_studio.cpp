// The scripted run behind `motionlod-studio --screenshot` (editor/studio/scripted_run.h),
// under Xvfb with Mesa: the sample imported, a joint and a level shown, the window saved as a
// PNG that holds the rendered views; the crowd variant measures its frames and reports the
// figures first; a file that cannot be imported gives status 2 and still a picture; an
// unwritable PNG gives status 1.

#include "editor/document/document.h"
#include "editor/main_window.h"
#include "editor/studio/scripted_run.h"

#include <QApplication>
#include <QDockWidget>
#include <QImage>
#include <QSet>
#include <QSignalSpy>
#include <QSurfaceFormat>
#include <QTemporaryDir>
#include <QTest>

using namespace mlod;

namespace {

struct Outcome {
  int status = -1;
  QStringList lines;  // what the run reported
  QStringList errors; // reported as errors
};

Outcome runScript(MainWindow& window, const ScriptedRunOptions& options) {
  Outcome out;
  ScriptedRun run(&window, options);
  QObject::connect(&run, &ScriptedRun::report,
                   [&](const QString& line, bool error) { (error ? out.errors : out.lines) << line; });
  QSignalSpy finished(&run, &ScriptedRun::finished);
  run.start();
  if (finished.wait(180000))
    out.status = finished.first()[0].toInt();
  return out;
}

// Colours in a grid of samples over the image: a blank or one-colour picture has one or two.
int sampledColours(const QImage& image) {
  QSet<QRgb> colours;
  for (int y = 0; y < image.height(); y += 7)
    for (int x = 0; x < image.width(); x += 7)
      colours.insert(image.pixel(x, y));
  return int(colours.size());
}

ScriptedRunOptions sampleRun(const QString& png) {
  ScriptedRunOptions options;
  options.files = {{MLOD_SAMPLE, 5.6444}};
  options.screenshot = png;
  return options;
}

} // namespace

class TestStudio : public QObject {
  Q_OBJECT
private slots:
  // The sample at level 2 with LeftUpLeg selected, saved as a PNG of the whole window.
  void screenshotShowsTheJointAndLevel() {
    QTemporaryDir dir;
    MainWindow window;
    window.resize(1600, 1000);
    window.show();
    ScriptedRunOptions options = sampleRun(dir.filePath("overview.png"));
    options.joint = "LeftUpLeg";
    options.level = 2;
    const Outcome outcome = runScript(window, options);
    QCOMPARE(outcome.status, 0);
    QVERIFY2(outcome.errors.isEmpty(), qPrintable(outcome.errors.join('\n')));
    QCOMPARE(outcome.lines, QStringList{"screenshot: " + options.screenshot});
    Document* document = window.document();
    QCOMPARE(document->currentLevel(), 2);
    QVERIFY(document->currentAssetPtr());
    QCOMPARE(document->currentJoint(), document->currentAssetPtr()->skeleton.find("LeftUpLeg"));
    const QImage shot(options.screenshot);
    QVERIFY(!shot.isNull());
    QCOMPARE(shot.size(), window.size() * window.devicePixelRatio());
    QVERIFY2(sampledColours(shot) > 50, "the picture is nearly blank");
  }

  // --crowd N: the Crowd dock in front with N agents, its figures reported, then the picture.
  void crowdScreenshotReportsItsFigures() {
    QTemporaryDir dir;
    MainWindow window;
    window.resize(1600, 1000);
    window.show();
    ScriptedRunOptions options = sampleRun(dir.filePath("crowd.png"));
    options.crowdAgents = 40;
    options.crowdFrames = 10;
    const Outcome outcome = runScript(window, options);
    QCOMPARE(outcome.status, 0);
    QVERIFY2(outcome.errors.isEmpty(), qPrintable(outcome.errors.join('\n')));
    QVERIFY(outcome.lines.size() >= 3);
    QVERIFY(outcome.lines.first().startsWith("crowd: "));
    QVERIFY2(outcome.lines.filter("mean over 10 frames").size() == 1, qPrintable(outcome.lines.join('\n')));
    QCOMPARE(outcome.lines.last(), "screenshot: " + options.screenshot);
    QVERIFY(window.crowdDock()->isVisible());
    QVERIFY(window.centralWidget()->isVisible()); // the character beside the crowd
    QVERIFY(!QImage(options.screenshot).isNull());
  }

  // A file that cannot be imported: status 2 (bad input), the picture still taken.
  void badInputGivesStatusTwo() {
    QTemporaryDir dir;
    MainWindow window;
    window.show();
    ScriptedRunOptions options;
    options.files = {{dir.filePath("missing.bvh"), 0.0}};
    options.screenshot = dir.filePath("empty.png");
    const Outcome outcome = runScript(window, options);
    QCOMPARE(outcome.status, 2);
    QVERIFY(QFile::exists(options.screenshot));
  }

  // A PNG that cannot be written: status 1 and an error line naming it.
  void unwritableScreenshotGivesStatusOne() {
    QTemporaryDir dir;
    MainWindow window;
    window.show();
    const Outcome outcome = runScript(window, sampleRun(dir.filePath("no/such/folder/shot.png")));
    QCOMPARE(outcome.status, 1);
    QCOMPARE(outcome.errors.size(), 1);
    QVERIFY(outcome.errors.first().contains("no/such/folder/shot.png"));
  }
};

int main(int argc, char** argv) {
  QSurfaceFormat format;
  format.setVersion(3, 3);
  format.setProfile(QSurfaceFormat::CoreProfile);
  format.setDepthBufferSize(24);
  QSurfaceFormat::setDefaultFormat(format);
  QApplication app(argc, argv);
  TestStudio test;
  return QTest::qExec(&test, argc, argv);
}

#include "test_studio.moc"
