#include "editor/views/mapping_dialog.h"

#include "editor/document/document.h"
#include "editor/document/edits.h"
#include "editor/models/mapping_model.h"

#include <QAction>
#include <QDialogButtonBox>
#include <QHeaderView>
#include <QLabel>
#include <QPushButton>
#include <QTableView>
#include <QVBoxLayout>

namespace mlod {

MappingDialog::MappingDialog(Document* document, int mapping, QWidget* parent)
    : QDialog(parent), m_document(document), m_model(new MappingModel(document, mapping, this)), m_table(new QTableView) {
  setObjectName("mappingDialog");
  const ProjectMapping& entry = document->project().mappings[static_cast<std::size_t>(mapping)];
  setWindowTitle(tr("Joint Mapping: %1 → %2")
                     .arg(QString::fromStdString(entry.mapping.motionName), QString::fromStdString(entry.mapping.characterName)));
  auto* layout = new QVBoxLayout(this);
  auto* note = new QLabel(tr("Which joint of the motion drives each joint of the character. Joints without one keep "
                             "their rest pose. Every change is one undo step (Ctrl+Z)."));
  note->setWordWrap(true);
  layout->addWidget(note);
  m_table->setObjectName("mappingTable");
  m_table->setModel(m_model);
  m_table->setItemDelegate(new MappingDelegate(m_table));
  m_table->setSelectionBehavior(QAbstractItemView::SelectRows);
  m_table->setSelectionMode(QAbstractItemView::SingleSelection);
  m_table->setEditTriggers(QAbstractItemView::DoubleClicked | QAbstractItemView::EditKeyPressed |
                           QAbstractItemView::SelectedClicked);
  m_table->verticalHeader()->hide();
  m_table->horizontalHeader()->setStretchLastSection(true);
  m_table->setColumnWidth(MappingModel::CharacterColumn, 220);
  layout->addWidget(m_table);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Close);
  QPushButton* automatic = buttons->addButton(tr("&Automatic"), QDialogButtonBox::ResetRole);
  automatic->setObjectName("automaticMappingButton");
  automatic->setToolTip(tr("Match the joints by name again (rig conventions), replacing the edits (one undo step)"));
  connect(automatic, &QPushButton::clicked, this, [this] { edit::resetMapping(*m_document, m_model->mapping()); });
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  layout->addWidget(buttons);
  // The document's undo and redo work here too (a dialog is its own window for shortcuts).
  QAction* undo = document->undoStack()->createUndoAction(this);
  undo->setShortcut(QKeySequence::Undo);
  QAction* redo = document->undoStack()->createRedoAction(this);
  redo->setShortcut(QKeySequence::Redo);
  addAction(undo);
  addAction(redo);
  // The mapping can go (undo of the assignment, asset removed): nothing left to edit.
  connect(document, &Document::mappingsChanged, this, [this] {
    if (m_model->mapping() >= static_cast<int>(m_document->project().mappings.size()))
      close();
  });
  resize(520, 600);
}

} // namespace mlod
