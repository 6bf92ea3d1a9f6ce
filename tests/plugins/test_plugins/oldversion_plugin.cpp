// Test plugin "testoldversion" (tests/plugins/CMakeLists.txt says how it is built).
#include "test_exporter.h"

class TestOldversionPlugin : public QObject, public mlod::test::SummaryExporter {
  Q_OBJECT
  Q_PLUGIN_METADATA(IID "org.motionlod.Exporter/1" FILE "testoldversion_metadata.json")
  Q_INTERFACES(mlod::Exporter)
};

#include "oldversion_plugin.moc"
