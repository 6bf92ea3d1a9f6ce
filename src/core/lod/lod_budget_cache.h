#pragma once
// What a pixel budget's level search (lod_set.h, LodSet::fromPixelBudget) keeps between runs
// on one character, so that a search asked again (the studio's Budget preview with another
// pixel budget, level count or projection, or after a joint edit) computes only what it has
// not computed before (issue 26): the prepared character (its JPC tracks and bounding
// radius), every joint clustering made (lod_character.h), every level motion tried (by level
// slot and threshold), the progressive mesh of every motion whose mesh was simplified (one
// progressive mesh serves every ratio) and the levels measured on it (by ratio).
//
// What it holds is checked against each run's inputs, by value: another skeleton, mesh, clip
// or mesh setting starts afresh; other JPC settings keep the character and the joint
// clusterings whose key is unchanged (so an edit of one joint re-clusters that joint alone)
// and drop the motions and meshes, which depend on every joint. So a run with a cache gives
// the same levels, to the bit, as one without.
//
// Not thread-safe: one run at a time may use a cache; nothing in it refers to a run's cancel
// flag once the run has returned. A cancelled or failed run keeps only what it finished.
// Implemented in lod_set.cpp.

#include <memory>

namespace mlod {

class LodBudgetCache {
public:
  LodBudgetCache();
  ~LodBudgetCache();
  LodBudgetCache(LodBudgetCache&&) noexcept;
  LodBudgetCache& operator=(LodBudgetCache&&) noexcept;

  // Forgets everything (the next run starts afresh).
  void clear();
  // True when nothing is kept.
  bool empty() const { return m_state == nullptr; }

  struct State; // lod_set.cpp

private:
  friend class LodBudgetRun;
  std::unique_ptr<State> m_state;
};

} // namespace mlod
