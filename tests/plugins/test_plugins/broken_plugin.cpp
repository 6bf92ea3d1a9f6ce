// Test plugin "testbroken" (tests/plugins/CMakeLists.txt says how it is built).
#include "test_exporter.h"

// Defined nowhere: the dynamic linker refuses the plugin at load time.
extern "C" int mlod_test_symbol_that_does_not_exist;
class TestBrokenPlugin : public QObject, public mlod::test::SummaryExporter {
  Q_OBJECT
  Q_PLUGIN_METADATA(IID "org.motionlod.Exporter/1" FILE "testbroken_metadata.json")
  Q_INTERFACES(mlod::Exporter)
public:
  QString version() const override { return QString::number(mlod_test_symbol_that_does_not_exist); }
};

#include "broken_plugin.moc"
