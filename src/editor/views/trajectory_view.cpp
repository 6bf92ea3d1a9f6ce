#include "editor/views/trajectory_view.h"

#include <QMouseEvent>
#include <QPainter>

#include <cmath>
#include <numbers>

namespace mlod {

TrajectoryView::TrajectoryView(QWidget* parent) : QWidget(parent) {
  setMinimumSize(200, 200);
  setToolTip(tr("Trajectory (Figure 6): the joint's direction to its child on the unit sphere, per frame, coloured by "
                "cluster; drag to rotate"));
}

void TrajectoryView::setAnalysis(std::shared_ptr<const JpcAnalysis> analysis, int joint, int level) {
  m_analysis = std::move(analysis);
  m_joint = joint;
  m_level = level;
  update();
}

void TrajectoryView::paintEvent(QPaintEvent*) {
  QPainter painter(this);
  painter.setRenderHint(QPainter::Antialiasing);
  painter.fillRect(rect(), palette().color(QPalette::Base));
  m_points = 0;
  const bool valid = m_analysis && m_joint >= 0 && m_joint < m_analysis->prepared->jointCount() &&
                     m_level < m_analysis->levelCount() && m_analysis->prepared->clusterable(m_joint) &&
                     !m_analysis->prepared->locked(m_joint) && m_analysis->prepared->track(m_joint).directionCount() > 0;
  const double radius = std::min(width(), height()) * 0.42;
  const QPointF centre(width() / 2.0, height() / 2.0);
  painter.setPen(QPen(palette().color(QPalette::Mid), 1.0));
  painter.drawEllipse(centre, radius, radius);
  if (!valid) {
    painter.setPen(palette().color(QPalette::Text));
    painter.drawText(rect().adjusted(8, 8, -8, -8), Qt::AlignHCenter | Qt::AlignBottom | Qt::TextWordWrap,
                     tr("Select a clustered joint with a child to see its trajectory."));
    return;
  }
  const double yaw = m_yaw * std::numbers::pi / 180.0, pitch = m_pitch * std::numbers::pi / 180.0;
  // Orthographic view of the sphere after yaw about y, then pitch about x; z towards the viewer.
  const auto project = [&](const glm::dvec3& v, double& out_depth) {
    const double x1 = std::cos(yaw) * v.x + std::sin(yaw) * v.z;
    const double z1 = -std::sin(yaw) * v.x + std::cos(yaw) * v.z;
    const double y2 = std::cos(pitch) * v.y - std::sin(pitch) * z1;
    out_depth = std::sin(pitch) * v.y + std::cos(pitch) * z1;
    return QPointF(centre.x() + x1 * radius, centre.y() - y2 * radius);
  };
  // Equator and prime meridian, for orientation.
  painter.setPen(QPen(palette().color(QPalette::Midlight), 0.8, Qt::DashLine));
  for (int ring = 0; ring < 2; ++ring) {
    QPolygonF line;
    for (int i = 0; i <= 72; ++i) {
      const double a = i * 2.0 * std::numbers::pi / 72.0;
      double depth = 0.0;
      line << project(ring == 0 ? glm::dvec3(std::cos(a), 0, std::sin(a)) : glm::dvec3(std::cos(a), std::sin(a), 0), depth);
    }
    painter.drawPolyline(line);
  }
  const JointTrack& track = m_analysis->prepared->track(m_joint);
  const ClusterSet& clusters = m_analysis->levels[static_cast<std::size_t>(m_level)].clusters;
  const int frames = track.frameCount();
  QPointF previous;
  for (int t = 0; t < frames; ++t) {
    double depth = 0.0;
    const glm::dvec3 v = glm::normalize(track.directions(t)[0]);
    const QPointF p = project(v, depth);
    const int cluster = clusters.clusterAt(m_joint, t);
    QColor colour = cluster < 0 ? QColor(150, 150, 150) : QColor::fromHsv((cluster * 47) % 360, 220, 230);
    if (depth < 0)
      colour = colour.darker(170); // the far side of the sphere
    if (t > 0) {
      painter.setPen(QPen(colour, 2.0));
      painter.drawLine(previous, p);
    }
    previous = p;
    ++m_points;
  }
  painter.setPen(QPen(Qt::black, 1.0));
  for (const Cluster& cluster : clusters.joints[static_cast<std::size_t>(m_joint)]) {
    double depth = 0.0;
    const QPointF p = project(glm::normalize(track.directions(cluster.key)[0]), depth);
    painter.setBrush(QColor::fromHsv((clusters.clusterAt(m_joint, cluster.key) * 47) % 360, 220, 255));
    painter.drawEllipse(p, 4.5, 4.5);
  }
  painter.setPen(palette().color(QPalette::Text));
  painter.drawText(rect().adjusted(6, 4, -6, -4), Qt::AlignLeft | Qt::AlignTop,
                   tr("%1 · %2 frames · %3 clusters").arg(QString::fromStdString(m_analysis->prepared->jointName(m_joint))).arg(frames)
                       .arg(clusters.joints[static_cast<std::size_t>(m_joint)].size()));
}

void TrajectoryView::mousePressEvent(QMouseEvent* event) { m_last = event->pos(); }

void TrajectoryView::mouseMoveEvent(QMouseEvent* event) {
  if (!(event->buttons() & Qt::LeftButton))
    return;
  const QPoint delta = event->pos() - m_last;
  m_last = event->pos();
  m_yaw += delta.x() * 0.5;
  m_pitch = std::clamp(m_pitch + delta.y() * 0.5, -89.0, 89.0);
  update();
}

} // namespace mlod
