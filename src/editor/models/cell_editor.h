#pragma once
// Where an item delegate puts its editor: over the cell, and wide enough for the editor's own
// size hint where the column is narrower (a threshold spin box in a column sized for "5.00"
// showed "5.00 c" of "5.00 cm·°"), kept inside the view. The Skeleton and LOD Levels docks'
// delegates both place their editors with it.

class QStyleOptionViewItem;
class QWidget;

namespace mlod {

// Sets `editor`'s geometry: option.rect, widened to editor->sizeHint().width() when the cell is
// narrower, moved left as far as needed (never past the parent's left edge) to stay inside
// the editor's parent (the view's viewport).
void placeCellEditor(QWidget* editor, const QStyleOptionViewItem& option);

} // namespace mlod
