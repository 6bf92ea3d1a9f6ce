#include "editor/views/help_browser.h"

#include <QDialogButtonBox>
#include <QTextBrowser>
#include <QVBoxLayout>

// The guide lives in the editor library's resources (resources/help/help.qrc); a static
// library registers them explicitly.
static void initHelpResources() {
  Q_INIT_RESOURCE(help);
}

namespace mlod {

HelpBrowser::HelpBrowser(QWidget* parent) : QDialog(parent), m_browser(new QTextBrowser(this)) {
  initHelpResources();
  setObjectName("helpBrowser");
  setWindowTitle(tr("Motion LOD Studio — User Guide"));
  resize(900, 760);
  m_browser->setObjectName("helpText");
  m_browser->setOpenLinks(true);
  m_browser->setOpenExternalLinks(true); // http(s) pages go to the system's browser
  m_browser->setSource(QUrl(QStringLiteral("qrc:/help/user-guide.md")), QTextDocument::MarkdownResource);
  auto* layout = new QVBoxLayout(this);
  layout->addWidget(m_browser);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Close, this);
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::close);
  layout->addWidget(buttons);
}

} // namespace mlod
