#include "core/mesh/mesh_lod_report.h"

#include <nlohmann/json.hpp>

namespace mlod {

MeshLodReport::Level reportLevel(const MeshLodLevel& level, double seconds) {
  MeshLodReport::Level out;
  out.ratio = level.ratio;
  out.triangles = level.triangles();
  out.vertices = level.vertices();
  out.maxErrorCm = level.maxErrorCm;
  out.bindErrorCm = level.bindErrorCm;
  out.animatedMaxErrorCm = level.animatedErrorCm;
  out.animatedMeanErrorCm = level.animatedMeanErrorCm;
  out.lockedVerticesPreserved = level.lockedVerticesPreserved;
  out.warning = level.warning;
  out.seconds = seconds;
  return out;
}

std::string meshLodReportJson(const MeshLodReport& report, int indent) {
  using nlohmann::json;
  json doc;
  doc["file"] = report.file;
  doc["triangles"] = report.triangles;
  doc["vertices"] = report.vertices;
  doc["locked_vertices"] = report.lockedVertices;
  json levels = json::array();
  for (const MeshLodReport::Level& level : report.levels)
    levels.push_back({{"ratio", level.ratio},
                      {"triangles", level.triangles},
                      {"vertices", level.vertices},
                      {"max_error", level.maxErrorCm},
                      {"error_cm",
                       {{"bind", level.bindErrorCm},
                        {"animated_max", level.animatedMaxErrorCm},
                        {"animated_mean", level.animatedMeanErrorCm}}},
                      {"shared_vertices_preserved", level.lockedVerticesPreserved},
                      {"warning", level.warning.empty() ? json(nullptr) : json(level.warning)},
                      {"seconds", level.seconds}});
  doc["levels"] = std::move(levels);
  return doc.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace); // a file name kept as bytes
}

} // namespace mlod
