#pragma once
// Help > User Guide (F1): docs/user-guide.md, built into the editor's resources with its
// pictures, shown as rich text; links to other pages open in the system's browser.

#include <QDialog>

class QTextBrowser;

namespace mlod {

class HelpBrowser : public QDialog {
  Q_OBJECT
public:
  explicit HelpBrowser(QWidget* parent = nullptr);
  QTextBrowser* browser() const { return m_browser; }

private:
  QTextBrowser* m_browser;
};

} // namespace mlod
