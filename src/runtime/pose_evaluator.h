#pragma once
// The crowd pose evaluator (docs/architecture.md section 5; Ahn & Wohn, "Motion Level-of-Detail",
// section 4: "our system transforms the key posture and current joint's information is
// updated to his parent, until current clustered area of joint is finished").
//
// For every character of a crowd (a LodClip = the level it plays, and a time in seconds)
// PoseEvaluatorJob writes the model-space matrices of its joints and its skinning palette
// (model x inverse bind). Per character, at frame position f = time x fps, i0 = floor(f):
// - a *moving* joint (rotation outside a cluster's frozen frames, or an animated
//   translation or scale) has its two entries around f decoded from the clip's compressed
//   streams (internal/compressed_tracks.h), its rotation nlerped, translation and scale
//   lerped;
// - a *frozen* joint (both frames among one cluster's frozen frames) keeps the key it
//   decoded when its cluster began: the character's pose holds it, and a span per joint
//   (the frames over which nothing changes) finds it again in two compares;
// - a joint the clip never moves (BVH end sites) keeps its static values, written once
//   when the character starts the clip;
// - the local matrices are made 8 joints at once from the pose, and the hierarchy pass is
//   the same two products (model = parent's model x local; palette = model x inverse bind)
//   for every joint, without a branch on its kind.
//
// With blendFrames = 0 the result is forward kinematics of the simplified motion M'(t) as
// the clip stores it (LodClip::rotationAt() etc.). With blendFrames = N > 0, joints resume
// without popping:
// - after a cluster ends, as LodClip describes: the clip is built for N and stores the
//   blended frames (LodClipSource::blendFrames; the job refuses a clip with clusters
//   built for another N);
// - at a looping clip's wrap (from the second period on, for f < N): the jump from the
//   pose at the last frame to the pose at frame 0 decays over N frames (rotations; the
//   root's translation wraps as the clip does: root motion is the caller's business);
// - when a character's clip changes (a level switch, or another motion), every rotation
//   that differs decays from the old clip's to the new clip's over N frames of the new
//   clip, starting at the time of the first run with the new clip. This one depends on
//   the character's history; PoseEvaluatorContext keeps it.
// A blending joint's rotation is multiplied by its offsets before it becomes a matrix
// (unnormalised: the matrix divides by the squared length), in a copy of the pose, so that
// the keys it holds stay as they are. Translations are never blended.
//
// Cost: the job never allocates; the context holds every buffer, sized once. Characters
// are spread over the threads of an optional WorkerPool; the result does not depend on
// the thread count (each character's output depends on its own inputs and state alone).
//
// Clip lifetime: a character's state keeps the `const LodClip*` of its last run, keys,
// region cursors and spans of it, and reads that clip again at a level switch (to blend from what it
// showed). Before a clip is freed or moved, reset the characters that played it
// (PoseEvaluatorContext::reset()).

#include "runtime/lod_clip.h"
#include "runtime/worker_pool.h"

#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <span>
#include <string>
#include <vector>

namespace mlod {

struct PoseEvaluation; // the implementation (pose_evaluator.cpp)

namespace internal {
// Per character and joint whose rotation animates: the frames i0 in [from, until) over
// which its rotation needs no look-up: its pose holds its cluster's key (delta ==
// kHeldKey), or it decodes entry i0 + delta and the next (internal/pose_decode.inl).
struct JointSpan {
  static constexpr std::int32_t kHeldKey = INT32_MIN;
  std::int32_t from = 0;
  std::int32_t until = 0; // empty: look it up
  std::int32_t delta = 0;
};
} // namespace internal

// The caller-owned state and scratch of PoseEvaluatorJob: per character, the clip of its
// last run and its level-change blend (start, offsets); per thread, sampling buffers.
// Allocates in resize() only.
class PoseEvaluatorContext {
public:
  PoseEvaluatorContext() = default;
  PoseEvaluatorContext(int characters, int joints, int threads = 1) { resize(characters, joints, threads); }

  // Sizes the context for up to `characters` characters of `joints` joints evaluated on up
  // to `threads` threads (the WorkerPool's threadCount()). Forgets every character's state.
  // Per character it holds the pose (40 bytes a joint) and four words a joint.
  void resize(int characters, int joints, int threads = 1);
  // Forgets every character's state (the clip of its last run: no level blend follows).
  // Call it after changing the skeleton's inverse binds in place.
  void reset();
  void reset(int character);

  int characterCount() const { return static_cast<int>(m_states.size()); }
  int jointCount() const { return m_joints; }
  int threadCount() const { return static_cast<int>(m_scratch.size()); }
  // Bytes of per-character state (what an engine pays per character, outputs excluded).
  std::size_t bytesPerCharacter() const;
  std::size_t byteSize() const;

  // Statistics of the last run, summed over characters: joints whose local matrix was
  // computed (sampled or blended).
  std::int64_t jointsSampled() const { return m_lastSampled; }

private:
  friend struct PoseEvaluation;
  friend struct PoseEvaluatorJob;
  struct CharacterState {
    const LodClip* clip = nullptr; // the clip of the last run
    std::int32_t blendFrames = 0;  // of the last run
    bool levelBlend = false;       // a level-change blend is under way
    double levelStart = 0.0;       // seconds
    double levelSeconds = 0.0;
  };
  struct alignas(64) Scratch {
    std::vector<float> samples;         // a blending character's pose, copied to take its offsets
    std::vector<float> locals;          // a character's local matrices, lane layout (LodClip::laneOffset())
    std::vector<glm::mat4> models;      // model matrices when the job has no out_models
    std::vector<glm::quat> wrapOffsets; // a looping clip's wrap offsets (they depend on the clip alone)
    const LodClip* wrapClip = nullptr;  // the clip of wrapOffsets (none at the start of a run)
    bool singleRoot = true; // joint 0 is the only root (the job's skeleton)
    std::int64_t sampled = 0;
  };

  int m_joints = 0;
  std::vector<CharacterState> m_states;
  std::vector<glm::quat> m_levelOffset;     // per character x joint
  // Per character: its pose (rotations, scales, translations of its joints, blocks of 8:
  // pose_evaluator.cpp), and per joint the region of its clip it was last in and its span.
  std::vector<float> m_pose;
  std::size_t m_poseFloats = 0;
  std::vector<std::uint32_t> m_cursor;
  std::vector<internal::JointSpan> m_span;
  std::vector<float> m_splat;               // the job's inverse binds laid out for the palette product
  const void* m_inverseBindsSeen = nullptr; // the inverse binds m_splat holds
  std::vector<Scratch> m_scratch;
  std::int64_t m_lastSampled = 0;
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
  // Frames over which a resuming joint blends back (0 = off: exactly M'(t)). A clip with
  // clusters must be built for it (LodClip::blendFrames(): its windows are stored).
  int blendFrames = 0;
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
  // duration (a frame position <= frameCount - 1 + 1e-6); blendFrames in [0, kMaxBlendFrames] and
  // equal to the blendFrames() of every clip with clusters;
  // out_palette characters x joints; out_models empty or characters x joints.
  // Returns false and, where out_error is given, says which rule the job breaks.
  bool validate(std::string* out_error = nullptr) const;
  // Returns false (and writes nothing) when validate() fails.
  bool run() const;
};

} // namespace mlod
