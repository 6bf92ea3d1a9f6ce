// motionlod: the batch command line (docs/architecture.md section 6).

#include "cli/batch_command.h"
#include "cli/bench_crowd_command.h"
#include "cli/bundle_info.h"
#include "cli/export_command.h"
#include "cli/info_command.h"
#include "cli/meshlod_command.h"
#include "cli/plugins_command.h"
#include "cli/simplify_command.h"
#include "core/version.h"

#include <CLI/CLI.hpp>
#include <QCoreApplication>
#include <assimp/version.h>

#include <functional>
#include <iostream>
#include <new>

namespace {
std::string versionText() {
  return std::string("motionlod ") + mlod::kVersion + " (Assimp " + std::to_string(aiGetVersionMajor()) + "." +
         std::to_string(aiGetVersionMinor()) + "." + std::to_string(aiGetVersionPatch()) + ", Qt " + qVersion() + ")";
}
} // namespace

int main(int argc, char** argv) {
  QCoreApplication application(argc, argv);
  QCoreApplication::setApplicationName("motionlod");
  QCoreApplication::setApplicationVersion(mlod::kVersion);

  CLI::App app{"Motion LOD Studio command line: motion level-of-detail for crowds", "motionlod"};
  app.set_version_flag("--version", versionText());
  app.require_subcommand(1);
  mlod::cli::InfoCommand info;
  info.attach(app);
  mlod::cli::SimplifyCommand simplify;
  simplify.attach(app);
  mlod::cli::MeshLodCommand meshLod;
  meshLod.attach(app);
  mlod::cli::BenchCrowdCommand benchCrowd;
  benchCrowd.attach(app);
  mlod::cli::ExportCommand exportCommand;
  exportCommand.attach(app);
  mlod::cli::PluginsCommand plugins;
  plugins.attach(app);
  mlod::cli::BatchCommand batch;
  batch.attach(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return mlod::cli::kExitBadInput;
  }
  // each command, what runs it and the input its errors name
  const struct {
    const char* name;
    std::function<int()> run;
    const std::string* input; // null: none
  } commands[] = {
      {"info", [&] { return mlod::cli::isBundleFile(info.file) ? mlod::cli::describeBundle(info.file, info.json) : info.run(); },
       &info.file},
      {"simplify", [&] { return simplify.run(); }, &simplify.file},
      {"meshlod", [&] { return meshLod.run(); }, &meshLod.file},
      {"bench-crowd", [&] { return benchCrowd.run(); }, &benchCrowd.file},
      {"export", [&] { return exportCommand.run(); }, &exportCommand.job.input},
      {"plugins", [&] { return plugins.run(); }, nullptr},
      {"batch", [&] { return batch.run(); }, &batch.manifest},
  };
  for (const auto& command : commands) {
    if (!app.got_subcommand(command.name))
      continue;
    try {
      return command.run();
    } catch (const std::bad_alloc&) {
      // (it printed "error: std::bad_alloc" alone: the file and a reason a user can act on)
      std::cerr << "error: " << (command.input ? *command.input : std::string("motionlod"))
                << ": not enough memory for this input (the process's memory limit was reached)" << std::endl;
      return mlod::cli::kExitFailure;
    } catch (const std::exception& e) {
      std::cerr << "error: " << e.what() << std::endl;
      return mlod::cli::kExitFailure;
    }
  }
  return mlod::cli::kExitFailure;
}
