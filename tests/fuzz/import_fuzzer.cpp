// libFuzzer entry for the import path: the first byte picks the format Assimp is told
// the bytes are in (or our own asset stream), the rest is the file. Whatever the bytes,
// the importer must return an Asset that validates or an Error: never crash, never UB.

#include "io/asset_stream.h"
#include "io/importer.h"

#include <array>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

namespace {
// note: only parsers that survive fuzzing are fuzzed in-process, so that what this finds
// is ours. Within seconds libFuzzer found in Assimp 5.2: an endless loop in the SMD parser,
// segfaults in the X and MD5 parsers and a heap use-after-free in the glTF parser
// (tests/data/bad/ keeps the inputs that also fail outside ASan). The studio and the CLI
// import in a sandboxed worker, which the isolated-import tests check on those files.
// MLOD_FUZZ_FORMATS=gltf,x lets a developer study the others.
constexpr std::array<const char*, 3> kFormats{"bvh", "obj", "stream"};
} // namespace

// MLOD_FUZZ_FORMATS=bvh,gltf narrows the formats (to study one parser at a time).
const std::vector<std::string>& formats() {
  static const std::vector<std::string> list = [] {
    std::vector<std::string> out;
    if (const char* env = std::getenv("MLOD_FUZZ_FORMATS")) {
      std::string text = env;
      for (std::size_t start = 0, end; start <= text.size(); start = end + 1) {
        end = text.find(',', start);
        if (end == std::string::npos)
          end = text.size();
        if (end > start)
          out.emplace_back(text.substr(start, end - start));
      }
    }
    if (out.empty())
      out.assign(kFormats.begin(), kFormats.end());
    return out;
  }();
  return list;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2)
    return 0;
  const std::string& format = formats()[data[0] % formats().size()];
  const std::string_view bytes(reinterpret_cast<const char*>(data + 1), size - 1);
  mlod::Result<mlod::Asset> asset = format == "stream" ? mlod::readAssetStream(bytes)
                                                       : mlod::importAssetFromMemory(bytes.data(), bytes.size(), format);
  if (asset.ok() && asset->validate())
    std::abort(); // an Asset that came back must be valid
  return 0;
}
