#include "core/mesh/mesh_lod.h"

#include "core/mesh/skinning.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <limits>
#include <thread>

namespace mlod {

Error MeshLodSettings::validate() const {
  const ProgressiveMeshSettings& s = simplification;
  for (double weight : {s.borderWeight, s.seamWeight, s.skinWeight, s.moveWeight})
    if (!std::isfinite(weight) || weight < 0.0)
      return Error("mesh LOD: the border, seam, skin and move weights must be finite and >= 0");
  if (!std::isfinite(samplingSpacingCm) || samplingSpacingCm < 0.0)
    return Error("mesh LOD: the sampling spacing must be finite and >= 0 cm");
  if (simplifyPoses < 0 || measurePoses < 0)
    return Error("mesh LOD: pose counts must be >= 0");
  for (float importance : jointImportance)
    if (!std::isfinite(importance) || !(importance > 0.0f))
      return Error("mesh LOD: a joint's mesh importance must be finite and > 0");
  return {};
}

std::vector<float> vertexImportance(const SkinnedMesh& mesh, std::span<const float> jointImportance) {
  std::vector<float> out(mesh.vertexCount(), 1.0f);
  if (!mesh.skinned() || jointImportance.empty())
    return out;
  for (std::size_t v = 0; v < out.size(); ++v) {
    float sum = 0.0f;
    for (int i = 0; i < kMaxInfluences; ++i)
      if (mesh.weights[v][i] > 0.0f)
        sum += mesh.weights[v][i] * jointImportance[mesh.joints[v][i]];
    out[v] = sum > 0.0f ? sum : 1.0f;
  }
  return out;
}

std::vector<std::pair<int, int>> spreadFrames(std::span<const int> frameCounts, int count,
                                              std::span<const std::pair<int, int>> exclude) {
  std::vector<std::pair<int, int>> all; // every frame of every clip, in order
  for (std::size_t c = 0; c < frameCounts.size(); ++c)
    for (int f = 0; f < frameCounts[c]; ++f)
      if (std::find(exclude.begin(), exclude.end(), std::pair<int, int>(int(c), f)) == exclude.end())
        all.emplace_back(int(c), f);
  std::vector<std::pair<int, int>> out;
  const std::size_t n = all.size();
  const std::size_t k = std::min<std::size_t>(std::size_t(std::max(count, 0)), n);
  for (std::size_t i = 0; i < k; ++i) // the middle of each of k equal stretches
    out.push_back(all[std::min(n - 1, static_cast<std::size_t>((double(i) + 0.5) * double(n) / double(k)))]);
  return out;
}

Result<MeshLod> MeshLod::build(const SkinnedMesh& mesh, const Skeleton* skeleton, std::span<const Clip> clips,
                               const MeshLodSettings& settings) {
  if (Error error = settings.validate())
    return error;
  const int jointCount = skeleton ? skeleton->jointCount() : 65536;
  if (Error error = mesh.validate(jointCount))
    return Error("mesh '" + mesh.name + "': " + error.message());
  if (!clips.empty() && !skeleton)
    return Error("mesh LOD: clips need the skeleton they animate");
  for (const Clip& clip : clips)
    if (Error error = clip.validate(*skeleton))
      return Error("clip '" + clip.name + "': " + error.message());
  if (!settings.jointImportance.empty() &&
      (!skeleton || int(settings.jointImportance.size()) != skeleton->jointCount()))
    return Error("mesh LOD: one mesh importance per joint of the skeleton");

  if (cancelled(settings.cancel))
    return Error(kCancelled);
  MeshLod out;
  out.m_original = mesh;
  out.m_settings = settings;

  glm::vec3 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
  for (const glm::vec3& p : mesh.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const double diagonal = glm::length(glm::dvec3(hi) - glm::dvec3(lo));
  out.m_spacing =
      settings.samplingSpacingCm > 0.0 ? settings.samplingSpacingCm : (diagonal > 0.0 ? 0.005 * diagonal : 1.0);

  out.m_simplifyPoses.push_back(mesh.positions);
  out.m_simplifyFrames.emplace_back(-1, -1);
  if (skeleton && mesh.skinned() && !clips.empty()) {
    std::vector<int> frameCounts;
    int total = 0;
    for (const Clip& clip : clips) {
      frameCounts.push_back(clip.frameCount);
      total += clip.frameCount;
    }
    // note: at most half the frames shape the mesh, so that others are left to measure it in
    const int simplify = std::min(settings.simplifyPoses, settings.measurePoses > 0 ? total / 2 : total);
    const std::vector<std::pair<int, int>> fitted = spreadFrames(frameCounts, simplify);
    const std::vector<std::pair<int, int>> measured = spreadFrames(frameCounts, settings.measurePoses, fitted);
    for (const auto& [c, frame] : fitted) {
      if (cancelled(settings.cancel))
        return Error(kCancelled);
      out.m_simplifyPoses.push_back(posedPositions(mesh, *skeleton, clips[std::size_t(c)], frame));
      out.m_simplifyFrames.emplace_back(c, frame);
    }
    for (const auto& [c, frame] : measured) {
      if (cancelled(settings.cancel))
        return Error(kCancelled);
      out.m_measurePoses.push_back(posedPositions(mesh, *skeleton, clips[std::size_t(c)], frame));
      out.m_measureFrames.emplace_back(c, frame);
    }
  }
  auto trees = std::make_shared<std::vector<TriangleTree>>();
  trees->emplace_back(mesh.positions, mesh.indices);
  for (const std::vector<glm::vec3>& pose : out.m_measurePoses) {
    if (cancelled(settings.cancel))
      return Error(kCancelled);
    trees->emplace_back(pose, mesh.indices);
  }
  out.m_originalTrees = std::move(trees);
  const std::vector<float> importance = vertexImportance(mesh, settings.jointImportance);
  out.m_progressive =
      ProgressiveMesh::build(mesh, out.m_simplifyPoses, importance, settings.simplification, settings.cancel);
  if (cancelled(settings.cancel)) // the collapse order may have stopped short
    return Error(kCancelled);
  return out;
}

MeshLod::Errors MeshLod::errorsOf(const MeshLevelIndices& level) const {
  // one pose: the symmetric max distance, the original's tree built once (build())
  const std::vector<std::uint32_t>& original = m_original.indices;
  const auto poseError = [&](std::size_t pose) {
    if (cancelled(m_settings.cancel)) // the caller drops what is measured after a cancel
      return 0.0;
    const std::vector<glm::vec3>& positions = pose == 0 ? m_original.positions : m_measurePoses[pose - 1];
    const TriangleTree levelTree(positions, level.indices);
    const double toLevel = oneSidedMaxDistance(positions, original, level.indices, levelTree, m_spacing);
    return oneSidedMaxDistance(positions, level.indices, original, (*m_originalTrees)[pose], m_spacing, toLevel);
  };
  // note: the poses are independent, so they are measured on as many threads as there are
  // cores (up to one per pose); each result goes to its own slot
  const std::size_t poses = 1 + m_measurePoses.size();
  std::vector<double> errors(poses, 0.0);
  const std::size_t threads = std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1, poses);
  std::vector<std::thread> workers;
  for (std::size_t t = 1; t < threads; ++t)
    workers.emplace_back([&, t] {
      for (std::size_t p = t; p < poses; p += threads)
        errors[p] = poseError(p);
    });
  for (std::size_t p = 0; p < poses; p += threads)
    errors[p] = poseError(p);
  for (std::thread& worker : workers)
    worker.join();
  Errors out;
  out.bindCm = errors[0];
  double sum = 0.0;
  for (std::size_t p = 1; p < poses; ++p) {
    out.animatedMaxCm = std::max(out.animatedMaxCm, errors[p]);
    sum += errors[p];
  }
  out.animatedMeanCm = m_measurePoses.empty() ? 0.0 : sum / double(m_measurePoses.size());
  return out;
}

bool MeshLod::exceeds(const MeshLevelIndices& level, double maxErrorCm) const {
  // note: with the bound as the floor, a sample nearer than it is settled by the first
  // triangle found within it (surface_distance.h), so a level that fits costs far less than
  // measuring it, and one that does not stops at the first pose that shows it
  const std::vector<std::uint32_t>& original = m_original.indices;
  for (std::size_t pose = 0; pose <= m_measurePoses.size(); ++pose) {
    if (cancelled(m_settings.cancel)) // the caller drops what is measured after a cancel
      return false;
    const std::vector<glm::vec3>& positions = pose == 0 ? m_original.positions : m_measurePoses[pose - 1];
    const TriangleTree levelTree(positions, level.indices);
    if (oneSidedMaxDistance(positions, original, level.indices, levelTree, m_spacing, maxErrorCm) > maxErrorCm ||
        oneSidedMaxDistance(positions, level.indices, original, (*m_originalTrees)[pose], m_spacing, maxErrorCm) >
            maxErrorCm)
      return true;
  }
  return false;
}

MeshLod::Errors MeshLod::errorsAt(std::size_t collapses) const {
  if (collapses == 0)
    return {};
  return errorsOf(m_progressive.level(collapses));
}

SkinnedMesh MeshLod::compact(const MeshLevelIndices& level, std::vector<std::uint32_t>* out_sourceVertices) const {
  const SkinnedMesh& source = m_original;
  constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> remap(source.vertexCount(), kUnused);
  for (std::uint32_t v : level.indices)
    remap[v] = 0;
  SkinnedMesh out;
  out.name = source.name;
  std::vector<std::uint32_t> sources;
  for (std::size_t v = 0; v < source.vertexCount(); ++v) {
    if (remap[v] == kUnused)
      continue;
    remap[v] = static_cast<std::uint32_t>(sources.size());
    sources.push_back(static_cast<std::uint32_t>(v));
    out.positions.push_back(source.positions[v]);
    if (!source.normals.empty())
      out.normals.push_back(source.normals[v]);
    if (!source.uvs.empty())
      out.uvs.push_back(source.uvs[v]);
    if (source.skinned()) {
      out.joints.push_back(source.joints[v]);
      out.weights.push_back(source.weights[v]);
    }
  }
  out.indices.reserve(level.indices.size());
  for (std::uint32_t v : level.indices)
    out.indices.push_back(remap[v]);
  // parts: triangles keep their original order, so each part stays one range
  for (const MeshPart& part : source.parts) {
    const std::uint32_t firstTriangle = part.firstIndex / 3, endTriangle = (part.firstIndex + part.indexCount) / 3;
    const auto begin = std::lower_bound(level.triangles.begin(), level.triangles.end(), firstTriangle);
    const auto end = std::lower_bound(level.triangles.begin(), level.triangles.end(), endTriangle);
    MeshPart kept = part;
    kept.firstIndex = static_cast<std::uint32_t>(begin - level.triangles.begin()) * 3;
    kept.indexCount = static_cast<std::uint32_t>(end - begin) * 3;
    out.parts.push_back(kept);
  }
  if (out_sourceVertices)
    *out_sourceVertices = std::move(sources);
  return out;
}

MeshLodLevel MeshLod::makeLevel(std::size_t collapses, double ratio, std::size_t target) const {
  MeshLodLevel level;
  level.ratio = ratio;
  level.targetTriangles = target;
  level.collapses = collapses;
  const MeshLevelIndices indices = m_progressive.level(collapses);
  level.mesh = compact(indices, &level.sourceVertices);
  const Errors errors = collapses == 0 ? Errors{} : errorsOf(indices);
  level.bindErrorCm = errors.bindCm;
  level.animatedErrorCm = errors.animatedMaxCm;
  level.animatedMeanErrorCm = errors.animatedMeanCm;
  level.maxErrorCm = errors.maxCm();

  // every locked vertex the original uses must still be used, where it was
  std::vector<std::uint8_t> used(m_original.vertexCount(), 0), kept(m_original.vertexCount(), 0);
  for (std::uint32_t v : m_original.indices)
    used[v] = 1;
  for (std::size_t i = 0; i < level.sourceVertices.size(); ++i) {
    const std::uint32_t v = level.sourceVertices[i];
    kept[m_progressive.weld()[v]] = level.mesh.positions[i] == m_original.positions[v] ? 1 : 0;
  }
  const std::vector<std::uint8_t>& locked = m_progressive.locked();
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v] && locked[v] && !kept[m_progressive.weld()[v]])
      level.lockedVerticesPreserved = false;
  return level;
}

MeshLodLevel MeshLod::levelAt(std::size_t collapses) const {
  assert(collapses <= m_progressive.collapseCount());
  const std::size_t triangles = m_progressive.trianglesAfter(collapses);
  const double ratio = double(triangles) / double(m_progressive.triangleCount());
  return makeLevel(collapses, ratio, triangles);
}

MeshLodLevel MeshLod::levelForRatio(double ratio) const {
  assert(ratio > 0.0 && ratio <= 1.0);
  const std::size_t total = m_progressive.triangleCount();
  const std::size_t target = std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(ratio * double(total))));
  const std::size_t collapses = m_progressive.collapsesFor(target);
  MeshLodLevel level = makeLevel(collapses, ratio, target);
  const std::size_t reached = m_progressive.trianglesAfter(collapses);
  if (reached > target) {
    char text[320];
    std::snprintf(text, sizeof text,
                  "ratio %g asks for %zu triangles; collapses that keep the surface manifold stop at %zu (ratio %.3f; "
                  "%d of %d welded vertices locked as non-manifold)",
                  ratio, target, reached, double(reached) / double(total), m_progressive.lockedCount(),
                  m_progressive.weldedVertexCount());
    level.warning = text;
  }
  return level;
}

MeshLodLevel MeshLod::levelForError(double maxErrorCm) const {
  assert(maxErrorCm >= 0.0);
  // largest k with error(k) <= maxErrorCm; error(0) = 0
  const std::size_t all = m_progressive.collapseCount();
  if (errorsAt(all).maxCm() <= maxErrorCm)
    return levelAt(all);
  std::size_t good = 0, bad = all;
  while (bad - good > 1) {
    const std::size_t mid = good + (bad - good) / 2;
    if (errorsAt(mid).maxCm() <= maxErrorCm)
      good = mid;
    else
      bad = mid;
  }
  return levelAt(good);
}

MeshLodLevel MeshLod::levelForErrorAmong(double maxErrorCm, std::span<const double> ratios) const {
  assert(maxErrorCm >= 0.0);
  const std::size_t total = m_progressive.triangleCount();
  const auto collapsesOf = [&](double ratio) {
    assert(ratio > 0.0 && ratio <= 1.0);
    return m_progressive.collapsesFor(
        std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(ratio * double(total)))));
  };
  // note: bisection over the candidates (the error grows as the ratio falls, if not
  // strictly): the largest index that fits, in about log2(n) measurements
  std::size_t fits = 0, misses = ratios.size() + 1; // in 1-based candidate positions; 0 = the original
  while (misses - fits > 1) {
    const std::size_t mid = fits + (misses - fits) / 2;
    if (!exceeds(m_progressive.level(collapsesOf(ratios[mid - 1])), maxErrorCm))
      fits = mid;
    else
      misses = mid;
  }
  return levelAt(fits == 0 ? 0 : collapsesOf(ratios[fits - 1]));
}

} // namespace mlod
