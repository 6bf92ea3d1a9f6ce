#pragma once
// What the exporter plugin tests share: the real-data packages (built once per test
// program), loading a plugin from its file, and the Khronos glTF-Validator.

#include "sdk/exporter.h"

#include <QString>
#include <optional>
#include <string>

namespace mlod::test {

// CMU 01_01 (BVH, --unit-scale cmu) and BCN_Epileptic (X, --unit-scale m) with the default
// LOD set of a plain file (4 levels within 1 pixel), built on first use; a failure to import
// or build fails the calling test.
const LodPackage& cmuPackage();
const LodPackage& bcnPackage();
// The package of any file of Debian's assimp-testmodels (unitScale 0: the file's own), or
// nothing with a test failure.
std::optional<LodPackage> packageOf(const std::string& file, double unitScale = 0.0);

// The exporter of the plugin file `path` (QPluginLoader; the plugin stays loaded), or null
// with a test failure saying why.
Exporter* loadExporter(const QString& path);

// The exporter's options at their defaults, with `values` (key=value) applied.
QVariantMap exporterOptions(const Exporter& exporter, const QStringList& values = {});

struct ValidatorReport {
  int exitCode = -1; // validate.js: 0 no errors, 1 errors, 2 it could not run
  int errors = -1;
  int warnings = -1;
  int infos = -1;
  std::string output; // its JSON document (or what it printed on failure)
};
// Runs tests/plugins/validator/validate.js (installed by the validator_setup fixture).
ValidatorReport runValidator(const QString& file);

// three.js and Babylon.js in Node (tests/plugins/loaders/play.mjs, installed beside the
// validator) loading `file` and playing animation `animation` to `seconds`: exit code 0 when
// both loaded, and the script's JSON document (or what it printed on failure).
struct LoaderReport {
  int exitCode = -1;
  std::string output;
  std::string errors; // its stderr
};
bool haveNode(); // false: the tests that need Node skip
LoaderReport runLoaders(const QString& file, int animation, double seconds);

// The files in `dir`, for checking that nothing was left behind.
QStringList filesIn(const QString& dir);

} // namespace mlod::test
