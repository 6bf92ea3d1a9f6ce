// libFuzzer target for the batch manifest reader (src/cli/batch_manifest.h): arbitrary
// text as a manifest. Every input gives jobs with their rules kept or an Error; never a
// crash or an exception.
#include "cli/batch_manifest.h"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto jobs =
      mlod::cli::parseBatchManifest(std::string_view(reinterpret_cast<const char*>(data), size), "/farm/library");
  if (jobs)
    for (const mlod::cli::ManifestJob& job : *jobs)
      if (job.input.empty() || job.output.empty() || job.plugin.empty() || !job.options.is_object())
        std::abort();
  return 0;
}
