// The .mlod project document: JSON round trip, refusal of bad files, asset paths relative
// to the project, level edits that carry per-joint overrides.

#include "core/lod/lod_levels.h"
#include "core/project.h"
#include "core/project_package.h"

#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/stat.h>
#include <unistd.h>

namespace mlod {
namespace {

LodLevel level(std::string name, double threshold, double ratio = 1.0, double distance = 0.0) {
  LodLevel out;
  out.name = std::move(name);
  out.motionThreshold = threshold;
  out.meshRatio = ratio;
  out.switchDistanceCm = distance;
  return out;
}

Project sampleProject() {
  Project project;
  project.alpha = 7.5;
  project.mode = JpcMode::Optimal;
  project.lods.levels = {level("Original", 0.0), level("Near", 5.0, 0.75, 500.0), level("Mid", 42.25, 0.5, 1234.5),
                         level("Far", 300.0, 0.1 / 3.0, 4000.0)};
  project.lods.levels[2].pixelError = 0.75;
  project.lods.levels[2].triangles = 2500;
  project.lods.projection.verticalFovDegrees = 45.0;
  project.lods.boundingRadiusCm = 95.5;
  ProjectAsset asset;
  asset.path = "clips/01_01.bvh";
  asset.unitScale = 2.54 / 0.45; // not representable in a short decimal: the round trip must be exact
  asset.joints["LeftUpLeg"].thresholds = {std::nullopt, std::nullopt, 12.5};
  asset.joints["Head"].alpha = 0.1;
  asset.joints["Spine"].locked = true;
  asset.joints["Head"].meshImportance = 4.0;
  project.assets.push_back(asset);
  ProjectAsset character;
  character.path = "characters/BCN_Epileptic.X";
  project.assets.push_back(character);
  ProjectMapping mapping;
  mapping.motion = 0;
  mapping.character = 1;
  mapping.mapping.motionName = "01_01.bvh";
  mapping.mapping.characterName = "BCN_Epileptic.X";
  mapping.mapping.pairs = {{"Bip01_Pelvis", "Hips"}, {"Bip01_Spine", "LowerBack"}};
  project.mappings.push_back(mapping);
  project.view = {0, 0, 2, "LeftUpLeg"};
  return project;
}

// Guards the contract the editor and the CLI share: what is written reads back equal, bit for bit.
TEST(Project, JsonRoundTripIsExact) {
  const Project project = sampleProject();
  const Result<Project> read = projectFromJson(projectToJson(project));
  ASSERT_TRUE(read) << read.message();
  EXPECT_TRUE(*read == project);
  EXPECT_EQ(read->assets[0].unitScale, 2.54 / 0.45);
}

// Guards per-character LOD sets (issue 26, item 2; version 4): a character's own set is written
// with it and reads back exactly; an asset without one plays with the project's; a version 3
// file (one set) gives its set to every asset; a bad own set is refused naming its asset.
TEST(Project, EachCharacterOwnsItsLodSet) {
  Project project = sampleProject();
  LodSet own;
  own.levels = {level("LOD0", 0.0), level("Close", 2.0, 0.5, 898.0), level("Away", 5.0, 0.1, 4774.0)};
  own.boundingRadiusCm = 31.25;
  project.assets[1].lods = own;
  EXPECT_EQ(&lodSetFor(project, 1), &*project.assets[1].lods);
  EXPECT_EQ(&lodSetFor(project, 0), &*project.assets[1].lods); // the motion mapped onto it
  EXPECT_EQ(&lodSetFor(project, -1), &project.lods);
  EXPECT_EQ(&lodSetFor(project, 7), &project.lods);
  EXPECT_EQ(levelThresholdsFor(project, 1), (std::vector<double>{0.0, 2.0, 5.0}));
  EXPECT_EQ(levelThresholdsFor(project, 0), (std::vector<double>{0.0, 2.0, 5.0}));
  EXPECT_EQ(levelThresholdsFor(project, -1), project.levelThresholds());
  ASSERT_FALSE(project.validate());
  const nlohmann::json written = nlohmann::json::parse(projectToJson(project));
  EXPECT_EQ(written["version"], 4);
  EXPECT_FALSE(written["assets"][0].contains("lods"));
  ASSERT_TRUE(written["assets"][1].contains("lods"));
  EXPECT_EQ(written["assets"][1]["lods"]["levels"].size(), 3u);
  const Result<Project> read = projectFromJson(written.dump());
  ASSERT_TRUE(read) << read.message();
  EXPECT_TRUE(*read == project);

  // version 3: one set, every asset's (an asset's "lods" there is not read)
  nlohmann::json version3 = written;
  version3["version"] = 3;
  const Result<Project> old = projectFromJson(version3.dump());
  ASSERT_TRUE(old) << old.message();
  for (const ProjectAsset& asset : old->assets)
    EXPECT_FALSE(asset.lods);
  EXPECT_EQ(&lodSetFor(*old, 1), &old->lods);
  EXPECT_EQ(old->lods, project.lods);

  // a bad own set names its asset
  nlohmann::json bad = written;
  bad["assets"][1]["lods"]["levels"][1]["mesh_ratio"] = 0.0;
  const Result<Project> refused = projectFromJson(bad.dump());
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.message().find("asset 1's LOD set"), std::string::npos) << refused.message();
  nlohmann::json noLevels = written;
  noLevels["assets"][1]["lods"].erase("levels");
  EXPECT_NE(projectFromJson(noLevels.dump()).message().find("asset 1 \"lods\" has no \"levels\""), std::string::npos)
      << projectFromJson(noLevels.dump()).message();
}

// Guards where skinning runs (issue 25): a set's "skinning" is written and reads back, the
// project's and a character's own alike; a file saved before it was kept (no "skinning")
// loads as before, skinned on the GPU; another value is refused naming its set.
TEST(Project, SkinningIsSavedWithItsSetAndDefaultsToTheGpu) {
  Project project = sampleProject();
  EXPECT_EQ(project.lods.skinning, LodSkinning::Gpu);
  project.lods.skinning = LodSkinning::Cpu;
  LodSet own = project.lods;
  own.skinning = LodSkinning::Gpu;
  project.assets[1].lods = own;
  const nlohmann::json written = nlohmann::json::parse(projectToJson(project));
  EXPECT_EQ(written["lods"]["skinning"], "cpu");
  EXPECT_EQ(written["assets"][1]["lods"]["skinning"], "gpu");
  const Result<Project> read = projectFromJson(written.dump());
  ASSERT_TRUE(read) << read.message();
  EXPECT_TRUE(*read == project);
  EXPECT_EQ(read->lods.skinning, LodSkinning::Cpu);
  EXPECT_EQ(read->assets[1].lods->skinning, LodSkinning::Gpu);

  nlohmann::json old = written; // as saved before the field was kept
  old["lods"].erase("skinning");
  old["assets"][1]["lods"].erase("skinning");
  const Result<Project> before = projectFromJson(old.dump());
  ASSERT_TRUE(before) << before.message();
  EXPECT_EQ(before->lods.skinning, LodSkinning::Gpu);
  EXPECT_EQ(before->assets[1].lods->skinning, LodSkinning::Gpu);
  EXPECT_EQ(before->lods.levels, project.lods.levels);

  for (const nlohmann::json& value : {nlohmann::json("GPU"), nlohmann::json("both"), nlohmann::json(1)}) {
    nlohmann::json bad = written;
    bad["assets"][1]["lods"]["skinning"] = value;
    const Result<Project> refused = projectFromJson(bad.dump());
    ASSERT_FALSE(refused) << value;
    EXPECT_NE(refused.message().find("asset 1 \"lods\" skinning"), std::string::npos) << refused.message();
  }
}

// Guards level edits of one character (issue 26: levels generated for one character were
// offered for another): the edited character gets its own set, copied from what it played
// with, and the per-joint overrides of what plays with it (the motion mapped onto it) follow
// their level; the other assets and the project's set are untouched. With no asset (-1) the
// project's set is edited, as before.
TEST(Project, ALevelEditChangesOneCharactersSet) {
  Project project = sampleProject(); // asset 0 (mapped onto asset 1) overrides LeftUpLeg at level 2
  ProjectAsset other;
  other.path = "characters/Testwuson.X";
  other.joints["Body"].thresholds = {std::nullopt, std::nullopt, 7.0};
  project.assets.push_back(other);
  const LodSet shared = project.lods;
  Result<LodSetEdit> removed = removeLodLevel(lodSetFor(project, 1), 1);
  ASSERT_TRUE(removed) << removed.message();
  applyLodSetEdit(project, 1, *removed);
  ASSERT_TRUE(project.assets[1].lods);
  EXPECT_EQ(project.assets[1].lods->levels.size(), shared.levels.size() - 1);
  EXPECT_EQ(project.lods, shared);
  EXPECT_FALSE(project.assets[0].lods);
  EXPECT_FALSE(project.assets[2].lods);
  EXPECT_EQ(&lodSetFor(project, 0), &*project.assets[1].lods); // the motion plays with its character's
  EXPECT_EQ(&lodSetFor(project, 2), &project.lods);
  // the motion's LeftUpLeg override of old level 2 is now at level 1; the other character's stays
  EXPECT_EQ(project.assets[0].joints["LeftUpLeg"].thresholds, (std::vector<std::optional<double>>{std::nullopt, 12.5}));
  EXPECT_EQ(project.assets[2].joints["Body"].thresholds,
            (std::vector<std::optional<double>>{std::nullopt, std::nullopt, 7.0}));
  EXPECT_FALSE(project.validate());
  // an edit of the project's set leaves the character with its own set, overrides and all
  Result<LodSetEdit> renamed = renameLodLevel(project.lods, 1, "Nearby");
  ASSERT_TRUE(renamed);
  applyLodSetEdit(project, -1, *renamed);
  EXPECT_EQ(project.lods.levels[1].name, "Nearby");
  EXPECT_EQ(project.assets[1].lods->levels[1].name, "Mid");
  EXPECT_EQ(project.assets[0].joints["LeftUpLeg"].thresholds, (std::vector<std::optional<double>>{std::nullopt, 12.5}));
}

// Guards the rule "a clip plays with the set of the character it is mapped to" (issue 26,
// item 7: the studio showed a mapped motion with the motion's own levels): lodSetOwner() of
// a mapped motion is its character, of anything else the asset itself; a level edit made
// with the motion in view edits the character's set; unmapped, the motion keeps its own.
TEST(Project, AMappedMotionPlaysWithItsCharactersSet) {
  Project project = sampleProject(); // motion 0 mapped onto character 1
  EXPECT_EQ(lodSetOwner(project, 0), 1);
  EXPECT_EQ(lodSetOwner(project, 1), 1);
  EXPECT_EQ(lodSetOwner(project, -1), -1);
  EXPECT_EQ(lodSetOwner(project, 2), -1);
  LodSet motionOwn = project.lods;
  motionOwn.levels.pop_back();
  project.assets[0].lods = motionOwn; // a set the motion made before it was mapped
  LodSet characterOwn = project.lods;
  characterOwn.levels[1].motionThreshold = 2.0;
  project.assets[1].lods = characterOwn;
  EXPECT_EQ(lodSetFor(project, 0), characterOwn);
  EXPECT_EQ(levelThresholdsFor(project, 0), levelThresholdsFor(project, 1));

  Result<LodSetEdit> edited = setLodLevelThreshold(lodSetFor(project, 0), 1, 3.5);
  ASSERT_TRUE(edited) << edited.message();
  applyLodSetEdit(project, 0, *edited); // with the motion in view
  EXPECT_EQ(project.assets[1].lods->levels[1].motionThreshold, 3.5);
  EXPECT_EQ(project.assets[0].lods, motionOwn);

  project.mappings.clear(); // unassigned: the motion plays with its own again
  EXPECT_EQ(lodSetOwner(project, 0), 0);
  EXPECT_EQ(lodSetFor(project, 0), motionOwn);
}

// sampleProject() with a second character, Testwuson (asset 2), the motion mapped onto both
// (BCN first), each character with its own set: BCN's thresholds 0, 2, 5; Testwuson's 0, 10,
// 20, 40.
Project motionOnTwoCharacters() {
  Project project = sampleProject();
  ProjectAsset wuson;
  wuson.path = "characters/Testwuson.X";
  project.assets.push_back(wuson);
  ProjectMapping second = project.mappings[0];
  second.character = 2;
  second.mapping.characterName = "Testwuson.X";
  project.mappings.push_back(second);
  LodSet bcn;
  bcn.levels = {level("LOD0", 0.0), level("Close", 2.0, 0.5, 898.0), level("Away", 5.0, 0.1, 4774.0)};
  project.assets[1].lods = bcn;
  LodSet wusonOwn;
  wusonOwn.levels = {level("LOD0", 0.0), level("W1", 10.0, 0.5, 300.0), level("W2", 20.0, 0.25, 600.0),
                     level("W3", 40.0, 0.1, 1200.0)};
  project.assets[2].lods = wusonOwn;
  EXPECT_FALSE(project.validate());
  return project;
}

// Guards issue 26's last item ("a clip plays with the set of the character it is mapped to"):
// a motion mapped onto two characters plays with the set of the one it is viewed on; viewed
// on none (its own skeleton), or on a character it is not mapped onto, with its first
// mapping's; a character keeps its own whatever is viewed. A level edit made with the motion
// viewed on the second character edits that one's set, and the motion's overrides follow it.
TEST(Project, AMotionPlaysWithTheSetOfTheCharacterItIsViewedOn) {
  Project project = motionOnTwoCharacters();
  const LodSet bcn = *project.assets[1].lods, wuson = *project.assets[2].lods;
  EXPECT_EQ(lodSetOwner(project, 0, 2), 2);
  EXPECT_EQ(lodSetOwner(project, 0, 1), 1);
  EXPECT_EQ(lodSetOwner(project, 0), 1);    // none viewed: the first mapping's
  EXPECT_EQ(lodSetOwner(project, 0, 0), 1); // on its own skeleton
  EXPECT_EQ(lodSetOwner(project, 0, 7), 1); // out of range
  EXPECT_EQ(lodSetOwner(project, 1, 2), 1); // a character is no motion of another
  EXPECT_EQ(lodSetOwner(project, -1, 2), -1);
  EXPECT_EQ(lodSetFor(project, 0, 2), wuson);
  EXPECT_EQ(lodSetFor(project, 0, 1), bcn);
  EXPECT_EQ(lodSetFor(project, 0), bcn);
  EXPECT_EQ(levelThresholdsFor(project, 0, 2), (std::vector<double>{0.0, 10.0, 20.0, 40.0}));
  EXPECT_EQ(levelThresholdsFor(project, 0), (std::vector<double>{0.0, 2.0, 5.0}));
  EXPECT_TRUE(playsWithSetOf(project, 0, 2));
  EXPECT_TRUE(playsWithSetOf(project, 0, 1));
  EXPECT_FALSE(playsWithSetOf(project, 1, 2));
  EXPECT_TRUE(isMappedOnto(project, 0, 2));
  EXPECT_FALSE(isMappedOnto(project, 2, 0));

  // viewed on Testwuson: removing its level 1 edits its set; BCN's stays; the motion's
  // LeftUpLeg override (level 2) follows to level 1
  Result<LodSetEdit> removed = removeLodLevel(lodSetFor(project, 0, 2), 1);
  ASSERT_TRUE(removed) << removed.message();
  applyLodSetEdit(project, 0, *removed, 2);
  EXPECT_EQ(project.assets[1].lods, bcn);
  ASSERT_TRUE(project.assets[2].lods);
  EXPECT_EQ(project.assets[2].lods->levels.size(), 3u);
  EXPECT_EQ(project.assets[2].lods->levels[1].name, "W2");
  EXPECT_EQ(project.assets[0].joints["LeftUpLeg"].thresholds, (std::vector<std::optional<double>>{std::nullopt, 12.5}));
  EXPECT_EQ(overrideCountFor(project, 2), 1); // the motion's, per level of either set
  EXPECT_FALSE(project.validate());
}

// Guards the one rule for "which character does this asset export as" (issue 26: the CLI, the
// Export dialog and the main window each had their own): a character is itself; a motion is
// the character it is viewed on, else its first mapping's; no asset in view: the first
// mapping's character that plays a clip (defaultPackageAsset()) once imported, -1 before.
TEST(Project, ExportCharacterOfIsTheSetOwner) {
  const Project project = motionOnTwoCharacters();
  EXPECT_EQ(exportCharacterOf(project, 1), 1);
  EXPECT_EQ(exportCharacterOf(project, 2), 2);
  EXPECT_EQ(exportCharacterOf(project, 2, 1), 2); // a character viewed "on" another stays itself
  EXPECT_EQ(exportCharacterOf(project, 0), 1);
  EXPECT_EQ(exportCharacterOf(project, 0, 2), 2);
  EXPECT_EQ(exportCharacterOf(project, 0, 1), 1);
  EXPECT_EQ(exportCharacterOf(project, 0, 0), 1);
  for (int asset = 0; asset < 3; ++asset)
    for (int viewed = -1; viewed < 4; ++viewed)
      EXPECT_EQ(exportCharacterOf(project, asset, viewed), lodSetOwner(project, asset, viewed))
          << asset << " " << viewed;
  // nothing in view: the candidates imported first
  EXPECT_EQ(exportCharacterOf(project, -1), -1);
  EXPECT_EQ(exportCharacterOf(project, 9), -1);
  Asset motion, character, other;
  motion.clips.resize(1);
  character.clips.resize(1);
  other.clips.resize(1);
  const std::vector<const Asset*> imported{&motion, &character, &other};
  EXPECT_EQ(exportCharacterOf(project, -1, -1, imported), 1);
  Project none;
  EXPECT_EQ(exportCharacterOf(none, -1, -1, imported), -1);
}

// Guards `motionlod export --character NAME`: a character by file name, stem, stored path or
// index; an unknown name, a motion, an index out of range and a name of two are refused with
// the project's characters listed.
TEST(Project, ExportCharacterNamed) {
  Project project = motionOnTwoCharacters();
  EXPECT_EQ(exportCharacters(project), (std::vector<int>{1, 2}));
  EXPECT_EQ(exportCharacterList(project), "1 BCN_Epileptic.X, 2 Testwuson.X");
  EXPECT_EQ(*exportCharacterNamed(project, "Testwuson.X"), 2);
  EXPECT_EQ(*exportCharacterNamed(project, "Testwuson"), 2);
  EXPECT_EQ(*exportCharacterNamed(project, "characters/BCN_Epileptic.X"), 1);
  EXPECT_EQ(*exportCharacterNamed(project, "1"), 1);
  const Result<int> unknown = exportCharacterNamed(project, "Wuson.X");
  ASSERT_FALSE(unknown);
  EXPECT_EQ(unknown.message(),
            "the project has no character 'Wuson.X'; the project's characters: 1 BCN_Epileptic.X, 2 Testwuson.X");
  const Result<int> motion = exportCharacterNamed(project, "01_01.bvh");
  ASSERT_FALSE(motion);
  EXPECT_NE(motion.message().find("is a motion (asset 0), exported with BCN_Epileptic.X"), std::string::npos)
      << motion.message();
  EXPECT_NE(exportCharacterNamed(project, "0").message().find("is a motion"), std::string::npos);
  EXPECT_NE(exportCharacterNamed(project, "3").message().find("no asset 3; the project's characters: 1 "),
            std::string::npos);
  project.assets.push_back(ProjectAsset{"elsewhere/Testwuson.X", 0.0, {}});
  const Result<int> two = exportCharacterNamed(project, "Testwuson.X");
  ASSERT_FALSE(two);
  EXPECT_NE(two.message().find("names 2 characters"), std::string::npos) << two.message();
  EXPECT_EQ(*exportCharacterNamed(project, "elsewhere/Testwuson.X"), 3);
}

// Guards JpcSettings from a project: alpha, mode, joints, and the zero-length rule in file units.
TEST(Project, JpcSettingsComeFromTheProject) {
  const Project project = sampleProject();
  const JpcSettings settings = project.jpcSettings(0, 2.0);
  EXPECT_EQ(settings.alpha, 7.5);
  EXPECT_EQ(settings.mode, JpcMode::Optimal);
  EXPECT_EQ(settings.zeroLength, 2e-6);
  EXPECT_EQ(settings.thresholdFor("LeftUpLeg", 2, 42.25), 12.5);
  EXPECT_EQ(settings.thresholdFor("LeftUpLeg", 1, 5.0), 5.0);
  EXPECT_TRUE(settings.lockedFor("Spine"));
  EXPECT_EQ(settings.alphaFor("Head"), 0.1);
  EXPECT_EQ(settings.meshImportanceFor("Head"), 4.0);
  EXPECT_EQ(settings.meshImportanceFor("Spine"), 1.0);
}

// Guards refusal: each bad document gives a message that says what is wrong, never a crash.
TEST(Project, BadDocumentsAreRefusedWithAReason) {
  const std::string good = projectToJson(sampleProject());
  const struct {
    std::string text;
    std::string reason;
  } cases[] = {
      {"", "not valid JSON"},
      {"{\"format\": \"motionlod-project\", \"version\": 1,", "not valid JSON"},
      {"[1, 2]", "not a Motion LOD project"},
      {"{\"format\": \"something-else\", \"version\": 1}", "not a Motion LOD project"},
      {"{\"format\": \"motionlod-project\"}", "no version"},
      {"{\"format\": \"motionlod-project\", \"version\": 5}", "newer Motion LOD Studio"},
      // 2^63 and -2^63 read whole (narrowed to int, 2^63 read as "version 0": issue 29)
      {"{\"format\": \"motionlod-project\", \"version\": 9223372036854775808}",
       "the project is version 9223372036854775808, made by a newer"},
      {"{\"format\": \"motionlod-project\", \"version\": -9223372036854775808}",
       "the project version -9223372036854775808 is not valid"},
      {"{\"format\": \"motionlod-project\", \"version\": 4294967297}", "the project is version 4294967297"},
      {"{\"format\": \"motionlod-project\", \"version\": 2, \"alpha\": 5, \"mode\": \"greedy\", \"assets\": []}",
       "has no \"lods\""},
      {"{\"format\": \"motionlod-project\", \"version\": 1}", "has no \"alpha\""},
      {"{\"format\": \"motionlod-project\", \"version\": 1, \"alpha\": \"5\", \"mode\": \"greedy\", \"levels\": [], "
       "\"assets\": []}",
       "alpha is not a number"},
      {"{\"format\": \"motionlod-project\", \"version\": 1, \"alpha\": 5, \"mode\": \"best\", \"levels\": [], "
       "\"assets\": []}",
       "neither greedy nor optimal"},
      {"{\"format\": \"motionlod-project\", \"version\": 2, \"alpha\": 5, \"mode\": \"greedy\", \"lods\": "
       "{\"projection\": {\"vertical_fov_degrees\": 60, \"viewport_height_pixels\": 1080}, \"bounding_radius_cm\": 0, "
       "\"levels\": []}, \"assets\": []}",
       "no level"},
      {"{\"format\": \"motionlod-project\", \"version\": 1, \"alpha\": 5, \"mode\": \"greedy\", \"levels\": "
       "[{\"threshold\": -1}], \"assets\": []}",
       "level 1 threshold"},
      {"{\"format\": \"motionlod-project\", \"version\": 1, \"alpha\": 5, \"mode\": \"greedy\", \"levels\": "
       "[{\"threshold\": 5}], \"assets\": [{\"path\": \"a.bvh\", \"unit_scale\": 1, \"joints\": {\"J\": {\"alpha\": "
       "null, \"thresholds\": [-3], \"locked\": false}}}]}",
       "joint J"},
      {"{\"format\": \"motionlod-project\", \"version\": 1, \"alpha\": 5, \"mode\": \"greedy\", \"levels\": "
       "[{\"threshold\": 5}], \"assets\": [{\"unit_scale\": 1, \"joints\": {}}]}",
       "asset 0 has no \"path\""},
  };
  for (const auto& c : cases) {
    const Result<Project> read = projectFromJson(c.text);
    ASSERT_FALSE(read) << c.text;
    EXPECT_NE(read.message().find(c.reason), std::string::npos) << read.message();
  }
  EXPECT_TRUE(projectFromJson(good));
  // A version-2 level 0 that is not the original, a duplicate name, a joint overriding level 0.
  Project bad = sampleProject();
  bad.lods.levels[0].motionThreshold = 1.0;
  EXPECT_FALSE(projectFromJson(projectToJson(bad)));
  bad = sampleProject();
  bad.lods.levels[3].name = "Near";
  EXPECT_NE(projectFromJson(projectToJson(bad)).message().find("used twice"), std::string::npos);
  bad = sampleProject();
  bad.assets[0].joints["Head"].thresholds = {1.0};
  EXPECT_NE(projectFromJson(projectToJson(bad)).message().find("level 0 is the original"), std::string::npos);
}

// Guards the file's-own-unit rule (issue 16: a project with unit_scale 0 was accepted): an
// asset at its file's own unit is written without "unit_scale" and reads back at 0; a
// written unit must be positive, so 0 and less are refused with the reason; version 2
// (0.1.0), which wrote 0 for the file's own unit, reads as before.
TEST(Project, UnitScaleIsPositiveOrAbsent) {
  const Project project = sampleProject(); // asset 1 at its file's own unit
  const nlohmann::json written = nlohmann::json::parse(projectToJson(project));
  EXPECT_EQ(written["version"], kProjectVersion);
  EXPECT_EQ(written["assets"][0]["unit_scale"], 2.54 / 0.45);
  EXPECT_FALSE(written["assets"][1].contains("unit_scale"));
  const Result<Project> read = projectFromJson(written.dump());
  ASSERT_TRUE(read) << read.message();
  EXPECT_EQ(read->assets[1].unitScale, 0.0);
  for (const nlohmann::json& bad : {nlohmann::json(0), nlohmann::json(0.0), nlohmann::json(-2.5)}) {
    nlohmann::json doc = written;
    doc["assets"][1]["unit_scale"] = bad;
    const Result<Project> refused = projectFromJson(doc.dump());
    ASSERT_FALSE(refused) << bad;
    EXPECT_EQ(
        refused.message().rfind("asset 1: unit_scale must be positive (cm per file unit); it is " + bad.dump(), 0), 0u)
        << refused.message();
  }
  nlohmann::json version2 = written;
  version2["version"] = 2;
  version2["assets"][1]["unit_scale"] = 0.0;
  const Result<Project> old = projectFromJson(version2.dump());
  ASSERT_TRUE(old) << old.message();
  EXPECT_EQ(*old, *read);
  version2["assets"][1].erase("unit_scale"); // version 2 always wrote it
  EXPECT_NE(projectFromJson(version2.dump()).message().find("asset 1 has no \"unit_scale\""), std::string::npos);
}

// Guards that saving never throws for a name that is not UTF-8 (issue 16: nlohmann's dump()
// threw type_error 316 for a Latin-1 byte): such bytes are written as U+FFFD.
TEST(Project, Latin1NamesAreWrittenWithReplacementCharacters) {
  Project project = sampleProject();
  project.assets[0].path = "clips/d\xE9mo.bvh";
  project.assets[0].joints["Cou\xE9"].locked = true;
  std::string text;
  ASSERT_NO_THROW(text = projectToJson(project));
  const Result<Project> read = projectFromJson(text);
  ASSERT_TRUE(read) << read.message();
  EXPECT_EQ(read->assets[0].path, "clips/d\xEF\xBF\xBDmo.bvh");
  EXPECT_TRUE(read->assets[0].joints.at("Cou\xEF\xBF\xBD").locked);
}

// Guards version 1 (a threshold per level, no original): it reads as a LodSet with the
// original in front, every per-joint override and the current level one level later.
TEST(Project, VersionOneGetsTheOriginalLevelInFront) {
  const Result<Project> read = projectFromJson(
      "{\"format\": \"motionlod-project\", \"version\": 1, \"alpha\": 5, \"mode\": \"greedy\", \"levels\": "
      "[{\"threshold\": 5}, {\"threshold\": 50}], \"assets\": [{\"path\": \"a.bvh\", \"unit_scale\": 1, \"joints\": "
      "{\"J\": {\"alpha\": null, \"thresholds\": [null, 20], \"locked\": false}, \"K\": {\"alpha\": 1, "
      "\"thresholds\": [], \"locked\": true}}}], \"current\": {\"asset\": 0, \"clip\": 0, \"level\": 1, \"joint\": "
      "\"J\"}}");
  ASSERT_TRUE(read) << read.message();
  ASSERT_EQ(read->levelCount(), 3);
  EXPECT_EQ(read->levelThresholds(), (std::vector<double>{0.0, 5.0, 50.0}));
  EXPECT_EQ(read->lods.levels[1].name, "LOD1");
  EXPECT_EQ(read->lods.levels[2].meshRatio, 1.0);
  EXPECT_EQ(read->assets[0].joints.at("J").thresholds,
            (std::vector<std::optional<double>>{std::nullopt, std::nullopt, 20.0}));
  EXPECT_TRUE(read->assets[0].joints.at("K").thresholds.empty());
  EXPECT_EQ(read->assets[0].joints.at("K").meshImportance, 1.0) << "absent before issue 14: 1";
  EXPECT_EQ(read->view.level, 2);
  // Saved again, it is the current version and reads back equal.
  const std::string saved = projectToJson(*read);
  EXPECT_NE(saved.find("\"version\": " + std::to_string(kProjectVersion)), std::string::npos);
  EXPECT_TRUE(*projectFromJson(saved) == *read);
}

// Guards the view of a hand-edited or damaged file: every "current" field out of range reads as
// the nearest valid view (a level of the set, an asset of the project, a clip >= 0), not as a
// refusal and not as an index that crashes the editor (2^31 read as -2^31 did).
TEST(Project, CurrentFieldsOutOfRangeAreBroughtInRange) {
  struct Case {
    const char* current;
    ProjectView expected;
  };
  for (const Case& c : {Case{R"({"asset": 2147483648, "clip": 2147483648, "level": 2147483648, "joint": "x"})",
                             {0, 1073741823, 3, "x"}},
                        Case{R"({"asset": -5, "clip": -1, "level": -1, "joint": ""})", {0, 0, 0, ""}},
                        Case{R"({"asset": -1, "clip": 7, "level": 4, "joint": ""})", {-1, 7, 3, ""}},
                        Case{R"({"asset": 18446744073709551615, "clip": -9223372036854775808, "level": 2,)"
                             R"( "joint": ""})",
                             {0, 0, 2, ""}}}) {
    SCOPED_TRACE(c.current);
    std::string text = projectToJson(sampleProject());
    const std::size_t at = text.find("\"current\": ");
    ASSERT_NE(at, std::string::npos);
    text = text.substr(0, at) + "\"current\": " + c.current + text.substr(text.find('}', at) + 1);
    const Result<Project> read = projectFromJson(text);
    ASSERT_TRUE(read) << read.message();
    EXPECT_EQ(read->view.asset, c.expected.asset);
    EXPECT_EQ(read->view.clip, c.expected.clip);
    EXPECT_EQ(read->view.level, c.expected.level);
    EXPECT_EQ(read->view.joint, c.expected.joint);
  }
  // A value that is no integer is still refused: the file is not what it claims.
  std::string text = projectToJson(sampleProject());
  const std::size_t at = text.find("\"level\": 2");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 10, "\"level\": \"2\"");
  EXPECT_FALSE(projectFromJson(text));
}

// Guards a fuzz finding (fuzz.project, crash-72f6eeaf): a project of one level without a
// "current" object kept the default view's level 1, which it does not have; written and read
// back it came back at level 0, so reading was not stable. The default view is clamped too.
TEST(Project, DefaultViewIsClampedWithoutCurrent) {
  Project project = sampleProject();
  project.lods.levels.resize(1);
  for (ProjectAsset& asset : project.assets)
    for (auto& [name, joint] : asset.joints)
      joint.thresholds.resize(std::min<std::size_t>(joint.thresholds.size(), 1));
  std::string text = projectToJson(project);
  const std::size_t at = text.find("\"current\": ");
  ASSERT_NE(at, std::string::npos);
  text = text.substr(0, at) + "\"no_current\": " + text.substr(at + 11);
  const Result<Project> read = projectFromJson(text);
  ASSERT_TRUE(read) << read.message();
  EXPECT_EQ(read->view.level, 0);
  const Result<Project> again = projectFromJson(projectToJson(*read));
  ASSERT_TRUE(again) << again.message();
  EXPECT_TRUE(*again == *read);
}

// Guards mappings: they follow their assets when one is removed or inserted, and a mapping
// to an asset that is not there is refused.
TEST(Project, MappingsFollowTheirAssets) {
  Project project = sampleProject();
  insertProjectAsset(project, 0, ProjectAsset{"first.bvh", 0.0, {}});
  ASSERT_EQ(project.mappings.size(), 1u);
  EXPECT_EQ(project.mappings[0].motion, 1);
  EXPECT_EQ(project.mappings[0].character, 2);
  eraseProjectAsset(project, 0);
  EXPECT_TRUE(project == sampleProject());
  eraseProjectAsset(project, 1); // the character goes, and its mapping with it
  EXPECT_TRUE(project.mappings.empty());
  Project bad = sampleProject();
  bad.mappings[0].character = 5;
  const Result<Project> read = projectFromJson(projectToJson(bad));
  ASSERT_FALSE(read);
  EXPECT_NE(read.message().find("mapping 0"), std::string::npos) << read.message();
}

// Guards the load work: a motion plays on a character through one table, so a project that
// names the pair twice is refused at once (2,000 copies kept the studio retargeting the clip
// 2,000 times, past a minute, issue 29's studio round), and the same motion on two
// characters is fine.
TEST(Project, AMotionAssignedTwiceToOneCharacterIsRefused) {
  Project twice = sampleProject();
  twice.mappings.push_back(twice.mappings[0]);
  const Result<Project> read = projectFromJson(projectToJson(twice));
  ASSERT_FALSE(read);
  EXPECT_NE(read.message().find("mapping 1 assigns asset 0 to asset 1 again (mapping 0 does)"), std::string::npos)
      << read.message();
  Project two = sampleProject();
  two.assets.push_back(ProjectAsset{"characters/Testwuson.X", 0.0, {}});
  two.mappings.push_back(two.mappings[0]);
  two.mappings[1].character = 2;
  EXPECT_TRUE(projectFromJson(projectToJson(two))) << "one motion on two characters";
}

// Guards paths: assets inside the project's folder are stored relative to it and resolve
// back; one outside is stored absolute, so that the project reopens without asking
// (checkAssetPaths() refuses relative paths that leave the folder).
TEST(Project, AssetPathsAreRelativeToTheProject) {
  EXPECT_EQ(storedAssetPath("/data/projects/crowd.mlod", "/data/projects/clips/a.bvh"), "clips/a.bvh");
  EXPECT_EQ(storedAssetPath("/data/projects/crowd.mlod", "/data/mocap/b.bvh"), "/data/mocap/b.bvh");
  EXPECT_EQ(resolveAssetPath("/data/projects/crowd.mlod", "../mocap/b.bvh"), std::filesystem::path("/data/mocap/b.bvh"));
  EXPECT_EQ(resolveAssetPath("/data/projects/crowd.mlod", "/abs/c.bvh"), std::filesystem::path("/abs/c.bvh"));
}

// Guards level edits: per-joint overrides follow their level when levels move or go.
TEST(Project, RemapLevelsCarriesOverrides) {
  Project project = sampleProject(); // LeftUpLeg overrides level 2 only
  const std::vector<LodLevel> levels = project.lods.levels;
  remapLevels(project, {0, 2, 1, 3}, {levels[0], levels[2], levels[1], levels[3]});
  const auto& moved = project.assets[0].joints.at("LeftUpLeg").thresholds;
  ASSERT_EQ(moved.size(), 2u);
  EXPECT_EQ(*moved[1], 12.5);
  remapLevels(project, {0, 2, 3, -1}, {levels[0], levels[1], levels[3], level("Farther", 600.0)}); // remove level 1, add one
  EXPECT_TRUE(project.assets[0].joints.at("LeftUpLeg").thresholds.empty());
  EXPECT_EQ(project.levelThresholds(), (std::vector<double>{0.0, 5.0, 300.0, 600.0}));
  EXPECT_EQ(project.lods.levels[3].name, "Farther");
}

// Guards loadProjectFile on files that are not there or empty.
TEST(Project, FilesThatCannotBeReadAreRefused) {
  EXPECT_FALSE(loadProjectFile("/no/such/project.mlod"));
  const std::filesystem::path empty = std::filesystem::temp_directory_path() / "mlod_empty_project.mlod";
  std::ofstream(empty).close();
  const Result<Project> read = loadProjectFile(empty);
  ASSERT_FALSE(read);
  EXPECT_EQ(read.message(), "the file is empty");
  std::filesystem::remove(empty);
}

// Guards the reader against files that never end or block: a FIFO named .mlod blocked it
// forever, a link to /dev/zero read until memory ran out. Both are refused from their type.
TEST(Project, SpecialFilesAreRefusedAtOnce) {
  namespace fs = std::filesystem;
  const fs::path fifo = fs::temp_directory_path() / ("mlod_fifo_" + std::to_string(::getpid()) + ".mlod");
  const fs::path zero = fs::temp_directory_path() / ("mlod_zero_" + std::to_string(::getpid()) + ".mlod");
  fs::remove(fifo);
  fs::remove(zero);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  fs::create_symlink("/dev/zero", zero);
  const Result<Project> fromFifo = loadProjectFile(fifo);
  const Result<Project> fromZero = loadProjectFile(zero);
  fs::remove(fifo);
  fs::remove(zero);
  ASSERT_FALSE(fromFifo);
  EXPECT_EQ(fromFifo.message(), "it is a FIFO (named pipe), not a regular file");
  ASSERT_FALSE(fromZero);
  EXPECT_EQ(fromZero.message(), "it is a device, not a regular file");
}

// Guards the level cap: a project of 70,000 levels ran for minutes growing memory; it is
// refused from the size of its level list, before a level is read.
TEST(Project, LevelsAreCappedOnLoad) {
  Project project;
  project.assets.push_back({"a.bvh", 1.0, {}});
  std::string text = projectToJson(project);
  ASSERT_TRUE(projectFromJson(text));
  while (project.lods.levels.size() < std::size_t(kMaxProjectLevels))
    project.lods.levels.push_back({.name = "L" + std::to_string(project.lods.levels.size()),
                                   .motionThreshold = 1000.0 + double(project.lods.levels.size())});
  EXPECT_TRUE(projectFromJson(projectToJson(project))) << "exactly the cap is fine";
  project.lods.levels.push_back({.name = "one more", .motionThreshold = 1e6});
  const Result<Project> over = projectFromJson(projectToJson(project));
  ASSERT_FALSE(over);
  EXPECT_EQ(over.message(), "the project has 33 LOD levels; a project may have at most 32");
  EXPECT_TRUE(project.validate()) << "validate() states the cap too";
}

// A project folder of its own for one test, holding the sample clip at clips/a.bvh.
std::filesystem::path projectFolderWithClip(const std::string& name) {
  namespace fs = std::filesystem;
  const fs::path folder = fs::temp_directory_path() / ("mlod_paths_" + std::to_string(::getpid())) / name;
  fs::remove_all(folder);
  fs::create_directories(folder / "clips");
  fs::copy_file(MLOD_SAMPLE_BVH, folder / "clips" / "a.bvh");
  return folder;
}

Result<Project> loadWithAsset(const std::filesystem::path& folder, const std::string& assetPath,
                              const ProjectFileOptions& options = {}) {
  Project project;
  project.assets.push_back({assetPath, 0.0, {}});
  const std::filesystem::path file = folder / "p.mlod";
  std::ofstream(file) << projectToJson(project);
  return loadProjectFile(file, options);
}

// Guards issue 29's `../../../../../../etc/passwd`: a relative asset path that leaves the
// project's folder is refused, naming the asset and the path, unless allowed; relative paths
// inside and absolute paths anywhere are followed.
TEST(Project, RelativeAssetPathsStayInTheProjectsFolder) {
  const std::filesystem::path folder = projectFolderWithClip("climb");
  const Result<Project> climbing = loadWithAsset(folder, "../../../../../../etc/passwd");
  ASSERT_FALSE(climbing);
  EXPECT_NE(climbing.message().find("asset 0 ('../../../../../../etc/passwd') leads outside the project's folder"),
            std::string::npos)
      << climbing.message();
  EXPECT_NE(climbing.message().find("/etc/passwd)"), std::string::npos) << climbing.message();
  EXPECT_FALSE(loadWithAsset(folder, "clips/../../x.bvh")) << "inside, then out";
  EXPECT_TRUE(loadWithAsset(folder, "../../../../../../etc/passwd", {.allowOutsideAssets = true}));
  EXPECT_TRUE(loadWithAsset(folder, "clips/a.bvh"));
  EXPECT_TRUE(loadWithAsset(folder, "./clips/../clips/a.bvh")) << "climbs, but stays inside";
  EXPECT_TRUE(loadWithAsset(folder, "clips/not_yet_there.bvh")) << "missing is the import's to report";
  EXPECT_TRUE(loadWithAsset(folder, "/etc/passwd")) << "absolute: the author's explicit choice";
  EXPECT_TRUE(loadWithAsset(folder, (folder / "clips" / "a.bvh").string()));
}

// Guards links: a symlink inside the folder that leads out of it is outside (a relative path
// is checked once links are followed); one that stays inside is fine.
TEST(Project, SymlinksOutOfTheFolderAreOutside) {
  namespace fs = std::filesystem;
  const fs::path folder = projectFolderWithClip("links");
  fs::create_directory_symlink("/etc", folder / "system");
  fs::create_symlink(folder / "clips" / "a.bvh", folder / "inside.bvh");
  const Result<Project> viaLink = loadWithAsset(folder, "system/passwd");
  ASSERT_FALSE(viaLink);
  EXPECT_NE(viaLink.message().find("'system/passwd'"), std::string::npos) << viaLink.message();
  EXPECT_TRUE(loadWithAsset(folder, "inside.bvh"));
  // what the studio saves: inside relative, outside (even through a link) absolute, so it reopens
  EXPECT_EQ(storedAssetPath(folder / "p.mlod", folder / "clips" / "a.bvh"), "clips/a.bvh");
  EXPECT_EQ(storedAssetPath(folder / "p.mlod", folder / "system" / "passwd"), (folder / "system" / "passwd").string());
  EXPECT_EQ(storedAssetPath(folder / "p.mlod", "/etc/passwd"), "/etc/passwd");
}

// Guards names where they enter: a 100,000-character level name made the studio lay it out
// for half a minute. Level names, joint names and asset paths past their caps are refused
// with the field named (never clipped: a clipped joint name would tune another joint).
TEST(Project, OverlongNamesAreRefused) {
  Project project;
  project.assets.push_back({"a.bvh", 0.0, {}});
  project.lods.levels[1].name = std::string(kMaxLevelNameBytes, 'n');
  ASSERT_TRUE(projectFromJson(projectToJson(project))) << "exactly the cap is fine";
  project.lods.levels[1].name = std::string(100000, 'n');
  const Result<Project> level = projectFromJson(projectToJson(project));
  ASSERT_FALSE(level);
  EXPECT_EQ(level.message(), "LOD set: level 1: the name is 100000 bytes long; a level name has at most 256");

  Project joints;
  joints.assets.push_back({"a.bvh", 0.0, {}});
  joints.assets[0].joints[std::string(kMaxJointNameBytes + 1, 'j')].locked = true;
  const Result<Project> joint = projectFromJson(projectToJson(joints));
  ASSERT_FALSE(joint);
  EXPECT_EQ(joint.message(), "asset 0: a joint name is 1025 bytes long; a joint name has at most 1024");

  Project paths;
  paths.assets.push_back({std::string(kMaxAssetPathBytes + 1, 'p'), 0.0, {}});
  const Result<Project> path = projectFromJson(projectToJson(paths));
  ASSERT_FALSE(path);
  EXPECT_EQ(path.message(), "asset 0: the path is 4097 bytes long; a path has at most 4096");

  // the view's joint names no figure: one that long names no joint, and the view forgets it
  Project view;
  view.view.joint = std::string(kMaxJointNameBytes + 1, 'v');
  const Result<Project> read = projectFromJson(projectToJson(view));
  ASSERT_TRUE(read) << read.message();
  EXPECT_TRUE(read->view.joint.empty());
}

} // namespace
} // namespace mlod
