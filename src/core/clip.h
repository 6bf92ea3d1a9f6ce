#pragma once
// A motion sampled at a fixed frame rate: frame = index, time = frame / fps seconds.
// Tracks are stored joint-major (all frames of joint 0, then joint 1, ...) because
// every algorithm on clips (JPC above all) walks one joint's frames at a time.

#include "core/error.h"
#include "core/skeleton.h"

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace mlod {

class Clip {
public:
  std::string name;
  double fps = 30.0;    // frames per second
  int frameCount = 0;   // >= 1
  int jointCount = 0;   // = the skeleton's joint count
  bool looping = false; // wraps in the runtime (and blends at the wrap)

  // [joint * frameCount + frame]. Joints without a channel hold their rest values.
  std::vector<glm::quat> rotations;    // local, unit quaternions
  std::vector<glm::vec3> translations; // local, cm; joint 0's is the root translation
  std::vector<glm::vec3> scales;       // local
  // Per joint: 1 where the source file carries that channel for the joint. A joint
  // with a rotation channel is clusterable (docs/architecture.md section 4); BVH End Sites have none.
  std::vector<std::uint8_t> hasRotation;
  std::vector<std::uint8_t> hasTranslation;
  std::vector<std::uint8_t> hasScale;

  // A clip of `frames` frames that holds the skeleton's rest pose, with no channels.
  static Clip restPose(const Skeleton& skeleton, int frames, double fps);

  double durationSeconds() const { return frameCount > 1 ? (frameCount - 1) / fps : 0.0; }
  std::size_t index(int joint, int frame) const {
    return static_cast<std::size_t>(joint) * static_cast<std::size_t>(frameCount) + static_cast<std::size_t>(frame);
  }
  const glm::quat& rotation(int joint, int frame) const { return rotations[index(joint, frame)]; }
  const glm::vec3& translation(int joint, int frame) const { return translations[index(joint, frame)]; }
  const glm::vec3& scale(int joint, int frame) const { return scales[index(joint, frame)]; }
  Transform local(int joint, int frame) const;
  // Model-space matrices of every joint at `frame`, written to out_models (jointCount entries).
  void modelMatrices(const Skeleton& skeleton, int frame, std::vector<glm::mat4>& out_models) const;
  int rotationChannelCount() const;

  // Rules: a name; fps finite in (0, 10000]; frameCount >= 1; jointCount equals the
  // skeleton's; every track holds jointCount * frameCount finite values; rotations are
  // unit within 1e-3; channel flags hold one entry per joint.
  Error validate(const Skeleton& skeleton) const;
};

} // namespace mlod
