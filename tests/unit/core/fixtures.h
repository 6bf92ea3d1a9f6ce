#pragma once
// Small synthetic skeletons and clips with known answers.

#include "core/clip.h"
#include "core/skeleton.h"

#include <string>

namespace mlod::test {

// A chain of `count` joints named j0, j1 ..., each `length` cm along +y from its parent.
inline Skeleton makeChain(int count, float length = 10.0f) {
  Skeleton skeleton;
  for (int i = 0; i < count; ++i) {
    Joint joint;
    joint.name = "j" + std::to_string(i);
    joint.parent = i - 1;
    joint.rest.translation = i == 0 ? glm::vec3(0.0f) : glm::vec3(0.0f, length, 0.0f);
    skeleton.joints.push_back(joint);
  }
  return skeleton;
}

} // namespace mlod::test
