#include "editor/views/clustering_table_view.h"

#include <QMouseEvent>
#include <QPainter>
#include <QToolTip>
#include <QWheelEvent>

#include <algorithm>
#include <cmath>

namespace mlod {

namespace {
// Errors as heat on a square-root scale up to the largest error in view: 0 blue, then
// green, yellow, red. Entries in a row's run (E <= T) are bright, the others dimmed.
QRgb heat(double error, double largest, bool inBand) {
  const double x = std::clamp(std::sqrt(error / std::max(largest, 1e-9)), 0.0, 1.0);
  QColor colour = QColor::fromHsvF(static_cast<float>(0.66 * (1.0 - x)), 0.85f, inBand ? 0.95f : 0.45f);
  return colour.rgb();
}
} // namespace

ClusteringTableView::ClusteringTableView(QWidget* parent) : QWidget(parent) {
  setMouseTracking(true);
  setMinimumSize(240, 200);
  setToolTip(tr("Clustering table (Figure 5): E_j(t, t_ref) in cm·degrees; wheel zooms, drag pans"));
}

void ClusteringTableView::setAnalysis(std::shared_ptr<const JpcAnalysis> analysis, int joint, int level) {
  const bool sameClip = m_analysis && analysis && m_analysis->asset == analysis->asset && m_analysis->clip == analysis->clip;
  m_analysis = std::move(analysis);
  m_joint = joint;
  m_level = level;
  m_track = nullptr;
  m_table.reset();
  if (m_analysis && joint >= 0 && joint < m_analysis->prepared->jointCount() && level < m_analysis->levelCount() &&
      m_analysis->prepared->clusterable(joint) && !m_analysis->prepared->locked(joint)) {
    m_track = &m_analysis->prepared->track(joint);
    m_threshold = m_analysis->levels[static_cast<std::size_t>(level)].joints[static_cast<std::size_t>(joint)].threshold;
    m_table = std::make_unique<ClusteringTable>(*m_track, m_threshold, TableRows::Ends);
  }
  if (!sameClip)
    resetZoom();
  m_dirty = true;
  update();
}

void ClusteringTableView::resetZoom() {
  m_first = 0.0;
  m_span = m_analysis ? std::max(1, m_analysis->clipRef().frameCount) : 1.0;
  m_dirty = true;
  update();
}

// Room right of the table for its colour scale.
constexpr int kLegendWidth = 78;

QRect ClusteringTableView::plotRect() const {
  const int side = std::max(10, std::min(width() - 56 - kLegendWidth, height() - 40));
  return QRect(48, 8, side, side);
}

double ClusteringTableView::frameAtX(double x) const {
  const QRect r = plotRect();
  return m_first + (x - r.left()) / r.width() * m_span;
}
double ClusteringTableView::frameAtY(double y) const {
  const QRect r = plotRect();
  return m_first + (y - r.top()) / r.height() * m_span;
}

std::optional<ClusteringTableView::Entry> ClusteringTableView::entryAt(QPoint position) const {
  if (!m_table || !plotRect().contains(position))
    return std::nullopt;
  const int frames = m_table->frameCount();
  Entry entry;
  entry.t = static_cast<int>(std::floor(frameAtX(position.x() + 0.5)));
  entry.ref = static_cast<int>(std::floor(frameAtY(position.y() + 0.5)));
  if (entry.t < 0 || entry.ref < 0 || entry.t >= frames || entry.ref >= frames)
    return std::nullopt;
  entry.error = m_table->entry(entry.t, entry.ref);
  entry.inBand = entry.t >= entry.ref && entry.t <= m_table->rowEnd(entry.ref);
  return entry;
}

void ClusteringTableView::renderImage() {
  m_dirty = false;
  const QRect r = plotRect();
  m_image = QImage(r.size(), QImage::Format_RGB32);
  m_image.fill(palette().color(QPalette::Base));
  if (!m_table)
    return;
  const int frames = m_table->frameCount();
  std::vector<double> errors(static_cast<std::size_t>(r.width()) * static_cast<std::size_t>(r.height()), -1.0);
  double largest = 0.0;
  for (int y = 0; y < r.height(); ++y) {
    const int ref = static_cast<int>(std::floor(m_first + (y + 0.5) / r.height() * m_span));
    if (ref < 0 || ref >= frames)
      continue;
    for (int x = 0; x < r.width(); ++x) {
      const int t = static_cast<int>(std::floor(m_first + (x + 0.5) / r.width() * m_span));
      if (t < 0 || t >= frames)
        continue;
      const double e = m_track->error(t, ref);
      errors[static_cast<std::size_t>(y) * static_cast<std::size_t>(r.width()) + static_cast<std::size_t>(x)] = e;
      largest = std::max(largest, e);
    }
  }
  m_largest = largest;
  for (int y = 0; y < r.height(); ++y) {
    const int ref = static_cast<int>(std::floor(m_first + (y + 0.5) / r.height() * m_span));
    if (ref < 0 || ref >= frames)
      continue;
    const int end = m_table->rowEnd(ref);
    QRgb* line = reinterpret_cast<QRgb*>(m_image.scanLine(y));
    for (int x = 0; x < r.width(); ++x) {
      const int t = static_cast<int>(std::floor(m_first + (x + 0.5) / r.width() * m_span));
      if (t < 0 || t >= frames)
        continue;
      const double e = errors[static_cast<std::size_t>(y) * static_cast<std::size_t>(r.width()) + static_cast<std::size_t>(x)];
      line[x] = heat(e, largest, t >= ref && t <= end);
    }
  }
}

void ClusteringTableView::paintEvent(QPaintEvent*) {
  QPainter painter(this);
  painter.fillRect(rect(), palette().color(QPalette::Window));
  const QRect r = plotRect();
  if (!m_table) {
    painter.setPen(palette().color(QPalette::Text));
    QString text = tr("Select a joint in the Skeleton dock to see its clustering table.");
    if (m_analysis && m_joint >= 0 && m_joint < m_analysis->prepared->jointCount())
      text = m_analysis->prepared->locked(m_joint) ? tr("%1 is locked: never clustered.").arg(QString::fromStdString(m_analysis->prepared->jointName(m_joint)))
                                                   : tr("%1 has no rotation channel: never clustered.").arg(QString::fromStdString(m_analysis->prepared->jointName(m_joint)));
    painter.drawText(rect().adjusted(12, 12, -12, -12), Qt::AlignCenter | Qt::TextWordWrap, text);
    return;
  }
  if (m_dirty || m_image.size() != r.size())
    renderImage();
  painter.drawImage(r.topLeft(), m_image);
  painter.setClipRect(r);
  const auto toX = [&](double frame) { return r.left() + (frame - m_first) / m_span * r.width(); };
  const auto toY = [&](double frame) { return r.top() + (frame - m_first) / m_span * r.height(); };
  const auto& clusters = m_analysis->levels[static_cast<std::size_t>(m_level)].clusters.joints[static_cast<std::size_t>(m_joint)];
  for (const Cluster& cluster : clusters) {
    const QRectF box(QPointF(toX(cluster.first), toY(cluster.first)), QPointF(toX(cluster.last + 1), toY(cluster.last + 1)));
    painter.setPen(QPen(Qt::white, 1.5));
    painter.setBrush(Qt::NoBrush);
    painter.drawRect(box);
    // The key posture's row: its errors to every frame of the cluster stay within T (eq. 7).
    painter.setPen(QPen(QColor(255, 40, 200), 2.0));
    const double keyY = toY(cluster.key + 0.5);
    painter.drawLine(QPointF(box.left(), keyY), QPointF(box.right(), keyY));
    painter.setBrush(QColor(255, 40, 200));
    painter.drawEllipse(QPointF(toX(cluster.key + 0.5), keyY), 3.0, 3.0);
  }
  painter.setClipping(false);
  painter.setPen(palette().color(QPalette::Text));
  painter.setBrush(Qt::NoBrush);
  painter.drawRect(r);
  painter.drawText(QRect(0, r.top(), r.left() - 4, 20), Qt::AlignRight, QString::number(int(m_first)));
  painter.drawText(QRect(0, r.bottom() - 20, r.left() - 4, 20), Qt::AlignRight, QString::number(int(m_first + m_span)));
  painter.drawText(QRect(r.left(), r.bottom() + 2, r.width(), 18), Qt::AlignLeft,
                   tr("t →   (t_ref ↓)   T = %1 cm·°, %2 clusters").arg(m_threshold).arg(clusters.size()));
  paintLegend(painter, r);
}

void ClusteringTableView::paintLegend(QPainter& painter, const QRect& plot) const {
  // The colour scale: E from 0 (bottom) to the largest in view (top), square-root spaced as
  // heat() maps it; the threshold T marked; dimmed colours are entries outside a run.
  const QRect bar(plot.right() + 12, plot.top() + 14, 12, std::max(20, plot.height() - 28));
  for (int y = 0; y < bar.height(); ++y) {
    const double x = 1.0 - (y + 0.5) / bar.height(); // heat()'s sqrt(E / largest)
    painter.setPen(QColor(heat(x * x * m_largest, m_largest, true)));
    painter.drawLine(bar.left(), bar.top() + y, bar.right(), bar.top() + y);
  }
  painter.setPen(palette().color(QPalette::Text));
  painter.setBrush(Qt::NoBrush);
  painter.drawRect(bar.adjusted(0, 0, -1, -1));
  const auto yOf = [&](double error) {
    const double x = m_largest > 0.0 ? std::sqrt(std::clamp(error / m_largest, 0.0, 1.0)) : 0.0;
    return bar.bottom() - x * bar.height();
  };
  const int textLeft = bar.right() + 4;
  const int textWidth = width() - textLeft;
  painter.drawText(QRect(bar.left() - 8, plot.top() - 2, textWidth + 20, 14), Qt::AlignLeft, tr("E cm·°"));
  painter.drawText(QRect(textLeft, bar.top() - 7, textWidth, 14), Qt::AlignLeft | Qt::AlignVCenter,
                   QString::number(m_largest, 'f', m_largest < 10.0 ? 1 : 0));
  painter.drawText(QRect(textLeft, bar.bottom() - 7, textWidth, 14), Qt::AlignLeft | Qt::AlignVCenter,
                   QStringLiteral("0"));
  if (m_threshold > 0.0 && m_threshold < m_largest) {
    const int y = static_cast<int>(std::lround(yOf(m_threshold)));
    painter.setPen(QPen(palette().color(QPalette::Text), 1.5));
    painter.drawLine(bar.left() - 3, y, bar.right() + 3, y);
    painter.drawText(QRect(textLeft + 2, y - 7, textWidth, 14), Qt::AlignLeft | Qt::AlignVCenter,
                     tr("T %1").arg(m_threshold));
  }
}

void ClusteringTableView::wheelEvent(QWheelEvent* event) {
  if (!m_table)
    return;
  const int delta = event->angleDelta().y() != 0 ? event->angleDelta().y() : event->angleDelta().x();
  if (delta == 0) { // a touchpad's phase event: no zoom either way
    event->accept();
    return;
  }
  const double anchor = frameAtX(event->position().x()); // the frame under the cursor stays there
  const double factor = delta > 0 ? 0.8 : 1.25;
  const double frames = m_table->frameCount();
  m_span = std::clamp(m_span * factor, 8.0, frames);
  m_first = std::clamp(anchor - (anchor - m_first) * factor, 0.0, std::max(0.0, frames - m_span));
  m_dirty = true;
  update();
  event->accept();
}

void ClusteringTableView::mousePressEvent(QMouseEvent* event) {
  if (event->button() == Qt::LeftButton) {
    m_dragging = true;
    m_dragFrom = event->pos();
    m_dragFirst = m_first;
  } else if (event->button() == Qt::RightButton) {
    resetZoom();
  }
}

void ClusteringTableView::mouseMoveEvent(QMouseEvent* event) {
  if (m_dragging && m_table) {
    const double perPixel = m_span / plotRect().width();
    const double frames = m_table->frameCount();
    m_first = std::clamp(m_dragFirst - (event->pos().x() - m_dragFrom.x()) * perPixel, 0.0, std::max(0.0, frames - m_span));
    m_dirty = true;
    update();
    return;
  }
  if (const std::optional<Entry> entry = entryAt(event->pos())) {
    const QString text = tr("t = %1, t_ref = %2\nE = %3 cm·° (T = %4)%5")
                             .arg(entry->t)
                             .arg(entry->ref)
                             .arg(entry->error, 0, 'f', 2)
                             .arg(m_threshold)
                             .arg(entry->inBand ? tr("\nin t_ref's run") : QString());
    QToolTip::showText(event->globalPosition().toPoint(), text, this);
    emit hovered(entry->t, entry->ref, entry->error);
  }
}

void ClusteringTableView::mouseReleaseEvent(QMouseEvent*) { m_dragging = false; }

void ClusteringTableView::resizeEvent(QResizeEvent*) { m_dirty = true; }

} // namespace mlod
