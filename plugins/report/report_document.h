#pragma once
// The report of a LodPackage (plugins/report/README.md has the JSON schema): the paper's
// Table 1 per clip and level, what each level costs and how far it strays, and the per-joint
// figures. One JSON document holds every figure; the CSV tables and the HTML page are made
// from it, so the three formats always agree. Nothing is recomputed: every figure is the
// package's (LodPackageLevel::metrics, ::build, ::settings).
//
// Units: thresholds and errors E in cm·degrees, lengths and errors in cm, sizes on screen in
// pixels, percentages in [0, 100].

#include "core/lod/lod_package.h"

#include <nlohmann/json.hpp>
#include <string>

namespace mlod::report {

inline constexpr const char* kReportFormat = "motionlod-report";
inline constexpr int kReportVersion = 1;

// Every figure of `package`, as README.md describes.
nlohmann::json reportJson(const LodPackage& package);

enum class CsvTable {
  Levels, // one row per clip and level: Table 1 and the level's cost and errors
  Joints, // one row per clip, level and clusterable joint
};
inline constexpr int kLevelColumns = 19;
inline constexpr int kJointColumns = 12;

// RFC 4180 CSV (comma separated, CRLF line ends, a header row) of a reportJson() document.
std::string reportCsv(const nlohmann::json& report, CsvTable table);

// A self-contained HTML page (no external resource: styles inline, charts as inline SVG) of a
// reportJson() document.
std::string reportHtml(const nlohmann::json& report);

} // namespace mlod::report
