// Synthetic BVH files with hand-computed answers: channel orders, root translation,
// unit scale, frame rate, End Sites, one-frame clips and zero-length bones.

#include "io/importer.h"
#include "test_files.h"

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include <cmath>

namespace mlod {
namespace {

const char* kRoot6 = "Xposition Yposition Zposition Zrotation Yrotation Xrotation";

glm::quat axis(float degrees, glm::vec3 direction) { return glm::angleAxis(glm::radians(degrees), direction); }
const glm::vec3 X(1, 0, 0), Y(0, 1, 0), Z(0, 0, 1);

// Rotations compare as rotations: q and -q are the same.
void expectSameRotation(const glm::quat& actual, const glm::quat& expected) {
  EXPECT_NEAR(std::abs(glm::dot(actual, expected)), 1.0f, 1e-6f)
      << "actual (" << actual.w << ", " << actual.x << ", " << actual.y << ", " << actual.z << ") expected ("
      << expected.w << ", " << expected.x << ", " << expected.y << ", " << expected.z << ")";
}

Asset importText(const std::string& name, const std::string& text, ImportOptions options = {}) {
  Result<Asset> asset = importAsset(test::writeTemp(name, text), options);
  EXPECT_TRUE(asset.ok()) << (asset.ok() ? "" : asset.message());
  return asset.ok() ? std::move(asset).value() : Asset{};
}

struct OrderCase {
  const char* channels;
  glm::quat expected; // for the values 30 20 10 in the listed order
};

class BvhChannelOrder : public ::testing::TestWithParam<OrderCase> {};

// Guards docs/architecture.md section 4: Euler channels compose in the order listed, intrinsic, so
// "Zrotation Yrotation Xrotation" with values (30, 20, 10) is qz(30) * qy(20) * qx(10).
TEST_P(BvhChannelOrder, ComposesInListedOrder) {
  const OrderCase& c = GetParam();
  const Asset asset = importText("order.bvh", test::makeBvh(kRoot6, c.channels, 2, "0.0333333",
                                                            "0 0 0 0 0 0 30 20 10\n0 0 0 0 0 0 0 0 0\n"));
  ASSERT_EQ(asset.clips.size(), 1u);
  const int chest = asset.skeleton.find("Chest");
  ASSERT_GE(chest, 0);
  expectSameRotation(asset.clips[0].rotation(chest, 0), c.expected);
  expectSameRotation(asset.clips[0].rotation(chest, 1), glm::quat(1, 0, 0, 0));
}

INSTANTIATE_TEST_SUITE_P(
    Orders, BvhChannelOrder,
    ::testing::Values(OrderCase{"Zrotation Yrotation Xrotation", axis(30, Z) * axis(20, Y) * axis(10, X)},
                      OrderCase{"Xrotation Yrotation Zrotation", axis(30, X) * axis(20, Y) * axis(10, Z)},
                      OrderCase{"Yrotation Xrotation Zrotation", axis(30, Y) * axis(20, X) * axis(10, Z)},
                      OrderCase{"Zrotation Xrotation Yrotation", axis(30, Z) * axis(20, X) * axis(10, Y)}));

// Guards the root translation channel and the unit scale applied to every length.
TEST(BvhImport, RootTranslationAndUnitScale) {
  ImportOptions options;
  options.unitScale = 2.0;
  const Asset asset = importText("translate.bvh",
                                 test::makeBvh(kRoot6, "Zrotation Yrotation Xrotation", 2, "0.0333333",
                                               "1 2 3 0 0 0 0 0 0\n-4 5.5 6 90 0 0 0 0 0\n"),
                                 options);
  const Clip& clip = asset.clips.at(0);
  EXPECT_EQ(asset.unitScale, 2.0);
  EXPECT_EQ(asset.unitSource, "option");
  EXPECT_EQ(clip.translation(0, 0), glm::vec3(2, 4, 6));
  EXPECT_EQ(clip.translation(0, 1), glm::vec3(-8, 11, 12));
  expectSameRotation(clip.rotation(0, 1), axis(90, Z));
  EXPECT_TRUE(clip.hasTranslation[0]);
  const int chest = asset.skeleton.find("Chest");
  EXPECT_FALSE(clip.hasTranslation[static_cast<std::size_t>(chest)]);
  EXPECT_EQ(asset.skeleton.joints[static_cast<std::size_t>(chest)].rest.translation, glm::vec3(0, 20, 0));
  EXPECT_EQ(clip.translation(chest, 1), glm::vec3(0, 20, 0));
}

// Guards End Sites as leaf joints without a rotation channel, and the frame rate taken
// from "Frame Time" (0.0333333 s is 30 fps, not 30.0000003).
TEST(BvhImport, EndSitesFramesAndRate) {
  ImportOptions options; // a stated unit: no guess, so no warning that the guess failed
  options.unitScale = 1.0;
  const Asset asset = importText("endsite.bvh",
                                 test::makeBvh(kRoot6, "Zrotation Yrotation Xrotation", 3, "0.0333333",
                                               "0 0 0 0 0 0 0 0 0\n0 0 0 0 0 0 1 0 0\n"
                                               "0 0 0 0 0 0 2 0 0\n"),
                                 options);
  ASSERT_EQ(asset.skeleton.jointCount(), 3);
  EXPECT_EQ(asset.skeleton.joints[2].name, "EndSite_Chest");
  EXPECT_EQ(asset.skeleton.joints[2].parent, 1);
  EXPECT_EQ(asset.skeleton.joints[2].rest.translation, glm::vec3(0, 5, 0));
  const Clip& clip = asset.clips.at(0);
  EXPECT_EQ(clip.frameCount, 3);
  EXPECT_EQ(clip.fps, 30.0);
  EXPECT_EQ(clip.hasRotation, (std::vector<std::uint8_t>{1, 1, 0}));
  EXPECT_EQ(clip.rotationChannelCount(), 2);
  EXPECT_TRUE(asset.meshes.empty()); // Assimp's generated BVH skeleton mesh is left out
  EXPECT_TRUE(asset.warnings.empty());
}

// Guards a one-frame clip, a valid edge case.
TEST(BvhImport, OneFrameClip) {
  const Asset asset = importText("one.bvh", test::makeBvh(kRoot6, "Zrotation Yrotation Xrotation", 1, "0.01",
                                                          "0 0 0 0 0 0 5 6 7\n"));
  ASSERT_EQ(asset.clips.size(), 1u);
  EXPECT_EQ(asset.clips[0].frameCount, 1);
  EXPECT_EQ(asset.clips[0].fps, 100.0);
  EXPECT_EQ(asset.clips[0].durationSeconds(), 0.0);
}

// Guards zero-length bones (the CMU hips have zero offsets): valid, kept as joints.
TEST(BvhImport, ZeroLengthBones) {
  const std::string text =
      "HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 6 " + std::string(kRoot6) +
      "\n JOINT LHipJoint\n {\n  OFFSET 0 0 0\n  CHANNELS 3 Zrotation Yrotation Xrotation\n"
      "  JOINT LeftUpLeg\n  {\n   OFFSET 1 -2 0\n   CHANNELS 3 Zrotation Yrotation Xrotation\n"
      "   End Site\n   {\n    OFFSET 0 -7 0\n   }\n  }\n }\n}\nMOTION\nFrames: 2\nFrame Time: 0.0083333\n"
      "0 0 0 0 0 0 0 0 0 0 0 0\n0 0 0 0 0 0 10 0 0 0 0 0\n";
  const Asset asset = importText("zero.bvh", text);
  ASSERT_EQ(asset.skeleton.jointCount(), 4);
  EXPECT_EQ(asset.skeleton.joints[1].rest.translation, glm::vec3(0.0f));
  EXPECT_EQ(asset.clips.at(0).fps, 120.0);
}

// Guards the unit guess (docs/architecture.md section 3): the preset that puts the height nearest
// 170 cm, only within 100-250 cm.
TEST(UnitScale, GuessPicksThePresetNearestAHumanHeight) {
  const auto guess = [](double height) {
    const UnitPreset* preset = guessUnitPreset(height);
    return preset ? std::string(preset->name) : std::string("none");
  };
  EXPECT_EQ(guess(1.8), "m");     // 180 cm
  EXPECT_EQ(guess(170.0), "cm");  // the file is in cm already
  EXPECT_EQ(guess(1750.0), "mm"); // 175 cm
  EXPECT_EQ(guess(70.0), "inch"); // 177.8 cm (cmu would make 395 cm)
  EXPECT_EQ(guess(30.0), "cmu");  // 169.3 cm (inch would make 76 cm)
  EXPECT_EQ(guess(15.0), "none"); // 38 cm in inches, 85 cm in CMU units: no human
  EXPECT_EQ(guess(5000.0), "none");
  EXPECT_EQ(guess(0.0), "none");
  EXPECT_EQ(guess(std::nan("")), "none");
}

// Guards the guess on import: a file without a unit is scaled to the guessed preset and says
// so; one that no preset makes human stays at 1 cm per unit with a warning; an option wins.
TEST(BvhImport, UnitIsGuessedFromTheStandingHeight) {
  // Hips at 0, chest 10 above, head end 20 above the chest: 30 units tall, a CMU-sized figure.
  const std::string text = "HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 6 " + std::string(kRoot6) +
                           "\n JOINT Chest\n {\n  OFFSET 0 10 0\n  CHANNELS 3 Zrotation Yrotation Xrotation\n"
                           "  End Site\n  {\n   OFFSET 0 20 0\n  }\n }\n}\nMOTION\nFrames: 1\nFrame Time: 0.0083333\n"
                           "1 2 3 0 0 0 0 0 0\n";
  const Asset guessed = importText("cmu_sized.bvh", text);
  EXPECT_EQ(guessed.unitSource, "guessed");
  EXPECT_NEAR(guessed.unitScale, 2.54 / 0.45, 1e-9);
  EXPECT_NEAR(standingHeightCm(guessed), 30.0 * 2.54 / 0.45, 1e-3);
  EXPECT_NEAR(guessed.clips.at(0).translation(0, 0).z, 3.0 * 2.54 / 0.45, 1e-4); // every length follows
  EXPECT_TRUE(guessed.warnings.empty());

  const Asset small = importText(
      "small.bvh", test::makeBvh(kRoot6, "Zrotation Yrotation Xrotation", 1, "0.0333333", "0 0 0 0 0 0 0 0 0\n"));
  EXPECT_EQ(small.unitSource, "guessed");
  EXPECT_EQ(small.unitScale, 1.0);
  ASSERT_EQ(small.warnings.size(), 1u);
  EXPECT_NE(small.warnings[0].find("states no unit"), std::string::npos);

  ImportOptions options;
  options.unitScale = 1.0;
  const Asset chosen = importText("cmu_sized.bvh", text, options);
  EXPECT_EQ(chosen.unitSource, "option");
  EXPECT_EQ(chosen.unitScale, 1.0);
  EXPECT_NEAR(standingHeightCm(chosen), 30.0, 1e-4);
}

// Guards the unit presets users pick for files without a unit.
TEST(UnitScale, PresetsAndNumbers) {
  EXPECT_NEAR(parseUnitScale("cmu").value(), 5.6444, 1e-4);
  EXPECT_EQ(parseUnitScale("m").value(), 100.0);
  EXPECT_EQ(parseUnitScale("2.5").value(), 2.5);
  EXPECT_FALSE(parseUnitScale("-1"));
  EXPECT_FALSE(parseUnitScale("0"));
  EXPECT_FALSE(parseUnitScale("nan"));
  EXPECT_FALSE(parseUnitScale("3cm"));
  EXPECT_FALSE(parseUnitScale(""));
  EXPECT_GE(unitPresets().size(), 5u);
}

} // namespace
} // namespace mlod
