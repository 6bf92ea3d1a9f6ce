#pragma once
// The meshes of a character's LOD levels as the Viewport draws them (docs/architecture.md
// section 7): exactly what an exporter gets for that level, core's
// buildLodPackage(project, imported, character, {level}) (the level's motion, bone
// reduction and simplified mesh, with every motion assigned to the character), its mesh
// bound to the full skeleton (levelMeshOnFullSkeleton()) so that the viewport's palettes
// skin it. Built off the UI thread, one level at a time (a newer request cancels the
// running one), and kept per level: a level whose threshold, mesh ratio, JPC settings and
// assigned motions are unchanged is not built again. While a job the artist waits for runs
// (Document::isWaitedJobRunning(): an export, the Budget preview) nothing is built: a running
// build is cancelled and the latest request starts when the job ends. No algorithm here: glue
// over core.

#include "core/asset.h"
#include "core/jpc/jpc_settings.h"
#include "core/project.h"
#include "core/skinned_mesh.h"

#include <QFutureWatcher>
#include <QObject>
#include <QString>

#include <atomic>
#include <cstddef>
#include <memory>
#include <vector>

namespace mlod {

class Document;

class LevelMeshes : public QObject {
  Q_OBJECT
public:
  // One level's mesh, or why there is none.
  struct Level {
    SkinnedMesh mesh;   // the level's simplified mesh, joint indices of the full skeleton
    int joints = 0;     // joints of the level's skeleton (after bone reduction)
    double seconds = 0; // how long building it took
    QString error;      // non-empty: no mesh, and why
  };

  explicit LevelMeshes(Document* document, QObject* parent = nullptr);
  ~LevelMeshes() override;

  // Level `level` (> 0) of the project's asset `character` (which must carry a skinned
  // mesh), as the project says it now: the built level, or null while it is being built
  // (ready() follows). A request for another level cancels the one being built.
  std::shared_ptr<const Level> request(int character, int level);
  bool isBuilding() const { return m_watcher.isRunning(); }
  // Levels built so far (for tests: a level asked for again is not built again).
  int builds() const { return m_builds; }

signals:
  void ready(int character, int level);

private:
  // What a level's mesh is built from (the level's switch distance and name do not count).
  struct Key {
    std::shared_ptr<const Asset> character;
    int characterIndex = -1;
    int level = 0;
    double threshold = 0.0;
    double meshRatio = 1.0;
    JpcSettings jpc;                      // the character's: alpha, mode, its joints with their per-level overrides
    std::vector<ProjectMapping> mappings; // those that play a motion on the character
    std::vector<std::shared_ptr<const Asset>> motions; // their motions, imported
    bool operator==(const Key& other) const;
  };
  Key keyOf(int character, int level) const;
  void start(const Key& key);
  void onFinished();
  void waitedJobChanged(bool running);

  Document* m_document = nullptr;
  struct Kept {
    Key key;
    std::shared_ptr<const Level> level;
  };
  std::vector<Kept> m_kept; // most recent last, at most kMaxKept
  static constexpr std::size_t kMaxKept = 12;
  Key m_running;
  std::unique_ptr<Key> m_waiting; // the latest request while one runs
  std::shared_ptr<std::atomic<bool>> m_cancel;
  QFutureWatcher<std::shared_ptr<Level>> m_watcher;
  int m_builds = 0;
};

} // namespace mlod
