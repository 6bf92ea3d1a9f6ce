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
class QPointF;

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
  // The per-joint chart's joint names (its bars', in order), and the step between the names
  // its axis labels: 1 where every label fits beside the next, else every step-th joint is
  // named (thinned to fit the chart's width; each bar's tooltip names its joint).
  const QStringList& jointNames() const { return m_jointNames; }
  int jointLabelStep() const { return m_jointLabelStep; }
  // The frame the 3D views show, drawn as a vertical line on the per-frame chart; -1: none.
  void setPlayhead(int frame);
  int playhead() const { return m_playhead; }
  // The per-frame chart zooms with the wheel towards the frame under the cursor (as the
  // Clustering Table does); a right click shows the whole clip again.
  double visibleFramesMin() const;
  double visibleFramesMax() const;

protected:
  bool eventFilter(QObject* watched, QEvent* event) override;

private:
  void placePlayhead();
  // Zooms the per-frame chart's frame axis by `wheelDelta` (1/8 degrees, + = in) about the
  // frame under `viewportPos`; the frame there stays under the cursor.
  void zoomFrames(const QPointF& viewportPos, int wheelDelta);
  void showAllFrames();
  void fillTable();
  void fillCharts();
  // (Re)labels the per-joint chart's axis for the chart's current plot width.
  void labelJoints();

  std::shared_ptr<const JpcAnalysis> m_analysis;
  int m_level = 0;
  int m_playhead = -1;
  int m_frameCount = 0; // of the per-frame chart
  QStringList m_names;
  QStringList m_jointNames;
  int m_jointLabelStep = 1;
  QTableWidget* m_table;
  QTabWidget* m_tabs;
  QChartView* m_jointView;
  QChartView* m_frameView;
  QChartView* m_errorView;
  QLineSeries* m_playheadLine = nullptr; // owned by the per-frame chart; null when it has none
};

} // namespace mlod
