#include "editor/viewport/view_source.h"

#include "core/jpc/simplified_motion.h"
#include "core/mapping/motion_mapping.h"
#include "editor/document/document.h"

#include <QCoreApplication>

#include <algorithm>

namespace mlod {

namespace {
QString tr(const char* text) { return QCoreApplication::translate("ViewSource", text); }
} // namespace

std::vector<bool> ViewSource::frozenAt(int frame) const {
  std::vector<bool> out(static_cast<std::size_t>(skeleton.jointCount()), false);
  if (!clusters || !simplifiedReady)
    return out;
  for (std::size_t j = 0; j < out.size() && j < motionJoint.size(); ++j) {
    const int m = motionJoint[j];
    if (m >= 0 && m < clusters->jointCount() && frame >= 0 && frame < clusters->frameCount)
      out[j] = clusters->clusterAt(m, frame) >= 0;
  }
  return out;
}

std::vector<int> mappingsOfCurrentAsset(const Document& document) {
  std::vector<int> out;
  const auto& mappings = document.project().mappings;
  for (std::size_t i = 0; i < mappings.size(); ++i)
    if (mappings[i].motion == document.currentAsset() && mappings[i].character >= 0 &&
        mappings[i].character < document.assetCount() && document.asset(mappings[i].character))
      out.push_back(static_cast<int>(i));
  return out;
}

ViewSource makeViewSource(const Document& document, int mapping) {
  ViewSource out;
  out.motionAsset = document.currentAsset();
  if (out.motionAsset < 0 || out.motionAsset >= document.assetCount() || !document.asset(out.motionAsset)) {
    out.error = tr("Import a character or a motion (File → Import…) to see it here.");
    return out;
  }
  out.motion = document.asset(out.motionAsset);
  const Asset& motion = *out.motion;
  const int clipIndex = document.currentClip();
  const Clip* clip = clipIndex >= 0 && clipIndex < static_cast<int>(motion.clips.size())
                         ? &motion.clips[static_cast<std::size_t>(clipIndex)]
                         : nullptr;

  // The level's clusters, once the analysis of this very clip has landed.
  out.level = document.currentLevel();
  const std::shared_ptr<const JpcAnalysis> analysis = document.analysis();
  if (clip && analysis && analysis->asset == out.motion && analysis->clip == clipIndex && analysis->levelCount() > 0) {
    out.level = std::clamp(out.level, 0, analysis->levelCount() - 1);
    out.clusters = analysis->levels[static_cast<std::size_t>(out.level)].clusters;
    out.simplifiedReady = true;
  }

  const auto& mappings = document.project().mappings;
  const bool mapped = mapping >= 0 && mapping < static_cast<int>(mappings.size()) &&
                      mappings[static_cast<std::size_t>(mapping)].motion == out.motionAsset;
  if (mapped && clip) {
    const ProjectMapping& entry = mappings[static_cast<std::size_t>(mapping)];
    out.character = entry.character >= 0 && entry.character < document.assetCount() ? document.asset(entry.character)
                                                                                      : nullptr;
    if (!out.character || out.character->skeleton.empty()) {
      out.error = tr("The character of this motion mapping is missing or has no skeleton.");
      return out;
    }
    out.mapping = mapping;
    out.characterAsset = entry.character;
    Result<RestPoseDifferences> differences =
        restPoseDifferences(entry.mapping, motion.skeleton, out.character->skeleton);
    if (!differences) {
      out.error = tr("Motion mapping: %1").arg(QString::fromStdString(differences.message()));
      return out;
    }
    Result<Clip> original = retargetClip(*differences, motion.skeleton, *clip, out.character->skeleton);
    Result<Clip> simplified =
        out.clusters ? retargetClip(*differences, motion.skeleton, simplifiedClip(*clip, *out.clusters),
                                    out.character->skeleton)
                     : original;
    if (!original || !simplified) {
      out.error = tr("Motion mapping: %1").arg(QString::fromStdString((!original ? original : simplified).message()));
      return out;
    }
    out.skeleton = out.character->skeleton;
    out.original = std::move(original).value();
    out.simplified = std::move(simplified).value();
    out.motionJoint = differences->source;
    out.description = tr("%1 on %2 (mapping)")
                          .arg(QString::fromStdString(clip->name), QString::fromStdString(entry.mapping.characterName));
  } else {
    out.character = out.motion;
    out.characterAsset = out.motionAsset;
    if (motion.skeleton.empty()) {
      // a mesh without a skeleton: one joint at the origin holds it
      Joint root;
      root.name = "root";
      out.skeleton.joints.push_back(root);
      out.original = Clip::restPose(out.skeleton, 1, 30.0);
      out.original.name = "rest";
      out.description = tr("static mesh (no skeleton)");
    } else {
      out.skeleton = motion.skeleton;
      out.original = clip ? *clip : Clip::restPose(motion.skeleton, 1, 30.0);
      if (!clip)
        out.original.name = "rest pose";
      out.description = clip ? QString::fromStdString(clip->name) : tr("rest pose (no clip)");
    }
    out.simplified = out.clusters && clip ? simplifiedClip(out.original, *out.clusters) : out.original;
    out.motionJoint.resize(static_cast<std::size_t>(out.skeleton.jointCount()));
    for (std::size_t j = 0; j < out.motionJoint.size(); ++j)
      out.motionJoint[j] = static_cast<int>(j);
  }
  for (const SkinnedMesh& mesh : out.character->meshes) {
    const bool fits = mesh.skinned() ? !mesh.validate(out.skeleton.jointCount()) : !mesh.validate(0);
    if (fits) // a static mesh is drawn rigidly with the root
      out.meshes.push_back(&mesh);
  }
  return out;
}

} // namespace mlod
