#include "cli/batch_command.h"

#include "cli/cli_common.h"
#include "cli/batch_manifest.h"
#include "cli/export_job.h"
#include "cli/terminal_progress.h"
#include "cli/file_checks.h"
#include "runtime/input_file.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <iostream>
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
  command->add_flag("--allow-outside", allowOutside,
                    "write outputs outside the manifest's folder without a warning");
  addProjectOptions(*command, project);
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

ExportJob toExportJob(const ManifestJob& entry) {
  ExportJob job;
  job.input = entry.input;
  job.plugin = entry.plugin;
  job.output = entry.output;
  job.levels = entry.levels;
  job.unitScale = entry.unitScale;
  job.character = entry.character;
  job.skinning = entry.skinning;
  for (auto it = entry.options.begin(); it != entry.options.end(); ++it) {
    const QString key = QString::fromStdString(it.key());
    if (it->is_boolean())
      job.options.insert(key, it->get<bool>());
    else if (it->is_number_integer())
      job.options.insert(key, QVariant::fromValue(it->get<long long>()));
    else if (it->is_number())
      job.options.insert(key, it->get<double>());
    else
      job.options.insert(key, QString::fromStdString(it->get<std::string>()));
  }
  return job;
}

// Nothing lost (file_checks.h), over the whole manifest and before any job runs: no job
// writes the manifest, its own input or another job's input (by file identity), over an
// existing file that is not a regular one, or to the same file as another job.
Error checkOutputs(const std::string& manifest, const std::vector<ExportJob>& jobs) {
  std::vector<std::string> inputs{manifest};
  for (const ExportJob& job : jobs)
    for (std::string& file : exportInputFiles(job.input))
      inputs.push_back(std::move(file));
  std::map<std::string, std::size_t> written; // normalOutputPath() -> job
  std::vector<std::pair<FileIdentity, std::size_t>> existing;
  for (std::size_t i = 0; i < jobs.size(); ++i)
    for (const std::string& file : exportOutputFiles(jobs[i].plugin, jobs[i].output, jobs[i].options)) {
      const std::string where = "job " + std::to_string(i) + ": " + file + ": ";
      if (std::string problem = outputProblem(file, inputs); !problem.empty())
        return Error(where + problem);
      const std::string key = normalOutputPath(file);
      if (const auto other = written.find(key); other != written.end())
        return Error(where + "job " + std::to_string(other->second) + " writes the same file");
      if (const std::optional<FileIdentity> identity = fileIdentity(file)) {
        for (const auto& [seen, other] : existing)
          if (seen == *identity)
            return Error(where + "job " + std::to_string(other) + " writes the same file");
        existing.emplace_back(*identity, i);
      }
      written.emplace(key, i);
    }
  return {};
}

} // namespace

int BatchCommand::run() const {
  int shardIndex = 0, shardCount = 1;
  if (!parseShard(shard, shardIndex, shardCount)) {
    printError(manifest, "--shard '" + shard + "' is not I/N with 0 <= I < N");
    return kExitBadInput;
  }
  std::string reason;
  const std::optional<std::string> text = readInputFile(manifest, kMaxManifestBytes, &reason);
  if (!text) {
    printError(manifest, reason);
    return kExitBadInput;
  }
  const std::filesystem::path folder = std::filesystem::absolute(manifest).parent_path();
  Result<std::vector<ManifestJob>> parsed = parseBatchManifest(*text, folder);
  if (!parsed) {
    printError(manifest, parsed.message());
    return kExitBadInput;
  }
  std::vector<ExportJob> all;
  for (const ManifestJob& entry : *parsed) {
    all.push_back(toExportJob(entry));
    all.back().project = project;
  }
  if (Error error = checkOutputs(manifest, all)) {
    printError(manifest, error.message());
    return kExitBadInput;
  }
  PluginHost host;
  host.loadDefault();
  // Each output's suffix is its plugin's, over the whole manifest (every shard refuses the
  // same manifest) and before any job runs; an unknown plugin fails its own job below.
  for (std::size_t i = 0; i < all.size(); ++i)
    if (std::string problem = outputSuffixProblem(host, all[i].plugin, all[i].output); !problem.empty()) {
      printError(manifest, "job " + std::to_string(i) + ": " + all[i].output + ": " + problem);
      return kExitBadInput;
    }
  if (!allowOutside) {
    const std::string inside = normalOutputPath(folder.string());
    for (std::size_t i = 0; i < all.size(); ++i)
      if (!isInsideFolder(normalOutputPath(all[i].output), inside))
        std::cerr << "warning: " << manifest << ": job " << i << " writes " << all[i].output
                  << ", outside the manifest's folder (--allow-outside: no warning)" << std::endl;
  }
  std::vector<std::size_t> mine;
  for (std::size_t i = 0; i < all.size(); ++i)
    if (i % std::size_t(shardCount) == std::size_t(shardIndex))
      mine.push_back(i);

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
      seconds[k] = secondsSince(jobStart);
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
  const double total = secondsSince(start);

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
    printWarnings(job.output, outcome.warnings);
    jobList.push_back({{"index", mine[k]},
                       {"input", job.input},
                       {"plugin", job.plugin},
                       {"output", job.output},
                       {"ok", outcome.ok()},
                       {"exit", outcome.exitCode},
                       {"message", outcome.message},
                       {"bytes", outcome.bytes},
                       {"seconds", seconds[k]}});
    if (!outcome.character.empty()) // a project's: the character exported
      jobList.back()["character"] = outcome.character;
  }
  if (json) {
    const nlohmann::json out = {{"manifest", manifest},
                                {"shard", {{"index", shardIndex}, {"count", shardCount}}},
                                {"jobs", jobList},
                                {"succeeded", int(mine.size()) - failed},
                                {"failed", failed},
                                {"seconds", total}};
    std::cout << jsonText(out) << std::endl;
  } else {
    std::printf("batch %s, shard %d/%d: %zu of %zu jobs, %d at once\n", manifest.c_str(), shardIndex, shardCount,
                mine.size(), all.size(), std::min<int>(jobs, std::max<int>(1, int(mine.size()))));
    for (std::size_t k = 0; k < mine.size(); ++k) {
      const ExportJob& job = all[mine[k]];
      const std::string character = outcomes[k].character.empty() ? "" : " (character " + outcomes[k].character + ")";
      std::printf("  [%zu] %-6s %s%s -> %s (%s) %.2f s%s\n", mine[k], outcomes[k].ok() ? "ok" : "FAILED",
                  job.input.c_str(), character.c_str(), job.output.c_str(), job.plugin.c_str(), seconds[k],
                  outcomes[k].ok() ? (", " + std::to_string(outcomes[k].bytes) + " bytes").c_str() : "");
    }
    std::printf("%zu succeeded, %d failed, %.2f s\n", mine.size() - std::size_t(failed), failed, total);
  }
  return exitCode;
}

} // namespace mlod::cli
