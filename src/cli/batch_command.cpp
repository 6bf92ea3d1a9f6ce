#include "cli/batch_command.h"

#include "cli/export_job.h"
#include "cli/terminal_progress.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>

namespace mlod::cli {

void BatchCommand::attach(CLI::App& app) {
  CLI::App* command = app.add_subcommand("batch", "Export every job of a manifest (or one shard of it)");
  command->add_option("MANIFEST", manifest,
                      "JSON: {\"jobs\":[{\"input\",\"plugin\",\"output\",\"options\":{}}]}, paths relative to it")
      ->required();
  command->add_option("--shard", shard, "I/N: the jobs whose index is I mod N (default 0/1: all)");
  command->add_option("--jobs", jobs, "jobs to run at once on this machine")->check(CLI::Range(1, 256));
  command->add_flag("--json", json, "print one JSON document on stdout");
  command->add_flag("-q,--quiet", quiet, "no progress line on the terminal (stderr)");
}

namespace {

bool parseShard(const std::string& text, int& out_index, int& out_count) {
  const std::size_t slash = text.find('/');
  if (slash == std::string::npos)
    return false;
  try {
    std::size_t a = 0, b = 0;
    out_index = std::stoi(text.substr(0, slash), &a);
    out_count = std::stoi(text.substr(slash + 1), &b);
    return a == slash && b == text.size() - slash - 1 && out_count >= 1 && out_index >= 0 && out_index < out_count;
  } catch (const std::exception&) {
    return false;
  }
}

// A job of the manifest, paths resolved against its folder; false and a reason when malformed.
bool readJob(const nlohmann::json& entry, std::size_t index, const std::filesystem::path& folder, ExportJob& out,
             std::string& out_reason) {
  const std::string where = "job " + std::to_string(index);
  if (!entry.is_object()) {
    out_reason = where + " is not an object";
    return false;
  }
  for (const char* key : {"input", "plugin", "output"})
    if (!entry.contains(key) || !entry[key].is_string() || entry[key].get<std::string>().empty()) {
      out_reason = where + ": \"" + key + "\" must be a non-empty string";
      return false;
    }
  for (auto it = entry.begin(); it != entry.end(); ++it)
    if (it.key() != "input" && it.key() != "plugin" && it.key() != "output" && it.key() != "options" &&
        it.key() != "levels" && it.key() != "unit_scale") {
      out_reason = where + ": unknown key \"" + it.key() + "\"";
      return false;
    }
  const auto resolve = [&](const std::string& path) {
    const std::filesystem::path p(path);
    return (p.is_absolute() ? p : folder / p).lexically_normal().string();
  };
  out.input = resolve(entry["input"].get<std::string>());
  out.output = resolve(entry["output"].get<std::string>());
  out.plugin = entry["plugin"].get<std::string>();
  if (entry.contains("options")) {
    if (!entry["options"].is_object()) {
      out_reason = where + ": \"options\" must be an object";
      return false;
    }
    for (auto it = entry["options"].begin(); it != entry["options"].end(); ++it) {
      const QString key = QString::fromStdString(it.key());
      if (it->is_boolean())
        out.options.insert(key, it->get<bool>());
      else if (it->is_number_integer())
        out.options.insert(key, QVariant::fromValue(it->get<long long>()));
      else if (it->is_number())
        out.options.insert(key, it->get<double>());
      else if (it->is_string())
        out.options.insert(key, QString::fromStdString(it->get<std::string>()));
      else {
        out_reason = where + ": option \"" + it.key() + "\" must be a bool, number or string";
        return false;
      }
    }
  }
  if (entry.contains("levels")) {
    if (!entry["levels"].is_array()) {
      out_reason = where + ": \"levels\" must be an array of level indices";
      return false;
    }
    for (const nlohmann::json& level : entry["levels"]) {
      if (!level.is_number_integer() || level.get<long long>() < 0 || level.get<long long>() > 65535) {
        out_reason = where + ": \"levels\" must be an array of level indices";
        return false;
      }
      out.levels.push_back(level.get<int>());
    }
  }
  if (entry.contains("unit_scale")) {
    if (entry["unit_scale"].is_number())
      out.unitScale = std::to_string(entry["unit_scale"].get<double>());
    else if (entry["unit_scale"].is_string())
      out.unitScale = entry["unit_scale"].get<std::string>();
    else {
      out_reason = where + ": \"unit_scale\" must be a number or a preset name";
      return false;
    }
  }
  return true;
}

} // namespace

int BatchCommand::run() const {
  int shardIndex = 0, shardCount = 1;
  if (!parseShard(shard, shardIndex, shardCount)) {
    printError(manifest, "--shard '" + shard + "' is not I/N with 0 <= I < N");
    return kExitBadInput;
  }
  std::ifstream file(manifest);
  if (!file) {
    printError(manifest, "cannot open the manifest");
    return kExitBadInput;
  }
  std::stringstream text;
  text << file.rdbuf();
  nlohmann::json doc = nlohmann::json::parse(text.str(), nullptr, false);
  if (doc.is_discarded()) {
    printError(manifest, "not JSON");
    return kExitBadInput;
  }
  if (!doc.is_object() || !doc.contains("jobs") || !doc["jobs"].is_array()) {
    printError(manifest, "not a batch manifest: {\"jobs\":[{\"input\",\"plugin\",\"output\",\"options\":{}}]}");
    return kExitBadInput;
  }
  const std::filesystem::path folder = std::filesystem::absolute(manifest).parent_path();
  std::vector<ExportJob> all;
  for (std::size_t i = 0; i < doc["jobs"].size(); ++i) {
    ExportJob job;
    std::string reason;
    if (!readJob(doc["jobs"][i], i, folder, job, reason)) {
      printError(manifest, reason);
      return kExitBadInput;
    }
    all.push_back(std::move(job));
  }
  std::vector<std::size_t> mine;
  for (std::size_t i = 0; i < all.size(); ++i)
    if (i % std::size_t(shardCount) == std::size_t(shardIndex))
      mine.push_back(i);

  PluginHost host;
  host.loadDefault();
  const std::atomic<bool>* cancel = installInterruptHandler();
  const auto start = std::chrono::steady_clock::now();
  std::vector<ExportOutcome> outcomes(mine.size());
  std::vector<double> seconds(mine.size(), 0.0);
  std::atomic<std::size_t> next{0};
  std::atomic<std::size_t> finished{0};
  TerminalProgress line(!quiet && !json);
  const auto worker = [&] {
    for (std::size_t k = next++; k < mine.size(); k = next++) {
      const auto jobStart = std::chrono::steady_clock::now();
      const std::string name = "batch " + std::to_string(finished.load()) + "/" + std::to_string(mine.size()) +
                               " done; job " + std::to_string(mine[k]) + " ";
      outcomes[k] = runExportJob(host, all[mine[k]], cancel,
                                 [&](std::string_view stage, double fraction, std::string_view detail) {
                                   line.show(name + std::string(stage), fraction, detail);
                                 });
      seconds[k] = std::chrono::duration<double>(std::chrono::steady_clock::now() - jobStart).count();
      ++finished;
    }
  };
  std::vector<std::thread> threads;
  for (int t = 1; t < std::min<int>(jobs, static_cast<int>(mine.size())); ++t)
    threads.emplace_back(worker);
  worker();
  for (std::thread& thread : threads)
    thread.join();
  line.clear();
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  int exitCode = kExitOk, failed = 0;
  nlohmann::json jobList = nlohmann::json::array();
  for (std::size_t k = 0; k < mine.size(); ++k) {
    const ExportJob& job = all[mine[k]];
    const ExportOutcome& outcome = outcomes[k];
    if (!outcome.ok()) {
      ++failed;
      if (exitCode == kExitOk)
        exitCode = outcome.exitCode;
      printError(outcome.errorFile, outcome.message);
    }
    jobList.push_back({{"index", mine[k]},
                       {"input", job.input},
                       {"plugin", job.plugin},
                       {"output", job.output},
                       {"ok", outcome.ok()},
                       {"exit", outcome.exitCode},
                       {"message", outcome.message},
                       {"bytes", outcome.bytes},
                       {"seconds", seconds[k]}});
  }
  if (json) {
    const nlohmann::json out = {{"manifest", manifest},
                                {"shard", {{"index", shardIndex}, {"count", shardCount}}},
                                {"jobs", jobList},
                                {"succeeded", int(mine.size()) - failed},
                                {"failed", failed},
                                {"seconds", total}};
    std::cout << out.dump(2) << std::endl;
  } else {
    std::printf("batch %s, shard %d/%d: %zu of %zu jobs, %d at once\n", manifest.c_str(), shardIndex, shardCount,
                mine.size(), all.size(), std::min<int>(jobs, std::max<int>(1, int(mine.size()))));
    for (std::size_t k = 0; k < mine.size(); ++k) {
      const ExportJob& job = all[mine[k]];
      std::printf("  [%zu] %-6s %s -> %s (%s) %.2f s%s\n", mine[k], outcomes[k].ok() ? "ok" : "FAILED",
                  job.input.c_str(), job.output.c_str(), job.plugin.c_str(), seconds[k],
                  outcomes[k].ok() ? (", " + std::to_string(outcomes[k].bytes) + " bytes").c_str() : "");
    }
    std::printf("%zu succeeded, %d failed, %.2f s\n", mine.size() - std::size_t(failed), failed, total);
  }
  return exitCode;
}

} // namespace mlod::cli
