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
#include "wearscar/support/atomic_file.h"

namespace wearscar::app {

namespace {
int g_exit_status = 0;
}  // namespace

void SetExitStatus(int status) { g_exit_status = status; }
int ExitStatus() { return g_exit_status; }

void WriteTextAtomically(const std::string& path, const std::string& text) {
  support::WriteFileAtomically<UsageError>(path, text);
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
