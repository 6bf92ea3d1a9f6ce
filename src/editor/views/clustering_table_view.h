#pragma once
// The paper's Figure 5: the selected joint's clustering table E_j(t, t_ref) as a heat map,
// t across, t_ref down. Entries inside the band (the run [t_ref, row end] whose errors stay
// within T) are in full colour, the rest dimmed; clusters are outlined and key postures
// marked. Wheel zooms about the cursor, dragging pans, hovering shows t, t_ref and E.

#include "core/jpc/clustering_table.h"
#include "core/jpc/jpc_analysis.h"

#include <QImage>
#include <QWidget>

#include <memory>
#include <optional>

namespace mlod {

class ClusteringTableView : public QWidget {
  Q_OBJECT
public:
  explicit ClusteringTableView(QWidget* parent = nullptr);

  void setAnalysis(std::shared_ptr<const JpcAnalysis> analysis, int joint, int level);
  // Visible frames: [first, first + span) on both axes.
  double firstFrame() const { return m_first; }
  double visibleFrames() const { return m_span; }
  void resetZoom();
  // The table entry under a widget position, when it is inside the table.
  struct Entry {
    int t = 0, ref = 0;
    double error = 0.0;
    bool inBand = false;
  };
  std::optional<Entry> entryAt(QPoint position) const;
  bool hasTable() const { return m_table != nullptr; }
  // The largest E in view (cm·degrees): the top of the colour scale drawn beside the table.
  double scaleMaximum() const { return m_largest; }
  QImage renderedImage() const { return m_image; }

signals:
  void hovered(int frame, int reference, double error);

protected:
  void paintEvent(QPaintEvent*) override;
  void wheelEvent(QWheelEvent* event) override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void mouseReleaseEvent(QMouseEvent* event) override;
  void resizeEvent(QResizeEvent*) override;

private:
  QRect plotRect() const;
  void renderImage();
  void paintLegend(QPainter& painter, const QRect& plot) const;
  double frameAtX(double x) const;
  double frameAtY(double y) const;

  std::shared_ptr<const JpcAnalysis> m_analysis;
  int m_joint = -1;
  int m_level = 0;
  const JointTrack* m_track = nullptr;
  std::unique_ptr<ClusteringTable> m_table;
  double m_threshold = 0.0;
  double m_largest = 0.0;
  double m_first = 0.0, m_span = 1.0;
  QImage m_image;
  bool m_dirty = true;
  QPoint m_dragFrom;
  double m_dragFirst = 0.0;
  bool m_dragging = false;
};

} // namespace mlod
