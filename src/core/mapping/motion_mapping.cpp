#include "core/mapping/motion_mapping.h"

#include "core/mapping/joint_names.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <tuple>

namespace mlod {

namespace {

std::vector<int> depths(const Skeleton& skeleton) {
  std::vector<int> out(skeleton.joints.size(), 0);
  for (std::size_t j = 0; j < out.size(); ++j)
    if (skeleton.joints[j].parent >= 0)
      out[j] = out[static_cast<std::size_t>(skeleton.joints[j].parent)] + 1;
  return out;
}

// Joints of one (part, side), by their place along the chain: nearest the root first.
using RoleKey = std::pair<std::string, BodySide>;
std::map<RoleKey, std::vector<int>> groupByRole(const Skeleton& skeleton, std::vector<JointRole>& out_roles) {
  const std::vector<int> depth = depths(skeleton);
  std::map<RoleKey, std::vector<int>> groups;
  out_roles.clear();
  for (std::size_t j = 0; j < skeleton.joints.size(); ++j) {
    out_roles.push_back(jointRole(skeleton.joints[j].name));
    const JointRole& role = out_roles.back();
    if (role.part.empty() || role.end)
      continue;
    groups[{role.part, role.side}].push_back(static_cast<int>(j));
  }
  for (auto& [key, joints] : groups)
    std::stable_sort(joints.begin(), joints.end(), [&](int a, int b) {
      return depth[static_cast<std::size_t>(a)] < depth[static_cast<std::size_t>(b)];
    });
  return groups;
}

glm::dquat rotationOf(const glm::mat4& m) {
  glm::dmat3 r(m);
  for (int c = 0; c < 3; ++c)
    r[c] = glm::normalize(r[c]);
  return glm::normalize(glm::quat_cast(r));
}

// The smallest rotation that turns unit vector a onto unit vector b.
glm::dquat rotationBetween(const glm::dvec3& a, const glm::dvec3& b) {
  const double d = glm::dot(a, b);
  if (d < -1.0 + 1e-12) { // opposite: half a turn about any axis perpendicular to a
    glm::dvec3 axis = glm::cross(glm::dvec3(1.0, 0.0, 0.0), a);
    if (glm::dot(axis, axis) < 1e-12)
      axis = glm::cross(glm::dvec3(0.0, 1.0, 0.0), a);
    return glm::angleAxis(glm::pi<double>(), glm::normalize(axis));
  }
  const glm::dvec3 c = glm::cross(a, b);
  return glm::normalize(glm::dquat(1.0 + d, c.x, c.y, c.z));
}

// The 24 rotations that map coordinate axes onto coordinate axes.
std::vector<glm::dquat> axisRotations() {
  std::vector<glm::dquat> out;
  const std::array<std::array<int, 3>, 6> permutations = {{{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  for (const auto& p : permutations)
    for (int signs = 0; signs < 8; ++signs) {
      glm::dmat3 m(0.0);
      for (int c = 0; c < 3; ++c)
        m[c][p[static_cast<std::size_t>(c)]] = (signs >> c) & 1 ? -1.0 : 1.0;
      if (glm::determinant(m) > 0.0)
        out.push_back(glm::normalize(glm::quat_cast(m)));
    }
  return out;
}

} // namespace

MotionMapping MotionMapping::automatic(const Skeleton& motion, const Skeleton& character) {
  MotionMapping mapping;
  std::vector<JointRole> motionRoles, characterRoles;
  const auto motionGroups = groupByRole(motion, motionRoles);
  const auto characterGroups = groupByRole(character, characterRoles);
  std::vector<std::pair<int, int>> found; // (character, motion)
  for (const auto& [key, characterJoints] : characterGroups) {
    const auto it = motionGroups.find(key);
    if (it == motionGroups.end())
      continue;
    const std::vector<int>& motionJoints = it->second;
    const bool chain = characterRoles[static_cast<std::size_t>(characterJoints.front())].chain();
    if (!chain) {
      found.emplace_back(characterJoints.front(), motionJoints.front()); // the one nearest the root
      continue;
    }
    // along the chain, spread evenly and one to one: the shorter chain picks from the longer
    const std::size_t n = characterJoints.size(), m = motionJoints.size();
    const auto spread = [](std::size_t i, std::size_t from, std::size_t to) {
      return from == 1 ? std::size_t(0) : static_cast<std::size_t>(std::lround(double(i) * double(to - 1) / double(from - 1)));
    };
    if (m <= n)
      for (std::size_t i = 0; i < m; ++i)
        found.emplace_back(characterJoints[spread(i, m, n)], motionJoints[i]);
    else
      for (std::size_t j = 0; j < n; ++j)
        found.emplace_back(characterJoints[j], motionJoints[spread(j, n, m)]);
  }
  std::sort(found.begin(), found.end());
  for (const auto& [c, s] : found)
    mapping.pairs.push_back(JointPair{character.joints[static_cast<std::size_t>(c)].name,
                                      motion.joints[static_cast<std::size_t>(s)].name});
  return mapping;
}

const std::string* MotionMapping::motionFor(std::string_view characterJoint) const {
  for (const JointPair& pair : pairs)
    if (pair.character == characterJoint)
      return &pair.motion;
  return nullptr;
}

void MotionMapping::set(const std::string& characterJoint, const std::string& motionJoint) {
  std::erase_if(pairs, [&](const JointPair& p) { return p.character == characterJoint || p.motion == motionJoint; });
  pairs.push_back(JointPair{characterJoint, motionJoint});
}

void MotionMapping::clear(std::string_view characterJoint) {
  std::erase_if(pairs, [&](const JointPair& p) { return p.character == characterJoint; });
}

Error MotionMapping::validate(const Skeleton& motion, const Skeleton& character) const {
  std::set<std::string> characterSeen, motionSeen;
  for (const JointPair& pair : pairs) {
    if (character.find(pair.character) < 0)
      return Error("mapping: the character has no joint '" + pair.character + "'");
    if (motion.find(pair.motion) < 0)
      return Error("mapping: the motion has no joint '" + pair.motion + "'");
    if (!characterSeen.insert(pair.character).second)
      return Error("mapping: character joint '" + pair.character + "' is mapped twice");
    if (!motionSeen.insert(pair.motion).second)
      return Error("mapping: motion joint '" + pair.motion + "' drives two character joints");
  }
  return {};
}

std::string motionMappingToJson(const MotionMapping& mapping, int indent) {
  using nlohmann::json;
  json pairs = json::array();
  for (const JointPair& pair : mapping.pairs)
    pairs.push_back({{"character", pair.character}, {"motion", pair.motion}});
  json doc = {{"format", "motionlod-mapping"},
              {"version", kMotionMappingVersion},
              {"motion", mapping.motionName},
              {"character", mapping.characterName},
              {"pairs", std::move(pairs)}};
  return doc.dump(indent);
}

Result<MotionMapping> motionMappingFromJson(std::string_view text) {
  using nlohmann::json;
  const json doc = json::parse(text, nullptr, false);
  if (doc.is_discarded() || !doc.is_object())
    return Error("mapping: not a JSON object");
  if (!doc.contains("format") || doc["format"] != "motionlod-mapping")
    return Error("mapping: not a motion mapping (\"format\" is not \"motionlod-mapping\")");
  if (!doc.contains("version") || !doc["version"].is_number_integer())
    return Error("mapping: no version");
  if (doc["version"].get<int>() > kMotionMappingVersion)
    return Error("mapping: version " + std::to_string(doc["version"].get<int>()) +
                 " was made by a newer Motion LOD Studio");
  MotionMapping mapping;
  for (const char* key : {"motion", "character"}) {
    if (!doc.contains(key))
      continue;
    if (!doc[key].is_string())
      return Error(std::string("mapping: \"") + key + "\" is not a string");
    (key[0] == 'm' ? mapping.motionName : mapping.characterName) = doc[key].get<std::string>();
  }
  if (!doc.contains("pairs") || !doc["pairs"].is_array())
    return Error("mapping: no \"pairs\" array");
  for (const json& pair : doc["pairs"]) {
    if (!pair.is_object() || !pair.contains("character") || !pair.contains("motion") ||
        !pair["character"].is_string() || !pair["motion"].is_string())
      return Error("mapping: a pair needs \"character\" and \"motion\" joint names");
    mapping.pairs.push_back(JointPair{pair["character"].get<std::string>(), pair["motion"].get<std::string>()});
  }
  return mapping;
}

MappingAgreement compareMappings(const MotionMapping& automatic, const MotionMapping& reference) {
  MappingAgreement out;
  out.referencePairs = static_cast<int>(reference.pairs.size());
  for (const JointPair& pair : reference.pairs) {
    const std::string* mine = automatic.motionFor(pair.character);
    if (!mine)
      ++out.missing;
    else if (*mine == pair.motion)
      ++out.found;
    else
      ++out.wrong;
  }
  for (const JointPair& pair : automatic.pairs)
    if (!reference.motionFor(pair.character))
      ++out.extra;
  return out;
}

Result<RestPoseDifferences> restPoseDifferences(const MotionMapping& mapping, const Skeleton& motion,
                                                const Skeleton& character) {
  if (Error error = motion.validate())
    return Error("motion skeleton: " + error.message());
  if (Error error = character.validate())
    return Error("character skeleton: " + error.message());
  if (Error error = mapping.validate(motion, character))
    return error;
  if (mapping.pairs.empty())
    return Error("mapping: no joint is mapped");

  RestPoseDifferences out;
  const std::size_t nc = character.joints.size();
  out.source.assign(nc, -1);
  for (const JointPair& pair : mapping.pairs)
    out.source[static_cast<std::size_t>(character.find(pair.character))] = motion.find(pair.motion);
  const auto sourceOf = [&](int c) { return out.source[static_cast<std::size_t>(c)]; };

  const std::vector<glm::mat4> motionRest = motion.restModelMatrices();
  const std::vector<glm::mat4> characterRest = character.restModelMatrices();
  const auto motionPosition = [&](int j) { return glm::dvec3(motionRest[static_cast<std::size_t>(j)][3]); };
  const auto characterPosition = [&](int j) { return glm::dvec3(characterRest[static_cast<std::size_t>(j)][3]); };
  const auto nearestMappedAncestor = [&](int c) {
    int a = character.joints[static_cast<std::size_t>(c)].parent;
    while (a >= 0 && sourceOf(a) < 0)
      a = character.joints[static_cast<std::size_t>(a)].parent;
    return a;
  };

  // scale: the mapped bones' lengths, character over motion
  double characterLength = 0.0, motionLength = 0.0;
  for (int c = 0; c < int(nc); ++c) {
    const int a = sourceOf(c) >= 0 ? nearestMappedAncestor(c) : -1;
    if (a < 0)
      continue;
    characterLength += glm::length(characterPosition(c) - characterPosition(a));
    motionLength += glm::length(motionPosition(sourceOf(c)) - motionPosition(sourceOf(a)));
  }
  out.scale = motionLength > 0.0 && characterLength > 0.0 ? characterLength / motionLength : 1.0;

  // alignment: the axis-aligned rotation that best overlays the rest poses about the
  // shallowest mapped pair (skeletons are authored along axes: Y-up, Z-up, facing +-z ...)
  const std::vector<int> depth = depths(character);
  int anchor = -1;
  for (int c = 0; c < int(nc); ++c)
    if (sourceOf(c) >= 0 && (anchor < 0 || depth[std::size_t(c)] < depth[std::size_t(anchor)]))
      anchor = c;
  double best = std::numeric_limits<double>::infinity();
  for (const glm::dquat& a : axisRotations()) {
    double cost = 0.0;
    for (int c = 0; c < int(nc); ++c)
      if (sourceOf(c) >= 0) {
        const glm::dvec3 d = a * ((motionPosition(sourceOf(c)) - motionPosition(sourceOf(anchor))) * out.scale) -
                             (characterPosition(c) - characterPosition(anchor));
        cost += glm::dot(d, d);
      }
    if (cost < best - 1e-9) {
      best = cost;
      out.alignment = a;
    }
  }

  // R_c: turns the character's rest bones at c onto the motion's (aligned) rest bones
  const double kMinLength = 1e-4; // cm
  std::vector<int> mappedBelow(nc, 0);
  for (int c = int(nc) - 1; c >= 0; --c) {
    mappedBelow[std::size_t(c)] += sourceOf(c) >= 0;
    const int parent = character.joints[std::size_t(c)].parent;
    if (parent >= 0)
      mappedBelow[std::size_t(parent)] += mappedBelow[std::size_t(c)];
  }
  std::vector<glm::dquat> align(nc, glm::dquat(1.0, 0.0, 0.0, 0.0));
  for (int c = 0; c < int(nc); ++c) {
    const int s = sourceOf(c);
    if (s < 0)
      continue;
    struct Bone {
      glm::dvec3 character, motion;
      int weight;
    };
    std::vector<Bone> bones;
    // the first mapped descendants of c at a distance from it, and their partners' bones
    std::vector<int> stack = character.children(c);
    while (!stack.empty()) {
      const int d = stack.back();
      stack.pop_back();
      if (sourceOf(d) >= 0) {
        const glm::dvec3 vc = characterPosition(d) - characterPosition(c);
        const glm::dvec3 vs = out.alignment * (motionPosition(sourceOf(d)) - motionPosition(s));
        if (glm::length(vc) > kMinLength && glm::length(vs) > kMinLength) {
          bones.push_back(Bone{glm::normalize(vc), glm::normalize(vs), mappedBelow[std::size_t(d)]});
          continue;
        }
      }
      for (int child : character.children(d))
        stack.push_back(child);
    }
    if (bones.empty()) { // a mapped leaf keeps its rest relation to its mapped parent
      const int a = nearestMappedAncestor(c);
      align[std::size_t(c)] = a >= 0 ? align[std::size_t(a)] : glm::dquat(1.0, 0.0, 0.0, 0.0);
      continue;
    }
    std::stable_sort(bones.begin(), bones.end(), [](const Bone& a, const Bone& b) { return a.weight > b.weight; });
    glm::dquat r = rotationBetween(bones[0].character, bones[0].motion);
    // a second bone, clearly off the first, fixes the twist about it
    const Bone* second = nullptr;
    double sine = 0.2;
    for (std::size_t i = 1; i < bones.size(); ++i) {
      const double s2 = glm::length(glm::cross(bones[0].character, bones[i].character));
      if (s2 > sine) {
        sine = s2;
        second = &bones[i];
      }
    }
    if (second) {
      const glm::dvec3 axis = bones[0].motion;
      glm::dvec3 from = r * second->character, to = second->motion;
      from -= axis * glm::dot(from, axis);
      to -= axis * glm::dot(to, axis);
      if (glm::length(from) > 1e-6 && glm::length(to) > 1e-6)
        r = rotationBetween(glm::normalize(from), glm::normalize(to)) * r;
    }
    align[std::size_t(c)] = r;
  }

  out.difference.assign(nc, glm::dquat(1.0, 0.0, 0.0, 0.0));
  for (int c = 0; c < int(nc); ++c) {
    const int s = sourceOf(c);
    if (s < 0)
      continue;
    const glm::dquat motionRestRotation = out.alignment * rotationOf(motionRest[std::size_t(s)]);
    out.difference[std::size_t(c)] =
        glm::normalize(glm::inverse(motionRestRotation) * align[std::size_t(c)] * rotationOf(characterRest[std::size_t(c)]));
  }
  out.rootSource = sourceOf(0) >= 0 ? sourceOf(0) : 0;
  return out;
}

Result<Clip> retargetClip(const RestPoseDifferences& differences, const Skeleton& motion, const Clip& clip,
                          const Skeleton& character) {
  if (Error error = clip.validate(motion))
    return Error("clip '" + clip.name + "': " + error.message());
  const std::size_t nc = character.joints.size();
  if (differences.source.size() != nc || differences.difference.size() != nc)
    return Error("retarget: the rest-pose differences were made for another character");
  for (int s : differences.source)
    if (s >= motion.jointCount())
      return Error("retarget: the rest-pose differences were made for another motion");

  Clip out = Clip::restPose(character, clip.frameCount, clip.fps);
  out.name = clip.name;
  out.looping = clip.looping;
  for (std::size_t c = 0; c < nc; ++c)
    out.hasRotation[c] = differences.source[c] >= 0 || c == 0 ? 1 : 0;
  out.hasTranslation[0] = 1;

  std::vector<glm::mat4> models;
  std::vector<glm::dquat> global(nc);
  glm::dvec3 rootStart(0.0);
  const glm::dvec3 restRoot(character.joints[0].rest.translation);
  for (int t = 0; t < clip.frameCount; ++t) {
    clip.modelMatrices(motion, t, models);
    const glm::dvec3 root(models[std::size_t(differences.rootSource)][3]);
    if (t == 0)
      rootStart = root;
    for (std::size_t c = 0; c < nc; ++c) {
      const int parent = character.joints[c].parent;
      const glm::dquat parentGlobal = parent >= 0 ? global[std::size_t(parent)] : glm::dquat(1.0, 0.0, 0.0, 0.0);
      const int s = differences.source[c];
      if (s >= 0)
        global[c] = glm::normalize(differences.alignment * rotationOf(models[std::size_t(s)]) * differences.difference[c]);
      else
        global[c] = glm::normalize(parentGlobal * glm::dquat(character.joints[c].rest.rotation));
      // an unmapped joint holds its rest rotation exactly (no round trip through model space)
      glm::quat local = s >= 0 ? glm::quat(glm::normalize(glm::inverse(parentGlobal) * global[c]))
                               : character.joints[c].rest.rotation;
      if (t > 0 && s >= 0) { // one hemisphere along the track, for interpolation
        const glm::quat& previous = out.rotations[out.index(int(c), t - 1)];
        if (glm::dot(local, previous) < 0.0f)
          local = -local;
      }
      out.rotations[out.index(int(c), t)] = local;
    }
    out.translations[out.index(0, t)] =
        glm::vec3(restRoot + differences.alignment * ((root - rootStart) * differences.scale));
  }
  return out;
}

MappingCoverage mappingCoverage(const MotionMapping& mapping, const Skeleton& character) {
  std::vector<std::uint8_t> parent(character.joints.size(), 0);
  for (const Joint& joint : character.joints)
    if (joint.parent >= 0 && std::size_t(joint.parent) < parent.size())
      parent[std::size_t(joint.parent)] = 1;
  MappingCoverage out;
  for (std::size_t j = 0; j < parent.size(); ++j) {
    if (!parent[j])
      continue;
    ++out.joints;
    out.mapped += mapping.motionFor(character.joints[j].name) ? 1 : 0;
  }
  return out;
}

std::string mappingReach(const MappingCoverage& coverage, std::string_view characterName) {
  return std::to_string(coverage.mapped) + " of " + std::string(characterName) + "'s " +
         std::to_string(coverage.joints) + " joints with a child (" +
         std::to_string(int(std::lround(100.0 * coverage.share()))) + "%)";
}

std::string tooLittleMappedReason(const MappingCoverage& coverage, std::string_view characterName) {
  return "the automatic mapping drives " + mappingReach(coverage, characterName) + ", below " +
         std::to_string(int(std::lround(100.0 * kMinMappedShare))) + "%: the rest of the body would hold its rest pose";
}

Result<MappedMotion> mapMotionAutomatically(const Skeleton& motion, std::span<const Clip> clips,
                                            const Skeleton& character, std::string_view characterName) {
  if (clips.empty() || motion.empty())
    return Error("has no animation clip to play");
  MappedMotion out;
  out.mapping = MotionMapping::automatic(motion, character);
  Result<RestPoseDifferences> differences = restPoseDifferences(out.mapping, motion, character);
  if (!differences)
    return Error("cannot be mapped onto " + std::string(characterName) + ": " + differences.message());
  for (const Clip& clip : clips) {
    Result<Clip> retargeted = retargetClip(*differences, motion, clip, character);
    if (!retargeted)
      return retargeted.error();
    out.clips.push_back(std::move(retargeted).value());
  }
  out.coverage = mappingCoverage(out.mapping, character);
  return out;
}

} // namespace mlod
