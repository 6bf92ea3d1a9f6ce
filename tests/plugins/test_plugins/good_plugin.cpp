// Test plugin "testgood" (tests/plugins/CMakeLists.txt says how it is built).
#include "test_exporter.h"

class TestGoodPlugin : public QObject, public mlod::test::SummaryExporter {
  Q_OBJECT
  Q_PLUGIN_METADATA(IID "org.motionlod.Exporter/1" FILE "testgood_metadata.json")
  Q_INTERFACES(mlod::Exporter)
};

#include "good_plugin.moc"
