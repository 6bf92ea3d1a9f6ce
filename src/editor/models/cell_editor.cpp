#include "editor/models/cell_editor.h"

#include <QStyleOptionViewItem>
#include <QWidget>

#include <algorithm>

namespace mlod {

void placeCellEditor(QWidget* editor, const QStyleOptionViewItem& option) {
  QRect rect = option.rect;
  const int wanted = editor->sizeHint().width();
  if (rect.width() < wanted) {
    rect.setWidth(wanted);
    if (const QWidget* parent = editor->parentWidget(); parent && rect.right() >= parent->width())
      rect.moveRight(parent->width() - 1);
    if (rect.left() < 0)
      rect.moveLeft(0);
  }
  editor->setGeometry(rect);
}

} // namespace mlod
