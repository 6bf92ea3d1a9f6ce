// The plugin host on deliberately built plugins: a good one, one with a missing symbol, one
// with another IID, one built for an old interface version, a static one, a file that is
// no plugin at all, and a duplicate id.

#include "sdk/plugin_host.h"
#include "sdk/plugin_paths.h"

#include <QCoreApplication>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QTemporaryDir>
#include <QtPlugin>

#include <gtest/gtest.h>

Q_IMPORT_PLUGIN(TestStaticPlugin)

namespace mlod {
namespace {

const PluginFailure* failureFor(const PluginHost& host, const QString& fileName) {
  for (const PluginFailure& failure : host.failures())
    if (QFileInfo(failure.file).fileName() == fileName)
      return &failure;
  return nullptr;
}

QString library(const QString& id) {
  return QStringLiteral("libmotionlod_%1.so").arg(id);
}

TEST(PluginHost, LoadsTheGoodAndReportsEveryFailure) {
  PluginHost host;
  host.load({MLOD_TEST_PLUGIN_DIR});
  QStringList ids;
  for (const PluginInfo& info : host.plugins())
    ids << info.id;
  EXPECT_EQ(ids, QStringList({"teststatic", "testgood"}));
  Exporter* good = host.exporter("testgood");
  ASSERT_NE(good, nullptr);
  EXPECT_EQ(good->name(), "Test summary");
  EXPECT_EQ(good->suffixes(), QStringList({"txt", "text"}));
  EXPECT_EQ(host.plugins()[1].version, "2.5.0");
  EXPECT_EQ(host.plugins()[0].file, ":static");

  ASSERT_EQ(host.failures().size(), 3) << [&] {
    std::string all;
    for (const PluginFailure& f : host.failures())
      all += f.file.toStdString() + ": " + f.reason.toStdString() + "\n";
    return all;
  }();
  const PluginFailure* broken = failureFor(host, library("testbroken"));
  ASSERT_NE(broken, nullptr);
  EXPECT_TRUE(broken->reason.startsWith("cannot load")) << broken->reason.toStdString();
  EXPECT_TRUE(broken->reason.contains("mlod_test_symbol_that_does_not_exist")) << broken->reason.toStdString();
  const PluginFailure* wrongIid = failureFor(host, library("testwrongiid"));
  ASSERT_NE(wrongIid, nullptr);
  EXPECT_TRUE(wrongIid->reason.contains("not an exporter plugin (IID 'org.example.NotAnExporter/1'"))
      << wrongIid->reason.toStdString();
  const PluginFailure* old = failureFor(host, library("testoldversion"));
  ASSERT_NE(old, nullptr);
  EXPECT_TRUE(old->reason.contains("old interface version 0; this host needs 1")) << old->reason.toStdString();
  EXPECT_EQ(host.exporter("testbroken"), nullptr);
  EXPECT_EQ(host.exporter("testoldversion"), nullptr);
  EXPECT_EQ(host.exporter("nosuch"), nullptr);
}

TEST(PluginHost, NotAPluginAndDuplicateIdsAreReported) {
  QTemporaryDir first, second;
  ASSERT_TRUE(first.isValid() && second.isValid());
  const QString good = QDir(MLOD_TEST_PLUGIN_DIR).filePath(library("testgood"));
  ASSERT_TRUE(QFile::copy(good, first.filePath(library("testgood"))));
  ASSERT_TRUE(QFile::copy(good, second.filePath("libmotionlod_copy.so")));
  QFile garbage(second.filePath("libgarbage.so"));
  ASSERT_TRUE(garbage.open(QIODevice::WriteOnly));
  garbage.write("this is no ELF file");
  garbage.close();
  QFile text(second.filePath("README.txt")); // not a library name: not tried at all
  ASSERT_TRUE(text.open(QIODevice::WriteOnly));
  text.close();

  PluginHost host;
  host.load({first.path(), second.path(), first.filePath("missing-folder")});
  ASSERT_NE(host.exporter("testgood"), nullptr);
  EXPECT_EQ(QFileInfo(host.plugins().last().file).dir().path(), QFileInfo(first.path()).absoluteFilePath());
  ASSERT_EQ(host.failures().size(), 2);
  const PluginFailure* duplicate = failureFor(host, "libmotionlod_copy.so");
  ASSERT_NE(duplicate, nullptr);
  EXPECT_TRUE(duplicate->reason.contains("duplicate id 'testgood'")) << duplicate->reason.toStdString();
  const PluginFailure* notPlugin = failureFor(host, "libgarbage.so");
  ASSERT_NE(notPlugin, nullptr);
  EXPECT_TRUE(notPlugin->reason.startsWith("not a Qt plugin")) << notPlugin->reason.toStdString();
}

TEST(PluginHost, SearchPathPutsTheEnvironmentFirst) {
  qputenv("MOTIONLOD_PLUGIN_PATH", "/tmp/a:/tmp/b");
  const QStringList paths = pluginSearchPaths("/opt/motionlod/bin");
  qunsetenv("MOTIONLOD_PLUGIN_PATH");
  ASSERT_EQ(paths.size(), 3);
  EXPECT_EQ(paths[0], "/tmp/a");
  EXPECT_EQ(paths[1], "/tmp/b");
  EXPECT_TRUE(paths[2].startsWith("/opt/motionlod/lib")) << paths[2].toStdString();
  EXPECT_TRUE(paths[2].endsWith("/motionlod/plugins")) << paths[2].toStdString();
}

} // namespace
} // namespace mlod
