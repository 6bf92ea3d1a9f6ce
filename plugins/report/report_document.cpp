#include "report_document.h"

#include "core/lod/held_keys.h"

#include "svg_chart.h"

#include <cmath>
#include <cstdio>

namespace mlod::report {

using nlohmann::json;

namespace {

json jointsJson(const LodPackage& package, const LodPackageLevel& level, const JpcLevelResult& metrics) {
  json out = json::array();
  const std::vector<std::uint8_t>& removed = level.build.motion.bones.removed;
  for (std::size_t j = 0; j < metrics.joints.size() && j < package.skeleton.joints.size(); ++j) {
    const JointMetrics& m = metrics.joints[j];
    if (!m.clusterable)
      continue; // joints without a rotation channel (BVH End Sites) are never clustered
    out.push_back({{"name", package.skeleton.joints[j].name},
                   {"threshold", m.threshold},
                   {"locked", m.locked},
                   {"removed", j < removed.size() && removed[j] != 0},
                   {"clusters", m.clusters},
                   {"clustered_frames", m.clusteredFrames},
                   {"simplified_percent", m.simplifiedPercent},
                   {"max_error", m.maxError}});
  }
  return out;
}

// A number as the CSV writes it: the shortest text that reads back to the same double.
std::string csvNumber(const json& value) {
  return value.is_null() ? std::string() : value.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos)
    return text;
  std::string out = "\"";
  for (char c : text)
    out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string csvRow(const std::vector<std::string>& fields) {
  std::string out;
  for (std::size_t i = 0; i < fields.size(); ++i)
    out += (i ? "," : "") + fields[i];
  return out + "\r\n";
}

// A figure for people: `digits` decimals.
std::string fixed(const json& value, int digits) {
  if (!value.is_number())
    return "–";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, value.get<double>());
  return buffer;
}

std::string td(const std::string& content, const char* cls = "num") {
  return std::string("<td class=\"") + cls + "\">" + content + "</td>";
}

const char* kStyle = R"(body{font-family:sans-serif;margin:2em;color:#222;max-width:1200px}
h1{font-size:1.6em}h2{font-size:1.3em;margin-top:1.6em;border-bottom:1px solid #ccc}h3{font-size:1.1em}
table{border-collapse:collapse;margin:0.6em 0}th,td{border:1px solid #ccc;padding:3px 8px}
th{background:#f0f0f0;text-align:left}td.num{text-align:right;font-variant-numeric:tabular-nums}
tr.removed td{color:#999}dl{display:grid;grid-template-columns:max-content auto;gap:2px 12px}dt{font-weight:bold}
.charts{display:flex;flex-wrap:wrap;gap:12px}svg.chart{border:1px solid #eee;background:#fff}
.note{color:#555;font-size:0.9em})";

} // namespace

json reportJson(const LodPackage& package) {
  json doc;
  doc["format"] = kReportFormat;
  doc["version"] = kReportVersion;
  doc["name"] = package.name;
  doc["source"] = package.sourcePath;
  doc["unit_scale"] = package.unitScale;
  doc["mode"] = toString(package.jpc.mode);
  doc["alpha"] = package.jpc.alpha;
  doc["joints"] = package.skeleton.jointCount();
  doc["mesh"] = package.mesh
                    ? json{{"vertices", package.mesh->vertexCount()}, {"triangles", package.mesh->triangleCount()}}
                    : json(nullptr);
  doc["bounding_radius_cm"] = package.lods.boundingRadiusCm;
  doc["projection"] = {{"vertical_fov_degrees", package.lods.projection.verticalFovDegrees},
                       {"viewport_height_pixels", package.lods.projection.viewportHeightPixels}};
  json clips = json::array();
  for (const Clip& clip : package.clips)
    clips.push_back({{"name", clip.name},
                     {"frames", clip.frameCount},
                     {"fps", clip.fps},
                     {"duration_seconds", clip.durationSeconds()}});
  doc["clips"] = std::move(clips);

  json levels = json::array();
  for (const LodPackageLevel& level : package.levels) {
    const SkinnedMesh* mesh = level.mesh();
    json entry = {{"level", level.index},
                  {"name", level.settings.name},
                  {"threshold", level.settings.motionThreshold},
                  {"mesh_ratio", level.settings.meshRatio},
                  {"switch_distance_cm", level.settings.switchDistanceCm},
                  {"screen_size_pixels", level.settings.screenSizePixels},
                  {"pixel_error", level.settings.pixelError},
                  {"active_joints", level.skeleton().jointCount()},
                  {"removed_joints", level.build.motion.bones.removedCount()},
                  {"triangles", mesh ? mesh->triangleCount() : 0},
                  {"vertices", mesh ? mesh->vertexCount() : 0},
                  {"motion_error_cm", level.build.motion.motionErrorCm},
                  {"mesh_error_cm", level.build.meshErrorCm()},
                  {"deviation_cm", level.build.deviationCm()}};
    // the level's animations as held keys (core/lod/held_keys.h), as the glTF exporter writes them
    const LevelKeyBytes keys = levelKeyBytes(package, level);
    entry["animation_keys"] = keys.rotationKeys;
    entry["animation_bytes"] = keys.bytes;
    json perClip = json::array();
    for (std::size_t c = 0; c < level.metrics.size() && c < package.clips.size(); ++c) {
      const JpcLevelResult& m = level.metrics[c];
      perClip.push_back({{"clip", package.clips[c].name},
                         {"threshold", m.threshold},
                         {"simplified_joint_percent", m.simplifiedPercent},
                         {"clusters", m.clusterCount},
                         {"max_error", m.maxError},
                         {"max_joint_position_error_cm", m.maxJointPositionErrorCm},
                         {"mean_joint_position_error_cm", m.meanJointPositionErrorCm},
                         {"joints", jointsJson(package, level, m)}});
      // what the runtime holds for it (the compressed LodClip the package built)
      if (c < level.runtimeClips.size()) {
        const LodClip& runtime = level.runtimeClips[c];
        json& clip = perClip.back();
        clip["runtime_bytes"] = runtime.byteSize();
        clip["runtime_bytes_per_second"] = runtime.bytesPerSecond();
        clip["precision_cm"] = runtime.precisionCm();
        clip["encoded_error_cm"] = runtime.encodedErrorCm();
      }
    }
    entry["clips"] = std::move(perClip);
    levels.push_back(std::move(entry));
  }
  doc["levels"] = std::move(levels);
  return doc;
}

std::string reportCsv(const json& report, CsvTable table) {
  std::string out;
  if (table == CsvTable::Levels) {
    out += csvRow({"clip", "level", "name", "threshold", "simplified_joint_percent", "clusters", "max_error",
                   "max_joint_position_error_cm", "mean_joint_position_error_cm", "mesh_ratio", "triangles",
                   "active_joints", "motion_error_cm", "mesh_error_cm", "deviation_cm", "switch_distance_cm",
                   "screen_size_pixels", "animation_keys", "animation_bytes"});
    const json& clips = report.at("clips");
    // One row per clip and level; a package without clips gets one row per level, its Table 1 columns empty.
    const std::size_t rows = std::max<std::size_t>(clips.size(), 1);
    for (std::size_t c = 0; c < rows; ++c) {
      for (const json& level : report.at("levels")) {
        const json none = json::object();
        const json& m = c < level.at("clips").size() ? level["clips"][c] : none;
        const auto figure = [&](const char* key) { return m.contains(key) ? csvNumber(m[key]) : std::string(); };
        out +=
            csvRow({csvField(c < clips.size() ? clips[c].at("name").get<std::string>() : std::string()),
                    csvNumber(level.at("level")), csvField(level.at("name").get<std::string>()),
                    csvNumber(level.at("threshold")), figure("simplified_joint_percent"), figure("clusters"),
                    figure("max_error"), figure("max_joint_position_error_cm"), figure("mean_joint_position_error_cm"),
                    csvNumber(level.at("mesh_ratio")), csvNumber(level.at("triangles")),
                    csvNumber(level.at("active_joints")), csvNumber(level.at("motion_error_cm")),
                    csvNumber(level.at("mesh_error_cm")), csvNumber(level.at("deviation_cm")),
                    csvNumber(level.at("switch_distance_cm")), csvNumber(level.at("screen_size_pixels")),
                    csvNumber(level.at("animation_keys")), csvNumber(level.at("animation_bytes"))});
      }
    }
    return out;
  }
  out += csvRow({"clip", "frames", "level", "level_name", "joint", "threshold", "locked", "removed", "clusters",
                 "clustered_frames", "simplified_percent", "max_error"});
  const json& clips = report.at("clips");
  for (std::size_t c = 0; c < clips.size(); ++c) {
    for (const json& level : report.at("levels")) {
      if (c >= level.at("clips").size())
        continue;
      for (const json& joint : level["clips"][c].at("joints"))
        out += csvRow({csvField(clips[c].at("name").get<std::string>()), csvNumber(clips[c].at("frames")),
                       csvNumber(level.at("level")), csvField(level.at("name").get<std::string>()),
                       csvField(joint.at("name").get<std::string>()), csvNumber(joint.at("threshold")),
                       joint.at("locked").get<bool>() ? "true" : "false",
                       joint.at("removed").get<bool>() ? "true" : "false", csvNumber(joint.at("clusters")),
                       csvNumber(joint.at("clustered_frames")), csvNumber(joint.at("simplified_percent")),
                       csvNumber(joint.at("max_error"))});
    }
  }
  return out;
}

std::string reportHtml(const json& report) {
  const std::string name = report.at("name").get<std::string>();
  const json& levels = report.at("levels");
  const json& clips = report.at("clips");
  std::string out =
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>Motion LOD report: " +
      escapeXml(name) + "</title>\n<style>\n" + kStyle + "\n</style>\n</head>\n<body>\n";
  out += "<h1>Motion LOD report: " + escapeXml(name) + "</h1>\n<dl>\n";
  out += "<dt>Source</dt><dd>" + escapeXml(report.at("source").get<std::string>()) + "</dd>\n";
  out += "<dt>Joints</dt><dd>" + report.at("joints").dump() + "</dd>\n";
  if (report.at("mesh").is_object())
    out += "<dt>Mesh</dt><dd>" + report["mesh"].at("vertices").dump() + " vertices, " +
           report["mesh"].at("triangles").dump() + " triangles</dd>\n";
  out += "<dt>Clips</dt><dd>";
  for (std::size_t c = 0; c < clips.size(); ++c)
    out += (c ? ", " : "") + escapeXml(clips[c].at("name").get<std::string>()) + " (" + clips[c].at("frames").dump() +
           " frames at " + fixed(clips[c].at("fps"), 2) + " fps)";
  out += "</dd>\n<dt>Clustering</dt><dd>" + escapeXml(report.at("mode").get<std::string>()) +
         ", &alpha; = " + fixed(report.at("alpha"), 2) + " cm</dd>\n";
  out += "<dt>Bounding radius</dt><dd>" + fixed(report.at("bounding_radius_cm"), 1) +
         " cm (projection: " + fixed(report["projection"].at("vertical_fov_degrees"), 0) +
         "&deg; vertical field of view, " + fixed(report["projection"].at("viewport_height_pixels"), 0) +
         " pixels high)</dd>\n</dl>\n";

  // The levels: what each costs and how far it strays.
  out += "<h2>LOD levels</h2>\n<table class=\"levels\">\n<tr><th>Level</th><th>Name</th><th>Threshold E "
         "(cm&middot;&deg;)</th>"
         "<th>Mesh ratio</th><th>Triangles</th><th>Active joints</th><th>Motion error (cm)</th><th>Mesh error (cm)</th>"
         "<th>Deviation (cm)</th><th>Switch distance (m)</th><th>Screen size (px)</th><th>Animation keys</th>"
         "<th>Animation bytes</th></tr>\n";
  for (const json& level : levels)
    out += "<tr class=\"level\">" + td(level.at("level").dump()) +
           td(escapeXml(level.at("name").get<std::string>()), "") + td(fixed(level.at("threshold"), 1)) +
           td(fixed(level.at("mesh_ratio"), 3)) + td(level.at("triangles").dump()) +
           td(level.at("active_joints").dump()) + td(fixed(level.at("motion_error_cm"), 3)) +
           td(fixed(level.at("mesh_error_cm"), 3)) + td(fixed(level.at("deviation_cm"), 3)) +
           td(fixed(json(level.at("switch_distance_cm").get<double>() / 100.0), 2)) +
           td(fixed(level.at("screen_size_pixels"), 1)) + td(level.at("animation_keys").dump()) +
           td(level.at("animation_bytes").dump()) + "</tr>\n";
  out += "</table>\n<p class=\"note\">Deviation = motion error + mesh error: a bound of how far the level's skin "
         "strays from the original in every measured pose. Switch distance: the camera distance from which the level "
         "is used. Animation keys and bytes: the level's rotation keys and the bytes of its key times and values as "
         "the glTF exporter writes them (frozen spans held by their ends).</p>\n";
  {
    LineSeries deviation{"deviation (cm)", {}}, motion{"motion error (cm)", {}}, mesh{"mesh error (cm)", {}};
    for (const json& level : levels) {
      const double d = level.at("switch_distance_cm").get<double>() / 100.0;
      deviation.points.emplace_back(d, level.at("deviation_cm").get<double>());
      motion.points.emplace_back(d, level.at("motion_error_cm").get<double>());
      mesh.points.emplace_back(d, level.at("mesh_error_cm").get<double>());
    }
    out += "<div class=\"charts\">\n" +
           lineChart("Deviation by switch distance", "switch distance (m)", "cm", {deviation, motion, mesh}) +
           "</div>\n";
  }

  for (std::size_t c = 0; c < clips.size(); ++c) {
    const std::string clipName = clips[c].at("name").get<std::string>();
    out += "<h2>Clip " + escapeXml(clipName) + "</h2>\n<h3>Table 1: joint posture clustering</h3>\n";
    out += "<table class=\"table1\">\n<tr><th>Level</th><th>Threshold E (cm&middot;&deg;)</th><th>Simplified joints "
           "(%)</th>"
           "<th>Clusters</th><th>Max error E (cm&middot;&deg;)</th><th>Joint position error, max (cm)</th>"
           "<th>Joint position error, mean (cm)</th></tr>\n";
    LineSeries simplified{"simplified joints (%)", {}}, maxPos{"max (cm)", {}}, meanPos{"mean (cm)", {}};
    for (const json& level : levels) {
      if (c >= level.at("clips").size())
        continue;
      const json& m = level["clips"][c];
      out += "<tr class=\"level\">" + td(escapeXml(level.at("name").get<std::string>()), "") +
             td(fixed(m.at("threshold"), 1)) + td(fixed(m.at("simplified_joint_percent"), 2)) +
             td(m.at("clusters").dump()) + td(fixed(m.at("max_error"), 2)) +
             td(fixed(m.at("max_joint_position_error_cm"), 3)) + td(fixed(m.at("mean_joint_position_error_cm"), 3)) +
             "</tr>\n";
      const double t = m.at("threshold").get<double>();
      simplified.points.emplace_back(t, m.at("simplified_joint_percent").get<double>());
      maxPos.points.emplace_back(t, m.at("max_joint_position_error_cm").get<double>());
      meanPos.points.emplace_back(t, m.at("mean_joint_position_error_cm").get<double>());
    }
    out += "</table>\n";

    // Per joint: simplified % at each level (chart and table).
    std::vector<std::string> jointNames;
    std::vector<std::string> levelNames;
    std::vector<std::vector<double>> percents;
    for (const json& level : levels) {
      if (c >= level.at("clips").size())
        continue;
      levelNames.push_back(level.at("name").get<std::string>());
      std::vector<double> row;
      for (const json& joint : level["clips"][c].at("joints")) {
        if (percents.empty())
          jointNames.push_back(joint.at("name").get<std::string>());
        row.push_back(joint.at("simplified_percent").get<double>());
      }
      percents.push_back(std::move(row));
    }
    out += "<div class=\"charts\">\n" +
           lineChart("Simplified joints by threshold", "threshold E (cm\xC2\xB7\xC2\xB0)", "%", {simplified}) +
           lineChart("Joint position error by threshold", "threshold E (cm\xC2\xB7\xC2\xB0)", "cm", {maxPos, meanPos}) +
           barChart("Simplified frames per joint", "simplified (%)", jointNames, levelNames, percents) + "</div>\n";

    out += "<h3>Per joint</h3>\n<table class=\"joints\">\n<tr><th>Joint</th>";
    for (const std::string& levelName : levelNames)
      out += "<th>" + escapeXml(levelName) + ": simplified (%)</th><th>clusters</th><th>max E</th>";
    out += "</tr>\n";
    for (std::size_t j = 0; j < jointNames.size(); ++j) {
      std::string cells;
      bool removedEverywhere = !levels.empty();
      for (const json& level : levels) {
        if (c >= level.at("clips").size() || j >= level["clips"][c].at("joints").size())
          continue;
        const json& joint = level["clips"][c]["joints"][j];
        const bool removed = joint.at("removed").get<bool>();
        removedEverywhere = removedEverywhere && removed;
        cells += td(fixed(joint.at("simplified_percent"), 1) + (removed ? " (removed)" : "")) +
                 td(joint.at("clusters").dump()) + td(fixed(joint.at("max_error"), 2));
      }
      out += std::string("<tr class=\"joint") + (removedEverywhere ? " removed" : "") + "\"><td>" +
             escapeXml(jointNames[j]) + "</td>" + cells + "</tr>\n";
    }
    out += "</table>\n<p class=\"note\">A joint marked removed has no bone at that level: bone reduction froze it "
           "for every frame of every clip and moved its skin to its nearest active ancestor.</p>\n";
  }
  out += "</body>\n</html>\n";
  return out;
}

} // namespace mlod::report
