#include "core/mapping/joint_names.h"

#include <algorithm>
#include <cctype>
#include <initializer_list>

namespace mlod {

namespace {

bool isUpper(char c) { return std::isupper(static_cast<unsigned char>(c)) != 0; }
bool isLower(char c) { return std::islower(static_cast<unsigned char>(c)) != 0; }
bool isDigit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }
bool isAlnum(char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0; }

bool contains(const std::vector<std::string>& words, std::string_view word) {
  return std::find(words.begin(), words.end(), word) != words.end();
}

bool containsAny(const std::vector<std::string>& words, std::initializer_list<std::string_view> any) {
  return std::any_of(any.begin(), any.end(), [&](std::string_view w) { return contains(words, w); });
}

// Names that only say "this is a bone" (B_, Bip01, DEF-, jnt ...).
bool noise(const std::string& word) {
  static const char* const kNoise[] = {"b", "bip", "bn", "def", "mch", "org", "jnt", "bone", "ctrl", "drv", "sk", "mixamorig"};
  return std::any_of(std::begin(kNoise), std::end(kNoise), [&](const char* n) { return word == n; });
}

} // namespace

bool JointRole::chain() const {
  static const char* const kChains[] = {"spine", "neck", "thumb", "index", "middle", "ring", "pinky", "finger", "tail"};
  return std::any_of(std::begin(kChains), std::end(kChains), [&](const char* c) { return part == c; });
}

std::vector<std::string> nameTokens(std::string_view name) {
  const std::size_t cut = name.find_last_of(":|");
  if (cut != std::string_view::npos)
    name.remove_prefix(cut + 1); // namespaces and node paths
  std::vector<std::string> out;
  std::string word;
  const auto flush = [&] {
    if (!word.empty())
      out.push_back(word);
    word.clear();
  };
  for (std::size_t i = 0; i < name.size(); ++i) {
    const char c = name[i];
    if (!isAlnum(c)) {
      flush();
      continue;
    }
    if (!word.empty()) {
      const char p = name[i - 1];
      const bool caseStep = isUpper(c) && (isLower(p) || isDigit(p));
      // "LThumb": an upper-case run ends before the capital that starts a lower-case word
      const bool acronymEnd = isUpper(c) && isUpper(p) && i + 1 < name.size() && isLower(name[i + 1]);
      const bool digitStep = isDigit(c) != isDigit(p);
      if (caseStep || acronymEnd || digitStep)
        flush();
    }
    word += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  flush();
  return out;
}

JointRole jointRole(std::string_view name) {
  JointRole role;
  std::vector<std::string> words;
  const std::vector<std::string> tokens = nameTokens(name);
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    const std::string& t = tokens[i];
    if (t == "bip" && i + 1 < tokens.size() && isDigit(tokens[i + 1][0])) {
      ++i; // Bip01: the rig's name, not a number of this joint
      continue;
    }
    if (noise(t))
      continue;
    if (t == "left" || t == "l" || t == "lft") {
      role.side = BodySide::Left;
      continue;
    }
    if (t == "right" || t == "r" || t == "rt" || t == "rgt") {
      role.side = BodySide::Right;
      continue;
    }
    if (isDigit(t[0])) {
      if (role.number < 0)
        role.number = std::stoi(t.size() > 6 ? t.substr(t.size() - 6) : t);
      continue;
    }
    if (t == "end" || t == "site" || t == "endsite" || t == "nub" || t == "tip") {
      role.end = true;
      continue;
    }
    words.push_back(t);
  }
  const auto has = [&](std::string_view w) { return contains(words, w); };
  const auto any = [&](std::initializer_list<std::string_view> list) { return containsAny(words, list); };
  const bool lower = any({"lower", "low", "lo"});
  const bool upper = any({"upper", "up"});

  std::string part;
  if (has("hip") && has("joint"))
    part = "hip_side"; // CMU/MotionBuilder LHipJoint: the pelvis side, not the thigh
  else if (any({"thigh", "upleg", "upperleg"}) || (upper && has("leg")))
    part = "thigh";
  else if (has("hip") && role.side != BodySide::Center)
    part = "thigh"; // B_Hip_Left: the hip joint turns the thigh
  else if (any({"calf", "knee", "shin", "lowerleg"}) || has("leg"))
    part = "shin";
  else if (any({"foot", "ankle"}))
    part = "foot";
  else if (any({"toe", "toes", "toebase", "ball"}))
    part = "toe";
  else if (has("neck"))
    part = "neck";
  else if (has("head"))
    part = "head";
  else if (any({"hips", "hip", "pelvis", "root"}))
    part = "hips";
  else if (any({"spine", "chest", "torso", "abdomen", "waist", "lowerback", "back"}))
    part = "spine";
  else if (any({"clavicle", "collar", "shoulder"}))
    part = "clavicle";
  else if (has("thumb"))
    part = "thumb";
  else if (has("index"))
    part = "index";
  else if (has("middle"))
    part = "middle";
  else if (has("ring"))
    part = "ring";
  else if (any({"pinky", "little", "small"}))
    part = "pinky";
  else if (any({"finger", "fingers", "fingerbase"}))
    part = "finger";
  else if (any({"forearm", "lowerarm", "elbow"}) || (has("arm") && (lower || has("fore"))))
    part = "forearm";
  else if (any({"upperarm", "arm"}))
    part = "upper_arm";
  else if (any({"hand", "wrist", "palm"}))
    part = "hand";
  else if (has("jaw"))
    part = "jaw";
  else if (any({"eyelid", "lid"}))
    part = "eyelid";
  else if (any({"brow", "eyebrow"}))
    part = "brow";
  else if (any({"eye", "eyes"}))
    part = "eye";
  else if (any({"lip", "lips"}))
    part = "lip";
  else if (has("mouth"))
    part = "mouth";
  else if (has("cheek"))
    part = "cheek";
  else if (has("tongue"))
    part = "tongue";
  else if (any({"tail", "ponytail"}))
    part = "tail";
  role.part = part;
  static const char* const kCentre[] = {"hips", "spine", "neck", "head", "jaw", "tongue", "tail"};
  if (std::any_of(std::begin(kCentre), std::end(kCentre), [&](const char* c) { return part == c; }))
    role.side = BodySide::Center;
  // a chain part's own numbering is its order; a side part's number (Bip01 L Finger0) too
  return role;
}

const char* toString(BodySide side) {
  switch (side) {
  case BodySide::Left:
    return "left";
  case BodySide::Right:
    return "right";
  case BodySide::Center:
    break;
  }
  return "center";
}

} // namespace mlod
