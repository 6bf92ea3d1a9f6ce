#pragma once
// Reading an input file whole, bounded (docs/architecture.md section 9: huge or hostile
// inputs give a clear error, never a hang or unbounded memory). Only regular files are
// read: a FIFO would block the reader forever and a device such as /dev/zero (or a symlink
// to one) never ends, so both are refused from their type alone, before anything is opened.
// Symlinks are followed: a link to a regular file is that file.
//
// Every reader of a whole file (projects, bundles, batch manifests) goes through these two
// functions with its own cap, so the rules and messages are the same everywhere.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace mlod {

// Why `path` cannot be read as an input of at most `maxBytes` bytes: "no such file", "it is
// a folder, not a file", "it is a FIFO (named pipe), not a regular file", "it is a device,
// not a regular file", "it is N bytes, more than the M bytes ..." ... Empty when it can.
// Nothing is opened.
std::string inputFileProblem(const std::filesystem::path& path, std::uint64_t maxBytes);

// The whole file, or nothing and the reason (inputFileProblem()'s, or a read error). Reads
// at most `maxBytes` + 1 bytes whatever the file claims, so a file that grows while it is
// read is refused too.
std::optional<std::string> readInputFile(const std::filesystem::path& path, std::uint64_t maxBytes,
                                         std::string* out_error = nullptr);

} // namespace mlod
