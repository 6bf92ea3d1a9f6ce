#pragma once
// What every motionlod command checks about the files it reads and writes before it does
// any work (docs/architecture.md sections 6 and 9: nothing lost, nothing hangs):
// - an output is never one of the inputs: compared by file identity (device and inode, so
//   a hard link, a symlink or another spelling of the same file is caught, not by name);
// - an output that exists and is not a regular file (a device, a FIFO, a folder) is never
//   replaced: as root `-o /dev/null` would otherwise replace /dev/null;
// - the files an export writes are known: the output, and for the bundle its manifest.
// Inputs themselves are read through runtime/input_file.h (regular files, capped).

#include "core/project.h"

#include <QVariantMap>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace mlod::cli {

// The largest batch manifest `motionlod batch` reads.
inline constexpr std::uint64_t kMaxManifestBytes = std::uint64_t(64) << 20;

// A file's identity: equal for every path that names the same file.
struct FileIdentity {
  std::uint64_t device = 0;
  std::uint64_t inode = 0;
  friend bool operator==(const FileIdentity&, const FileIdentity&) = default;
};

// The identity of the file `path` names (symlinks followed), or nothing when there is none.
std::optional<FileIdentity> fileIdentity(const std::string& path);

// Every file `motionlod export --plugin PLUGIN -o OUTPUT` may write: OUTPUT, and for the
// bundle exporter OUTPUT.json unless its "manifest" option is off; for the glTF exporter
// with split_levels, OUT_LOD<n>.<suffix> for every level a project may have instead.
std::vector<std::string> exportOutputFiles(const std::string& plugin, const std::string& output,
                                           const QVariantMap& options);

// Every file an export of `input` reads: the input, and for a .mlod project every asset it
// names (as the project resolves them). A project that cannot be read adds nothing more:
// the export reports why when it reads it.
std::vector<std::string> exportInputFiles(const std::string& input);

// Why `output` must not be written: it exists and is not a regular file (a folder aside:
// the writer cannot replace one, and says so), or it is one of `inputs` (by identity).
// Empty when it may be.
std::string outputProblem(const std::string& output, std::span<const std::string> inputs);

// `path` made absolute with its existing part resolved (symlinks, "..", "."), so that two
// spellings of one output compare equal.
std::string normalOutputPath(const std::string& path);

// Whether `path` (normalOutputPath()) lies inside `folder` (normalOutputPath()).
bool isInsideFolder(const std::string& path, const std::string& folder);

// Projects: isProjectFile() and kProjectSuffix of core/project.h, the editor's too.
using mlod::isProjectFile;

} // namespace mlod::cli
