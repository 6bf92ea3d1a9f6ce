// PoseEvaluatorJob on real motion (CMU 01_01, 38 joints, 2,752 frames at 120 fps) at the
// thresholds of the paper's Table 1: exactly forward kinematics of M'(t) without blending,
// with model matrices and palette-only; the original at threshold 0; bounded and continuous
// with blending; deterministic over threads; and validate() rejecting each invalid input
// in turn.

#include "runtime/pose_evaluator.h"
#include "unit/real_files.h"
#include "unit/runtime/runtime_fixtures.h"

#include <algorithm>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <random>
#include <vector>

namespace mlod {
namespace {

using test::elementsNear;
using test::levelsOf;
using test::plainModels;
using test::runtimeAsset;

constexpr const char* kCmu = "BVH/01_01.bvh";
constexpr float kTolerance = 1e-5f; // x max(1, |x|), cm

struct Rig {
  std::vector<std::int16_t> parents;
  std::vector<glm::mat4> inverseBinds;
  explicit Rig(const Skeleton& skeleton)
      : parents(skeleton.parentIndices()), inverseBinds(paletteInverseBinds(skeleton)) {}
  int joints() const { return static_cast<int>(parents.size()); }
};

// The runtime clip, built for `blendFrames` of unfreeze blending.
LodClip lodClip(const Clip& clip, const ClusterSet* clusters, bool looping = false, int blendFrames = 0) {
  Result<LodClip> built = buildLodClip(clip, clusters, looping, {}, blendFrames);
  if (!built)
    throw std::runtime_error(built.message());
  return std::move(built).value();
}

// One character played along `times` (seconds), one run per step, the clip of each step
// from `clips`; the models and palettes of every step, step-major.
struct Playback {
  std::vector<glm::mat4> models;
  std::vector<glm::mat4> palette;
  std::int64_t sampled = 0;
};

Playback play(const Rig& rig, const std::vector<const LodClip*>& clips, const std::vector<double>& times,
              int blendFrames, bool models = true) {
  const std::size_t joints = static_cast<std::size_t>(rig.joints());
  Playback out;
  if (models)
    out.models.resize(times.size() * joints);
  out.palette.resize(times.size() * joints);
  PoseEvaluatorContext context(1, rig.joints());
  for (std::size_t step = 0; step < times.size(); ++step) {
    PoseEvaluatorJob job;
    job.parents = rig.parents;
    job.inverseBinds = rig.inverseBinds;
    job.clips = std::span<const LodClip* const>(&clips[step], 1);
    job.times = std::span<const double>(&times[step], 1);
    job.blendFrames = blendFrames;
    job.context = &context;
    if (models)
      job.out_models = std::span<glm::mat4>(&out.models[step * joints], joints);
    job.out_palette = std::span<glm::mat4>(&out.palette[step * joints], joints);
    if (!job.run())
      throw std::runtime_error("the job did not validate");
    out.sampled += context.jointsSampled();
  }
  return out;
}

Playback play(const Rig& rig, const LodClip& clip, const std::vector<double>& times, int blendFrames,
              bool models = true) {
  return play(rig, std::vector<const LodClip*>(times.size(), &clip), times, blendFrames, models);
}

// palette = model x inverse bind within tolerance x (the joint's position + the magnitude of
// the product's terms): the rounding that the product of two float matrices may carry.
bool paletteNear(const glm::mat4& palette, const glm::mat4& model, const glm::mat4& inverseBind) {
  const glm::mat4 product = model * inverseBind;
  const float position = std::max(1.0f, glm::length(glm::vec3(model[3])));
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) {
      float magnitude = position;
      for (int k = 0; k < 4; ++k)
        magnitude += std::abs(model[k][r] * inverseBind[c][k]);
      if (!(std::abs(palette[c][r] - product[c][r]) <= kTolerance * magnitude))
        return false;
    }
  return true;
}

// Palette-only runs (out_models empty): every palette matrix is
// plain FK of `reference` times the inverse bind.
void expectPlainPalette(const Skeleton& skeleton, const Clip& reference, const Rig& rig, const Playback& played,
                        const std::vector<double>& times, const std::string& what) {
  const std::size_t joints = static_cast<std::size_t>(rig.joints());
  std::vector<glm::mat4> expected;
  for (std::size_t step = 0; step < times.size(); ++step) {
    plainModels(skeleton, reference, times[step] * reference.fps, expected);
    for (std::size_t j = 0; j < joints; ++j)
      if (!paletteNear(played.palette[step * joints + j], expected[j], rig.inverseBinds[j])) {
        ADD_FAILURE() << what << ": palette of joint " << j << " at frame position " << times[step] * reference.fps
                      << " is not plain FK of M'(t) x inverse bind";
        return;
      }
  }
}

// Frame positions first, first + step, ... up to last, as times of `clip`.
std::vector<double> timesAlong(const Clip& clip, double first, double last, double step = 1.0) {
  std::vector<double> times;
  for (double f = first; f <= last + 1e-9; f += step)
    times.push_back(f / clip.fps);
  return times;
}

// Every model matrix within tolerance of plain FK of `reference` at the same frame
// position; the palette within the rounding of model x inverse bind. Returns the worst
// element ratio; fails the test on the first mismatch.
float expectPlainKinematics(const Skeleton& skeleton, const Clip& reference, const Rig& rig, const Playback& played,
                            const std::vector<double>& times, const std::string& what) {
  const std::size_t joints = static_cast<std::size_t>(rig.joints());
  std::vector<glm::mat4> expected;
  float worst = 0.0f, worstLiteral = 0.0f;
  for (std::size_t step = 0; step < times.size(); ++step) {
    plainModels(skeleton, reference, times[step] * reference.fps, expected);
    for (std::size_t j = 0; j < joints; ++j) {
      float ratio = 0.0f, literal = 0.0f;
      const glm::mat4& model = played.models[step * joints + j];
      const bool near = elementsNear(model, expected[j], kTolerance, &ratio, &literal);
      worstLiteral = std::max(worstLiteral, literal);
      if (!near) {
        ADD_FAILURE() << what << ": joint " << j << " at frame position " << times[step] * reference.fps
                      << " differs from plain FK of M'(t) by " << ratio << " x max(1, |x|)";
        return ratio;
      }
      worst = std::max(worst, ratio);
      if (!paletteNear(played.palette[step * joints + j], model, rig.inverseBinds[j])) {
        ADD_FAILURE() << what << ": palette of joint " << j << " at frame position " << times[step] * reference.fps
                      << " is not model x inverse bind";
        return ratio;
      }
    }
  }
  ::testing::Test::RecordProperty(what + " worst ratio to the coordinate alone", std::to_string(worstLiteral));
  return worst;
}

// Guards the central equivalence (docs/architecture.md section 5): without blending, at every frame
// and at every threshold, the evaluator is forward kinematics of M'(t); and so is the
// palette of palette-only runs.
TEST(PoseEvaluator, EveryFrameEqualsKinematicsOfSimplifiedMotion) {
  const Asset& asset = runtimeAsset(kCmu);
  const Clip& clip = asset.clips.front();
  const Rig rig(asset.skeleton);
  const std::vector<double> times = timesAlong(clip, 0.0, clip.frameCount - 1);
  for (const JpcLevelResult& level : levelsOf(kCmu)) {
    const Clip simplified = simplifiedClip(clip, level.clusters);
    const LodClip lod = lodClip(clip, &level.clusters);
    const Playback played = play(rig, lod, times, 0);
    const std::string what = "E=" + std::to_string(level.threshold);
    const float worst = expectPlainKinematics(asset.skeleton, simplified, rig, played, times, what);
    RecordProperty(what, std::to_string(worst));
    expectPlainPalette(asset.skeleton, simplified, rig, play(rig, lod, times, 0, false), times,
                       what + ", palette only");
  }
}

// Guards interpolation between frames, across cluster starts and ends included: at half
// frames the evaluator is FK of M' nlerped between the two frames.
TEST(PoseEvaluator, HalfFramesEqualInterpolatedSimplifiedMotion) {
  const Asset& asset = runtimeAsset(kCmu);
  const Clip& clip = asset.clips.front();
  const Rig rig(asset.skeleton);
  const std::vector<double> times = timesAlong(clip, 0.5, clip.frameCount - 1.5);
  for (const JpcLevelResult& level : levelsOf(kCmu)) {
    if (level.threshold != 50.0 && level.threshold != 300.0)
      continue;
    const Clip simplified = simplifiedClip(clip, level.clusters);
    const LodClip lod = lodClip(clip, &level.clusters);
    const Playback played = play(rig, lod, times, 0);
    expectPlainKinematics(asset.skeleton, simplified, rig, played, times, "E=" + std::to_string(level.threshold));
  }
}

// Guards "the original at threshold 0" and full detail: both equal FK of the clip itself.
TEST(PoseEvaluator, ThresholdZeroAndFullDetailEqualTheOriginal) {
  const Asset& asset = runtimeAsset(kCmu);
  const Clip& clip = asset.clips.front();
  const Rig rig(asset.skeleton);
  const std::vector<double> times = timesAlong(clip, 0.0, clip.frameCount - 1);
  const JpcLevelResult& zero = levelsOf(kCmu).front();
  ASSERT_EQ(zero.threshold, 0.0);
  ASSERT_GT(zero.clusterCount, 0) << "CMU 01_01 has joints that never move: T = 0 clusters them";
  const LodClip atZero = lodClip(clip, &zero.clusters);
  const LodClip full = lodClip(clip, nullptr);
  EXPECT_EQ(full.clusterCount(), 0);
  expectPlainKinematics(asset.skeleton, clip, rig, play(rig, atZero, times, 0), times, "E=0");
  expectPlainKinematics(asset.skeleton, clip, rig, play(rig, full, times, 0), times, "full detail");
}

// Guards what a character keeps (held keys, region cursors): one character
// stepping through the clip gives bit for bit what a whole crowd in one run (one
// character per frame, each evaluated once) gives.
TEST(PoseEvaluator, SteppingEqualsFreshCharacters) {
  const Asset& asset = runtimeAsset(kCmu);
  const Clip& clip = asset.clips.front();
  const Rig rig(asset.skeleton);
  const JpcLevelResult& level = levelsOf(kCmu)[2];
  const LodClip lod = lodClip(clip, &level.clusters);
  const std::vector<double> times = timesAlong(clip, 0.0, clip.frameCount - 1);
  const std::size_t joints = static_cast<std::size_t>(rig.joints());
  for (bool withModels : {true, false}) {
    const Playback sequential = play(rig, lod, times, 0, withModels);
    std::vector<const LodClip*> clips(times.size(), &lod);
    std::vector<glm::mat4> models(times.size() * joints), palette(times.size() * joints);
    PoseEvaluatorContext context(static_cast<int>(times.size()), rig.joints());
    PoseEvaluatorJob job;
    job.parents = rig.parents;
    job.inverseBinds = rig.inverseBinds;
    job.clips = clips;
    job.times = times;
    job.context = &context;
    if (withModels)
      job.out_models = models;
    job.out_palette = palette;
    ASSERT_TRUE(job.run());
    EXPECT_EQ(context.jointsSampled(), sequential.sampled);
    if (withModels) {
      EXPECT_EQ(std::memcmp(models.data(), sequential.models.data(), models.size() * sizeof(glm::mat4)), 0);
    }
    EXPECT_EQ(std::memcmp(palette.data(), sequential.palette.data(), palette.size() * sizeof(glm::mat4)), 0);
  }
}

// Guards determinism over threads, with model matrices and palette-only.
TEST(PoseEvaluator, ThreadsAndPaletteOnlyChangeNothing) {
  const Asset& asset = runtimeAsset(kCmu);
  const Clip& clip = asset.clips.front();
  const Rig rig(asset.skeleton);
  const LodClip lod = lodClip(clip, &levelsOf(kCmu)[2].clusters, true, 4);
  const LodClip full = lodClip(clip, nullptr, true);
  const int characters = 301;
  const std::size_t n = static_cast<std::size_t>(characters) * static_cast<std::size_t>(rig.joints());
  std::vector<const LodClip*> clips(static_cast<std::size_t>(characters));
  std::vector<double> starts(static_cast<std::size_t>(characters));
  for (int c = 0; c < characters; ++c) {
    clips[static_cast<std::size_t>(c)] = c % 3 == 0 ? &full : &lod;
    starts[static_cast<std::size_t>(c)] = std::fmod(c * 0.618034 * lod.duration(), lod.duration());
  }
  struct Run {
    std::vector<glm::mat4> models, palette;
  };
  const auto crowd = [&](int threads, bool withModels) {
    WorkerPool pool(threads);
    PoseEvaluatorContext context(characters, rig.joints(), threads);
    Run run;
    if (withModels)
      run.models = std::vector<glm::mat4>(n, glm::mat4(0.0f));
    run.palette = std::vector<glm::mat4>(n, glm::mat4(0.0f));
    std::vector<double> times = starts;
    for (int frame = 0; frame < 40; ++frame) {
      for (int c = 0; c < characters; ++c)
        times[static_cast<std::size_t>(c)] = starts[static_cast<std::size_t>(c)] + frame / 60.0;
      PoseEvaluatorJob job;
      job.parents = rig.parents;
      job.inverseBinds = rig.inverseBinds;
      job.clips = clips;
      job.times = times;
      job.blendFrames = 4;
      job.pool = &pool;
      job.context = &context;
      job.out_models = run.models;
      job.out_palette = run.palette;
      if (!job.run())
        ADD_FAILURE() << "the job did not validate";
    }
    return run;
  };
  const Run one = crowd(1, true);
  const Run two = crowd(2, true);
  EXPECT_EQ(std::memcmp(one.models.data(), two.models.data(), n * sizeof(glm::mat4)), 0);
  EXPECT_EQ(std::memcmp(one.palette.data(), two.palette.data(), n * sizeof(glm::mat4)), 0);
  // palette only: the same on any thread count, and within rounding
  // of model x inverse bind
  const Run single = crowd(1, false);
  const Run three = crowd(3, false);
  EXPECT_EQ(std::memcmp(single.palette.data(), three.palette.data(), n * sizeof(glm::mat4)), 0);
  for (std::size_t i = 0; i < n; ++i)
    ASSERT_TRUE(
        paletteNear(three.palette[i], one.models[i], rig.inverseBinds[i % static_cast<std::size_t>(rig.joints())]))
        << "matrix " << i;
}

// Guards what the LOD is for: at a high threshold fewer joints are sampled than at full
// detail, where every animated joint is, every frame.
TEST(PoseEvaluator, LodSamplesFewerJoints) {
  const Asset& asset = runtimeAsset(kCmu);
  const Clip& clip = asset.clips.front();
  const Rig rig(asset.skeleton);
  const std::vector<double> times = timesAlong(clip, 0.0, clip.frameCount - 1);
  const LodClip full = lodClip(clip, nullptr);
  int animated = 0;
  for (int j = 0; j < full.jointCount(); ++j)
    animated += (full.flags(j) & (LodClip::kRotationAnimated | LodClip::kTranslationAnimated | LodClip::kScaleAnimated))
                    ? 1
                    : 0;
  const Playback fullPlay = play(rig, full, times, 0);
  EXPECT_EQ(fullPlay.sampled, static_cast<std::int64_t>(animated) * static_cast<std::int64_t>(times.size()));
  const LodClip lod = lodClip(clip, &levelsOf(kCmu).back().clusters);
  const Playback lodPlay = play(rig, lod, times, 0);
  EXPECT_LT(lodPlay.sampled * 2, fullPlay.sampled) << "at E = 300 most joint-frames are frozen";
}

// Per joint and frame position: does joint j or an ancestor lie in an unfreeze window of
// `blendFrames` frames after one of its clusters?
std::vector<std::uint8_t> blendWindows(const Skeleton& skeleton, const ClusterSet& clusters,
                                       const std::vector<double>& frames, int blendFrames) {
  const std::size_t joints = static_cast<std::size_t>(skeleton.jointCount());
  std::vector<std::uint8_t> out(frames.size() * joints, 0);
  for (std::size_t step = 0; step < frames.size(); ++step)
    for (std::size_t j = 0; j < joints; ++j) {
      bool inside = false;
      for (const Cluster& cluster : clusters.joints[j])
        inside = inside || (cluster.last < clusters.frameCount - 1 && frames[step] >= cluster.last &&
                            frames[step] < cluster.last + blendFrames);
      const int parent = skeleton.joints[j].parent;
      out[step * joints + j] = inside || (parent >= 0 && out[step * joints + static_cast<std::size_t>(parent)]);
    }
  return out;
}

float distance(const glm::mat4& a, const glm::mat4& b) {
  return glm::length(glm::vec3(a[3]) - glm::vec3(b[3]));
}

// Guards unfreeze blending (docs/architecture.md section 5): equal to M'(t) outside blend windows;
// inside them every joint within the level's joint-position fidelity of M'(t); and no
// joint jumping between consecutive frames by more than the original motion does plus
// that figure. At the bench's step (1/60 s on a 120 fps clip) and at every frame.
TEST(PoseEvaluator, BlendingStaysWithinFidelityAndOutsideWindowsEqualsSimplified) {
  const Asset& asset = runtimeAsset(kCmu);
  const Clip& clip = asset.clips.front();
  const Rig rig(asset.skeleton);
  const std::size_t joints = static_cast<std::size_t>(rig.joints());
  const std::vector<glm::vec3> original = jointPositions(asset.skeleton, clip);
  for (const JpcLevelResult& level : levelsOf(kCmu)) {
    if (level.threshold == 0.0)
      continue;
    const Clip simplified = simplifiedClip(clip, level.clusters);
    const float fidelity = static_cast<float>(level.maxJointPositionErrorCm);
    for (int blendFrames : {4, 10}) {
      const LodClip lod = lodClip(clip, &level.clusters, false, blendFrames);
      for (double step : {1.0, 2.0}) {
        const std::vector<double> times = timesAlong(clip, 0.0, clip.frameCount - 1, step);
        std::vector<double> frames(times.size());
        for (std::size_t s = 0; s < times.size(); ++s)
          frames[s] = times[s] * clip.fps;
        const Playback played = play(rig, lod, times, blendFrames);
        const std::vector<std::uint8_t> windows = blendWindows(asset.skeleton, level.clusters, frames, blendFrames);
        std::vector<glm::mat4> expected;
        std::size_t inside = 0;
        float worstInside = 0.0f;
        const std::string what = "E=" + std::to_string(level.threshold) + " N=" + std::to_string(blendFrames);
        for (std::size_t s = 0; s < times.size(); ++s) {
          plainModels(asset.skeleton, simplified, frames[s], expected);
          for (std::size_t j = 0; j < joints; ++j) {
            const glm::mat4& model = played.models[s * joints + j];
            if (windows[s * joints + j]) {
              ++inside;
              const float error = distance(model, expected[j]);
              worstInside = std::max(worstInside, error);
              ASSERT_LE(error, fidelity) << what << ": joint " << j << " at frame " << frames[s];
            } else {
              ASSERT_TRUE(elementsNear(model, expected[j], kTolerance))
                  << what << ": joint " << j << " at frame " << frames[s] << " is outside every window";
            }
            if (s > 0) {
              const long f1 = std::lround(frames[s]), f0 = std::lround(frames[s - 1]);
              const float moved = glm::length(original[static_cast<std::size_t>(f1) * joints + j] -
                                              original[static_cast<std::size_t>(f0) * joints + j]);
              const float jump = distance(model, played.models[(s - 1) * joints + j]);
              ASSERT_LE(jump, moved + fidelity + 1e-3f) << what << ": joint " << j << " jumps at frame " << frames[s];
            }
          }
        }
        EXPECT_GT(inside, 0u) << what << ": some joint-frames lie in windows";
        RecordProperty(what + " step " + std::to_string(step) + ": worst cm inside windows (fidelity " +
                           std::to_string(fidelity) + ")",
                       std::to_string(worstInside));
      }
    }
  }
}

// Guards level changes: switching a character between levels blends (no joint jumps more
// than the motion plus both levels' fidelity), stays within both fidelities of the new
// level, and after the blend equals the new level's M'(t) (outside its unfreeze windows).
TEST(PoseEvaluator, LevelChangesBlend) {
  const Asset& asset = runtimeAsset(kCmu);
  const Clip& clip = asset.clips.front();
  const Rig rig(asset.skeleton);
  const std::size_t joints = static_cast<std::size_t>(rig.joints());
  const std::vector<JpcLevelResult>& levels = levelsOf(kCmu);
  const JpcLevelResult& fine = levels[1];
  const JpcLevelResult& coarse = levels[3];
  const int blendFrames = 6;
  const LodClip fineClip = lodClip(clip, &fine.clusters, false, blendFrames);
  const LodClip coarseClip = lodClip(clip, &coarse.clusters, false, blendFrames);
  const Clip fineSimplified = simplifiedClip(clip, fine.clusters);
  const Clip coarseSimplified = simplifiedClip(clip, coarse.clusters);
  const std::vector<glm::vec3> original = jointPositions(asset.skeleton, clip);
  const float bound = static_cast<float>(fine.maxJointPositionErrorCm + coarse.maxJointPositionErrorCm);
  const std::vector<double> times = timesAlong(clip, 0.0, clip.frameCount - 1);
  // a level switch every 97 frames
  std::vector<const LodClip*> clips(times.size());
  for (std::size_t s = 0; s < times.size(); ++s)
    clips[s] = (s / 97) % 2 == 0 ? &coarseClip : &fineClip;
  const Playback played = play(rig, clips, times, blendFrames);
  std::vector<double> frames(times.size());
  for (std::size_t s = 0; s < times.size(); ++s)
    frames[s] = static_cast<double>(s);
  const std::vector<std::uint8_t> fineWindows = blendWindows(asset.skeleton, fine.clusters, frames, blendFrames);
  const std::vector<std::uint8_t> coarseWindows = blendWindows(asset.skeleton, coarse.clusters, frames, blendFrames);
  std::vector<glm::mat4> expected;
  int switches = 0;
  for (std::size_t s = 1; s < times.size(); ++s) {
    const bool coarseNow = clips[s] == &coarseClip;
    plainModels(asset.skeleton, coarseNow ? coarseSimplified : fineSimplified, frames[s], expected);
    const std::size_t sinceSwitch = s % 97;
    switches += sinceSwitch == 0 ? 1 : 0;
    for (std::size_t j = 0; j < joints; ++j) {
      const glm::mat4& model = played.models[s * joints + j];
      const float moved = glm::length(original[s * joints + j] - original[(s - 1) * joints + j]);
      ASSERT_LE(distance(model, played.models[(s - 1) * joints + j]), moved + bound + 1e-3f)
          << "joint " << j << " jumps at frame " << s;
      ASSERT_LE(distance(model, expected[j]), bound) << "joint " << j << " at frame " << s;
      const bool window = (coarseNow ? coarseWindows : fineWindows)[s * joints + j];
      if (s >= 97 && sinceSwitch >= static_cast<std::size_t>(blendFrames) && !window) {
        ASSERT_TRUE(elementsNear(model, expected[j], kTolerance))
            << "joint " << j << " at frame " << s << ", " << sinceSwitch << " frames after a switch";
      }
    }
  }
  EXPECT_GT(switches, 20);
}

Clip withoutFirstFrame(const Clip& clip) {
  Clip out = clip;
  out.frameCount = clip.frameCount - 1;
  out.rotations.clear();
  out.translations.clear();
  out.scales.clear();
  for (int j = 0; j < clip.jointCount; ++j)
    for (int t = 1; t < clip.frameCount; ++t) {
      out.rotations.push_back(clip.rotation(j, t));
      out.translations.push_back(clip.translation(j, t));
      out.scales.push_back(clip.scale(j, t));
    }
  return out;
}

// Guards the loop wrap: a looping clip blends from its last pose to its first over N
// frames (no pop: the first frame after the wrap shows the last pose), then plays the clip.
TEST(PoseEvaluator, LoopingClipsBlendAtTheWrap) {
  const Asset& asset = runtimeAsset(kCmu);
  // CMU 01_01's frame 0 is a calibration pose (hands 70 cm from frame 1's): loop the walk
  // from frame 1 on
  const Clip clip = withoutFirstFrame(asset.clips.front());
  const Rig rig(asset.skeleton);
  const std::size_t joints = static_cast<std::size_t>(rig.joints());
  const LodClip looping = lodClip(clip, nullptr, true);
  const double last = clip.frameCount - 1;
  const int blendFrames = 8;
  const std::vector<double> times = timesAlong(clip, last - 4, last + 2 * blendFrames);
  // positions relative to the root: its translation wraps unblended (root motion is the caller's)
  const auto relative = [&](const Playback& played, std::size_t s, std::size_t j) {
    return glm::vec3(played.models[s * joints + j][3]) - glm::vec3(played.models[s * joints][3]);
  };
  const Playback blended = play(rig, looping, times, blendFrames);
  const Playback popped = play(rig, looping, times, 0);
  float blendedJump = 0.0f, poppedJump = 0.0f;
  std::vector<glm::mat4> expected;
  for (std::size_t s = 1; s < times.size(); ++s) {
    const double frame = times[s] * clip.fps;
    for (std::size_t j = 0; j < joints; ++j) {
      blendedJump = std::max(blendedJump, glm::length(relative(blended, s, j) - relative(blended, s - 1, j)));
      poppedJump = std::max(poppedJump, glm::length(relative(popped, s, j) - relative(popped, s - 1, j)));
    }
    if (std::abs(frame - last) < 1e-6) {
      // at the wrap the pose is still the last frame's
      plainModels(asset.skeleton, clip, last, expected);
      for (std::size_t j = 0; j < joints; ++j)
        EXPECT_LT(glm::length(relative(blended, s, j) - (glm::vec3(expected[j][3]) - glm::vec3(expected[0][3]))), 1e-3f)
            << "joint " << j;
    }
    if (frame - last >= blendFrames) {
      plainModels(asset.skeleton, clip, frame - last, expected);
      for (std::size_t j = 0; j < joints; ++j)
        ASSERT_TRUE(elementsNear(blended.models[s * joints + j], expected[j], kTolerance))
            << "joint " << j << " after the wrap's blend, frame " << frame - last;
    }
  }
  EXPECT_GT(poppedJump, 5.0f) << "01_01 does not loop: its wrap pops";
  EXPECT_LT(blendedJump, 0.5f * poppedJump);
}

// A straightforward reference of one character (docs/architecture.md section 5): per joint
// the rotation LodClip::rotationAt() gives (M' with its unfreeze blends), the wrap offset
// inside a looping clip's wrap window, the level-change offset after a clip change, as
// normalised quaternions; local = T R S; model = parent's model x local.
struct ReferenceCharacter {
  const LodClip* clip = nullptr;
  bool levelBlend = false;
  double levelStart = 0.0, levelSeconds = 0.0;
  std::vector<glm::quat> levelOffset;

  static glm::quat positiveW(const glm::quat& q) { return q.w < 0.0f ? -q : q; }
  static glm::quat shown(const LodClip& clip, int j, double t, int blendFrames) {
    std::int64_t loop = 0;
    const double f = clip.framePosition(t, &loop);
    glm::quat q = clip.rotationAt(j, f);
    std::int32_t i0 = 0;
    float fraction = 0.0f;
    clip.split(f, i0, fraction);
    if (blendFrames > 0 && clip.looping() && loop >= 1 && i0 < blendFrames) {
      const glm::quat wrap =
          positiveW(clip.rotationAt(j, clip.frameCount() - 1) * glm::inverse(clip.rotationAt(j, 0.0)));
      q = scaleOffset(wrap, static_cast<float>(1.0 - std::min(f / blendFrames, 1.0))) * q;
    }
    return q;
  }
  double levelWeight(double t) {
    if (!levelBlend)
      return -1.0;
    const double w = (t - levelStart) / levelSeconds;
    return w >= 0.0 && w < 1.0 ? 1.0 - w : -1.0;
  }
  void play(const LodClip& next, double t, int blendFrames) {
    if (clip && clip != &next && blendFrames > 0) {
      const double previous = levelWeight(t);
      levelOffset.resize(static_cast<std::size_t>(next.jointCount()));
      for (int j = 0; j < next.jointCount(); ++j) {
        glm::quat before = shown(*clip, j, t, blendFrames);
        if (previous >= 0.0)
          before = scaleOffset(levelOffset[static_cast<std::size_t>(j)], static_cast<float>(previous)) * before;
        levelOffset[static_cast<std::size_t>(j)] = positiveW(before * glm::inverse(shown(next, j, t, blendFrames)));
      }
      levelBlend = true;
      levelStart = t;
      levelSeconds = blendFrames / next.fps();
    } else if (clip != &next) {
      levelBlend = false;
    }
    clip = &next;
  }
  void models(const Rig& rig, double t, int blendFrames, std::vector<glm::mat4>& out) {
    const double weight = levelWeight(t);
    if (weight < 0.0)
      levelBlend = false;
    const double f = clip->framePosition(t);
    out.resize(static_cast<std::size_t>(rig.joints()));
    for (int j = 0; j < rig.joints(); ++j) {
      glm::quat q = shown(*clip, j, t, blendFrames);
      if (weight >= 0.0)
        q = scaleOffset(levelOffset[static_cast<std::size_t>(j)], static_cast<float>(weight)) * q;
      const glm::mat4 local = glm::translate(glm::mat4(1.0f), clip->translationAt(j, f)) *
                              glm::mat4_cast(glm::normalize(q)) * glm::scale(glm::mat4(1.0f), clip->scaleAt(j, f));
      const int p = rig.parents[static_cast<std::size_t>(j)];
      out[static_cast<std::size_t>(j)] = p >= 0 ? out[static_cast<std::size_t>(p)] * local : local;
    }
  }
};

// Guards the whole evaluator against the reference above over thousands of random
// character-frames: a crowd in one job per step (two threads), each character stepping
// forward, now and then jumping back or several periods ahead (loop wraps) and switching
// between full detail and two levels (level changes, also during a running blend), with
// blending off and on.
// On every fixture clip and animated character (their first clip): CMU clips where only
// the root translates, characters whose other joints translate too and whose skeletons and
// hierarchies differ.
class RandomFrames : public ::testing::TestWithParam<std::string> {};

TEST_P(RandomFrames, EqualTheReference) {
  const std::string file = GetParam();
  const Asset& asset = runtimeAsset(file);
  const Clip& clip = asset.clips.front();
  const Rig rig(asset.skeleton);
  const std::size_t joints = static_cast<std::size_t>(rig.joints());
  const std::vector<JpcLevelResult>& levels = levelsOf(file);
  LodClip full = lodClip(clip, nullptr, true);
  LodClip fine = lodClip(clip, &levels[2].clusters, true);
  LodClip coarse = lodClip(clip, &levels.back().clusters, true);
  const LodClip* choices[3] = {&full, &fine, &coarse};
  // each level's joint-position fidelity (cm): the bound inside unfreeze windows
  const float fidelity[3] = {0.0f, static_cast<float>(levels[2].maxJointPositionErrorCm),
                             static_cast<float>(levels.back().maxJointPositionErrorCm)};
  // does a cluster of the coarse level end before the clip does (an unfreeze window)
  bool hasWindows = false;
  for (int j = 0; j < coarse.jointCount(); ++j)
    for (const LodClip::Cluster& cluster : coarse.clusters(j))
      hasWindows = hasWindows || cluster.last < coarse.frameCount() - 1;
  constexpr int kCharacters = 40, kSteps = 60;
  WorkerPool pool(2);
  for (const int blendFrames : {0, 5}) {
    // built for this N (they store their unfreeze windows), at the same addresses
    full = lodClip(clip, nullptr, true, blendFrames);
    fine = lodClip(clip, &levels[2].clusters, true, blendFrames);
    coarse = lodClip(clip, &levels.back().clusters, true, blendFrames);
    int inside = 0, outside = 0;
    std::mt19937 random(13u + static_cast<unsigned>(blendFrames));
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    PoseEvaluatorContext context(kCharacters, rig.joints(), 2);
    std::vector<ReferenceCharacter> reference(kCharacters);
    std::vector<const LodClip*> clips(kCharacters);
    std::vector<double> times(kCharacters);
    for (int c = 0; c < kCharacters; ++c) {
      clips[static_cast<std::size_t>(c)] = choices[c % 3];
      times[static_cast<std::size_t>(c)] = unit(random) * full.duration();
    }
    std::vector<glm::mat4> models(kCharacters * joints), palette(kCharacters * joints), expected, simplified;
    std::vector<std::uint8_t> window;
    int compared = 0, switches = 0, wraps = 0;
    for (int step = 0; step < kSteps; ++step) {
      for (int c = 0; c < kCharacters; ++c) {
        const std::size_t ci = static_cast<std::size_t>(c);
        const double roll = unit(random);
        if (step > 0) {
          if (roll < 0.05)
            times[ci] = unit(random) * times[ci]; // back
          else if (roll < 0.10)
            times[ci] += (1.0 + 3.0 * unit(random)) * full.duration(); // periods ahead
          else
            times[ci] += (0.5 + unit(random)) / 60.0;
          if (unit(random) < 0.12) {
            clips[ci] = choices[(std::find(choices, choices + 3, clips[ci]) - choices + 1 + (roll < 0.5)) % 3];
            ++switches;
          }
        }
        if (std::fmod(times[ci] * full.fps(), full.frameCount() - 1.0) < blendFrames && times[ci] > full.duration())
          ++wraps;
      }
      PoseEvaluatorJob job;
      job.parents = rig.parents;
      job.inverseBinds = rig.inverseBinds;
      job.clips = clips;
      job.times = times;
      job.blendFrames = blendFrames;
      job.pool = &pool;
      job.context = &context;
      job.out_models = models;
      job.out_palette = palette;
      ASSERT_TRUE(job.run());
      for (int c = 0; c < kCharacters; ++c) {
        const std::size_t ci = static_cast<std::size_t>(c);
        reference[ci].play(*clips[ci], times[ci], blendFrames);
        reference[ci].models(rig, times[ci], blendFrames, expected);
        for (std::size_t j = 0; j < joints; ++j) {
          ASSERT_TRUE(elementsNear(models[ci * joints + j], expected[j], 2e-4f))
              << "N=" << blendFrames << " step " << step << " character " << c << " joint " << j << " at " << times[ci]
              << " s";
          ASSERT_TRUE(paletteNear(palette[ci * joints + j], models[ci * joints + j], rig.inverseBinds[j]));
        }
        ++compared;
        // away from a wrap's and a level change's blends: forward kinematics of M'(t)
        // outside unfreeze windows (a joint and its ancestors), within the level's
        // fidelity inside them
        const LodClip& lod = *clips[ci];
        std::int64_t loop = 0;
        const double f = lod.framePosition(times[ci], &loop);
        std::int32_t i0 = 0;
        float fraction = 0.0f;
        lod.split(f, i0, fraction);
        if (blendFrames == 0 || reference[ci].levelWeight(times[ci]) >= 0.0 || (loop >= 1 && i0 < blendFrames))
          continue;
        ReferenceCharacter plain;
        plain.play(lod, times[ci], 0);
        plain.models(rig, times[ci], 0, simplified);
        window.assign(joints, 0);
        for (std::size_t j = 0; j < joints; ++j) {
          for (const LodClip::Cluster& cluster : lod.clusters(static_cast<int>(j)))
            window[j] = window[j] ||
                        (cluster.last < lod.frameCount() - 1 && i0 >= cluster.last && i0 < cluster.last + blendFrames);
          const int parent = rig.parents[j];
          window[j] = window[j] || (parent >= 0 && window[static_cast<std::size_t>(parent)]);
          const glm::mat4& model = models[ci * joints + j];
          if (window[j]) {
            ++inside;
            ASSERT_LE(distance(model, simplified[j]), fidelity[std::find(choices, choices + 3, &lod) - choices])
                << "step " << step << " character " << c << " joint " << j << " inside an unfreeze window";
          } else {
            ++outside;
            ASSERT_TRUE(elementsNear(model, simplified[j], 2e-4f))
                << "step " << step << " character " << c << " joint " << j << " outside every window";
          }
        }
      }
    }
    EXPECT_EQ(compared, kCharacters * kSteps);
    EXPECT_GT(switches, 100);
    if (blendFrames > 0) {
      EXPECT_GT(wraps, 0) << "some character-frames lie in a wrap window";
      if (hasWindows) {
        EXPECT_GT(inside, 0) << "joint-frames inside unfreeze windows";
      }
      EXPECT_GT(outside, static_cast<int>(joints) * kCharacters * kSteps / 4) << "joint-frames outside every window";
    }
  }
}

std::vector<std::string> randomFrameFiles() {
  std::vector<std::string> files = test::fixtureClips();
  for (const std::string& character : test::fixtureCharacters("animated"))
    files.push_back(character);
  return files;
}
INSTANTIATE_TEST_SUITE_P(Fixtures, RandomFrames, ::testing::ValuesIn(randomFrameFiles()), test::fixtureName);

// Guards the precision (docs/architecture.md section 5, "Compressed clips"): a clip built as
// production builds it (with the skeleton's parents, default precision) shows, at random
// frame positions of a two-thread crowd, every joint and every point 3 cm from one (ACL's
// shell) within the precision of forward kinematics of the unquantized M'(t), at full
// detail and at two levels; the encoder's own bound says so too; and a joint frozen in a
// cluster holds one key (the same bits at every frame of it).
class Quantized : public ::testing::TestWithParam<std::string> {};

TEST_P(Quantized, StaysWithinThePrecision) {
  const std::string file = GetParam();
  const Asset& asset = runtimeAsset(file);
  const Clip& clip = asset.clips.front();
  const Rig rig(asset.skeleton);
  const std::size_t joints = static_cast<std::size_t>(rig.joints());
  const std::vector<JpcLevelResult>& levels = levelsOf(file);
  for (const std::size_t index : {std::size_t{0}, std::size_t{2}, levels.size() - 1}) {
    const JpcLevelResult& level = levels[index];
    const std::string what = file + " E=" + std::to_string(level.threshold);
    Result<LodClip> built = buildLodClip(clip, &level.clusters, false, rig.parents);
    ASSERT_TRUE(built) << built.message();
    const LodClip& lod = *built;
    const double precision = lod.precisionCm();
    EXPECT_EQ(precision, kDefaultClipPrecisionCm);
    EXPECT_LE(lod.encodedErrorCm(), precision) << what;
    const Clip simplified = simplifiedClip(clip, level.clusters);
    constexpr int kCharacters = 64;
    WorkerPool pool(2);
    PoseEvaluatorContext context(kCharacters, rig.joints(), 2);
    std::mt19937 random(7u + static_cast<unsigned>(index));
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const std::vector<const LodClip*> clips(kCharacters, &lod);
    std::vector<double> times(kCharacters);
    for (double& t : times)
      t = unit(random) * lod.duration();
    std::vector<glm::mat4> models(kCharacters * joints), palette(kCharacters * joints), expected;
    PoseEvaluatorJob job;
    job.parents = rig.parents;
    job.inverseBinds = rig.inverseBinds;
    job.clips = clips;
    job.times = times;
    job.pool = &pool;
    job.context = &context;
    job.out_models = models;
    job.out_palette = palette;
    ASSERT_TRUE(job.run());
    double worst = 0.0, worstRatio = 0.0;
    for (std::size_t c = 0; c < kCharacters; ++c) {
      plainModels(asset.skeleton, simplified, times[c] * clip.fps, expected);
      for (std::size_t j = 0; j < joints; ++j) {
        const glm::mat4& actual = models[c * joints + j];
        const glm::vec3 at(actual[3]), want(expected[j][3]);
        // float forward kinematics itself rounds at about 1e-5 of the position (cm)
        const double allowed = precision + 2e-5 * std::max(1.0f, glm::length(want));
        double error = glm::distance(at, want);
        for (int k = 0; k < 3; ++k) {
          const glm::vec3 shell = at + 3.0f * glm::normalize(glm::vec3(actual[k]));
          const glm::vec3 wanted = want + 3.0f * glm::normalize(glm::vec3(expected[j][k]));
          error = std::max(error, double(glm::distance(shell, wanted)));
        }
        worst = std::max(worst, error);
        worstRatio = std::max(worstRatio, error / allowed);
        ASSERT_LE(error, allowed) << what << ": character " << c << " joint " << j << " at frame position "
                                  << times[c] * clip.fps;
      }
    }
    RecordProperty(what + " worst error (cm)", std::to_string(worst));
    // a frozen joint holds its key: the same bits through the cluster
    for (int j = 0; j < lod.jointCount(); ++j)
      for (const LodClip::Cluster& cluster : lod.clusters(j)) {
        const glm::quat key = lod.rotationAt(j, cluster.first);
        for (int f = cluster.first + 1; f <= cluster.last; ++f) {
          const glm::quat shown = lod.rotationAt(j, f);
          ASSERT_EQ(std::memcmp(&key, &shown, sizeof key), 0) << what << ": joint " << j << " frame " << f;
        }
      }
  }
}
INSTANTIATE_TEST_SUITE_P(Fixtures, Quantized, ::testing::ValuesIn(randomFrameFiles()), test::fixtureName);

// Guards validate(): each invalid input in turn fails, and run() then writes nothing.
TEST(PoseEvaluator, RejectsInvalidJobs) {
  const Asset& asset = runtimeAsset(kCmu);
  const Clip& clip = asset.clips.front();
  const Rig rig(asset.skeleton);
  const LodClip lod = lodClip(clip, nullptr);
  const LodClip looping = lodClip(clip, nullptr, true);
  const std::size_t joints = static_cast<std::size_t>(rig.joints());
  std::vector<const LodClip*> clips{&lod, &lod};
  std::vector<double> times{0.0, 1.0};
  std::vector<glm::mat4> models(2 * joints), palette(2 * joints, glm::mat4(7.0f));
  PoseEvaluatorContext context(2, rig.joints());
  const auto valid = [&] {
    PoseEvaluatorJob job;
    job.parents = rig.parents;
    job.inverseBinds = rig.inverseBinds;
    job.clips = clips;
    job.times = times;
    job.context = &context;
    job.out_models = models;
    job.out_palette = palette;
    return job;
  };
  std::string accepted = "unchanged";
  ASSERT_TRUE(valid().validate(&accepted));
  EXPECT_EQ(accepted, "unchanged") << "a valid job leaves the message alone";
  std::vector<PoseEvaluatorJob> invalid;
  {
    PoseEvaluatorJob job = valid();
    job.context = nullptr; // no context
    invalid.push_back(job);
  }
  {
    PoseEvaluatorJob job = valid();
    job.out_palette = {}; // no palette
    invalid.push_back(job);
  }
  {
    PoseEvaluatorJob job = valid();
    job.out_palette = std::span<glm::mat4>(palette.data(), joints); // palette of one character
    invalid.push_back(job);
  }
  {
    PoseEvaluatorJob job = valid();
    job.out_models = std::span<glm::mat4>(models.data(), 2 * joints - 1); // models one short
    invalid.push_back(job);
  }
  const LodClip* none[2] = {&lod, nullptr};
  {
    PoseEvaluatorJob job = valid();
    job.clips = none; // a null clip
    invalid.push_back(job);
  }
  {
    PoseEvaluatorJob job = valid();
    job.clips = std::span<const LodClip* const>(clips.data(), 1); // clips and times differ
    invalid.push_back(job);
  }
  const double late[2] = {0.0, lod.duration() + 0.01};
  const double early[2] = {-0.001, 0.0};
  const double nan[2] = {0.0, std::nan("")};
  for (const double* bad : {late, early, nan}) {
    PoseEvaluatorJob job = valid();
    job.times = std::span<const double>(bad, 2); // time out of range
    invalid.push_back(job);
  }
  {
    PoseEvaluatorJob job = valid();
    job.inverseBinds = std::span<const glm::mat4>(rig.inverseBinds.data(), joints - 1); // inverse binds short
    invalid.push_back(job);
  }
  std::vector<glm::mat4> projective = rig.inverseBinds;
  projective[3][0][3] = 0.5f;
  {
    PoseEvaluatorJob job = valid();
    job.inverseBinds = projective; // not affine
    invalid.push_back(job);
  }
  std::vector<std::int16_t> cyclic = rig.parents;
  cyclic[2] = 5;
  {
    PoseEvaluatorJob job = valid();
    job.parents = cyclic; // a child before its parent
    invalid.push_back(job);
  }
  PoseEvaluatorContext small(1, rig.joints());
  PoseEvaluatorContext otherSkeleton(2, rig.joints() - 1);
  for (PoseEvaluatorContext* bad : {&small, &otherSkeleton}) {
    PoseEvaluatorJob job = valid();
    job.context = bad; // a context for fewer characters / another skeleton
    invalid.push_back(job);
  }
  WorkerPool pool(2);
  {
    PoseEvaluatorJob job = valid();
    job.pool = &pool; // more threads than the context has scratch for
    invalid.push_back(job);
  }
  {
    PoseEvaluatorJob job = valid();
    job.blendFrames = -1;
    invalid.push_back(job);
  }
  const LodClip clustered = lodClip(clip, &levelsOf(kCmu)[2].clusters, false, 4);
  const LodClip* clusteredClips[2] = {&lod, &clustered};
  for (const int blendFrames : {0, 5}) {
    PoseEvaluatorJob job = valid();
    job.clips = clusteredClips;
    job.blendFrames = blendFrames; // the clip is set for 4 frames of blending
    invalid.push_back(job);
  }
  for (std::size_t i = 0; i < invalid.size(); ++i) {
    std::string why;
    EXPECT_FALSE(invalid[i].validate(&why)) << "case " << i;
    EXPECT_FALSE(why.empty()) << "case " << i << ": validate() says why it refuses";
    EXPECT_FALSE(invalid[i].run()) << "case " << i;
  }
  EXPECT_EQ(palette[0], glm::mat4(7.0f)) << "a failed run writes nothing";
  {
    PoseEvaluatorJob job = valid();
    job.clips = clusteredClips;
    job.blendFrames = 4;
    EXPECT_TRUE(job.validate()) << "a clip set for the job's blending";
  }
  // a looping clip takes any time >= 0
  const LodClip* loopingClips[2] = {&looping, &looping};
  const double later[2] = {0.0, 10 * looping.duration() + 0.3};
  PoseEvaluatorJob job = valid();
  job.clips = loopingClips;
  job.times = later;
  EXPECT_TRUE(job.run());
}

} // namespace
} // namespace mlod
