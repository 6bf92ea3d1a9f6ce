#pragma once
// Imports a list of a project's assets one after another, off the UI thread, in the sandboxed
// import worker (ImportJob): what opening a project, relinking a missing file or importing a
// file again at another unit runs. A new list replaces the one in progress: results of the
// old list that arrive later are dropped.

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

signals:
  void loaded(const mlod::AssetLoader::Item& item, std::shared_ptr<const mlod::Asset> asset);
  void failed(const mlod::AssetLoader::Item& item, const QString& reason);
  // The list is done; `failures` has one line per item that failed (empty: every one loaded).
  void finished(const QString& failures);

private:
  void next();

  ImportJob* m_job = nullptr;
  std::deque<Item> m_queue;
  Item m_current;
  int m_list = 0;        // increases with every load()
  int m_currentList = 0; // the list m_current belongs to
  bool m_active = false;
  QString m_failures;
};

} // namespace mlod
