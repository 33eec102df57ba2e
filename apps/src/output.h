#pragma once

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "usage_error.h"
#include "wearscar/fusion/batch.h"
#include "wearscar/fusion/products.h"

namespace wearscar::app {

// What an analysing command prints on stdout: its human summary (the
// default), nothing (--quiet) or its summary as JSON (--json). Warnings
// and errors go to stderr in every mode.
enum class PrintMode { kText, kQuiet, kJson };
PrintMode CurrentPrintMode();
// Adds -q,--quiet and --json to a command.
void AddPrintModeOptions(CLI::App* cmd);

// fmt::print to stdout in text mode only.
template <typename... Args>
void Say(fmt::format_string<Args...> format, Args&&... args) {
  if (CurrentPrintMode() == PrintMode::kText)
    fmt::print(format, std::forward<Args>(args)...);
}

// The command's summary on stdout in --json mode (indented, one document).
void PrintJsonSummary(const nlohmann::json& summary);

// Writes text to a temporary name beside `path`, then renames. A failure
// (a full disk, a read-only folder) removes the temporary file and says
// the system's reason.
void WriteTextAtomically(const std::string& path, const std::string& text);

// Everything one command writes into an output folder, written first into
// a hidden staging folder inside it and moved into place by Commit: a run
// that fails leaves nothing new (the destructor removes the staging).
class StagedOutput {
 public:
  // `command` names the run in the folder's manifest (RecordOutputs).
  StagedOutput(std::string out, std::string command);
  ~StagedOutput();
  StagedOutput(const StagedOutput&) = delete;
  StagedOutput& operator=(const StagedOutput&) = delete;
  // The folder to write into now.
  const std::string& dir() const { return staging_; }
  // The final folder.
  const std::string& out() const { return out_; }
  // Moves every file of the staging folder (and its sub-folders) into the
  // final folder, replacing files of the same name; removes the files an
  // earlier wearscar run wrote there that this one did not (RecordOutputs).
  // Returns the number of files written.
  size_t Commit();
  // A path under dir() as it will be after Commit.
  std::string Final(const std::string& staged_path) const;

 private:
  std::string out_, command_, staging_;
};

// An exclusive lock on an output folder for the life of the object (flock
// on <out>/.wearscar.lock; released when the process ends, however it
// ends). A second writer fails at once with a clear message.
class OutputLock {
 public:
  explicit OutputLock(const std::string& out);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

 private:
  int fd_ = -1;
};

// Keeps <out>/.wearscar-manifest, the list of what wearscar wrote in a
// folder and which command wrote it (relative paths; a folder written by
// wearscar ends with '/'). With remove_stale, what the same command wrote
// there before and `entries` does not name is removed (a folder only when
// it has a manifest of its own); what another command wrote (the
// simulated inputs a fuse reads from the same folder) and files wearscar
// did not write are never touched. Without remove_stale nothing is
// removed and the lists are merged (an audit shard adds to the folder).
void RecordOutputs(const std::string& out,
                   const std::string& command,
                   std::vector<std::string> entries,
                   bool remove_stale);

using fusion::Table;

// A specimen name from a file name: the stem without ".force" / "_force"
// ("data/B-RT-R.force.csv" -> "B-RT-R").
using fusion::SpecimenName;

// Creates the directory (and parents); UsageError on failure.
void EnsureDirectory(const std::string& path);

// Progress on a terminal (a bar on stderr), plain lines otherwise.
class Progress {
 public:
  Progress(std::string label, long total);
  void Update(long done);
  void Finish();

 private:
  std::string label_;
  long total_;
  bool tty_;
  int last_percent_ = -1;
};

}  // namespace wearscar::app
