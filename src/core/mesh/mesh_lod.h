#pragma once
// Mesh LOD of a skinned character (Ahn & Wohn, section 5): the mesh split by joint segment
// with its shared and border vertices locked (mesh_segments.h), a progressive mesh per
// segment (progressive_mesh.h), and levels taken from it by triangle ratio or by error, each
// measured against the original in cm (surface_distance.h).
//
// Error of a level: the symmetric maximum distance between each segment's simplified
// triangles and its own original triangles (which bounds the whole surfaces' distance from
// above), the largest over the segments and over the measured poses: the bind pose and,
// where a skeleton and clips are given, `posesPerClip` evenly spaced frames of each clip,
// skinned. A simplified mesh keeps original vertices with their own weights, so both
// surfaces are skinned alike in every pose.
//
// A ratio the locks do not allow (the shared vertices and borders stay, so do the triangles
// between them) gives the fewest triangles that can be reached, with a warning.

#include "core/clip.h"
#include "core/error.h"
#include "core/mesh/mesh_segments.h"
#include "core/mesh/progressive_mesh.h"
#include "core/skeleton.h"
#include "core/skinned_mesh.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace mlod {

struct MeshLodSettings {
  ProgressiveMeshSettings decimation;
  // Width of the sampling cells of the error (cm, > 0); 0 = 0.5% of the diagonal of the
  // mesh's bounding box (about 1 cm on a 1.8 m character).
  double samplingSpacingCm = 0.0;
  int posesPerClip = 8; // animated poses measured per clip (evenly spaced frames, the last included), >= 0

  // Rules: decimation.maxNormalDeviationDegrees in (0, 180]; maxAspectRatio 0 or >= 1;
  // samplingSpacingCm finite and >= 0; posesPerClip >= 0.
  Error validate() const;
};

struct MeshLodLevel {
  double ratio = 1.0;              // the ratio asked for (for a level by error: the one reached)
  std::size_t targetTriangles = 0; // round(ratio x original triangles), at least 1
  std::size_t collapses = 0;       // of the progressive mesh's global order
  SkinnedMesh mesh;                // the level: only the vertices it uses, parts kept
  std::vector<std::uint32_t> sourceVertices; // per vertex of `mesh`: the original vertex it is
  double bindErrorCm = 0.0;        // symmetric max distance to the original in the bind pose
  double animatedErrorCm = 0.0;    // the largest over the measured animated poses (0 without)
  double maxErrorCm = 0.0;         // max of the two
  // Every locked vertex (shared, border) the original uses is still used, at its position.
  bool sharedVerticesPreserved = true;
  std::string warning; // empty unless the target could not be reached

  std::size_t triangles() const { return mesh.triangleCount(); }
  std::size_t vertices() const { return mesh.vertexCount(); }
};

class MeshLod {
public:
  // Segments and decimates `mesh`; `skeleton` and `clips` (may be empty) give the animated
  // poses the errors are measured in. Errors: a mesh that does not validate (against the
  // skeleton's joint count where there is one), clips that do not match the skeleton, bad
  // settings.
  static Result<MeshLod> build(const SkinnedMesh& mesh, const Skeleton* skeleton = nullptr,
                               std::span<const Clip> clips = {}, const MeshLodSettings& settings = {});

  const SkinnedMesh& original() const { return m_original; }
  const MeshSegmentation& segmentation() const { return m_segmentation; }
  const ProgressiveMesh& progressive() const { return m_progressive; }
  const MeshLodSettings& settings() const { return m_settings; }
  double samplingSpacingCm() const { return m_spacing; }
  // Skinned positions of the original vertices in each measured pose: [0] the bind pose.
  const std::vector<std::vector<glm::vec3>>& posePositions() const { return m_poses; }
  // Which clip and frame each pose is (-1, -1 for the bind pose).
  const std::vector<std::pair<int, int>>& poseFrames() const { return m_poseFrames; }

  // The level after the first `collapses` collapses (<= progressive().collapseCount()), measured.
  MeshLodLevel levelAt(std::size_t collapses) const;
  // The fewest collapses that reach round(ratio x triangles), ratio in (0, 1]; a warning
  // when the locks stop it short.
  MeshLodLevel levelForRatio(double ratio) const;
  // The most collapses whose error stays within maxErrorCm (>= 0), by bisection over the
  // collapse order (the error grows with it, if not strictly).
  MeshLodLevel levelForError(double maxErrorCm) const;

  // Errors (cm) of the mesh after `collapses` collapses, or of explicit triangles (original
  // vertex indices, e.g. another simplifier's output on the same vertices).
  struct Errors {
    double bindCm = 0.0;
    double animatedCm = 0.0;
    double maxCm() const { return bindCm > animatedCm ? bindCm : animatedCm; }
  };
  Errors errorsAt(std::size_t collapses) const;
  Errors errorsOf(const MeshLevelIndices& level) const;

  // The compacted mesh of `level` (vertices in original order), and per vertex its source.
  SkinnedMesh compact(const MeshLevelIndices& level, std::vector<std::uint32_t>* out_sourceVertices = nullptr) const;

private:
  MeshLodLevel makeLevel(std::size_t collapses, double ratio, std::size_t target) const;
  // The largest of floorCm and the level's error in one pose.
  double poseError(std::size_t pose, const MeshLevelIndices& level, double floorCm) const;

  SkinnedMesh m_original;
  MeshLodSettings m_settings;
  MeshSegmentation m_segmentation;
  ProgressiveMesh m_progressive;
  double m_spacing = 1.0;
  std::vector<std::vector<glm::vec3>> m_poses;
  std::vector<std::pair<int, int>> m_poseFrames;
  std::vector<std::vector<std::uint32_t>> m_segmentIndices; // original triangles per segment
};

} // namespace mlod
