#include "cli/bench_crowd_command.h"

#include "core/crowd/crowd.h"
#include "core/jpc/jpc.h"
#include "core/lod/lod_set.h"
#include "core/lod_clip_builder.h"
#include "core/mapping/motion_mapping.h"
#include "runtime/pose_evaluator.h"
#include "runtime/skinning_job.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>

namespace mlod::cli {

namespace {
std::string number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}
} // namespace

void BenchCrowdCommand::attach(CLI::App& app) {
  CLI::App* command = app.add_subcommand(
      "bench-crowd",
      "What the motion LOD buys at run time: a crowd evaluated at full detail and at the LOD of one threshold, "
      "in one run (pose evaluation, palette, and skinning where the file has a mesh)");
  command->add_option("FILE", file, "motion or character file (its first clip plays); with --scene, the character")
      ->required();
  command->add_option("--characters", characters, "characters in the crowd (default 1000)")
      ->check(CLI::Range(1, 1000000));
  command->add_option("--frames", frames, "frames per repetition, 1/60 s apart (default 100)")
      ->check(CLI::Range(1, 1000000));
  command->add_option("--threshold", threshold, "the LOD's JPC threshold E, cm·degrees (required without --scene)");
  command->add_flag("--scene", scene,
                    "the paper's Figure 12: frame time of a crowd of the character, pose evaluation and CPU skinning, "
                    "with no simplification, skeletal only, mesh only and both; each level's agent cost is the frame "
                    "time with every agent forced to that level over the same with every agent at LOD0, timed in the "
                    "same run");
  command->add_option("--motion", motion, "--scene: a clip mapped onto the character (automatic motion mapping)");
  command->add_option("--agents", agents, "--scene: agents in the crowd (default 1000)")
      ->check(CLI::Range(1, kMaxCrowdAgents));
  command->add_option("--budget-px", budgetPixels, "--scene: pixel budget of the generated LOD set (default 1)")
      ->check(CLI::Range(0.01, 1000.0));
  command->add_option("--levels", levelCount, "--scene: levels of the generated LOD set, level 0 included (default 4)")
      ->check(CLI::Range(1, 16));
  addSkinningOption(*command, budgetSkinning, "--scene: for the generated LOD set");
  command->add_flag("--no-skinning", noSkinning,
                    "skin nothing: time the pose alone (what an engine's CPU pays when the GPU skins)");
  command->add_option("--layout", layout, "--scene: grid or scattered (default grid)")
      ->check(CLI::IsMember({"grid", "scattered"}));
  command->add_option("--alpha", alpha, "orientation weight alpha, cm (default " + number(kDefaultJpcAlpha) + ")");
  command->add_option("--threads", threads, "threads to spread characters over (default 1)")->check(CLI::Range(1, 256));
  command
      ->add_option("--blend-frames", blendFrames, "frames over which resuming joints blend back (default 4; 0 = off)")
      ->check(CLI::Range(0, kMaxBlendFrames));
  command->add_option("--repetitions", repetitions, "timed repetitions of each side (default 5; median)")
      ->check(CLI::Range(1, 1000));
  command->add_flag("--palette-only", paletteOnly, "write the skinning palette only, no model matrices");
  command->add_option("--only", only, "full or lod: run one side only, no warm-up (for callgrind)")
      ->check(CLI::IsMember({"full", "lod"}));
  command->add_flag("--json", json, "print one JSON document on stdout");
  addImportOptions(*command, import);
}

namespace {

double median(std::vector<double> values) {
  if (values.empty())
    return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t mid = values.size() / 2;
  return values.size() % 2 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
}

// One side of the comparison: full detail or the LOD, each a crowd of one level.
struct Side {
  const char* name = "";
  Crowd crowd;
  std::vector<double> poseSeconds;
  std::vector<double> skinSeconds;
  std::int64_t sampled = 0; // joints evaluated in the last repetition
};

} // namespace

int BenchCrowdCommand::run() const {
  if (scene)
    return runScene();
  if (budgetSkinning) {
    printError(file, "--skinning applies to --scene's generated LOD set (--no-skinning times the pose alone)");
    return kExitBadInput;
  }
  if (!threshold) {
    printError(file, "--threshold is required (or --scene)");
    return kExitBadInput;
  }
  const double e = *threshold;
  if (Error error = validateThreshold(e, "--threshold " + number(e))) {
    printError(file, error.message());
    return kExitBadInput;
  }
  if (Error error = validateAlpha(alpha, "--alpha")) {
    printError(file, error.message());
    return kExitBadInput;
  }
  const std::optional<Asset> asset = importForCommand(file, import);
  if (!asset)
    return kExitBadInput;
  if (asset->clips.empty()) {
    printError(file, "has no animation clip to play");
    return kExitBadInput;
  }
  const Clip& clip = asset->clips.front();
  if (clip.frameCount < 2) {
    printError(file, "clip '" + clip.name + "' has one frame: nothing to play");
    return kExitBadInput;
  }
  JpcSettings settings;
  settings.alpha = alpha;
  settings.zeroLength = 1e-6 * asset->unitScale;
  const double thresholds[1] = {e};
  Result<std::vector<JpcLevelResult>> levels = simplifyClip(asset->skeleton, clip, settings, thresholds);
  if (!levels) {
    printError(file, levels.message());
    return kExitBadInput;
  }
  const JpcLevelResult& level = levels->front();
  const SkinnedMesh* skinned = nullptr;
  for (const SkinnedMesh& mesh : asset->meshes)
    if (mesh.skinned() && !skinned)
      skinned = &mesh;
  // one level each, the original skeleton and mesh: full detail (no clusters) and the LOD,
  // played by core's Crowd (the loop the studio's Crowd dock runs), looping
  Result<CrowdLevel> fullLevel = buildCrowdLevel(asset->skeleton, skinned, clip, nullptr);
  Result<CrowdLevel> lodLevel = buildCrowdLevel(asset->skeleton, skinned, clip, &level.clusters);
  if (!fullLevel || !lodLevel) {
    printError(file, (!fullLevel ? fullLevel : lodLevel).message());
    return kExitBadInput;
  }
  const std::size_t joints = fullLevel->parents.size();
  std::optional<SkinningMesh> skinning; // for its figures (the crowd skins its own)
  if (skinned) {
    Result<SkinningMesh> built = buildSkinningMesh(*skinned, asset->skeleton.jointCount());
    if (!built) {
      printError(file, built.message());
      return kExitBadInput;
    }
    skinning = std::move(built).value();
  }
  const LodClip& full = fullLevel->clip;
  const LodClip& lod = lodLevel->clip;
  // every clip a side's evaluator reads, each once: one each here
  const std::size_t fullBytes = full.byteSize(), lodBytes = lod.byteSize();
  const double clipSeconds = full.duration();

  // the crowd: starts spread over the clip (golden-ratio steps), 1/60 s per frame
  const std::size_t n = static_cast<std::size_t>(characters);
  std::vector<CrowdAgent> crowdAgents(n);
  for (std::size_t c = 0; c < n; ++c)
    crowdAgents[c].timeOffset = std::fmod(static_cast<double>(c) * 0.6180339887498949, 1.0) * full.duration();
  Side sides[2];
  sides[0].name = "full";
  sides[1].name = "lod";
  std::vector<CrowdLevel> sideLevels[2];
  sideLevels[0].push_back(std::move(fullLevel).value());
  sideLevels[1].push_back(std::move(lodLevel).value());
  const int animated = sideLevels[0].front().clip.animatedJointCount();
  for (int s = 0; s < 2; ++s) {
    Crowd& crowd = sides[s].crowd;
    crowd.setLevels(std::move(sideLevels[s]));
    Crowd::Selection selection;
    selection.forcedLevel = 0;
    crowd.setSelection(selection);
    crowd.setThreads(threads);
    crowd.setModels(!paletteOnly);
    crowd.setBlendFrames(blendFrames);
    crowd.setSkinning(skinned != nullptr && !noSkinning);
  }

  std::string failure;
  const auto repetition = [&](Side& side, bool record) {
    side.crowd.setAgents(crowdAgents); // every repetition from the same start
    double pose = 0.0, skin = 0.0;
    std::int64_t sampled = 0;
    for (int frame = 0; frame < frames; ++frame) {
      if (Error error = side.crowd.update(frame / 60.0, glm::vec3(0.0f)))
        failure = error.message();
      const CrowdFrameStats& stats = side.crowd.stats();
      pose += stats.poseMs / 1000.0;
      skin += stats.skinMs / 1000.0;
      sampled += stats.jointsEvaluated;
    }
    if (record) {
      side.poseSeconds.push_back(pose);
      side.skinSeconds.push_back(skin);
      side.sampled = sampled;
    }
  };
  const bool runFull = only.empty() || only == "full";
  const bool runLod = only.empty() || only == "lod";
  if (only.empty()) {
    repetition(sides[0], false); // warm-up: caches, pages, the threads
    repetition(sides[1], false);
  }
  for (int r = 0; r < repetitions; ++r) {
    if (runFull)
      repetition(sides[0], true);
    if (runLod)
      repetition(sides[1], true);
  }
  if (!failure.empty()) {
    printError(file, failure + " (a bug: please report it)");
    return kExitFailure;
  }

  const double charFrames = static_cast<double>(characters) * frames;
  const std::size_t perCharacter = PoseEvaluatorContext(1, static_cast<int>(joints)).bytesPerCharacter() +
                                   (paletteOnly ? 1 : 2) * joints * sizeof(glm::mat4);
  const auto sideJson = [&](const Side& side, std::size_t clipBytes) {
    nlohmann::ordered_json out;
    const double seconds = median(side.poseSeconds);
    out["clip_bytes"] = clipBytes;
    out["bytes_per_second"] = bytesPerSecond(clipBytes, clipSeconds);
    out["seconds"] = seconds;
    out["joints_evaluated"] = side.sampled;
    out["char_frames_per_second"] = seconds > 0.0 ? charFrames / seconds : 0.0;
    out["ns_per_character_frame"] = 1e9 * seconds / charFrames;
    out["joints_evaluated_per_character_frame"] = static_cast<double>(side.sampled) / charFrames;
    out["repetition_seconds"] = side.poseSeconds;
    return out;
  };
  nlohmann::ordered_json doc;
  doc["file"] = file;
  doc["clip"] = clip.name;
  doc["characters"] = characters;
  doc["frames"] = frames;
  doc["threshold"] = e;
  doc["alpha"] = alpha;
  doc["threads"] = threads;
  doc["blend_frames"] = blendFrames;
  doc["outputs"] = paletteOnly ? "palette" : "models+palette";
  doc["repetitions"] = repetitions;
  doc["joints"] = joints;
  doc["animated_joints"] = animated;
  doc["simplified_joint_percent"] = level.simplifiedPercent;
  doc["max_joint_position_error_cm"] = level.maxJointPositionErrorCm;
  doc["clip_seconds"] = clipSeconds;
  doc["full"] = runFull ? sideJson(sides[0], fullBytes) : nlohmann::ordered_json();
  doc["lod"] = runLod ? sideJson(sides[1], lodBytes) : nlohmann::ordered_json();
  const double fullSeconds = median(sides[0].poseSeconds), lodSeconds = median(sides[1].poseSeconds);
  doc["speedup"] = runFull && runLod && lodSeconds > 0.0 ? nlohmann::ordered_json(fullSeconds / lodSeconds)
                                                         : nlohmann::ordered_json();
  // the ratio of each repetition's full and LOD runs, taken one after the other: how far
  // the speedup moves with the machine's noise
  std::vector<double> pairs;
  if (runFull && runLod)
    std::transform(sides[0].poseSeconds.begin(), sides[0].poseSeconds.end(), sides[1].poseSeconds.begin(),
                   std::back_inserter(pairs), std::divides<>());
  doc["speedup_pairs"] = runFull && runLod ? nlohmann::ordered_json(pairs) : nlohmann::ordered_json();
  doc["memory"] = {{"full_bytes", fullBytes},
                   {"lod_bytes", lodBytes},
                   {"precision_cm", full.precisionCm()},
                   {"full_encoded_error_cm", full.encodedErrorCm()},
                   {"lod_encoded_error_cm", lod.encodedErrorCm()},
                   {"per_character_bytes", perCharacter}};
  double fullSkin = 0.0, lodSkin = 0.0;
  if (skinning && !noSkinning) {
    fullSkin = median(sides[0].skinSeconds);
    lodSkin = median(sides[1].skinSeconds);
    nlohmann::ordered_json skin;
    skin["vertices"] = skinning->vertexCount();
    skin["vertices_by_influences"] = {
        skinning->groupBegin(2) - skinning->groupBegin(1), skinning->groupBegin(3) - skinning->groupBegin(2),
        skinning->groupBegin(4) - skinning->groupBegin(3), skinning->groupBegin(5) - skinning->groupBegin(4)};
    skin["full_seconds"] = runFull ? nlohmann::ordered_json(fullSkin) : nlohmann::ordered_json();
    skin["lod_seconds"] = runLod ? nlohmann::ordered_json(lodSkin) : nlohmann::ordered_json();
    skin["ns_per_character_frame"] = 1e9 * (runFull ? fullSkin : lodSkin) / charFrames;
    skin["mesh_bytes"] = skinning->byteSize();
    if (runFull && runLod) {
      skin["full_total_seconds"] = fullSeconds + fullSkin;
      skin["lod_total_seconds"] = lodSeconds + lodSkin;
      skin["speedup_with_skinning"] = (fullSeconds + fullSkin) / (lodSeconds + lodSkin);
    }
    doc["skinning"] = skin;
  }
  if (json) {
    std::cout << jsonText(doc) << std::endl;
    return kExitOk;
  }
  std::printf("file:       %s, clip '%s' (%d frames at %g fps, looped), %zu joints (%d animated)\n", file.c_str(),
              clip.name.c_str(), clip.frameCount, clip.fps, joints, animated);
  std::printf("crowd:      %d characters x %d frames (1/60 s apart), %d thread(s), blend %d frames, %s\n", characters,
              frames, threads, blendFrames, paletteOnly ? "palette only" : "model matrices and palette");
  std::printf("LOD:        E = %g (alpha %g): %.1f%% joint-frames simplified, joint position error up to %.3f cm\n", e,
              alpha, level.simplifiedPercent, level.maxJointPositionErrorCm);
  std::printf("median of %d repetitions, alternating full and LOD:\n", repetitions);
  std::printf("  %-6s %12s %18s %16s\n", "", "seconds", "ns/character-frame", "joints sampled/cf");
  for (const Side& side : sides) {
    if ((&side == &sides[0] && !runFull) || (&side == &sides[1] && !runLod))
      continue;
    const double seconds = median(side.poseSeconds);
    std::printf("  %-6s %12.6f %18.1f %16.2f\n", side.name, seconds, 1e9 * seconds / charFrames,
                static_cast<double>(side.sampled) / charFrames);
  }
  if (runFull && runLod) {
    std::printf("  speedup (pose): %.3fx", fullSeconds / lodSeconds);
    if (pairs.size() > 1) {
      const auto [lowest, highest] = std::minmax_element(pairs.begin(), pairs.end());
      std::printf(" (repetition by repetition %.3fx to %.3fx)", *lowest, *highest);
    }
    std::printf("\n");
  }
  if (skinning && !noSkinning) {
    std::printf("skinning:   %d vertices: %.1f ns/character-frame", skinning->vertexCount(),
                1e9 * (runFull ? fullSkin : lodSkin) / charFrames);
    if (runFull && runLod)
      std::printf("; pose + skinning speedup %.3fx", (fullSeconds + fullSkin) / (lodSeconds + lodSkin));
    std::printf("\n");
  }
  std::printf("memory:     clip %zu bytes full, %zu bytes LOD (precision %.4g cm; encoded error %.4g and %.4g cm); "
              "%zu bytes per character\n",
              fullBytes, lodBytes, full.precisionCm(), full.encodedErrorCm(), lod.encodedErrorCm(), perCharacter);
  std::printf("            per second of animation (%.3f s): %.0f bytes/s full, %.0f bytes/s LOD\n", clipSeconds,
              bytesPerSecond(fullBytes, clipSeconds), bytesPerSecond(lodBytes, clipSeconds));
  return kExitOk;
}

int BenchCrowdCommand::runScene() const {
  const std::optional<Asset> asset = importForCommand(file, import);
  if (!asset)
    return kExitBadInput;
  const SkinnedMesh* mesh = nullptr;
  for (const SkinnedMesh& candidate : asset->meshes)
    if (candidate.skinned() && !mesh)
      mesh = &candidate;
  if (!mesh || asset->skeleton.empty()) {
    printError(file, "has no skinned mesh: --scene needs a character");
    return kExitBadInput;
  }
  // the clip the crowd plays: --motion mapped onto the character, else the character's own
  Clip clip;
  std::vector<Clip> mapped;
  if (!motion.empty()) {
    ImportArguments motionImport;
    const std::optional<Asset> source = importForCommand(motion, motionImport);
    if (!source)
      return kExitBadInput;
    // the one path that puts a clip on a character (core/mapping/motion_mapping.h), as export --motion
    Result<MappedMotion> played = mapMotionAutomatically(
        source->skeleton, std::span<const Clip>(source->clips).first(std::min<std::size_t>(source->clips.size(), 1)),
        asset->skeleton, file);
    if (!played) {
      printError(motion, played.message());
      return kExitBadInput;
    }
    mapped = std::move(played->clips);
    clip = mapped.front();
  } else if (!asset->clips.empty()) {
    clip = asset->clips.front();
  } else {
    printError(file, "has no animation clip to play (give one with --motion)");
    return kExitBadInput;
  }
  if (clip.frameCount < 2) {
    printError(motion.empty() ? file : motion, "clip '" + clip.name + "' has one frame: nothing to play");
    return kExitBadInput;
  }
  LodBudgetOptions budget;
  budget.clips = mapped;
  budget.jpc.zeroLength = 1e-6 * asset->unitScale;
  budget.skinning = budgetSkinning.value_or(LodSkinning::Gpu);
  Result<LodSet> lods = LodSet::fromPixelBudget(*asset, budgetPixels, levelCount, budget);
  if (!lods) {
    printError(file, lods.message());
    return kExitBadInput;
  }
  CrowdLayout crowdLayout;
  crowdLayout.kind = layout == "scattered" ? CrowdLayout::Kind::Scattered : CrowdLayout::Kind::Grid;
  crowdLayout.agents = agents;
  float top = 0.0f;
  for (const glm::vec3& p : mesh->positions)
    top = std::max(top, p.y);
  const std::vector<CrowdAgent> placed =
      layoutCrowd(crowdLayout, clip.frameCount > 1 ? (clip.frameCount - 1) / clip.fps : 0.0);
  CrowdComparisonSettings settings;
  settings.frames = frames;
  settings.repetitions = repetitions;
  settings.threads = threads;
  settings.centreHeightCm = 0.5f * top;
  settings.jpc = budget.jpc;
  settings.skinning = !noSkinning;
  settings.levelCosts = true;
  Result<CrowdComparison> compared =
      compareCrowdConfigurations(asset->skeleton, mesh, clip, *lods, placed, crowdFrontCamera(placed), settings);
  if (!compared) {
    printError(file, compared.message());
    return kExitBadInput;
  }
  const CrowdConfigurationFigures* runs = compared->configurations;
  const CrowdConfigurationFigures& both = runs[3];
  nlohmann::ordered_json doc;
  doc["file"] = file;
  doc["motion"] = motion.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(motion);
  doc["clip"] = clip.name;
  doc["agents"] = agents;
  doc["frames"] = frames;
  doc["threads"] = threads;
  doc["repetitions"] = repetitions;
  doc["layout"] = layout;
  doc["budget_px"] = budgetPixels;
  doc["budget_skinning"] = lodSkinningName(budget.skinning);
  doc["cpu_skinning"] = !noSkinning;
  doc["clip_seconds"] = compared->clipSeconds;
  nlohmann::ordered_json levelsJson = nlohmann::ordered_json::array();
  for (std::size_t l = 0; l < compared->levels.size(); ++l) {
    const LodLevel& spec = lods->levels[l];
    const CrowdComparison::Level& level = compared->levels[l];
    nlohmann::ordered_json out;
    out["name"] = spec.name;
    out["threshold"] = spec.motionThreshold;
    out["mesh_ratio"] = spec.meshRatio;
    out["triangles"] = level.triangles;
    out["vertices"] = level.vertices;
    out["joints"] = level.joints;
    out["switch_distance_m"] = spec.switchDistanceCm / 100.0;
    out["agents"] = l < both.agentsPerLevel.size() ? both.agentsPerLevel[l] : 0;
    out["all_agents_frame_ms"] = l < compared->levelFrameMs.size() ? compared->levelFrameMs[l] : 0.0;
    out["agent_cost"] = l < compared->levelCost.size() ? compared->levelCost[l] : 0.0;
    levelsJson.push_back(out);
  }
  doc["levels"] = levelsJson;
  nlohmann::ordered_json configurations;
  for (int r = 0; r < 4; ++r) {
    const CrowdConfigurationFigures& run = runs[r];
    nlohmann::ordered_json out;
    out["frame_ms"] = run.frameMs;
    out["pose_ms"] = run.poseMs;
    out["skin_ms"] = run.skinMs;
    out["joints_evaluated"] = run.jointsEvaluated;
    out["vertices_skinned"] = run.verticesSkinned;
    out["repetition_frame_ms"] = run.repetitionFrameMs;
    out["clip_bytes"] = run.clipBytes;
    out["bytes_per_second"] = bytesPerSecond(run.clipBytes, compared->clipSeconds);
    configurations[run.name] = out;
  }
  doc["configurations"] = configurations;
  nlohmann::ordered_json speedup;
  for (int r = 1; r < 4; ++r)
    speedup[runs[r].name] = compared->speedup(r);
  doc["speedup"] = speedup;
  if (json) {
    std::cout << jsonText(doc) << std::endl;
    return kExitOk;
  }
  std::printf("character:  %s (%zu vertices, %d joints)\n", file.c_str(), mesh->vertexCount(),
              asset->skeleton.jointCount());
  std::printf("motion:     %s, clip '%s' (%d frames at %g fps, looped)\n",
              motion.empty() ? file.c_str() : motion.c_str(), clip.name.c_str(), clip.frameCount, clip.fps);
  std::printf("crowd:      %d agents (%s), %d frames (1/60 s apart), %d thread(s), camera at the front, %s\n", agents,
              layout.c_str(), frames, threads, noSkinning ? "pose only (no skinning)" : "pose and CPU skinning");
  std::printf("levels (pixel budget %g px, skinning %s):\n", budgetPixels, lodSkinningName(budget.skinning));
  std::printf("  %-8s %10s %6s %10s %9s %7s %12s %7s %11s\n", "", "threshold", "mesh", "triangles", "vertices",
              "joints", "switch (m)", "agents", "agent cost");
  for (const auto& level : levelsJson)
    std::printf("  %-8s %10g %6.3f %10d %9d %7d %12.2f %7d %11.3f\n", level["name"].get<std::string>().c_str(),
                level["threshold"].get<double>(), level["mesh_ratio"].get<double>(), level["triangles"].get<int>(),
                level["vertices"].get<int>(), level["joints"].get<int>(), level["switch_distance_m"].get<double>(),
                level["agents"].get<int>(), level["agent_cost"].get<double>());
  std::printf("  (agent cost: the frame with every agent at the level over every agent at LOD0, %s)\n",
              noSkinning ? "pose only" : "pose and skinning");
  std::printf("per frame, median of %d repetitions:\n", repetitions);
  std::printf("  %-9s %10s %10s %10s %14s %16s %9s %12s %12s\n", "", "frame ms", "pose ms", "skin ms", "joints",
              "vertices", "speedup", "clip bytes", "bytes/s");
  for (int r = 0; r < 4; ++r) {
    const CrowdConfigurationFigures& run = runs[r];
    std::printf("  %-9s %10.3f %10.3f %10.3f %14.0f %16.0f %8.2fx %12zu %12.0f\n", run.name, run.frameMs, run.poseMs,
                run.skinMs, run.jointsEvaluated, run.verticesSkinned, compared->speedup(r), run.clipBytes,
                bytesPerSecond(run.clipBytes, compared->clipSeconds));
  }
  return kExitOk;
}

} // namespace mlod::cli
