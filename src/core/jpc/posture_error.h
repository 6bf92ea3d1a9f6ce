#pragma once
// The JPC error metric: how far apart two postures of one joint are (Ahn & Wohn, section
// 4.1, eqs. (1)-(6), as docs/architecture.md section 4 makes them precise).
//
// Units: lengths in cm, angles in degrees, errors E in cm·degrees.
//   E_j(t, ref) = E_pos + alpha_j * E_ori                                         eq. (1)
//   v'_j(t)     = rotate(q_j(t), v_j) / |v_j|, a unit vector                       eq. (2)
//   theta       = the angle between v'_j(t) and v'_j(ref)                          eq. (3)
//   r_j         = the sum of |offset| over j's strict descendants                  eq. (4)
//   E_pos       = r_j * theta, the largest over j's child directions               eq. (5)
//   E_ori       = 2 |log(q_j(t)^-1 q_j(ref))|, the rotation angle between the two,
//                 the shorter way                                                  eq. (6)
// The angles use forms that are exactly 0 for identical postures, accurate near 0 and
// exactly symmetric, so E_j(t, ref) == E_j(ref, t) bit for bit:
//   theta = atan2(|a x b|, a . b);   E_ori = 4 atan2(|a - s b|, |a + s b|), s = sign(a . b).
// E is a pseudometric (a positive sum of angles between rays and between rotations), so
// the triangle inequality holds up to rounding: the clustering table relies on it to skip
// evaluations without changing any result (clustering_table.h).

#include "core/skeleton.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <numbers>
#include <span>
#include <vector>

namespace mlod {

inline constexpr double kDegreesPerRadian = 180.0 / std::numbers::pi;

// The angle between two non-zero vectors, degrees in [0, 180] (eq. (3)). Exactly 0 for
// a == b and exactly symmetric; the vectors need not be unit.
inline double directionAngleDegrees(const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 c{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  const double sine = std::sqrt(c.x * c.x + c.y * c.y + c.z * c.z);
  const double cosine = a.x * b.x + a.y * b.y + a.z * b.z;
  return std::atan2(sine, cosine) * kDegreesPerRadian;
}

// The angle of the rotation that takes unit quaternion a to b, the shorter way (q and -q
// are the same rotation), degrees in [0, 180] (eq. (6)). Exactly 0 for a == +-b and exactly
// symmetric.
inline double rotationAngleDegrees(const glm::dquat& a, const glm::dquat& b) {
  const double dot = a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
  const double s = dot < 0.0 ? -1.0 : 1.0;
  const double dw = a.w - s * b.w, dx = a.x - s * b.x, dy = a.y - s * b.y, dz = a.z - s * b.z;
  const double pw = a.w + s * b.w, px = a.x + s * b.x, py = a.y + s * b.y, pz = a.z + s * b.z;
  const double minus = std::sqrt(dw * dw + dx * dx + dy * dy + dz * dz);
  const double plus = std::sqrt(pw * pw + px * px + py * py + pz * pz);
  return 4.0 * std::atan2(minus, plus) * kDegreesPerRadian;
}

// Landmark lower bounds (key_posture.cpp): for t in [first, first + count), count <= 256,
// the sum of max over p < landmarks of |rows[p * stride + t] - at[p]|. Float SIMD; the
// sum is within 2e-5 relative of the exact sum of those float terms.
double landmarkDistanceSum(const float* rows, int landmarks, std::size_t stride, const float* at, int first, int count);

// What the rest pose says about one joint's error: its child directions and its weight.
struct JointGeometry {
  // Unit vectors from the joint towards its children, in the joint's local frame (before
  // its animated rotation, ignoring its scale). A zero-length child is followed down every
  // branch to the first descendants with a non-zero offset, composing the rest transforms
  // in between. Empty for a leaf (E_pos = 0).
  std::vector<glm::dvec3> directions;
  double radius = 0.0; // r_j, eq. (4): sum of |rest offset| over strict descendants, cm
};

// One entry per joint of `skeleton` (which must validate). Offsets shorter than
// `zeroLength` (cm) count as zero-length.
std::vector<JointGeometry> jointGeometry(const Skeleton& skeleton, double zeroLength = 1e-6);

// One joint's motion, prepared for many error evaluations: rotations renormalised in
// double precision and the child directions rotated, once per frame. Memory:
// (56 + 36 x directions) bytes per frame (bytesFor()).
class JointTrack {
public:
  JointTrack() = default;
  // `rotations`: the joint's local rotation per frame (at least one frame, finite, unit
  // within 1e-3); alpha in cm, >= 0.
  JointTrack(const JointGeometry& geometry, double alpha, std::span<const glm::quat> rotations);

  // The bytes a track of `frames` frames with `directionCount` child directions holds.
  static std::size_t bytesFor(int frames, int directionCount) {
    const std::size_t directions = static_cast<std::size_t>(directionCount);
    return static_cast<std::size_t>(frames) * (sizeof(glm::dquat) + directions * sizeof(glm::dvec3) + 2 * sizeof(int) +
                                               (3 * directions + 4) * sizeof(float));
  }

  int frameCount() const { return m_frames; }
  double alpha() const { return m_alpha; }
  double radius() const { return m_radius; }
  int directionCount() const { return m_directionCount; }
  // The largest value error() can take: r_j * 180 (when the joint has a direction) +
  // alpha * 180, raised by a relative 1e-12 so that rounding never exceeds it.
  double maxError() const { return m_maxError; }

  // E_j(t, ref) in cm·degrees, eq. (1).
  double error(int t, int ref) const {
    double position = 0.0;
    if (m_directionCount > 0 && m_radius > 0.0) {
      const glm::dvec3* a = &m_directions[static_cast<std::size_t>(t) * static_cast<std::size_t>(m_directionCount)];
      const glm::dvec3* b = &m_directions[static_cast<std::size_t>(ref) * static_cast<std::size_t>(m_directionCount)];
      double theta = directionAngleDegrees(a[0], b[0]);
      for (int d = 1; d < m_directionCount; ++d)
        theta = std::max(theta, directionAngleDegrees(a[d], b[d])); // eq. (5): the largest
      position = m_radius * theta;
    }
    if (m_alpha > 0.0)
      return position + m_alpha * rotationAngleDegrees(m_rotations[static_cast<std::size_t>(t)],
                                                       m_rotations[static_cast<std::size_t>(ref)]);
    return position;
  }

  // A fast approximation of error(t, ref) for the `count` frames t = first, first + 1, ...,
  // written to out[0 .. count): float SIMD (AVX2 where the CPU has it). Every value is
  // within approximationBound() of error(t, ref). Used only to decide what is clearly
  // inside or outside a threshold; anything closer than the bound is evaluated exactly,
  // so no result depends on it.
  void approximateErrors(int ref, int first, int count, float* out) const;
  // cm·degrees; about 10x the largest difference measured (jpc_error_test.cpp).
  double approximationBound() const { return m_approximationBound; }

  // Frame t holds the same rotation as frame t - 1 (equal floats, up to the sign of the
  // quaternion), so error(t, x) == error(t - 1, x) exactly for every x. False for t = 0.
  bool sameAsPrevious(int t) const { return t > 0 && m_runFirst[static_cast<std::size_t>(t)] != t; }
  // First and last frame of the run of consecutive frames identical to frame t.
  int runFirst(int t) const { return m_runFirst[static_cast<std::size_t>(t)]; }
  int runLast(int t) const { return m_runLast[static_cast<std::size_t>(t)]; }

  // The normalised rotation and the rotated child directions (eq. (2)) at frame t.
  const glm::dquat& rotation(int t) const { return m_rotations[static_cast<std::size_t>(t)]; }
  std::span<const glm::dvec3> directions(int t) const {
    return {m_directions.data() + static_cast<std::size_t>(t) * static_cast<std::size_t>(m_directionCount),
            static_cast<std::size_t>(m_directionCount)};
  }

private:
  int m_frames = 0;
  int m_directionCount = 0;
  double m_radius = 0.0;
  double m_alpha = 0.0;
  double m_maxError = 0.0;
  std::vector<glm::dquat> m_rotations;  // per frame
  std::vector<glm::dvec3> m_directions; // [frame * directionCount + d]
  std::vector<int> m_runFirst;          // per frame
  std::vector<int> m_runLast;           // per frame
  // Float copies for approximateErrors(), one array per component:
  // [(3 d + axis) * frames + t] for the directions, then w, x, y, z of the rotations.
  std::vector<float> m_approximate;
  double m_approximationBound = 0.0;
};

} // namespace mlod
