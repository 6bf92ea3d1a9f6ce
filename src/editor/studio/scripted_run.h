#pragma once
// A scripted run of the studio, as `motionlod-studio --screenshot PNG [--joint NAME]
// [--level N] [--crowd N] FILES…` asks for it (the user guide's screenshots and the release
// checks are taken this way): import or open the files in order, then show a joint and a
// level, wait until the imports and clustering are done, and save the window as PNG. With
// crowd agents, first show the Crowd dock with that many agents, render `crowdFrames` frames
// and report its figures. Without a screenshot the run only loads the files (the studio stays
// open).
//
// What it prints goes out through report() (main() writes it on stdout, errors on stderr);
// finished() gives the status: 0, 1 when something could not be done (an unwritable PNG, a
// crowd without levels), 2 when an input was bad (an import or a project that failed).

#include <QList>
#include <QObject>
#include <QString>
#include <algorithm>

class QImage;

namespace mlod {

class MainWindow;

struct ScriptedRunOptions {
  struct File {
    QString path;           // a project (.mlod, opened) or a file to import
    double unitScale = 0.0; // cm per file unit; 0: the window's import unit
  };
  QList<File> files;
  QString screenshot;  // PNG to save when everything is done; empty: load only
  QString joint;       // joint to select once loaded (skeleton name); empty: the window's choice
  int level = 0;       // LOD level to show once loaded (> 0)
  int crowdAgents = 0; // > 0: the crowd screenshot
  int crowdFrames = 120;
};

class ScriptedRun : public QObject {
  Q_OBJECT
public:
  ScriptedRun(MainWindow* window, ScriptedRunOptions options, QObject* parent = nullptr);

  // Starts with the next turn of the event loop.
  void start();
  int status() const { return m_status; }

  // The window as it looks, the 3D views drawn as they render (a plain grab leaves them blank).
  static QImage grabWindow(MainWindow& window);

signals:
  void report(const QString& line, bool error);
  void finished(int status); // once, after the screenshot (never without one)

private:
  void next();
  void shoot();
  void fail(int status) { m_status = std::max(m_status, status); }

  MainWindow* m_window;
  ScriptedRunOptions m_options;
  int m_status = 0;
  bool m_shotStarted = false;
  bool m_jointApplied = false;
};

} // namespace mlod
