#include "lock_files.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

#include "wearscar/report/output_folder.h"

namespace wearscar::report::internal {
namespace {

namespace fs = std::filesystem;

// How long a merge waits for another to end before it says who holds it.
constexpr auto kMergeWait = std::chrono::minutes(15);

std::string HostName() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0) return "unknown-host";
  return name;
}

// Who holds a lock file, as it says.
struct Holder {
  std::string host, file;
  long pid = 0;
  long long since = 0;  // seconds since the epoch
  // Gone: it ran on this host and no process has its pid.
  bool Gone() const {
    return host == HostName() && pid > 0 &&
           ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
  }
  std::string Said() const {
    const std::time_t t = static_cast<std::time_t>(since);
    char when[32] = "?";
    std::tm tm{};
    if (gmtime_r(&t, &tm) != nullptr)
      std::strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S UTC", &tm);
    return fmt::format("{} (wearscar pid {} on {} since {})",
                       file,
                       pid,
                       host.empty() ? "?" : host,
                       when);
  }
};

Holder ReadHolder(const fs::path& file) {
  Holder h;
  h.file = file.string();
  std::ifstream in(file);
  in >> h.host >> h.pid >> h.since;
  return h;
}

// Creates `file` naming this process; false when it exists.
bool Create(const fs::path& file) {
  const int fd =
      ::open(file.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) {
    if (errno == EEXIST) return false;
    throw OutputError(fmt::format("{}: cannot create the lock file: {}",
                                  file.string(),
                                  std::strerror(errno)));
  }
  const std::string me =
      fmt::format("{} {} {}\n",
                  HostName(),
                  ::getpid(),
                  static_cast<long long>(std::time(nullptr)));
  const bool written =
      ::write(fd, me.data(), me.size()) == static_cast<ssize_t>(me.size());
  ::close(fd);
  if (!written) {
    fs::remove(file);
    throw OutputError(fmt::format("{}: cannot write the lock file: {}",
                                  file.string(),
                                  std::strerror(errno)));
  }
  return true;
}

std::vector<fs::path> ShardFiles(const fs::path& out) {
  std::vector<fs::path> found;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(out, ec))
    if (e.path().filename().string().rfind(".wearscar.lock.shard-", 0) == 0)
      found.push_back(e.path());
  return found;
}

// A lock file that stands in the way: removed with break_lock, else the
// refusal that names its holder.
void Clear(const std::string& out, const Holder& h, bool break_lock) {
  if (break_lock) {
    std::error_code ec;
    fs::remove(h.file, ec);
    return;
  }
  throw OutputError(
      h.Gone()
          ? fmt::format("{}: a stale lock: {} is no longer running (killed?); "
                        "expected no lock (--break-lock removes it)",
                        out,
                        h.Said())
          : fmt::format("{}: another wearscar is writing into this folder: {}; "
                        "wait for it or choose another --out (--break-lock if "
                        "that wearscar is gone)",
                        out,
                        h.Said()));
}

void ClearShards(const std::string& out, bool break_lock) {
  for (const fs::path& f : ShardFiles(out))
    Clear(out, ReadHolder(f), break_lock);
}

}  // namespace

std::string TakeLockFile(const std::string& out,
                         LockFileMode mode,
                         bool break_lock) {
  const fs::path dir(out);
  const fs::path held = dir / ".wearscar.lock.held";
  switch (mode) {
    case LockFileMode::kExclusive:
      ClearShards(out, break_lock);
      if (!Create(held)) {
        Clear(out, ReadHolder(held), break_lock);
        if (!Create(held)) Clear(out, ReadHolder(held), false);
      }
      return held.string();
    case LockFileMode::kShard: {
      if (fs::exists(held)) Clear(out, ReadHolder(held), break_lock);
      const fs::path mine =
          dir /
          fmt::format(".wearscar.lock.shard-{}-{}", HostName(), ::getpid());
      if (!Create(mine)) {  // a pid reused: the file is a dead one's
        fs::remove(mine);
        Create(mine);
      }
      return mine.string();
    }
    case LockFileMode::kMerge: {
      const fs::path merge = dir / ".wearscar.merge.lock.held";
      const auto until = std::chrono::steady_clock::now() + kMergeWait;
      while (!Create(merge)) {
        const Holder h = ReadHolder(merge);
        if (break_lock || h.Gone() || std::chrono::steady_clock::now() > until)
          Clear(out, h, break_lock);
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
      }
      return merge.string();
    }
  }
  return {};
}

}  // namespace wearscar::report::internal
