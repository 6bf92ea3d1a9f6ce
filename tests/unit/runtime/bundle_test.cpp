// The runtime bundle's reader and writer on a small synthetic bundle: round trip, and every
// kind of damage refused with a clear message (truncation at and inside every section,
// every single-byte flip, wrong magic and version, counts that lie under valid checksums).

#include "runtime/bundle.h"
#include "unit/runtime/play_bundle.h"

#include <gtest/gtest.h>

#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sys/stat.h>
#include <unistd.h>
#include <string>

namespace mlod {
namespace {

// Three joints in a chain, one clip of 12 frames (2 blend frames) with a cluster on joint 1,
// a two-triangle mesh; a second level without clusters or mesh.
Bundle smallBundle() {
  Bundle b;
  b.name = "chain";
  b.source = "synthetic";
  b.boundingRadiusCm = 30.0;
  b.jointNames = {"root", "mid", "tip"};
  b.jointParents = {-1, 0, 1};
  BundleLevel level;
  level.index = 1;
  level.name = "LOD1";
  level.motionThreshold = 5.0;
  level.switchDistanceCm = 500.0;
  level.fullJoints = {0, 1, 2};
  level.parents = {-1, 0, 1};
  for (int j = 0; j < 3; ++j) {
    glm::mat4 ib(1.0f);
    ib[3] = glm::vec4(0.0f, -10.0f * float(j), 0.0f, 1.0f);
    level.inverseBinds.push_back(ib);
  }
  std::vector<glm::quat> rotations;
  std::vector<glm::vec3> translations, scales;
  for (int j = 0; j < 3; ++j)
    for (int f = 0; f < 12; ++f) {
      const float angle = j == 0 ? 0.0f : 0.1f * float(f) * float(j);
      glm::quat q = glm::angleAxis(angle, glm::vec3(0.0f, 0.0f, 1.0f));
      if (j == 1 && f >= 3 && f <= 7)
        q = glm::angleAxis(0.1f * 5.0f, glm::vec3(0.0f, 0.0f, 1.0f)); // the cluster holds frame 5's rotation
      rotations.push_back(q);
      translations.push_back(j == 0 ? glm::vec3(float(f), 0.0f, 0.0f) : glm::vec3(0.0f, 10.0f, 0.0f));
      scales.push_back(glm::vec3(1.0f));
    }
  const std::vector<LodCluster> clusters = {LodCluster{3, 7, 5}};
  const std::vector<std::uint32_t> clusterBegin = {0, 0, 1, 1};
  const auto clipOf = [&](bool clustered) {
    LodClipSource source;
    source.fps = 30.0;
    source.frameCount = 12;
    source.jointCount = 3;
    source.rotations = rotations;
    source.translations = translations;
    source.scales = scales;
    if (clustered) {
      source.clusters = clusters;
      source.clusterBegin = clusterBegin;
    }
    source.parents = level.parents;
    source.blendFrames = 2;
    std::optional<LodClip> built = LodClip::build(source);
    EXPECT_TRUE(built);
    return built ? *built : LodClip();
  };
  level.clips.push_back(BundleClip{"wave", clipOf(true)});
  BundleMesh mesh;
  mesh.positions = {{-1, 0, 0}, {1, 0, 0}, {1, 20, 0}, {-1, 20, 0}};
  mesh.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  mesh.joints = {{0, 0, 0, 0}, {0, 1, 0, 0}, {2, 1, 0, 0}, {2, 0, 0, 0}};
  mesh.weights = {{1, 0, 0, 0}, {0.5f, 0.5f, 0, 0}, {0.75f, 0.25f, 0, 0}, {1, 0, 0, 0}};
  level.mesh = mesh;
  b.levels.push_back(level);
  BundleLevel coarse = level;
  coarse.index = 2;
  coarse.name = "LOD2";
  coarse.mesh.reset();
  coarse.clips[0].clip = clipOf(false);
  b.levels.push_back(coarse);
  return b;
}

std::vector<std::uint8_t> bytesOf(const Bundle& b) {
  std::string error;
  std::vector<std::uint8_t> bytes = writeBundle(b, &error);
  EXPECT_FALSE(bytes.empty()) << error;
  return bytes;
}

std::uint64_t le(const std::vector<std::uint8_t>& bytes, std::size_t at, int n) {
  std::uint64_t v = 0;
  for (int i = 0; i < n; ++i)
    v |= std::uint64_t(bytes[at + std::size_t(i)]) << (8 * i);
  return v;
}
void putLe(std::vector<std::uint8_t>& bytes, std::size_t at, std::uint64_t v, int n) {
  for (int i = 0; i < n; ++i)
    bytes[at + std::size_t(i)] = static_cast<std::uint8_t>(v >> (8 * i));
}

// Section boundaries: (offset, size) of each section, from the table.
std::vector<std::pair<std::size_t, std::size_t>> sectionsOf(const std::vector<std::uint8_t>& bytes) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  const std::size_t count = le(bytes, 12, 4);
  for (std::size_t i = 0; i < count; ++i)
    out.emplace_back(le(bytes, 24 + 24 * i + 8, 8), le(bytes, 24 + 24 * i + 16, 8));
  return out;
}

// Recomputes every checksum after an edit, so only the reader's other checks can refuse it.
void reseal(std::vector<std::uint8_t>& bytes) {
  const auto sections = sectionsOf(bytes);
  for (std::size_t i = 0; i < sections.size(); ++i)
    putLe(bytes, 24 + 24 * i + 4,
          crc32(std::span<const std::uint8_t>(bytes).subspan(sections[i].first, sections[i].second)), 4);
  const std::size_t tableEnd = 24 + 24 * sections.size();
  putLe(bytes, tableEnd, crc32(std::span<const std::uint8_t>(bytes).first(tableEnd)), 4);
}

// Guards the check exporters make before a package is built (bundle plugin's
// planProblem(), the CLI and the studio): no skeleton is refused, and the joint-frame cap
// counts every joint at level 0 and at least the root at the others, to the joint-frame.
TEST(Bundle, PlanProblemCountsTheLeastJointFrames) {
  EXPECT_NE(bundlePlanProblem(100, 0, 4, true).find("has no skeleton"), std::string::npos);
  // 31 joints at level 0 and 3 more levels: 34 joint-frames per frame
  const std::uint64_t fits = kMaxBundleJointFrames / 34;
  EXPECT_EQ(bundlePlanProblem(fits, 31, 4, true), "");
  const std::string over = bundlePlanProblem(fits + 1, 31, 4, true);
  EXPECT_NE(over.find("need at least " + std::to_string((fits + 1) * 34)), std::string::npos) << over;
  EXPECT_NE(over.find("at most " + std::to_string(kMaxBundleJointFrames) + " joint-frames"), std::string::npos) << over;
  // without level 0: one joint-frame per frame and level
  EXPECT_EQ(bundlePlanProblem(kMaxBundleJointFrames / 3, 31, 3, false), "");
  EXPECT_NE(bundlePlanProblem(kMaxBundleJointFrames / 3 + 1, 31, 3, false), "");
}

TEST(Bundle, Crc32IsZlibs) {
  const std::string text = "123456789";
  EXPECT_EQ(crc32(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()), text.size())),
            0xCBF43926u);
}

TEST(Bundle, RoundTripIsExact) {
  const Bundle b = smallBundle();
  const std::vector<std::uint8_t> bytes = bytesOf(b);
  std::string error;
  std::optional<Bundle> read = readBundle(bytes, &error);
  ASSERT_TRUE(read) << error;
  EXPECT_EQ(read->name, "chain");
  EXPECT_EQ(read->jointNames, b.jointNames);
  ASSERT_EQ(read->levels.size(), 2u);
  const LodClip& clip = read->levels[0].clips[0].clip;
  const LodClip& original = b.levels[0].clips[0].clip;
  EXPECT_EQ(read->levels[0].clips[0].name, "wave");
  EXPECT_EQ(clip.frameCount(), 12);
  EXPECT_EQ(clip.blendFrames(), 2);
  EXPECT_EQ(clip.clusterCount(), 1);
  EXPECT_EQ(clip.byteSize(), original.byteSize());
  EXPECT_EQ(clip.encodedErrorCm(), original.encodedErrorCm());
  for (int j = 0; j < 3; ++j) {
    EXPECT_EQ(clip.flags(j), original.flags(j));
    for (double f = 0.0; f <= 11.0; f += 0.25) {
      const glm::quat a = clip.rotationAt(j, f), e = original.rotationAt(j, f);
      EXPECT_EQ(std::memcmp(&a, &e, sizeof a), 0) << j << " " << f;
      const glm::vec3 t = clip.translationAt(j, f), u = original.translationAt(j, f);
      EXPECT_EQ(std::memcmp(&t, &u, sizeof t), 0) << j << " " << f;
    }
  }
  ASSERT_EQ(clip.clusters(1).size(), 1u);
  EXPECT_EQ(clip.clusters(1)[0].first, 3);
  EXPECT_EQ(clip.clusters(1)[0].last, 7);
  ASSERT_TRUE(read->levels[0].mesh);
  EXPECT_EQ(read->levels[0].mesh->indices, b.levels[0].mesh->indices);
  EXPECT_FALSE(read->levels[1].mesh);
  EXPECT_EQ(bytesOf(*read), bytes); // written again: the same bytes
  std::optional<BundleLevelRuntime> runtime = buildBundleLevel(read->levels[0], &error);
  ASSERT_TRUE(runtime) << error;
  EXPECT_EQ(runtime->clips[0].clusterCount(), 1);
  ASSERT_TRUE(runtime->mesh);
  EXPECT_EQ(runtime->mesh->vertexCount(), 4);
}

TEST(Bundle, TruncationAnywhereIsRefused) {
  const std::vector<std::uint8_t> bytes = bytesOf(smallBundle());
  std::vector<std::size_t> cuts = {0, 7, 8, 23, 24, 30};
  for (const auto& [offset, size] : sectionsOf(bytes)) {
    cuts.push_back(offset); // at every section boundary
    cuts.push_back(offset + size / 2);
    cuts.push_back(offset + size - 1);
  }
  for (std::size_t cut : cuts) {
    ASSERT_LT(cut, bytes.size());
    std::string error;
    EXPECT_FALSE(readBundle(std::span<const std::uint8_t>(bytes).first(cut), &error)) << "cut at " << cut;
    EXPECT_FALSE(error.empty());
    if (cut >= 24) {
      EXPECT_NE(error.find("truncated"), std::string::npos) << cut << ": " << error;
    }
  }
  std::vector<std::uint8_t> padded = bytes;
  padded.push_back(0);
  std::string error;
  EXPECT_FALSE(readBundle(padded, &error));
  EXPECT_NE(error.find("padded"), std::string::npos) << error;
}

TEST(Bundle, EveryByteFlipIsRefused) {
  const std::vector<std::uint8_t> bytes = bytesOf(smallBundle());
  for (std::size_t at = 0; at < bytes.size(); ++at) {
    std::vector<std::uint8_t> damaged = bytes;
    damaged[at] ^= 0x5A;
    std::string error;
    EXPECT_FALSE(readBundle(damaged, &error)) << "byte " << at;
    EXPECT_FALSE(error.empty());
  }
}

TEST(Bundle, WrongMagicAndVersionSaySo) {
  std::vector<std::uint8_t> bytes = bytesOf(smallBundle());
  std::vector<std::uint8_t> magic = bytes;
  magic[0] = 'X';
  std::string error;
  EXPECT_FALSE(readBundle(magic, &error));
  EXPECT_NE(error.find("not a Motion LOD bundle"), std::string::npos) << error;
  std::vector<std::uint8_t> newer = bytes;
  putLe(newer, 8, kBundleVersion + 1, 4);
  reseal(newer);
  EXPECT_FALSE(readBundle(newer, &error));
  EXPECT_NE(error.find("version 2"), std::string::npos) << error;
  EXPECT_NE(error.find("newer"), std::string::npos) << error;
  EXPECT_FALSE(readBundle(std::vector<std::uint8_t>{}, &error));
  std::vector<std::uint8_t> older = bytes;
  putLe(older, 8, 1, 4);
  reseal(older);
  EXPECT_FALSE(readBundle(older, &error));
  EXPECT_NE(error.find("version 1"), std::string::npos) << error;
  EXPECT_NE(error.find("export the character again"), std::string::npos) << error;
}

// Offset of the first clip's storage in the first level section, and its end.
std::pair<std::size_t, std::size_t> firstClipOf(const std::vector<std::uint8_t>& bytes) {
  const auto sections = sectionsOf(bytes);
  const std::size_t level = sections[1].first;
  const std::size_t joints = level + 4 + 4 + 4 + 7 * 8;
  const std::size_t begin = joints + 4 + 3 * 72 + 4;
  return {begin, begin + bundleClipBytes(smallBundle().levels[0].clips[0])};
}

// Every 32-bit word of a clip's storage set to values that lie (0, 1, 0xFFFF, 0x10000,
// 0xFFFFFFFF, the word plus or minus one), under valid checksums: each bundle is refused
// with a message, or it reads and plays within bounds.
TEST(Bundle, LiesInsideAClipAreRefusedOrPlaySafely) {
  const std::vector<std::uint8_t> bytes = bytesOf(smallBundle());
  const auto [begin, end] = firstClipOf(bytes);
  ASSERT_EQ(le(bytes, begin, 4), 4u); // the name's length: "wave"
  int refused = 0, read = 0, played = 0;
  for (std::size_t at = begin; at + 4 <= end; ++at) {
    const std::uint64_t word = le(bytes, at, 4);
    for (std::uint64_t lie : {0ull, 1ull, 0xFFFFull, 0x10000ull, 0xFFFFFFFFull, (word + 1) & 0xFFFFFFFFull,
                              (word - 1) & 0xFFFFFFFFull}) {
      if (lie == word)
        continue;
      std::vector<std::uint8_t> damaged = bytes;
      putLe(damaged, at, lie, 4);
      reseal(damaged);
      std::string error;
      std::optional<Bundle> back = readBundle(damaged, &error);
      if (!back) {
        ++refused;
        EXPECT_FALSE(error.empty());
        continue;
      }
      ++read;
      EXPECT_EQ(writeBundle(*back), damaged); // read as it is written
      played += test::playBundle(*back, 24);
    }
  }
  // values (ranges, statics, the name) may take other values; counts, indices, regions,
  // widths may not
  EXPECT_GT(refused, 1000) << refused << " refused, " << read << " read";
  EXPECT_GT(read, 0);
  EXPECT_GT(played, 24 * read / 2) << played; // most of what reads plays
}

// Storage that breaks the evaluator's rules is refused, and the message says what.
TEST(Bundle, BrokenClipStorageSaysWhat) {
  const Bundle b = smallBundle();
  const std::vector<std::uint8_t> bytes = bytesOf(b);
  const auto [begin, end] = firstClipOf(bytes);
  // the clip's fields: name (8), fps (8), frames (4), looping (1), blend (4), precision (8),
  // error (8), clusters (4); then 53 bytes per joint: flags, rotation, translation, scale, streams
  const std::size_t joints = begin + 8 + 8 + 4 + 1 + 4 + 8 + 8 + 4;
  const std::size_t rotationStream = joints + 53 * 1 + 1 + 16 + 12 + 12; // joint 1's
  ASSERT_EQ(b.levels[0].clips[0].clip.rotationStream(1), std::int32_t(le(bytes, rotationStream, 4)));
  const auto refusal = [&](std::size_t at, std::uint64_t value, int n) {
    std::vector<std::uint8_t> damaged = bytes;
    putLe(damaged, at, value, n);
    reseal(damaged);
    std::string error;
    EXPECT_FALSE(readBundle(damaged, &error)) << at;
    return error;
  };
  EXPECT_NE(refusal(rotationStream, 99, 4).find("joint 1: an animated channel without a stream"), std::string::npos);
  EXPECT_NE(refusal(joints + 53, 0x40, 1).find("joint 1: unknown flags"), std::string::npos);
  const std::string wide = refusal(begin + 8 + 8, 70000, 4);
  EXPECT_NE(wide.find("region"), std::string::npos) << wide; // read as wide regions: they no longer hold
  EXPECT_NE(refusal(begin + 8 + 8 + 4 + 1, 10001, 4).find("blend frames 10001"), std::string::npos);
}

// The fuzzer's seed (tests/fuzz/bundle_corpus/chain.mlodb) is this file's bundle as the
// writer writes it today: a format change that forgot the seed fails here. Set
// MLOD_UPDATE_FUZZ_SEEDS=1 to write it again.
TEST(Bundle, FuzzSeedIsTheCurrentFormat) {
  const std::vector<std::uint8_t> bytes = bytesOf(smallBundle());
  const std::filesystem::path seed = std::filesystem::path(MLOD_SOURCE_DIR) / "tests/fuzz/bundle_corpus/chain.mlodb";
  if (std::getenv("MLOD_UPDATE_FUZZ_SEEDS")) {
    std::ofstream out(seed, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  }
  std::ifstream in(seed, std::ios::binary);
  const std::vector<std::uint8_t> stored((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(stored, bytes) << seed << " is not the current format: rerun with MLOD_UPDATE_FUZZ_SEEDS=1";
}

TEST(Bundle, LyingCountsUnderValidChecksumsAreRefused) {
  const std::vector<std::uint8_t> bytes = bytesOf(smallBundle());
  const auto sections = sectionsOf(bytes);
  const std::size_t level = sections[1].first;
  // the level section: i32 index, string name (4 + 4 bytes), 7 doubles, then u32 joints
  const std::size_t joints = level + 4 + 4 + 4 + 7 * 8;
  ASSERT_EQ(le(bytes, joints, 4), 3u);
  for (std::uint64_t lie : {0ull, 4ull, 40000ull, 0xFFFFFFFFull}) {
    std::vector<std::uint8_t> damaged = bytes;
    putLe(damaged, joints, lie, 4);
    reseal(damaged);
    std::string error;
    EXPECT_FALSE(readBundle(damaged, &error)) << lie;
    EXPECT_FALSE(error.empty());
  }
  // a frame count of 2^30: refused before anything that large is allocated
  const std::size_t clipStart = joints + 4 + 3 * 72 + 4; // joints, then the clip count
  const std::size_t frames = clipStart + 4 + 4 + 8;      // clip name "wave", fps
  ASSERT_EQ(le(bytes, frames, 4), 12u);
  std::vector<std::uint8_t> huge = bytes;
  putLe(huge, frames, 1u << 30, 4);
  reseal(huge);
  std::string error;
  EXPECT_FALSE(readBundle(huge, &error));
  EXPECT_FALSE(error.empty());
  // a parent after its child
  std::vector<std::uint8_t> cyclic = bytes;
  putLe(cyclic, joints + 4 + 72 + 4, 2, 4); // joint 1's parent := 2
  reseal(cyclic);
  EXPECT_FALSE(readBundle(cyclic, &error));
  EXPECT_NE(error.find("parent"), std::string::npos) << error;
}

// Found by fuzz_bundle once it saw the reader's coverage: a header whose file size is its
// own 24 bytes and 1 more made the section table's room wrap around (an unsigned 25 - 28),
// and the reader read the table's CRC-32 past the data. Every size from 24 to 27 is refused.
TEST(Bundle, AHeaderWithoutRoomForATableIsRefused) {
  for (std::size_t size = 24; size < 28; ++size) {
    std::vector<std::uint8_t> bytes(size, 0);
    std::memcpy(bytes.data(), kBundleMagic, sizeof kBundleMagic);
    putLe(bytes, 8, kBundleVersion, 4);
    putLe(bytes, 12, 3, 4);
    putLe(bytes, 16, size, 8);
    std::string error;
    EXPECT_FALSE(readBundle(bytes, &error)) << size;
    EXPECT_NE(error.find("corrupt section table"), std::string::npos) << error;
  }
}

TEST(Bundle, InconsistentBundlesAreNotWritten) {
  Bundle b = smallBundle();
  b.levels[0].mesh->indices.push_back(9);
  std::string error;
  EXPECT_TRUE(writeBundle(b, &error).empty());
  EXPECT_NE(error.find("index"), std::string::npos) << error;
  b = smallBundle();
  b.levels.clear();
  EXPECT_TRUE(writeBundle(b, &error).empty());
  b = smallBundle();
  b.levels[1].clips[0].clip = LodClip(); // never built: the writer has no storage to write
  EXPECT_TRUE(writeBundle(b, &error).empty());
  EXPECT_NE(error.find("clip 'wave'"), std::string::npos) << error;
}

TEST(Bundle, MissingFileSaysSo) {
  std::string error;
  EXPECT_FALSE(readBundleFile("/nonexistent/x.mlodb", &error));
  EXPECT_EQ(error, "no such file");
}

// Guards the reader against a FIFO (it blocked forever) and a link to /dev/zero (it read
// until memory ran out): both are refused from their type, before anything is opened.
TEST(Bundle, SpecialFilesAreRefusedAtOnce) {
  namespace fs = std::filesystem;
  const fs::path fifo = fs::temp_directory_path() / ("mlod_fifo_" + std::to_string(::getpid()) + ".mlodb");
  const fs::path zero = fs::temp_directory_path() / ("mlod_zero_" + std::to_string(::getpid()) + ".mlodb");
  fs::remove(fifo);
  fs::remove(zero);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  fs::create_symlink("/dev/zero", zero);
  std::string fifoError, zeroError;
  EXPECT_FALSE(readBundleFile(fifo.string(), &fifoError));
  EXPECT_FALSE(readBundleFile(zero.string(), &zeroError));
  fs::remove(fifo);
  fs::remove(zero);
  EXPECT_EQ(fifoError, "it is a FIFO (named pipe), not a regular file");
  EXPECT_EQ(zeroError, "it is a device, not a regular file");
}

} // namespace
} // namespace mlod
