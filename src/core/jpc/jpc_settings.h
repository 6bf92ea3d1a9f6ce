#pragma once
// Settings of joint posture clustering (JPC, docs/architecture.md sections 3 and 4).
//
// Units: thresholds are errors E in cm·degrees (the paper's Table 1 uses 5, 50, 100, 300;
// E / 57.3 is roughly a displacement in cm); alpha weighs the orientation error and is a
// length in cm (alpha = 5: one degree of twist counts like one degree of swing of a 5 cm
// segment).

#include "core/error.h"
#include "core/skeleton.h"

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace mlod {

inline constexpr double kDefaultJpcAlpha = 5.0; // cm

// How the clusters of one joint are chosen under the error bound.
enum class JpcMode {
  Greedy,  // the paper's STEPs 1-6: the longest row range first
  Optimal, // the partition that covers the most frames, then has the fewest clusters
};

const char* toString(JpcMode mode);                           // "greedy", "optimal"
std::optional<JpcMode> parseJpcMode(const std::string& text); // inverse of toString()

// Per-joint settings (docs/architecture.md section 3). Everything absent falls back to JpcSettings.
struct JointSettings {
  std::optional<double> alpha; // cm, >= 0; absent = JpcSettings::alpha
  // Threshold override per LOD level (index = level), cm·degrees, >= 0. An absent entry,
  // or a level past the end, uses that level's threshold.
  std::vector<std::optional<double>> thresholds;
  bool locked = false; // never simplified, whatever the threshold
  // Mesh importance (finite, > 0): scales the collapse cost of the vertices the joint
  // influences, weighted by the skin (core/mesh/mesh_lod.h); raise it for the face or hands.
  double meshImportance = 1.0;
  friend bool operator==(const JointSettings&, const JointSettings&) = default;
};

struct JpcSettings {
  double alpha = kDefaultJpcAlpha; // cm, >= 0: the orientation weight of every joint without its own
  JpcMode mode = JpcMode::Greedy;
  // Child offsets shorter than this are zero-length (followed down to the next non-zero
  // ones, docs/architecture.md section 4), cm. The rule is 1e-6 file units: pass 1e-6 x the asset's
  // unit scale.
  double zeroLength = 1e-6;
  std::map<std::string, JointSettings> joints; // by joint name; a joint not listed takes the defaults
  friend bool operator==(const JpcSettings&, const JpcSettings&) = default;

  // alpha of joint `name` (JointSettings::alpha, else `alpha`).
  double alphaFor(const std::string& name) const;
  // Threshold T_j of joint `name` at LOD level `level` whose own threshold is
  // `levelThreshold` (cm·degrees).
  double thresholdFor(const std::string& name, int level, double levelThreshold) const;
  bool lockedFor(const std::string& name) const;
  double meshImportanceFor(const std::string& name) const; // 1 for a joint not listed

  // Rules: alpha finite and >= 0; zeroLength finite and >= 0; every joint name exists in
  // `skeleton`; every per-joint alpha and threshold finite and >= 0; mesh importances
  // finite and > 0.
  Error validate(const Skeleton& skeleton) const;
};

// Rules: a threshold is finite and >= 0. `what` names it in the message ("threshold 2").
Error validateThreshold(double threshold, const std::string& what = "threshold");
// Rules: alpha is finite and >= 0 (cm). `what` names it in the message ("alpha of joint 'Neck'").
// The one place the rule lives: settings, projects, the CLI's --alpha and the editor use it.
Error validateAlpha(double alpha, const std::string& what = "alpha");
// Rules: a joint's mesh importance is finite and > 0. `what` names it in the message.
Error validateMeshImportance(double importance, const std::string& what = "the mesh importance");

} // namespace mlod
