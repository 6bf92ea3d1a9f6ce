#include "core/mesh/mesh_lod.h"

#include "core/mesh/skinning.h"
#include "core/mesh/surface_distance.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>

namespace mlod {

Error MeshLodSettings::validate() const {
  const double normal = decimation.maxNormalDeviationDegrees;
  if (!(normal > 0.0 && normal <= 180.0))
    return Error("mesh LOD: the largest normal deviation per collapse must be in (0, 180] degrees");
  const double aspect = decimation.maxAspectRatio;
  if (!std::isfinite(aspect) || !(aspect == 0.0 || aspect >= 1.0))
    return Error("mesh LOD: the aspect-ratio guard must be 0 (off) or at least 1");
  if (!std::isfinite(samplingSpacingCm) || samplingSpacingCm < 0.0)
    return Error("mesh LOD: the sampling spacing must be finite and >= 0 cm");
  if (posesPerClip < 0)
    return Error("mesh LOD: poses per clip must be >= 0");
  return {};
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

  MeshLod out;
  out.m_original = mesh;
  out.m_settings = settings;
  out.m_segmentation = segmentMesh(mesh);
  out.m_progressive = ProgressiveMesh::build(mesh, out.m_segmentation, settings.decimation);

  glm::vec3 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
  for (const glm::vec3& p : mesh.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const double diagonal = glm::length(glm::dvec3(hi) - glm::dvec3(lo));
  out.m_spacing = settings.samplingSpacingCm > 0.0 ? settings.samplingSpacingCm : (diagonal > 0.0 ? 0.005 * diagonal : 1.0);

  out.m_poses.push_back(mesh.positions);
  out.m_poseFrames.emplace_back(-1, -1);
  if (skeleton && mesh.skinned())
    for (std::size_t c = 0; c < clips.size(); ++c) {
      const Clip& clip = clips[c];
      const int count = std::min(settings.posesPerClip, clip.frameCount);
      int previous = -1;
      for (int i = 0; i < count; ++i) {
        const int frame = count == 1 ? 0 : static_cast<int>(std::lround(double(i) * (clip.frameCount - 1) / (count - 1)));
        if (frame == previous)
          continue;
        previous = frame;
        out.m_poses.push_back(posedPositions(mesh, *skeleton, clip, frame));
        out.m_poseFrames.emplace_back(static_cast<int>(c), frame);
      }
    }

  out.m_segmentIndices.resize(out.m_segmentation.segments.size());
  for (std::size_t s = 0; s < out.m_segmentation.segments.size(); ++s)
    for (std::uint32_t t : out.m_segmentation.segments[s].triangles)
      for (std::size_t k = 0; k < 3; ++k)
        out.m_segmentIndices[s].push_back(mesh.indices[std::size_t(t) * 3 + k]);
  return out;
}

double MeshLod::poseError(std::size_t pose, const MeshLevelIndices& level, double floorCm) const {
  const std::vector<glm::vec3>& positions = m_poses[pose];
  std::vector<std::vector<std::uint32_t>> levelIndices(m_segmentIndices.size());
  for (std::size_t i = 0; i < level.triangles.size(); ++i) {
    const auto s = static_cast<std::size_t>(m_segmentation.triangleSegment[level.triangles[i]]);
    levelIndices[s].insert(levelIndices[s].end(), level.indices.begin() + std::ptrdiff_t(i * 3),
                           level.indices.begin() + std::ptrdiff_t(i * 3 + 3));
  }
  // note: segments in falling order of the progressive mesh's estimate, so that the largest
  // distance is found early and every later sample nearer than it is settled at once
  std::vector<std::pair<double, std::size_t>> order;
  for (std::size_t s = 0; s < m_segmentIndices.size(); ++s) {
    if (levelIndices[s] == m_segmentIndices[s])
      continue; // untouched segment
    const std::size_t removed = m_segmentIndices[s].size() / 3 - levelIndices[s].size() / 3;
    std::size_t collapses = 0; // each collapse of a segment removes two of its triangles
    while (collapses < m_progressive.segmentCollapseCount(int(s)) &&
           m_progressive.segmentTrianglesAfter(int(s), collapses) > m_segmentIndices[s].size() / 3 - removed)
      ++collapses;
    order.emplace_back(m_progressive.segmentCostAt(int(s), collapses), s);
  }
  std::sort(order.begin(), order.end(), std::greater<>());
  double worst = floorCm;
  for (const auto& [estimate, s] : order)
    worst = symmetricMaxDistance(positions, m_segmentIndices[s], levelIndices[s], m_spacing, worst);
  return worst;
}

MeshLod::Errors MeshLod::errorsOf(const MeshLevelIndices& level) const {
  Errors errors;
  errors.bindCm = poseError(0, level, 0.0);
  for (std::size_t pose = 1; pose < m_poses.size(); ++pose)
    errors.animatedCm = poseError(pose, level, errors.animatedCm);
  return errors;
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
  level.animatedErrorCm = errors.animatedCm;
  level.maxErrorCm = errors.maxCm();

  // every locked vertex the original uses must still be used, where it was
  std::vector<std::uint8_t> used(m_original.vertexCount(), 0), kept(m_original.vertexCount(), 0);
  for (std::uint32_t v : m_original.indices)
    used[v] = 1;
  for (std::size_t i = 0; i < level.sourceVertices.size(); ++i) {
    const std::uint32_t v = level.sourceVertices[i];
    kept[v] = level.mesh.positions[i] == m_original.positions[v] ? 1 : 0;
  }
  const std::vector<std::uint8_t>& locked = m_progressive.locked();
  for (std::size_t v = 0; v < used.size(); ++v)
    if (used[v] && locked[v] && !kept[v])
      level.sharedVerticesPreserved = false;
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
                  "ratio %g asks for %zu triangles; the locked vertices (%d of %zu: shared between joints or on a "
                  "border) allow no fewer than %zu (ratio %.3f)",
                  ratio, target, m_progressive.lockedCount(), m_original.vertexCount(), reached,
                  double(reached) / double(total));
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

} // namespace mlod
