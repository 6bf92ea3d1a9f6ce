#pragma once
// The crowd pose evaluator (docs/architecture.md section 5; Ahn & Wohn, "Motion Level-of-Detail",
// section 4: "our system transforms the key posture and current joint's information is
// updated to his parent, until current clustered area of joint is finished").
//
// For every character of a crowd (a LodClip = the level it plays, and a time in seconds)
// PoseEvaluatorJob writes the model-space matrices of its joints and its skinning palette
// (model x inverse bind). Per character and joint, at frame position f = time x fps:
// - an *active* joint is sampled: its rotation nlerped between the two frames around f,
//   translation and scale lerped, turned into a local matrix, composed with its parent's;
// - a *frozen* joint (inside a cluster, translation and scale static) or a static one (a
//   joint the clip never moves: BVH end sites) takes its constant local matrix: no
//   sampling, no quaternion work, but still one product for its model matrix and one for
//   its palette entry.
// - folding: in a palette-only job (no out_models), a frozen joint whose model matrix
//   nobody needs (no active joint below it) is folded: F, the product of the constant
//   local matrices from its nearest ancestor A with a model matrix down to it, and
//   F x inverse bind are kept per character, so it costs one product (model_A x F x IB).
//   Where model matrices are written, every joint's is computed anyway and a folded one
//   would cost the same product, so nothing folds.
// The plan (which joints are active, where their rotations are read, the folds) is
// rebuilt incrementally: a character stepping forward re-reads only the joints with an
// event in between (a cluster starts or ends, an unfreeze window ends), from the clip's
// per-frame event lists ("hierarchy reconstruction", the paper's cost of variable
// motion); a jump back or far ahead re-reads every joint.
//
// With blendFrames = 0 the result is forward kinematics of the simplified motion M'(t)
// (LodClip::rotationAt() etc.). With blendFrames = N > 0, joints resume without popping:
// - after a cluster ends, as LodClip describes (a property of the clip and f alone);
// - at a looping clip's wrap (from the second period on, for f < N): the jump from the
//   pose at the last frame to the pose at frame 0 decays over N frames (rotations; the
//   root's translation wraps as the clip does: root motion is the caller's business);
// - when a character's clip changes (a level switch, or another motion), every rotation
//   that differs decays from the old clip's to the new clip's over N frames of the new
//   clip, starting at the time of the first run with the new clip. This one depends on
//   the character's history; PoseEvaluatorContext keeps it.
// Translations are never blended.
//
// Cost: the job never allocates; the context holds every buffer, sized once. Characters
// are spread over the threads of an optional WorkerPool; the result does not depend on
// the thread count (each character's output depends on its own inputs and state alone).

#include "runtime/lod_clip.h"
#include "runtime/worker_pool.h"

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace mlod {

struct PoseEvaluation; // the implementation (pose_evaluator.cpp)

// The caller-owned state and scratch of PoseEvaluatorJob: per character, the plan of its
// current interval (which joints are active, cursors into the clip, folded matrices, blend
// offsets); per thread, structure-of-arrays sampling buffers. Allocates in resize() only.
class PoseEvaluatorContext {
public:
  PoseEvaluatorContext() = default;
  PoseEvaluatorContext(int characters, int joints, int threads = 1) { resize(characters, joints, threads); }

  // Sizes the context for up to `characters` characters of `joints` joints evaluated on up
  // to `threads` threads (the WorkerPool's threadCount()). Forgets every character's state.
  void resize(int characters, int joints, int threads = 1);
  // Forgets every character's state (cursors, folds, the clip of its last run: no level
  // blend follows). Call it after changing the skeleton's inverse binds in place.
  void reset();
  void reset(int character);

  int characterCount() const { return static_cast<int>(m_states.size()); }
  int jointCount() const { return m_joints; }
  int threadCount() const { return static_cast<int>(m_scratch.size()); }
  // Bytes of per-character state (what an engine pays per character, outputs excluded).
  std::size_t bytesPerCharacter() const;
  std::size_t byteSize() const;

  // Statistics of the last run, summed over characters: joints whose local matrix was
  // computed (sampled or blended), and characters whose plan was rebuilt.
  std::int64_t jointsSampled() const { return m_lastSampled; }
  std::int64_t planRebuilds() const { return m_lastRebuilds; }

private:
  friend struct PoseEvaluation;
  friend struct PoseEvaluatorJob;
  struct CharacterState {
    const LodClip* clip = nullptr; // the clip of the last run (its plan is below)
    bool planValid = false;
    bool folding = false;          // settings the plan was made with
    bool models = false;
    std::int32_t blendFrames = 0;
    std::int32_t i0 = 0;           // the frame the plan was made at
    std::int64_t loop = 0;
    bool wrapWindow = false;
    bool levelBlend = false;
    double levelStart = 0.0;       // seconds
    double levelSeconds = 0.0;
    std::int32_t activeCount = 0;
  };
  struct alignas(64) Scratch {
    std::vector<float> soa;             // the active joints' sampling buffers, in blocks of 8 (AoSoA)
    std::vector<glm::mat4> models;      // model matrices when the job has no out_models
    std::vector<glm::mat4> locals;      // the active joints' local matrices, in active order
    std::vector<std::int16_t> blending; // (joint, lane) of the joints that blend this frame
    std::vector<std::uint8_t> changed;  // all 0 between rebuilds
    std::vector<std::uint8_t> foldChanged;
    std::int64_t sampled = 0;
    std::int64_t rebuilds = 0;
  };

  int m_joints = 0;
  std::size_t m_blocks = 0; // blocks of 8 joints
  std::size_t m_words = 0;  // 64-bit words of a joint set
  std::vector<CharacterState> m_states;
  // per character x joint
  std::vector<std::int32_t> m_cursor;
  std::vector<std::uint8_t> m_status;
  std::vector<std::int32_t> m_rotationIndex;
  std::vector<std::int32_t> m_rotationStep;
  std::vector<std::int32_t> m_windowLatest;
  std::vector<std::int32_t> m_windowCount;
  std::vector<const glm::mat4*> m_constLocal; // constant joints: their local matrix in the clip
  std::vector<glm::mat4> m_local;             // constant joints: a copy of it
  std::vector<std::int16_t> m_anchor;
  std::vector<std::uint8_t> m_needModel;
  // per character x word: the active joints (bit j % 64 of word j / 64)
  std::vector<std::uint64_t> m_activeSet;
  std::vector<glm::mat4> m_fold;        // frozen: F relative to the anchor
  std::vector<glm::mat4> m_foldPalette; // frozen: F x inverse bind
  std::vector<glm::quat> m_levelOffset;
  std::vector<glm::quat> m_wrapOffset;
  std::vector<Scratch> m_scratch;
  const void* m_parentsSeen = nullptr; // the skeleton arrays the folds were made with
  const void* m_inverseBindsSeen = nullptr;
  std::int64_t m_lastSampled = 0;
  std::int64_t m_lastRebuilds = 0;
};

struct PoseEvaluatorJob {
  // The skeleton: parent of each joint, parents before children, -1 for a root. The joint
  // count is parents.size() (1 to 32767).
  std::span<const std::int16_t> parents;
  // Mesh space -> joint space at bind time, one per joint, affine (bottom row 0 0 0 1);
  // palette = model x inverse bind (cm).
  std::span<const glm::mat4> inverseBinds;
  // Per character: the clip it plays (its LOD level; the skeleton's joint count; never
  // null) and its time in seconds: finite, >= 0, and <= duration() unless the clip loops.
  std::span<const LodClip* const> clips;
  std::span<const double> times;
  // Frames over which a resuming joint blends back (0 = off: exactly M'(t)).
  int blendFrames = 0;
  // Fold frozen chains whose model matrices are not needed (palette-only jobs; see above).
  bool folding = true;
  // Threads to spread characters over; null = the calling thread only.
  WorkerPool* pool = nullptr;
  // State and scratch, sized for at least clips.size() characters of this skeleton and
  // pool's thread count. Character i's state is the context's entry i.
  PoseEvaluatorContext* context = nullptr;
  // Outputs, character-major ([character * joints + joint]): model-space matrices (cm;
  // may be empty when only the palette is wanted) and the skinning palette.
  std::span<glm::mat4> out_models;
  std::span<glm::mat4> out_palette;

  // Rules: a context sized as above; parents valid; inverseBinds one per joint and affine;
  // clips and times one per character; every clip non-null with the skeleton's joint
  // count; every time finite, >= 0 and, for a clip that does not loop, at most its
  // duration (a frame position <= frameCount - 1 + 1e-6); blendFrames in [0, 10000];
  // out_palette characters x joints; out_models empty or characters x joints.
  bool validate() const;
  // Returns false (and writes nothing) when validate() fails.
  bool run() const;
};

} // namespace mlod
