#include "core/skeleton.h"

#include "runtime/local_to_model_job.h"

#include <cmath>
#include <unordered_set>

namespace mlod {

namespace {
bool isFinite(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r]))
        return false;
  return true;
}
} // namespace

int Skeleton::find(const std::string& name) const {
  for (int i = 0; i < jointCount(); ++i)
    if (joints[static_cast<std::size_t>(i)].name == name)
      return i;
  return -1;
}

std::vector<int> Skeleton::children(int joint) const {
  std::vector<int> out;
  for (int i = joint + 1; i < jointCount(); ++i)
    if (joints[static_cast<std::size_t>(i)].parent == joint)
      out.push_back(i);
  return out;
}

std::vector<std::int16_t> Skeleton::parentIndices() const {
  std::vector<std::int16_t> out;
  out.reserve(joints.size());
  for (const Joint& joint : joints)
    out.push_back(static_cast<std::int16_t>(joint.parent));
  return out;
}

std::vector<glm::mat4> Skeleton::restModelMatrices() const {
  std::vector<glm::mat4> locals;
  locals.reserve(joints.size());
  for (const Joint& joint : joints)
    locals.push_back(toMatrix(joint.rest));
  std::vector<glm::mat4> models(joints.size());
  const std::vector<std::int16_t> parents = parentIndices();
  LocalToModelJob job;
  job.parents = parents;
  job.locals = locals;
  job.out_models = models;
  [[maybe_unused]] const bool ran = job.run();
  assert(ran && "restModelMatrices() needs a skeleton that validates");
  return models;
}

int Skeleton::leafCount() const {
  std::vector<bool> hasChild(joints.size(), false);
  for (const Joint& joint : joints)
    if (joint.parent >= 0)
      hasChild[static_cast<std::size_t>(joint.parent)] = true;
  int count = 0;
  for (bool b : hasChild)
    count += b ? 0 : 1;
  return count;
}

Error Skeleton::validate() const {
  if (joints.size() > 32767)
    return Error("skeleton has " + std::to_string(joints.size()) + " joints; at most 32767 are supported");
  std::unordered_set<std::string> names;
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const Joint& joint = joints[i];
    const std::string where = "joint " + std::to_string(i) + " '" + joint.name + "'";
    if (joint.name.empty())
      return Error("joint " + std::to_string(i) + " has no name");
    if (!names.insert(joint.name).second)
      return Error("two joints are named '" + joint.name + "'");
    if (i == 0 && joint.parent != -1)
      return Error(where + " is first and must be the root");
    if (i > 0 && (joint.parent < 0 || joint.parent >= static_cast<int>(i)))
      return Error(where + " has parent " + std::to_string(joint.parent) +
                   "; parents must come before their children and there must be one root");
    if (!joint.rest.isValid())
      return Error(where + " has a non-finite or non-unit rest transform");
    if (joint.inverseBind) {
      if (!isFinite(*joint.inverseBind))
        return Error(where + " has a non-finite inverse bind matrix");
      if (std::abs(glm::determinant(*joint.inverseBind)) < 1e-12f)
        return Error(where + " has a singular inverse bind matrix");
    }
  }
  // finite offsets can still add up past float's range (a BVH with every OFFSET 1e38): such
  // a skeleton has no height, and every distance derived from it is infinite
  const std::vector<glm::mat4> rest = restModelMatrices();
  for (std::size_t i = 0; i < rest.size(); ++i)
    if (!isFinite(rest[i]))
      return Error("joint " + std::to_string(i) + " '" + joints[i].name +
                   "' lies at a non-finite position in the rest pose (its offsets add up past 3.4e38)");
  return {};
}

} // namespace mlod
