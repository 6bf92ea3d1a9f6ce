#pragma once
// LodPackages of real files of Debian's assimp-testmodels with the default LOD set of a
// plain file (docs/architecture.md section 6), built once per test program: what the runtime bundle's
// round trip and the bundle exporter's tests share. No Qt (the sanitizer build runs them).

#include "core/lod/lod_package.h"
#include "io/importer.h"

#include <map>
#include <stdexcept>
#include <string>
#include <utility>

namespace mlod::test {

// `relative` below MLOD_ASSIMP_MODELS imported at `unitScale` cm per file unit; an import
// or build failure throws (the calling test fails with the reason).
inline const LodPackage& realPackage(const std::string& relative, double unitScale) {
  static std::map<std::pair<std::string, double>, LodPackage> cache;
  const std::pair<std::string, double> key{relative, unitScale};
  auto found = cache.find(key);
  if (found == cache.end()) {
    ImportOptions options;
    options.unitScale = unitScale;
    Result<Asset> asset = importAsset(std::string(MLOD_ASSIMP_MODELS) + "/" + relative, options);
    if (!asset)
      throw std::runtime_error(relative + ": " + asset.message());
    Result<LodPackage> package = buildLodPackage(*asset);
    if (!package)
      throw std::runtime_error(relative + ": " + package.message());
    found = cache.emplace(key, std::move(package).value()).first;
  }
  return found->second;
}

} // namespace mlod::test
