#include "gltf_writer.h"

#include "core/lod/error_budget.h"
#include "core/lod/held_keys.h"
#include "core/lod_clip_builder.h"

#include <algorithm>
#include <cassert>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <glm/gtc/quaternion.hpp>
#include <meshoptimizer.h>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <span>
#include <sstream>
#include <string>
#include <tiny_gltf.h>
#include <unordered_map>

namespace mlod::gltf {

namespace {

using nlohmann::json;
using tinygltf::Value;

// glTF enums (the specification's, as tinygltf names them).
constexpr int kArrayBuffer = TINYGLTF_TARGET_ARRAY_BUFFER;
constexpr int kElementArrayBuffer = TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER;
constexpr int kNoTarget = 0;

Value number(double x) {
  return Value(x);
}
Value integer(int i) {
  return Value(i);
}

// A unit quaternion with w written last, as glTF stores it; q and -q are the same rotation.
glm::quat unit(const glm::quat& q) {
  const float length = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
  return length > 0.0f && std::isfinite(length) ? q * (1.0f / length) : glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
}

// S * m * S^-1 with S = scale(kMetresPerCm): the same transform on lengths in metres.
glm::mat4 toMetres(const glm::mat4& m) {
  glm::mat4 out = m;
  const float s = static_cast<float>(kMetresPerCm);
  for (int row = 0; row < 3; ++row) {
    out[3][row] = m[3][row] * s; // translation
    out[row][3] = m[row][3] / s; // projective row (0 for affine matrices)
  }
  return out;
}

// How EXT_meshopt_compression encodes one buffer view (compressMeshopt()): element size,
// TRIANGLES (an index buffer) or ATTRIBUTES, and the filter its bytes already went through.
struct ViewCodec {
  std::size_t stride = 0;
  bool triangles = false;
  const char* filter = nullptr; // "QUATERNION", "OCTAHEDRAL" or none
};

// Bits per quaternion component under meshopt's QUATERNION filter (4..16): the most it keeps.
constexpr int kQuatFilterBits = 16;

// Builds the one buffer, its views and accessors.
class Builder {
public:
  Builder(tinygltf::Model& model, Compression compression, bool floatRotations)
      : m_model(model), m_compression(compression), m_floatRotations(floatRotations) {
    m_model.buffers.emplace_back();
  }

  Compression compression() const { return m_compression; }
  const std::vector<ViewCodec>& codecs() const { return m_codecs; }
  // The largest angle (degrees) between a rotation key and what a reader decodes from the file.
  double rotationErrorDegrees() const { return m_rotationError; }

  int view(const void* data, std::size_t bytes, int target, std::size_t stride = 4, bool triangles = false,
           const char* filter = nullptr) {
    m_codecs.push_back({stride, triangles, filter});
    std::vector<unsigned char>& buffer = m_model.buffers[0].data;
    buffer.resize((buffer.size() + 3) / 4 * 4, 0); // every component type here is at most 4 bytes
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = buffer.size();
    v.byteLength = bytes;
    v.target = target;
    const auto* begin = static_cast<const unsigned char*>(data);
    buffer.insert(buffer.end(), begin, begin + bytes);
    m_model.bufferViews.push_back(std::move(v));
    return static_cast<int>(m_model.bufferViews.size()) - 1;
  }

  // Float elements of `components` each (type: TINYGLTF_TYPE_*); bounds where asked.
  int floats(const std::vector<float>& values, int components, int type, int target, bool bounds) {
    tinygltf::Accessor a;
    a.bufferView = view(values.data(), values.size() * sizeof(float), target,
                        sizeof(float) * static_cast<std::size_t>(components));
    a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    a.type = type;
    a.count = values.size() / static_cast<std::size_t>(components);
    if (bounds) {
      a.minValues.assign(static_cast<std::size_t>(components), std::numeric_limits<double>::infinity());
      a.maxValues.assign(static_cast<std::size_t>(components), -std::numeric_limits<double>::infinity());
      for (std::size_t i = 0; i < values.size(); ++i) {
        const std::size_t c = i % static_cast<std::size_t>(components);
        a.minValues[c] = std::min(a.minValues[c], static_cast<double>(values[i]));
        a.maxValues[c] = std::max(a.maxValues[c], static_cast<double>(values[i]));
      }
    }
    return push(std::move(a));
  }

  template <typename T>
  int integers(const std::vector<T>& values, int componentType, int components, int type, int target) {
    tinygltf::Accessor a;
    a.bufferView = view(values.data(), values.size() * sizeof(T), target,
                        sizeof(T) * static_cast<std::size_t>(components), target == kElementArrayBuffer);
    a.componentType = componentType;
    a.type = type;
    a.count = values.size() / static_cast<std::size_t>(components);
    return push(std::move(a));
  }

  // Animation data: an accessor holding exactly these values already is shared (the same
  // key times between channels; tracks a coarser level leaves as they were).
  int shared(const std::vector<float>& values, int components, int type, bool bounds) {
    std::string key(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float));
    key += static_cast<char>(type);
    const auto found = m_shared.find(key);
    if (found != m_shared.end())
      return found->second;
    const int accessor = floats(values, components, type, kNoTarget, bounds);
    m_shared.emplace(std::move(key), accessor);
    return accessor;
  }

  // Rotation keys (x, y, z, w, unit) as normalized signed 16-bit integers, shared like
  // shared(): rounded (quantizeRotations(), core/lod/held_keys.h), or under meshopt's
  // QUATERNION filter when compressing. Keeps the largest error a reader will see.
  int rotations(const std::vector<float>& values) {
    if (m_floatRotations)
      return shared(values, 4, TINYGLTF_TYPE_VEC4, false);
    const std::size_t keys = values.size() / 4;
    std::vector<std::int16_t> shorts(values.size());
    std::vector<std::int16_t> decoded;
    if (m_compression == Compression::Meshopt) {
      meshopt_encodeFilterQuat(shorts.data(), keys, 8, kQuatFilterBits, values.data());
      decoded = shorts;
      meshopt_decodeFilterQuat(decoded.data(), keys, 8);
    } else {
      shorts = quantizeRotations(values);
      decoded = shorts;
    }
    for (std::size_t k = 0; k < keys; ++k) {
      const glm::quat key(values[4 * k + 3], values[4 * k], values[4 * k + 1], values[4 * k + 2]);
      m_rotationError = std::max(m_rotationError, rotationAngleDegrees(key, dequantizeRotation(&decoded[4 * k])));
    }
    std::string key(reinterpret_cast<const char*>(shorts.data()), shorts.size() * sizeof(std::int16_t));
    key += 'q';
    const auto found = m_shared.find(key);
    if (found != m_shared.end())
      return found->second;
    tinygltf::Accessor a;
    a.bufferView = view(shorts.data(), shorts.size() * sizeof(std::int16_t), kNoTarget, 8, false,
                        m_compression == Compression::Meshopt ? "QUATERNION" : nullptr);
    a.componentType = TINYGLTF_COMPONENT_TYPE_SHORT;
    a.normalized = true;
    a.type = TINYGLTF_TYPE_VEC4;
    a.count = keys;
    const int accessor = push(std::move(a));
    m_shared.emplace(std::move(key), accessor);
    return accessor;
  }

  // Unit normals as 8-bit normalized integers under meshopt's OCTAHEDRAL filter, 4 bytes a
  // vertex (x, y, z and a pad), a vertex buffer: KHR_mesh_quantization.
  int octNormals(const std::vector<float>& xyz) {
    const std::size_t n = xyz.size() / 3;
    std::vector<float> xyzw;
    xyzw.reserve(n * 4);
    for (std::size_t i = 0; i < n; ++i)
      xyzw.insert(xyzw.end(), {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2], 0.0f});
    std::vector<std::int8_t> bytes(n * 4);
    meshopt_encodeFilterOct(bytes.data(), n, 4, 8, xyzw.data());
    tinygltf::Accessor a;
    a.bufferView = view(bytes.data(), bytes.size(), kArrayBuffer, 4, false, "OCTAHEDRAL");
    m_model.bufferViews.back().byteStride = 4;
    a.componentType = TINYGLTF_COMPONENT_TYPE_BYTE;
    a.normalized = true;
    a.type = TINYGLTF_TYPE_VEC3;
    a.count = n;
    m_quantizedMesh = true;
    return push(std::move(a));
  }
  bool quantizedMesh() const { return m_quantizedMesh; }

  // Key times (seconds, with bounds) of `frames` at `fps`.
  int times(const std::vector<int>& frames, double fps) {
    std::vector<float> seconds(frames.size());
    for (std::size_t i = 0; i < frames.size(); ++i)
      seconds[i] = static_cast<float>(frames[i] / fps);
    return shared(seconds, 1, TINYGLTF_TYPE_SCALAR, true);
  }

private:
  int push(tinygltf::Accessor a) {
    m_model.accessors.push_back(std::move(a));
    return static_cast<int>(m_model.accessors.size()) - 1;
  }

  tinygltf::Model& m_model;
  Compression m_compression;
  bool m_floatRotations = false;
  std::unordered_map<std::string, int> m_shared;
  std::vector<ViewCodec> m_codecs; // per buffer view
  double m_rotationError = 0.0;
  bool m_quantizedMesh = false;
};

void addChannel(tinygltf::Animation& animation, int node, const char* path, int input, int output) {
  tinygltf::AnimationSampler sampler;
  sampler.input = input;
  sampler.output = output;
  sampler.interpolation = "LINEAR";
  animation.samplers.push_back(std::move(sampler));
  tinygltf::AnimationChannel channel;
  channel.sampler = static_cast<int>(animation.samplers.size()) - 1;
  channel.target_node = node;
  channel.target_path = path;
  animation.channels.push_back(std::move(channel));
}

// The level's motion of one clip as an animation of the joint nodes 0 .. J-1, named
// `name`; `extras` describes it (fps, frame count, clip, level).
Result<tinygltf::Animation> levelAnimation(Builder& builder, const LodPackage& package, const LodPackageLevel& level,
                                           std::size_t clipIndex, const std::string& name) {
  const Clip& clip = package.clips[clipIndex];
  const int joints = package.skeleton.jointCount();
  if (clip.jointCount != joints)
    return Error("clip '" + clip.name + "' does not animate the package's skeleton");
  const ClusterSet* clusters =
      clipIndex < level.build.motion.clusters.size() ? &level.build.motion.clusters[clipIndex] : nullptr;
  if (clusters && !clusters->joints.empty() && clusters->jointCount() != joints)
    return Error("the clusters of clip '" + clip.name + "' at level " + std::to_string(level.index) +
                 " are not of the package's skeleton");

  // every joint keyed (core/lod/held_keys.h): a clip played after another leaves nothing of it
  tinygltf::Animation animation;
  animation.name = name;
  for (const LevelTrack& track : levelTracks(package, level, clipIndex)) {
    const bool rotation = track.path == TrackPath::Rotation;
    const int output = rotation ? builder.rotations(track.values)
                                : builder.shared(track.values, track.components(), TINYGLTF_TYPE_VEC3, false);
    const char* path = rotation ? "rotation" : track.path == TrackPath::Translation ? "translation" : "scale";
    addChannel(animation, track.joint, path, builder.times(track.frames, clip.fps), output);
  }
  // glTF keeps no frame rate: the source's, so that readers can key on its frames again.
  Value::Object extras;
  extras["fps"] = number(clip.fps);
  extras["frameCount"] = integer(clip.frameCount);
  extras["clip"] = Value(clip.name);
  extras["looping"] = Value(clip.looping);
  extras["level"] = integer(level.index);
  extras["levelName"] = Value(level.settings.name);
  animation.extras = Value(std::move(extras));
  return animation;
}

// Orders the triangles `inout_local` (indices into `inout_vertices`, every one used) for the
// GPU's post-transform vertex cache, then the vertices in the order those triangles first use
// them (meshoptimizer 0.18: meshopt_optimizeVertexCache, meshopt_optimizeVertexFetchRemap).
// `inout_vertices` (the source vertex of each) is permuted with the indices, so every
// attribute written from it, skin joints and weights included, follows. The triangles stay
// the same, each with its corners in the same order (winding kept).
void optimizeForGpu(std::vector<std::uint32_t>& inout_local, std::vector<std::uint32_t>& inout_vertices) {
  static_assert(sizeof(unsigned int) == sizeof(std::uint32_t));
  const std::size_t n = inout_vertices.size();
  unsigned int* indices = reinterpret_cast<unsigned int*>(inout_local.data());
  meshopt_optimizeVertexCache(indices, indices, inout_local.size(), n);
  std::vector<unsigned int> fetch(n);
  const std::size_t used = meshopt_optimizeVertexFetchRemap(fetch.data(), indices, inout_local.size(), n);
  assert(used == n); // the primitive holds only the vertices its triangles use
  (void)used;
  meshopt_remapIndexBuffer(indices, indices, inout_local.size(), fetch.data());
  std::vector<std::uint32_t> reordered(n);
  for (std::size_t i = 0; i < n; ++i)
    reordered[fetch[i]] = inout_vertices[i];
  inout_vertices = std::move(reordered);
}

// One primitive: the triangles `indices` (into `mesh`) with the vertices they use, ordered
// for the GPU (optimizeForGpu()), bound to the one skin of the full skeleton.
Result<tinygltf::Primitive> primitiveOf(Builder& builder, const SkinnedMesh& mesh,
                                        std::span<const std::uint32_t> indices, int jointCount,
                                        const std::string& name) {
  const std::size_t total = mesh.positions.size();
  std::vector<std::uint32_t> remap(total, UINT32_MAX);
  std::vector<std::uint32_t> vertices; // of `mesh`, per vertex of the primitive
  std::vector<std::uint32_t> local;    // the triangles, in the primitive's vertices
  local.reserve(indices.size());
  for (std::uint32_t i : indices) {
    if (i >= total)
      return Error("the mesh of " + name + " has an index out of range");
    if (remap[i] == UINT32_MAX) {
      remap[i] = static_cast<std::uint32_t>(vertices.size());
      vertices.push_back(i);
    }
    local.push_back(remap[i]);
  }
  const std::size_t n = vertices.size();
  optimizeForGpu(local, vertices);
  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;

  std::vector<float> values;
  values.reserve(n * 4);
  const float s = static_cast<float>(kMetresPerCm);
  for (std::uint32_t v : vertices) {
    const glm::vec3& p = mesh.positions[v];
    values.insert(values.end(), {p.x * s, p.y * s, p.z * s});
  }
  primitive.attributes["POSITION"] = builder.floats(values, 3, TINYGLTF_TYPE_VEC3, kArrayBuffer, true);

  if (mesh.normals.size() == total) {
    values.clear();
    for (std::uint32_t v : vertices) {
      // Unit length in float, as the specification asks; a degenerate normal gets +Z.
      const glm::vec3& m = mesh.normals[v];
      const double length = std::sqrt(double(m.x) * m.x + double(m.y) * m.y + double(m.z) * m.z);
      const glm::vec3 u =
          length > 1e-12 && std::isfinite(length) ? glm::vec3(glm::dvec3(m) / length) : glm::vec3(0.0f, 0.0f, 1.0f);
      values.insert(values.end(), {u.x, u.y, u.z});
    }
    primitive.attributes["NORMAL"] = builder.compression() == Compression::Meshopt
                                         ? builder.octNormals(values)
                                         : builder.floats(values, 3, TINYGLTF_TYPE_VEC3, kArrayBuffer, false);
  }
  if (mesh.uvs.size() == total) {
    values.clear();
    for (std::uint32_t v : vertices) // core keeps Assimp's origin (bottom left); glTF's is top left
      values.insert(values.end(), {mesh.uvs[v].x, 1.0f - mesh.uvs[v].y});
    primitive.attributes["TEXCOORD_0"] = builder.floats(values, 2, TINYGLTF_TYPE_VEC2, kArrayBuffer, false);
  }
  if (mesh.skinned()) {
    if (mesh.joints.size() != total || mesh.weights.size() != total)
      return Error("the mesh of " + name + " has influences for " + std::to_string(mesh.weights.size()) + " of " +
                   std::to_string(total) + " vertices");
    std::vector<std::uint16_t> joints;
    joints.reserve(n * 4);
    values.clear();
    for (std::uint32_t v : vertices) {
      glm::vec4 w = mesh.weights[v];
      glm::u16vec4 jv = mesh.joints[v];
      // Exactly 1 in float (x + y + z + w): the residual of the rounding goes to the largest
      // weight (TOOLCHAIN.md); core's meshes already are, so this changes nothing there.
      int largest = 0;
      for (int k = 1; k < 4; ++k)
        if (w[k] > w[largest])
          largest = k;
      if (!(w[largest] > 0.0f))
        return Error("vertex " + std::to_string(v) + " of " + name + " has no positive weight");
      const float sum = w.x + w.y + w.z + w.w;
      if (sum != 1.0f) {
        for (int k = 0; k < 4; ++k)
          w[k] /= sum;
        w[largest] += 1.0f - (w.x + w.y + w.z + w.w);
      }
      for (int k = 0; k < 4; ++k) {
        if (w[k] == 0.0f)
          jv[k] = 0; // the validator expects unused slots at joint 0
        else if (jv[k] >= jointCount)
          return Error("vertex " + std::to_string(v) + " of " + name + " names joint " + std::to_string(jv[k]) +
                       " of " + std::to_string(jointCount));
        joints.push_back(jv[k]);
      }
      values.insert(values.end(), {w.x, w.y, w.z, w.w});
    }
    if (jointCount <= 256) {
      const std::vector<std::uint8_t> bytes(joints.begin(), joints.end());
      primitive.attributes["JOINTS_0"] =
          builder.integers(bytes, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, 4, TINYGLTF_TYPE_VEC4, kArrayBuffer);
    } else {
      primitive.attributes["JOINTS_0"] =
          builder.integers(joints, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, 4, TINYGLTF_TYPE_VEC4, kArrayBuffer);
    }
    primitive.attributes["WEIGHTS_0"] = builder.floats(values, 4, TINYGLTF_TYPE_VEC4, kArrayBuffer, false);
  }
  if (n <= 65536) {
    const std::vector<std::uint16_t> shortIndices(local.begin(), local.end());
    primitive.indices = builder.integers(shortIndices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, 1, TINYGLTF_TYPE_SCALAR,
                                         kElementArrayBuffer);
  } else {
    primitive.indices =
        builder.integers(local, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, 1, TINYGLTF_TYPE_SCALAR, kElementArrayBuffer);
  }
  return primitive;
}

// A level's mesh: one primitive per part (the source meshes, kept through simplification)
// where the parts cover the triangles exactly, so an engine can give each its material;
// else one primitive. Each primitive holds the vertices its triangles use: with attributes
// shared between primitives, the re-import through Assimp 5.2.5 (io/importer.h) failed, its
// bone weights naming vertices past a primitive's own.
Result<tinygltf::Mesh> levelMesh(Builder& builder, const SkinnedMesh& mesh, int jointCount, const std::string& name) {
  if (mesh.positions.empty() || mesh.indices.empty())
    return Error("the mesh of " + name + " is empty");
  std::vector<std::tuple<std::size_t, std::size_t, std::string>> parts; // first index, count, name
  for (const MeshPart& part : mesh.parts)
    if (part.indexCount > 0)
      parts.emplace_back(part.firstIndex, part.indexCount, part.name);
  std::sort(parts.begin(), parts.end());
  std::size_t at = 0;
  bool exact = parts.size() > 1;
  for (const auto& [first, count, partName] : parts) {
    exact = exact && first == at && count % 3 == 0;
    at = first + count;
  }
  if (!exact || at != mesh.indices.size())
    parts = {{0, mesh.indices.size(), mesh.name}};

  tinygltf::Mesh out;
  out.name = name;
  Value::Array names;
  for (const auto& [first, count, partName] : parts) {
    Result<tinygltf::Primitive> primitive = primitiveOf(
        builder, mesh, std::span<const std::uint32_t>(mesh.indices).subspan(first, count), jointCount, name);
    if (!primitive)
      return primitive.error();
    out.primitives.push_back(std::move(primitive).value());
    names.push_back(Value(partName));
  }
  if (parts.size() > 1) {
    Value::Object extras;
    extras["parts"] = Value(std::move(names)); // the source mesh of each primitive, in order
    out.extras = Value(std::move(extras));
  }
  return out;
}

// MSFT_screencoverage of the written mesh levels `meshLevels` (places in `selected`): entry k
// is the fraction of the viewport height the bounding sphere spans where the next of them
// switches in (screenSizePixels() over the viewport's height, under the set's projection:
// R / (d tan(fov / 2))), 0 for the last. Not clamped: a level that switches in nearer than
// where the sphere fills the screen has a coverage above 1. Where the set has no bounding
// radius or one of those levels no switch distance (levels by --mesh-ratio, a hand-written
// project), there is no coverage to give: nothing, and `out_reason` says why.
std::optional<Value::Array> screenCoverages(const LodPackage& package, const std::vector<std::size_t>& selected,
                                            const std::vector<std::size_t>& meshLevels, std::string& out_reason) {
  const LodSet& lods = package.lods;
  if (!(lods.boundingRadiusCm > 0.0) || !std::isfinite(lods.boundingRadiusCm)) {
    out_reason = "the LOD set has no bounding radius";
    return std::nullopt;
  }
  Value::Array coverage;
  for (std::size_t k = 1; k < meshLevels.size(); ++k) {
    const LodLevel& next = package.levels[selected[meshLevels[k]]].settings;
    const double distance = next.switchDistanceCm;
    const double c = distance > 0.0 ? screenSizePixels(lods.boundingRadiusCm, distance, lods.projection) /
                                          lods.projection.viewportHeightPixels
                                    : 0.0;
    if (!(distance > 0.0) || !std::isfinite(c) || !(c > 0.0)) {
      out_reason = "level " + next.name + " has no switch distance";
      return std::nullopt;
    }
    coverage.push_back(number(c));
  }
  coverage.push_back(number(0.0)); // the coarsest level down to nothing
  return coverage;
}

// `bytes` (a .glb or a .gltf that tinygltf wrote) with `value` as the top-level extension `name`.
Result<std::string> withExtension(const std::string& bytes, const WriteOptions& options, const char* name, json value) {
  if (!options.binary) {
    json document = json::parse(bytes, nullptr, false);
    if (document.is_discarded())
      return Error("the glTF serializer wrote invalid JSON");
    document["extensions"][name] = std::move(value);
    return document.dump(options.pretty ? 2 : -1, ' ', false, json::error_handler_t::replace) + "\n";
  }
  // GLB: a 12-byte header, the JSON chunk (length, "JSON", text padded with spaces), the BIN chunk.
  const auto u32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    std::memcpy(&v, bytes.data() + at, 4);
    return v;
  };
  if (bytes.size() < 20 || bytes.compare(0, 4, "glTF") != 0 || u32(16) != 0x4E4F534Au || 20 + u32(12) > bytes.size())
    return Error("the glTF serializer wrote an invalid GLB");
  const std::size_t jsonLength = u32(12);
  json document = json::parse(bytes.begin() + 20, bytes.begin() + 20 + std::ptrdiff_t(jsonLength), nullptr, false);
  if (document.is_discarded())
    return Error("the glTF serializer wrote invalid JSON");
  document["extensions"][name] = std::move(value);
  std::string text = document.dump(-1, ' ', false, json::error_handler_t::replace);
  text.resize((text.size() + 3) / 4 * 4, ' ');
  const std::string bin = bytes.substr(20 + jsonLength);
  std::string out;
  const auto put = [&](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
  out.reserve(20 + text.size() + bin.size());
  out.append("glTF", 4);
  put(2);
  put(static_cast<std::uint32_t>(20 + text.size() + bin.size()));
  put(static_cast<std::uint32_t>(text.size()));
  put(0x4E4F534Au); // "JSON"
  out += text;
  out += bin;
  return out;
}

std::string base64Encoded(std::string_view bytes) {
  static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t bits = 0;
    for (std::size_t k = 0; k < 3; ++k)
      bits = (bits << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k)
      out += k <= n ? kDigits[(bits >> (18 - 6 * k)) & 63u] : '=';
  }
  return out;
}

// The bytes of one buffer view as meshoptimizer's codecs encode them (EXT_meshopt_compression,
// vertex codec version 0, index codec version 1), or empty where they fail.
std::string encodedView(std::string_view data, const ViewCodec& codec) {
  const std::size_t count = data.size() / codec.stride;
  std::vector<unsigned char> out;
  std::size_t size = 0;
  if (codec.triangles) {
    std::vector<unsigned int> indices(count);
    unsigned int vertices = 0;
    for (std::size_t i = 0; i < count; ++i) {
      if (codec.stride == 2) {
        std::uint16_t v = 0;
        std::memcpy(&v, data.data() + 2 * i, 2);
        indices[i] = v;
      } else {
        std::memcpy(&indices[i], data.data() + 4 * i, 4);
      }
      vertices = std::max(vertices, indices[i] + 1);
    }
    meshopt_encodeIndexVersion(1);
    out.resize(meshopt_encodeIndexBufferBound(count, vertices));
    size = meshopt_encodeIndexBuffer(out.data(), out.size(), indices.data(), count);
  } else {
    meshopt_encodeVertexVersion(0);
    out.resize(meshopt_encodeVertexBufferBound(count, codec.stride));
    size = meshopt_encodeVertexBuffer(out.data(), out.size(), data.data(), count, codec.stride);
  }
  return std::string(reinterpret_cast<const char*>(out.data()), size);
}

// The GLB `glb` (as tinygltf and withExtension() wrote it, `codecs` per buffer view) with
// every buffer view meshopt-encoded (EXT_meshopt_compression): the views move to buffer 1, a
// fallback buffer without data (their offsets into it as before), and their extension points
// at the encoded bytes in buffer 0 (the BIN chunk, or the .gltf's data URI). `out_viewBytes`
// receives the encoded size of each view.
Result<std::string> compressMeshopt(const std::string& glb, const std::vector<ViewCodec>& codecs, bool quantizedMesh,
                                    const WriteOptions& options, std::vector<std::size_t>& out_viewBytes) {
  const auto u32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    std::memcpy(&v, glb.data() + at, 4);
    return v;
  };
  if (glb.size() < 28 || glb.compare(0, 4, "glTF") != 0 || 28 + std::size_t(u32(12)) > glb.size())
    return Error("the glTF serializer wrote an invalid GLB");
  const std::size_t jsonLength = u32(12);
  json document = json::parse(glb.begin() + 20, glb.begin() + 20 + std::ptrdiff_t(jsonLength), nullptr, false);
  const std::size_t binAt = 20 + jsonLength;
  if (document.is_discarded() || u32(binAt + 4) != 0x004E4942u || binAt + 8 + u32(binAt) > glb.size())
    return Error("the glTF serializer wrote an invalid GLB");
  const std::string_view bin(glb.data() + binAt + 8, u32(binAt));
  json& views = document["bufferViews"];
  if (!views.is_array() || views.size() != codecs.size())
    return Error("the buffer views are not those written");
  std::string packed;
  out_viewBytes.assign(codecs.size(), 0);
  for (std::size_t i = 0; i < codecs.size(); ++i) {
    json& view = views[i];
    const std::size_t offset = view.value("byteOffset", std::size_t(0));
    const std::size_t length = view.value("byteLength", std::size_t(0));
    const ViewCodec& codec = codecs[i];
    if (offset + length > bin.size() || codec.stride == 0 || length % codec.stride != 0)
      return Error("buffer view " + std::to_string(i) + " does not fit its codec");
    const std::string encoded = encodedView(bin.substr(offset, length), codec);
    if (encoded.empty())
      return Error("meshoptimizer could not encode buffer view " + std::to_string(i));
    packed.resize((packed.size() + 3) / 4 * 4, '\0');
    json extension = {{"buffer", 0},
                      {"byteOffset", packed.size()},
                      {"byteLength", encoded.size()},
                      {"byteStride", codec.stride},
                      {"count", length / codec.stride},
                      {"mode", codec.triangles ? "TRIANGLES" : "ATTRIBUTES"}};
    if (codec.filter)
      extension["filter"] = codec.filter;
    packed += encoded;
    out_viewBytes[i] = encoded.size();
    view["buffer"] = 1;
    view["extensions"]["EXT_meshopt_compression"] = std::move(extension);
  }
  packed.resize((packed.size() + 3) / 4 * 4, '\0');
  json buffer = {{"byteLength", packed.size()}};
  if (!options.binary)
    buffer["uri"] = "data:application/octet-stream;base64," + base64Encoded(packed);
  document["buffers"] =
      json::array({std::move(buffer),
                   {{"byteLength", bin.size()}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}});
  for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
    json& list = document[key];
    list.push_back("EXT_meshopt_compression");
    if (quantizedMesh)
      list.push_back("KHR_mesh_quantization");
  }
  if (!options.binary)
    return document.dump(options.pretty ? 2 : -1, ' ', false, json::error_handler_t::replace) + "\n";
  std::string text = document.dump(-1, ' ', false, json::error_handler_t::replace);
  text.resize((text.size() + 3) / 4 * 4, ' ');
  std::string out;
  const auto put = [&](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
  out.reserve(28 + text.size() + packed.size());
  out.append("glTF", 4);
  put(2);
  put(static_cast<std::uint32_t>(28 + text.size() + packed.size()));
  put(static_cast<std::uint32_t>(text.size()));
  put(0x4E4F534Au); // "JSON"
  out += text;
  put(static_cast<std::uint32_t>(packed.size()));
  put(0x004E4942u); // "BIN\0"
  out += packed;
  return out;
}

bool step(const WriteProgress& progress, double fraction, std::string_view message) {
  return !progress || progress(std::clamp(fraction, 0.0, 1.0), message);
}

} // namespace

std::string lodName(const std::string& name, std::size_t level) {
  return name + "_LOD" + std::to_string(level);
}

Result<std::string> writeGltf(const LodPackage& package, const WriteOptions& options, const WriteProgress& progress,
                              WriteStats* out_stats) {
  const Skeleton& skeleton = package.skeleton;
  const int jointCount = skeleton.jointCount();
  if (jointCount == 0 && !package.mesh)
    return Error("the package has neither a skeleton nor a mesh");
  if (package.levels.empty())
    return Error("the package has no level");
  std::vector<std::size_t> selected = options.levels;
  if (selected.empty())
    for (std::size_t i = 0; i < package.levels.size(); ++i)
      selected.push_back(i);
  for (std::size_t i : selected)
    if (i >= package.levels.size())
      return Error("the package has no level " + std::to_string(i));
  if (!step(progress, 0.0, "skeleton"))
    return Error(kWriteCancelled);

  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = options.generator;
  Builder builder(model, options.compression, options.floatRotations);
  WriteStats stats;

  // Joints: nodes 0 .. J-1, the rest pose in metres.
  const float s = static_cast<float>(kMetresPerCm);
  for (int j = 0; j < jointCount; ++j) {
    const Joint& joint = skeleton.joints[static_cast<std::size_t>(j)];
    tinygltf::Node node;
    node.name = joint.name;
    const glm::vec3 t = joint.rest.translation * s;
    if (t != glm::vec3(0.0f))
      node.translation = {t.x, t.y, t.z};
    const glm::quat q = unit(joint.rest.rotation);
    if (q != glm::quat(1.0f, 0.0f, 0.0f, 0.0f))
      node.rotation = {q.x, q.y, q.z, q.w};
    if (joint.rest.scale != glm::vec3(1.0f))
      node.scale = {joint.rest.scale.x, joint.rest.scale.y, joint.rest.scale.z};
    model.nodes.push_back(std::move(node));
  }
  for (int j = 1; j < jointCount; ++j) {
    const int parent = skeleton.joints[static_cast<std::size_t>(j)].parent;
    if (parent < 0 || parent >= j)
      return Error("joint '" + skeleton.joints[static_cast<std::size_t>(j)].name + "' does not follow its parent");
    model.nodes[static_cast<std::size_t>(parent)].children.push_back(j);
  }

  tinygltf::Scene scene;
  scene.name = package.name;
  if (jointCount > 0)
    scene.nodes.push_back(0);

  // One skin over every joint, also without a mesh: it is what makes Blender, three.js and
  // engines import the joints as an armature (bones) rather than as plain nodes.
  int skin = -1;
  if (jointCount > 0) {
    std::vector<float> matrices;
    for (const glm::mat4& m : paletteInverseBinds(skeleton)) {
      const glm::mat4 metres = toMetres(m);
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
          matrices.push_back(metres[c][r]); // column-major, as glTF stores matrices
    }
    tinygltf::Skin out;
    out.name = package.name + "_skin";
    out.skeleton = 0;
    out.inverseBindMatrices = builder.floats(matrices, 16, TINYGLTF_TYPE_MAT4, kNoTarget, false);
    for (int j = 0; j < jointCount; ++j)
      out.joints.push_back(j);
    model.skins.push_back(std::move(out));
    skin = 0;
  }
  // Meshes: one per level that has one, named <name>_LOD<n> (n: the level's place in the
  // package), bound to the one skin.
  std::vector<int> levelNodes(selected.size(), -1);
  for (std::size_t k = 0; k < selected.size(); ++k) {
    const LodPackageLevel& level = package.levels[selected[k]];
    std::optional<SkinnedMesh> mesh = levelMeshOnFullSkeleton(level);
    if (!mesh)
      continue;
    if (!step(progress, 0.05 + 0.25 * double(k) / double(selected.size()), "mesh of " + level.settings.name))
      return Error(kWriteCancelled);
    const std::string name = lodName(package.name, selected[k]);
    Result<tinygltf::Mesh> built = levelMesh(builder, *mesh, mesh->skinned() ? jointCount : 0, name);
    if (!built)
      return built.error();
    model.meshes.push_back(std::move(built).value());
    tinygltf::Node node;
    node.name = name;
    node.mesh = static_cast<int>(model.meshes.size()) - 1;
    if (mesh->skinned()) {
      if (skin < 0)
        return Error("the mesh of " + name + " is skinned but the package has no skeleton");
      node.skin = skin;
    }
    model.nodes.push_back(std::move(node));
    levelNodes[k] = static_cast<int>(model.nodes.size()) - 1;
  }
  std::vector<std::size_t> meshLevels; // the places in `selected` with a mesh node, in order
  for (std::size_t k = 0; k < levelNodes.size(); ++k)
    if (levelNodes[k] >= 0)
      meshLevels.push_back(k);
  if (!meshLevels.empty()) {
    tinygltf::Node& top = model.nodes[static_cast<std::size_t>(levelNodes[meshLevels[0]])];
    scene.nodes.push_back(levelNodes[meshLevels[0]]);
    if (meshLevels.size() > 1) {
      Value::Array ids;
      for (std::size_t k = 1; k < meshLevels.size(); ++k)
        ids.push_back(integer(levelNodes[meshLevels[k]]));
      Value::Object lod;
      lod["ids"] = Value(std::move(ids));
      top.extensions["MSFT_lod"] = Value(std::move(lod));
      std::string reason;
      if (std::optional<Value::Array> coverage = screenCoverages(package, selected, meshLevels, reason)) {
        Value::Object extras;
        extras["MSFT_screencoverage"] = Value(std::move(*coverage));
        top.extras = Value(std::move(extras));
      } else {
        stats.warnings.push_back("no MSFT_screencoverage: " + reason +
                                 " (a reader that switches by coverage cannot tell when to show each level)");
      }
      model.extensionsUsed.push_back("MSFT_lod");
    }
  }
  model.scenes.push_back(std::move(scene));
  model.defaultScene = 0;

  // Animations: per level, per clip, named <clip>_LOD<n>; and the cluster tables beside them.
  // Nodes and animations are referred to by index and by name, so that a tool that renumbers
  // them leaves a way to find them.
  json levelsJson = json::array();
  std::vector<std::vector<int>> levelViews; // per written level, the buffer views of its animations
  const std::size_t clipCount = jointCount > 0 ? package.clips.size() : 0;
  std::size_t done = 0;
  for (std::size_t k = 0; k < selected.size(); ++k) {
    const LodPackageLevel& level = package.levels[selected[k]];
    const BoneReduction& bones = level.build.motion.bones;
    json removed = json::array();
    json removedNames = json::array();
    if (static_cast<int>(bones.removed.size()) == jointCount)
      for (int j = 0; j < jointCount; ++j)
        if (bones.removed[static_cast<std::size_t>(j)]) {
          removed.push_back(j);
          removedNames.push_back(skeleton.joints[static_cast<std::size_t>(j)].name);
        }
    json animations = json::array();
    std::set<int> accessors; // every accessor the level's animations use
    LevelStats levelStats;
    levelStats.name = lodName(package.name, selected[k]);
    for (std::size_t c = 0; c < clipCount; ++c, ++done) {
      if (!step(progress, 0.3 + 0.6 * double(done) / double(clipCount * selected.size()),
                "animation " + package.clips[c].name + " at " + level.settings.name))
        return Error(kWriteCancelled);
      const Clip& clip = package.clips[c];
      const std::string name = lodName(clip.name, selected[k]);
      Result<tinygltf::Animation> animation = levelAnimation(builder, package, level, c, name);
      if (!animation)
        return animation.error();
      for (const tinygltf::AnimationSampler& sampler : animation->samplers) {
        accessors.insert(sampler.input);
        accessors.insert(sampler.output);
        if (model.accessors[static_cast<std::size_t>(sampler.input)].count < static_cast<std::size_t>(clip.frameCount))
          ++levelStats.heldTracks;
      }
      for (const tinygltf::AnimationChannel& channel : animation->channels)
        if (channel.target_path == "rotation")
          levelStats.rotationKeys += model
                                         .accessors[static_cast<std::size_t>(
                                             animation->samplers[static_cast<std::size_t>(channel.sampler)].input)]
                                         .count;
      model.animations.push_back(std::move(animation).value());
      // the clusters as one binary table (version 2): 8 bytes a cluster where JSON took ~12
      int table = -1;
      if (c < level.build.motion.clusters.size() && level.build.motion.clusters[c].jointCount() == jointCount) {
        const ClusterTable rows = clusterTable(level.build.motion.clusters[c]);
        if (!rows.rows.empty()) {
          if (rows.wide)
            table = builder.integers(rows.rows, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, 4, TINYGLTF_TYPE_VEC4, kNoTarget);
          else
            table = builder.integers(std::vector<std::uint16_t>(rows.rows.begin(), rows.rows.end()),
                                     TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, 4, TINYGLTF_TYPE_VEC4, kNoTarget);
          accessors.insert(table);
        }
      }
      animations.push_back({{"animation", static_cast<int>(model.animations.size()) - 1},
                            {"animationName", name},
                            {"clip", clip.name},
                            {"frameCount", clip.frameCount},
                            {"fps", clip.fps},
                            {"looping", clip.looping}});
      if (table >= 0)
        animations.back()["clusters"] = table;
    }
    std::set<int> views; // accessors of one view (none here) count once
    for (int accessor : accessors)
      views.insert(model.accessors[static_cast<std::size_t>(accessor)].bufferView);
    levelViews.emplace_back(views.begin(), views.end());
    stats.levels.push_back(std::move(levelStats));
    json entry = {{"level", level.index},
                  {"name", level.settings.name},
                  {"threshold", level.settings.motionThreshold},
                  {"switchDistance", level.settings.switchDistanceCm * kMetresPerCm},
                  {"node", levelNodes[k]}};
    if (levelNodes[k] >= 0)
      entry["nodeName"] = model.nodes[static_cast<std::size_t>(levelNodes[k])].name;
    entry["removedJoints"] = std::move(removed);
    entry["removedJointNames"] = std::move(removedNames);
    entry["animations"] = std::move(animations);
    levelsJson.push_back(std::move(entry));
  }
  json extension;
  if (jointCount > 0) {
    json jointNames = json::array();
    for (const Joint& joint : skeleton.joints)
      jointNames.push_back(joint.name);
    extension = {{"version", kClusterExtensionVersion},
                 {"mode", toString(package.jpc.mode)},
                 {"alpha", package.jpc.alpha},
                 {"jointNames", std::move(jointNames)},
                 {"levels", std::move(levelsJson)}};
    model.extensionsUsed.push_back(kClusterExtension);
  }

  if (!step(progress, 0.9, "writing"))
    return Error(kWriteCancelled);
  // compressed: a GLB first, which compressMeshopt() encodes and turns into what was asked
  const bool compress = options.compression == Compression::Meshopt;
  WriteOptions serialized = options;
  serialized.binary = options.binary || compress;
  tinygltf::TinyGLTF writer;
  std::ostringstream stream;
  if (!writer.WriteGltfSceneToStream(&model, stream, serialized.pretty && !serialized.binary, serialized.binary) ||
      !stream)
    return Error("the glTF serializer failed");
  std::string bytes = stream.str();
  // (a stop asked while a large file was serialized is answered before the cluster tables
  // are merged into it: a 5 MB .gltf's JSON is parsed and written again there)
  if (!step(progress, 0.95, "writing"))
    return Error(kWriteCancelled);
  if (!extension.is_null()) {
    // tinygltf's extension values cannot hold an empty array: the vendor extension goes into
    // the serialized JSON with nlohmann-json instead.
    Result<std::string> out = withExtension(bytes, serialized, kClusterExtension, std::move(extension));
    if (!out)
      return out.error();
    bytes = std::move(out).value();
  }
  std::vector<std::size_t> viewBytes(model.bufferViews.size());
  for (std::size_t i = 0; i < viewBytes.size(); ++i)
    viewBytes[i] = model.bufferViews[i].byteLength;
  if (compress) {
    if (!step(progress, 0.95, "compressing"))
      return Error(kWriteCancelled);
    Result<std::string> out = compressMeshopt(bytes, builder.codecs(), builder.quantizedMesh(), options, viewBytes);
    if (!out)
      return out.error();
    bytes = std::move(out).value();
  }
  for (std::size_t k = 0; k < stats.levels.size(); ++k)
    for (int view : levelViews[k])
      stats.levels[k].animationBytes += viewBytes[static_cast<std::size_t>(view)];
  stats.rotationErrorDegrees = builder.rotationErrorDegrees();
  stats.rotationErrorCm = rotationQuantizationBoundCm(skeleton, stats.rotationErrorDegrees);
  step(progress, 1.0, "done");
  if (out_stats)
    *out_stats = std::move(stats);
  return bytes;
}

} // namespace mlod::gltf
