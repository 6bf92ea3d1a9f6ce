#pragma once
// The joint-mapping table of a motion assigned to a character, editable in place (a combo
// box of the motion's joints per character joint), every edit one undo step; "Automatic"
// puts the name-matched table back (one step too). Displays and forwards intents only.

#include <QDialog>

class QTableView;

namespace mlod {

class Document;
class MappingModel;

class MappingDialog : public QDialog {
  Q_OBJECT
public:
  MappingDialog(Document* document, int mapping, QWidget* parent = nullptr);
  QTableView* table() const { return m_table; }
  MappingModel* model() const { return m_model; }

private:
  Document* m_document;
  MappingModel* m_model;
  QTableView* m_table;
};

} // namespace mlod
