#pragma once
// Imports a list of a project's assets one after another, off the UI thread, in the sandboxed
// import worker (ImportJob): what opening a project, relinking a missing file or importing a
// file again at another unit runs. A new list replaces the one in progress: results of the
// old list that arrive later are dropped.
//
// Items naming the same file (its canonical path, symlinks followed) with the same import
// options are imported once and share one Asset: a project may list one clip many times, and
// each import starts a worker process (issue 29: 20,000 copies did not open in a minute).

#include "core/asset.h"
#include "io/import_options.h"

#include <QObject>
#include <QString>
#include <deque>
#include <memory>
#include <vector>

namespace mlod {

class ImportJob;

class AssetLoader : public QObject {
  Q_OBJECT
public:
  struct Item {
    int index = -1;        // the project's asset index, passed back
    QString path;          // absolute
    ImportOptions options; // unit scale and rate
  };

  explicit AssetLoader(QObject* parent = nullptr);

  // Starts importing `items` in order (an empty list: finished() at once).
  void load(std::vector<Item> items);
  bool isLoading() const; // a list is in progress
  // Imports started since construction (identical items count once).
  int importCount() const { return m_imports; }

signals:
  // Every item of one file: `items` share `asset` (loaded) or `reason` (failed).
  void loaded(const std::vector<mlod::AssetLoader::Item>& items, std::shared_ptr<const mlod::Asset> asset);
  void failed(const std::vector<mlod::AssetLoader::Item>& items, const QString& reason);
  // The list is done; `failures` has one line per file that failed (empty: every one loaded).
  void finished(const QString& failures);

private:
  void next();

  ImportJob* m_job = nullptr;
  std::deque<std::vector<Item>> m_queue; // items grouped by file and options
  std::vector<Item> m_current;
  int m_list = 0;        // increases with every load()
  int m_currentList = 0; // the list m_current belongs to
  bool m_active = false;
  int m_imports = 0;
  QString m_failures;
};

} // namespace mlod
