#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "wearscar/fusion/batch.h"
#include "wearscar/fusion/products.h"

namespace wearscar::app {

// Thrown for bad command-line input; main maps it to exit status 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Writes text to a temporary name beside `path`, then renames. A failure
// (a full disk, a read-only folder) removes the temporary file and says
// the system's reason.
void WriteTextAtomically(const std::string& path, const std::string& text);

// Everything one command writes into an output folder, written first into
// a hidden staging folder inside it and moved into place by Commit: a run
// that fails leaves nothing new (the destructor removes the staging).
class StagedOutput {
 public:
  explicit StagedOutput(std::string out);
  ~StagedOutput();
  StagedOutput(const StagedOutput&) = delete;
  StagedOutput& operator=(const StagedOutput&) = delete;
  // The folder to write into now.
  const std::string& dir() const { return staging_; }
  // The final folder.
  const std::string& out() const { return out_; }
  // Moves every file of the staging folder into the final folder
  // (replacing files of the same name) and removes the staging.
  void Commit();
  // A path under dir() as it will be after Commit.
  std::string Final(const std::string& staged_path) const;

 private:
  std::string out_, staging_;
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
