#include "editor/charts/statistics_view.h"

#include <QBarCategoryAxis>
#include <QBarSeries>
#include <QBarSet>
#include <QCategoryAxis>
#include <QChart>
#include <QChartView>
#include <QCursor>
#include <QFontMetricsF>
#include <QHeaderView>
#include <QLineSeries>
#include <QMouseEvent>
#include <QPen>
#include <QSplitter>
#include <QTabWidget>
#include <QTableWidget>
#include <QToolTip>
#include <QVBoxLayout>
#include <QWheelEvent>
#include <QValueAxis>

#include <algorithm>
#include <cmath>

namespace mlod {

StatisticsView::StatisticsView(QWidget* parent)
    : QWidget(parent), m_table(new QTableWidget(this)), m_tabs(new QTabWidget(this)), m_jointView(new QChartView(this)),
      m_frameView(new QChartView(this)), m_errorView(new QChartView(this)) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  auto* splitter = new QSplitter(Qt::Horizontal, this); // the dock is wide and low
  layout->addWidget(splitter);
  splitter->addWidget(m_table);
  splitter->addWidget(m_tabs);
  splitter->setStretchFactor(1, 3);
  splitter->setSizes({460, 700});
  m_table->setObjectName("table1");
  m_table->setEditTriggers(QAbstractItemView::NoEditTriggers);
  m_table->setRowCount(RowCount);
  m_table->setVerticalHeaderLabels({tr("Simplified joints %"), tr("Clusters"), tr("Max E (cm·°)"),
                                    tr("Max joint pos. error (cm)"), tr("Mean joint pos. error (cm)")});
  m_table->verticalHeaderItem(SimplifiedRow)->setToolTip(tr("100 × clustered joint-frames / (clusterable joints × frames): the paper's Table 1"));
  m_table->verticalHeaderItem(MaxErrorRow)->setToolTip(tr("Largest E(t, key) over the clustered frames, cm·degrees"));
  m_table->verticalHeaderItem(MaxPositionRow)->setToolTip(tr("Forward kinematics of the simplified motion against the original, every joint and frame, cm"));
  m_table->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  m_table->setToolTip(tr("The paper's Table 1 for the clip in view; `motionlod simplify` prints the same figures"));
  for (QChartView* view : {m_jointView, m_frameView, m_errorView}) {
    view->setRenderHint(QPainter::Antialiasing);
    view->chart()->legend()->hide();
    view->chart()->setMargins(QMargins(4, 4, 4, 4));
  }
  m_tabs->addTab(m_jointView, tr("Per joint"));
  m_tabs->addTab(m_frameView, tr("Per frame"));
  m_tabs->addTab(m_errorView, tr("Position error"));
  m_jointView->setToolTip(tr("Simplified frames per joint at the current level, % of the clip"));
  m_frameView->setToolTip(tr("Joints frozen at a key posture per frame, at the current level "
                              "(wheel: zoom towards the cursor; right click: the whole clip)"));
  m_frameView->viewport()->installEventFilter(this);
  connect(m_jointView->chart(), &QChart::plotAreaChanged, this, [this] { labelJoints(); });
  m_errorView->setToolTip(tr("Max joint-position error of each level, cm (forward kinematics)"));
}

bool StatisticsView::eventFilter(QObject* watched, QEvent* event) {
  if (watched == m_frameView->viewport()) {
    if (event->type() == QEvent::Wheel) {
      const auto* wheel = static_cast<QWheelEvent*>(event);
      zoomFrames(wheel->position(), wheel->angleDelta().y());
      return true;
    }
    if (event->type() == QEvent::MouseButtonPress && static_cast<QMouseEvent*>(event)->button() == Qt::RightButton) {
      showAllFrames();
      return true;
    }
  }
  return QWidget::eventFilter(watched, event);
}

namespace {
QValueAxis* frameAxisOf(QChart* chart) {
  const auto axes = chart->axes(Qt::Horizontal);
  return axes.isEmpty() ? nullptr : qobject_cast<QValueAxis*>(axes.first());
}
} // namespace

double StatisticsView::visibleFramesMin() const {
  const QValueAxis* axis = frameAxisOf(m_frameView->chart());
  return axis ? axis->min() : 0.0;
}

double StatisticsView::visibleFramesMax() const {
  const QValueAxis* axis = frameAxisOf(m_frameView->chart());
  return axis ? axis->max() : 0.0;
}

void StatisticsView::zoomFrames(const QPointF& viewportPos, int wheelDelta) {
  QChart* chart = m_frameView->chart();
  QValueAxis* axis = frameAxisOf(chart);
  if (!axis || wheelDelta == 0 || m_frameCount < 2)
    return;
  const double last = m_frameCount - 1;
  const QRectF plot = chart->plotArea();
  if (plot.width() <= 0.0)
    return;
  const QPointF at = chart->mapFromScene(m_frameView->mapToScene(viewportPos.toPoint()));
  const double x = std::clamp((at.x() - plot.left()) / plot.width(), 0.0, 1.0);
  const double min = axis->min();
  const double span = axis->max() - min;
  const double cursor = min + x * span;
  // One wheel step (120) shows 80% of the frames; never fewer than 10 frames nor more than the clip.
  const double zoomed = std::clamp(span * std::pow(0.8, wheelDelta / 120.0), std::min(10.0, last), last);
  const double from = std::clamp(cursor - x * zoomed, 0.0, last - zoomed);
  axis->setRange(from, from + zoomed);
}

void StatisticsView::showAllFrames() {
  if (QValueAxis* axis = frameAxisOf(m_frameView->chart()); axis && m_frameCount >= 1)
    axis->setRange(0, std::max(1, m_frameCount - 1));
}

QChart* StatisticsView::jointChart() const { return m_jointView->chart(); }
QChart* StatisticsView::frameChart() const { return m_frameView->chart(); }
QChart* StatisticsView::errorChart() const { return m_errorView->chart(); }

void StatisticsView::setPlayhead(int frame) {
  if (frame == m_playhead)
    return;
  m_playhead = frame;
  placePlayhead();
}

void StatisticsView::placePlayhead() {
  if (!m_playheadLine || !m_analysis || m_level >= m_analysis->levelCount())
    return;
  const int frames = m_analysis->levels[static_cast<std::size_t>(m_level)].clusters.frameCount;
  if (m_playhead < 0 || m_playhead >= frames) {
    m_playheadLine->clear();
    return;
  }
  const qreal top = m_analysis->prepared->clusterableCount();
  m_playheadLine->replace(QList<QPointF>{{qreal(m_playhead), 0.0}, {qreal(m_playhead), top}});
}

void StatisticsView::setAnalysis(std::shared_ptr<const JpcAnalysis> analysis, int level, const QStringList& names) {
  m_analysis = std::move(analysis);
  m_level = level;
  m_names = names;
  fillTable();
  fillCharts();
}

void StatisticsView::fillTable() {
  // One column per LOD level; level 0 is the original (nothing clustered: zeros, measured).
  const int levels = m_analysis ? m_analysis->levelCount() : 0;
  m_table->setColumnCount(levels);
  QStringList headers;
  for (int l = 0; l < levels; ++l) {
    const QString name = l < m_names.size() ? m_names[l] : tr("L%1").arg(l);
    headers << (l == 0 ? tr("%1\nOriginal").arg(name)
                       : tr("%1\nE=%2").arg(name).arg(m_analysis->levels[static_cast<std::size_t>(l)].threshold));
  }
  m_table->setHorizontalHeaderLabels(headers);
  const auto set = [&](int row, int column, const QString& text) {
    auto* item = new QTableWidgetItem(text);
    item->setTextAlignment(Qt::AlignRight | Qt::AlignVCenter);
    if (column == m_level) {
      QFont bold = item->font();
      bold.setBold(true);
      item->setFont(bold);
    }
    m_table->setItem(row, column, item);
  };
  for (int l = 0; l < levels; ++l) {
    const JpcLevelResult& r = m_analysis->levels[static_cast<std::size_t>(l)];
    set(SimplifiedRow, l, QString::number(r.simplifiedPercent, 'f', 1));
    set(ClustersRow, l, QString::number(r.clusterCount));
    set(MaxErrorRow, l, QString::number(r.maxError, 'f', 2));
    set(MaxPositionRow, l, QString::number(r.maxJointPositionErrorCm, 'f', 3));
    set(MeanPositionRow, l, QString::number(r.meanJointPositionErrorCm, 'f', 3));
  }
}

void StatisticsView::labelJoints() {
  QChart* chart = m_jointView->chart();
  const auto axes = chart->axes(Qt::Horizontal);
  auto* axis = axes.isEmpty() ? nullptr : qobject_cast<QCategoryAxis*>(axes.first());
  const int count = static_cast<int>(m_jointNames.size());
  if (!axis || count == 0)
    return;
  // A label (rotated) takes a line of text across, and Qt Charts adds its text margins and
  // padding; one in `step` bars is named so that each named bar has two lines of room (at 1.5,
  // Testwuson's 38 bars were all "…"). Before the first layout the plot area is empty:
  // the view's width stands in for it (plotAreaChanged() relabels).
  const qreal width = chart->plotArea().width() > 1.0 ? chart->plotArea().width() : 0.8 * m_jointView->width();
  const qreal line = 2.0 * QFontMetricsF(axis->labelsFont()).height();
  const qreal perBar = std::max(1.0, width / count);
  const int step = std::clamp(static_cast<int>(std::ceil(line / perBar)), 1, count);
  if (step == m_jointLabelStep)
    return;
  m_jointLabelStep = step;
  for (const QString& label : axis->categoriesLabels())
    axis->remove(label);
  axis->setStartValue(-0.5);
  for (int j = 0; j < count; j += step)
    axis->append(m_jointNames[j], j);
  axis->setRange(-0.5, count - 0.5);
}

void StatisticsView::fillCharts() {
  m_playheadLine = nullptr; // removeAllSeries() deletes it
  for (QChartView* view : {m_jointView, m_frameView, m_errorView}) {
    view->chart()->removeAllSeries();
    for (QAbstractAxis* axis : view->chart()->axes())
      view->chart()->removeAxis(axis);
  }
  if (!m_analysis || m_level >= m_analysis->levelCount())
    return;
  const JpcLevelResult& level = m_analysis->levels[static_cast<std::size_t>(m_level)];
  const JpcClip& jpc = *m_analysis->prepared;

  // Simplified % per clusterable joint. The joints' axis is a category axis over the bars'
  // positions (0, 1, …) so that its labels can be thinned: a QBarCategoryAxis names every bar,
  // and at 38 or 54 joints each name had less room than a line of text, so every label was
  // elided to "…" (shown rotated as "⋮").
  auto* perJoint = new QBarSet(tr("simplified %"));
  m_jointNames.clear();
  for (int j = 0; j < jpc.jointCount(); ++j)
    if (jpc.clusterable(j)) {
      *perJoint << level.joints[static_cast<std::size_t>(j)].simplifiedPercent;
      m_jointNames << QString::fromStdString(jpc.jointName(j));
    }
  auto* bars = new QBarSeries;
  bars->append(perJoint);
  connect(bars, &QBarSeries::hovered, this, [this, perJoint](bool inside, int index) {
    if (!inside || index < 0 || index >= m_jointNames.size()) {
      QToolTip::hideText();
      return;
    }
    QToolTip::showText(QCursor::pos(), tr("%1: %2% of the frames simplified")
                                           .arg(m_jointNames[index])
                                           .arg(QString::number(perJoint->at(index), 'f', 1)));
  });
  QChart* chart = m_jointView->chart();
  chart->addSeries(bars);
  auto* jointAxis = new QCategoryAxis;
  jointAxis->setObjectName("jointAxis");
  jointAxis->setLabelsPosition(QCategoryAxis::AxisLabelsPositionOnValue);
  jointAxis->setGridLineVisible(false);
  jointAxis->setLabelsAngle(-90);
  QFont small = jointAxis->labelsFont();
  small.setPointSizeF(6.5);
  jointAxis->setLabelsFont(small);
  auto* percent = new QValueAxis;
  percent->setRange(0, 100);
  percent->setTitleText(tr("%"));
  chart->addAxis(jointAxis, Qt::AlignBottom);
  chart->addAxis(percent, Qt::AlignLeft);
  bars->attachAxis(jointAxis);
  bars->attachAxis(percent);
  m_jointLabelStep = 0; // none yet
  labelJoints();
  chart->setTitle(tr("Simplified %, level %1 (E = %2)").arg(m_level).arg(level.threshold));

  // Joints frozen per frame.
  auto* line = new QLineSeries;
  const ClusterSet& clusters = level.clusters;
  std::vector<int> perFrame(static_cast<std::size_t>(clusters.frameCount), 0);
  for (const auto& joint : clusters.joints)
    for (const Cluster& cluster : joint)
      for (int t = cluster.first; t <= cluster.last; ++t)
        ++perFrame[static_cast<std::size_t>(t)];
  for (std::size_t t = 0; t < perFrame.size(); ++t)
    line->append(static_cast<qreal>(t), perFrame[t]);
  chart = m_frameView->chart();
  chart->addSeries(line);
  auto* frameAxis = new QValueAxis;
  m_frameCount = clusters.frameCount;
  frameAxis->setRange(0, std::max(1, clusters.frameCount - 1));
  frameAxis->setTitleText(tr("frame"));
  frameAxis->setLabelFormat("%d");
  auto* countAxis = new QValueAxis;
  countAxis->setRange(0, jpc.clusterableCount());
  countAxis->setTitleText(tr("simplified joints"));
  countAxis->setLabelFormat("%d");
  chart->addAxis(frameAxis, Qt::AlignBottom);
  chart->addAxis(countAxis, Qt::AlignLeft);
  line->attachAxis(frameAxis);
  line->attachAxis(countAxis);
  m_playheadLine = new QLineSeries;
  m_playheadLine->setObjectName("playhead");
  m_playheadLine->setName(tr("current frame"));
  m_playheadLine->setPen(QPen(QColor(220, 60, 40), 1.5));
  chart->addSeries(m_playheadLine);
  m_playheadLine->attachAxis(frameAxis);
  m_playheadLine->attachAxis(countAxis);
  placePlayhead();
  chart->setTitle(tr("Simplified joints per frame, level %1").arg(m_level));

  // Max joint-position error per level.
  auto* errors = new QBarSet(tr("max cm"));
  QStringList levels;
  double largest = 0.0;
  for (int l = 0; l < m_analysis->levelCount(); ++l) {
    const double cm = m_analysis->levels[static_cast<std::size_t>(l)].maxJointPositionErrorCm;
    *errors << cm;
    largest = std::max(largest, cm);
    levels << tr("L%1").arg(l);
  }
  auto* errorBars = new QBarSeries;
  errorBars->append(errors);
  chart = m_errorView->chart();
  chart->addSeries(errorBars);
  auto* levelAxis = new QBarCategoryAxis;
  levelAxis->append(levels);
  auto* cmAxis = new QValueAxis;
  cmAxis->setRange(0, largest > 0 ? largest * 1.1 : 1.0);
  cmAxis->setTitleText(tr("cm"));
  chart->addAxis(levelAxis, Qt::AlignBottom);
  chart->addAxis(cmAxis, Qt::AlignLeft);
  errorBars->attachAxis(levelAxis);
  errorBars->attachAxis(cmAxis);
  chart->setTitle(tr("Max joint-position error per level (cm)"));
}

} // namespace mlod
