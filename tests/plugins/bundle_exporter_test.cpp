// The bundle exporter plugin loaded through the plugin host: exports BCN_Epileptic and CMU
// 01_01, the runtime reads the file back into exactly the package's bundle, the manifest
// describes it; an unwritable output or a cancelled export leaves nothing behind.

#include "core/lod/lod_package.h"
#include "runtime/bundle.h"
#include "unit/package_fixtures.h"
#include "sdk/plugin_host.h"

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

Exporter* bundleExporter() {
  static PluginHost host;
  static bool loaded = false;
  if (!loaded) {
    host.load({MLOD_PLUGIN_DIR});
    loaded = true;
  }
  return host.exporter("bundle");
}

QStringList filesIn(const QString& dir) {
  return QDir(dir).entryList(QDir::Files | QDir::Hidden | QDir::NoDotAndDotDot);
}

void exportAndReadBack(const LodPackage& package) {
  Exporter* exporter = bundleExporter();
  ASSERT_NE(exporter, nullptr);
  EXPECT_EQ(exporter->suffixes(), QStringList{"mlodb"});
  QTemporaryDir dir;
  const QString path = dir.filePath("out.mlodb");
  double last = -1.0;
  ExportResult result = exporter->exportPackage(package, path, defaultExporterOptions(exporter->options()),
                                                ExportProgress([&](double f, const QString&) { last = f; }, {}));
  ASSERT_TRUE(result.ok) << result.message.toStdString();
  EXPECT_DOUBLE_EQ(last, 1.0);
  EXPECT_EQ(filesIn(dir.path()), QStringList({"out.mlodb", "out.mlodb.json"}));

  std::string error;
  std::optional<Bundle> read = readBundleFile(path.toStdString(), &error);
  ASSERT_TRUE(read) << error;
  Result<Bundle> expected = packageBundle(package);
  ASSERT_TRUE(expected);
  EXPECT_EQ(writeBundle(*read), writeBundle(*expected)); // exactly the package's bundle
  for (const BundleLevel& level : read->levels)
    EXPECT_TRUE(buildBundleLevel(level, &error)) << error;

  QFile manifestFile(path + ".json");
  ASSERT_TRUE(manifestFile.open(QIODevice::ReadOnly));
  const QJsonObject manifest = QJsonDocument::fromJson(manifestFile.readAll()).object();
  EXPECT_EQ(manifest["format"].toString(), "motionlod-bundle");
  EXPECT_EQ(manifest["version"].toInt(), 2);
  EXPECT_EQ(manifest["bytes"].toInteger(), QFileInfo(path).size());
  const QJsonArray levels = manifest["levels"].toArray();
  ASSERT_EQ(levels.size(), qsizetype(package.levels.size()));
  for (qsizetype l = 0; l < levels.size(); ++l) {
    const LodPackageLevel& level = package.levels[std::size_t(l)];
    EXPECT_EQ(levels[l]["joints"].toInt(), level.skeleton().jointCount());
    const QJsonArray clips = levels[l]["clips"].toArray();
    ASSERT_EQ(clips.size(), qsizetype(level.runtimeClips.size()));
    for (qsizetype c = 0; c < clips.size(); ++c) {
      const LodClip& clip = read->levels[std::size_t(l)].clips[std::size_t(c)].clip;
      EXPECT_EQ(clips[c]["bytes"].toInteger(), qint64(clip.byteSize()));
      EXPECT_EQ(clips[c]["blend_frames"].toInt(), kDefaultBundleBlendFrames);
      EXPECT_EQ(clips[c]["clusters"].toInt(), clip.clusterCount());
    }
    EXPECT_EQ(levels[l]["mesh"].toObject()["triangles"].toInt(), level.mesh() ? int(level.mesh()->triangleCount()) : 0);
  }
}

TEST(BundleExporter, BcnEpilepticReadsBack) { exportAndReadBack(test::realPackage("X/BCN_Epileptic.X", 100.0)); }

TEST(BundleExporter, Cmu0101ReadsBack) { exportAndReadBack(test::realPackage("BVH/01_01.bvh", 2.54 / 0.45)); }

TEST(BundleExporter, OptionsDropMeshesAndManifest) {
  Exporter* exporter = bundleExporter();
  ASSERT_NE(exporter, nullptr);
  QTemporaryDir dir;
  QVariantMap options;
  QString error;
  ASSERT_TRUE(parseExporterOptions(exporter->options(), {"manifest=false", "meshes=false"}, &options, &error));
  const QString path = dir.filePath("motion.mlodb");
  ExportResult result = exporter->exportPackage(test::realPackage("X/BCN_Epileptic.X", 100.0), path, options, {});
  ASSERT_TRUE(result.ok) << result.message.toStdString();
  EXPECT_EQ(filesIn(dir.path()), QStringList({"motion.mlodb"}));
  std::string readError;
  std::optional<Bundle> read = readBundleFile(path.toStdString(), &readError);
  ASSERT_TRUE(read) << readError;
  for (const BundleLevel& level : read->levels)
    EXPECT_FALSE(level.mesh);
}

// blend_frames and precision_cm reach the clips: the engine plays them with that N, and a
// coarser precision takes fewer bytes.
TEST(BundleExporter, BlendFramesAndPrecisionReachTheClips) {
  Exporter* exporter = bundleExporter();
  ASSERT_NE(exporter, nullptr);
  const LodPackage& package = test::realPackage("X/BCN_Epileptic.X", 100.0);
  QTemporaryDir dir;
  std::vector<std::size_t> bytes;
  for (const QStringList& given : {QStringList{}, QStringList{"blend_frames=0", "precision_cm=0.1"}}) {
    QVariantMap options;
    QString error;
    ASSERT_TRUE(parseExporterOptions(exporter->options(), given, &options, &error)) << error.toStdString();
    const QString path = dir.filePath(QStringLiteral("b%1.mlodb").arg(bytes.size()));
    ExportResult result = exporter->exportPackage(package, path, options, {});
    ASSERT_TRUE(result.ok) << result.message.toStdString();
    std::string readError;
    std::optional<Bundle> read = readBundleFile(path.toStdString(), &readError);
    ASSERT_TRUE(read) << readError;
    std::size_t total = 0;
    for (const BundleLevel& level : read->levels)
      for (const BundleClip& clip : level.clips) {
        EXPECT_EQ(clip.clip.blendFrames(), given.isEmpty() ? kDefaultBundleBlendFrames : 0);
        EXPECT_DOUBLE_EQ(clip.clip.precisionCm(), given.isEmpty() ? kDefaultClipPrecisionCm : 0.1);
        EXPECT_LE(clip.clip.encodedErrorCm(), clip.clip.precisionCm());
        total += clip.clip.byteSize();
      }
    bytes.push_back(total);
  }
  EXPECT_LT(bytes[1], bytes[0]);
  QVariantMap bad;
  QString error;
  EXPECT_FALSE(parseExporterOptions(exporter->options(), {"blend_frames=-1"}, &bad, &error));
}

TEST(BundleExporter, UnwritableOutputLeavesNothingAndSaysWhy) {
  Exporter* exporter = bundleExporter();
  ASSERT_NE(exporter, nullptr);
  QTemporaryDir dir;
  const QString path = dir.filePath("missing/folder/out.mlodb");
  ExportResult result = exporter->exportPackage(test::realPackage("BVH/01_01.bvh", 2.54 / 0.45), path,
                                                defaultExporterOptions(exporter->options()), {});
  EXPECT_FALSE(result.ok);
  EXPECT_TRUE(result.message.contains("missing/folder/out.mlodb")) << result.message.toStdString();
  EXPECT_TRUE(filesIn(dir.path()).isEmpty());
}

TEST(BundleExporter, CancelLeavesNothing) {
  Exporter* exporter = bundleExporter();
  ASSERT_NE(exporter, nullptr);
  for (int cancelAt : {1, 2, 3}) {
    QTemporaryDir dir;
    int steps = 0;
    ExportResult result =
        exporter->exportPackage(test::realPackage("BVH/01_01.bvh", 2.54 / 0.45), dir.filePath("out.mlodb"),
                                defaultExporterOptions(exporter->options()),
                                ExportProgress([&](double, const QString&) { ++steps; }, [&] { return steps >= cancelAt; }));
    EXPECT_FALSE(result.ok) << cancelAt;
    EXPECT_TRUE(result.message.startsWith("cancelled")) << result.message.toStdString();
    EXPECT_TRUE(filesIn(dir.path()).isEmpty()) << cancelAt;
  }
}

} // namespace
} // namespace mlod
