#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace wearscar::app {

// Thrown for bad command-line input; main maps it to exit status 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Writes text to a temporary name beside `path`, then renames.
void WriteTextAtomically(const std::string& path, const std::string& text);

// A CSV table: column names carry units ("mu_hat", "x_mm", "Q_N").
struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  std::string ToCsv() const;
};

// A specimen name from a file name: the stem without ".force" / "_force"
// ("data/B-RT-R.force.csv" -> "B-RT-R").
std::string SpecimenName(const std::string& path);

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
