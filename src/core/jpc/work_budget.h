#pragma once
// A bound on the work of joint posture clustering (issue 29: "simplify of any input finishes
// or is refused within 60 s"). The key-posture search grows faster than a cluster's length
// on some motions (about m^1.8 on a slow 3D wobble that stays within the threshold), so
// frame and joint-frame limits alone cannot bound its time. A JpcWorkBudget counts the work
// every joint and level of a clip spends, shared across threads; once past its limit the
// clustering stops and the caller refuses the clip, naming the limit.
//
// The unit is one frame of a float row (the approximate kernel's E(t, k), or the landmark
// kernel's frame against its landmark rows); an exact E(t, k) (two atan2, in double) costs
// about as much as kExactEvaluationUnits of those, and counts so. The total a clip needs
// does not depend on threads or timing, so whether a clip is refused is deterministic; only
// how far it got before stopping is not.

#include <atomic>
#include <cstdint>
#include <string>

namespace mlod {

inline constexpr std::int64_t kExactEvaluationUnits = 32;

// The default limit of one simplify (every joint and threshold of a clip). Measured on the
// development machine (2 cores shared by three builds, 2026): about 0.75e9 units per second
// of one core, on float-bound and exact-bound searches alike, so about 20 s of one core,
// 10 s with two threads. A slow 3D wobble of 100,000 frames (scripts/wobble-bvh.py) takes
// about 12 s of one core per joint at thresholds 5 and 50, so 40 of them (the joint-frame
// limit) are refused; real motion needs far less per frame: CMU 01_01 (2,752 frames, 31
// joints) takes 0.35 s at thresholds 5, 50, 100 and 300, and the same clip looped to
// 99,072 frames (3.1 million joint-frames, 14 minutes) 22 s, within the limit.
inline constexpr std::int64_t kMaxJpcWork = 15'000'000'000;

class JpcWorkBudget {
public:
  explicit JpcWorkBudget(std::int64_t limit = kMaxJpcWork) : m_limit(limit) {}
  JpcWorkBudget(const JpcWorkBudget&) = delete;
  JpcWorkBudget& operator=(const JpcWorkBudget&) = delete;

  // Counts `units` more (>= 0); false once the total is past the limit, and from then on.
  bool spend(std::int64_t units) {
    return m_spent.fetch_add(units, std::memory_order_relaxed) + units <= m_limit;
  }
  bool exhausted() const { return m_spent.load(std::memory_order_relaxed) > m_limit; }
  std::int64_t limit() const { return m_limit; }
  // The units counted so far (past the limit: at least the limit, not the clip's total).
  std::int64_t spent() const { return m_spent.load(std::memory_order_relaxed); }

private:
  std::int64_t m_limit;
  std::atomic<std::int64_t> m_spent{0};
};

// Why a clip past `budget`'s limit is refused: `clip` needs more work than `what` takes (the
// limit, in units over `scope`), and what the user can do (`remedy`).
inline std::string workLimitMessage(const std::string& clip, const JpcWorkBudget& budget, const std::string& what,
                                    const std::string& scope, const std::string& remedy) {
  return "clip '" + clip + "' needs more work than " + what + " takes (at most " + std::to_string(budget.limit()) +
         " units of error evaluation " + scope + "): " + remedy;
}

// True where `budget` (may be null: no limit) is past its limit.
inline bool exhausted(const JpcWorkBudget* budget) { return budget != nullptr && budget->exhausted(); }

} // namespace mlod
