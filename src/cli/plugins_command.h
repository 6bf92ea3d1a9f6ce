#pragma once

#include "cli/cli_common.h"

namespace CLI { class App; }

namespace mlod::cli {

// `motionlod plugins [--json]`: the exporter plugins found (id, name, version, suffixes,
// options) and every plugin that failed to load, with its file and the reason. JSON:
// {"plugins":[{"id","name","version","suffixes","file","options":[{"key","type","default",
// "minimum","maximum","choices","help"}]}],"failed":[{"file","reason"}],"search_path":[...]}
// Exit 0 (a failed plugin is reported, not fatal).
struct PluginsCommand {
  bool json = false;

  void attach(CLI::App& app);
  int run() const;
};

} // namespace mlod::cli
