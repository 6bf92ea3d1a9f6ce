// The approximate JPC error kernel (JointTrack::approximateErrors): eqs. (1)-(6) in float,
// vectorised. Built with -fno-math-errno and -fno-trapping-math so that the loops
// vectorise; on x86-64 they are also compiled for AVX2 and picked at load time.
#include "core/jpc/posture_error.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && !defined(MLOD_NO_TARGET_CLONES)
#define MLOD_TARGET_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define MLOD_TARGET_CLONES
#endif

namespace mlod {

namespace {
constexpr float kPi = 3.14159265358979f;

// atan2(y, x) for y >= 0, radians: octant reduction to [0, 1], then to [0, tan(pi/8)],
// and Cephes' atanf polynomial there. Branch-free (selects, not branches) so that the
// loops vectorise; the largest error measured is 2.7e-7 radians.
inline float atan2Approximate(float y, float x) {
  const float ax = std::fabs(x);
  const float hi = std::max(ax, y), lo = std::min(ax, y);
  // lo / hi past tan(pi/8) becomes (lo / hi - 1) / (lo / hi + 1): one division either way
  const bool reduce = lo > 0.41421356f * hi;
  const float z0 = (reduce ? lo - hi : lo) / (reduce ? lo + hi : std::max(hi, 1e-30f));
  const float z = z0 * z0;
  float p =
      (((8.05374449538e-2f * z - 1.38776856032e-1f) * z + 1.99777106478e-1f) * z - 3.33329491539e-1f) * z * z0 + z0;
  p += reduce ? 0.25f * kPi : 0.0f;
  p = y > ax ? 0.5f * kPi - p : p;
  return x < 0.0f ? kPi - p : p;
}

// eqs. (2), (3): the angle of one child direction, kept where larger (eq. (5)).
inline void directionAngles(const float* __restrict x, const float* __restrict y, const float* __restrict z, float bx,
                            float by, float bz, int count, float* __restrict out) {
  for (int i = 0; i < count; ++i) {
    const float cx = y[i] * bz - z[i] * by, cy = z[i] * bx - x[i] * bz, cz = x[i] * by - y[i] * bx;
    const float sine = std::sqrt(cx * cx + cy * cy + cz * cz);
    const float cosine = x[i] * bx + y[i] * by + z[i] * bz;
    out[i] = std::max(out[i], atan2Approximate(sine, cosine));
  }
}

// eq. (6) times `scale`, added to out (eq. (1)).
inline void addRotationAngles(const float* __restrict w, const float* __restrict x, const float* __restrict y,
                              const float* __restrict z, float bw, float bx, float by, float bz, float scale, int count,
                              float* __restrict out) {
  for (int i = 0; i < count; ++i) {
    const float dot = w[i] * bw + x[i] * bx + y[i] * by + z[i] * bz;
    const float s = std::copysign(1.0f, dot); // the sign of -0 does not matter: a and b are then orthogonal
    const float dw = w[i] - s * bw, dx = x[i] - s * bx, dy = y[i] - s * by, dz = z[i] - s * bz;
    const float pw = w[i] + s * bw, px = x[i] + s * bx, py = y[i] + s * by, pz = z[i] + s * bz;
    const float minus = std::sqrt(dw * dw + dx * dx + dy * dy + dz * dz);
    const float plus = std::sqrt(pw * pw + px * px + py * py + pz * pz);
    out[i] += scale * atan2Approximate(minus, plus);
  }
}

struct KernelInput {
  const float* data; // JointTrack::m_approximate
  int frames;
  int directions;
  float positionScale; // r * degrees per radian; 0 without E_pos
  float rotationScale; // 4 * alpha * degrees per radian; 0 without E_ori
};

MLOD_TARGET_CLONES
void approximateKernel(const KernelInput& in, int ref, int first, int count, float* out) {
  const std::size_t n = static_cast<std::size_t>(in.frames);
  const std::size_t r = static_cast<std::size_t>(ref), f = static_cast<std::size_t>(first);
  std::fill(out, out + count, 0.0f);
  if (in.positionScale > 0.0f) {
    for (int d = 0; d < in.directions; ++d) {
      const float* x = in.data + (3 * static_cast<std::size_t>(d)) * n;
      const float* y = x + n;
      const float* z = y + n;
      directionAngles(x + f, y + f, z + f, x[r], y[r], z[r], count, out);
    }
    for (int i = 0; i < count; ++i)
      out[i] *= in.positionScale;
  }
  if (in.rotationScale > 0.0f) {
    const float* w = in.data + (3 * static_cast<std::size_t>(in.directions)) * n;
    const float* x = w + n;
    const float* y = x + n;
    const float* z = y + n;
    addRotationAngles(w + f, x + f, y + f, z + f, w[r], x[r], y[r], z[r], in.rotationScale, count, out);
  }
}
MLOD_TARGET_CLONES
double landmarkKernel(const float* rows, int landmarks, std::size_t stride, const float* at, int first, int count) {
  float largest[256];
  std::fill(largest, largest + count, 0.0f);
  for (int p = 0; p < landmarks; ++p) {
    const float* row = rows + static_cast<std::size_t>(p) * stride + first;
    const float value = at[p];
    for (int t = 0; t < count; ++t)
      largest[t] = std::max(largest[t], std::fabs(row[t] - value));
  }
  // eight running sums: vectorises without reassociating a single sum
  float lanes[8] = {};
  int t = 0;
  for (; t + 8 <= count; t += 8)
    for (int l = 0; l < 8; ++l)
      lanes[l] += largest[t + l];
  double sum = 0.0;
  for (; t < count; ++t)
    sum += largest[t];
  for (float lane : lanes)
    sum += lane;
  return sum;
}
} // namespace

double landmarkDistanceSum(const float* rows, int landmarks, std::size_t stride, const float* at, int first,
                           int count) {
  assert(count >= 0 && count <= 256);
  return landmarkKernel(rows, landmarks, stride, at, first, count);
}

void JointTrack::approximateErrors(int ref, int first, int count, float* out) const {
  KernelInput in;
  in.data = m_approximate.data();
  in.frames = m_frames;
  in.directions = m_directionCount;
  in.positionScale = m_directionCount > 0 && m_radius > 0.0 ? static_cast<float>(m_radius * kDegreesPerRadian) : 0.0f;
  in.rotationScale = m_alpha > 0.0 ? static_cast<float>(4.0 * m_alpha * kDegreesPerRadian) : 0.0f;
  approximateKernel(in, ref, first, count, out);
}

} // namespace mlod
