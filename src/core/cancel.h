#pragma once
// One cancel flag for long work in core (issue 29): the CLI's SIGINT/SIGTERM handler and the
// studio's Cancel button set it, and the loops that can run for long (JPC's per-joint loop,
// the progressive mesh's collapses, mesh LOD's poses, the pixel-budget search, the package's
// levels) look at it often enough to stop well within a second.
//
// The flag is a `const std::atomic<bool>*` the caller owns; null means never cancelled. It is
// a run-time setting: never saved, never compared, and it must outlive the work it is given
// to (and any object that keeps it, such as a MeshLod's settings).

#include <atomic>

namespace mlod {

// True once `cancel` (may be null) is set.
inline bool cancelled(const std::atomic<bool>* cancel) {
  return cancel != nullptr && cancel->load(std::memory_order_relaxed);
}

// What a cancelled step below the LOD set and package returns (MeshLod::build,
// LodCharacter); LodSet::fromPixelBudget and buildLodPackage answer with their own
// kLodBudgetCancelled and kLodPackageCancelled.
inline constexpr const char* kCancelled = "cancelled";

} // namespace mlod
