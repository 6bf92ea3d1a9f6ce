// JPC error metric, Ahn & Wohn section 4.1, eqs. (1)-(6); docs/architecture.md section 4.
#include "core/jpc/posture_error.h"

#include <cassert>

namespace mlod {

namespace {
using ChildLists = std::vector<std::vector<int>>;

ChildLists childLists(const Skeleton& skeleton) {
  ChildLists children(skeleton.joints.size());
  for (std::size_t i = 1; i < skeleton.joints.size(); ++i)
    children[static_cast<std::size_t>(skeleton.joints[i].parent)].push_back(static_cast<int>(i));
  return children;
}

glm::dmat4 restMatrix(const Joint& joint) {
  const Transform& rest = joint.rest;
  const glm::dquat rotation(rest.rotation.w, rest.rotation.x, rest.rotation.y, rest.rotation.z);
  glm::dmat4 m = glm::mat4_cast(glm::normalize(rotation));
  m[0] *= static_cast<double>(rest.scale.x);
  m[1] *= static_cast<double>(rest.scale.y);
  m[2] *= static_cast<double>(rest.scale.z);
  m[3] = glm::dvec4(glm::dvec3(rest.translation), 1.0);
  return m;
}

// Collects the direction towards `child` as seen from the joint whose frame `toJoint`
// maps the child's parent frame into. note: zero-length offsets (CMU hips, LHipJoint) have
// no direction of their own, so the rest transforms are composed down every branch until
// a real offset appears; the intermediate joints' animated rotations are their own errors.
void collectDirections(const Skeleton& skeleton, const ChildLists& children, double zeroLength,
                       const glm::dmat4& toJoint, int child, std::vector<glm::dvec3>& out_directions) {
  const Joint& joint = skeleton.joints[static_cast<std::size_t>(child)];
  const glm::dvec3 offset(joint.rest.translation);
  if (glm::length(offset) >= zeroLength && glm::length(offset) > 0.0) {
    const glm::dvec3 v(toJoint * glm::dvec4(offset, 1.0));
    const double length = glm::length(v);
    if (length > 0.0 && std::isfinite(length))
      out_directions.push_back(v / length);
    return;
  }
  const glm::dmat4 deeper = toJoint * restMatrix(joint);
  for (int grandchild : children[static_cast<std::size_t>(child)])
    collectDirections(skeleton, children, zeroLength, deeper, grandchild, out_directions);
}

glm::dquat normalised(const glm::quat& q) {
  const double w = q.w, x = q.x, y = q.y, z = q.z;
  const double length = std::sqrt(w * w + x * x + y * y + z * z);
  return glm::dquat(w / length, x / length, y / length, z / length);
}

// v rotated by unit quaternion q. note: written out (not glm's operator) so that q and -q
// give the same bits: every term is a product of two quaternion components.
glm::dvec3 rotate(const glm::dquat& q, const glm::dvec3& v) {
  const glm::dvec3 u(q.x, q.y, q.z);
  const glm::dvec3 uv = glm::cross(u, v);
  const glm::dvec3 uuv = glm::cross(u, uv);
  return v + (uv * q.w + uuv) * 2.0;
}

bool sameRotation(const glm::quat& a, const glm::quat& b) {
  return (a.w == b.w && a.x == b.x && a.y == b.y && a.z == b.z) ||
         (a.w == -b.w && a.x == -b.x && a.y == -b.y && a.z == -b.z);
}
} // namespace

std::vector<JointGeometry> jointGeometry(const Skeleton& skeleton, double zeroLength) {
  const ChildLists children = childLists(skeleton);
  const std::size_t count = skeleton.joints.size();
  std::vector<JointGeometry> out(count);
  // eq. (4): children come after their parents, so one backward pass sums every subtree.
  std::vector<double> subtree(count, 0.0); // sum over the joint's strict descendants
  for (std::size_t i = count; i-- > 1;) {
    const std::size_t parent = static_cast<std::size_t>(skeleton.joints[i].parent);
    subtree[parent] += subtree[i] + glm::length(glm::dvec3(skeleton.joints[i].rest.translation));
  }
  for (std::size_t j = 0; j < count; ++j) {
    out[j].radius = subtree[j];
    for (int child : children[j])
      collectDirections(skeleton, children, zeroLength, glm::dmat4(1.0), child, out[j].directions);
  }
  return out;
}

JointTrack::JointTrack(const JointGeometry& geometry, double alpha, std::span<const glm::quat> rotations)
    : m_frames(static_cast<int>(rotations.size())), m_directionCount(static_cast<int>(geometry.directions.size())),
      m_radius(geometry.radius), m_alpha(alpha) {
  assert(!rotations.empty());
  assert(alpha >= 0.0 && std::isfinite(alpha));
  const double position = m_directionCount > 0 ? m_radius * 180.0 : 0.0;
  m_maxError = (position + m_alpha * 180.0) * (1.0 + 1e-12);

  const std::size_t frames = rotations.size();
  m_rotations.resize(frames);
  m_directions.resize(frames * geometry.directions.size());
  m_runFirst.resize(frames);
  m_runLast.resize(frames);
  for (std::size_t t = 0; t < frames; ++t) {
    assert(std::abs(glm::length(rotations[t]) - 1.0f) <= 1e-3f);
    m_rotations[t] = normalised(rotations[t]);
    for (std::size_t d = 0; d < geometry.directions.size(); ++d)
      m_directions[t * geometry.directions.size() + d] = rotate(m_rotations[t], geometry.directions[d]); // eq. (2)
    const bool same = t > 0 && sameRotation(rotations[t], rotations[t - 1]);
    m_runFirst[t] = same ? m_runFirst[t - 1] : static_cast<int>(t);
  }
  for (std::size_t t = frames; t-- > 0;) {
    const bool sameAsNext = t + 1 < frames && m_runFirst[t + 1] == m_runFirst[t];
    m_runLast[t] = sameAsNext ? m_runLast[t + 1] : static_cast<int>(t);
  }

  const std::size_t directions = geometry.directions.size();
  m_approximate.resize((3 * directions + 4) * frames);
  for (std::size_t t = 0; t < frames; ++t) {
    for (std::size_t d = 0; d < directions; ++d)
      for (std::size_t axis = 0; axis < 3; ++axis)
        m_approximate[(3 * d + axis) * frames + t] =
            static_cast<float>(m_directions[t * directions + d][static_cast<glm::length_t>(axis)]);
    const glm::dquat& q = m_rotations[t];
    const double components[4] = {q.w, q.x, q.y, q.z};
    for (std::size_t c = 0; c < 4; ++c)
      m_approximate[(3 * directions + c) * frames + t] = static_cast<float>(components[c]);
  }
  // note: float inputs, float arithmetic and a polynomial arctangent each cost a few 1e-7
  // radians (measured: < 3e-7 for the arctangent, < 1e-6 all told); the bound allows 4e-6
  // radians per direction angle, 4 x 4e-6 for the rotation angle (its formula takes 4 x an
  // arctangent) and 1e-6 of the largest error for the float products and sums.
  const double angle = 4e-6 * kDegreesPerRadian;
  m_approximationBound = (position > 0.0 ? m_radius * angle : 0.0) + m_alpha * 4.0 * angle + 1e-6 * m_maxError;
}

} // namespace mlod
