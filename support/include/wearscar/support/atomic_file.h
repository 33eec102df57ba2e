#pragma once

// Writing a file so that no reader ever sees it half-written: the bytes go
// to a temporary name beside it, which is renamed into place once complete.

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <string_view>

namespace wearscar::support {

// A temporary file beside `path`: Write appends, Commit renames it into
// place; destroyed uncommitted, it is removed. Failures throw Error with
// the path and the system's reason ("No space left on device").
template <class Error>
class AtomicFile {
 public:
  explicit AtomicFile(std::string path)
      : path_(std::move(path)),
        tmp_(fmt::format("{}.tmp-{:08x}", path_, std::random_device{}())) {
    fd_ = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0) Fail("cannot write", errno);
  }
  ~AtomicFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!committed_) std::remove(tmp_.c_str());
  }
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void Write(std::string_view bytes) {
    size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
      if (n < 0) {
        if (errno == EINTR) continue;
        Fail("write failed", errno);
      }
      done += static_cast<size_t>(n);
    }
  }
  void Commit() {
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) Fail("write failed", errno);
    if (std::rename(tmp_.c_str(), path_.c_str()) != 0)
      Fail("cannot rename into place", errno);
    committed_ = true;
  }

 private:
  [[noreturn]] void Fail(const char* what, int error) {
    throw Error(fmt::format("{}: {}: {}", path_, what, std::strerror(error)));
  }
  std::string path_, tmp_;
  int fd_ = -1;
  bool committed_ = false;
};

// The whole of `bytes` written atomically to `path`.
template <class Error>
void WriteFileAtomically(const std::string& path, std::string_view bytes) {
  AtomicFile<Error> file(path);
  file.Write(bytes);
  file.Commit();
}

}  // namespace wearscar::support
