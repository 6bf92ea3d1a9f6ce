#pragma once
// The Statistics dock: the paper's Table 1 for the clip in view at every level (formatted as
// `motionlod simplify` prints it) and three charts: simplified % per joint at the current
// level, simplified joints per frame over time, max joint-position error per level (cm).

#include "core/jpc/jpc_analysis.h"

#include <QStringList>
#include <QWidget>

#include <memory>

class QTableWidget;
class QTabWidget;
class QChartView;
class QChart;
class QLineSeries;

namespace mlod {

class StatisticsView : public QWidget {
  Q_OBJECT
public:
  enum Row { SimplifiedRow, ClustersRow, MaxErrorRow, MaxPositionRow, MeanPositionRow, RowCount };
  explicit StatisticsView(QWidget* parent = nullptr);
  // `names`: the LOD levels' names for the column headers (L<i> where missing).
  void setAnalysis(std::shared_ptr<const JpcAnalysis> analysis, int level, const QStringList& names = {});
  QTableWidget* table() const { return m_table; }
  QChart* jointChart() const;
  QChart* frameChart() const;
  QChart* errorChart() const;
  // The frame the 3D views show, drawn as a vertical line on the per-frame chart; -1: none.
  void setPlayhead(int frame);
  int playhead() const { return m_playhead; }

private:
  void placePlayhead();
  void fillTable();
  void fillCharts();

  std::shared_ptr<const JpcAnalysis> m_analysis;
  int m_level = 0;
  int m_playhead = -1;
  QStringList m_names;
  QTableWidget* m_table;
  QTabWidget* m_tabs;
  QChartView* m_jointView;
  QChartView* m_frameView;
  QChartView* m_errorView;
  QLineSeries* m_playheadLine = nullptr; // owned by the per-frame chart; null when it has none
};

} // namespace mlod
