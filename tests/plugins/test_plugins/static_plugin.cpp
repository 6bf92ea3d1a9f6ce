// Test plugin "teststatic" (tests/plugins/CMakeLists.txt says how it is built).
#include "test_exporter.h"

class TestStaticPlugin : public QObject, public mlod::test::SummaryExporter {
  Q_OBJECT
  Q_PLUGIN_METADATA(IID "org.motionlod.Exporter/1" FILE "teststatic_metadata.json")
  Q_INTERFACES(mlod::Exporter)
};

#include "static_plugin.moc"
