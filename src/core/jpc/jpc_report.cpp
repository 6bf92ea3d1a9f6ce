#include "core/jpc/jpc_report.h"

#include <nlohmann/json.hpp>

namespace mlod {

std::string jpcReportJson(const JpcReport& report, int indent) {
  using nlohmann::json;
  json doc;
  doc["file"] = report.file;
  doc["clip"] = report.clip;
  doc["frames"] = report.frames;
  doc["fps"] = report.fps;
  doc["mode"] = toString(report.mode);
  doc["alpha"] = report.alpha;
  doc["unit_scale"] = report.unitScale;
  json thresholds = json::array();
  for (const JpcLevelResult& level : report.levels) {
    json joints = json::array();
    for (std::size_t j = 0; j < level.joints.size(); ++j) {
      const JointMetrics& metrics = level.joints[j];
      if (!metrics.clusterable)
        continue;
      joints.push_back({{"name", j < report.jointNames.size() ? report.jointNames[j] : std::to_string(j)},
                        {"clusters", metrics.clusters},
                        {"simplified_percent", metrics.simplifiedPercent},
                        {"max_error", metrics.maxError}});
    }
    thresholds.push_back({{"threshold", level.threshold},
                          {"simplified_joint_percent", level.simplifiedPercent},
                          {"clusters", level.clusterCount},
                          {"max_error", level.maxError},
                          {"max_joint_position_error_cm", level.maxJointPositionErrorCm},
                          {"mean_joint_position_error_cm", level.meanJointPositionErrorCm},
                          {"joints", std::move(joints)}});
  }
  doc["thresholds"] = std::move(thresholds);
  doc["seconds"] = report.seconds;
  return doc.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace); // a file name kept as bytes
}

} // namespace mlod
