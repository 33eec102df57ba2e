#pragma once

// Large fresh buffers mapped ahead of the code that fills them.

#include <atomic>
#include <cstddef>
#include <thread>
#include <utility>
#include <vector>

namespace wearscar::support {

// Maps the pages of large fresh buffers on a thread of its own while the
// caller fills them: transparent huge pages advised for each, then each
// buffer's next 2 MiB in turn mapped by MADV_POPULATE_WRITE, as a write
// would map them but writing nothing (a page the caller reaches first is
// left as it is). On a virtual machine the first touch of fresh memory,
// more than the copying, is the cost of filling a buffer; beside the
// filling it takes a core that would wait. Only a hint: no value changes,
// and nothing happens where the kernel does not offer it (before Linux
// 5.14) or for buffers under 4 MiB in all. Stop() before a buffer is freed
// or moved.
class BackgroundPrefault {
 public:
  // A buffer: its first byte and its size in bytes.
  using Buffer = std::pair<void*, std::size_t>;

  BackgroundPrefault() = default;
  BackgroundPrefault(const BackgroundPrefault&) = delete;
  BackgroundPrefault& operator=(const BackgroundPrefault&) = delete;
  ~BackgroundPrefault() { Stop(); }

  void Start(std::vector<Buffer> buffers);
  // Stops where it is and waits for the thread.
  void Stop();
  // Waits until every page is mapped (or the kernel declined).
  void Wait();

 private:
  void Run(const std::vector<Buffer>& buffers);

  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace wearscar::support
