#pragma once
// Inputs for the mesh LOD tests: a synthetic two-segment tube with known shared vertices, an
// attribute seam and a bend, and BCN_Epileptic (Debian's assimp-testmodels) in cm.

#include "core/asset.h"
#include "core/clip.h"
#include "core/skeleton.h"
#include "core/skinned_mesh.h"
#include "io/importer.h"

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>

namespace mlod::test {

// An open tube along +y around two joints: "lower" at the origin and "upper" 20 cm above
// it, radius 5 cm, `rings` rings of `sides` vertices every `step` cm (y = 0, step, ...).
// Rings below y = 16 cm follow "lower" alone (w = 1), rings above y = 24 cm "upper" alone,
// rings in between blend linearly: those are the shared vertices (0 < w < 1). A UV seam
// runs along the angle 0 (u = 0 and u = 1 there: two vertices at one position). Normals
// point outwards. Both ends are open borders. `bulge` (cm) swells the radius in the middle
// (5 + bulge x sin(pi y / length)), so that removing a ring costs something.
struct Tube {
  Skeleton skeleton;
  SkinnedMesh mesh;
  int rings = 0;
  int sides = 0;
  int sharedRings = 0; // rings with 0 < w < 1
};

inline Tube makeTube(int rings = 41, int sides = 16, float step = 1.0f, float bulge = 0.0f) {
  Tube tube;
  tube.rings = rings;
  tube.sides = sides;
  Joint lower;
  lower.name = "lower";
  Joint upper;
  upper.name = "upper";
  upper.parent = 0;
  upper.rest.translation = glm::vec3(0.0f, 20.0f, 0.0f);
  lower.inverseBind = glm::mat4(1.0f);
  glm::mat4 upperInverseBind(1.0f);
  upperInverseBind[3] = glm::vec4(0.0f, -20.0f, 0.0f, 1.0f); // the joint sits at y = 20 at bind time
  upper.inverseBind = upperInverseBind;
  tube.skeleton.joints = {lower, upper};

  SkinnedMesh& mesh = tube.mesh;
  mesh.name = "tube";
  const float radius = 5.0f;
  // sides + 1 vertices per ring: the last repeats the first with u = 1 (the seam)
  for (int r = 0; r < rings; ++r) {
    const float y = float(r) * step;
    const float ringRadius = radius + bulge * std::sin(std::numbers::pi_v<float> * float(r) / float(rings - 1));
    const float upperWeight = std::clamp((y - 16.0f) / 8.0f, 0.0f, 1.0f);
    if (upperWeight > 0.0f && upperWeight < 1.0f)
      ++tube.sharedRings;
    for (int s = 0; s <= sides; ++s) {
      const float angle = 2.0f * std::numbers::pi_v<float> * float(s % sides) / float(sides);
      const glm::vec3 radial(std::cos(angle), 0.0f, std::sin(angle));
      mesh.positions.push_back(glm::vec3(ringRadius * radial.x, y, ringRadius * radial.z));
      mesh.normals.push_back(radial);
      mesh.uvs.push_back(glm::vec2(float(s) / float(sides), y / (float(rings - 1) * step)));
      const int joints[2] = {0, 1};
      const float weights[2] = {1.0f - upperWeight, upperWeight};
      glm::u16vec4 j;
      glm::vec4 w;
      normalizeInfluences(joints, weights, 2, j, w);
      mesh.joints.push_back(j);
      mesh.weights.push_back(w);
    }
  }
  const auto vertex = [&](int r, int s) { return static_cast<std::uint32_t>(r * (sides + 1) + s); };
  for (int r = 0; r + 1 < rings; ++r)
    for (int s = 0; s < sides; ++s) {
      // outward-facing: counter-clockwise seen from outside
      mesh.indices.insert(mesh.indices.end(), {vertex(r, s), vertex(r + 1, s), vertex(r + 1, s + 1)});
      mesh.indices.insert(mesh.indices.end(), {vertex(r, s), vertex(r + 1, s + 1), vertex(r, s + 1)});
    }
  mesh.parts.push_back(MeshPart{"tube", 0, static_cast<std::uint32_t>(mesh.indices.size())});
  return tube;
}

// A clip of the tube that bends "upper" about z by up to `degrees`, over `frames` frames.
inline Clip tubeBendClip(const Skeleton& skeleton, int frames = 12, float degrees = 60.0f) {
  Clip clip = Clip::restPose(skeleton, frames, 30.0);
  clip.name = "bend";
  clip.hasRotation = {1, 1};
  for (int t = 0; t < frames; ++t)
    clip.rotations[clip.index(1, t)] =
        glm::angleAxis(glm::radians(degrees * float(t) / float(frames - 1)), glm::vec3(0.0f, 0.0f, 1.0f));
  return clip;
}

// A real file, imported once per test program; X files are in metres (unit scale 100),
// CMU BVH clips at 5.6444 cm per unit.
inline const Asset& meshAsset(const std::string& relative) {
  static std::map<std::string, Asset> cache;
  auto found = cache.find(relative);
  if (found == cache.end()) {
    ImportOptions options;
    if (relative.find("BVH/") == 0)
      options.unitScale = 5.6444;
    else if (relative.find("X/") == 0)
      options.unitScale = 100.0;
    Result<Asset> asset = importAsset(std::string(MLOD_ASSIMP_MODELS) + "/" + relative, options);
    if (!asset)
      throw std::runtime_error(relative + ": " + asset.message());
    found = cache.emplace(relative, std::move(asset).value()).first;
  }
  return found->second;
}

inline const Asset& bcnEpileptic() { return meshAsset("X/BCN_Epileptic.X"); }

// A character of the shared fixture list (unit/real_files.h), imported once per test
// program at its own unit or the guessed one (a human height), as the studio imports it.
inline const Asset& fixtureCharacter(const std::string& relative) {
  static std::map<std::string, Asset> cache;
  auto found = cache.find(relative);
  if (found == cache.end()) {
    Result<Asset> asset = importAsset(std::string(MLOD_ASSIMP_MODELS) + "/" + relative);
    if (!asset)
      throw std::runtime_error(relative + ": " + asset.message());
    found = cache.emplace(relative, std::move(asset).value()).first;
  }
  return found->second;
}

} // namespace mlod::test
