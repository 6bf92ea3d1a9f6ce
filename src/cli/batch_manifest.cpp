#include "cli/batch_manifest.h"

#include "io/import_options.h"

#include <cmath>
#include <cstdio>

namespace mlod::cli {

namespace {

using nlohmann::json;

// A job of the manifest, paths resolved against its folder; an Error when malformed.
Error readJob(const json& entry, std::size_t index, const std::filesystem::path& folder, ManifestJob& out) {
  const std::string where = "job " + std::to_string(index);
  if (!entry.is_object())
    return Error(where + " is not an object");
  for (const char* key : {"input", "plugin", "output"})
    if (!entry.contains(key) || !entry[key].is_string() || entry[key].get_ref<const std::string&>().empty())
      return Error(where + ": \"" + key + "\" must be a non-empty string");
  for (auto it = entry.begin(); it != entry.end(); ++it)
    if (it.key() != "input" && it.key() != "plugin" && it.key() != "output" && it.key() != "options" &&
        it.key() != "levels" && it.key() != "unit_scale" && it.key() != "character" && it.key() != "skinning")
      return Error(where + ": unknown key \"" + it.key() + "\"");
  const auto resolve = [&](const std::string& path) {
    const std::filesystem::path p(path);
    return (p.is_absolute() ? p : folder / p).lexically_normal().string();
  };
  out.input = resolve(entry["input"].get<std::string>());
  out.output = resolve(entry["output"].get<std::string>());
  out.plugin = entry["plugin"].get<std::string>();
  if (entry.contains("options")) {
    if (!entry["options"].is_object())
      return Error(where + ": \"options\" must be an object");
    for (auto it = entry["options"].begin(); it != entry["options"].end(); ++it)
      if (!it->is_boolean() && !it->is_number() && !it->is_string())
        return Error(where + ": option \"" + it.key() + "\" must be a bool, number or string");
    out.options = entry["options"];
  }
  if (entry.contains("levels")) {
    if (!entry["levels"].is_array())
      return Error(where + ": \"levels\" must be an array of level indices");
    for (const json& level : entry["levels"]) {
      if (!level.is_number_integer() || level.get<long long>() < 0 || level.get<long long>() > 65535)
        return Error(where + ": \"levels\" must be an array of level indices");
      out.levels.push_back(level.get<int>());
    }
  }
  if (entry.contains("character")) {
    const json& character = entry["character"];
    if (character.is_number_integer() && character.get<long long>() >= 0 && character.get<long long>() <= 65535)
      out.character = std::to_string(character.get<long long>());
    else if (character.is_string() && !character.get_ref<const std::string&>().empty())
      out.character = character.get<std::string>();
    else
      return Error(where + ": \"character\" must be a project's character: its file name, path or index");
  }
  if (entry.contains("skinning")) {
    const json& skinning = entry["skinning"];
    out.skinning = skinning.is_string() ? lodSkinningFromName(skinning.get<std::string>()) : std::nullopt;
    if (!out.skinning)
      return Error(where + ": \"skinning\" must be \"gpu\" or \"cpu\" (where the character is skinned)");
  }
  if (entry.contains("unit_scale")) {
    const json& scale = entry["unit_scale"];
    const std::string problem = where + ": \"unit_scale\" must be a positive number of cm per file unit or a preset "
                                        "(cm, m, mm, inch, cmu)";
    if (scale.is_number()) {
      const double value = scale.get<double>();
      if (!std::isfinite(value) || value <= 0.0)
        return Error(problem);
      char text[64];
      std::snprintf(text, sizeof text, "%.17g", value);
      out.unitScale = text;
    } else if (scale.is_string() && parseUnitScale(scale.get<std::string>())) {
      out.unitScale = scale.get<std::string>();
    } else {
      return Error(problem);
    }
  }
  return {};
}

} // namespace

Result<std::vector<ManifestJob>> parseBatchManifest(std::string_view text, const std::filesystem::path& folder) {
  const json doc = json::parse(text, nullptr, false);
  if (doc.is_discarded())
    return Error("not JSON");
  if (!doc.is_object() || !doc.contains("jobs") || !doc["jobs"].is_array())
    return Error("not a batch manifest: {\"jobs\":[{\"input\",\"plugin\",\"output\",\"options\":{}}]}");
  std::vector<ManifestJob> jobs;
  for (std::size_t i = 0; i < doc["jobs"].size(); ++i) {
    ManifestJob job;
    if (Error error = readJob(doc["jobs"][i], i, folder, job))
      return error;
    jobs.push_back(std::move(job));
  }
  return jobs;
}

} // namespace mlod::cli
