// libFuzzer entry for the import path: the first byte picks the format Assimp is told
// the bytes are in (or our own asset stream), the rest is the file. Whatever the bytes,
// the importer must return an Asset that validates or an Error: never crash, never UB.

#include "io/asset_stream.h"
#include "io/importer.h"
#include "io/isolated_import.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include <unistd.h>

namespace {
// note: only parsers that survive fuzzing are fuzzed in-process, so that what this finds
// is ours. Within seconds libFuzzer found in Assimp 5.2: an endless loop in the SMD parser,
// segfaults in the X and MD5 parsers and a heap use-after-free in the glTF parser
// (tests/data/bad/ keeps the inputs that also fail outside ASan). The studio and the CLI
// import in a sandboxed worker, which the isolated-import tests check on those files.
constexpr std::array<const char*, 3> kFormats{"bvh", "obj", "stream"};

// Any other format (MLOD_FUZZ_FORMATS=3ds, one ctest entry per format with seeds from
// assimp-testmodels) is imported as the CLI and the studio import it: in the sandboxed
// worker, so a crash or a hang inside Assimp is the worker's Error, and what must hold is
// that the caller gets a valid Asset or an Error. (The worker's coverage is not seen by
// libFuzzer: for these formats it mutates blindly from the seeds.) MLOD_FUZZ_IN_PROCESS=1
// imports them in-process instead, to study a parser.
bool inProcess(const std::string& format) {
  static const bool forced = std::getenv("MLOD_FUZZ_IN_PROCESS") != nullptr;
  return forced || std::find(kFormats.begin(), kFormats.end(), format) != kFormats.end();
}

mlod::Result<mlod::Asset> importIsolated(std::string_view bytes, const std::string& format) {
  static const std::string folder = [] {
    const char* tmp = std::getenv("TMPDIR");
    return std::string(tmp && *tmp ? tmp : "/tmp");
  }();
  // the format is the file's suffix, as the CLI sees it
  const std::string path = folder + "/mlod_fuzz_" + std::to_string(::getpid()) + "." + format;
  if (std::FILE* file = std::fopen(path.c_str(), "wb")) {
    const bool written = std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size();
    if (std::fclose(file) == 0 && written) {
      mlod::IsolationLimits limits;
      limits.timeoutSeconds = 10.0; // below libFuzzer's -timeout: a hang is the worker's
      mlod::Result<mlod::Asset> asset = mlod::importAssetIsolated(path, {}, limits);
      std::remove(path.c_str());
      return asset;
    }
  }
  std::abort(); // the scratch file could not be written: the run says nothing
}
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
                                    : inProcess(format)
                                        ? mlod::importAssetFromMemory(bytes.data(), bytes.size(), format)
                                        : importIsolated(bytes, format);
  if (asset.ok() && asset->validate())
    std::abort(); // an Asset that came back must be valid
  return 0;
}
