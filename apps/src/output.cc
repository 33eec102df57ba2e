#include "output.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
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
  auto fail = [&](const char* what, int error) {
    std::remove(tmp.c_str());
    throw UsageError(
        fmt::format("{}: {}: {}", path, what, std::strerror(error)));
  };
  const int fd =
      ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail("cannot write", errno);
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int error = errno;
      ::close(fd);
      fail("write failed", error);
    }
    done += static_cast<size_t>(n);
  }
  if (::close(fd) != 0) fail("write failed", errno);
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    fail("cannot rename into place", errno);
}

StagedOutput::StagedOutput(std::string out) : out_(std::move(out)) {
  EnsureDirectory(out_);
  // Staging left by a run that was killed (the caller holds the folder's
  // lock, so no other run is using one).
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(out_, ec)) {
    if (e.path().filename().string().rfind(".wearscar-staging-", 0) == 0)
      std::filesystem::remove_all(e.path(), ec);
  }
  staging_ = (std::filesystem::path(out_) /
              fmt::format(".wearscar-staging-{:08x}", std::random_device{}()))
                 .string();
  EnsureDirectory(staging_);
}

StagedOutput::~StagedOutput() {
  std::error_code ec;
  std::filesystem::remove_all(staging_, ec);
}

void StagedOutput::Commit() {
  for (const auto& e : std::filesystem::directory_iterator(staging_)) {
    if (!e.is_regular_file()) continue;
    const auto to = std::filesystem::path(out_) / e.path().filename();
    if (std::rename(e.path().c_str(), to.c_str()) != 0) {
      throw UsageError(fmt::format(
          "{}: cannot move into place: {}", to.string(), std::strerror(errno)));
    }
  }
}

std::string StagedOutput::Final(const std::string& staged_path) const {
  return (std::filesystem::path(out_) /
          std::filesystem::path(staged_path).filename())
      .string();
}

OutputLock::OutputLock(const std::string& out) {
  EnsureDirectory(out);
  const std::string path =
      (std::filesystem::path(out) / ".wearscar.lock").string();
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    throw UsageError(fmt::format(
        "{}: cannot create the lock file: {}", path, std::strerror(errno)));
  }
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd_);
    fd_ = -1;
    throw UsageError(fmt::format(
        "{}: another wearscar is writing into this folder (it holds {}); "
        "wait for it or choose another --out",
        out,
        path));
  }
}

OutputLock::~OutputLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock
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
