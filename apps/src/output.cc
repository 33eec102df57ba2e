#include "output.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "commands.h"

namespace wearscar::app {

namespace {
int g_exit_status = 0;
}  // namespace

void SetExitStatus(int status) { g_exit_status = status; }
int ExitStatus() { return g_exit_status; }

void WriteTextAtomically(const std::string& path, const std::string& text) {
  const std::string tmp =
      fmt::format("{}.tmp-{:08x}", path, std::random_device{}());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) {
      throw UsageError(
          fmt::format("{}: cannot write: {}", path, std::strerror(errno)));
    }
    out << text;
    out.flush();
    if (!out) {
      out.close();
      std::remove(tmp.c_str());
      throw UsageError(fmt::format("{}: write failed", path));
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw UsageError(fmt::format("{}: cannot rename: {}", path, ec.message()));
  }
}

std::string Table::ToCsv() const {
  fmt::memory_buffer buf;
  for (size_t c = 0; c < columns.size(); ++c) {
    fmt::format_to(std::back_inserter(buf), "{}{}", c ? "," : "", columns[c]);
  }
  buf.push_back('\n');
  for (const auto& row : rows) {
    for (size_t c = 0; c < row.size(); ++c) {
      if (c) buf.push_back(',');
      if (std::isfinite(row[c]))
        fmt::format_to(std::back_inserter(buf), "{:.8g}", row[c]);
    }
    buf.push_back('\n');
  }
  return fmt::to_string(buf);
}

std::string SpecimenName(const std::string& path) {
  std::string stem = std::filesystem::path(path).stem().string();
  for (const char* suffix :
       {".force", "_force", "-force", ".scan", "_scan", "-scan"}) {
    const std::string sfx = suffix;
    if (stem.size() > sfx.size() &&
        stem.compare(stem.size() - sfx.size(), sfx.size(), sfx) == 0) {
      return stem.substr(0, stem.size() - sfx.size());
    }
  }
  return stem;
}

void EnsureDirectory(const std::string& path) {
  std::error_code ec;
  std::filesystem::create_directories(path, ec);
  if (ec)
    throw UsageError(
        fmt::format("{}: cannot create directory: {}", path, ec.message()));
}

Progress::Progress(std::string label, long total)
    : label_(std::move(label)),
      total_(total),
      tty_(isatty(STDERR_FILENO) != 0) {}

void Progress::Update(long done) {
  const int percent = total_ > 0 ? static_cast<int>(100 * done / total_) : 100;
  if (tty_) {
    if (percent == last_percent_) return;
    const int width = 30, filled = width * percent / 100;
    fmt::print(stderr,
               "\r{} [{}{}] {:3d}% ({}/{})",
               label_,
               std::string(filled, '#'),
               std::string(width - filled, '.'),
               percent,
               done,
               total_);
    std::fflush(stderr);
  } else if (percent / 25 != last_percent_ / 25) {
    fmt::print(stderr, "{}: {}/{} ({}%)\n", label_, done, total_, percent);
  }
  last_percent_ = percent;
}

void Progress::Finish() {
  Update(total_);
  if (tty_) fmt::print(stderr, "\n");
}

}  // namespace wearscar::app
