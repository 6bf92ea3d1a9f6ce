#pragma once
// Names from files are bytes: a Latin-1 BVH or FBX gives joint names that are not UTF-8,
// and JSON (projects, --json output, glTF, reports) cannot hold them. Names are made valid
// UTF-8 deliberately, once, where they enter (the importer says so in the asset's
// warnings); file names stay bytes, and JSON writers replace their invalid bytes.

#include <string>
#include <string_view>

namespace mlod {

// Whether `text` is well-formed UTF-8 (no overlong forms, no surrogates, at most U+10FFFF).
bool isValidUtf8(std::string_view text);

// `text` with every byte that is not part of a well-formed UTF-8 sequence replaced by
// U+FFFD (EF BF BD); `text` itself when it is valid.
std::string validUtf8(std::string_view text);

} // namespace mlod
