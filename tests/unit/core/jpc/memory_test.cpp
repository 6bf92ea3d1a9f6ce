// Guards the memory of simplifyClip() on a long clip (docs/user-guide.md, the memory
// table): beyond the clip, its peak heap stays within the decoded clip itself, so the
// command line's `simplify` stays within twice the decoded clip plus a fixed overhead.
// Counted, not timed: this program replaces the global operator new and delete and
// records the peak of the bytes held (malloc_usable_size), which depends on neither the
// machine's speed nor its load. Not built with the sanitizers (they own operator new).

#include "core/jpc/jpc.h"
#include "unit/core/jpc/fixtures.h"
#include "unit/real_files.h"

#include <atomic>
#include <cstdlib>
#include <gtest/gtest.h>
#include <malloc.h>
#include <new>

namespace {
std::atomic<std::size_t> g_held{0};
std::atomic<std::size_t> g_peak{0};

void* counted(void* pointer) {
  if (!pointer)
    throw std::bad_alloc();
  const std::size_t held = g_held.fetch_add(malloc_usable_size(pointer)) + malloc_usable_size(pointer);
  std::size_t peak = g_peak.load();
  while (held > peak && !g_peak.compare_exchange_weak(peak, held)) {
  }
  return pointer;
}

void released(void* pointer) noexcept {
  if (!pointer)
    return;
  g_held.fetch_sub(malloc_usable_size(pointer));
  std::free(pointer);
}

void* alignedNew(std::size_t size, std::align_val_t alignment) {
  const std::size_t align = static_cast<std::size_t>(alignment);
  return counted(std::aligned_alloc(align, (size + align - 1) / align * align));
}
} // namespace

void* operator new(std::size_t size) {
  return counted(std::malloc(size == 0 ? 1 : size));
}
void* operator new[](std::size_t size) {
  return counted(std::malloc(size == 0 ? 1 : size));
}
void* operator new(std::size_t size, std::align_val_t alignment) {
  return alignedNew(size, alignment);
}
void* operator new[](std::size_t size, std::align_val_t alignment) {
  return alignedNew(size, alignment);
}
void operator delete(void* pointer) noexcept {
  released(pointer);
}
void operator delete[](void* pointer) noexcept {
  released(pointer);
}
void operator delete(void* pointer, std::size_t) noexcept {
  released(pointer);
}
void operator delete[](void* pointer, std::size_t) noexcept {
  released(pointer);
}
void operator delete(void* pointer, std::align_val_t) noexcept {
  released(pointer);
}
void operator delete[](void* pointer, std::align_val_t) noexcept {
  released(pointer);
}
void operator delete(void* pointer, std::size_t, std::align_val_t) noexcept {
  released(pointer);
}
void operator delete[](void* pointer, std::size_t, std::align_val_t) noexcept {
  released(pointer);
}

namespace mlod {
namespace {

std::size_t decodedBytes(const Clip& clip) {
  return clip.rotations.size() * sizeof(glm::quat) +
         (clip.translations.size() + clip.scales.size()) * sizeof(glm::vec3);
}

// The peak heap simplifyClip() adds to what is held before it, on 8 threads whatever the
// machine has (the most joints at once that their buffers allow).
std::size_t simplifyPeak(const Asset& asset, const Clip& clip, JpcMode mode, const std::vector<double>& thresholds) {
  JpcSettings settings;
  settings.mode = mode;
  settings.zeroLength = 1e-6 * asset.unitScale;
  const std::size_t before = g_held.load();
  g_peak.store(before);
  Result<std::vector<JpcLevelResult>> levels = simplifyClip(asset.skeleton, clip, settings, thresholds, 8);
  const std::size_t peak = g_peak.load();
  EXPECT_TRUE(levels) << levels.message();
  return peak - before;
}

// Guards the 2x goal of the memory table: simplifyClip() once held every joint's error
// track at once, 2.3 times the decoded clip (3.4 times in all with the clip and its joint
// positions, 1,018,748 KB at 200,000 frames). Now it holds the joint positions (12 bytes
// per joint-frame, 0.3 times the clip) and the buffers of the joints in flight, within
// the larger of 16 MiB and half the clip: at most 0.8 times the clip. Each clip here is
// repeated to 35 MiB (CMU 01_01: 24,000 frames), so half of it exceeds the 16 MiB floor.
// Greedy at the command line's T = 50 and at T = 300 (96% simplified: long clusters, the
// larger key-posture buffers); optimal at T = 50 (row starts kept too). On every clip of the
// shared fixture list.
class JpcMemory : public ::testing::TestWithParam<std::string> {};

TEST_P(JpcMemory, SimplifyHoldsAtMostTheDecodedClipBesideIt) {
  const Asset& asset = test::realAsset(GetParam());
  const Clip& source = asset.clips.front();
  const std::size_t perFrame = decodedBytes(source) / static_cast<std::size_t>(source.frameCount);
  const Clip clip = test::repeated(source, static_cast<int>((std::size_t{35} << 20) / perFrame) + 1);
  const std::size_t decoded = decodedBytes(clip);
  ASSERT_GT(decoded, 2 * kSimplifyWorkingBytes);
  const std::size_t greedy = simplifyPeak(asset, clip, JpcMode::Greedy, {50.0, 300.0});
  const std::size_t optimal = simplifyPeak(asset, clip, JpcMode::Optimal, {50.0});
  EXPECT_LE(greedy, decoded) << "greedy: " << greedy << " bytes beside a decoded clip of " << decoded;
  EXPECT_LE(optimal, decoded) << "optimal: " << optimal << " bytes beside a decoded clip of " << decoded;
  std::printf("%s: decoded clip %zu bytes; simplifyClip peak beside it: greedy %zu, optimal %zu\n",
              GetParam().c_str(), decoded, greedy, optimal);
}

INSTANTIATE_TEST_SUITE_P(Clips, JpcMemory, ::testing::ValuesIn(test::fixtureClips()), test::fixtureName);

} // namespace
} // namespace mlod
