// libFuzzer target for the runtime bundle reader: arbitrary bytes, with the checksums made
// right before reading (otherwise almost every mutation stops at a CRC-32 check), so the
// parsers behind them meet lying counts, sizes and indices. What reads is played: every
// clip of every level through the pose evaluator at frames across the clip, so that storage
// the reader let through is read the way an engine reads it (under ASan and UBSan).
#include "runtime/bundle.h"
#include "unit/runtime/play_bundle.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace {
std::uint64_t le(const std::vector<std::uint8_t>& b, std::size_t at, int n) {
  std::uint64_t v = 0;
  for (int i = 0; i < n; ++i)
    v |= std::uint64_t(b[at + std::size_t(i)]) << (8 * i);
  return v;
}
void put(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i)
    b[at + std::size_t(i)] = std::uint8_t(v >> (8 * i));
}
void reseal(std::vector<std::uint8_t>& b) {
  if (b.size() < 24)
    return;
  const std::uint64_t count = le(b, 12, 4);
  if (count > 1000 || 24 + 24 * count + 4 > b.size())
    return;
  for (std::uint64_t i = 0; i < count; ++i) {
    const std::uint64_t offset = le(b, 24 + 24 * i + 8, 8), size = le(b, 24 + 24 * i + 16, 8);
    if (offset <= b.size() && size <= b.size() - offset)
      put(b, 24 + 24 * i + 4, mlod::crc32(std::span<const std::uint8_t>(b).subspan(offset, size)));
  }
  const std::size_t tableEnd = 24 + 24 * count;
  put(b, tableEnd, mlod::crc32(std::span<const std::uint8_t>(b).first(tableEnd)));
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> bytes(data, data + size);
  reseal(bytes);
  std::string error;
  std::optional<mlod::Bundle> bundle = mlod::readBundle(bytes, &error);
  if (!bundle)
    return 0;
  for (const mlod::BundleLevel& level : bundle->levels)
    (void)mlod::buildBundleLevel(level, &error);
  (void)mlod::test::playBundle(*bundle, 8);
  return 0;
}
