// The example exporter as the host loads it: metadata, options, the summary of a real
// package (figures equal to the package's), compact output, cancel and an unwritable
// path leaving nothing behind.

#include "core/lod/lod_package.h"
#include "io/import_options.h"
#include "io/importer.h"
#include "sdk/exporter.h"
#include "sdk/plugin_host.h"

#include <QCoreApplication>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QTemporaryDir>

#include <gtest/gtest.h>

namespace mlod {
namespace {

// One package of the sample clip (CMU units), built once: the default LOD set of a file.
const LodPackage& samplePackage() {
  static const LodPackage package = [] {
    ImportOptions options;
    options.unitScale = *parseUnitScale("cmu");
    Result<Asset> asset = importAsset(MLOD_SAMPLE, options);
    EXPECT_TRUE(asset.ok()) << (asset.ok() ? "" : asset.message());
    Result<LodPackage> built = buildLodPackage(*asset);
    EXPECT_TRUE(built.ok()) << (built.ok() ? "" : built.message());
    return *built;
  }();
  return package;
}

class ExampleExporterTest : public ::testing::Test {
protected:
  void SetUp() override {
    m_host.load({QFileInfo(MLOD_PLUGIN_FILE).absolutePath()});
    m_exporter = m_host.exporter("example");
    ASSERT_NE(m_exporter, nullptr) << "the example plugin did not load from " << MLOD_PLUGIN_FILE;
    ASSERT_TRUE(m_dir.isValid());
  }
  QJsonObject exportAndRead(const QVariantMap& values, QByteArray* out_bytes = nullptr) {
    QVariantMap options;
    QString error;
    EXPECT_TRUE(checkExporterOptions(m_exporter->options(), values, &options, &error)) << error.toStdString();
    const QString path = m_dir.filePath("summary.json");
    const ExportResult result = m_exporter->exportPackage(samplePackage(), path, options, {});
    EXPECT_TRUE(result.ok) << result.message.toStdString();
    QFile file(path);
    EXPECT_TRUE(file.open(QIODevice::ReadOnly));
    const QByteArray bytes = file.readAll();
    if (out_bytes)
      *out_bytes = bytes;
    QJsonParseError parseError;
    const QJsonDocument document = QJsonDocument::fromJson(bytes, &parseError);
    EXPECT_EQ(parseError.error, QJsonParseError::NoError) << parseError.errorString().toStdString();
    return document.object();
  }

  PluginHost m_host;
  Exporter* m_exporter = nullptr;
  QTemporaryDir m_dir;
};

// The metadata the host read and what the plugin says agree.
TEST_F(ExampleExporterTest, DescribesItself) {
  EXPECT_EQ(m_exporter->id(), "example");
  EXPECT_EQ(m_exporter->suffixes(), QStringList{"json"});
  ASSERT_EQ(m_exporter->options().size(), 1);
  EXPECT_EQ(m_exporter->options()[0].key, "indent");
  EXPECT_EQ(defaultExporterOptions(m_exporter->options()).value("indent").toBool(), true);
  bool listed = false;
  for (const PluginInfo& info : m_host.plugins())
    listed = listed || (info.id == "example" && info.version == m_exporter->version());
  EXPECT_TRUE(listed);
}

// Every figure of the summary is the package's own: the exporter recomputes nothing.
TEST_F(ExampleExporterTest, SummaryHoldsThePackageFigures) {
  const LodPackage& package = samplePackage();
  ASSERT_GE(package.levels.size(), 2u);
  const QJsonObject summary = exportAndRead({});
  EXPECT_EQ(summary["format"].toString(), "motionlod-example-summary");
  EXPECT_EQ(summary["name"].toString().toStdString(), package.name);
  EXPECT_EQ(summary["joints"].toInt(), package.skeleton.jointCount());
  EXPECT_DOUBLE_EQ(summary["unit_scale"].toDouble(), package.unitScale);
  const QJsonArray clips = summary["clips"].toArray();
  ASSERT_EQ(clips.size(), qsizetype(package.clips.size()));
  EXPECT_EQ(clips[0].toObject()["frames"].toInt(), package.clips[0].frameCount);
  const QJsonArray levels = summary["levels"].toArray();
  ASSERT_EQ(levels.size(), qsizetype(package.levels.size()));
  for (qsizetype i = 0; i < levels.size(); ++i) {
    const QJsonObject level = levels[i].toObject();
    const LodPackageLevel& expected = package.levels[std::size_t(i)];
    EXPECT_EQ(level["index"].toInt(), expected.index);
    EXPECT_DOUBLE_EQ(level["motion_threshold"].toDouble(), expected.settings.motionThreshold);
    EXPECT_DOUBLE_EQ(level["switch_distance_cm"].toDouble(), expected.settings.switchDistanceCm);
    EXPECT_EQ(level["active_joints"].toInt(), expected.skeleton().jointCount());
    const QJsonArray levelClips = level["clips"].toArray();
    ASSERT_EQ(levelClips.size(), qsizetype(expected.metrics.size()));
    EXPECT_DOUBLE_EQ(levelClips[0].toObject()["simplified_joint_percent"].toDouble(),
                     expected.metrics[0].simplifiedPercent);
    EXPECT_EQ(levelClips[0].toObject()["clusters"].toInt(), expected.metrics[0].clusterCount);
  }
  // Level 0 is the original: nothing clustered.
  EXPECT_EQ(levels[0].toObject()["clips"].toArray()[0].toObject()["clusters"].toInt(), 0);
}

// indent=false writes one line; the content is the same.
TEST_F(ExampleExporterTest, CompactOptionWritesOneLine) {
  QByteArray indented;
  QByteArray compact;
  const QJsonObject a = exportAndRead({}, &indented);
  const QJsonObject b = exportAndRead({{"indent", "false"}}, &compact);
  EXPECT_EQ(a, b);
  EXPECT_FALSE(compact.contains('\n'));
  EXPECT_TRUE(indented.contains('\n'));
  EXPECT_LT(compact.size(), indented.size());
}

// A bad option value is refused before the exporter runs.
TEST_F(ExampleExporterTest, RefusesABadOption) {
  QVariantMap options;
  QString error;
  EXPECT_FALSE(parseExporterOptions(m_exporter->options(), {"indent=sometimes"}, &options, &error));
  EXPECT_TRUE(error.contains("indent")) << error.toStdString();
  EXPECT_FALSE(parseExporterOptions(m_exporter->options(), {"colour=red"}, &options, &error));
}

// Cancel during the levels: a cancelled result and no file.
TEST_F(ExampleExporterTest, CancelLeavesNothing) {
  const QString path = m_dir.filePath("cancelled.json");
  int reports = 0;
  const ExportProgress progress([&](double, const QString&) { ++reports; }, [&] { return reports >= 2; });
  const ExportResult result =
      m_exporter->exportPackage(samplePackage(), path, defaultExporterOptions(m_exporter->options()), progress);
  EXPECT_FALSE(result.ok);
  EXPECT_EQ(result.message, cancelledResult().message);
  EXPECT_FALSE(QFileInfo::exists(path));
}

// An output folder that does not exist: a failure that names the file, nothing written.
TEST_F(ExampleExporterTest, UnwritablePathFailsCleanly) {
  const QString path = m_dir.filePath("missing-folder/summary.json");
  const ExportResult result =
      m_exporter->exportPackage(samplePackage(), path, defaultExporterOptions(m_exporter->options()), {});
  EXPECT_FALSE(result.ok);
  EXPECT_TRUE(result.message.contains("summary.json")) << result.message.toStdString();
  EXPECT_TRUE(QDir(m_dir.path()).entryList(QDir::NoDotAndDotDot | QDir::AllEntries).isEmpty());
}

} // namespace
} // namespace mlod

int main(int argc, char** argv) {
  QCoreApplication app(argc, argv); // QPluginLoader wants an application object
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
