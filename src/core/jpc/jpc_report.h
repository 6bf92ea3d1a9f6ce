#pragma once
// The JSON document of `motionlod simplify --json` (docs/architecture.md section 6): keys exactly
//   {"file","clip","frames","fps","mode","alpha","unit_scale",
//    "thresholds":[{"threshold","simplified_joint_percent","clusters","max_error",
//                   "max_joint_position_error_cm","mean_joint_position_error_cm",
//                   "joints":[{"name","clusters","simplified_percent","max_error"}]}],
//    "seconds"}
// Units: thresholds and errors in cm·degrees, positions in cm, seconds of wall clock.
// "joints" lists the clusterable joints (those with a rotation channel), locked ones
// included, in skeleton order.

#include "core/jpc/jpc.h"
#include "core/jpc/jpc_settings.h"

#include <string>
#include <vector>

namespace mlod {

struct JpcReport {
  std::string file;
  std::string clip;
  int frames = 0;
  double fps = 0.0;
  JpcMode mode = JpcMode::Greedy;
  double alpha = kDefaultJpcAlpha;     // cm
  double unitScale = 1.0;              // cm per file unit
  std::vector<std::string> jointNames; // per skeleton joint
  std::vector<JpcLevelResult> levels;
  double seconds = 0.0; // clustering and measuring, import excluded
};

std::string jpcReportJson(const JpcReport& report, int indent = 2);

} // namespace mlod
