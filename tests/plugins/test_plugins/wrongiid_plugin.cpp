// Test plugin "testwrongiid" (tests/plugins/CMakeLists.txt says how it is built).
#include "test_exporter.h"

class TestWrongiidPlugin : public QObject, public mlod::test::SummaryExporter {
  Q_OBJECT
  Q_PLUGIN_METADATA(IID "org.example.NotAnExporter/1" FILE "testwrongiid_metadata.json")
  Q_INTERFACES(mlod::Exporter)
};

#include "wrongiid_plugin.moc"
