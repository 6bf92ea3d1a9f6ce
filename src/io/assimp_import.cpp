// Assimp scene -> core Asset. docs/architecture.md section 3 states the import rules; this file
// applies them and guards against what broken files hand us (null nodes, cycles,
// dangling bone names, unsorted or non-finite keys).

#include "io/importer.h"

#include "core/utf8.h"
#include "io/gltf_metadata.h"
#include "runtime/input_file.h"

#include <assimp/DefaultIOSystem.h>
#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <unordered_map>

namespace mlod {

namespace {

constexpr unsigned kPostProcess = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                  aiProcess_LimitBoneWeights | aiProcess_GenSmoothNormals |
                                  aiProcess_ValidateDataStructure;
constexpr std::size_t kMaxNodes = 1'000'000;
constexpr int kMaxFrames = 10'000'000;
// The highest frame rate a clip may have (Clip::validate()'s bound), fps.
constexpr double kMaxFps = 10000.0;

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

glm::mat4 toGlm(const aiMatrix4x4& m) {
  // Assimp is row-major (a1..a4 is the first row); GLM is column-major.
  return glm::mat4(m.a1, m.b1, m.c1, m.d1, m.a2, m.b2, m.c2, m.d2, m.a3, m.b3, m.c3, m.d3, m.a4, m.b4, m.c4, m.d4);
}
glm::vec3 toGlm(const aiVector3D& v) { return {v.x, v.y, v.z}; }
glm::quat toGlm(const aiQuaternion& q) { return glm::quat(q.w, q.x, q.y, q.z); }

bool isIdentity(const glm::mat4& m) {
  const glm::mat4 identity(1.0f);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (std::abs(m[c][r] - identity[c][r]) > 1e-6f)
        return false;
  return true;
}

std::string metadataString(const aiScene& scene, const char* key) {
  aiString value;
  if (scene.mMetaData && scene.mMetaData->Get(key, value))
    return value.C_Str();
  return {};
}

std::optional<double> metadataNumber(const aiScene& scene, const char* key) {
  if (!scene.mMetaData)
    return std::nullopt;
  for (unsigned i = 0; i < scene.mMetaData->mNumProperties; ++i) {
    if (std::string(scene.mMetaData->mKeys[i].C_Str()) != key)
      continue;
    const aiMetadataEntry& entry = scene.mMetaData->mValues[i];
    switch (entry.mType) {
    case AI_FLOAT: return *static_cast<const float*>(entry.mData);
    case AI_DOUBLE: return *static_cast<const double*>(entry.mData);
    case AI_INT32: return *static_cast<const std::int32_t*>(entry.mData);
    default: return std::nullopt;
    }
  }
  return std::nullopt;
}

// The <unit meter="..."/> of a Collada file's <asset> header, in metres per unit.
std::optional<double> colladaMetresPerUnit(const std::string& header) {
  const std::size_t unit = header.find("<unit");
  if (unit == std::string::npos)
    return std::nullopt;
  const std::size_t close = header.find('>', unit);
  const std::size_t meter = header.find("meter=", unit);
  if (meter == std::string::npos || (close != std::string::npos && meter > close))
    return std::nullopt;
  const std::size_t quote = meter + 6;
  if (quote >= header.size() || (header[quote] != '"' && header[quote] != '\''))
    return std::nullopt;
  const double value = std::strtod(header.c_str() + quote + 1, nullptr);
  if (!std::isfinite(value) || value <= 0.0)
    return std::nullopt;
  return value;
}

// One node of the scene graph, flattened in depth-first order (parents first).
struct FlatNode {
  const aiNode* node = nullptr;
  int parent = -1;
  glm::mat4 local{1.0f};
  glm::mat4 global{1.0f};
};

// Flattens the node graph, refusing cycles, null children and absurd sizes.
// `rootCorrection` is multiplied into the root node's transform.
Error flattenNodes(const aiNode* root, const glm::mat4& rootCorrection, std::vector<FlatNode>& out_nodes) {
  std::set<const aiNode*> seen;
  std::vector<std::pair<const aiNode*, int>> stack{{root, -1}};
  while (!stack.empty()) {
    auto [node, parent] = stack.back();
    stack.pop_back();
    if (!node)
      return Error("its node graph has a dangling (null) node");
    if (!seen.insert(node).second)
      return Error("its node graph is cyclic (node '" + std::string(node->mName.C_Str()) + "' is reached twice)");
    if (out_nodes.size() >= kMaxNodes)
      return Error("it has more than " + std::to_string(kMaxNodes) + " nodes");
    FlatNode flat;
    flat.node = node;
    flat.parent = parent;
    flat.local = toGlm(node->mTransformation);
    if (parent < 0)
      flat.local = flat.local * rootCorrection;
    flat.global = parent < 0 ? flat.local : out_nodes[static_cast<std::size_t>(parent)].global * flat.local;
    const int index = static_cast<int>(out_nodes.size());
    out_nodes.push_back(flat);
    if (node->mNumChildren > 0 && !node->mChildren)
      return Error("its node graph has a dangling (null) node");
    for (unsigned c = node->mNumChildren; c-- > 0;)
      stack.emplace_back(node->mChildren[c], index);
  }
  return {};
}

// Sample of a key track at `time` (ticks): the exact key where the time hits one,
// linear (or spherical) interpolation between keys, clamped outside them.
template <typename Key, typename Value, typename Lerp>
Value sampleKeys(const Key* keys, unsigned count, double time, Value fallback, Lerp lerp) {
  if (count == 0)
    return fallback;
  if (count == 1 || time <= keys[0].mTime)
    return keys[0].mValue;
  if (time >= keys[count - 1].mTime)
    return keys[count - 1].mValue;
  const Key* upper = std::upper_bound(keys, keys + count, time, [](double t, const Key& k) { return t < k.mTime; });
  const Key* below = upper - 1;
  if (below->mTime == time)
    return below->mValue;
  const double span = upper->mTime - below->mTime;
  const float a = span > 0.0 ? static_cast<float>((time - below->mTime) / span) : 0.0f;
  return lerp(below->mValue, upper->mValue, a);
}

template <typename Key>
bool keysSortedAndFinite(const Key* keys, unsigned count) {
  for (unsigned i = 0; i < count; ++i) {
    if (!std::isfinite(keys[i].mTime))
      return false;
    if (i > 0 && keys[i].mTime < keys[i - 1].mTime)
      return false;
  }
  return true;
}

bool nearlyEqual(const glm::vec3& a, const glm::vec3& b) {
  const float scale = std::max({1.0f, glm::length(a), glm::length(b)});
  return glm::length(a - b) <= 1e-6f * scale;
}
bool sameRotation(const glm::quat& a, const glm::quat& b) { return std::abs(glm::dot(a, b)) >= 1.0f - 1e-7f; }

// Whether a channel moves its node away from the rest pose at all.
bool channelAnimates(const aiNodeAnim& channel, const Transform& rest) {
  for (unsigned i = 0; i < channel.mNumPositionKeys; ++i)
    if (!nearlyEqual(toGlm(channel.mPositionKeys[i].mValue), rest.translation))
      return true;
  for (unsigned i = 0; i < channel.mNumRotationKeys; ++i)
    if (!sameRotation(glm::normalize(toGlm(channel.mRotationKeys[i].mValue)), rest.rotation))
      return true;
  for (unsigned i = 0; i < channel.mNumScalingKeys; ++i)
    if (!nearlyEqual(toGlm(channel.mScalingKeys[i].mValue), rest.scale))
      return true;
  return false;
}

// Gives a sampled channel's keys back (the scene is ours: convert() orphans it).
void releaseKeys(aiNodeAnim& channel) {
  delete[] channel.mPositionKeys;
  delete[] channel.mRotationKeys;
  delete[] channel.mScalingKeys;
  channel.mPositionKeys = nullptr;
  channel.mRotationKeys = nullptr;
  channel.mScalingKeys = nullptr;
  channel.mNumPositionKeys = channel.mNumRotationKeys = channel.mNumScalingKeys = 0;
}

// A BVH's "Frame Time:" (seconds per frame) and "Frames:" count. Assimp turns an "inf" time
// into 0 ticks per second (then 25 fps are assumed), 0 or NaN into a tick rate nobody can
// name, and 0 frames into a duration that wraps: the header says what is wrong instead. A
// file without them is Assimp's to refuse.
Error checkBvhHeader(std::string_view header) {
  const std::size_t at = header.find("Frame Time:");
  if (at == std::string_view::npos)
    return {};
  const std::size_t begin = header.find_first_not_of(" \t", at + 11);
  const std::size_t end = header.find_first_of("\r\n", at);
  const std::string value(begin == std::string_view::npos || begin >= end ? std::string_view()
                                                                           : header.substr(begin, end - begin));
  char* stop = nullptr;
  const double seconds = std::strtod(value.c_str(), &stop);
  if (value.empty() || stop == value.c_str() || !std::isfinite(seconds) || seconds < 1e-4)
    return Error("its Frame Time '" + value.substr(0, 40) +
                 "' is not a finite number of seconds per frame of at least 0.0001 (10,000 frames per second)");
  // "Frames: 0" made Assimp's duration frames - 1 wrap to 4,294,967,295 ("too long")
  const std::size_t frames = header.rfind("Frames:", at);
  if (frames != std::string_view::npos) {
    const std::size_t from = header.find_first_not_of(" \t", frames + 7);
    const std::size_t to = header.find_first_of("\r\n", frames);
    const std::string count(from == std::string_view::npos || from >= to ? std::string_view()
                                                                           : header.substr(from, to - from));
    char* countEnd = nullptr;
    const long long n = std::strtoll(count.c_str(), &countEnd, 10);
    if (count.empty() || countEnd == count.c_str() || n < 1)
      return Error("its 'Frames: " + count.substr(0, 40) + "' is not a count of at least 1 frame");
  }
  return {};
}

// The BVH header up to the end of its "Frame Time:" line (at most 16 MiB are looked at).
std::string bvhHeader(std::istream& stream) {
  std::string header;
  char buffer[1 << 16];
  while (stream && header.size() < (std::size_t(16) << 20)) {
    stream.read(buffer, sizeof buffer);
    header.append(buffer, static_cast<std::size_t>(stream.gcount()));
    const std::size_t at = header.find("Frame Time:");
    if (at != std::string::npos && header.find_first_of("\r\n", at) != std::string::npos)
      break;
  }
  return header;
}

std::string percentDecoded(const std::string& uri) {
  std::string out;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out.push_back(static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16)));
      i += 2;
    } else {
      out.push_back(uri[i]);
    }
  }
  return out;
}

// glTF buffers named by URI are read by Assimp from wherever the URI points: one that is
// absolute, has a scheme, or climbs out of the file's folder (../../../../etc/passwd) is
// refused, and so is one that is no regular file (a FIFO would block the import).
Error checkGltfBuffers(std::string_view json, const std::filesystem::path& folder) {
  const nlohmann::json doc = nlohmann::json::parse(json, nullptr, false);
  if (doc.is_discarded() || !doc.is_object() || !doc.contains("buffers") || !doc["buffers"].is_array())
    return {}; // Assimp's to refuse
  for (std::size_t b = 0; b < doc["buffers"].size(); ++b) {
    const nlohmann::json& buffer = doc["buffers"][b];
    if (!buffer.is_object() || !buffer.contains("uri") || !buffer["uri"].is_string())
      continue;
    const std::string uri = buffer["uri"].get<std::string>();
    if (uri.rfind("data:", 0) == 0)
      continue;
    const std::string where = "its buffer " + std::to_string(b) + " ('" + uri.substr(0, 80) + "')";
    const std::string decoded = percentDecoded(uri);
    const std::filesystem::path relative = std::filesystem::path(decoded).lexically_normal();
    const std::size_t colon = decoded.find(':');
    if (relative.is_absolute() || (colon != std::string::npos && colon < decoded.find('/')))
      return Error(where + " is not a path relative to the file's folder");
    if (!relative.empty() && *relative.begin() == "..")
      return Error(where + " lies outside the file's folder");
    const std::filesystem::path file = folder / relative;
    std::error_code error;
    if (std::filesystem::exists(file, error))
      if (std::string problem = inputFileProblem(file, kMaxImportFileBytes); !problem.empty())
        return Error(where + ": " + problem);
  }
  return {};
}

// A COLLADA <accessor> names more <param>s than its stride: Assimp 5.2 then reads each
// element's extra params past the source's array, so the same file gave other vertex
// positions on every run (issue 29: heights from 100 m to 7e27 cm). Refused with the
// accessor named. (A plain scan of the text: the accessors of a valid file hold params only.)
Error checkColladaAccessors(std::string_view text) {
  int index = 0;
  for (std::size_t at = text.find("<accessor"); at != std::string_view::npos; at = text.find("<accessor", at + 1)) {
    ++index;
    const std::size_t tagEnd = text.find('>', at);
    if (tagEnd == std::string_view::npos)
      return {}; // Assimp's to refuse
    const std::string_view tag = text.substr(at, tagEnd - at);
    const std::size_t close = text.find("</accessor>", tagEnd);
    const std::string_view body = close == std::string_view::npos ? std::string_view() : text.substr(tagEnd, close - tagEnd);
    int params = 0;
    for (std::size_t p = body.find("<param"); p != std::string_view::npos; p = body.find("<param", p + 1))
      ++params;
    long stride = 1; // COLLADA's default
    if (const std::size_t s = tag.find("stride=\""); s != std::string_view::npos)
      stride = std::strtol(std::string(tag.substr(s + 8, 12)).c_str(), nullptr, 10);
    if (params > stride)
      return Error("COLLADA accessor " + std::to_string(index) + " names " + std::to_string(params) +
                   " params but has a stride of " + std::to_string(stride) +
                   " (its elements would be read past its array)");
  }
  return {};
}

// What Assimp reads beside the file itself, checked first: a BVH's frame time, a glTF's
// buffers (the JSON of a .gltf, the JSON chunk of a .glb), COLLADA's accessors.
Error checkBeforeImport(const std::filesystem::path& file, const std::string& extension) {
  if (extension != "bvh" && extension != "gltf" && extension != "glb" && extension != "dae")
    return {};
  std::ifstream stream(file, std::ios::binary);
  if (extension == "bvh")
    return checkBvhHeader(bvhHeader(stream));
  if (extension == "dae") {
    std::optional<std::string> text = readInputFile(file, kMaxImportFileBytes);
    return text ? checkColladaAccessors(*text) : Error(); // (importAsset() said why already, or Assimp will)
  }
  std::string json;
  if (extension == "gltf") {
    std::optional<std::string> text = readInputFile(file, kMaxImportFileBytes);
    if (!text)
      return {}; // importAsset() said why already, or Assimp will
    json = std::move(*text);
  } else {
    std::uint32_t header[5] = {};
    stream.read(reinterpret_cast<char*>(header), sizeof header);
    constexpr std::uint32_t kJsonChunk = 0x4E4F534Au; // "JSON", little-endian
    std::error_code error;
    if (!stream || header[4] != kJsonChunk || header[3] > std::filesystem::file_size(file, error))
      return {}; // Assimp's to refuse
    json.resize(header[3]);
    stream.read(json.data(), static_cast<std::streamsize>(json.size()));
  }
  return checkGltfBuffers(json, file.parent_path());
}

class SceneConverter {
public:
  SceneConverter(const aiScene& scene, const ImportOptions& options, std::string sourcePath, std::string extension,
                 std::optional<double> colladaMetres, std::vector<GltfAnimationInfo> gltf)
      : m_scene(scene), m_options(options), m_extension(std::move(extension)), m_colladaMetres(colladaMetres),
        m_gltf(std::move(gltf)) {
    m_asset.sourcePath = std::move(sourcePath);
  }

  Result<Asset> run() {
    if (!m_scene.mRootNode)
      return Error("it has no root node");
    m_asset.format = metadataString(m_scene, "SourceAsset_Format");
    if (m_asset.format.empty())
      m_asset.format = m_extension;
    m_isBvh = lower(m_asset.format).rfind("bvh", 0) == 0 || m_extension == "bvh";
    chooseUnitScale();
    if (Error error = flattenNodes(m_scene.mRootNode, m_rootCorrection, m_nodes))
      return error;
    for (std::size_t i = 0; i < m_nodes.size(); ++i)
      m_nodeByName.emplace(m_nodes[i].node->mName.C_Str(), static_cast<int>(i));
    if (Error error = buildSkeleton())
      return error;
    for (unsigned a = 0; a < m_scene.mNumAnimations; ++a)
      if (Error error = buildClip(a))
        return error;
    attachClusters();
    // note: Assimp's BVH loader adds a generated skeleton mesh; it is no character mesh.
    if (!m_isBvh)
      if (Error error = buildMeshes())
        return error;
    if (m_asset.clips.empty() && m_asset.meshes.empty())
      return Error("it holds no animation and no triangle mesh");
    if (m_replacedNames > 0)
      m_asset.warnings.push_back(std::to_string(m_replacedNames) +
                                 " names (joints, clips, meshes) held bytes that are not UTF-8 (a Latin-1 file?); "
                                 "each such byte was replaced by U+FFFD");
    if (m_asset.unitSource == "guessed")
      guessUnitScale();
    if (Error error = m_asset.validate())
      return error;
    return std::move(m_asset);
  }

private:
  // A name from the file as valid UTF-8 (core/utf8.h): JSON cannot hold other bytes.
  std::string validName(std::string_view raw) {
    if (isValidUtf8(raw))
      return std::string(raw);
    ++m_replacedNames;
    return validUtf8(raw);
  }

  void chooseUnitScale() {
    const std::string format = lower(m_asset.format);
    const bool collada = format.find("collada") != std::string::npos || m_extension == "dae" || m_extension == "zae";
    // Assimp 5.2 scales a Collada root node by <unit meter>, so its scene is in metres. Where
    // we know that factor we divide it back out: joint offsets stay true file lengths.
    if (collada && m_colladaMetres)
      m_rootCorrection = glm::scale(glm::mat4(1.0f), glm::vec3(static_cast<float>(1.0 / *m_colladaMetres)));
    if (m_options.unitScale > 0.0) {
      m_asset.unitScale = m_options.unitScale;
      m_asset.unitSource = "option";
    } else if (format.find("gltf") != std::string::npos || m_extension == "gltf" || m_extension == "glb") {
      m_asset.unitScale = 100.0;
      m_asset.unitSource = "file"; // metres by the format's specification
    } else if (format.find("fbx") != std::string::npos || m_extension == "fbx") {
      const std::optional<double> factor = metadataNumber(m_scene, "UnitScaleFactor");
      const bool valid = factor && std::isfinite(*factor) && *factor > 0.0;
      m_asset.unitScale = valid ? *factor : 1.0;
      m_asset.unitSource = valid ? "file" : "guessed";
    } else if (collada) {
      if (m_colladaMetres) {
        m_asset.unitScale = *m_colladaMetres * 100.0;
        m_asset.unitSource = "file";
      } else {
        m_asset.unitScale = 100.0;
        m_asset.unitSource = "format";
      }
    } else {
      m_asset.unitScale = 1.0; // read at 1 cm per unit, then guessed: guessUnitScale()
      m_asset.unitSource = "guessed";
    }
  }

  // A file without a unit of its own was read at 1 cm per unit; the preset that makes it a
  // human height scales it (docs/architecture.md section 3), else it stays at 1 with a warning.
  void guessUnitScale() {
    const double height = standingHeightCm(m_asset);
    if (const UnitPreset* preset = guessUnitPreset(height)) {
      if (preset->cmPerUnit != 1.0)
        scaleAssetLengths(m_asset, preset->cmPerUnit);
      return;
    }
    char text[256];
    std::snprintf(text, sizeof text,
                  "the file states no unit and no preset makes its height (%.4g units) a human %g-%g cm; it was "
                  "kept at 1 cm per unit: set the unit if that is wrong",
                  height, kGuessMinHeightCm, kGuessMaxHeightCm);
    m_asset.warnings.push_back(text);
  }

  int nodeIndex(const aiString& name) const {
    const auto it = m_nodeByName.find(name.C_Str());
    return it == m_nodeByName.end() ? -1 : it->second;
  }

  bool isAncestorOrSelf(int ancestor, int node) const {
    for (int n = node; n >= 0; n = m_nodes[static_cast<std::size_t>(n)].parent)
      if (n == ancestor)
        return true;
    return false;
  }

  Error buildSkeleton() {
    std::set<int> seeds;
    if (!m_isBvh) {
      for (unsigned m = 0; m < m_scene.mNumMeshes; ++m) {
        const aiMesh* mesh = m_scene.mMeshes[m];
        if (!mesh)
          return Error("mesh " + std::to_string(m) + " is missing");
        for (unsigned b = 0; b < mesh->mNumBones; ++b) {
          const aiBone* bone = mesh->mBones[b];
          if (!bone)
            return Error("mesh '" + std::string(mesh->mName.C_Str()) + "' has a missing bone");
          const int node = nodeIndex(bone->mName);
          if (node < 0) {
            m_asset.warnings.push_back("bone '" + std::string(bone->mName.C_Str()) + "' of mesh '" +
                                       mesh->mName.C_Str() + "' names no node; its weights were left out");
            continue;
          }
          seeds.insert(node);
        }
      }
    }
    for (unsigned a = 0; a < m_scene.mNumAnimations; ++a) {
      const aiAnimation* animation = m_scene.mAnimations[a];
      if (!animation)
        return Error("animation " + std::to_string(a) + " is missing");
      for (unsigned c = 0; c < animation->mNumChannels; ++c) {
        const aiNodeAnim* channel = animation->mChannels[c];
        if (!channel)
          return Error("animation " + std::to_string(a) + " has a missing channel");
        const int node = nodeIndex(channel->mNodeName);
        if (node < 0) {
          m_asset.warnings.push_back("animation channel for '" + std::string(channel->mNodeName.C_Str()) +
                                     "', which is no node, was ignored");
          continue;
        }
        // A node with a channel is a joint; except that some exporters (X files, BCN_Epileptic)
        // give mesh nodes a channel that never moves them: those stay out of the skeleton.
        const FlatNode& flat = m_nodes[static_cast<std::size_t>(node)];
        if (m_isBvh || flat.node->mNumMeshes == 0 || channelAnimates(*channel, decompose(flat.local)))
          seeds.insert(node);
      }
    }
    if (seeds.empty())
      return {};

    // The lowest common ancestor of every seed becomes the root joint.
    int root = *seeds.begin();
    for (int seed : seeds)
      while (!isAncestorOrSelf(root, seed))
        root = m_nodes[static_cast<std::size_t>(root)].parent;
    std::vector<bool> isJoint(m_nodes.size(), false);
    for (int seed : seeds)
      for (int n = seed; n != root; n = m_nodes[static_cast<std::size_t>(n)].parent)
        isJoint[static_cast<std::size_t>(n)] = true;
    isJoint[static_cast<std::size_t>(root)] = true;
    // Leaf nodes without meshes below a joint are end effectors (BVH End Sites, "_Nub"s).
    for (std::size_t i = 0; i < m_nodes.size(); ++i) {
      const FlatNode& flat = m_nodes[i];
      if (!isJoint[i] && flat.parent >= 0 && isJoint[static_cast<std::size_t>(flat.parent)] &&
          flat.node->mNumChildren == 0 && flat.node->mNumMeshes == 0)
        isJoint[i] = true;
    }

    m_jointOfNode.assign(m_nodes.size(), -1);
    Skeleton& skeleton = m_asset.skeleton;
    std::set<std::string> names;
    const int rootParent = m_nodes[static_cast<std::size_t>(root)].parent;
    m_rootParentGlobal = rootParent >= 0 ? m_nodes[static_cast<std::size_t>(rootParent)].global : glm::mat4(1.0f);
    for (std::size_t i = 0; i < m_nodes.size(); ++i) {
      if (!isJoint[i])
        continue;
      if (skeleton.joints.size() >= 32767)
        return Error("its skeleton has more than 32767 joints");
      const FlatNode& flat = m_nodes[i];
      Joint joint;
      joint.name = validName(flat.node->mName.C_Str());
      if (joint.name.empty())
        joint.name = "joint" + std::to_string(skeleton.joints.size());
      if (!names.insert(joint.name).second) {
        const std::string original = joint.name;
        for (int k = 2; !names.insert(joint.name).second; ++k)
          joint.name = original + "#" + std::to_string(k);
        m_asset.warnings.push_back("two joints are named '" + original + "'; one was renamed '" + joint.name + "'");
      }
      joint.parent = static_cast<int>(i) == root ? -1 : m_jointOfNode[static_cast<std::size_t>(flat.parent)];
      const glm::mat4 local = static_cast<int>(i) == root ? m_rootParentGlobal * flat.local : flat.local;
      joint.rest = decompose(local);
      joint.rest.translation *= static_cast<float>(m_asset.unitScale);
      m_jointOfNode[i] = static_cast<int>(skeleton.joints.size());
      skeleton.joints.push_back(std::move(joint));
    }
    return {};
  }

  Error buildClip(unsigned animationIndex) {
    const aiAnimation& animation = *m_scene.mAnimations[animationIndex];
    Skeleton& skeleton = m_asset.skeleton;
    if (skeleton.empty())
      return {};
    std::string name = validName(animation.mName.C_Str());
    if (name.empty())
      name = "Take " + std::to_string(animationIndex + 1);
    for (const Clip& other : m_asset.clips)
      if (other.name == name)
        name += " (" + std::to_string(animationIndex + 1) + ")";
    const std::string where = "animation '" + name + "'";
    double ticksPerSecond = animation.mTicksPerSecond;
    if (!std::isfinite(ticksPerSecond) || ticksPerSecond < 0.0)
      return Error(where + " has an invalid tick rate");
    if (ticksPerSecond == 0.0) {
      ticksPerSecond = 25.0; // Assimp's convention for files that state none
      m_asset.warnings.push_back(where + " states no tick rate; 25 ticks per second assumed");
    }
    if (!std::isfinite(animation.mDuration) || animation.mDuration < 0.0)
      return Error(where + " has an invalid duration");

    Clip clip;
    clip.name = name;
    double framesExact = 0.0;
    if (m_isBvh) {
      // BVH: one key per frame at integer ticks, ticks per second = 1 / Frame Time. Files
      // write the frame time rounded (CMU: .0083333 for 1/120 s); a rate within 0.001 fps
      // of a whole number is that number.
      clip.fps = std::abs(ticksPerSecond - std::round(ticksPerSecond)) < 1e-3 ? std::round(ticksPerSecond)
                                                                              : ticksPerSecond;
      framesExact = animation.mDuration;
    } else if (const GltfAnimationInfo* info = gltfInfo(animationIndex); info && info->fps) {
      // A glTF that states its source's frame rate (docs/gltf-extension.md): keyed on those frames.
      clip.fps = *info->fps;
      framesExact = animation.mDuration / ticksPerSecond * clip.fps;
      if (info->frameCount && std::abs(framesExact + 1.0 - *info->frameCount) < 0.5)
        framesExact = *info->frameCount - 1;
      if (info->looping)
        clip.looping = *info->looping;
    } else {
      clip.fps = m_options.fps;
      framesExact = animation.mDuration / ticksPerSecond * clip.fps;
    }
    // the rate is checked before anything is resampled at it: a glTF stating 500,000 fps made
    // `info` resample for 24 s and reach 5.9 GB before the clip's own check refused it
    if (!(clip.fps > 0.0) || !std::isfinite(clip.fps) || clip.fps > kMaxFps)
      return Error(where + " has a frame rate of " + std::to_string(clip.fps) + " fps; it must be in (0, " +
                   std::to_string(static_cast<int>(kMaxFps)) + "] fps");
    if (framesExact + 1.0 > kMaxFrames)
      return Error(where + " is too long (" + std::to_string(framesExact) + " frames)");
    clip.frameCount = static_cast<int>(std::lround(framesExact)) + 1;
    clip.jointCount = skeleton.jointCount();
    // Joint after joint (the clip is joint-major), each joint's channel freed once sampled:
    // the clip's pages are touched only as they are filled while Assimp's keys are given
    // back, so a long clip and its keys never sit in memory whole at once.
    std::vector<aiNodeAnim*> channelOf(skeleton.joints.size(), nullptr);
    for (unsigned c = 0; c < animation.mNumChannels; ++c) {
      aiNodeAnim* channel = animation.mChannels[c];
      const int node = nodeIndex(channel->mNodeName);
      if (node < 0 || m_jointOfNode[static_cast<std::size_t>(node)] < 0)
        continue;
      if (!keysSortedAndFinite(channel->mPositionKeys, channel->mNumPositionKeys) ||
          !keysSortedAndFinite(channel->mRotationKeys, channel->mNumRotationKeys) ||
          !keysSortedAndFinite(channel->mScalingKeys, channel->mNumScalingKeys))
        return Error(where + " has key times that are not finite or not in order on '" +
                     std::string(channel->mNodeName.C_Str()) + "'");
      channelOf[static_cast<std::size_t>(m_jointOfNode[static_cast<std::size_t>(node)])] = channel;
    }
    const std::size_t frames = static_cast<std::size_t>(clip.frameCount);
    const std::size_t total = frames * skeleton.joints.size();
    clip.rotations.reserve(total);
    clip.translations.reserve(total);
    clip.scales.reserve(total);
    clip.hasRotation.assign(skeleton.joints.size(), 0);
    clip.hasTranslation.assign(skeleton.joints.size(), 0);
    clip.hasScale.assign(skeleton.joints.size(), 0);

    const float unit = static_cast<float>(m_asset.unitScale);
    const bool foldRoot = !isIdentity(m_rootParentGlobal);
    for (std::size_t j_ = 0; j_ < skeleton.joints.size(); ++j_) {
      const int j = static_cast<int>(j_);
      clip.rotations.resize(clip.rotations.size() + frames, skeleton.joints[j_].rest.rotation);
      clip.translations.resize(clip.translations.size() + frames, skeleton.joints[j_].rest.translation);
      clip.scales.resize(clip.scales.size() + frames, skeleton.joints[j_].rest.scale);
      aiNodeAnim* const animated = channelOf[j_];
      if (!animated)
        continue;
      const aiNodeAnim& channel = *animated;
      const int node = nodeIndex(channel.mNodeName);
      const Transform nodeRest = decompose(m_nodes[static_cast<std::size_t>(node)].local);
      clip.hasRotation[j_] = channel.mNumRotationKeys > 0;
      for (unsigned i = 0; i < channel.mNumPositionKeys && !clip.hasTranslation[j_]; ++i)
        clip.hasTranslation[j_] = !nearlyEqual(toGlm(channel.mPositionKeys[i].mValue), nodeRest.translation);
      for (unsigned i = 0; i < channel.mNumScalingKeys && !clip.hasScale[j_]; ++i)
        clip.hasScale[j_] = !nearlyEqual(toGlm(channel.mScalingKeys[i].mValue), nodeRest.scale);

      const auto vecLerp = [](const aiVector3D& a, const aiVector3D& b, float t) { return a + (b - a) * t; };
      const auto quatLerp = [](const aiQuaternion& a, const aiQuaternion& b, float t) {
        aiQuaternion out;
        aiQuaternion::Interpolate(out, a, b, t);
        return out;
      };
      const aiVector3D restT(nodeRest.translation.x, nodeRest.translation.y, nodeRest.translation.z);
      const aiVector3D restS(nodeRest.scale.x, nodeRest.scale.y, nodeRest.scale.z);
      const aiQuaternion restR(nodeRest.rotation.w, nodeRest.rotation.x, nodeRest.rotation.y, nodeRest.rotation.z);
      for (int f = 0; f < clip.frameCount; ++f) {
        const double ticks = m_isBvh ? f : f / clip.fps * ticksPerSecond;
        Transform local;
        local.translation = toGlm(sampleKeys(channel.mPositionKeys, channel.mNumPositionKeys, ticks, restT, vecLerp));
        local.scale = toGlm(sampleKeys(channel.mScalingKeys, channel.mNumScalingKeys, ticks, restS, vecLerp));
        const glm::quat q = toGlm(sampleKeys(channel.mRotationKeys, channel.mNumRotationKeys, ticks, restR, quatLerp));
        const float length = glm::length(q);
        // A zero or non-finite key stays as it is, so validate() names it.
        local.rotation = length > 0.0f && std::isfinite(length) ? q / length : q;
        if (j == 0 && foldRoot)
          local = decompose(m_rootParentGlobal * toMatrix(local));
        const std::size_t k = clip.index(j, f);
        clip.rotations[k] = local.rotation;
        clip.translations[k] = local.translation * unit;
        clip.scales[k] = local.scale;
      }
      releaseKeys(*animated);
    }
    m_asset.clips.push_back(std::move(clip));
    return {};
  }

  // What the glTF says of Assimp's animation `index` (Assimp keeps the file's order and names).
  const GltfAnimationInfo* gltfInfo(unsigned index) const {
    if (index >= m_gltf.size() || m_gltf.size() != m_scene.mNumAnimations)
      return nullptr;
    const std::string name = m_scene.mAnimations[index]->mName.C_Str();
    return name.empty() || name == m_gltf[index].name ? &m_gltf[index] : nullptr;
  }

  // The clusters of a glTF's MLOD_joint_clusters, per clip on the imported skeleton; a clip's
  // set that does not fit its joints and frames is dropped with a warning.
  void attachClusters() {
    bool any = false;
    for (unsigned a = 0; a < m_scene.mNumAnimations; ++a)
      if (const GltfAnimationInfo* info = gltfInfo(a))
        any = any || !info->clusters.empty();
    if (!any || m_asset.clips.size() != m_scene.mNumAnimations)
      return;
    for (unsigned a = 0; a < m_scene.mNumAnimations; ++a) {
      const Clip& clip = m_asset.clips[a];
      ClusterSet set;
      set.frameCount = clip.frameCount;
      set.joints.resize(static_cast<std::size_t>(m_asset.skeleton.jointCount()));
      std::string problem;
      if (const GltfAnimationInfo* info = gltfInfo(a))
        for (const auto& [name, clusters] : info->clusters) {
          const int joint = m_asset.skeleton.find(name);
          if (joint < 0)
            problem = "no joint '" + name + "'";
          else
            set.joints[static_cast<std::size_t>(joint)] = clusters;
        }
      if (problem.empty())
        if (Error error = set.validate())
          problem = error.message();
      if (!problem.empty()) {
        m_asset.warnings.push_back("MLOD_joint_clusters of animation '" + clip.name + "' ignored: " + problem);
        set.joints.assign(set.joints.size(), {});
      }
      m_asset.clusters.push_back(std::move(set));
    }
  }

  // Nearest joint at or above a node, or -1.
  int jointAtOrAbove(int node) const {
    for (int n = node; n >= 0; n = m_nodes[static_cast<std::size_t>(n)].parent)
      if (!m_jointOfNode.empty() && m_jointOfNode[static_cast<std::size_t>(n)] >= 0)
        return m_jointOfNode[static_cast<std::size_t>(n)];
    return -1;
  }

  Error buildMeshes() {
    Skeleton& skeleton = m_asset.skeleton;
    const std::vector<glm::mat4> restModels = skeleton.empty() ? std::vector<glm::mat4>{} : skeleton.restModelMatrices();
    SkinnedMesh character;
    SkinnedMesh fixed;
    int skippedFaces = 0;
    int degenerateFaces = 0;
    int unweighted = 0;
    const float unit = static_cast<float>(m_asset.unitScale);
    // Rest model matrices are in cm already; mesh data is still in file units until the end.
    const glm::mat4 toFileUnits = glm::scale(glm::mat4(1.0f), glm::vec3(1.0f / unit));
    const glm::mat4 toCm = glm::scale(glm::mat4(1.0f), glm::vec3(unit));

    for (std::size_t n = 0; n < m_nodes.size(); ++n) {
      const aiNode& node = *m_nodes[n].node;
      if (node.mNumMeshes > 0 && !node.mMeshes)
        return Error("node '" + std::string(node.mName.C_Str()) + "' has a dangling mesh list");
      for (unsigned k = 0; k < node.mNumMeshes; ++k) {
        const unsigned meshIndex = node.mMeshes[k];
        if (meshIndex >= m_scene.mNumMeshes || !m_scene.mMeshes[meshIndex])
          return Error("node '" + std::string(node.mName.C_Str()) + "' refers to mesh " + std::to_string(meshIndex) +
                       ", which does not exist");
        const aiMesh& mesh = *m_scene.mMeshes[meshIndex];
        if (mesh.mNumVertices == 0 || !mesh.mVertices)
          continue;
        const bool hasBones = mesh.mNumBones > 0 && !skeleton.empty();
        const int rigidJoint = hasBones ? -1 : jointAtOrAbove(static_cast<int>(n));
        SkinnedMesh& target = (hasBones || rigidJoint >= 0) ? character : fixed;
        const glm::mat4& meshGlobal = m_nodes[n].global; // file units
        // Model-space bind position = placement * mesh-space position.
        glm::mat4 placement = meshGlobal;
        if (hasBones) {
          // A skinned mesh's node transform is ignored when it is drawn (glTF says so, Assimp's
          // viewer does so): a vertex lands at boneGlobal * offset * v. So the mesh is placed
          // where the skeleton's rest pose puts it, through its heaviest bone; skinning gives
          // the same result for any placement, and merged meshes then agree on one bind pose.
          const int heaviest = heaviestBone(mesh);
          if (heaviest >= 0) {
            const aiBone& bone = *mesh.mBones[heaviest];
            const int j = m_jointOfNode[static_cast<std::size_t>(nodeIndex(bone.mName))];
            placement = toFileUnits * restModels[static_cast<std::size_t>(j)] * toCm * toGlm(bone.mOffsetMatrix);
          }
        } else if (rigidJoint >= 0) {
          const Joint& joint = skeleton.joints[static_cast<std::size_t>(rigidJoint)];
          const glm::mat4 jointRest = toFileUnits * restModels[static_cast<std::size_t>(rigidJoint)] * toCm;
          if (joint.inverseBind) {
            const glm::mat4 inverseBind = toFileUnits * *joint.inverseBind * toCm;
            placement = glm::inverse(inverseBind) * glm::inverse(jointRest) * meshGlobal;
          }
        }
        const glm::mat3 normalMatrix = glm::inverseTranspose(glm::mat3(placement));
        const auto base = static_cast<std::uint32_t>(target.positions.size());
        std::vector<std::vector<std::pair<int, float>>> influences;
        if (hasBones)
          influences.resize(mesh.mNumVertices);
        for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
          target.positions.push_back(glm::vec3(placement * glm::vec4(toGlm(mesh.mVertices[v]), 1.0f)) * unit);
          if (mesh.mNormals) {
            const glm::vec3 normal = normalMatrix * toGlm(mesh.mNormals[v]);
            const float length = glm::length(normal);
            target.normals.push_back(length > 0.0f && std::isfinite(length) ? normal / length : glm::vec3(0, 1, 0));
          } else {
            target.normals.push_back(glm::vec3(0, 1, 0));
          }
          target.uvs.push_back(mesh.mTextureCoords[0] ? glm::vec2(mesh.mTextureCoords[0][v].x, mesh.mTextureCoords[0][v].y)
                                                      : glm::vec2(0.0f));
        }
        if (hasBones) {
          for (unsigned b = 0; b < mesh.mNumBones; ++b) {
            const aiBone& bone = *mesh.mBones[b];
            const int boneNode = nodeIndex(bone.mName);
            if (boneNode < 0)
              continue; // warned about in buildSkeleton()
            const int j = m_jointOfNode[static_cast<std::size_t>(boneNode)];
            // Offset: mesh space -> bone space. Ours: model space -> joint space.
            glm::mat4 inverseBind = toGlm(bone.mOffsetMatrix) * glm::inverse(placement);
            inverseBind[3] = glm::vec4(glm::vec3(inverseBind[3]) * unit, 1.0f);
            Joint& joint = skeleton.joints[static_cast<std::size_t>(j)];
            if (!joint.inverseBind)
              joint.inverseBind = inverseBind;
            else if (!sameMatrix(*joint.inverseBind, inverseBind))
              m_asset.warnings.push_back("bone '" + joint.name + "' has different bind poses in different meshes; "
                                         "the first was kept");
            if (bone.mNumWeights > 0 && !bone.mWeights)
              return Error("bone '" + joint.name + "' has a dangling weight list");
            for (unsigned w = 0; w < bone.mNumWeights; ++w) {
              const aiVertexWeight& weight = bone.mWeights[w];
              if (weight.mVertexId >= mesh.mNumVertices)
                return Error("bone '" + joint.name + "' weights vertex " + std::to_string(weight.mVertexId) +
                             ", which does not exist");
              if (!std::isfinite(weight.mWeight) || weight.mWeight < 0.0f)
                return Error("bone '" + joint.name + "' has an invalid weight");
              influences[weight.mVertexId].emplace_back(j, weight.mWeight);
            }
          }
        }
        const int fallbackJoint = std::max(0, jointAtOrAbove(static_cast<int>(n)));
        for (unsigned v = 0; v < mesh.mNumVertices && &target == &character; ++v) {
          std::vector<int> joints;
          std::vector<float> weights;
          if (hasBones)
            for (const auto& [j, w] : influences[v]) {
              joints.push_back(j);
              weights.push_back(w);
            }
          glm::u16vec4 outJoints;
          glm::vec4 outWeights;
          if (!normalizeInfluences(joints.data(), weights.data(), static_cast<int>(joints.size()), outJoints, outWeights)) {
            const int rigid = rigidJoint >= 0 ? rigidJoint : fallbackJoint;
            if (hasBones)
              ++unweighted;
            outJoints = glm::u16vec4(static_cast<std::uint16_t>(rigid), 0, 0, 0);
            outWeights = glm::vec4(1.0f, 0.0f, 0.0f, 0.0f);
            ensureInverseBind(rigid, restModels);
          }
          character.joints.push_back(outJoints);
          character.weights.push_back(outWeights);
        }
        MeshPart part;
        part.name = validName(mesh.mName.length > 0 ? mesh.mName.C_Str() : node.mName.C_Str());
        part.firstIndex = static_cast<std::uint32_t>(target.indices.size());
        for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
          const aiFace& face = mesh.mFaces[f];
          if (face.mNumIndices != 3 || !face.mIndices) {
            ++skippedFaces;
            continue;
          }
          for (int i = 0; i < 3; ++i)
            if (face.mIndices[i] >= mesh.mNumVertices)
              return Error("mesh '" + part.name + "' has a face with a vertex index out of range");
          if (face.mIndices[0] == face.mIndices[1] || face.mIndices[1] == face.mIndices[2] ||
              face.mIndices[0] == face.mIndices[2]) {
            ++degenerateFaces;
            continue;
          }
          for (int i = 0; i < 3; ++i)
            target.indices.push_back(base + face.mIndices[i]);
        }
        part.indexCount = static_cast<std::uint32_t>(target.indices.size()) - part.firstIndex;
        if (part.indexCount > 0)
          target.parts.push_back(part);
      }
    }
    if (skippedFaces > 0)
      m_asset.warnings.push_back(std::to_string(skippedFaces) + " point and line primitives were left out");
    if (degenerateFaces > 0)
      m_asset.warnings.push_back(std::to_string(degenerateFaces) + " degenerate triangles (a vertex used twice) were left out");
    if (unweighted > 0)
      m_asset.warnings.push_back(std::to_string(unweighted) +
                                 " vertices of skinned meshes had no weights and were bound rigidly");
    const std::string stem = validName(std::filesystem::path(m_asset.sourcePath).stem().string());
    character.name = stem.empty() ? "character" : stem;
    fixed.name = skeleton.empty() ? character.name : "static";
    for (SkinnedMesh* mesh : {&character, &fixed}) {
      if (mesh->indices.empty())
        continue;
      m_asset.meshes.push_back(std::move(*mesh));
    }
    return {};
  }

  // The bone of `mesh` (naming a node) with the largest total weight, or -1.
  int heaviestBone(const aiMesh& mesh) const {
    int best = -1;
    double bestWeight = -1.0;
    for (unsigned b = 0; b < mesh.mNumBones; ++b) {
      const aiBone& bone = *mesh.mBones[b];
      if (nodeIndex(bone.mName) < 0)
        continue;
      double total = 0.0;
      for (unsigned w = 0; w < bone.mNumWeights && bone.mWeights; ++w)
        total += std::isfinite(bone.mWeights[w].mWeight) ? bone.mWeights[w].mWeight : 0.0;
      if (total > bestWeight) {
        bestWeight = total;
        best = static_cast<int>(b);
      }
    }
    return best;
  }

  static bool sameMatrix(const glm::mat4& a, const glm::mat4& b) {
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (std::abs(a[c][r] - b[c][r]) > 1e-3f * std::max(1.0f, std::abs(a[c][r])))
          return false;
    return true;
  }

  void ensureInverseBind(int joint, const std::vector<glm::mat4>& restModels) {
    Joint& target = m_asset.skeleton.joints[static_cast<std::size_t>(joint)];
    if (!target.inverseBind)
      target.inverseBind = glm::inverse(restModels[static_cast<std::size_t>(joint)]);
  }

  const aiScene& m_scene;
  const ImportOptions& m_options;
  std::string m_extension;
  std::optional<double> m_colladaMetres;
  std::vector<GltfAnimationInfo> m_gltf; // per animation of a glTF file; empty for other formats
  Asset m_asset;
  bool m_isBvh = false;
  std::vector<FlatNode> m_nodes;
  std::unordered_map<std::string, int> m_nodeByName;
  std::vector<int> m_jointOfNode;
  glm::mat4 m_rootParentGlobal{1.0f};
  glm::mat4 m_rootCorrection{1.0f};
  int m_replacedNames = 0;
};

// Every file Assimp opens goes through this: the file itself and what it names beside it
// (an OBJ's mtllib, a glTF's buffers ...). One that exists and is no regular file of bounded
// size is refused before it is opened (a FIFO blocked the import until its timeout, a link
// to /dev/zero would never end): Assimp sees it as missing, and the import fails with the
// reason. A side file that does not exist is Assimp's to report, as before.
class SideFileGuard : public Assimp::DefaultIOSystem {
public:
  bool Exists(const char* file) const override { return !refused(file) && DefaultIOSystem::Exists(file); }
  Assimp::IOStream* Open(const char* file, const char* mode = "rb") override {
    return refused(file) ? nullptr : DefaultIOSystem::Open(file, mode);
  }
  // The first side file refused and why; empty when none was.
  const std::string& problem() const { return m_problem; }

private:
  bool refused(const char* file) const {
    if (!file)
      return false;
    std::error_code error;
    if (!std::filesystem::exists(std::filesystem::status(file, error)))
      return false;
    std::string problem = inputFileProblem(file, kMaxImportFileBytes);
    if (problem.empty())
      return false;
    if (m_problem.empty())
      m_problem = "the file it reads beside it, '" + std::string(file) + "', is refused: " + problem;
    return true;
  }
  mutable std::string m_problem;
};

// The guard that `importer` (configured by configure()) opens its files through.
const SideFileGuard& sideFileGuard(const Assimp::Importer& importer) {
  return *static_cast<const SideFileGuard*>(importer.GetIOHandler());
}

void configure(Assimp::Importer& importer) {
  // FBX: fold pivots into the nodes instead of inserting helper nodes into the hierarchy.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, false);
  importer.SetPropertyInteger(AI_CONFIG_PP_LBW_MAX_WEIGHTS, kMaxInfluences);
  importer.SetIOHandler(new SideFileGuard); // the importer owns it
}

// Assimp 5.2.5 reads a glTF rotation output of normalized integers (SHORT, which the glTF
// exporter writes, or BYTE) as if its bytes were floats: the keys that gltf_metadata.h decoded
// from the file replace them, channel by channel (Assimp keeps the file's animations in order,
// one channel per node, every key of the sampler). A file whose keys cannot be decoded, or
// that Assimp read into other channels, is refused rather than played wrong.
Error putNormalizedRotations(const std::vector<GltfAnimationInfo>& gltf, aiScene& scene) {
  for (std::size_t a = 0; a < gltf.size(); ++a) {
    const GltfAnimationInfo& info = gltf[a];
    if (!info.normalizedRotationProblem.empty())
      return Error(info.normalizedRotationProblem);
    if (info.normalizedRotations.empty())
      continue;
    if (gltf.size() != scene.mNumAnimations)
      return Error("Assimp read " + std::to_string(scene.mNumAnimations) + " of the file's " +
                   std::to_string(gltf.size()) + " animations, so its normalized rotation keys cannot be placed");
    const aiAnimation& animation = *scene.mAnimations[a];
    for (const auto& [node, keys] : info.normalizedRotations) {
      aiNodeAnim* channel = nullptr;
      for (unsigned c = 0; c < animation.mNumChannels && !channel; ++c)
        if (animation.mChannels[c] && node == animation.mChannels[c]->mNodeName.C_Str())
          channel = animation.mChannels[c];
      if (!channel || channel->mNumRotationKeys != keys.size())
        return Error("the rotation keys of node '" + node + "' in animation '" + info.name +
                     "' are normalized integers, and Assimp read " +
                     (channel ? std::to_string(channel->mNumRotationKeys) + " keys of " + std::to_string(keys.size())
                              : std::string("no such channel")));
      for (std::size_t k = 0; k < keys.size(); ++k)
        channel->mRotationKeys[k].mValue = aiQuaternion(keys[k].w, keys[k].x, keys[k].y, keys[k].z);
    }
  }
  return {};
}

// The scene made ours and the importer (its loaders' buffers: a BVH's whole text and
// channel values) let go before the conversion, so they do not sit beside the clips.
Result<Asset> convert(std::unique_ptr<Assimp::Importer> importer, const aiScene* read, const std::string& sourcePath,
                      const std::string& extension, const ImportOptions& options, std::optional<double> colladaMetres,
                      std::string_view gltfBytes) {
  if (!read) {
    std::string reason = importer->GetErrorString();
    if (reason.empty())
      reason = "Assimp could not read it";
    // a glTF compressed with meshoptimizer (the glTF exporter's compress=meshopt): say so
    // rather than Assimp's "buffer with non-zero length missing the uri attribute"
    for (const std::string& required : requiredGltfExtensions(gltfBytes))
      if (required == "EXT_meshopt_compression")
        return Error("it is compressed with EXT_meshopt_compression, which Assimp 5.2 cannot read (three.js, "
                     "Babylon.js and gltf-transform can; export it without compress=meshopt to read it here)");
    // Assimp catches the allocation failure itself and keeps only its what().
    if (reason.find("bad_alloc") != std::string::npos)
      reason = "it needs more memory than the import may use (the file may be broken)";
    return Error(reason);
  }
  const std::unique_ptr<aiScene> scene(importer->GetOrphanedScene());
  importer.reset();
  if (!(options.fps > 0.0) || !std::isfinite(options.fps) || options.fps > kMaxFps)
    return Error("the resampling rate must be in (0, 10000] fps");
  if (!std::isfinite(options.unitScale) || options.unitScale < 0.0)
    return Error("the unit scale must be a positive number of cm per unit");
  try {
    std::vector<std::string> warnings;
    std::vector<GltfAnimationInfo> gltf = readGltfAnimationInfo(gltfBytes, warnings);
    if (Error error = putNormalizedRotations(gltf, *scene))
      return error;
    Result<Asset> asset = SceneConverter(*scene, options, sourcePath, extension, colladaMetres, std::move(gltf)).run();
    if (asset)
      asset->warnings.insert(asset->warnings.end(), warnings.begin(), warnings.end());
    return asset;
  } catch (const std::bad_alloc&) {
    return Error("it needs more memory than the import may use (the file may be broken)");
  } catch (const std::exception& e) {
    return Error(e.what());
  }
}

std::optional<double> colladaUnitOf(const std::string& extension, const std::string& head) {
  if (extension != "dae")
    return std::nullopt;
  return colladaMetresPerUnit(head);
}

} // namespace

Result<Asset> importAsset(const std::string& path, const ImportOptions& options) {
  const std::filesystem::path file(path);
  if (std::string problem = inputFileProblem(file, kMaxImportFileBytes); !problem.empty())
    return Error(problem);
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  if (size == 0)
    return Error("the file is empty");
  std::ifstream stream(file, std::ios::binary);
  if (!stream)
    return Error("cannot open it for reading");
  std::string head(4096, '\0');
  stream.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(stream.gcount()));
  std::string extension = lower(file.extension().string());
  if (!extension.empty())
    extension.erase(0, 1);

  if (Error error = checkBeforeImport(file, extension))
    return error;
  auto importer = std::make_unique<Assimp::Importer>();
  configure(*importer);
  try {
    const aiScene* scene = importer->ReadFile(path, kPostProcess);
    if (const std::string& refused = sideFileGuard(*importer).problem(); !refused.empty())
      return Error(refused);
    std::string gltf; // a glTF's own JSON: what it states beyond what Assimp reads (or why it failed)
    if (extension == "glb" || extension == "gltf") {
      stream.clear();
      stream.seekg(0);
      gltf.resize(static_cast<std::size_t>(size));
      stream.read(gltf.data(), static_cast<std::streamsize>(gltf.size()));
      gltf.resize(static_cast<std::size_t>(stream.gcount()));
    }
    return convert(std::move(importer), scene, path, extension, options, colladaUnitOf(extension, head), gltf);
  } catch (const std::bad_alloc&) {
    return Error("it needs more memory than the import may use (the file may be broken)");
  } catch (const std::exception& e) {
    return Error(e.what());
  }
}

Result<Asset> importAssetFromMemory(const void* data, std::size_t size, const std::string& extension,
                                    const ImportOptions& options) {
  if (size == 0 || !data)
    return Error("the file is empty");
  const std::string ext = lower(extension);
  if (ext == "bvh")
    if (Error error = checkBvhHeader(std::string_view(static_cast<const char*>(data), size)))
      return error;
  if (ext == "dae")
    if (Error error = checkColladaAccessors(std::string_view(static_cast<const char*>(data), size)))
      return error;
  auto importer = std::make_unique<Assimp::Importer>();
  configure(*importer);
  try {
    const aiScene* scene = importer->ReadFileFromMemory(data, size, kPostProcess, ext.c_str());
    if (const std::string& refused = sideFileGuard(*importer).problem(); !refused.empty())
      return Error(refused);
    const std::string head(static_cast<const char*>(data), std::min<std::size_t>(size, 4096));
    const bool gltf = ext == "glb" || ext == "gltf";
    return convert(std::move(importer), scene, "memory." + ext, ext, options, colladaUnitOf(ext, head),
                   gltf ? std::string_view(static_cast<const char*>(data), size) : std::string_view());
  } catch (const std::bad_alloc&) {
    return Error("it needs more memory than the import may use (the file may be broken)");
  } catch (const std::exception& e) {
    return Error(e.what());
  }
}

} // namespace mlod
