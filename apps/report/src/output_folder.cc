#include "wearscar/report/output_folder.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <stdio.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <vector>

#include "lock_files.h"
#include "wearscar/support/atomic_file.h"

namespace wearscar::report {

void WriteTextAtomically(const std::string& path, const std::string& text) {
  support::WriteFileAtomically<OutputError>(path, text);
}

StagedOutput::StagedOutput(std::string out, std::string command)
    : out_(std::move(out)), command_(std::move(command)) {
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

namespace {

constexpr const char* kManifest = ".wearscar-manifest";

// A manifest entry is a relative path inside the folder (a folder entry
// ends with '/'); anything else (absolute, "..", empty) is ignored, so an
// edited manifest cannot make wearscar remove files outside the folder.
bool SafeEntry(const std::string& entry) {
  const std::filesystem::path p(entry);
  if (entry.empty() || p.is_absolute()) return false;
  for (const auto& part : p) {
    if (part == ".." || part == ".") return false;
  }
  return true;
}

// The folder's manifest: one line per file (or folder) wearscar wrote,
// "COMMAND<tab>PATH".
struct ManifestEntry {
  std::string command, path;
};

std::vector<ManifestEntry> ReadManifest(const std::string& out) {
  std::ifstream in(std::filesystem::path(out) / kManifest);
  std::vector<ManifestEntry> entries;
  for (std::string line; std::getline(in, line);) {
    const size_t tab = line.find('\t');
    if (tab == std::string::npos) continue;
    ManifestEntry e{line.substr(0, tab), line.substr(tab + 1)};
    if (SafeEntry(e.path)) entries.push_back(std::move(e));
  }
  return entries;
}

// Removes what `old` names in `out`: a file, or a folder that has a
// manifest of its own (wearscar wrote it); a sub-folder left empty goes
// with its last file.
void RemoveStale(const std::string& out, const std::string& old) {
  namespace fs = std::filesystem;
  const fs::path p = fs::path(out) / old;
  std::error_code ec;
  if (old.back() == '/') {
    if (fs::is_regular_file(p / kManifest, ec)) fs::remove_all(p, ec);
    return;
  }
  if (!fs::is_regular_file(fs::symlink_status(p, ec))) return;
  fs::remove(p, ec);
  for (fs::path d = fs::path(old).parent_path(); !d.empty();
       d = d.parent_path()) {
    if (!fs::remove(fs::path(out) / d, ec)) break;
  }
}

// An earlier run's regular file at `to` exchanged with the new one at
// `from` (readers see one or the other, as with a rename); the earlier
// one leaves with the staging folder. A rename over it makes ext4 start
// writing the new file out first (auto_da_alloc), 0.3-2 ms a file. False
// where there is none, or where the file system cannot exchange (a
// rename then moves the file).
bool ExchangedWithEarlier(const std::string& from, const std::string& to) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(
          std::filesystem::symlink_status(to, ec)))
    return false;
  return ::renameat2(
             AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_EXCHANGE) ==
         0;
}

}  // namespace

void RecordOutputs(const std::string& out,
                   const std::string& command,
                   std::vector<std::string> entries,
                   bool remove_stale) {
  namespace fs = std::filesystem;
  std::sort(entries.begin(), entries.end());
  std::vector<ManifestEntry> kept;
  for (ManifestEntry& e : ReadManifest(out)) {
    const bool rewritten =
        std::binary_search(entries.begin(), entries.end(), e.path);
    if (rewritten) continue;  // listed again below, under this command
    if (e.command == command && remove_stale) {
      RemoveStale(out, e.path);
    } else {
      kept.push_back(std::move(e));  // another command's, or a shard's
    }
  }
  std::string text;
  for (const ManifestEntry& e : kept)
    text.append(e.command).append("\t").append(e.path).append("\n");
  for (const std::string& e : entries)
    text.append(command).append("\t").append(e).append("\n");
  WriteTextAtomically((fs::path(out) / kManifest).string(), text);
}

size_t StagedOutput::Commit() {
  namespace fs = std::filesystem;
  std::vector<std::string> fresh;
  for (const auto& e : fs::recursive_directory_iterator(staging_)) {
    if (e.is_regular_file())
      fresh.push_back(fs::relative(e.path(), staging_).string());
  }
  // Files of the earlier run that this one does not write go first, so
  // that a name reused as a folder (or the reverse) can move in.
  RecordOutputs(out_, command_, fresh, true);
  for (const std::string& f : fresh) {
    const fs::path to = fs::path(out_) / f;
    EnsureDirectory(to.parent_path().string());
    const std::string from = (fs::path(staging_) / f).string();
    if (ExchangedWithEarlier(from, to)) continue;
    if (std::rename(from.c_str(), to.c_str()) != 0) {
      throw OutputError(fmt::format(
          "{}: cannot move into place: {}", to.string(), std::strerror(errno)));
    }
  }
  return fresh.size();
}

std::string StagedOutput::Final(const std::string& staged_path) const {
  return (std::filesystem::path(out_) /
          std::filesystem::path(staged_path).filename())
      .string();
}

OutputLock::OutputLock(const std::string& out, Mode mode, bool break_lock) {
  EnsureDirectory(out);
  const std::string path =
      (std::filesystem::path(out) /
       (mode == kMerge ? ".wearscar.merge.lock" : ".wearscar.lock"))
          .string();
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    throw OutputError(fmt::format(
        "{}: cannot create the lock file: {}", path, std::strerror(errno)));
  }
  const int how = mode == kMerge   ? LOCK_EX
                  : mode == kShard ? LOCK_SH | LOCK_NB
                                   : LOCK_EX | LOCK_NB;
  int rc;
  do {
    rc = ::flock(fd_, how);
  } while (rc != 0 && errno == EINTR && mode == kMerge);
  if (rc != 0 && (errno == ENOLCK || errno == ENOSYS || errno == EOPNOTSUPP)) {
    const int refused = errno;
    ::close(fd_);
    fd_ = -1;
    static bool said = false;  // once per process
    if (!said) {
      fmt::print(stderr,
                 "wearscar: warning: {}: the file system refuses flock ({}; "
                 "a Lustre or NFS mount without locks?): locking with files "
                 "created with O_EXCL instead (.wearscar.lock.*; "
                 "--break-lock clears one left by a killed wearscar)\n",
                 out,
                 std::strerror(refused));
      said = true;
    }
    lock_file_ = internal::TakeLockFile(
        out,
        mode == kMerge   ? internal::LockFileMode::kMerge
        : mode == kShard ? internal::LockFileMode::kShard
                         : internal::LockFileMode::kExclusive,
        break_lock);
    return;
  }
  if (rc != 0) {
    ::close(fd_);
    fd_ = -1;
    throw OutputError(fmt::format(
        "{}: another wearscar is writing into this folder (it holds {}); "
        "wait for it or choose another --out{}",
        out,
        path,
        mode == kShard ? " (shards of one audit may share a folder; an "
                         "unsharded run may not)"
                       : ""));
  }
}

OutputLock::~OutputLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock
  std::error_code ec;
  if (!lock_file_.empty()) std::filesystem::remove(lock_file_, ec);
}

void EnsureDirectory(const std::string& path) {
  std::error_code ec;
  std::filesystem::create_directories(path, ec);
  if (ec)
    throw OutputError(
        fmt::format("{}: cannot create directory: {}", path, ec.message()));
}

}  // namespace wearscar::report
