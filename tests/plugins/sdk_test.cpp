// The exporter SDK without a plugin: options as data, key=value parsing, atomic writes.

#include "sdk/exporter.h"

#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QTemporaryDir>

#include <gtest/gtest.h>
#include <cstdlib>
#include <vector>
#include <thread>
#include <atomic>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

namespace mlod {
namespace {

ExporterOptions sampleOptions() {
  ExporterOptions options;
  options.append({"binary", ExporterOption::Bool, true, {}, {}, {}, "Write .glb"});
  options.append({"levels", ExporterOption::Int, 4, 1, 8, {}, "How many"});
  options.append({"scale", ExporterOption::Double, 0.01, 1e-6, 1e6, {}, "Metres per cm"});
  options.append({"title", ExporterOption::String, QString("LODs"), {}, {}, {}, "A title"});
  options.append({"format", ExporterOption::Choice, QString("html"), {}, {}, {"html", "csv", "json"}, "Which"});
  return options;
}

TEST(ExporterOptions, DefaultsFillWhatIsNotGiven) {
  QVariantMap values;
  QString error;
  ASSERT_TRUE(parseExporterOptions(sampleOptions(), {"levels=3", "format=csv"}, &values, &error)) << error.toStdString();
  EXPECT_EQ(values.size(), 5);
  EXPECT_EQ(values["binary"].toBool(), true);
  EXPECT_EQ(values["levels"].typeId(), QMetaType::Int);
  EXPECT_EQ(values["levels"].toInt(), 3);
  EXPECT_EQ(values["format"].toString(), "csv");
  EXPECT_DOUBLE_EQ(values["scale"].toDouble(), 0.01);
}

TEST(ExporterOptions, TypesConvertFromText) {
  QVariantMap values;
  QString error;
  ASSERT_TRUE(parseExporterOptions(sampleOptions(), {"binary=no", "scale=2.5", "title=a=b"}, &values, &error));
  EXPECT_EQ(values["binary"].toBool(), false);
  EXPECT_EQ(values["binary"].typeId(), QMetaType::Bool);
  EXPECT_DOUBLE_EQ(values["scale"].toDouble(), 2.5);
  EXPECT_EQ(values["title"].toString(), "a=b"); // only the first '=' splits
}

TEST(ExporterOptions, BadValuesAreRefusedWithTheOptionNamed) {
  const ExporterOptions options = sampleOptions();
  const struct {
    QString entry;
    QString expected;
  } cases[] = {
      {"nosuch=1", "unknown option 'nosuch'"}, {"levels=9", "out of range"}, {"levels=2.5", "not an integer"},
      {"scale=nan", "not a finite number"},    {"binary=maybe", "not a bool"}, {"format=pdf", "not one of html, csv, json"},
      {"levels", "not key=value"},             {"=3", "not key=value"},
  };
  for (const auto& c : cases) {
    QString error;
    QVariantMap values;
    EXPECT_FALSE(parseExporterOptions(options, {c.entry}, &values, &error)) << c.entry.toStdString();
    EXPECT_TRUE(error.contains(c.expected)) << c.entry.toStdString() << ": " << error.toStdString();
  }
  QString error;
  EXPECT_FALSE(parseExporterOptions(options, {"levels=2", "levels=3"}, nullptr, &error));
  EXPECT_TRUE(error.contains("twice"));
}

TEST(ExporterOptions, CheckTakesTypedValues) {
  QVariantMap values;
  QString error;
  ASSERT_TRUE(checkExporterOptions(sampleOptions(), {{"levels", 2}, {"binary", false}}, &values, &error));
  EXPECT_EQ(values["levels"].toInt(), 2);
  EXPECT_FALSE(checkExporterOptions(sampleOptions(), {{"levels", 0}}, &values, &error));
}

TEST(AtomicWrite, WritesAndReplaces) {
  QTemporaryDir dir;
  ASSERT_TRUE(dir.isValid());
  const QString path = dir.filePath("out.bin");
  ASSERT_TRUE(writeFileAtomically(path, "first").ok);
  ExportResult second = writeFileAtomically(path, "second");
  ASSERT_TRUE(second.ok) << second.message.toStdString();
  QFile file(path);
  ASSERT_TRUE(file.open(QIODevice::ReadOnly));
  EXPECT_EQ(file.readAll(), QByteArray("second"));
  EXPECT_EQ(QDir(dir.path()).entryList(QDir::Files | QDir::Hidden).size(), 1); // no temporary left
}

TEST(AtomicWrite, UnwritableFolderLeavesNothingAndSaysWhy) {
  QTemporaryDir dir;
  const QString missing = dir.filePath("no/such/folder/out.bin");
  ExportResult result = writeFileAtomically(missing, "data");
  EXPECT_FALSE(result.ok);
  EXPECT_TRUE(result.message.contains(missing)) << result.message.toStdString();
  EXPECT_FALSE(QFileInfo::exists(missing));

  ExportResult pair = writeFilesAtomically({{dir.filePath("a.bin"), "a"}, {missing, "b"}});
  EXPECT_FALSE(pair.ok);
  EXPECT_FALSE(QFileInfo::exists(dir.filePath("a.bin"))) << "the first file of a failed set must not stay";
  EXPECT_EQ(QDir(dir.path()).entryList(QDir::Files | QDir::Hidden).size(), 0);
}

TEST(AtomicWrite, SetOfFilesLandsTogether) {
  QTemporaryDir dir;
  ExportResult result = writeFilesAtomically({{dir.filePath("x.mlodb"), "xx"}, {dir.filePath("x.mlodb.json"), "{}"}});
  ASSERT_TRUE(result.ok) << result.message.toStdString();
  EXPECT_EQ(QFileInfo(dir.filePath("x.mlodb")).size(), 2);
  EXPECT_EQ(QFileInfo(dir.filePath("x.mlodb.json")).size(), 2);
  EXPECT_EQ(QDir(dir.path()).entryList(QDir::Files | QDir::Hidden).size(), 2);
}

// Guards the pair: when renaming the second file fails, the first (already renamed) gets
// its previous version back. Before, it was removed, and the old bundle was gone too.
TEST(AtomicWrite, FailedSetKeepsThePreviousVersion) {
  QTemporaryDir dir;
  const QString bundle = dir.filePath("x.mlodb");
  ASSERT_TRUE(writeFileAtomically(bundle, "old bundle").ok);
  const QString manifest = dir.filePath("x.mlodb.json");
  ASSERT_TRUE(QDir(dir.path()).mkpath("x.mlodb.json/taken")); // no file can replace this folder
  const ExportResult result = writeFilesAtomically({{bundle, "new bundle"}, {manifest, "{}"}});
  EXPECT_FALSE(result.ok);
  EXPECT_TRUE(result.message.startsWith(manifest + ": cannot write: ")) << result.message.toStdString();
  QFile file(bundle);
  ASSERT_TRUE(file.open(QIODevice::ReadOnly));
  EXPECT_EQ(file.readAll(), QByteArray("old bundle"));
  EXPECT_EQ(QDir(dir.path()).entryList(QDir::Files | QDir::Hidden), QStringList{"x.mlodb"}) << "no temporary left";
}

// The bytes of the file at `path` ("<none>" when it cannot be read).
QByteArray contentOf(const QString& path) {
  QFile file(path);
  return file.open(QIODevice::ReadOnly) ? file.readAll() : QByteArray("<none>");
}

// Sets or clears the immutable attribute (chattr +i): no rename may replace such a file,
// not even root's. False where the file system or the user cannot.
bool setImmutable(const QString& path, bool immutable) {
  const QByteArray command = QByteArray("chattr ") + (immutable ? "+i '" : "-i '") + QFile::encodeName(path) +
                             "' 2>/dev/null";
  return std::system(command.constData()) == 0;
}

// Guards every file of a set when its last file cannot take its place (issue 29: with
// glTF's split_levels, the old LOD0 and LOD1 went when LOD2's rename failed): the files
// already placed get their previous versions back byte for byte, and no temporary or kept
// version stays. The last place is taken by a folder, and (where chattr works) by an
// immutable file, which refuses the exchange itself.
TEST(AtomicWrite, SetWhoseLastFileCannotLandKeepsEveryOldFile) {
  for (const bool immutable : {false, true}) {
    QTemporaryDir dir;
    const QStringList names{"x_LOD0.glb", "x_LOD1.glb", "x_LOD2.glb"};
    QList<QPair<QString, QByteArray>> oldSet, newSet;
    for (const QString& name : names) {
      oldSet.append({dir.filePath(name), "old " + name.toUtf8()});
      newSet.append({dir.filePath(name), "new " + name.toUtf8()});
    }
    ASSERT_TRUE(writeFilesAtomically(oldSet).ok);
    const QString last = dir.filePath(names.back());
    if (!immutable) {
      ASSERT_TRUE(QFile::remove(last));
      ASSERT_TRUE(QDir(dir.path()).mkpath(names.back() + "/taken"));
    } else if (!setImmutable(last, true)) {
      continue; // no immutable files here (not root, or the file system): the folder covers it
    }
    const ExportResult result = writeFilesAtomically(newSet);
    if (immutable)
      setImmutable(last, false);
    EXPECT_FALSE(result.ok);
    EXPECT_TRUE(result.message.startsWith(last + ": cannot write: ")) << result.message.toStdString();
    for (qsizetype i = 0; i + 1 < names.size(); ++i)
      EXPECT_EQ(contentOf(oldSet[i].first), oldSet[i].second) << names[i].toStdString();
    if (immutable) {
      EXPECT_EQ(contentOf(last), oldSet.back().second);
    }
    QStringList left = QDir(dir.path()).entryList(QDir::Files | QDir::Hidden);
    left.sort();
    EXPECT_EQ(left, immutable ? names : names.mid(0, 2)) << "no temporary left";
  }
}

// Guards the previous version when no hard link to it can be made, nor a copy (issue 29:
// the exporting user did not own the old out.mlodb, so under fs.protected_hardlinks = 1,
// Debian's default, the kept link failed; when the manifest's rename then failed, the new
// bundle was removed and the old one was gone). The old bundle here is root's and only
// root may read it, so neither a link nor a copy can keep it: the exchange of names needs
// neither. Run as root: the writer is a child that becomes `nobody`, replacing root's files
// in a folder anyone may write.
TEST(AtomicWrite, AnotherUsersUnreadableFileIsKeptAndReplaced) {
  if (::geteuid() != 0)
    GTEST_SKIP() << "needs root (to write as another user)";
  QTemporaryDir dir;
  ASSERT_TRUE(QFile::setPermissions(dir.path(), QFileDevice::Permissions(0x7777)));
  const QString bundle = dir.filePath("x.mlodb"), manifest = dir.filePath("x.mlodb.json");
  ASSERT_TRUE(writeFileAtomically(bundle, "old bundle").ok);
  ASSERT_EQ(::chmod(QFile::encodeName(bundle).constData(), 0600), 0); // root's, unreadable to others
  ASSERT_TRUE(QDir(dir.path()).mkpath("x.mlodb.json/taken")); // no file can replace this folder
  const auto writeAsNobody = [&] {
    const pid_t writer = ::fork();
    if (writer == 0) {
      if (::setgid(65534) != 0 || ::setuid(65534) != 0)
        ::_exit(3);
      const ExportResult result = writeFilesAtomically({{bundle, "new bundle"}, {manifest, "{}"}});
      ::_exit(result.ok ? 0 : 1);
    }
    int status = 0;
    return ::waitpid(writer, &status, 0) == writer && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  EXPECT_EQ(writeAsNobody(), 1) << "the set cannot land (the manifest's place is a folder)";
  EXPECT_EQ(contentOf(bundle), QByteArray("old bundle"));
  EXPECT_EQ(QDir(dir.path()).entryList(QDir::Files | QDir::Hidden), QStringList{"x.mlodb"}) << "no temporary left";
  ASSERT_TRUE(QDir(manifest).removeRecursively());
  EXPECT_EQ(writeAsNobody(), 0) << "before, the writer refused: it could neither link nor copy the old bundle";
  EXPECT_EQ(contentOf(bundle), QByteArray("new bundle"));
  EXPECT_EQ(contentOf(manifest), QByteArray("{}"));
  EXPECT_EQ(QDir(dir.path()).entryList(QDir::Files | QDir::Hidden).size(), 2) << "no temporary left";
}

// A PID that runs no more: a child that has exited and been waited for.
pid_t deadPid() {
  const pid_t dead = ::fork();
  if (dead == 0)
    ::_exit(0);
  if (dead > 0)
    ::waitpid(dead, nullptr, 0);
  return dead;
}

// Guards a writer killed between renaming the previous version aside and renaming the new
// file in (the fallback where the file system cannot exchange): the next write of the file
// puts the version back before anything else, so even a write that then fails leaves it.
TEST(AtomicWrite, VersionAKilledWriterPutAsideGoesBack) {
  QTemporaryDir dir;
  const pid_t dead = deadPid();
  ASSERT_GT(dead, 0);
  const QString aside = dir.filePath(QStringLiteral(".x.mlodb.mlod-old-%1-AbC123").arg(dead));
  {
    QFile file(aside);
    ASSERT_TRUE(file.open(QIODevice::WriteOnly));
    file.write("old bundle");
  }
  const QString bundle = dir.filePath("x.mlodb");
  ASSERT_TRUE(QDir(dir.path()).mkpath("x.mlodb.json/taken")); // this set cannot land
  EXPECT_FALSE(writeFilesAtomically({{bundle, "new bundle"}, {dir.filePath("x.mlodb.json"), "{}"}}).ok);
  EXPECT_EQ(contentOf(bundle), QByteArray("old bundle"));
  EXPECT_EQ(QDir(dir.path()).entryList(QDir::Files | QDir::Hidden), QStringList{"x.mlodb"});
}

// Guards two writers of one set (issue 29: four exports of different clips to one .mlodb
// at once, 100 rounds, once gave one clip's bundle beside another's manifest): racing
// writers land whole sets one after another, so after every round the bundle and manifest
// on disk come from the same writer.
TEST(AtomicWrite, RacingWritersLandWholeSets) {
  QTemporaryDir dir;
  const QString bundle = dir.filePath("x.mlodb"), manifest = dir.filePath("x.mlodb.json");
  constexpr int kWriters = 4, kRounds = 150;
  int mixed = 0;
  for (int round = 0; round < kRounds; ++round) {
    std::atomic<int> ready{0};
    std::vector<std::thread> writers;
    for (int w = 0; w < kWriters; ++w)
      writers.emplace_back([&, w] {
        const QByteArray tag = QByteArray::number(round * kWriters + w);
        ready.fetch_add(1);
        while (ready.load() < kWriters) {
        }
        EXPECT_TRUE(writeFilesAtomically({{bundle, "bundle " + tag}, {manifest, "manifest " + tag}}).ok);
      });
    for (std::thread& writer : writers)
      writer.join();
    QFile b(bundle), m(manifest);
    ASSERT_TRUE(b.open(QIODevice::ReadOnly) && m.open(QIODevice::ReadOnly));
    mixed += b.readAll().mid(7) != m.readAll().mid(9) ? 1 : 0;
  }
  EXPECT_EQ(mixed, 0) << "rounds that left one writer's bundle beside another's manifest";
  EXPECT_EQ(QDir(dir.path()).entryList(QDir::Files | QDir::Hidden).size(), 2) << "no temporary left";
}

// Guards the leftovers of a killed writer: its temporaries and kept versions (named with its
// PID) are removed the next time the file is written; a running writer's are not.
TEST(AtomicWrite, LeftoversOfAKilledWriterAreRemoved) {
  QTemporaryDir dir;
  const pid_t dead = deadPid();
  ASSERT_GT(dead, 0);
  const QString deadTemporary = QStringLiteral(".x.mlodb.mlod-tmp-%1-AbC123").arg(dead);
  const QString deadKept = QStringLiteral(".x.mlodb.mlod-old-%1-AbC123").arg(dead);
  const QString live = QStringLiteral(".x.mlodb.mlod-tmp-1-AbC123"); // PID 1 always runs
  for (const QString& name : {deadTemporary, deadKept, live}) {
    QFile file(dir.filePath(name));
    ASSERT_TRUE(file.open(QIODevice::WriteOnly));
    file.write("partial");
  }
  ASSERT_TRUE(writeFileAtomically(dir.filePath("x.mlodb"), "bundle").ok);
  QStringList left = QDir(dir.path()).entryList(QDir::Files | QDir::Hidden);
  left.sort();
  EXPECT_EQ(left, (QStringList{live, "x.mlodb"}));
}

TEST(ExportProgress, ReportsAndCancels) {
  double last = -1.0;
  bool cancel = false;
  ExportProgress progress([&](double f, const QString&) { last = f; }, [&] { return cancel; });
  EXPECT_TRUE(progress.step(0.5, "half"));
  EXPECT_DOUBLE_EQ(last, 0.5);
  progress.report(2.0, "clamped");
  EXPECT_DOUBLE_EQ(last, 1.0);
  cancel = true;
  EXPECT_FALSE(progress.step(0.75, "late"));
  EXPECT_FALSE(ExportProgress().cancelled());
}

TEST(Suffix, AppendedOnlyWhenMissing) {
  EXPECT_EQ(withSuffix("a/b", "glb", {"glb", "gltf"}), "a/b.glb");
  EXPECT_EQ(withSuffix("a/b.GLTF", "glb", {"glb", "gltf"}), "a/b.GLTF");
}

// The output check of the Export dialog and the CLI: one of the plugin's suffixes, in any
// case, ends the name; one inside the name, another format's or none is not.
TEST(Suffix, OnlyThePluginsSuffixesEndAnOutput) {
  EXPECT_TRUE(hasSuffix("out/x.GLB", {"glb", "gltf"}));
  EXPECT_TRUE(hasSuffix("out/x.gltf", {"glb", "gltf"}));
  EXPECT_TRUE(hasSuffix("x.summary.json", {"json"}));
  EXPECT_FALSE(hasSuffix("x.bundle", {"glb", "gltf"}));
  EXPECT_FALSE(hasSuffix("x.glb.bak", {"glb", "gltf"}));
  EXPECT_FALSE(hasSuffix("out.glb/x", {"glb", "gltf"}));
  EXPECT_FALSE(hasSuffix("xglb", {"glb"}));
  EXPECT_FALSE(hasSuffix("x", {"glb"}));
  EXPECT_FALSE(hasSuffix("x.", {""}));
  EXPECT_EQ(withSuffix("a/b.bundle", "glb", {"glb", "gltf"}), "a/b.bundle.glb");
}

TEST(Suffix, NamedAsAMessageSaysThem) {
  EXPECT_EQ(suffixesText({"mlodb"}), ".mlodb");
  EXPECT_EQ(suffixesText({"glb", "gltf"}), ".glb or .gltf");
  EXPECT_EQ(suffixesText({"html", "csv", "json"}), ".html, .csv or .json");
}

} // namespace
} // namespace mlod
