#pragma once
// A compact binary form of an Asset, used to hand an import from a sandboxed child
// process to its parent. Not a file format: both ends are the same build.

#include "core/asset.h"
#include "core/error.h"

#include <string>
#include <string_view>

namespace mlod {

// Appends the asset to out_bytes.
void writeAssetStream(const Asset& asset, std::string& out_bytes);

// Reads what writeAssetStream wrote; refuses truncated or inconsistent bytes.
Result<Asset> readAssetStream(std::string_view bytes);

} // namespace mlod
