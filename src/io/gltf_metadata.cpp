#include "io/gltf_metadata.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>

namespace mlod {

namespace {

using nlohmann::json;

// The JSON text of a .glb (its first chunk) or of a .gltf; empty for anything else.
std::string_view jsonText(std::string_view bytes) {
  if (bytes.size() >= 20 && bytes.substr(0, 4) == "glTF") {
    std::uint32_t length = 0, type = 0;
    std::memcpy(&length, bytes.data() + 12, 4);
    std::memcpy(&type, bytes.data() + 16, 4);
    if (type != 0x4E4F534Au || length > bytes.size() - 20)
      return {};
    return bytes.substr(20, length);
  }
  const std::size_t start = bytes.find_first_not_of(" \t\r\n\xEF\xBB\xBF");
  return start != std::string_view::npos && bytes[start] == '{' ? bytes : std::string_view();
}

const json* member(const json& object, const char* key) {
  if (!object.is_object())
    return nullptr;
  const auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

std::optional<double> positiveNumber(const json* value) {
  if (!value || !value->is_number())
    return std::nullopt;
  const double x = value->get<double>();
  return std::isfinite(x) && x > 0.0 ? std::optional<double>(x) : std::nullopt;
}

std::optional<int> frameCount(const json* value) {
  if (!value || !value->is_number_integer())
    return std::nullopt;
  const std::int64_t n = value->get<std::int64_t>();
  return n >= 1 && n <= 10'000'000 ? std::optional<int>(static_cast<int>(n)) : std::nullopt;
}

std::string stringOf(const json* value) {
  return value && value->is_string() ? value->get<std::string>() : std::string();
}

// The index of the element of `array` named `name`; `index` when that one has the name (or
// no name is given); -1 when neither finds one.
int resolve(const json* array, const json* index, const std::string& name) {
  const int size = array && array->is_array() ? static_cast<int>(array->size()) : 0;
  const int at = index && index->is_number_integer() ? index->get<int>() : -1;
  if (at >= 0 && at < size && (name.empty() || stringOf(member((*array)[std::size_t(at)], "name")) == name))
    return at;
  if (!name.empty())
    for (int i = 0; i < size; ++i)
      if (stringOf(member((*array)[std::size_t(i)], "name")) == name)
        return i;
  return -1;
}

// What shows that `document` holds LOD levels as the glTF exporter writes them (animations
// whose extras name their level, which rewriting tools keep; MSFT_lod), in words; empty if nothing.
std::string levelSign(const json& document) {
  int levelled = 0;
  if (const json* animations = member(document, "animations"); animations && animations->is_array())
    for (const json& animation : *animations)
      if (const json* extras = member(animation, "extras"); extras && member(*extras, "level"))
        ++levelled;
  if (levelled > 0)
    return std::to_string(levelled) + " animation" + (levelled == 1 ? "" : "s") + " of LOD levels";
  if (const json* nodes = member(document, "nodes"); nodes && nodes->is_array())
    for (const json& node : *nodes)
      if (const json* extensions = member(node, "extensions"); extensions && member(*extensions, "MSFT_lod"))
        return "mesh levels (MSFT_lod)";
  return {};
}

} // namespace

std::vector<GltfAnimationInfo> readGltfAnimationInfo(std::string_view bytes, std::vector<std::string>& out_warnings) {
  const std::string_view text = jsonText(bytes);
  if (text.empty())
    return {};
  const json document = json::parse(text.begin(), text.end(), nullptr, false);
  const json* animations = member(document, "animations");
  if (document.is_discarded() || !animations || !animations->is_array() || animations->empty())
    return {};
  std::vector<GltfAnimationInfo> out(animations->size());
  for (std::size_t a = 0; a < out.size(); ++a) {
    const json& animation = (*animations)[a];
    out[a].name = stringOf(member(animation, "name"));
    static const json kNone;
    const json* found = member(animation, "extras");
    const json& extras = found ? *found : kNone;
    out[a].fps = positiveNumber(member(extras, "fps"));
    out[a].frameCount = frameCount(member(extras, "frameCount"));
    if (const json* looping = member(extras, "looping"); looping && looping->is_boolean())
      out[a].looping = looping->get<bool>();
  }

  const json* extensions = member(document, "extensions");
  const json* clusters = extensions ? member(*extensions, "MLOD_joint_clusters") : nullptr;
  const json* levels = clusters ? member(*clusters, "levels") : nullptr;
  if (!levels || !levels->is_array()) {
    if (const std::string sign = levelSign(document); !sign.empty())
      out_warnings.push_back("no MLOD_joint_clusters: " + sign +
                             ", but no cluster tables (a tool that rewrote the file, such as gltf-transform copy or "
                             "prune, drops vendor extensions; export it again to have them)");
    return out;
  }
  if (const json* version = member(*clusters, "version");
      !version || !version->is_number_integer() || version->get<int>() != 1) {
    out_warnings.push_back("MLOD_joint_clusters: not version 1; its cluster tables are ignored");
    return out;
  }
  const json* nodes = member(document, "nodes");
  for (const json& level : *levels) {
    const json* entries = member(level, "animations");
    if (!entries || !entries->is_array())
      continue;
    for (const json& entry : *entries) {
      const std::string animationName = stringOf(member(entry, "animationName"));
      const int a = resolve(animations, member(entry, "animation"), animationName);
      if (a < 0) {
        out_warnings.push_back("MLOD_joint_clusters: no animation " +
                               (animationName.empty() ? member(entry, "animation") ? member(entry, "animation")->dump()
                                                                                   : std::string("(none)")
                                                      : "'" + animationName + "'") +
                               " in the file; its clusters are ignored");
        continue;
      }
      GltfAnimationInfo& info = out[std::size_t(a)];
      if (!info.fps)
        info.fps = positiveNumber(member(entry, "fps"));
      if (!info.frameCount)
        info.frameCount = frameCount(member(entry, "frameCount"));
      if (const json* looping = member(entry, "looping"); !info.looping && looping && looping->is_boolean())
        info.looping = looping->get<bool>();
      const json* joints = member(entry, "joints");
      if (!joints || !joints->is_array())
        continue;
      for (const json& joint : *joints) {
        const std::string name = stringOf(member(joint, "name"));
        const int node = resolve(nodes, member(joint, "node"), name);
        const std::string nodeName = node >= 0 ? stringOf(member((*nodes)[std::size_t(node)], "name")) : std::string();
        if (nodeName.empty()) {
          out_warnings.push_back(
              "MLOD_joint_clusters: animation '" + info.name + "' names a joint that is not in the file (" +
              (name.empty() ? std::string("unnamed") : "'" + name + "'") + "); its clusters are ignored");
          continue;
        }
        std::vector<Cluster> list;
        const json* spans = member(joint, "clusters");
        for (std::size_t i = 0; spans && spans->is_array() && i < spans->size(); ++i) {
          const json& span = (*spans)[i];
          if (!span.is_array() || span.size() != 3 || !span[0].is_number_integer() || !span[1].is_number_integer() ||
              !span[2].is_number_integer())
            continue;
          list.push_back({span[0].get<int>(), span[1].get<int>(), span[2].get<int>()});
        }
        info.clusters.emplace_back(nodeName, std::move(list));
      }
    }
  }
  return out;
}

} // namespace mlod
