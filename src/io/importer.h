#pragma once
// Import of characters and motions through Assimp into core types (docs/architecture.md section 3):
// - skeleton: the nodes that bones name, the animated nodes, their ancestors up to
//   their lowest common one, and the leaf nodes below them (BVH End Sites);
// - clips: one per animation, resampled at a fixed rate (BVH at its own frame time);
// - meshes: every skinned mesh merged into one character mesh with its bones remapped,
//   at most 4 influences per vertex, weights normalised exactly; unskinned meshes
//   below a joint are bound to it rigidly, the others form a static mesh;
// - every length in cm (see ImportOptions::unitScale).
// Bad data returns an Error whose message names the problem; nothing throws.

#include "core/asset.h"
#include "core/error.h"
#include "io/import_options.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace mlod {

// The largest file importAsset() and importAssetIsolated() read: a regular file (never a
// FIFO or a device; runtime/input_file.h) of at most 4 GiB. Assimp reads a file whole.
inline constexpr std::uint64_t kMaxImportFileBytes = std::uint64_t(4) << 30;

// Reads `path` in this process. Assimp is not hardened against hostile files (some make
// it allocate without bound); use importAssetIsolated() for files from users.
Result<Asset> importAsset(const std::string& path, const ImportOptions& options = {});

// Reads a file held in memory; `extension` ("bvh", "glb" ...) tells Assimp the format.
Result<Asset> importAssetFromMemory(const void* data, std::size_t size, const std::string& extension,
                                    const ImportOptions& options = {});

} // namespace mlod
