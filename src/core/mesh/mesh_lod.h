#pragma once
// Mesh LOD of a skinned character (docs/architecture.md section 1, Geometric LOD): one
// simplification of the whole mesh, welded by position, whose collapse costs see the bind
// pose and K poses of the clips the character plays (progressive_mesh.h), and levels taken
// from it by triangle ratio or by error, each measured against the original in cm
// (surface_distance.h).
//
// Where the paper simplifies per joint segment and keeps the vertices shared between joints
// fixed (Ahn & Wohn, section 5), which on a smoothly skinned mesh locks most of it, the joint
// segments live on as a per-joint *mesh importance* that scales the collapse cost of the
// vertices a joint influences (weighted by the skin).
//
// Poses: the bind pose, `simplifyPoses` frames spread evenly over all the clips (taken one
// after another) that the collapse costs see, and `measurePoses` *other* frames, spread the
// same way, that the errors are measured in; so a level's animated error says how it holds
// in motion it was not fitted to.
//
// Error of a level in one pose: the symmetric maximum distance (Hausdorff, sampled) between
// the skinned level and the skinned original, cm. A level keeps original vertices with their
// own weights, so both surfaces skin alike in every pose. Reported: in the bind pose, the
// largest and the mean over the measured poses.

#include "core/cancel.h"
#include "core/clip.h"
#include "core/error.h"
#include "core/mesh/progressive_mesh.h"
#include "core/mesh/surface_distance.h"
#include "core/skeleton.h"
#include "core/skinned_mesh.h"

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace mlod {

struct MeshLodSettings {
  ProgressiveMeshSettings simplification;
  // Width of the sampling cells of the error (cm, > 0); 0 = 0.5% of the diagonal of the
  // mesh's bounding box (about 1 cm on a 1.8 m character).
  double samplingSpacingCm = 0.0;
  int simplifyPoses = 12; // K: animated poses the collapse costs see, over all clips, >= 0
  int measurePoses = 8;   // animated poses (other frames) the errors are measured in, >= 0
  // Mesh importance per joint of the skeleton the mesh is bound to (> 0, finite; 1 = as
  // any other, 4 = removing its vertices costs four times as much); empty = 1 for all.
  std::vector<float> jointImportance;
  // Run-time only, never saved or compared (core/cancel.h; may be null): build() stops
  // between poses and every few hundred collapses once it is set, and returns kCancelled; the
  // MeshLod keeps it, and a level measured after it is set is not to be used (errorsOf()
  // skips the poses left). It must outlive the MeshLod.
  const std::atomic<bool>* cancel = nullptr;

  // Rules: the simplification weights finite and >= 0; samplingSpacingCm finite and >= 0;
  // pose counts >= 0; importances finite and > 0 (their count is checked against the skeleton
  // by MeshLod::build).
  Error validate() const;
};

struct MeshLodLevel {
  double ratio = 1.0;                        // the ratio asked for (for a level by error: the one reached)
  std::size_t targetTriangles = 0;           // round(ratio x original triangles), at least 1
  std::size_t collapses = 0;                 // of the progressive mesh's order
  SkinnedMesh mesh;                          // the level: only the vertices it uses, parts kept
  std::vector<std::uint32_t> sourceVertices; // per vertex of `mesh`: the original vertex it is
  double bindErrorCm = 0.0;                  // symmetric max distance to the original in the bind pose
  double animatedErrorCm = 0.0;              // the largest over the measured animated poses (0 without)
  double animatedMeanErrorCm = 0.0;          // the mean over the measured animated poses (0 without)
  double maxErrorCm = 0.0;                   // max of bind and animated
  // Every locked vertex (non-manifold guard) the original uses is still used, at its position.
  bool lockedVerticesPreserved = true;
  std::string warning; // empty unless the target could not be reached

  std::size_t triangles() const { return mesh.triangleCount(); }
  std::size_t vertices() const { return mesh.vertexCount(); }
};

class MeshLod {
public:
  // Simplifies `mesh`; `skeleton` and `clips` (may be empty) give the animated poses. Errors:
  // a mesh that does not validate (against the skeleton's joint count where there is one),
  // clips that do not match the skeleton, bad settings, importances not one per joint,
  // settings.cancel set (kCancelled).
  static Result<MeshLod> build(const SkinnedMesh& mesh, const Skeleton* skeleton = nullptr,
                               std::span<const Clip> clips = {}, const MeshLodSettings& settings = {});

  const SkinnedMesh& original() const { return m_original; }
  const ProgressiveMesh& progressive() const { return m_progressive; }
  const MeshLodSettings& settings() const { return m_settings; }
  // The flag that stops the measurements from now on (MeshLodSettings::cancel; may be null):
  // for a MeshLod kept longer than the flag it was built with.
  void setCancel(const std::atomic<bool>* cancel) { m_settings.cancel = cancel; }
  double samplingSpacingCm() const { return m_spacing; }
  // Skinned positions of the original vertices in the poses the collapse costs saw: [0] the
  // bind pose; and which clip and frame each is (-1, -1 for the bind pose).
  const std::vector<std::vector<glm::vec3>>& simplifyPoses() const { return m_simplifyPoses; }
  const std::vector<std::pair<int, int>>& simplifyFrames() const { return m_simplifyFrames; }
  // The same for the animated poses the errors are measured in (none of them a simplify frame).
  const std::vector<std::vector<glm::vec3>>& measurePoses() const { return m_measurePoses; }
  const std::vector<std::pair<int, int>>& measureFrames() const { return m_measureFrames; }

  // The level after the first `collapses` collapses (<= progressive().collapseCount()), measured.
  MeshLodLevel levelAt(std::size_t collapses) const;
  // The fewest collapses that reach round(ratio x triangles), ratio in (0, 1]; a warning
  // when the mesh cannot be simplified that far.
  MeshLodLevel levelForRatio(double ratio) const;
  // The most collapses whose error (maxCm) stays within maxErrorCm (>= 0), by bisection
  // over the collapse order (the error grows with it, if not strictly).
  MeshLodLevel levelForError(double maxErrorCm) const;
  // The level of the smallest of `ratios` (each in (0, 1], falling) whose measured error
  // (maxCm) stays within maxErrorCm, by bisection over them (the error grows as the ratio
  // falls); the original (no collapse) when none fits. Cheaper than levelForError: about
  // log2(ratios.size()) measurements.
  MeshLodLevel levelForErrorAmong(double maxErrorCm, std::span<const double> ratios) const;

  // Errors (cm) of the mesh after `collapses` collapses, or of explicit triangles (original
  // vertex indices, e.g. another simplifier's output on the same vertices).
  struct Errors {
    double bindCm = 0.0;
    double animatedMaxCm = 0.0;
    double animatedMeanCm = 0.0;
    double maxCm() const { return bindCm > animatedMaxCm ? bindCm : animatedMaxCm; }
  };
  Errors errorsAt(std::size_t collapses) const;
  Errors errorsOf(const MeshLevelIndices& level) const;
  // errorsOf(level).maxCm() > maxErrorCm (>= 0), decided without measuring every pose exactly.
  bool exceeds(const MeshLevelIndices& level, double maxErrorCm) const;

  // The compacted mesh of `level` (vertices in original order), and per vertex its source.
  SkinnedMesh compact(const MeshLevelIndices& level, std::vector<std::uint32_t>* out_sourceVertices = nullptr) const;

private:
  MeshLodLevel makeLevel(std::size_t collapses, double ratio, std::size_t target) const;

  SkinnedMesh m_original;
  MeshLodSettings m_settings;
  ProgressiveMesh m_progressive;
  double m_spacing = 1.0;
  std::vector<std::vector<glm::vec3>> m_simplifyPoses, m_measurePoses;
  std::vector<std::pair<int, int>> m_simplifyFrames, m_measureFrames;
  // The original surface's trees in the bind pose and each measured pose (shared: built once)
  std::shared_ptr<const std::vector<TriangleTree>> m_originalTrees;
};

// Per vertex of `mesh`: its mesh importance, sum_i w_i x jointImportance[joint_i] (1 for a
// mesh without weights or an empty `jointImportance`).
std::vector<float> vertexImportance(const SkinnedMesh& mesh, std::span<const float> jointImportance);

// `count` frames spread evenly over `frameCounts` (clips one after another) as (clip, frame),
// none of them in `exclude`; fewer when the clips have fewer free frames.
std::vector<std::pair<int, int>> spreadFrames(std::span<const int> frameCounts, int count,
                                              std::span<const std::pair<int, int>> exclude = {});

} // namespace mlod
