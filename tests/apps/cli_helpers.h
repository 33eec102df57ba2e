#pragma once
// Running the wearscar command from tests: its output, status and files.

#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <string>

#include "common/paths.h"

namespace wearscar_test {

struct CommandResult {
  int status = -1;
  std::string output;  // stdout + stderr
};

// A shell command line; its standard output and exit status.
inline CommandResult Shell(const std::string& cmd) {
  CommandResult r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 65536> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0)
    r.output.append(buf.data(), n);
  const int st = pclose(pipe);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

inline CommandResult Wearscar(const std::string& args) {
  return Shell(std::string(WEARSCAR_BINARY) + " " + args + " 2>&1");
}

inline std::string Slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Every gnuplot script a command wrote in <out>/figure-data (each draws
// some of the figures, in both formats), one after the other.
inline std::string FigureScripts(const std::string& out) {
  return Slurp(out + "/figure-data/figures.gp");
}

inline int CountLines(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

}  // namespace wearscar_test
