#pragma once
// Edit > Generate Levels from Pixel Budget… (Ctrl+Shift+G; docs/architecture.md sections 5
// and 7): one dialog for the budget — pixel error, number of levels, projection (vertical
// field of view, viewport height), where the character is skinned (GPU or CPU: the motion's
// share of each level's deviation) — with a live preview of the levels it will make: E,
// mesh ratio, switch distance (m), simplified %, triangles, joints, the levels the rules
// left out and the per-joint overrides above a generated level's E. Every change of a value
// re-runs the generator (LevelGenerator::preview(), core's LodSet::fromPixelBudget) in the
// background after a short pause, behind a JobProgress (percent, Cancel; shown only after
// 300 ms). Apply lands exactly the previewed set as one undo step; Cancel (or closing)
// leaves the project as it was. The dialog computes nothing itself.

#include "core/lod/error_budget.h"
#include "core/lod/lod_set.h"

#include <QDialog>
#include <QTimer>

class QComboBox;
class QDialogButtonBox;
class QDoubleSpinBox;
class QLabel;
class QListWidget;
class QPushButton;
class QSpinBox;
class QTableWidget;

namespace mlod {

class JobProgress;
class LevelGenerator;

struct BudgetRequest {
  double pixels = 1.0; // > 0
  int levels = 4;      // >= 1, the original included
  LodProjection projection;
  LodSkinning skinning = LodSkinning::Gpu; // where the character is skinned (LodBudgetOptions::skinning)
  QString character; // the file name of the asset whose set the levels replace (named above the form)
};

class BudgetDialog : public QDialog {
  Q_OBJECT
public:
  enum Column {
    LevelColumn,
    ThresholdColumn,
    RatioColumn,
    DistanceColumn,
    SimplifiedColumn,
    TrianglesColumn,
    JointsColumn,
    ColumnCount
  };
  static constexpr int kSettleMs = 400; // a value rests this long before the preview re-runs

  BudgetDialog(LevelGenerator* generator, const BudgetRequest& initial, QWidget* parent = nullptr);
  ~BudgetDialog() override;

  BudgetRequest request() const;
  void setRequest(const BudgetRequest& request); // sets the fields; the preview follows

  // True once the preview shows the current values' levels (Apply is enabled).
  bool isPreviewCurrent() const { return m_current; }
  QTableWidget* table() const { return m_table; }
  QListWidget* overridesList() const { return m_overrides; }
  QLabel* notesLabel() const { return m_notes; }
  QLabel* statusLabel() const { return m_status; }
  QLabel* characterLabel() const { return m_character; } // "Levels of BCN_Epileptic.X"
  JobProgress* progress() const { return m_progress; }
  QPushButton* applyButton() const { return m_apply; }
  QPushButton* previewButton() const { return m_previewButton; }

  void reject() override; // cancels a running preview; the project stays as it was

signals:
  void previewShown(); // the table holds a fresh preview

private:
  void valuesChanged();
  void runPreview();
  void onPreviewed(bool ok, const QString& message);
  void showPlan();
  void applyPlan();

  LevelGenerator* m_generator;
  QDoubleSpinBox* m_pixels;
  QSpinBox* m_levels;
  QDoubleSpinBox* m_fov;
  QSpinBox* m_height;
  QComboBox* m_skinning;
  QTableWidget* m_table;
  QLabel* m_character;
  QLabel* m_notes;
  QLabel* m_overridesTitle;
  QListWidget* m_overrides;
  QLabel* m_status;
  QPushButton* m_previewButton;
  QPushButton* m_apply;
  QDialogButtonBox* m_buttons;
  JobProgress* m_progress;
  QTimer m_settle;
  bool m_current = false;    // the table shows the fields' values
  bool m_previewing = false; // our preview runs in the generator
};

} // namespace mlod
