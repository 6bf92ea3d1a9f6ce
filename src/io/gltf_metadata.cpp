#include "io/gltf_metadata.h"

#include "core/error.h"

#include <algorithm>
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

// The binary buffer 0 of a .glb (its BIN chunk) or of a .gltf whose buffer is embedded as a
// base64 data URI; empty for anything else (an external .bin is not at hand).
std::string bufferZero(std::string_view bytes, const json& document);

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

std::string base64(std::string_view text) {
  std::string out;
  out.reserve(text.size() / 4 * 3);
  std::uint32_t bits = 0;
  int count = 0;
  for (char ch : text) {
    int v = -1;
    if (ch >= 'A' && ch <= 'Z')
      v = ch - 'A';
    else if (ch >= 'a' && ch <= 'z')
      v = ch - 'a' + 26;
    else if (ch >= '0' && ch <= '9')
      v = ch - '0' + 52;
    else if (ch == '+')
      v = 62;
    else if (ch == '/')
      v = 63;
    else if (ch == '=')
      break;
    else
      return {};
    bits = (bits << 6) | std::uint32_t(v);
    if (++count == 4) {
      out += char((bits >> 16) & 0xFF);
      out += char((bits >> 8) & 0xFF);
      out += char(bits & 0xFF);
      bits = 0;
      count = 0;
    }
  }
  if (count == 3) {
    out += char((bits >> 10) & 0xFF);
    out += char((bits >> 2) & 0xFF);
  } else if (count == 2) {
    out += char((bits >> 4) & 0xFF);
  }
  return out;
}

std::string bufferZero(std::string_view bytes, const json& document) {
  if (bytes.size() >= 20 && bytes.substr(0, 4) == "glTF") {
    std::uint32_t jsonLength = 0;
    std::memcpy(&jsonLength, bytes.data() + 12, 4);
    const std::size_t at = 20 + std::size_t(jsonLength);
    if (at + 8 > bytes.size())
      return {};
    std::uint32_t length = 0, type = 0;
    std::memcpy(&length, bytes.data() + at, 4);
    std::memcpy(&type, bytes.data() + at + 4, 4);
    if (type != 0x004E4942u || length > bytes.size() - at - 8) // "BIN\0"
      return {};
    return std::string(bytes.substr(at + 8, length));
  }
  const json* buffers = member(document, "buffers");
  if (!buffers || !buffers->is_array() || buffers->empty())
    return {};
  const std::string uri = stringOf(member((*buffers)[0], "uri"));
  const std::size_t comma = uri.find(";base64,");
  if (uri.rfind("data:", 0) != 0 || comma == std::string::npos)
    return {};
  return base64(std::string_view(uri).substr(comma + 8));
}

// The rows (joint, first, last, key) of the cluster table `accessor` (MLOD_joint_clusters
// version 2: VEC4 of unsigned 16- or 32-bit integers, tightly packed, in buffer 0), or an
// error saying what does not fit.
Result<std::vector<std::uint32_t>> clusterRows(const json& document, const std::string& buffer, const json& accessor) {
  const json* accessors = member(document, "accessors");
  const json* views = member(document, "bufferViews");
  if (!accessor.is_number_integer() || !accessors || !accessors->is_array() || accessor.get<std::int64_t>() < 0 ||
      accessor.get<std::size_t>() >= accessors->size())
    return Error("no accessor " + accessor.dump());
  const json& a = (*accessors)[accessor.get<std::size_t>()];
  const json* component = member(a, "componentType");
  const int type = component && component->is_number_integer() ? component->get<int>() : 0;
  const std::size_t size = type == 5123 ? 2 : type == 5125 ? 4 : 0;
  const json* view = member(a, "bufferView");
  const json* count = member(a, "count");
  if (size == 0 || stringOf(member(a, "type")) != "VEC4" || !view || !view->is_number_integer() || !views ||
      !views->is_array() || view->get<std::int64_t>() < 0 || view->get<std::size_t>() >= views->size() || !count ||
      !count->is_number_integer() || count->get<std::int64_t>() < 0)
    return Error("accessor " + accessor.dump() + " is not a VEC4 of unsigned integers");
  const json& v = (*views)[view->get<std::size_t>()];
  const auto offsetOf = [](const json* value) {
    return value && value->is_number_integer() && value->get<std::int64_t>() >= 0 ? value->get<std::size_t>() : 0;
  };
  const json* stride = member(v, "byteStride");
  const json* bufferIndex = member(v, "buffer");
  const std::size_t n = count->get<std::size_t>();
  const std::size_t begin = offsetOf(member(v, "byteOffset")) + offsetOf(member(a, "byteOffset"));
  if ((stride && offsetOf(stride) != 4 * size) || (bufferIndex && offsetOf(bufferIndex) != 0) || buffer.empty() ||
      n > buffer.size() / (4 * size) || begin > buffer.size() - n * 4 * size ||
      offsetOf(member(a, "byteOffset")) + n * 4 * size > offsetOf(member(v, "byteLength")))
    return Error("accessor " + accessor.dump() + " lies outside its buffer");
  std::vector<std::uint32_t> rows(n * 4);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (size == 2) {
      std::uint16_t x = 0;
      std::memcpy(&x, buffer.data() + begin + 2 * i, 2);
      rows[i] = x;
    } else {
      std::memcpy(&rows[i], buffer.data() + begin + 4 * i, 4);
    }
  }
  return rows;
}

// Whether `accessor` holds normalized integers.
bool isNormalizedInteger(const json& document, const json* accessor) {
  const json* accessors = member(document, "accessors");
  if (!accessor || !accessor->is_number_integer() || !accessors || !accessors->is_array() ||
      accessor->get<std::int64_t>() < 0 || accessor->get<std::size_t>() >= accessors->size())
    return false;
  const json& a = (*accessors)[accessor->get<std::size_t>()];
  const json* normalized = member(a, "normalized");
  const json* component = member(a, "componentType");
  return normalized && normalized->is_boolean() && normalized->get<bool>() && component &&
         component->is_number_integer() && component->get<int>() != 5126;
}

// The keys of the animation sampler output `accessor` when it holds normalized integers (VEC4
// of BYTE, UNSIGNED_BYTE, SHORT or UNSIGNED_SHORT with "normalized": true): decoded and
// normalized; nullopt for a float accessor (Assimp reads those right); an error saying why
// they cannot be read.
Result<std::optional<std::vector<glm::quat>>> normalizedKeys(const json& document, const std::string& buffer,
                                                             const json* accessor) {
  const json* accessors = member(document, "accessors");
  const json* views = member(document, "bufferViews");
  if (!isNormalizedInteger(document, accessor))
    return std::optional<std::vector<glm::quat>>();
  const json& a = (*accessors)[accessor->get<std::size_t>()];
  const int type = member(a, "componentType")->get<int>();
  const std::size_t size = type == 5120 || type == 5121 ? 1 : type == 5122 || type == 5123 ? 2 : 0;
  const double scale = type == 5120 ? 127.0 : type == 5121 ? 255.0 : type == 5122 ? 32767.0 : 65535.0;
  const json* view = member(a, "bufferView");
  const json* count = member(a, "count");
  if (size == 0 || stringOf(member(a, "type")) != "VEC4" || !count || !count->is_number_integer() ||
      count->get<std::int64_t>() < 0)
    return Error("accessor " + accessor->dump() + " is not a VEC4 of normalized integers");
  if (member(a, "sparse"))
    return Error("accessor " + accessor->dump() + " is sparse");
  if (!view || !view->is_number_integer() || !views || !views->is_array() || view->get<std::int64_t>() < 0 ||
      view->get<std::size_t>() >= views->size())
    return Error("accessor " + accessor->dump() + " has no buffer view");
  const json& v = (*views)[view->get<std::size_t>()];
  const auto offsetOf = [](const json* value) {
    return value && value->is_number_integer() && value->get<std::int64_t>() >= 0 ? value->get<std::size_t>() : 0;
  };
  const json* bufferIndex = member(v, "buffer");
  if ((bufferIndex && offsetOf(bufferIndex) != 0) || buffer.empty())
    return Error("accessor " + accessor->dump() + " is not in the file's own buffer (an external .bin is not read)");
  const std::size_t n = count->get<std::size_t>();
  const std::size_t stride = member(v, "byteStride") ? offsetOf(member(v, "byteStride")) : 4 * size;
  const std::size_t begin = offsetOf(member(v, "byteOffset")) + offsetOf(member(a, "byteOffset"));
  const std::size_t viewEnd = offsetOf(member(v, "byteOffset")) + offsetOf(member(v, "byteLength"));
  if (stride < 4 * size || (n > 0 && (n - 1 > (buffer.size() / stride) ||
                                      begin + (n - 1) * stride + 4 * size > viewEnd || viewEnd > buffer.size())))
    return Error("accessor " + accessor->dump() + " lies outside its buffer");
  std::vector<glm::quat> keys(n);
  for (std::size_t i = 0; i < n; ++i) {
    double c[4];
    for (std::size_t k = 0; k < 4; ++k) {
      const char* at = buffer.data() + begin + i * stride + k * size;
      double value = 0.0;
      if (type == 5120) {
        std::int8_t x = 0;
        std::memcpy(&x, at, 1);
        value = x;
      } else if (type == 5121) {
        std::uint8_t x = 0;
        std::memcpy(&x, at, 1);
        value = x;
      } else if (type == 5122) {
        std::int16_t x = 0;
        std::memcpy(&x, at, 2);
        value = x;
      } else {
        std::uint16_t x = 0;
        std::memcpy(&x, at, 2);
        value = x;
      }
      c[k] = std::max(value / scale, -1.0); // glTF 2.0, "Animations": the decoding of normalized outputs
    }
    const double length = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] + c[3] * c[3]);
    keys[i] = length > 0.0
                  ? glm::quat(float(c[3] / length), float(c[0] / length), float(c[1] / length), float(c[2] / length))
                  : glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
  }
  return std::optional<std::vector<glm::quat>>(std::move(keys));
}

// Fills `out[a].normalizedRotations` (and the problem, if any) for every animation of `document`.
void readNormalizedRotations(std::string_view bytes, const json& document, const json& animations,
                             std::vector<GltfAnimationInfo>& out) {
  const json* nodes = member(document, "nodes");
  std::string buffer;
  bool bufferRead = false;
  for (std::size_t a = 0; a < out.size(); ++a) {
    const json* channels = member(animations[a], "channels");
    const json* samplers = member(animations[a], "samplers");
    if (!channels || !channels->is_array() || !samplers || !samplers->is_array())
      continue;
    for (const json& channel : *channels) {
      const json* target = member(channel, "target");
      const json* sampler = member(channel, "sampler");
      const json* node = target ? member(*target, "node") : nullptr;
      if (!target || stringOf(member(*target, "path")) != "rotation" || !sampler || !sampler->is_number_integer() ||
          sampler->get<std::int64_t>() < 0 || sampler->get<std::size_t>() >= samplers->size() || !node ||
          !node->is_number_integer() || !nodes || !nodes->is_array() || node->get<std::int64_t>() < 0 ||
          node->get<std::size_t>() >= nodes->size())
        continue;
      const json* output = member((*samplers)[sampler->get<std::size_t>()], "output");
      if (!isNormalizedInteger(document, output))
        continue; // floats: Assimp reads them right
      if (!bufferRead) {
        // only for files that need it
        buffer = bufferZero(bytes, document);
        bufferRead = true;
      }
      Result<std::optional<std::vector<glm::quat>>> keys = normalizedKeys(document, buffer, output);
      if (!keys) {
        if (out[a].normalizedRotationProblem.empty())
          out[a].normalizedRotationProblem = "the rotation keys of animation '" + out[a].name +
                                             "' are normalized integers that cannot be read: " + keys.message();
        continue;
      }
      if (!keys->has_value())
        continue;
      std::string name = stringOf(member((*nodes)[node->get<std::size_t>()], "name"));
      if (name.empty())
        name = "nodes_" + std::to_string(node->get<std::size_t>());
      out[a].normalizedRotations.emplace_back(std::move(name), std::move(**keys));
    }
  }
}

} // namespace

std::vector<std::string> requiredGltfExtensions(std::string_view bytes) {
  const std::string_view text = jsonText(bytes);
  if (text.empty())
    return {};
  const json document = json::parse(text.begin(), text.end(), nullptr, false);
  const json* required = member(document, "extensionsRequired");
  std::vector<std::string> out;
  if (!document.is_discarded() && required && required->is_array())
    for (const json& name : *required)
      if (name.is_string())
        out.push_back(name.get<std::string>());
  return out;
}

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
  readNormalizedRotations(bytes, document, *animations, out);

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
  const json* versionValue = member(*clusters, "version");
  const int version = versionValue && versionValue->is_number_integer() ? versionValue->get<int>() : 0;
  if (version != 1 && version != 2) {
    out_warnings.push_back("MLOD_joint_clusters: not version 1 or 2; its cluster tables are ignored");
    return out;
  }
  const json* nodes = member(document, "nodes");
  const json* jointNames = member(*clusters, "jointNames");
  const std::string buffer = version == 2 ? bufferZero(bytes, document) : std::string();
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
      if (version == 2) { // one binary table: rows (joint, first, last, key), a joint's rows together
        const json* table = member(entry, "clusters");
        if (!table)
          continue; // no clusters
        Result<std::vector<std::uint32_t>> rows = clusterRows(document, buffer, *table);
        if (!rows) {
          out_warnings.push_back("MLOD_joint_clusters: the cluster table of animation '" + info.name +
                                 "' cannot be read (" + rows.message() + "); its clusters are ignored");
          continue;
        }
        for (std::size_t r = 0; r < rows->size(); r += 4) {
          const std::uint32_t joint = (*rows)[r];
          const std::string name = jointNames && jointNames->is_array() && joint < jointNames->size()
                                       ? stringOf(&(*jointNames)[joint])
                                       : std::string();
          const json index = joint;
          const int node = resolve(nodes, &index, name);
          const std::string nodeName =
              node >= 0 ? stringOf(member((*nodes)[std::size_t(node)], "name")) : std::string();
          if (nodeName.empty()) {
            out_warnings.push_back(
                "MLOD_joint_clusters: animation '" + info.name + "' names a joint that is not in the file (" +
                (name.empty() ? "joint " + std::to_string(joint) : "'" + name + "'") + "); its clusters are ignored");
            while (r + 4 < rows->size() && (*rows)[r + 4] == joint)
              r += 4;
            continue;
          }
          if (r == 0 || (*rows)[r - 4] != joint)
            info.clusters.emplace_back(nodeName, std::vector<Cluster>());
          const auto value = [&](std::size_t k) {
            return static_cast<int>(std::min<std::uint32_t>((*rows)[r + k], 0x7FFFFFFF));
          };
          info.clusters.back().second.push_back({value(1), value(2), value(3)});
        }
        continue;
      }
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
