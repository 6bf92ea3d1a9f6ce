#include "core/project.h"

#include "runtime/input_file.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>

namespace mlod {

using nlohmann::json;

JpcSettings Project::jpcSettings(int asset, double unitScale) const {
  JpcSettings settings;
  settings.alpha = alpha;
  settings.mode = mode;
  settings.zeroLength = 1e-6 * unitScale; // docs/architecture.md section 4: 1e-6 file units
  if (asset >= 0 && asset < static_cast<int>(assets.size()))
    settings.joints = assets[static_cast<std::size_t>(asset)].joints;
  return settings;
}

std::vector<double> Project::levelThresholds() const {
  std::vector<double> out;
  for (const LodLevel& level : lods.levels)
    out.push_back(level.motionThreshold);
  return out;
}

LodSet defaultLodSet() {
  LodSet set;
  LodLevel original;
  original.name = "LOD0";
  set.levels.push_back(original);
  const double thresholds[] = {5.0, 50.0, 100.0, 300.0};
  for (double threshold : thresholds) {
    LodLevel level;
    level.name = "LOD" + std::to_string(set.levels.size());
    level.motionThreshold = threshold;
    set.levels.push_back(level);
  }
  return set;
}

namespace {
bool nonNegative(double value) { return std::isfinite(value) && value >= 0.0; }
std::string tooManyLevels(std::size_t count) {
  return "the project has " + std::to_string(count) + " LOD levels; a project may have at most " +
         std::to_string(kMaxProjectLevels);
}
} // namespace

Error Project::validate() const {
  if (Error error = validateAlpha(alpha))
    return error;
  if (lods.levels.size() > std::size_t(kMaxProjectLevels))
    return Error(tooManyLevels(lods.levels.size()));
  if (Error error = lods.validate())
    return error;
  for (std::size_t a = 0; a < assets.size(); ++a) {
    const ProjectAsset& asset = assets[a];
    const std::string where = "asset " + std::to_string(a);
    if (asset.path.empty())
      return Error(where + " has no path");
    if (asset.path.size() > kMaxAssetPathBytes)
      return Error(where + ": the path is " + std::to_string(asset.path.size()) + " bytes long; a path has at most " +
                   std::to_string(kMaxAssetPathBytes));
    if (!nonNegative(asset.unitScale))
      return Error(where + ": unit_scale " + std::to_string(asset.unitScale) +
                   " is not a finite number >= 0 (cm per file unit; 0 = the file's own unit)");
    if (asset.lods && asset.lods->levels.size() > std::size_t(kMaxProjectLevels))
      return Error(where + ": " + tooManyLevels(asset.lods->levels.size()));
    if (Error error = asset.lods ? asset.lods->validate() : Error())
      return Error(where + "'s LOD set: " + error.message());
    for (const auto& [name, joint] : asset.joints) {
      if (name.size() > kMaxJointNameBytes)
        return Error(where + ": a joint name is " + std::to_string(name.size()) +
                     " bytes long; a joint name has at most " + std::to_string(kMaxJointNameBytes));
      if (Error error = joint.alpha ? validateAlpha(*joint.alpha, where + ", joint " + name + ": alpha") : Error())
        return error;
      for (const std::optional<double>& threshold : joint.thresholds)
        if (threshold && !nonNegative(*threshold))
          return Error(where + ", joint " + name + ": a threshold must be a finite number >= 0 (cm·degrees)");
      if (!joint.thresholds.empty() && joint.thresholds.front())
        return Error(where + ", joint " + name + ": level 0 is the original; it has no threshold to override");
      if (Error error = validateMeshImportance(joint.meshImportance, where + ", joint " + name + ": the mesh importance"))
        return error;
    }
  }
  // A motion plays on a character through one table (assigning it again replaces the table,
  // project_mappings.h): a pair named twice is refused, not retargeted once per copy.
  std::map<std::pair<int, int>, std::size_t> pairs;
  for (std::size_t m = 0; m < mappings.size(); ++m) {
    const ProjectMapping& mapping = mappings[m];
    const int count = static_cast<int>(assets.size());
    if (mapping.motion < 0 || mapping.motion >= count || mapping.character < 0 || mapping.character >= count ||
        mapping.motion == mapping.character)
      return Error("mapping " + std::to_string(m) + " does not name two different assets of the project");
    if (const auto [first, added] = pairs.try_emplace({mapping.motion, mapping.character}, m); !added)
      return Error("mapping " + std::to_string(m) + " assigns asset " + std::to_string(mapping.motion) +
                   " to asset " + std::to_string(mapping.character) + " again (mapping " +
                   std::to_string(first->second) + " does)");
  }
  return {};
}

namespace {
json lodSetToJson(const LodSet& lods) {
  json levels = json::array();
  for (const LodLevel& level : lods.levels)
    levels.push_back({{"name", level.name},
                      {"threshold", level.motionThreshold},
                      {"mesh_ratio", level.meshRatio},
                      {"switch_distance_cm", level.switchDistanceCm},
                      {"pixel_error", level.pixelError},
                      {"screen_size_pixels", level.screenSizePixels},
                      {"motion_error_cm", level.motionErrorCm},
                      {"mesh_error_cm", level.meshErrorCm},
                      {"triangles", level.triangles},
                      {"active_joints", level.activeJoints}});
  return {{"projection",
           {{"vertical_fov_degrees", lods.projection.verticalFovDegrees},
            {"viewport_height_pixels", lods.projection.viewportHeightPixels}}},
          {"skinning", lodSkinningName(lods.skinning)},
          {"bounding_radius_cm", lods.boundingRadiusCm},
          {"levels", std::move(levels)}};
}
} // namespace

std::string projectToJson(const Project& project, int indent) {
  json doc;
  doc["format"] = kProjectFormat;
  doc["version"] = kProjectVersion;
  doc["alpha"] = project.alpha;
  doc["mode"] = toString(project.mode);
  doc["lods"] = lodSetToJson(project.lods);
  json assets = json::array();
  for (const ProjectAsset& asset : project.assets) {
    json joints = json::object();
    for (const auto& [name, settings] : asset.joints) {
      json entry;
      entry["alpha"] = settings.alpha ? json(*settings.alpha) : json(nullptr);
      json thresholds = json::array();
      for (const std::optional<double>& t : settings.thresholds)
        thresholds.push_back(t ? json(*t) : json(nullptr));
      entry["thresholds"] = std::move(thresholds);
      entry["locked"] = settings.locked;
      entry["mesh_importance"] = settings.meshImportance;
      joints[name] = std::move(entry);
    }
    json entry = {{"path", asset.path}};
    if (asset.unitScale > 0.0) // absent: the file's own unit
      entry["unit_scale"] = asset.unitScale;
    entry["joints"] = std::move(joints);
    if (asset.lods) // absent: the project's set
      entry["lods"] = lodSetToJson(*asset.lods);
    assets.push_back(std::move(entry));
  }
  doc["assets"] = std::move(assets);
  json mappings = json::array();
  for (const ProjectMapping& mapping : project.mappings)
    mappings.push_back({{"motion", mapping.motion},
                        {"character", mapping.character},
                        {"table", json::parse(motionMappingToJson(mapping.mapping))}});
  doc["mappings"] = std::move(mappings);
  doc["current"] = {{"asset", project.view.asset},
                    {"clip", project.view.clip},
                    {"level", project.view.level},
                    {"joint", project.view.joint}};
  // A name that is not UTF-8 (an asset path kept as bytes) is written with U+FFFD, as every
  // JSON writer does (core/utf8.h), where dump() would throw type_error 316.
  return doc.dump(indent, ' ', false, json::error_handler_t::replace);
}

namespace {
// Field access that names what is wrong instead of throwing nlohmann's type_error at callers.
const json& field(const json& object, const char* key, const std::string& where) {
  if (!object.is_object() || !object.contains(key))
    throw std::runtime_error(where + " has no \"" + key + "\"");
  return object.at(key);
}
double number(const json& value, const std::string& what) {
  if (!value.is_number())
    throw std::runtime_error(what + " is not a number");
  return value.get<double>();
}
std::optional<double> optionalNumber(const json& value, const std::string& what) {
  if (value.is_null())
    return std::nullopt;
  return number(value, what);
}
int integer(const json& value, const std::string& what) {
  if (!value.is_number_integer())
    throw std::runtime_error(what + " is not an integer");
  return value.get<int>();
}
// An index of the view: any integer is read (a hand-edited file may hold 2^31 or -5) and
// clampView() brings it in range; only a value that is no integer is refused.
int viewIndex(const json& value, const std::string& what) {
  if (!value.is_number_integer())
    throw std::runtime_error(what + " is not an integer");
  const long long wide = value.is_number_unsigned()
                             ? static_cast<long long>(std::min<std::uint64_t>(value.get<std::uint64_t>(), 1ull << 40))
                             : value.get<long long>();
  return static_cast<int>(
      std::clamp<long long>(wide, std::numeric_limits<int>::min() / 2, std::numeric_limits<int>::max() / 2));
}
// The view names no figure, so one out of range opens at the nearest valid place: a level of
// the set, an asset of the project (none when it has none), a clip >= 0 (the Document checks
// the clip count once the asset is imported).
void clampView(Project& project) {
  ProjectView& view = project.view;
  if (view.asset < -1 || view.asset >= static_cast<int>(project.assets.size()))
    view.asset = project.assets.empty() ? -1 : 0;
  view.level = std::clamp(view.level, 0, std::max(0, int(lodSetFor(project, view.asset).levels.size()) - 1));
  view.clip = std::max(0, view.clip);
  if (view.joint.size() > kMaxJointNameBytes) // no joint has such a name
    view.joint.clear();
}
std::string text(const json& value, const std::string& what) {
  if (!value.is_string())
    throw std::runtime_error(what + " is not a string");
  return value.get<std::string>();
}
// A "lods" object (the project's, or since version 4 an asset's own); `where` names it.
LodSet lodSetFromJson(const json& lods, const std::string& where) {
  LodSet out;
  const json& projection = field(lods, "projection", where);
  out.projection.verticalFovDegrees =
      number(field(projection, "vertical_fov_degrees", "the projection"), "vertical_fov_degrees");
  out.projection.viewportHeightPixels =
      number(field(projection, "viewport_height_pixels", "the projection"), "viewport_height_pixels");
  // absent (a project saved before it was kept): the default, skinned on the GPU
  if (lods.contains("skinning")) {
    const std::optional<LodSkinning> skinning = lodSkinningFromName(text(lods["skinning"], where + " skinning"));
    if (!skinning)
      throw std::runtime_error(where + " skinning is neither \"gpu\" nor \"cpu\"");
    out.skinning = *skinning;
  }
  out.boundingRadiusCm = number(field(lods, "bounding_radius_cm", where), "bounding_radius_cm");
  const json& levels = field(lods, "levels", where);
  if (!levels.is_array())
    throw std::runtime_error("\"levels\" is not a list");
  if (levels.size() > std::size_t(kMaxProjectLevels))
    throw std::runtime_error(tooManyLevels(levels.size()));
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const std::string at = "level " + std::to_string(i);
    const json& entry = levels[i];
    LodLevel level;
    level.name = text(field(entry, "name", at), at + " name");
    level.motionThreshold = number(field(entry, "threshold", at), at + " threshold");
    level.meshRatio = number(field(entry, "mesh_ratio", at), at + " mesh_ratio");
    level.switchDistanceCm = number(field(entry, "switch_distance_cm", at), at + " switch_distance_cm");
    level.pixelError = number(field(entry, "pixel_error", at), at + " pixel_error");
    level.screenSizePixels = number(field(entry, "screen_size_pixels", at), at + " screen_size_pixels");
    level.motionErrorCm = number(field(entry, "motion_error_cm", at), at + " motion_error_cm");
    level.meshErrorCm = number(field(entry, "mesh_error_cm", at), at + " mesh_error_cm");
    level.triangles = integer(field(entry, "triangles", at), at + " triangles");
    level.activeJoints = integer(field(entry, "active_joints", at), at + " active_joints");
    out.levels.push_back(std::move(level));
  }
  return out;
}
} // namespace

Result<Project> projectFromJson(std::string_view textIn) {
  const json doc = json::parse(textIn, nullptr, false);
  if (doc.is_discarded())
    return Error("not a Motion LOD project: the file is not valid JSON");
  if (!doc.is_object() || !doc.contains("format") || doc["format"] != kProjectFormat)
    return Error("not a Motion LOD project (no \"format\": \"motionlod-project\")");
  if (!doc.contains("version") || !doc["version"].is_number_integer())
    return Error("the project has no version number");
  // read wide first: 2^63 narrowed to int read as "version 0" (issue 29)
  const std::int64_t wide = doc["version"].is_number_unsigned()
                                ? static_cast<std::int64_t>(std::min<std::uint64_t>(doc["version"].get<std::uint64_t>(),
                                                                                    std::uint64_t(std::numeric_limits<std::int64_t>::max())))
                                : doc["version"].get<std::int64_t>();
  if (wide > kProjectVersion)
    return Error("the project is version " + doc["version"].dump() +
                 ", made by a newer Motion LOD Studio; this one reads up to version " + std::to_string(kProjectVersion));
  if (wide < 1)
    return Error("the project version " + doc["version"].dump() + " is not valid");
  const int version = static_cast<int>(wide);
  Project project;
  try {
    project.alpha = number(field(doc, "alpha", "the project"), "alpha");
    const std::string mode = text(field(doc, "mode", "the project"), "mode");
    const std::optional<JpcMode> parsed = parseJpcMode(mode);
    if (!parsed)
      return Error("mode '" + mode + "' is neither greedy nor optimal");
    project.mode = *parsed;
    project.lods = LodSet{};
    if (version == 1) { // a threshold per level, no original: it becomes level 0
      const json& levels = field(doc, "levels", "the project");
      if (!levels.is_array())
        return Error("\"levels\" is not a list");
      if (levels.size() + 1 > std::size_t(kMaxProjectLevels))
        return Error(tooManyLevels(levels.size() + 1));
      project.lods.levels.push_back(LodLevel{.name = "LOD0"});
      for (std::size_t i = 0; i < levels.size(); ++i) {
        LodLevel level;
        level.name = "LOD" + std::to_string(i + 1);
        level.motionThreshold =
            number(field(levels[i], "threshold", "level " + std::to_string(i)), "level " + std::to_string(i) + " threshold");
        project.lods.levels.push_back(std::move(level));
      }
    } else {
      project.lods = lodSetFromJson(field(doc, "lods", "the project"), "\"lods\"");
    }
    const json& assets = field(doc, "assets", "the project");
    if (!assets.is_array())
      return Error("\"assets\" is not a list");
    for (std::size_t a = 0; a < assets.size(); ++a) {
      const std::string where = "asset " + std::to_string(a);
      ProjectAsset asset;
      asset.path = text(field(assets[a], "path", where), where + " path");
      if (version <= 2) { // always there; 0 stood for the file's own unit
        asset.unitScale = number(field(assets[a], "unit_scale", where), where + " unit_scale");
      } else if (assets[a].is_object() && assets[a].contains("unit_scale")) {
        asset.unitScale = number(assets[a]["unit_scale"], where + " unit_scale");
        if (!std::isfinite(asset.unitScale) || !(asset.unitScale > 0.0))
          return Error(where + ": unit_scale must be positive (cm per file unit); it is " +
                       assets[a]["unit_scale"].dump() + " (leave it out for the file's own unit)");
      }
      const json& joints = field(assets[a], "joints", where);
      if (!joints.is_object())
        return Error(where + " \"joints\" is not an object");
      for (const auto& [name, entry] : joints.items()) {
        const std::string jointWhere = where + ", joint " + name;
        JointSettings settings;
        settings.alpha = optionalNumber(field(entry, "alpha", jointWhere), jointWhere + " alpha");
        const json& thresholds = field(entry, "thresholds", jointWhere);
        if (!thresholds.is_array())
          return Error(jointWhere + " \"thresholds\" is not a list");
        if (version == 1 && !thresholds.empty())
          settings.thresholds.push_back(std::nullopt); // version 1 had no original level
        for (const json& t : thresholds)
          settings.thresholds.push_back(optionalNumber(t, jointWhere + " threshold"));
        const json& locked = field(entry, "locked", jointWhere);
        if (!locked.is_boolean())
          return Error(jointWhere + " \"locked\" is not true or false");
        settings.locked = locked.get<bool>();
        if (entry.contains("mesh_importance")) // absent before issue 14: 1
          settings.meshImportance = number(entry["mesh_importance"], jointWhere + " mesh_importance");
        asset.joints[name] = std::move(settings);
      }
      if (version >= 4 && assets[a].contains("lods")) // a character's own set; before 4 the project's is every asset's
        asset.lods = lodSetFromJson(assets[a]["lods"], where + " \"lods\"");
      project.assets.push_back(std::move(asset));
    }
    if (doc.contains("mappings")) {
      const json& mappings = doc["mappings"];
      if (!mappings.is_array())
        return Error("\"mappings\" is not a list");
      for (std::size_t m = 0; m < mappings.size(); ++m) {
        const std::string where = "mapping " + std::to_string(m);
        ProjectMapping mapping;
        mapping.motion = integer(field(mappings[m], "motion", where), where + " motion");
        mapping.character = integer(field(mappings[m], "character", where), where + " character");
        Result<MotionMapping> table = motionMappingFromJson(field(mappings[m], "table", where).dump());
        if (!table)
          return Error(where + ": " + table.message());
        mapping.mapping = std::move(table).value();
        project.mappings.push_back(std::move(mapping));
      }
    }
    if (doc.contains("current")) {
      const json& current = doc["current"];
      project.view.asset = viewIndex(field(current, "asset", "\"current\""), "current asset");
      project.view.clip = viewIndex(field(current, "clip", "\"current\""), "current clip");
      project.view.level = viewIndex(field(current, "level", "\"current\""), "current level") + (version == 1 ? 1 : 0);
      project.view.joint = text(field(current, "joint", "\"current\""), "current joint");
    }
    // Without "current" too: the default view (level 1) may name a level the project lacks.
    clampView(project);
  } catch (const std::exception& error) {
    return Error(error.what());
  }
  if (Error error = project.validate())
    return error;
  return project;
}

Result<Project> loadProjectFile(const std::filesystem::path& file, const ProjectFileOptions& options) {
  std::string error;
  const std::optional<std::string> text = readInputFile(file, kMaxProjectFileBytes, &error);
  if (!text)
    return Error(error);
  if (text->empty())
    return Error("the file is empty");
  Result<Project> project = projectFromJson(*text);
  if (project && !options.allowOutsideAssets)
    if (Error outside = checkAssetPaths(*project, file))
      return outside;
  return project;
}

namespace {
namespace fs = std::filesystem;

fs::path projectFolder(const fs::path& projectFile) {
  return fs::absolute(projectFile).parent_path().lexically_normal();
}

bool lexicallyInside(const fs::path& path, const fs::path& folder) {
  const fs::path relative = path.lexically_relative(folder);
  return !relative.empty() && *relative.begin() != "..";
}

// `file` (absolute, lexically normal) inside `folder` both as written and with symlinks
// followed as far as the path exists (weakly_canonical), so a link cannot lead out. Where the
// links cannot be followed (a loop, no permission) the file cannot be read either: the
// lexical answer stands, and the import says what is wrong.
bool insideFolder(const fs::path& file, const fs::path& folder) {
  if (!lexicallyInside(file, folder))
    return false;
  std::error_code fileError, folderError;
  const fs::path realFile = fs::weakly_canonical(file, fileError);
  const fs::path realFolder = fs::weakly_canonical(folder, folderError);
  return fileError || folderError || lexicallyInside(realFile, realFolder);
}
} // namespace

Error checkAssetPaths(const Project& project, const std::filesystem::path& projectFile) {
  const fs::path folder = projectFolder(projectFile);
  for (std::size_t a = 0; a < project.assets.size(); ++a) {
    const std::string& stored = project.assets[a].path;
    if (fs::path(stored).is_absolute())
      continue; // the author's explicit choice
    const fs::path file = resolveAssetPath(projectFile, stored);
    if (!insideFolder(file, folder))
      return Error("asset " + std::to_string(a) + " ('" + stored + "') leads outside the project's folder " +
                   folder.string() + " (to " + file.string() +
                   "); a relative asset path must stay inside it unless assets outside are allowed");
  }
  return {};
}

std::string storedAssetPath(const std::filesystem::path& projectFile, const std::filesystem::path& assetFile) {
  const fs::path folder = projectFolder(projectFile);
  const fs::path asset = fs::absolute(assetFile).lexically_normal();
  return insideFolder(asset, folder) ? asset.lexically_relative(folder).generic_string() : asset.generic_string();
}

std::filesystem::path resolveAssetPath(const std::filesystem::path& projectFile, const std::string& stored) {
  const fs::path path(stored);
  if (path.is_absolute())
    return path.lexically_normal();
  return (projectFolder(projectFile) / path).lexically_normal();
}

void eraseProjectAsset(Project& project, int index) {
  project.assets.erase(project.assets.begin() + index);
  std::vector<ProjectMapping> kept;
  for (ProjectMapping mapping : project.mappings) {
    if (mapping.motion == index || mapping.character == index)
      continue;
    mapping.motion -= mapping.motion > index ? 1 : 0;
    mapping.character -= mapping.character > index ? 1 : 0;
    kept.push_back(std::move(mapping));
  }
  project.mappings = std::move(kept);
}

void insertProjectAsset(Project& project, int index, ProjectAsset asset) {
  project.assets.insert(project.assets.begin() + index, std::move(asset));
  for (ProjectMapping& mapping : project.mappings) {
    mapping.motion += mapping.motion >= index ? 1 : 0;
    mapping.character += mapping.character >= index ? 1 : 0;
  }
}

namespace {
// Per-joint threshold overrides following their level: new level i takes old level order[i]'s.
void remapJointThresholds(std::map<std::string, JointSettings>& joints, const std::vector<int>& order) {
  for (auto& [name, settings] : joints) {
    std::vector<std::optional<double>> remapped(order.size());
    for (std::size_t i = 0; i < order.size(); ++i)
      if (order[i] >= 0 && order[i] < static_cast<int>(settings.thresholds.size()))
        remapped[i] = settings.thresholds[static_cast<std::size_t>(order[i])];
    while (!remapped.empty() && !remapped.back())
      remapped.pop_back();
    settings.thresholds = std::move(remapped);
  }
}
} // namespace

namespace {
// Whether asset `asset` plays with the project's set on some view: it is no mapped motion and
// has no set of its own, or a character it is mapped onto has none.
bool playsWithProjectSet(const Project& project, int asset) {
  bool mapped = false;
  for (const ProjectMapping& mapping : project.mappings)
    if (mapping.motion == asset && mapping.character >= 0 && mapping.character < int(project.assets.size())) {
      mapped = true;
      if (!project.assets[std::size_t(mapping.character)].lods)
        return true;
    }
  return !mapped && !project.assets[std::size_t(asset)].lods;
}
} // namespace

void remapLevels(Project& project, const std::vector<int>& order, const std::vector<LodLevel>& levels) {
  assert(order.size() == levels.size());
  // only the assets that play with the project's set: an asset's own set has its own levels
  for (std::size_t a = 0; a < project.assets.size(); ++a)
    if (playsWithProjectSet(project, int(a)))
      remapJointThresholds(project.assets[a].joints, order);
  project.lods.levels = levels;
}

void applyLodSetEdit(Project& project, const LodSetEdit& edit) {
  remapLevels(project, edit.order, edit.lods.levels);
  project.lods = edit.lods;
}

bool isMappedOnto(const Project& project, int motion, int character) {
  const int count = static_cast<int>(project.assets.size());
  if (character < 0 || character >= count)
    return false;
  for (const ProjectMapping& mapping : project.mappings)
    if (mapping.motion == motion && mapping.character == character)
      return true;
  return false;
}

std::string assetFileName(const Project& project, int asset) {
  if (asset < 0 || asset >= static_cast<int>(project.assets.size()))
    return {};
  return std::filesystem::path(project.assets[std::size_t(asset)].path).filename().string();
}

int lodSetOwner(const Project& project, int asset, int viewedCharacter) {
  const int count = static_cast<int>(project.assets.size());
  if (asset < 0 || asset >= count)
    return -1;
  if (isMappedOnto(project, asset, viewedCharacter))
    return viewedCharacter;
  for (const ProjectMapping& mapping : project.mappings)
    if (mapping.motion == asset && mapping.character >= 0 && mapping.character < count)
      return mapping.character;
  return asset;
}

bool playsWithSetOf(const Project& project, int asset, int owner) {
  return asset >= 0 && asset < static_cast<int>(project.assets.size()) &&
         (asset == owner || isMappedOnto(project, asset, owner));
}

const LodSet& lodSetFor(const Project& project, int asset, int viewedCharacter) {
  const int owner = lodSetOwner(project, asset, viewedCharacter);
  if (owner >= 0 && project.assets[std::size_t(owner)].lods)
    return *project.assets[std::size_t(owner)].lods;
  return project.lods;
}

std::vector<double> levelThresholdsFor(const Project& project, int asset, int viewedCharacter) {
  std::vector<double> out;
  for (const LodLevel& level : lodSetFor(project, asset, viewedCharacter).levels)
    out.push_back(level.motionThreshold);
  return out;
}

std::vector<LodOverrideAbove> overridesAboveGeneratedLevels(const Project& project, int asset,
                                                            const LodSet& generated) {
  std::vector<LodOverrideAbove> out;
  const int owner = lodSetOwner(project, asset);
  if (owner < 0)
    return out;
  for (std::size_t a = 0; a < project.assets.size(); ++a) {
    if (!playsWithSetOf(project, int(a), owner))
      continue;
    const ProjectAsset& entry = project.assets[a];
    const std::string name = assetFileName(project, int(a));
    JpcSettings settings;
    settings.joints = entry.joints;
    for (LodOverrideAbove& above : overridesAboveLevels(settings, generated)) {
      above.asset = name;
      out.push_back(std::move(above));
    }
    for (const auto& [joint, own] : entry.joints) // a std::map: by name
      for (std::size_t level = generated.levels.size(); level < own.thresholds.size(); ++level)
        if (own.thresholds[level])
          out.push_back({joint, int(level), *own.thresholds[level], 0.0, name, true});
  }
  std::stable_sort(out.begin(), out.end(), [](const LodOverrideAbove& x, const LodOverrideAbove& y) {
    return std::tie(x.asset, x.level) < std::tie(y.asset, y.level);
  });
  return out;
}

int overrideCountFor(const Project& project, int asset) {
  const int owner = lodSetOwner(project, asset);
  int count = 0;
  for (std::size_t a = 0; owner >= 0 && a < project.assets.size(); ++a)
    if (playsWithSetOf(project, int(a), owner))
      for (const auto& [joint, own] : project.assets[a].joints)
        for (const std::optional<double>& threshold : own.thresholds)
          count += threshold ? 1 : 0;
  return count;
}

void applyLodSetEdit(Project& project, int asset, const LodSetEdit& edit, int viewedCharacter) {
  if (asset < 0 || asset >= static_cast<int>(project.assets.size())) {
    applyLodSetEdit(project, edit);
    return;
  }
  const int owner = lodSetOwner(project, asset, viewedCharacter);
  for (std::size_t a = 0; a < project.assets.size(); ++a) // the owner and the motions mapped onto it
    if (playsWithSetOf(project, int(a), owner))
      remapJointThresholds(project.assets[a].joints, edit.order);
  project.assets[std::size_t(owner)].lods = edit.lods;
}

} // namespace mlod
