// The glTF exporter plugin (plugins/gltf) on real data: CMU 01_01 (a skeleton alone) and
// BCN_Epileptic (a skinned character). The Khronos glTF-Validator must report no error; the
// file must read back (tinygltf, and Assimp through the project's importer) with the same
// joints and frames; weights sum to 1 exactly; MSFT_lod links the level meshes; the
// MLOD_joint_clusters extension holds the package's cluster tables; each level's animation
// plays like the runtime's LodClip; unwritable output and cancel leave nothing behind.
// What clients key on: a skin (armature) also without a mesh, <name>_LOD<n> names, the
// source fps and frame count in the animations' extras (read back by the importer, with the
// clusters), animation bytes that fall with each level, one valid file per level on request.

#include "core/lod/held_keys.h"
#include "core/mapping/motion_mapping.h"
#include "exporter_test_support.h"
#include "io/importer.h"
#include "test_files.h"
#include "unit/package_fixtures.h"
#include "unit/real_files.h"

#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QTemporaryDir>
#include <algorithm>
#include <array>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <cmath>
#include <cstring>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/gtx/quaternion.hpp>
#include <gtest/gtest.h>
#include <map>
#include <meshoptimizer.h>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <span>
#include <tiny_gltf.h>
#include <unistd.h>

namespace mlod {
namespace {

using nlohmann::json;

Exporter& gltfExporter() {
  static Exporter* exporter = test::loadExporter(QStringLiteral(MLOD_GLTF_PLUGIN));
  if (!exporter)
    throw std::runtime_error("no glTF exporter");
  return *exporter;
}

QByteArray readAll(const QString& path) {
  QFile file(path);
  return file.open(QIODevice::ReadOnly) ? file.readAll() : QByteArray();
}

// The JSON of a .glb (its first chunk) or of a .gltf.
json documentOf(const QByteArray& bytes) {
  if (bytes.startsWith("glTF")) {
    std::uint32_t length = 0;
    std::memcpy(&length, bytes.constData() + 12, 4);
    return json::parse(bytes.constData() + 20, bytes.constData() + 20 + length);
  }
  return json::parse(bytes.constData(), bytes.constData() + bytes.size());
}

tinygltf::Model parseModel(const QByteArray& bytes) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string error, warning;
  const bool ok = bytes.startsWith("glTF")
                      ? loader.LoadBinaryFromMemory(&model, &error, &warning,
                                                    reinterpret_cast<const unsigned char*>(bytes.constData()),
                                                    static_cast<unsigned>(bytes.size()))
                      : loader.LoadASCIIFromString(&model, &error, &warning, bytes.constData(),
                                                   static_cast<unsigned>(bytes.size()), "");
  EXPECT_TRUE(ok) << error;
  return model;
}

template <typename T> std::vector<T> elements(const tinygltf::Model& model, int accessorIndex, int components) {
  const tinygltf::Accessor& accessor = model.accessors.at(std::size_t(accessorIndex));
  const tinygltf::BufferView& view = model.bufferViews.at(std::size_t(accessor.bufferView));
  const unsigned char* data =
      model.buffers.at(std::size_t(view.buffer)).data.data() + view.byteOffset + accessor.byteOffset;
  std::vector<T> out(accessor.count * std::size_t(components));
  std::memcpy(out.data(), data, out.size() * sizeof(T));
  return out;
}

// The rotation keys behind `accessorIndex`, as a reader decodes them: floats, or normalized
// signed integers (glTF core: c = max(i / 32767, -1) for SHORT, / 127 for BYTE), normalized.
std::vector<glm::quat> rotationKeys(const tinygltf::Model& model, int accessorIndex) {
  const tinygltf::Accessor& accessor = model.accessors.at(std::size_t(accessorIndex));
  std::vector<double> c;
  if (accessor.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) {
    for (float x : elements<float>(model, accessorIndex, 4))
      c.push_back(x);
  } else if (accessor.componentType == TINYGLTF_COMPONENT_TYPE_SHORT && accessor.normalized) {
    for (std::int16_t x : elements<std::int16_t>(model, accessorIndex, 4))
      c.push_back(std::max(x / 32767.0, -1.0));
  } else if (accessor.componentType == TINYGLTF_COMPONENT_TYPE_BYTE && accessor.normalized) {
    for (std::int8_t x : elements<std::int8_t>(model, accessorIndex, 4))
      c.push_back(std::max(x / 127.0, -1.0));
  } else {
    ADD_FAILURE() << "accessor " << accessorIndex << " is not a rotation output (component type "
                  << accessor.componentType << ")";
  }
  std::vector<glm::quat> out;
  for (std::size_t k = 0; k + 3 < c.size(); k += 4)
    out.push_back(glm::normalize(glm::quat(float(c[k + 3]), float(c[k]), float(c[k + 1]), float(c[k + 2]))));
  return out;
}

// The parent of each joint node 0 .. J-1 of `model` (-1 for the root).
std::vector<int> parentsOf(const tinygltf::Model& model, int joints) {
  std::vector<int> parent(std::size_t(joints), -1);
  for (int j = 0; j < joints; ++j)
    for (int child : model.nodes[std::size_t(j)].children)
      if (child < joints)
        parent[std::size_t(child)] = j;
  return parent;
}

// The most that 16-bit rotation keys can move point `p` (metres) carried by joint `j` of a
// skeleton posed at `models` (`parent`): the quantization angle (kMaxRotationQuantizationDegrees,
// core/lod/held_keys.h) times its distance from each joint whose rotation moves it, j itself
// included where `withSelf` (a point off the joint), first order in the angle.
double quantizationBoundM(const std::vector<glm::mat4>& models, const std::vector<int>& parent, int j, glm::vec3 p,
                          bool withSelf) {
  double sum = 0.0;
  for (int a = withSelf ? j : parent[std::size_t(j)]; a >= 0; a = parent[std::size_t(a)])
    sum += glm::length(p - glm::vec3(models[std::size_t(a)][3]));
  return glm::radians(kMaxRotationQuantizationDegrees) * sum;
}

struct Exported {
  QString path;
  QByteArray bytes;
  ExportResult result;
};

Exported exportTo(const LodPackage& package, const QString& path, const QStringList& options = {}) {
  Exported out;
  out.path = path;
  out.result = gltfExporter().exportPackage(package, path, test::exporterOptions(gltfExporter(), options), {});
  out.bytes = readAll(path);
  return out;
}

// Model-space matrices of the joint nodes 0 .. J-1 of `model` playing `animation` at
// `seconds` (glTF's LINEAR: lerp, slerp for rotations).
std::vector<glm::mat4> evaluate(const tinygltf::Model& model, const tinygltf::Animation& animation, int joints,
                                double seconds) {
  std::vector<glm::vec3> t(std::size_t(joints), glm::vec3(0.0f)), s(std::size_t(joints), glm::vec3(1.0f));
  std::vector<glm::quat> r(std::size_t(joints), glm::quat(1.0f, 0.0f, 0.0f, 0.0f));
  for (int j = 0; j < joints; ++j) {
    const tinygltf::Node& node = model.nodes[std::size_t(j)];
    if (node.translation.size() == 3)
      t[std::size_t(j)] = glm::vec3(node.translation[0], node.translation[1], node.translation[2]);
    if (node.rotation.size() == 4)
      r[std::size_t(j)] =
          glm::quat(float(node.rotation[3]), float(node.rotation[0]), float(node.rotation[1]), float(node.rotation[2]));
    if (node.scale.size() == 3)
      s[std::size_t(j)] = glm::vec3(node.scale[0], node.scale[1], node.scale[2]);
  }
  for (const tinygltf::AnimationChannel& channel : animation.channels) {
    const tinygltf::AnimationSampler& sampler = animation.samplers[std::size_t(channel.sampler)];
    const std::vector<float> times = elements<float>(model, sampler.input, 1);
    const int n = channel.target_path == "rotation" ? 4 : 3;
    const std::vector<glm::quat> keys = n == 4 ? rotationKeys(model, sampler.output) : std::vector<glm::quat>();
    const std::vector<float> values = n == 3 ? elements<float>(model, sampler.output, n) : std::vector<float>();
    std::size_t k = 0;
    while (k + 1 < times.size() && times[k + 1] <= seconds)
      ++k;
    const std::size_t k1 = std::min(k + 1, times.size() - 1);
    const float a = k1 == k || seconds <= times[k] ? 0.0f : float((seconds - times[k]) / (times[k1] - times[k]));
    const std::size_t j = std::size_t(channel.target_node);
    if (n == 4) {
      r[j] = glm::slerp(keys[k], keys[k1], a);
    } else {
      const glm::vec3 v0(values[3 * k], values[3 * k + 1], values[3 * k + 2]);
      const glm::vec3 v1(values[3 * k1], values[3 * k1 + 1], values[3 * k1 + 2]);
      (channel.target_path == "translation" ? t : s)[j] = glm::mix(v0, v1, a);
    }
  }
  const std::vector<int> parent = parentsOf(model, joints);
  std::vector<glm::mat4> models(static_cast<std::size_t>(joints));
  for (std::size_t j = 0; j < std::size_t(joints); ++j) {
    const glm::mat4 local =
        glm::translate(glm::mat4(1.0f), t[j]) * glm::mat4_cast(r[j]) * glm::scale(glm::mat4(1.0f), s[j]);
    models[j] = parent[j] < 0 ? local : models[std::size_t(parent[j])] * local;
  }
  return models;
}

// Model-space matrices (cm) of the level's skeleton playing runtime clip `clip` at frame position `frame`.
std::vector<glm::mat4> evaluateRuntime(const LodPackageLevel& level, std::size_t clip, double frame) {
  const Skeleton& skeleton = level.skeleton();
  const LodClip& lod = level.runtimeClips[clip];
  std::vector<glm::mat4> models(std::size_t(skeleton.jointCount()));
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    const glm::mat4 local = glm::translate(glm::mat4(1.0f), lod.translationAt(j, frame)) *
                            glm::mat4_cast(lod.rotationAt(j, frame)) *
                            glm::scale(glm::mat4(1.0f), lod.scaleAt(j, frame));
    const int parent = skeleton.joints[std::size_t(j)].parent;
    models[std::size_t(j)] = parent < 0 ? local : models[std::size_t(parent)] * local;
  }
  return models;
}

// Every level's animation of every clip equals the runtime at every `stride`-th frame and
// half frame: joint positions within `toleranceM` metres beyond what the 16-bit rotation keys
// may move them (quantizationBoundM()) and what the runtime's own quantization may (its
// precision: the glTF is written from the unquantized clip).
void expectPlaysLikeTheRuntime(const LodPackage& package, const tinygltf::Model& model, int stride, double toleranceM) {
  const int joints = package.skeleton.jointCount();
  const std::vector<int> parent = parentsOf(model, joints);
  ASSERT_EQ(model.animations.size(), package.levels.size() * package.clips.size());
  std::size_t animation = 0;
  for (const LodPackageLevel& level : package.levels) {
    for (std::size_t c = 0; c < package.clips.size(); ++c, ++animation) {
      const Clip& clip = package.clips[c];
      double worst = 0.0;
      for (int f = 0; f < clip.frameCount; f += stride) {
        for (double frame : {double(f), f + 0.5}) {
          if (frame > clip.frameCount - 1)
            continue;
          const std::vector<glm::mat4> gltf = evaluate(model, model.animations[animation], joints, frame / clip.fps);
          const std::vector<glm::mat4> runtime = evaluateRuntime(level, c, frame);
          for (int r = 0; r < level.skeleton().jointCount(); ++r) {
            const int full = level.build.motion.bones.fullIndex[std::size_t(r)];
            const glm::vec3 expected = glm::vec3(runtime[std::size_t(r)][3]) * 0.01f;
            const double bound = quantizationBoundM(gltf, parent, full, expected, false);
            worst = std::max(worst, double(glm::length(glm::vec3(gltf[std::size_t(full)][3]) - expected)) - bound);
          }
        }
      }
      const double runtimePrecisionM = level.runtimeClips[c].precisionCm() * 0.01;
      EXPECT_LT(worst, toleranceM + runtimePrecisionM) << "level " << level.index << " clip " << clip.name;
    }
  }
}

// The triangle corners of a glTF mesh, primitive after primitive: what each corner's vertex holds.
struct Corners {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec4> weights;
  std::vector<glm::u8vec4> joints;
};

Corners cornersOf(const tinygltf::Model& model, const tinygltf::Mesh& mesh) {
  Corners out;
  for (const tinygltf::Primitive& primitive : mesh.primitives) {
    const std::vector<float> positions = elements<float>(model, primitive.attributes.at("POSITION"), 3);
    const bool skinned = primitive.attributes.count("WEIGHTS_0") > 0;
    const std::vector<float> weights =
        skinned ? elements<float>(model, primitive.attributes.at("WEIGHTS_0"), 4) : std::vector<float>();
    const std::vector<std::uint8_t> joints =
        skinned ? elements<std::uint8_t>(model, primitive.attributes.at("JOINTS_0"), 4) : std::vector<std::uint8_t>();
    for (std::uint16_t i : elements<std::uint16_t>(model, primitive.indices, 1)) {
      out.positions.push_back(glm::make_vec3(&positions[3 * i]));
      if (!skinned)
        continue;
      out.weights.push_back(glm::make_vec4(&weights[4 * i]));
      out.joints.emplace_back(joints[4 * i], joints[4 * i + 1], joints[4 * i + 2], joints[4 * i + 3]);
    }
  }
  return out;
}

// The corners of `mesh` (read back) in the order of `source`'s triangles (source.indices):
// the writer reorders triangles for the vertex cache, so each source triangle is found by its
// corners' positions in metres (the writer's float product, bit for bit), any rotation of
// them (the winding kept); among triangles at the same positions the one whose weights are
// nearest. A triangle not found leaves the result short.
Corners cornersInSourceOrder(const tinygltf::Model& model, const tinygltf::Mesh& mesh, const SkinnedMesh& source) {
  const Corners written = cornersOf(model, mesh);
  using Key = std::array<float, 9>;
  const auto keyOf = [](const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    return Key{a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z};
  };
  std::map<Key, std::vector<std::size_t>> byPositions; // first corner of each written triangle
  for (std::size_t t = 0; t + 2 < written.positions.size(); t += 3)
    byPositions[keyOf(written.positions[t], written.positions[t + 1], written.positions[t + 2])].push_back(t);
  Corners out;
  for (std::size_t t = 0; t + 2 < source.indices.size(); t += 3) {
    glm::vec3 p[3];
    glm::vec4 w[3];
    for (int c = 0; c < 3; ++c) {
      p[c] = source.positions[source.indices[t + std::size_t(c)]] * 0.01f;
      w[c] = source.skinned() ? source.weights[source.indices[t + std::size_t(c)]] : glm::vec4(0.0f);
    }
    std::vector<std::size_t>* best = nullptr;
    std::size_t bestAt = 0;
    int bestRotation = 0;
    double bestDistance = std::numeric_limits<double>::infinity();
    for (int r = 0; r < 3; ++r) {
      const auto found = byPositions.find(keyOf(p[r], p[(r + 1) % 3], p[(r + 2) % 3]));
      if (found == byPositions.end())
        continue;
      for (std::size_t i = 0; i < found->second.size(); ++i) {
        double distance = 0.0;
        if (!written.weights.empty())
          for (int c = 0; c < 3; ++c)
            distance += glm::length(written.weights[found->second[i] + std::size_t(c)] - w[(r + c) % 3]);
        if (distance < bestDistance) {
          bestDistance = distance;
          best = &found->second;
          bestAt = i;
          bestRotation = r;
        }
      }
    }
    if (!best)
      return out;
    const std::size_t first = (*best)[bestAt];
    best->erase(best->begin() + std::ptrdiff_t(bestAt));
    for (int c = 0; c < 3; ++c) { // corner c of the source triangle is corner (c - r) mod 3 written
      const std::size_t k = first + std::size_t((c - bestRotation + 3) % 3);
      out.positions.push_back(written.positions[k]);
      if (!written.weights.empty()) {
        out.weights.push_back(written.weights[k]);
        out.joints.push_back(written.joints[k]);
      }
    }
  }
  return out;
}

// Every level's mesh skinned by the glTF (its skin, weights and the level's animation) lands
// where the runtime skins the level's mesh (the level's skeleton, runtime clip and palette),
// at a few frames: positions within `toleranceM` metres beyond what the 16-bit rotation keys
// may move them (quantizationBoundM() of each influence, weighted).
void expectSkinsLikeTheRuntime(const LodPackage& package, const tinygltf::Model& model, double toleranceM) {
  const int joints = package.skeleton.jointCount();
  const std::vector<int> parent = parentsOf(model, joints);
  ASSERT_EQ(model.skins.size(), 1u);
  const std::vector<float> ibm = elements<float>(model, model.skins[0].inverseBindMatrices, 16);
  ASSERT_EQ(ibm.size(), std::size_t(joints) * 16);
  for (std::size_t i = 0; i < package.levels.size(); ++i) {
    const LodPackageLevel& level = package.levels[i];
    const SkinnedMesh* mesh = level.mesh();
    ASSERT_TRUE(mesh != nullptr);
    const Corners corners = cornersInSourceOrder(model, model.meshes.at(i), *mesh);
    ASSERT_EQ(corners.positions.size(), mesh->indices.size());
    for (std::size_t c = 0; c < package.clips.size(); ++c) {
      const Clip& clip = package.clips[c];
      double worst = 0.0;
      for (int frame : {0, clip.frameCount / 2, clip.frameCount - 1}) {
        const std::vector<glm::mat4> world =
            evaluate(model, model.animations[i * package.clips.size() + c], joints, frame / clip.fps);
        std::vector<glm::mat4> palette(world.size());
        for (std::size_t j = 0; j < world.size(); ++j)
          palette[j] = world[j] * glm::make_mat4(&ibm[16 * j]);
        const std::vector<glm::mat4> models = evaluateRuntime(level, c, frame);
        for (std::size_t k = 0; k < mesh->indices.size(); ++k) {
          const std::size_t v = mesh->indices[k];
          const glm::vec4 p(corners.positions[k], 1.0f);
          glm::vec3 gltf(0.0f), runtime(0.0f);
          for (int n = 0; n < 4; ++n) {
            gltf += corners.weights[k][n] * glm::vec3(palette[corners.joints[k][n]] * p);
            const std::size_t r = mesh->joints[v][n];
            runtime += mesh->weights[v][n] *
                       glm::vec3(models[r] * level.inverseBinds[r] * glm::vec4(mesh->positions[v], 1.0f));
          }
          double bound = 0.0;
          for (int n = 0; n < 4; ++n)
            bound += corners.weights[k][n] * quantizationBoundM(world, parent, corners.joints[k][n], gltf, true);
          worst = std::max(worst, double(glm::length(gltf - runtime * 0.01f)) - bound);
        }
      }
      const double runtimePrecisionM = level.runtimeClips[c].precisionCm() * 0.01;
      EXPECT_LT(worst, toleranceM + runtimePrecisionM) << "level " << level.index << " clip " << clip.name;
    }
  }
}

// The rows (joint, first, last, key) of the cluster table behind `accessor` (version 2).
std::vector<std::uint32_t> clusterRows(const tinygltf::Model& model, int accessor) {
  const tinygltf::Accessor& a = model.accessors.at(std::size_t(accessor));
  EXPECT_EQ(a.type, TINYGLTF_TYPE_VEC4);
  if (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
    return elements<std::uint32_t>(model, accessor, 4);
  EXPECT_EQ(a.componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
  const std::vector<std::uint16_t> shorts = elements<std::uint16_t>(model, accessor, 4);
  return std::vector<std::uint32_t>(shorts.begin(), shorts.end());
}

void expectClusterTablesRoundTrip(const LodPackage& package, const json& document, const tinygltf::Model& model) {
  ASSERT_TRUE(document.contains("extensionsUsed"));
  const auto used = document["extensionsUsed"].get<std::vector<std::string>>();
  EXPECT_NE(std::find(used.begin(), used.end(), "MLOD_joint_clusters"), used.end());
  EXPECT_FALSE(document.contains("extensionsRequired")); // every other reader can read the file
  const json& extension = document.at("extensions").at("MLOD_joint_clusters");
  EXPECT_EQ(extension.at("version").get<int>(), 2);
  ASSERT_EQ(extension.at("jointNames").size(), std::size_t(package.skeleton.jointCount()));
  for (std::size_t j = 0; j < extension["jointNames"].size(); ++j)
    EXPECT_EQ(extension["jointNames"][j], document["nodes"][j]["name"]);
  const json& levels = extension.at("levels");
  ASSERT_EQ(levels.size(), package.levels.size());
  for (std::size_t i = 0; i < package.levels.size(); ++i) {
    const LodPackageLevel& level = package.levels[i];
    const json& l = levels[i];
    EXPECT_EQ(l.at("level").get<int>(), level.index);
    if (l.at("node").get<int>() >= 0) { // referred to by name as well as by index
      EXPECT_EQ(l.at("nodeName"), document["nodes"][l["node"].get<std::size_t>()]["name"]);
    }
    EXPECT_EQ(l.at("name").get<std::string>(), level.settings.name);
    EXPECT_DOUBLE_EQ(l.at("threshold").get<double>(), level.settings.motionThreshold);
    std::vector<int> removed;
    for (std::size_t j = 0; j < level.build.motion.bones.removed.size(); ++j)
      if (level.build.motion.bones.removed[j])
        removed.push_back(int(j));
    EXPECT_EQ(l.at("removedJoints").get<std::vector<int>>(), removed);
    ASSERT_EQ(l.at("removedJointNames").size(), removed.size());
    for (std::size_t r = 0; r < removed.size(); ++r)
      EXPECT_EQ(l["removedJointNames"][r], document["nodes"][std::size_t(removed[r])]["name"]);
    ASSERT_EQ(l.at("animations").size(), package.clips.size());
    for (std::size_t c = 0; c < package.clips.size(); ++c) {
      const json& a = l["animations"][c];
      EXPECT_EQ(a.at("animation").get<std::size_t>(), i * package.clips.size() + c);
      const json& animation = document["animations"][a["animation"].get<std::size_t>()];
      EXPECT_EQ(a.at("animationName"), animation.at("name"));
      EXPECT_EQ(animation.at("name").get<std::string>(), package.clips[c].name + "_LOD" + std::to_string(i));
      // glTF keeps no frame rate: the animation's extras say the source's
      EXPECT_EQ(animation.at("extras").at("fps").get<double>(), package.clips[c].fps);
      EXPECT_EQ(animation.at("extras").at("frameCount").get<int>(), package.clips[c].frameCount);
      EXPECT_EQ(animation.at("extras").at("level").get<int>(), level.index);
      EXPECT_EQ(a.at("frameCount").get<int>(), package.clips[c].frameCount);
      EXPECT_EQ(a.at("fps").get<double>(), package.clips[c].fps);
      EXPECT_EQ(a.at("looping").get<bool>(), package.clips[c].looping);
      EXPECT_EQ(a.at("clip").get<std::string>(), package.clips[c].name);
      const ClusterSet& set = level.build.motion.clusters[c];
      std::vector<std::vector<Cluster>> parsed(set.joints.size());
      EXPECT_FALSE(a.contains("joints"));                        // version 1's JSON arrays are gone
      EXPECT_EQ(a.contains("clusters"), set.clusterCount() > 0); // no table without a cluster
      if (a.contains("clusters")) {
        const std::vector<std::uint32_t> rows = clusterRows(model, a["clusters"].get<int>());
        for (std::size_t r = 0; r + 3 < rows.size(); r += 4) {
          ASSERT_LT(rows[r], parsed.size());
          EXPECT_TRUE(r == 0 || rows[r - 4] <= rows[r]); // joints ascending
          parsed[rows[r]].push_back({int(rows[r + 1]), int(rows[r + 2]), int(rows[r + 3])});
        }
      }
      EXPECT_EQ(parsed, set.joints) << "level " << level.index << " clip " << c;
    }
  }
}

// Every level's animation of every clip came back through the project's importer at the
// source's fps and frame count, named <clip>_LOD<n>, with the level's clusters (joints
// matched by name: the importer may order them differently).
void expectReadBack(const LodPackage& package, const Asset& back) {
  ASSERT_EQ(back.clips.size(), package.levels.size() * package.clips.size());
  ASSERT_EQ(back.clusters.size(), back.clips.size());
  for (std::size_t l = 0; l < package.levels.size(); ++l)
    for (std::size_t c = 0; c < package.clips.size(); ++c) {
      const std::size_t a = l * package.clips.size() + c;
      const Clip& clip = back.clips[a];
      const Clip& source = package.clips[c];
      EXPECT_EQ(clip.name, source.name + "_LOD" + std::to_string(l));
      EXPECT_EQ(clip.fps, source.fps) << clip.name;
      EXPECT_EQ(clip.frameCount, source.frameCount) << clip.name;
      const ClusterSet& expected = package.levels[l].build.motion.clusters[c];
      const ClusterSet& got = back.clusters[a];
      EXPECT_EQ(got.frameCount, source.frameCount);
      int compared = 0;
      for (int j = 0; j < package.skeleton.jointCount(); ++j) {
        const int k = back.skeleton.find(package.skeleton.joints[std::size_t(j)].name);
        ASSERT_GE(k, 0);
        EXPECT_EQ(got.joints[std::size_t(k)], expected.joints[std::size_t(j)]) << clip.name << " joint " << j;
        compared += expected.joints[std::size_t(j)].empty() ? 0 : 1;
      }
      if (l > 0) {
        EXPECT_GT(compared, 0) << clip.name; // a coarser level has clusters to compare
      }
    }
}

// The bytes of the key times and values that each animation uses (data shared between
// channels counted once), per level: what a file of that level alone holds.
// The MSFT_lod node of a combined file (the scene's mesh node that carries MSFT_lod), or null.
const json* lodNode(const json& document) {
  for (const json& index : document["scenes"][0]["nodes"]) {
    const json& node = document["nodes"][index.get<std::size_t>()];
    if (node.contains("extensions") && node["extensions"].contains("MSFT_lod"))
      return &node;
  }
  return nullptr;
}

// MSFT_screencoverage read back: entry k is the fraction of the viewport height the
// package's bounding sphere spans at level k + 1's switch distance under the set's
// projection, R / (d tan(fov / 2)) (the sphere's diameter over the visible height at d),
// so the entries fall strictly (each level switches in farther out) down to 0 for the last.
void expectCoveragesFollowSwitchDistances(const LodPackage& package, const json& document) {
  const json* top = lodNode(document);
  ASSERT_TRUE(top != nullptr);
  const std::vector<double> coverage = top->at("extras").at("MSFT_screencoverage").get<std::vector<double>>();
  ASSERT_EQ(coverage.size(), package.levels.size());
  const double radius = package.lods.boundingRadiusCm;
  const double halfHeight = std::tan(0.5 * package.lods.projection.verticalFovDegrees * 3.14159265358979323846 / 180.0);
  ASSERT_GT(radius, 0.0);
  for (std::size_t k = 0; k + 1 < coverage.size(); ++k) {
    const double distance = package.levels[k + 1].settings.switchDistanceCm;
    ASSERT_GT(distance, 0.0) << "LOD" << k + 1;
    const double expected = radius / (distance * halfHeight);
    EXPECT_NEAR(coverage[k], expected, 1e-5 * expected) << "LOD" << k << " down to LOD" << k + 1 << "'s switch";
    if (k > 0) {
      EXPECT_LT(coverage[k], coverage[k - 1]) << "LOD" << k;
    }
  }
  EXPECT_GT(coverage[coverage.size() - 2], 0.0);
  EXPECT_EQ(coverage.back(), 0.0);
  std::cout << "[ coverage ] " << package.name << ":";
  for (double c : coverage)
    std::cout << " " << c;
  std::cout << "\n";
}

std::vector<std::size_t> animationBytesPerLevel(const tinygltf::Model& model, std::size_t levels) {
  std::vector<std::size_t> out;
  const std::size_t clips = model.animations.size() / levels;
  for (std::size_t l = 0; l < levels; ++l) {
    std::set<int> accessors;
    for (std::size_t c = 0; c < clips; ++c)
      for (const tinygltf::AnimationSampler& sampler : model.animations[l * clips + c].samplers)
        accessors.insert({sampler.input, sampler.output});
    // and the level's cluster tables (MLOD_joint_clusters version 2)
    const tinygltf::Value& entries =
        model.extensions.at("MLOD_joint_clusters").Get("levels").Get(int(l)).Get("animations");
    for (std::size_t c = 0; c < entries.ArrayLen(); ++c)
      if (entries.Get(int(c)).Has("clusters"))
        accessors.insert(entries.Get(int(c)).Get("clusters").GetNumberAsInt());
    std::size_t bytes = 0;
    for (int a : accessors)
      bytes += model.bufferViews[std::size_t(model.accessors[std::size_t(a)].bufferView)].byteLength;
    out.push_back(bytes);
  }
  return out;
}

TEST(GltfExporter, DescribesItselfAndItsOptions) {
  Exporter& exporter = gltfExporter();
  EXPECT_EQ(exporter.id(), "gltf");
  EXPECT_EQ(exporter.suffixes(), QStringList({"glb", "gltf"}));
  const QVariantMap defaults = test::exporterOptions(exporter);
  EXPECT_EQ(defaults.value("format").toString(), "auto");
  EXPECT_EQ(defaults.value("pretty").toBool(), false);
  EXPECT_EQ(defaults.value("split_levels").toBool(), false);
  EXPECT_EQ(defaults.value("compress").toString(), "none"); // Blender 3.4 cannot read meshopt
  QVariantMap compressed;
  QString compressError;
  EXPECT_TRUE(parseExporterOptions(exporter.options(), {"compress=meshopt"}, &compressed, &compressError))
      << compressError.toStdString();
  QVariantMap values;
  QString error;
  EXPECT_FALSE(parseExporterOptions(exporter.options(), {"format=fbx"}, &values, &error));
}

TEST(GltfExporter, SkinnedCharacterPassesTheValidatorAndReadsBack) {
  const LodPackage& package = test::bcnPackage();
  ASSERT_TRUE(package.mesh);
  ASSERT_EQ(package.levels.size(), 4u);
  QTemporaryDir dir;
  for (const QString& name : {QStringLiteral("BCN_Epileptic.glb"), QStringLiteral("BCN_Epileptic.gltf")}) {
    SCOPED_TRACE(name.toStdString());
    const Exported out = exportTo(package, dir.filePath(name));
    ASSERT_TRUE(out.result.ok) << out.result.message.toStdString();
    EXPECT_EQ(out.bytes.startsWith("glTF"), name.endsWith(".glb")); // the format follows the suffix

    const test::ValidatorReport report = test::runValidator(out.path);
    EXPECT_EQ(report.exitCode, 0) << report.output;
    EXPECT_EQ(report.errors, 0) << report.output;
    std::cout << "[ validator ] " << name.toStdString() << ": " << out.bytes.size() << " bytes, " << report.errors
              << " errors, " << report.warnings << " warnings, " << report.infos << " infos\n";

    const tinygltf::Model model = parseModel(out.bytes);
    const int joints = package.skeleton.jointCount();
    ASSERT_EQ(model.skins.size(), 1u);
    EXPECT_EQ(int(model.skins[0].joints.size()), joints);
    ASSERT_EQ(model.meshes.size(), package.levels.size()); // one mesh per level
    // weights sum to exactly 1 in float (x + y + z + w), unused slots name joint 0, positions in metres
    for (std::size_t m = 0; m < model.meshes.size(); ++m) {
      const SkinnedMesh* levelMesh = package.levels[m].mesh();
      ASSERT_TRUE(levelMesh != nullptr);
      // one primitive per source mesh (part); together every triangle of the level (in the
      // order meshoptimizer gives them)
      EXPECT_EQ(model.meshes[m].primitives.size(), std::max<std::size_t>(levelMesh->parts.size(), 1));
      const Corners corners = cornersInSourceOrder(model, model.meshes[m], *levelMesh);
      ASSERT_EQ(corners.positions.size(), levelMesh->indices.size());
      int bad = 0;
      for (std::size_t k = 0; k < corners.positions.size(); ++k) {
        const glm::vec4& w = corners.weights[k];
        bad += (w.x + w.y + w.z + w.w) != 1.0f;
        for (int n = 0; n < 4; ++n)
          bad += w[n] == 0.0f && corners.joints[k][n] != 0;
        bad += corners.positions[k] != levelMesh->positions[levelMesh->indices[k]] * 0.01f; // metres
      }
      EXPECT_EQ(bad, 0) << "mesh " << m;
    }
    // MSFT_lod on the first level's node names the other levels' nodes, coarser in order
    const json document = documentOf(out.bytes);
    const json& scene = document["scenes"][0]["nodes"];
    ASSERT_EQ(scene.size(), 2u); // the skeleton's root and the finest level's mesh
    const json& top = document["nodes"][scene[1].get<std::size_t>()];
    EXPECT_EQ(top.at("mesh").get<int>(), 0);
    const std::vector<int> ids = top.at("extensions").at("MSFT_lod").at("ids").get<std::vector<int>>();
    ASSERT_EQ(ids.size(), package.levels.size() - 1);
    for (std::size_t k = 0; k < ids.size(); ++k) {
      const json& node = document["nodes"][std::size_t(ids[k])];
      EXPECT_EQ(node.at("mesh").get<std::size_t>(), k + 1);
      EXPECT_EQ(node.at("skin").get<int>(), 0);
      EXPECT_EQ(node.at("name").get<std::string>(), "BCN_Epileptic_LOD" + std::to_string(k + 1));
      EXPECT_EQ(document["meshes"][k + 1].at("name").get<std::string>(), "BCN_Epileptic_LOD" + std::to_string(k + 1));
    }
    expectCoveragesFollowSwitchDistances(package, document);
    const auto used = document["extensionsUsed"].get<std::vector<std::string>>();
    EXPECT_NE(std::find(used.begin(), used.end(), "MSFT_lod"), used.end());
    expectClusterTablesRoundTrip(package, document, model);
    expectPlaysLikeTheRuntime(package, model, 1, 1e-5);
    expectSkinsLikeTheRuntime(package, model, 1e-5); // 10 um: float rounding is ~1.5 um

    // Assimp reads it back through the project's importer: the same joints, frames, fps
    // (from the animations' extras) and clusters
    const Result<Asset> back = importAsset(out.path.toStdString());
    ASSERT_TRUE(back) << back.message();
    EXPECT_EQ(back->skeleton.jointCount(), joints);
    expectReadBack(package, *back);
    ASSERT_FALSE(back->meshes.empty());
    const SkinnedMesh* finest = package.levels[0].mesh();
    ASSERT_TRUE(finest != nullptr);
    EXPECT_EQ(back->meshes[0].triangleCount(), finest->triangleCount());
  }
}

TEST(GltfExporter, SkeletonAlonePassesTheValidatorAndReadsBack) {
  const LodPackage& package = test::cmuPackage();
  ASSERT_FALSE(package.mesh);
  ASSERT_EQ(package.levels.size(), 4u);
  QTemporaryDir dir;
  const Exported out = exportTo(package, dir.filePath("01_01.glb"));
  ASSERT_TRUE(out.result.ok) << out.result.message.toStdString();
  const test::ValidatorReport report = test::runValidator(out.path);
  EXPECT_EQ(report.exitCode, 0) << report.output;
  EXPECT_EQ(report.errors, 0) << report.output;
  std::cout << "[ validator ] 01_01.glb: " << out.bytes.size() << " bytes, " << report.errors << " errors, "
            << report.warnings << " warnings, " << report.infos << " infos\n";

  const tinygltf::Model model = parseModel(out.bytes);
  EXPECT_TRUE(model.meshes.empty());
  // a skin over every joint, though no mesh uses it: clients import an armature, not empties
  ASSERT_EQ(model.skins.size(), 1u);
  EXPECT_EQ(int(model.skins[0].joints.size()), package.skeleton.jointCount());
  EXPECT_EQ(model.skins[0].skeleton, 0);
  EXPECT_EQ(int(model.nodes.size()), package.skeleton.jointCount());
  const json document = documentOf(out.bytes);
  expectClusterTablesRoundTrip(package, document, model);
  expectPlaysLikeTheRuntime(package, model, 7, 1e-5);

  // clustered spans are held keys: a coarser level keeps fewer rotation keys
  const auto rotationKeys = [&](std::size_t animation) {
    std::size_t keys = 0;
    for (const tinygltf::AnimationChannel& channel : model.animations[animation].channels)
      if (channel.target_path == "rotation")
        keys += model.accessors[std::size_t(model.animations[animation].samplers[std::size_t(channel.sampler)].input)]
                    .count;
    return keys;
  };
  EXPECT_LT(rotationKeys(3), rotationKeys(1));
  // data that repeats is stored once: the root's translation (never clustered) is one accessor for every level
  std::set<int> rootTranslation;
  for (const tinygltf::Animation& animation : model.animations)
    for (const tinygltf::AnimationChannel& channel : animation.channels)
      if (channel.target_node == 0 && channel.target_path == "translation")
        rootTranslation.insert(animation.samplers[std::size_t(channel.sampler)].output);
  EXPECT_EQ(rootTranslation.size(), 1u);
  EXPECT_LT(rotationKeys(1), rotationKeys(0) + 1);

  const Result<Asset> back = importAsset(out.path.toStdString()); // at the file's fps, not the default 30
  ASSERT_TRUE(back) << back.message();
  EXPECT_EQ(back->skeleton.jointCount(), package.skeleton.jointCount());
  expectReadBack(package, *back);
  // lengths come back in cm: metres in the file
  const std::vector<glm::mat4> restIn = package.skeleton.restModelMatrices();
  const std::vector<glm::mat4> restBack = back->skeleton.restModelMatrices();
  for (int j = 0; j < package.skeleton.jointCount(); ++j) {
    const int k = back->skeleton.find(package.skeleton.joints[std::size_t(j)].name);
    ASSERT_GE(k, 0) << package.skeleton.joints[std::size_t(j)].name;
    EXPECT_LT(glm::length(glm::vec3(restIn[std::size_t(j)][3]) - glm::vec3(restBack[std::size_t(k)][3])), 1e-3f);
  }
}

TEST(GltfExporter, StaticMeshAlonePassesTheValidator) {
  // a mesh without a skeleton (OBJ): mesh levels linked by MSFT_lod, no skin, no animation
  const std::optional<LodPackage> package = test::packageOf("OBJ/spider.obj");
  ASSERT_TRUE(package);
  ASSERT_TRUE(package->skeleton.empty());
  QTemporaryDir dir;
  const Exported out = exportTo(*package, dir.filePath("spider.glb"));
  ASSERT_TRUE(out.result.ok) << out.result.message.toStdString();
  const test::ValidatorReport report = test::runValidator(out.path);
  EXPECT_EQ(report.exitCode, 0) << report.output;
  EXPECT_EQ(report.errors, 0) << report.output;
  const tinygltf::Model model = parseModel(out.bytes);
  EXPECT_TRUE(model.skins.empty());
  EXPECT_TRUE(model.animations.empty());
  EXPECT_EQ(model.meshes.size(), package->levels.size());
  const json document = documentOf(out.bytes);
  EXPECT_FALSE(document.contains("extensions")); // no joints, no cluster tables
  const json& scene = document["scenes"][0]["nodes"];
  ASSERT_EQ(scene.size(), 1u);
  EXPECT_EQ(document["nodes"][scene[0].get<std::size_t>()]["extensions"]["MSFT_lod"]["ids"].size(),
            package->levels.size() - 1);
}

TEST(GltfExporter, PrettyGltfIsIndentedJson) {
  const LodPackage& package = test::cmuPackage();
  QTemporaryDir dir;
  const Exported out = exportTo(package, dir.filePath("pretty.gltf"), {"pretty=true"});
  ASSERT_TRUE(out.result.ok) << out.result.message.toStdString();
  EXPECT_TRUE(out.bytes.startsWith("{\n"));
  const Exported forced = exportTo(package, dir.filePath("forced.gltf"), {"format=glb"});
  ASSERT_TRUE(forced.result.ok);
  EXPECT_TRUE(forced.bytes.startsWith("glTF")); // the option wins over the suffix
}

TEST(GltfExporter, UnwritableOutputLeavesNothingAndSaysWhy) {
  const LodPackage& package = test::cmuPackage();
  QTemporaryDir dir;
  const QString missing = dir.filePath("no/such/folder/out.glb");
  const ExportResult result = gltfExporter().exportPackage(package, missing, test::exporterOptions(gltfExporter()), {});
  EXPECT_FALSE(result.ok);
  EXPECT_TRUE(result.message.contains("out.glb")) << result.message.toStdString();
  EXPECT_FALSE(QFileInfo::exists(missing));

  QDir(dir.path()).mkdir("readonly");
  const QString readonlyDir = dir.filePath("readonly");
  QFile::setPermissions(readonlyDir, QFileDevice::ReadOwner | QFileDevice::ExeOwner);
  const ExportResult denied =
      gltfExporter().exportPackage(package, readonlyDir + "/out.glb", test::exporterOptions(gltfExporter()), {});
  QFile::setPermissions(readonlyDir, QFileDevice::ReadOwner | QFileDevice::WriteOwner | QFileDevice::ExeOwner);
  if (::geteuid() != 0) { // root writes anywhere
    EXPECT_FALSE(denied.ok);
    EXPECT_TRUE(test::filesIn(readonlyDir).isEmpty());
  }
}

TEST(GltfExporter, CancelLeavesNothingBehindAndKeepsAnOldFile) {
  const LodPackage& package = test::bcnPackage();
  QTemporaryDir dir;
  for (int cancelAt : {1, 3, 1000}) {
    int calls = 0;
    double last = -1.0;
    const ExportProgress progress(
        [&](double fraction, const QString&) {
          EXPECT_GE(fraction, last);
          last = fraction;
        },
        [&] { return ++calls >= cancelAt; });
    const QString path = dir.filePath("cancelled.glb");
    const ExportResult result =
        gltfExporter().exportPackage(package, path, test::exporterOptions(gltfExporter()), progress);
    if (cancelAt == 1000) { // never cancelled: it went through
      EXPECT_TRUE(result.ok) << result.message.toStdString();
      continue;
    }
    EXPECT_FALSE(result.ok);
    EXPECT_TRUE(result.message.contains("cancelled")) << result.message.toStdString();
    EXPECT_TRUE(test::filesIn(dir.path()).isEmpty()) << test::filesIn(dir.path()).join(' ').toStdString();
  }
  // a cancelled export over an existing file keeps the old file as it was
  const QString path = dir.filePath("cancelled.glb");
  const QByteArray before = readAll(path);
  ASSERT_FALSE(before.isEmpty());
  const ExportProgress cancel({}, [] { return true; });
  EXPECT_FALSE(gltfExporter().exportPackage(package, path, test::exporterOptions(gltfExporter()), cancel).ok);
  EXPECT_EQ(readAll(path), before);
  EXPECT_EQ(test::filesIn(dir.path()), QStringList{"cancelled.glb"});
}

// Guards issue 28, item 2: a level without a switch distance (export --mesh-ratio) or a set
// without a bounding radius has no coverage to give. The file then has MSFT_lod without
// MSFT_screencoverage, and the result warns; before, it carried [1, 1, 1, 0], so a reader
// that honours coverage showed the coarsest level at any size below full screen.
TEST(GltfExporter, NoSwitchDistanceGivesNoCoverageAndAWarning) {
  LodPackage noDistance = test::bcnPackage();
  ASSERT_GE(noDistance.levels.size(), 3u);
  noDistance.levels[2].settings.switchDistanceCm = 0.0;
  LodPackage noRadius = test::bcnPackage();
  noRadius.lods.boundingRadiusCm = 0.0;
  const std::pair<const LodPackage*, std::string> cases[] = {{&noDistance, "level LOD2 has no switch distance"},
                                                             {&noRadius, "the LOD set has no bounding radius"}};
  for (const auto& [package, reason] : cases) {
    SCOPED_TRACE(reason);
    QTemporaryDir dir;
    const Exported out = exportTo(*package, dir.filePath("out.glb"));
    ASSERT_TRUE(out.result.ok) << out.result.message.toStdString();
    const json document = documentOf(out.bytes);
    const json* top = lodNode(document);
    ASSERT_TRUE(top != nullptr);
    EXPECT_EQ(top->at("extensions").at("MSFT_lod").at("ids").size(), package->levels.size() - 1);
    EXPECT_FALSE(top->contains("extras") && top->at("extras").contains("MSFT_screencoverage")) << top->dump();
    QString message = out.result.message;
    const QStringList warnings = splitExportWarnings(&message);
    ASSERT_EQ(warnings.size(), 1) << out.result.message.toStdString();
    EXPECT_TRUE(warnings[0].startsWith(QStringLiteral("no MSFT_screencoverage: ") + QString::fromStdString(reason)))
        << warnings[0].toStdString();
    EXPECT_FALSE(message.contains(QStringLiteral("warning"))) << message.toStdString();
    EXPECT_EQ(test::runValidator(out.path).errors, 0);
  }
  // with its distances and radius, the same package warns of nothing
  QTemporaryDir dir;
  const Exported out = exportTo(test::bcnPackage(), dir.filePath("out.glb"));
  ASSERT_TRUE(out.result.ok);
  QString message = out.result.message;
  EXPECT_TRUE(splitExportWarnings(&message).isEmpty()) << out.result.message.toStdString();
}

bool anyWarningStartsWith(const Asset& asset, const std::string& prefix) {
  return std::any_of(asset.warnings.begin(), asset.warnings.end(),
                     [&](const std::string& w) { return w.rfind(prefix, 0) == 0; });
}

// Guards issue 28, item 6: a tool that rewrites a file (gltf-transform copy, prune) drops the
// vendor extension MLOD_joint_clusters; reading such a file (motionlod info, the studio's
// import) says the cluster tables are gone instead of showing none without a word. The
// animations' extras (which such tools keep) or MSFT_lod tell a file of levels.
TEST(GltfExporter, LostClusterTablesAreSaid) {
  for (const LodPackage* package : {&test::cmuPackage(), &test::bcnPackage()}) {
    SCOPED_TRACE(package->name);
    QTemporaryDir dir;
    const Exported out = exportTo(*package, dir.filePath("out.gltf"));
    ASSERT_TRUE(out.result.ok);
    json document = documentOf(out.bytes);
    const std::string whole = document.dump();
    const Result<Asset> intact = importAssetFromMemory(whole.data(), whole.size(), "gltf");
    ASSERT_TRUE(intact) << intact.message();
    EXPECT_FALSE(anyWarningStartsWith(*intact, "no MLOD_joint_clusters"));
    EXPECT_EQ(intact->clusters.size(), package->clips.size() * package->levels.size());

    document["extensions"].erase("MLOD_joint_clusters"); // what gltf-transform copy leaves
    auto& used = document["extensionsUsed"];
    used.erase(std::remove(used.begin(), used.end(), json("MLOD_joint_clusters")), used.end());
    const std::string rewritten = document.dump();
    const Result<Asset> lost = importAssetFromMemory(rewritten.data(), rewritten.size(), "gltf");
    ASSERT_TRUE(lost) << lost.message();
    const std::string levels = std::to_string(package->clips.size() * package->levels.size());
    EXPECT_TRUE(anyWarningStartsWith(*lost, "no MLOD_joint_clusters: " + levels + " animations of LOD levels, but no "
                                            "cluster tables"))
        << ::testing::PrintToString(lost->warnings);
    if (!package->mesh)
      continue;
    for (json& animation : document["animations"]) // extras gone too: MSFT_lod still tells
      animation.erase("extras");
    const std::string bare = document.dump();
    const Result<Asset> meshOnly = importAssetFromMemory(bare.data(), bare.size(), "gltf");
    ASSERT_TRUE(meshOnly) << meshOnly.message();
    EXPECT_TRUE(anyWarningStartsWith(*meshOnly, "no MLOD_joint_clusters: mesh levels (MSFT_lod), but no cluster tables"))
        << ::testing::PrintToString(meshOnly->warnings);
  }
}

// Frozen spans are held by their ends (or, where cheaper, by the shared every-frame times), so
// a coarser level's keys take fewer bytes; the summary says how many per level, the cluster
// tables counted (issue 28 item 4: a coarser level has more clusters, so BCN_Epileptic's
// LOD1-3, whose keys differ by 20-40 bytes, take a few bytes more in all).
TEST(GltfExporter, AnimationBytesFallWithEachLevel) {
  for (const LodPackage* package : {&test::cmuPackage(), &test::bcnPackage()}) {
    SCOPED_TRACE(package->name);
    QTemporaryDir dir;
    const Exported out = exportTo(*package, dir.filePath("out.glb"));
    ASSERT_TRUE(out.result.ok) << out.result.message.toStdString();
    const std::vector<std::size_t> bytes = animationBytesPerLevel(parseModel(out.bytes), package->levels.size());
    std::cout << "[ animation bytes ] " << package->name << ":";
    for (std::size_t l = 0; l < bytes.size(); ++l)
      std::cout << " LOD" << l << " " << bytes[l];
    std::cout << "\n";
    const auto keyBytes = [&](std::size_t l) {
      const LevelKeyBytes figure = levelKeyBytes(*package, package->levels[l]);
      return figure.bytes - figure.clusterBytes;
    };
    // never more than the finer level; less at the first coarser one (BCN_Epileptic's coarser
    // levels hold every joint but the same few by two keys: their keys take the same bytes)
    for (std::size_t l = 1; l < bytes.size(); ++l)
      EXPECT_LE(keyBytes(l), keyBytes(l - 1)) << "LOD" << l;
    EXPECT_LT(keyBytes(1), keyBytes(0));
    // core's figure (the report's) is the file's, the cluster tables included
    std::size_t tables = 0;
    for (std::size_t l = 0; l < bytes.size(); ++l) {
      EXPECT_EQ(levelKeyBytes(*package, package->levels[l]).bytes, bytes[l]) << "LOD" << l;
      tables += levelKeyBytes(*package, package->levels[l]).clusterBytes;
    }
    EXPECT_GT(tables, 0u);
    // the summary reports the same figures
    const std::string message = out.result.message.toStdString();
    for (std::size_t l = 0; l < bytes.size(); ++l)
      EXPECT_NE(message.find(package->name + "_LOD" + std::to_string(l) + " " + std::to_string(bytes[l]) + " bytes"),
                std::string::npos)
          << message;
  }
}

// Issue 28, item 4: rotation outputs are normalized signed 16-bit integers (glTF core), each
// key within kMaxRotationQuantizationDegrees of the level's motion (held_keys.h), and the
// summary states what they add; CMU 01_01's four levels fit in 3.0 MB (4.07 MB of float keys).
// rotations=float keeps the keys as the level holds them, bit for bit (for readers that misread
// normalized integers, as Assimp 5.2 does); it is refused with compress=meshopt, which stores
// 16-bit keys.
TEST(GltfExporter, FloatRotationsOptionKeepsTheKeysExactly) {
  const LodPackage& package = test::cmuPackage();
  QTemporaryDir dir;
  const Exported out = exportTo(package, dir.filePath("out.glb"), {"rotations=float"});
  ASSERT_TRUE(out.result.ok) << out.result.message.toStdString();
  EXPECT_TRUE(out.result.message.contains("rotation keys as 32-bit floats")) << out.result.message.toStdString();
  const tinygltf::Model model = parseModel(out.bytes);
  std::size_t animation = 0, checked = 0;
  for (const LodPackageLevel& level : package.levels)
    for (std::size_t c = 0; c < package.clips.size(); ++c, ++animation) {
      const tinygltf::Animation& written = model.animations.at(animation);
      std::map<int, int> outputOf; // rotation output accessor by node
      for (const tinygltf::AnimationChannel& channel : written.channels)
        if (channel.target_path == "rotation")
          outputOf[channel.target_node] = written.samplers[std::size_t(channel.sampler)].output;
      for (const LevelTrack& track : levelTracks(package, level, c)) {
        if (track.path != TrackPath::Rotation)
          continue;
        const int output = outputOf.at(track.joint);
        ASSERT_EQ(model.accessors[std::size_t(output)].componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
        const std::vector<float> values = elements<float>(model, output, 4);
        ASSERT_EQ(values, track.values) << "joint " << track.joint;
        ++checked;
      }
    }
  EXPECT_GT(checked, 0u);
  const Exported refused = exportTo(package, dir.filePath("z.glb"), {"rotations=float", "compress=meshopt"});
  EXPECT_FALSE(refused.result.ok);
  EXPECT_TRUE(refused.result.message.contains("rotations")) << refused.result.message.toStdString();
}

TEST(GltfExporter, RotationKeysAreNormalizedShortsWithinTheStatedBound) {
  for (const LodPackage* package : {&test::cmuPackage(), &test::bcnPackage()}) {
    SCOPED_TRACE(package->name);
    QTemporaryDir dir;
    const Exported out = exportTo(*package, dir.filePath("out.glb"));
    ASSERT_TRUE(out.result.ok) << out.result.message.toStdString();
    std::cout << "[ size ] " << package->name << ": " << out.bytes.size() << " bytes\n";
    if (package == &test::cmuPackage()) {
      EXPECT_LE(out.bytes.size(), 3'000'000);
    }
    const tinygltf::Model model = parseModel(out.bytes);
    double worst = 0.0;
    std::size_t animation = 0, checked = 0;
    for (const LodPackageLevel& level : package->levels)
      for (std::size_t c = 0; c < package->clips.size(); ++c, ++animation) {
        const tinygltf::Animation& written = model.animations.at(animation);
        std::map<int, std::vector<glm::quat>> keysOf; // rotation keys by node
        for (const tinygltf::AnimationChannel& channel : written.channels) {
          if (channel.target_path != "rotation")
            continue;
          const int output = written.samplers[std::size_t(channel.sampler)].output;
          const tinygltf::Accessor& accessor = model.accessors[std::size_t(output)];
          EXPECT_EQ(accessor.componentType, TINYGLTF_COMPONENT_TYPE_SHORT);
          EXPECT_TRUE(accessor.normalized);
          keysOf[channel.target_node] = rotationKeys(model, output);
        }
        for (const LevelTrack& track : levelTracks(*package, level, c)) {
          if (track.path != TrackPath::Rotation)
            continue;
          const std::vector<glm::quat>& keys = keysOf[track.joint];
          ASSERT_EQ(keys.size(), track.frames.size()) << "joint " << track.joint;
          for (std::size_t k = 0; k < keys.size(); ++k) {
            const glm::quat expected(track.values[4 * k + 3], track.values[4 * k], track.values[4 * k + 1],
                                     track.values[4 * k + 2]);
            worst = std::max(worst, rotationAngleDegrees(keys[k], expected));
            ++checked;
          }
        }
      }
    EXPECT_GT(checked, 0u);
    EXPECT_LE(worst, kMaxRotationQuantizationDegrees);
    // the bound is 2 asin(1 / 32767); real keys come near it
    EXPECT_NEAR(kMaxRotationQuantizationDegrees, glm::degrees(2.0 * std::asin(1.0 / 32767.0)), 1e-6);
    EXPECT_GT(worst, 0.5 * kMaxRotationQuantizationDegrees);
    std::cout << "[ rotation error ] " << package->name << ": " << worst << " degrees, at most "
              << rotationQuantizationBoundCm(package->skeleton, worst) << " cm at the joints\n";
    // the summary states it, and the joint displacement it bounds
    const std::string message = out.result.message.toStdString();
    EXPECT_NE(message.find("rotation keys as 16-bit integers: at most"), std::string::npos) << message;
    char figure[64];
    std::snprintf(figure, sizeof figure, "%.5f degrees", worst);
    EXPECT_NE(message.find(figure), std::string::npos) << message;
  }
}

// Issue 28, item 4: Assimp 5.2.5 reads normalized integer rotation keys as if they were floats;
// the importer decodes them from the file itself (io/gltf_metadata.h), so a default export
// reads back (motionlod info, the studio) with the level's rotations, and the level's motion
// error stays honest: every joint of the read-back motion within the level's motionErrorCm plus
// what the 16-bit keys add (rotationQuantizationBoundCm()) of the source clip.
TEST(GltfExporter, QuantizedRotationsReadBackThroughTheImporter) {
  const LodPackage& package = test::cmuPackage();
  QTemporaryDir dir;
  const Exported out = exportTo(package, dir.filePath("01_01.glb"));
  ASSERT_TRUE(out.result.ok) << out.result.message.toStdString();
  const Result<Asset> back = importAsset(out.path.toStdString());
  ASSERT_TRUE(back) << back.message(); // before the fix: "has a non-finite rotation at joint 'Hips'"
  ASSERT_EQ(back->clips.size(), package.levels.size() * package.clips.size());
  const Skeleton& skeleton = package.skeleton;
  std::vector<int> to(std::size_t(skeleton.jointCount()));
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    to[std::size_t(j)] = back->skeleton.find(skeleton.joints[std::size_t(j)].name);
    ASSERT_GE(to[std::size_t(j)], 0);
  }
  const double addedCm = rotationQuantizationBoundCm(skeleton);
  for (std::size_t l = 0; l < package.levels.size(); ++l) {
    const LodPackageLevel& level = package.levels[l];
    for (std::size_t c = 0; c < package.clips.size(); ++c) {
      const Clip& source = package.clips[c];
      const Clip& clip = back->clips[l * package.clips.size() + c];
      ASSERT_EQ(clip.frameCount, source.frameCount);
      double worstDegrees = 0.0;
      for (const LevelTrack& track : levelTracks(package, level, c)) {
        if (track.path != TrackPath::Rotation)
          continue;
        std::size_t k = 0; // the key at or before frame f: held spans hold it, other tracks key every frame
        for (int f = 0; f < source.frameCount; ++f) {
          while (k + 1 < track.frames.size() && track.frames[k + 1] <= f)
            ++k;
          const glm::quat expected(track.values[4 * k + 3], track.values[4 * k], track.values[4 * k + 1],
                                   track.values[4 * k + 2]);
          worstDegrees =
              std::max(worstDegrees, rotationAngleDegrees(clip.rotation(to[std::size_t(track.joint)], f), expected));
        }
      }
      // float rounding of Assimp's and the importer's resampling on top of the 16-bit keys
      EXPECT_LT(worstDegrees, kMaxRotationQuantizationDegrees + 1e-3) << clip.name;
      // joint positions: the read-back motion against the source clip, within the level's
      // stated motion error plus the quantization's bound
      double worstCm = 0.0;
      std::vector<glm::mat4> original, read;
      for (int f = 0; f < source.frameCount; f += 3) {
        source.modelMatrices(skeleton, f, original);
        clip.modelMatrices(back->skeleton, f, read);
        for (int r = 0; r < level.skeleton().jointCount(); ++r) {
          const int j = level.build.motion.bones.fullIndex[std::size_t(r)];
          worstCm = std::max(worstCm, double(glm::length(glm::vec3(read[std::size_t(to[std::size_t(j)])][3]) -
                                                         glm::vec3(original[std::size_t(j)][3]))));
        }
      }
      EXPECT_LE(worstCm, level.build.motion.motionErrorCm + addedCm + 1e-3) << clip.name;
    }
  }
}

// The local rotation of `node` that `animation` of `model` gives at `seconds` (LINEAR: slerp
// between the keys around it); nullopt where the animation does not rotate the node.
std::optional<glm::quat> sampledRotation(const tinygltf::Model& model, const tinygltf::Animation& animation, int node,
                                         double seconds) {
  for (const tinygltf::AnimationChannel& channel : animation.channels) {
    if (channel.target_node != node || channel.target_path != "rotation")
      continue;
    const tinygltf::AnimationSampler& sampler = animation.samplers[std::size_t(channel.sampler)];
    const std::vector<float> times = elements<float>(model, sampler.input, 1);
    const std::vector<glm::quat> keys = rotationKeys(model, sampler.output);
    std::size_t k = 0;
    while (k + 1 < times.size() && times[k + 1] <= seconds)
      ++k;
    const std::size_t k1 = std::min(k + 1, times.size() - 1);
    const float a = k1 == k || seconds <= times[k] ? 0.0f : float((seconds - times[k]) / (times[k1] - times[k]));
    return glm::slerp(keys[k], keys[k1], a);
  }
  return std::nullopt;
}

// Issue 28, item 4: compress=meshopt (EXT_meshopt_compression with meshoptimizer's own
// encoders, KHR_mesh_quantization where the normals are quantized) passes the validator,
// brings CMU 01_01's four levels to at most 1.32 MB (gltfpack 1.3 -af 0 -c on the float
// file), and three.js r187 and Babylon.js 9 load it and play it as the uncompressed file plays
// (every rotated joint within 0.02 degrees at a half frame; every mesh vertex there), as .glb
// and as .gltf (the encoded buffer as a data URI). Skipped without Node.
TEST(GltfExporter, MeshoptCompressedPassesTheValidatorAndPlaysInThreeAndBabylon) {
  if (!test::haveNode())
    GTEST_SKIP() << "three.js and Babylon.js run in Node, which is not on PATH";
  for (const LodPackage* package : {&test::cmuPackage(), &test::bcnPackage()})
    for (const QString& file : {QStringLiteral("meshopt.glb"), QStringLiteral("meshopt.gltf")}) {
      SCOPED_TRACE(package->name + " " + file.toStdString());
      const bool binary = file.endsWith(".glb");
      QTemporaryDir dir;
      const Exported plain = exportTo(*package, dir.filePath("plain.glb"));
      const Exported out = exportTo(*package, dir.filePath(file), {"compress=meshopt"});
      ASSERT_TRUE(plain.result.ok && out.result.ok) << out.result.message.toStdString();
      std::cout << "[ size ] " << package->name << ": " << plain.bytes.size() << " bytes, compress=meshopt "
                << out.bytes.size() << " bytes (" << file.toStdString() << ")\n";
      EXPECT_EQ(out.bytes.startsWith("glTF"), binary);
      if (binary) {
        EXPECT_LT(out.bytes.size(), plain.bytes.size());
      }
      if (package == &test::cmuPackage() && binary) {
        EXPECT_LE(out.bytes.size(), 1'320'000);
      }
      const test::ValidatorReport report = test::runValidator(out.path);
      EXPECT_EQ(report.exitCode, 0) << report.output;
      EXPECT_EQ(report.errors, 0) << report.output;
      EXPECT_EQ(report.warnings, 0) << report.output;

      const json document = documentOf(out.bytes);
      const auto required = document.at("extensionsRequired").get<std::vector<std::string>>();
      EXPECT_NE(std::find(required.begin(), required.end(), "EXT_meshopt_compression"), required.end());
      EXPECT_EQ(std::find(required.begin(), required.end(), "KHR_mesh_quantization") != required.end(),
                package->mesh.has_value()); // the normals are 8-bit
      for (const json& view : document.at("bufferViews"))
        EXPECT_TRUE(view.at("extensions").contains("EXT_meshopt_compression")) << view.dump();
      EXPECT_TRUE(
          document.at("buffers").at(1).at("extensions").at("EXT_meshopt_compression").at("fallback").get<bool>());
      // Assimp 5.2 cannot read it: the importer says why
      const Result<Asset> back = importAsset(out.path.toStdString());
      ASSERT_FALSE(back);
      EXPECT_NE(back.message().find("EXT_meshopt_compression"), std::string::npos) << back.message();

      const tinygltf::Model model = parseModel(plain.bytes);
      const std::size_t animation = package->clips.size(); // LOD1's first clip
      const Clip& clip = package->clips[0];
      const double seconds = (std::min(100, clip.frameCount - 2) + 0.5) / clip.fps;
      const test::LoaderReport played = test::runLoaders(out.path, int(animation), seconds);
      ASSERT_EQ(played.exitCode, 0) << played.errors;
      const json result = json::parse(played.output);
      std::size_t vertices = 0;
      if (!model.meshes.empty())
        for (const tinygltf::Primitive& primitive : model.meshes[0].primitives)
          vertices += model.accessors[std::size_t(primitive.attributes.at("POSITION"))].count;
      for (const char* reader : {"three", "babylon"}) {
        SCOPED_TRACE(reader);
        const json& got = result.at(reader);
        ASSERT_EQ(got.at("animations").size(), model.animations.size());
        for (std::size_t a = 0; a < model.animations.size(); ++a)
          EXPECT_EQ(got.at("animations")[a].get<std::string>(), model.animations[a].name);
        EXPECT_EQ(got.at("vertices").get<std::size_t>(), vertices); // the finest level's mesh
        double worst = 0.0;
        int rotated = 0;
        for (int j = 0; j < package->skeleton.jointCount(); ++j) {
          const std::string& name = model.nodes[std::size_t(j)].name;
          const std::optional<glm::quat> expected = sampledRotation(model, model.animations[animation], j, seconds);
          if (!expected)
            continue;
          ASSERT_TRUE(got.at("rotations").contains(name)) << name;
          const std::vector<double> q = got.at("rotations").at(name).get<std::vector<double>>();
          ASSERT_EQ(q.size(), 4u);
          worst = std::max(
              worst, rotationAngleDegrees(glm::quat(float(q[3]), float(q[0]), float(q[1]), float(q[2])), *expected));
          ++rotated;
        }
        EXPECT_EQ(rotated, package->skeleton.jointCount()); // every joint is keyed
        EXPECT_LT(worst, 0.02);
        std::cout << "[ " << reader << " ] " << package->name << " " << model.animations[animation].name << " at "
                  << seconds << " s: " << rotated << " joints, at most " << worst
                  << " degrees from the uncompressed file\n";
      }
    }
}

// The claims about characters below run on every animated character of the shared fixture
// list (unit/real_files.h) at its own or guessed unit: Testwuson.X has three clips, so "one
// animation per clip and level" sees more than one clip (BCN_Epileptic has one).
class GltfExporterOnCharacters : public ::testing::TestWithParam<std::string> {};

// split_levels=true: OUT_LOD0.glb ... one complete character per level, each valid, each
// with its level's mesh, skin, animations and cluster table; OUT itself is not written.
TEST_P(GltfExporterOnCharacters, SplitLevelsWriteOneValidCharacterPerLevel) {
  const LodPackage& package = test::realPackage(GetParam(), 0.0);
  QTemporaryDir dir;
  const Exported whole = exportTo(package, dir.filePath("whole.glb"));
  ASSERT_TRUE(whole.result.ok);
  const std::vector<std::size_t> wholeBytes = animationBytesPerLevel(parseModel(whole.bytes), package.levels.size());
  QDir(dir.path()).mkdir("split");
  const Exported out = exportTo(package, dir.filePath("split/BCN.glb"), {"split_levels=true"});
  ASSERT_TRUE(out.result.ok) << out.result.message.toStdString();
  EXPECT_TRUE(out.bytes.isEmpty()); // no OUT, only OUT_LOD<n>
  QStringList expectedFiles;
  for (std::size_t l = 0; l < package.levels.size(); ++l)
    expectedFiles << QStringLiteral("BCN_LOD%1.glb").arg(l);
  EXPECT_EQ(test::filesIn(dir.filePath("split")), expectedFiles);
  for (std::size_t l = 0; l < package.levels.size(); ++l) {
    const std::string lod = "_LOD" + std::to_string(l);
    SCOPED_TRACE(lod);
    const QString path = dir.filePath(QString::fromStdString("split/BCN" + lod + ".glb"));
    const test::ValidatorReport report = test::runValidator(path);
    EXPECT_EQ(report.exitCode, 0) << report.output;
    EXPECT_EQ(report.errors, 0) << report.output;
    const QByteArray bytes = readAll(path);
    const tinygltf::Model model = parseModel(bytes);
    ASSERT_EQ(model.meshes.size(), 1u);
    EXPECT_EQ(model.meshes[0].name, package.name + lod);
    ASSERT_EQ(model.skins.size(), 1u);
    ASSERT_EQ(model.animations.size(), package.clips.size());
    for (std::size_t c = 0; c < package.clips.size(); ++c)
      EXPECT_EQ(model.animations[c].name, package.clips[c].name + lod);
    EXPECT_EQ(animationBytesPerLevel(model, 1), std::vector<std::size_t>{wholeBytes[l]});
    const json document = documentOf(bytes);
    EXPECT_FALSE(document["nodes"].back().contains("extensions")); // one mesh: no MSFT_lod
    const json& levels = document.at("extensions").at("MLOD_joint_clusters").at("levels");
    ASSERT_EQ(levels.size(), 1u);
    EXPECT_EQ(levels[0].at("level").get<int>(), package.levels[l].index);
    EXPECT_EQ(levels[0].at("nodeName").get<std::string>(), package.name + lod);
    const Result<Asset> back = importAsset(path.toStdString());
    ASSERT_TRUE(back) << back.message();
    ASSERT_EQ(back->clips.size(), package.clips.size());
    for (std::size_t c = 0; c < package.clips.size(); ++c) {
      EXPECT_EQ(back->clips[c].fps, package.clips[c].fps);
      EXPECT_EQ(back->clips[c].frameCount, package.clips[c].frameCount);
    }
  }
}

// Assimp itself (not only the project's importer, which builds the skeleton from nodes)
// sees what engines that import through it get: the mesh named <name>_LOD<n> with its bones,
// and one animation per level. From one file it takes the scene's level only (it ignores
// MSFT_lod, through which alone the coarser levels are reached); from split files each level.
std::set<std::string> assimpMeshes(const QString& path, std::size_t animations) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path.toStdString(), aiProcess_ValidateDataStructure);
  EXPECT_TRUE(scene) << importer.GetErrorString();
  std::set<std::string> names; // Assimp names a primitive's mesh <glTF mesh>-<primitive>
  if (!scene)
    return names;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const std::string name = scene->mMeshes[m]->mName.C_Str();
    names.insert(name.substr(0, name.rfind('-')));
    EXPECT_GT(scene->mMeshes[m]->mNumBones, 0u) << name;
  }
  EXPECT_EQ(scene->mNumAnimations, animations);
  return names;
}

TEST_P(GltfExporterOnCharacters, AssimpSeesBonesLevelNamesAndAnimations) {
  const LodPackage& package = test::realPackage(GetParam(), 0.0);
  QTemporaryDir dir;
  const Exported out = exportTo(package, dir.filePath("BCN.glb"));
  ASSERT_TRUE(out.result.ok);
  EXPECT_EQ(assimpMeshes(out.path, package.levels.size() * package.clips.size()),
            std::set<std::string>{package.name + "_LOD0"});
  const Exported split = exportTo(package, dir.filePath("BCN.glb"), {"split_levels=true"});
  ASSERT_TRUE(split.result.ok);
  for (std::size_t l = 0; l < package.levels.size(); ++l)
    EXPECT_EQ(assimpMeshes(dir.filePath(QStringLiteral("BCN_LOD%1.glb").arg(l)), package.clips.size()),
              std::set<std::string>{package.name + "_LOD" + std::to_string(l)});
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(out.path.toStdString(), aiProcess_ValidateDataStructure);
  ASSERT_TRUE(scene);
  ASSERT_EQ(scene->mNumAnimations, package.levels.size() * package.clips.size());
  std::vector<std::string> names; // one animation per level and clip, level by level
  for (unsigned a = 0; a < scene->mNumAnimations; ++a)
    names.push_back(scene->mAnimations[a]->mName.C_Str());
  std::vector<std::string> expected;
  for (std::size_t l = 0; l < package.levels.size(); ++l)
    for (const Clip& clip : package.clips)
      expected.push_back(clip.name + "_LOD" + std::to_string(l));
  EXPECT_EQ(names, expected);
}

// Issue 28, item 2: on every character, the coverage of each level is where the next one
// switches in, by the formula, strictly falling.
// The triangles of a primitive as position triples (metres, as written), each rotated to
// start at its least corner (the winding kept), sorted: the same set whatever their order.
using Triangle = std::array<std::array<float, 3>, 3>;
std::vector<Triangle> triangleSet(const std::vector<glm::vec3>& corners) {
  std::vector<Triangle> out;
  for (std::size_t t = 0; t + 2 < corners.size(); t += 3) {
    Triangle tri;
    for (int c = 0; c < 3; ++c)
      tri[std::size_t(c)] = {corners[t + std::size_t(c)].x, corners[t + std::size_t(c)].y, corners[t + std::size_t(c)].z};
    std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());
    out.push_back(tri);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Indices renumbered from 0 in order of first use, as the writer did before it ordered them
// for the GPU; `out_vertices` the vertices they use.
std::vector<unsigned int> firstUseOrder(std::span<const std::uint32_t> indices, std::size_t& out_vertices) {
  std::map<std::uint32_t, unsigned int> local;
  std::vector<unsigned int> out;
  for (std::uint32_t i : indices)
    out.push_back(local.emplace(i, unsigned(local.size())).first->second);
  out_vertices = local.size();
  return out;
}

// Issue 28 item 4: each primitive's triangles go through meshopt_optimizeVertexCache and its
// vertices through meshopt_optimizeVertexFetch (attributes, skin joints and weights remapped
// with them). Read back, every primitive has the same triangles (position triples, winding
// kept) as the level's part it was written from, and the ACMR of the 16-entry FIFO cache
// (meshopt_analyzeVertexCache) is no worse than the source order's and is what
// meshopt_optimizeVertexCache gives, nor the bytes fetched (first use: already optimal).
TEST_P(GltfExporterOnCharacters, MeshIndicesAreOrderedForTheGpuAndKeepTheirTriangles) {
  const LodPackage& package = test::realPackage(GetParam(), 0.0);
  QTemporaryDir dir;
  const Exported out = exportTo(package, dir.filePath("gpu.glb"));
  ASSERT_TRUE(out.result.ok) << out.result.message.toStdString();
  const tinygltf::Model model = parseModel(out.bytes);
  ASSERT_EQ(model.meshes.size(), package.levels.size());
  for (std::size_t l = 0; l < package.levels.size(); ++l) {
    SCOPED_TRACE("LOD" + std::to_string(l));
    const std::optional<SkinnedMesh> source = levelMeshOnFullSkeleton(package.levels[l]);
    ASSERT_TRUE(source);
    // the parts as the writer takes them: by first index, one primitive each (or one in all)
    std::vector<std::pair<std::size_t, std::size_t>> parts;
    for (const MeshPart& part : source->parts)
      if (part.indexCount > 0)
        parts.emplace_back(part.firstIndex, part.indexCount);
    std::sort(parts.begin(), parts.end());
    const tinygltf::Mesh& mesh = model.meshes[l];
    if (parts.size() != mesh.primitives.size())
      parts = {{0, source->indices.size()}};
    ASSERT_EQ(parts.size(), mesh.primitives.size());
    double before = 0.0, after = 0.0, optimal = 0.0, fetchBefore = 0.0, fetchAfter = 0.0, triangles = 0.0;
    for (std::size_t p = 0; p < parts.size(); ++p) {
      const tinygltf::Primitive& primitive = mesh.primitives[p];
      const std::span<const std::uint32_t> indices =
          std::span<const std::uint32_t>(source->indices).subspan(parts[p].first, parts[p].second);
      std::vector<glm::vec3> sourceCorners;
      for (std::uint32_t i : indices)
        sourceCorners.push_back(source->positions[i] * 0.01f); // metres, as the writer computes them
      tinygltf::Mesh alone;
      alone.primitives = {primitive};
      const Corners written = cornersOf(model, alone);
      EXPECT_EQ(triangleSet(written.positions), triangleSet(sourceCorners)) << "primitive " << p;

      std::size_t vertices = 0;
      const std::vector<unsigned int> old = firstUseOrder(indices, vertices);
      const std::vector<std::uint16_t> shorts = elements<std::uint16_t>(model, primitive.indices, 1);
      const std::vector<unsigned int> now(shorts.begin(), shorts.end());
      const std::size_t count = model.accessors[std::size_t(primitive.attributes.at("POSITION"))].count;
      ASSERT_EQ(count, vertices);
      before += meshopt_analyzeVertexCache(old.data(), old.size(), vertices, 16, 0, 0).vertices_transformed;
      after += meshopt_analyzeVertexCache(now.data(), now.size(), count, 16, 0, 0).vertices_transformed;
      std::vector<unsigned int> best(old.size());
      meshopt_optimizeVertexCache(best.data(), old.data(), old.size(), vertices);
      optimal += meshopt_analyzeVertexCache(best.data(), best.size(), vertices, 16, 0, 0).vertices_transformed;
      fetchBefore += meshopt_analyzeVertexFetch(old.data(), old.size(), vertices, 12).bytes_fetched;
      fetchAfter += meshopt_analyzeVertexFetch(now.data(), now.size(), count, 12).bytes_fetched;
      triangles += double(indices.size() / 3);
    }
    std::cout << "[ gpu order ] " << package.name << " LOD" << l << ": ACMR " << before / triangles << " -> "
              << after / triangles << ", position bytes fetched " << fetchBefore << " -> " << fetchAfter << "\n";
    EXPECT_LE(after, before);
    EXPECT_LE(after, optimal); // meshoptimizer's order (on main: the source order, 2x the misses on BCN_Epileptic)
    EXPECT_LE(fetchAfter, fetchBefore);
  }
}

TEST_P(GltfExporterOnCharacters, ScreenCoverageFollowsTheSwitchDistances) {
  const LodPackage& package = test::realPackage(GetParam(), 0.0);
  ASSERT_GE(package.levels.size(), 2u);
  QTemporaryDir dir;
  const Exported out = exportTo(package, dir.filePath("out.gltf"));
  ASSERT_TRUE(out.result.ok) << out.result.message.toStdString();
  EXPECT_FALSE(out.result.message.contains(QStringLiteral("warning: "))) << out.result.message.toStdString();
  expectCoveragesFollowSwitchDistances(package, documentOf(out.bytes));
}

INSTANTIATE_TEST_SUITE_P(Characters, GltfExporterOnCharacters, ::testing::ValuesIn(test::fixtureCharacters("animated")),
                         test::fixtureName);

// MLOD_joint_clusters names its animations and joints as well as numbering them: a tool that
// reorders the animations leaves the importer able to find each animation's clusters. On every
// clip of the fixture list (unit/real_files.h), at CMU's unit, every level's animation
// reversed.
class GltfExporterOnClips : public ::testing::TestWithParam<std::string> {};

TEST_P(GltfExporterOnClips, ClusterTablesSurviveRenumberedAnimations) {
  const LodPackage& package = test::realPackage(GetParam(), 5.6444);
  ASSERT_EQ(package.clips.size(), 1u);
  const std::size_t levels = package.levels.size();
  ASSERT_GE(levels, 2u);
  QTemporaryDir dir;
  const Exported out = exportTo(package, dir.filePath("clip.gltf"));
  ASSERT_TRUE(out.result.ok);
  json document = documentOf(out.bytes);
  json& animations = document["animations"];
  ASSERT_EQ(animations.size(), levels);
  std::reverse(animations.begin(), animations.end()); // the coarsest first: the indices now lie
  const std::string renumbered = document.dump();
  const Result<Asset> back = importAssetFromMemory(renumbered.data(), renumbered.size(), "gltf");
  ASSERT_TRUE(back) << back.message();
  ASSERT_EQ(back->clips.size(), levels);
  ASSERT_EQ(back->clusters.size(), levels);
  std::size_t clustered = 0;
  for (std::size_t a = 0; a < levels; ++a) {
    const std::size_t level = levels - 1 - a;
    EXPECT_EQ(back->clips[a].name, package.clips[0].name + "_LOD" + std::to_string(level));
    const std::size_t expected = package.levels[level].build.motion.clusters[0].clusterCount();
    EXPECT_EQ(back->clusters[a].clusterCount(), expected) << back->clips[a].name;
    clustered += expected;
  }
  EXPECT_GT(clustered, 0u) << "no level has clusters: nothing was checked";
}

// Issue 28 item 4: version 2 stores each clip's clusters as a binary table (8 bytes a
// cluster) where version 1 wrote JSON arrays. A file of version 1 (the exports made before)
// still reads, with the same clusters: the table here is turned back into version 1's
// joints[].clusters and both files imported.
TEST_P(GltfExporterOnClips, ClusterTablesOfVersion1AreStillRead) {
  const LodPackage& package = test::realPackage(GetParam(), 5.6444);
  QTemporaryDir dir;
  const Exported out = exportTo(package, dir.filePath("clip.gltf"));
  ASSERT_TRUE(out.result.ok);
  const tinygltf::Model model = parseModel(out.bytes);
  json document = documentOf(out.bytes);
  json& extension = document["extensions"]["MLOD_joint_clusters"];
  ASSERT_EQ(extension.at("version").get<int>(), 2);
  std::size_t tables = 0;
  for (json& level : extension.at("levels"))
    for (json& entry : level.at("animations")) {
      json joints = json::array();
      if (entry.contains("clusters")) {
        ++tables;
        const std::vector<std::uint32_t> rows = clusterRows(model, entry["clusters"].get<int>());
        for (std::size_t r = 0; r + 3 < rows.size(); r += 4) {
          if (joints.empty() || joints.back()["node"].get<std::uint32_t>() != rows[r])
            joints.push_back(
                {{"node", rows[r]}, {"name", document["nodes"][rows[r]]["name"]}, {"clusters", json::array()}});
          joints.back()["clusters"].push_back({rows[r + 1], rows[r + 2], rows[r + 3]});
        }
        entry.erase("clusters");
      }
      entry["joints"] = std::move(joints);
    }
  ASSERT_GT(tables, 0u) << "no cluster table: nothing was checked";
  extension["version"] = 1;
  extension.erase("jointNames");
  const std::string v1 = document.dump();
  const Result<Asset> old = importAssetFromMemory(v1.data(), v1.size(), "gltf");
  const Result<Asset> now = importAsset(out.path.toStdString());
  ASSERT_TRUE(old) << old.message();
  ASSERT_TRUE(now) << now.message();
  EXPECT_TRUE(old->warnings.empty()) << ::testing::PrintToString(old->warnings);
  ASSERT_EQ(old->clusters.size(), package.levels.size());
  ASSERT_EQ(now->clusters.size(), old->clusters.size());
  for (std::size_t a = 0; a < old->clusters.size(); ++a) {
    EXPECT_EQ(old->clusters[a].joints, now->clusters[a].joints) << "animation " << a;
    EXPECT_EQ(now->clusters[a].clusterCount(), package.levels[a].build.motion.clusters[0].clusterCount());
  }
}

// Guards issue 28, item 3: a CMU clip mapped onto BCN_Epileptic (the automatic mapping, as a
// project's mapping or export --motion makes it) drives only the joints the mapping names.
// In the file, every animation (the character's own clip and the mapped one, every level)
// keys every joint's rotation, and every translation or scale that any animation keys; each
// joint the mapping leaves out holds its rest (bind) rotation by a held track of at most 2
// keys. Before, the mapped clip keyed 27 of 54 joints, so played after the character's own
// clip the others kept that clip's pose. On every clip of the fixture list.
TEST_P(GltfExporterOnClips, MappedClipKeysEveryJointOfTheCharacter) {
  ImportOptions characterUnit, clipUnit;
  characterUnit.unitScale = 100.0;
  clipUnit.unitScale = 2.54 / 0.45;
  const Result<Asset> character = importAsset(test::modelPath("X/BCN_Epileptic.X"), characterUnit);
  const Result<Asset> motion = importAsset(test::modelPath(GetParam()), clipUnit);
  ASSERT_TRUE(character && motion);
  const MotionMapping mapping = MotionMapping::automatic(motion->skeleton, character->skeleton);
  const Result<RestPoseDifferences> differences =
      restPoseDifferences(mapping, motion->skeleton, character->skeleton);
  ASSERT_TRUE(differences) << differences.message();
  const Result<Clip> mapped = retargetClip(*differences, motion->skeleton, motion->clips.at(0), character->skeleton);
  ASSERT_TRUE(mapped) << mapped.message();
  const int joints = character->skeleton.jointCount();
  std::set<int> unmapped;
  for (int j = 1; j < joints; ++j)
    if (differences->source[std::size_t(j)] < 0)
      unmapped.insert(j);
  ASSERT_FALSE(unmapped.empty()) << "the mapping names every joint: nothing to check";
  std::cout << "[ mapped ] " << GetParam() << " on BCN_Epileptic: " << joints - int(unmapped.size()) << " of "
            << joints << " joints mapped\n";

  LodSet lods;
  lods.boundingRadiusCm = 100.0;
  lods.levels.resize(2);
  lods.levels[0].name = "LOD0";
  lods.levels[1] = {.name = "LOD1", .motionThreshold = 50.0, .meshRatio = 0.5, .switchDistanceCm = 1000.0};
  JpcSettings jpc;
  jpc.zeroLength = 1e-6 * character->unitScale;
  const Result<LodPackage> package = buildLodPackage(*character, lods, jpc, {}, {}, std::span<const Clip>(&*mapped, 1));
  ASSERT_TRUE(package) << package.message();
  ASSERT_EQ(package->clips.size(), character->clips.size() + 1);
  QTemporaryDir dir;
  const Exported out = exportTo(*package, dir.filePath("mapped.glb"));
  ASSERT_TRUE(out.result.ok) << out.result.message.toStdString();
  EXPECT_EQ(test::runValidator(out.path).errors, 0);
  const tinygltf::Model model = parseModel(out.bytes);
  ASSERT_EQ(model.animations.size(), package->clips.size() * package->levels.size());

  std::map<std::string, std::set<int>> keyedByAny; // path -> nodes some animation keys
  for (const tinygltf::Animation& animation : model.animations)
    for (const tinygltf::AnimationChannel& channel : animation.channels)
      keyedByAny[channel.target_path].insert(channel.target_node);
  int checked = 0;
  for (const tinygltf::Animation& animation : model.animations) {
    SCOPED_TRACE(animation.name);
    std::map<std::string, std::set<int>> keyed;
    for (const tinygltf::AnimationChannel& channel : animation.channels)
      EXPECT_TRUE(keyed[channel.target_path].insert(channel.target_node).second) << "node " << channel.target_node;
    std::set<int> every;
    for (int j = 0; j < joints; ++j)
      every.insert(j);
    EXPECT_EQ(keyed["rotation"], every);
    EXPECT_EQ(keyed["translation"], keyedByAny["translation"]);
    EXPECT_EQ(keyed["scale"], keyedByAny["scale"]);
    if (animation.name.rfind(mapped->name + "_LOD", 0) != 0)
      continue;
    // the mapped clip: what the mapping leaves out holds the node's rest rotation
    for (const tinygltf::AnimationChannel& channel : animation.channels) {
      if (channel.target_path != "rotation" || !unmapped.count(channel.target_node))
        continue;
      const tinygltf::AnimationSampler& sampler = animation.samplers[std::size_t(channel.sampler)];
      const std::vector<glm::quat> keys = rotationKeys(model, sampler.output);
      EXPECT_LE(keys.size(), 2u) << "node " << channel.target_node << ": a held key is at most 2 keys";
      const tinygltf::Node& node = model.nodes[std::size_t(channel.target_node)];
      const glm::quat rest = node.rotation.size() == 4 ? glm::quat(float(node.rotation[3]), float(node.rotation[0]),
                                                                   float(node.rotation[1]), float(node.rotation[2]))
                                                       : glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
      for (const glm::quat& q : keys)
        EXPECT_LE(rotationAngleDegrees(q, rest), kMaxRotationQuantizationDegrees) << node.name;
      ++checked;
    }
  }
  EXPECT_EQ(checked, int(unmapped.size() * package->levels.size()));
}

INSTANTIATE_TEST_SUITE_P(Clips, GltfExporterOnClips, ::testing::ValuesIn(test::fixtureClips()), test::fixtureName);

} // namespace
} // namespace mlod
