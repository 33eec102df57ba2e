#include "wearscar/report/figures.h"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "draw.h"
#include "wearscar/report/output_folder.h"

namespace wearscar::report {
namespace {

// gnuplot on the PATH, where posix_spawnp looks for it.
bool GnuplotOnPath() {
  const char* env = std::getenv("PATH");
  const std::string path = env ? env : "/usr/bin:/bin";
  for (size_t start = 0; start <= path.size();) {
    const size_t colon = std::min(path.find(':', start), path.size());
    const std::string dir = path.substr(start, colon - start);
    if (::access(((dir.empty() ? "." : dir) + "/gnuplot").c_str(), X_OK) == 0)
      return true;
    start = colon + 1;
  }
  return false;
}

}  // namespace

std::string FigureDataPath(const std::string& dir, const std::string& file) {
  const std::filesystem::path sub = std::filesystem::path(dir) / kFigureData;
  EnsureDirectory(sub.string());
  return (sub / file).string();
}

bool FigureFormats::Parse(const std::string& text, FigureFormats* formats) {
  FigureFormats f{false, false};
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = std::min(text.find(',', start), text.size());
    const std::string word = text.substr(start, comma - start);
    if (word == "svg") {
      f.svg = true;
    } else if (word == "png") {
      f.png = true;
    } else {
      return false;
    }
    start = comma + 1;
  }
  *formats = f;
  return true;
}

std::string FigureFormats::Text() const {
  return svg && png ? "svg,png" : png ? "png" : svg ? "svg" : "";
}

bool FigureFormats::IsValid(std::string* why) const {
  if (svg || png) return true;
  if (why) *why = "figures need a format: svg, png or both";
  return false;
}

bool RunGnuplotScript(const std::string& dir, const std::string& script) {
  return internal::RunGnuplot(dir, script);
}

bool PlotterAvailable(std::string* why) {
  static const bool found = GnuplotOnPath();
  if (!found && why) {
    *why =
        "gnuplot was not found: figures are skipped, the numeric outputs are "
        "complete (install the Debian package gnuplot-nox)";
  }
  return found;
}

}  // namespace wearscar::report
