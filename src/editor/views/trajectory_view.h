#pragma once
// The paper's Figure 6: the selected joint's child direction v'_j(t) (eq. 2) over the clip,
// a path on the unit sphere, each frame coloured by its cluster at the current level (grey:
// not clustered), key postures as large dots. Dragging rotates the sphere.

#include "core/jpc/jpc_analysis.h"

#include <QWidget>

#include <memory>

namespace mlod {

class TrajectoryView : public QWidget {
  Q_OBJECT
public:
  explicit TrajectoryView(QWidget* parent = nullptr);
  void setAnalysis(std::shared_ptr<const JpcAnalysis> analysis, int joint, int level);
  double yaw() const { return m_yaw; }
  double pitch() const { return m_pitch; }
  int pointCount() const { return m_points; }

protected:
  void paintEvent(QPaintEvent*) override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;

private:
  std::shared_ptr<const JpcAnalysis> m_analysis;
  int m_joint = -1;
  int m_level = 0;
  int m_points = 0;
  double m_yaw = 30.0, m_pitch = 20.0; // degrees
  QPoint m_last;
};

} // namespace mlod
