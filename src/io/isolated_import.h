#pragma once
// Import in a sandboxed child process. Assimp is not hardened against hostile or broken
// files: some crash it, some make it allocate without bound or loop for minutes. The
// child runs importAsset() under a memory limit and sends the Asset back through a
// pipe; a crash, a timeout or a cancel becomes an Error here, and the caller lives on.

#include "core/asset.h"
#include "core/error.h"
#include "io/import_options.h"

#include <atomic>
#include <cstddef>
#include <string>

namespace mlod {

struct IsolationLimits {
  double timeoutSeconds = 120.0;           // wall clock; 0 = none
  std::size_t memoryBytes = std::size_t{8} << 30; // address-space limit of the child; 0 = none
  const std::atomic<bool>* cancel = nullptr; // when set to true, the child is stopped
};

// For tests of stopping a stuck import: in a test build (mlod_io_testing, compiled with
// MLOD_TESTING) the worker for exactly the file this environment variable names says so on
// stderr and blocks instead of importing, until it is killed (a cancel, the timeout, its
// parent's death). Release builds (mlod_io) ignore the variable.
inline constexpr const char* kStuckImportVariable = "MLOD_TEST_STUCK_IMPORT";

Result<Asset> importAssetIsolated(const std::string& path, const ImportOptions& options = {},
                                  const IsolationLimits& limits = {});

} // namespace mlod
