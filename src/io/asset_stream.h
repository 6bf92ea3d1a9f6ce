#pragma once
// A compact binary form of an Asset, used to hand an import from a sandboxed child
// process to its parent. Not a file format: both ends are the same build.

#include "core/asset.h"
#include "core/error.h"

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>

namespace mlod {

// Appends the asset to out_bytes.
void writeAssetStream(const Asset& asset, std::string& out_bytes);

// Hands the same bytes to `sink` in pieces (small fields gathered up to 1 MiB, clip and
// mesh arrays straight from the asset), so no second copy of a long clip is made. Stops
// and returns false as soon as the sink returns false.
using AssetStreamSink = std::function<bool(const char* data, std::size_t size)>;
bool writeAssetStream(const Asset& asset, const AssetStreamSink& sink);

// Reads what writeAssetStream wrote; refuses truncated or inconsistent bytes.
Result<Asset> readAssetStream(std::string_view bytes);

} // namespace mlod
