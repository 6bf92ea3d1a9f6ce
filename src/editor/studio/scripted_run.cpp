#include "editor/studio/scripted_run.h"

#include "core/project.h"
#include "editor/document/document.h"
#include "editor/main_window.h"
#include "editor/viewport/crowd_panel.h"
#include "editor/viewport/scene_view.h"
#include "editor/viewport/viewport_panel.h"

#include <QDockWidget>
#include <QFileInfo>
#include <QImage>
#include <QOpenGLWidget>
#include <QPainter>
#include <QTimer>

namespace mlod {

ScriptedRun::ScriptedRun(MainWindow* window, ScriptedRunOptions options, QObject* parent)
    : QObject(parent), m_window(window), m_options(std::move(options)) {
  m_window->setUnattended(true); // a modal question would wait for no one
  const auto later = [this] { QTimer::singleShot(0, this, &ScriptedRun::next); };
  connect(m_window, &MainWindow::importFinished, this, [this, later](bool ok, const QString&, const QString&) {
    if (!ok)
      fail(2);
    later();
  });
  connect(m_window->document(), &Document::projectOpened, this, [later](bool, const QString&) { later(); });
  connect(m_window->document(), &Document::analysisFinished, this, [this, later](bool, const QString&) {
    if (m_options.files.isEmpty())
      later();
  });
  if (ViewportPanel* viewport = m_window->viewportPanel())
    connect(viewport, &ViewportPanel::levelMeshReady, this, [this, later] {
      if (m_options.files.isEmpty())
        later();
    });
}

void ScriptedRun::start() {
  QTimer::singleShot(0, this, &ScriptedRun::next);
}

QImage ScriptedRun::grabWindow(MainWindow& window) {
  QImage shot = window.grab().toImage();
  QPainter painter(&shot);
  for (QOpenGLWidget* view : window.findChildren<QOpenGLWidget*>())
    if (view->isVisible())
      painter.drawImage(QRect(view->mapTo(&window, QPoint(0, 0)), view->size()), view->grabFramebuffer());
  return shot;
}

// Called after every step (an import, a project opened, figures landed): does the next one.
void ScriptedRun::next() {
  if (!m_options.files.isEmpty()) {
    const ScriptedRunOptions::File file = m_options.files.takeFirst();
    if (isProjectFile(file.path.toStdString())) {
      if (m_window->openProject(file.path))
        return; // projectOpened() calls next
      // Refused (the window says why): the run goes on, and ends with status 2.
      const Result<Project> probe = loadProjectFile(QFileInfo(file.path).absoluteFilePath().toStdString());
      emit report(tr("%1: %2").arg(file.path,
                                   probe ? tr("the project was not opened") : QString::fromStdString(probe.message())),
                  true);
      fail(2);
      QTimer::singleShot(0, this, &ScriptedRun::next);
      return;
    }
    if (file.unitScale > 0.0)
      m_window->importFileWithUnit(file.path, file.unitScale);
    else
      m_window->importFile(file.path);
    return; // importFinished() calls next
  }
  Document* document = m_window->document();
  // the joint asked for wins over the one the window picks when an analysis finishes first
  // (once: a later step leaves the user's choice alone)
  if (!m_options.joint.isEmpty() && document->currentAssetPtr() && !m_jointApplied) {
    document->setCurrentJoint(document->currentAssetPtr()->skeleton.find(m_options.joint.toStdString()));
    m_jointApplied = true;
  }
  if (m_options.level > 0)
    document->setCurrentLevel(m_options.level);
  if (document->isAnalysing() || document->isLoading())
    return; // analysisFinished() or projectOpened() calls next
  if (m_window->viewportPanel() && m_window->viewportPanel()->levelMeshPending())
    return; // levelMeshReady() calls next
  if (m_options.screenshot.isEmpty() || m_shotStarted)
    return;
  m_shotStarted = true;
  CrowdPanel* crowd = m_window->crowdPanel();
  if (m_options.crowdAgents > 0 && crowd) {
    crowd->setAgentCount(m_options.crowdAgents);
    connect(crowd, &CrowdPanel::levelsReady, this, [this, crowd](bool ok, const QString& why) {
      if (!ok) { // nothing to measure: the picture says why
        emit report(tr("crowd: %1").arg(why), true);
        fail(1);
        shoot();
        return;
      }
      crowd->measure(m_options.crowdFrames);
    });
    connect(crowd, &CrowdPanel::measured, this, [this, crowd](double poseMs, double fps) {
      for (const QString& line : crowd->overlayLines())
        emit report(tr("crowd: %1").arg(line), false);
      emit report(tr("crowd: mean over %1 frames: pose evaluation %2 ms CPU per frame, %3 fps")
                      .arg(m_options.crowdFrames)
                      .arg(poseMs, 0, 'f', 3)
                      .arg(fps, 0, 'f', 1),
                  false);
      shoot();
    });
    m_window->showDock(m_window->crowdDock());
    return;
  }
  QTimer::singleShot(500, this, &ScriptedRun::shoot); // the character view (the centre), given time to render
}

void ScriptedRun::shoot() {
  const bool saved = grabWindow(*m_window).save(m_options.screenshot, "PNG");
  // what the character view drew, one line per character, and what reached the GPU
  if (ViewportPanel* viewport = m_window->viewportPanel()) {
    for (const QString& line : viewport->drawnLines())
      emit report(tr("viewport: %1").arg(line), false);
    if (SceneView* view = viewport->sceneView(); view && view->isVisible() && view->trianglesGenerated() >= 0)
      emit report(tr("viewport: %1 triangles reached the GPU in the last frame%2")
                      .arg(view->trianglesGenerated())
                      .arg(view->wireframe() ? tr(" (wireframe)") : QString()),
                  false);
  }
  if (saved)
    emit report(tr("screenshot: %1").arg(m_options.screenshot), false);
  else {
    emit report(tr("cannot write %1").arg(m_options.screenshot), true);
    fail(1);
  }
  emit finished(m_status);
}

} // namespace mlod
