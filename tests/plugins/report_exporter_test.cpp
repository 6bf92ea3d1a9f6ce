// The report exporter plugin (plugins/report) on real data: its JSON holds the package's
// figures exactly, its CSV tables parse with the documented columns and the same figures,
// its HTML page has a row per level, the inline SVG charts and nothing external; unwritable
// output and cancel leave nothing behind.

#include "exporter_test_support.h"

#include "core/lod/held_keys.h"

#include <QFile>
#include <QFileInfo>
#include <QTemporaryDir>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace mlod {
namespace {

using nlohmann::json;

Exporter& reportExporter() {
  static Exporter* exporter = test::loadExporter(QStringLiteral(MLOD_REPORT_PLUGIN));
  if (!exporter)
    throw std::runtime_error("no report exporter");
  return *exporter;
}

std::string exportText(const LodPackage& package, const QString& path, const QStringList& options = {}) {
  const ExportResult result =
      reportExporter().exportPackage(package, path, test::exporterOptions(reportExporter(), options), {});
  EXPECT_TRUE(result.ok) << result.message.toStdString();
  QFile file(path);
  return file.open(QIODevice::ReadOnly) ? file.readAll().toStdString() : std::string();
}

// RFC 4180: fields separated by commas, quoted when they hold commas, quotes or line ends.
std::vector<std::vector<std::string>> parseCsv(const std::string& text) {
  std::vector<std::vector<std::string>> rows(1);
  std::string field;
  bool quoted = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      rows.back().push_back(field);
      field.clear();
    } else if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') {
      rows.back().push_back(field);
      field.clear();
      rows.emplace_back();
      ++i;
    } else {
      field += c;
    }
  }
  if (!field.empty() || !rows.back().empty())
    rows.back().push_back(field);
  else
    rows.pop_back();
  return rows;
}

int countOf(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size()))
    ++n;
  return n;
}

int clusterableJoints(const JpcLevelResult& metrics) {
  int n = 0;
  for (const JointMetrics& joint : metrics.joints)
    n += joint.clusterable ? 1 : 0;
  return n;
}

class ReportOnRealData : public ::testing::TestWithParam<const char*> {
protected:
  const LodPackage& package() const {
    return std::string(GetParam()) == "BCN_Epileptic" ? test::bcnPackage() : test::cmuPackage();
  }
};

TEST(ReportExporter, DescribesItselfAndItsOptions) {
  Exporter& exporter = reportExporter();
  EXPECT_EQ(exporter.id(), "report");
  EXPECT_EQ(exporter.suffixes(), QStringList({"html", "csv", "json"}));
  const QVariantMap defaults = test::exporterOptions(exporter);
  EXPECT_EQ(defaults.value("format").toString(), "auto");
  EXPECT_EQ(defaults.value("csv_table").toString(), "levels");
  QVariantMap values;
  QString error;
  EXPECT_FALSE(parseExporterOptions(exporter.options(), {"format=pdf"}, &values, &error));
  EXPECT_FALSE(parseExporterOptions(exporter.options(), {"indent=9"}, &values, &error));
}

TEST_P(ReportOnRealData, JsonHoldsThePackagesFigures) {
  const LodPackage& p = package();
  ASSERT_EQ(p.levels.size(), 4u);
  QTemporaryDir dir;
  const json doc = json::parse(exportText(p, dir.filePath("report.json")));
  EXPECT_EQ(doc.at("format"), "motionlod-report");
  EXPECT_EQ(doc.at("version"), 1);
  EXPECT_EQ(doc.at("name"), p.name);
  EXPECT_EQ(doc.at("joints"), p.skeleton.jointCount());
  EXPECT_EQ(doc.at("mesh").is_null(), !p.mesh);
  ASSERT_EQ(doc.at("clips").size(), p.clips.size());
  ASSERT_EQ(doc.at("levels").size(), p.levels.size());
  for (std::size_t i = 0; i < p.levels.size(); ++i) {
    const LodPackageLevel& level = p.levels[i];
    const json& l = doc["levels"][i];
    EXPECT_EQ(l.at("level"), level.index);
    EXPECT_EQ(l.at("name"), level.settings.name);
    EXPECT_EQ(l.at("threshold").get<double>(), level.settings.motionThreshold);
    EXPECT_EQ(l.at("switch_distance_cm").get<double>(), level.settings.switchDistanceCm);
    EXPECT_EQ(l.at("active_joints").get<int>(), level.skeleton().jointCount());
    EXPECT_EQ(l.at("triangles").get<std::size_t>(), level.mesh() ? level.mesh()->triangleCount() : 0u);
    EXPECT_EQ(l.at("motion_error_cm").get<double>(), level.build.motion.motionErrorCm);
    EXPECT_EQ(l.at("mesh_error_cm").get<double>(), level.build.meshErrorCm());
    EXPECT_EQ(l.at("deviation_cm").get<double>(), level.build.deviationCm());
    EXPECT_EQ(l.at("animation_bytes").get<std::size_t>(), levelKeyBytes(p, level).bytes);
    EXPECT_EQ(l.at("animation_keys").get<std::size_t>(), levelKeyBytes(p, level).rotationKeys);
    if (i > 0 && !p.clips.empty()) { // frozen spans held by their ends: a level's keys take no more bytes
      // (the cluster tables, counted in animation_bytes, grow with the clusters: on BCN_Epileptic
      // the totals of LOD1-3 rise by 48 to 104 bytes while the keys stay: every track but the
      // same few is held by two keys at each of those levels)
      const LevelKeyBytes now = levelKeyBytes(p, level), before = levelKeyBytes(p, p.levels[i - 1]);
      EXPECT_LE(now.bytes - now.clusterBytes, before.bytes - before.clusterBytes);
      if (i == 1) {
        EXPECT_LT(now.bytes - now.clusterBytes, before.bytes - before.clusterBytes);
      }
    }
    ASSERT_EQ(l.at("clips").size(), level.metrics.size());
    for (std::size_t c = 0; c < level.metrics.size(); ++c) {
      const JpcLevelResult& m = level.metrics[c];
      const json& t = l["clips"][c];
      EXPECT_EQ(t.at("clip"), p.clips[c].name);
      EXPECT_EQ(t.at("simplified_joint_percent").get<double>(), m.simplifiedPercent);
      EXPECT_EQ(t.at("clusters").get<int>(), m.clusterCount);
      EXPECT_EQ(t.at("max_error").get<double>(), m.maxError);
      EXPECT_EQ(t.at("max_joint_position_error_cm").get<double>(), m.maxJointPositionErrorCm);
      EXPECT_EQ(t.at("mean_joint_position_error_cm").get<double>(), m.meanJointPositionErrorCm);
      const LodClip& runtime = level.runtimeClips[c];
      EXPECT_EQ(t.at("runtime_bytes").get<std::size_t>(), runtime.byteSize());
      EXPECT_NEAR(t.at("runtime_bytes_per_second").get<double>(), runtime.byteSize() / runtime.duration(), 1e-6);
      EXPECT_EQ(t.at("precision_cm").get<double>(), kDefaultClipPrecisionCm);
      EXPECT_LE(t.at("encoded_error_cm").get<double>(), t.at("precision_cm").get<double>());
      ASSERT_EQ(int(t.at("joints").size()), clusterableJoints(m));
      std::size_t k = 0;
      for (std::size_t j = 0; j < m.joints.size(); ++j) {
        if (!m.joints[j].clusterable)
          continue;
        const json& joint = t["joints"][k++];
        EXPECT_EQ(joint.at("name"), p.skeleton.joints[j].name);
        EXPECT_EQ(joint.at("clusters").get<int>(), m.joints[j].clusters);
        EXPECT_EQ(joint.at("clustered_frames").get<int>(), m.joints[j].clusteredFrames);
        EXPECT_EQ(joint.at("simplified_percent").get<double>(), m.joints[j].simplifiedPercent);
        EXPECT_EQ(joint.at("max_error").get<double>(), m.joints[j].maxError);
        EXPECT_EQ(joint.at("removed").get<bool>(), level.build.motion.bones.removed[j] != 0);
      }
    }
  }
  // coarser levels simplify more joints: the report shows what the package holds, not a constant
  EXPECT_GT(doc["levels"][3]["clips"][0]["simplified_joint_percent"].get<double>(),
            doc["levels"][1]["clips"][0]["simplified_joint_percent"].get<double>());
}

TEST_P(ReportOnRealData, CsvTablesParseWithTheirColumns) {
  const LodPackage& p = package();
  QTemporaryDir dir;
  const auto levels = parseCsv(exportText(p, dir.filePath("levels.csv")));
  ASSERT_EQ(levels.size(), 1 + p.clips.size() * p.levels.size()); // header + a row per clip and level
  for (const auto& row : levels)
    ASSERT_EQ(row.size(), 19u);
  EXPECT_EQ(levels[0][0], "clip");
  EXPECT_EQ(levels[0][4], "simplified_joint_percent");
  for (std::size_t c = 0; c < p.clips.size(); ++c)
    for (std::size_t i = 0; i < p.levels.size(); ++i) {
      const auto& row = levels[1 + c * p.levels.size() + i];
      const JpcLevelResult& m = p.levels[i].metrics[c];
      EXPECT_EQ(row[0], p.clips[c].name);
      EXPECT_EQ(std::stoi(row[1]), p.levels[i].index);
      EXPECT_EQ(std::stod(row[4]), m.simplifiedPercent); // shortest round-trip text: exact
      EXPECT_EQ(std::stoi(row[5]), m.clusterCount);
      EXPECT_EQ(std::stod(row[7]), m.maxJointPositionErrorCm);
      EXPECT_EQ(std::stod(row[14]), p.levels[i].build.deviationCm());
    }

  const auto joints = parseCsv(exportText(p, dir.filePath("joints.csv"), {"csv_table=joints"}));
  std::size_t expected = 1;
  for (const LodPackageLevel& level : p.levels)
    for (const JpcLevelResult& m : level.metrics)
      expected += std::size_t(clusterableJoints(m));
  ASSERT_EQ(joints.size(), expected);
  for (const auto& row : joints)
    ASSERT_EQ(row.size(), 12u);
  EXPECT_EQ(joints[0][4], "joint");
}

TEST_P(ReportOnRealData, HtmlIsSelfContainedWithARowPerLevelAndCharts) {
  const LodPackage& p = package();
  QTemporaryDir dir;
  const std::string html = exportText(p, dir.filePath("report.html"));
  ASSERT_FALSE(html.empty());
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  // the levels table and Table 1 of each clip: one row per level each
  EXPECT_EQ(countOf(html, "<tr class=\"level\">"), int(p.levels.size() * (1 + p.clips.size())));
  for (const LodPackageLevel& level : p.levels)
    EXPECT_NE(html.find(">" + level.settings.name + "<"), std::string::npos);
  // charts: deviation by distance, and per clip simplified %, joint error and per-joint bars
  EXPECT_EQ(countOf(html, "<svg "), int(1 + 3 * p.clips.size()));
  EXPECT_EQ(countOf(html, "<svg "), countOf(html, "</svg>"));
  EXPECT_GT(countOf(html, "<polyline"), 0);
  EXPECT_GT(countOf(html, "<rect x="), int(p.levels.size()));
  // per-joint rows: one per clusterable joint and clip
  int jointRows = 0;
  for (const JpcLevelResult& m : p.levels[0].metrics)
    jointRows += clusterableJoints(m);
  EXPECT_EQ(countOf(html, "<tr class=\"joint"), jointRows);
  // nothing external: no script, stylesheet link, image or URL besides the SVG namespace
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_EQ(html.find("<img"), std::string::npos);
  EXPECT_EQ(countOf(html, "http"), countOf(html, "xmlns=\"http://www.w3.org/2000/svg\""));
}

INSTANTIATE_TEST_SUITE_P(Assets, ReportOnRealData, ::testing::Values("CMU_01_01", "BCN_Epileptic"),
                         [](const ::testing::TestParamInfo<const char*>& asset) { return std::string(asset.param); });

TEST(ReportExporter, MeshWithoutClipsHasItsLevelsAndNoTable1) {
  const std::optional<LodPackage> p = test::packageOf("OBJ/spider.obj");
  ASSERT_TRUE(p);
  ASSERT_TRUE(p->clips.empty());
  QTemporaryDir dir;
  const auto rows = parseCsv(exportText(*p, dir.filePath("spider.csv")));
  ASSERT_EQ(rows.size(), 1 + p->levels.size()); // one row per level, the Table 1 columns empty
  for (std::size_t i = 1; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].size(), 19u);
    EXPECT_EQ(rows[i][4], "");
    const SkinnedMesh* mesh = p->levels[i - 1].mesh();
    ASSERT_TRUE(mesh != nullptr);
    EXPECT_EQ(std::stoul(rows[i][10]), mesh->triangleCount());
  }
  const std::string html = exportText(*p, dir.filePath("spider.html"));
  EXPECT_EQ(countOf(html, "<tr class=\"level\">"), int(p->levels.size()));
  EXPECT_EQ(countOf(html, "<svg "), 1);
}

TEST(ReportExporter, FormatFollowsTheSuffixUnlessAsked) {
  const LodPackage& p = test::cmuPackage();
  QTemporaryDir dir;
  EXPECT_EQ(exportText(p, dir.filePath("a.json")).front(), '{');
  EXPECT_EQ(exportText(p, dir.filePath("a.csv")).rfind("clip,level,", 0), 0u);
  EXPECT_EQ(exportText(p, dir.filePath("a.html")).rfind("<!DOCTYPE", 0), 0u);
  EXPECT_EQ(exportText(p, dir.filePath("a.txt"), {"format=json", "indent=0"}).find('\n'),
            exportText(p, dir.filePath("b.txt"), {"format=json", "indent=0"}).size() - 1); // one line
}

TEST(ReportExporter, UnwritableOutputAndCancelLeaveNothing) {
  const LodPackage& p = test::cmuPackage();
  QTemporaryDir dir;
  const QString missing = dir.filePath("missing/folder/report.html");
  const ExportResult result = reportExporter().exportPackage(p, missing, test::exporterOptions(reportExporter()), {});
  EXPECT_FALSE(result.ok);
  EXPECT_TRUE(result.message.contains("report.html")) << result.message.toStdString();
  EXPECT_FALSE(QFileInfo::exists(missing));

  for (int cancelAt : {1, 2, 3}) {
    int calls = 0;
    const ExportProgress progress({}, [&] { return ++calls >= cancelAt; });
    const ExportResult cancelled = reportExporter().exportPackage(p, dir.filePath("report.html"),
                                                                  test::exporterOptions(reportExporter()), progress);
    EXPECT_FALSE(cancelled.ok) << cancelAt;
    EXPECT_TRUE(cancelled.message.contains("cancelled"));
    EXPECT_TRUE(test::filesIn(dir.path()).isEmpty()) << test::filesIn(dir.path()).join(' ').toStdString();
  }
}

} // namespace
} // namespace mlod
