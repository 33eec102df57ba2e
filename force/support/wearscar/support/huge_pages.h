// Large working buffers: ask the kernel for transparent huge pages before
// the first write touches them.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <thread>
#include <utility>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace wearscar::support {

// Advises transparent huge pages for the whole 2 MiB pages inside
// [data, data + bytes). Call it on a fresh buffer, before it is written:
// a first write then maps 2 MiB at once instead of 512 pages of 4 KiB,
// each a page fault (about 10 us apiece on a virtual machine). Only a
// hint: it changes no value, fails silently, and does nothing for buffers
// under 2 MiB (a 2-4 MiB buffer holds one whole 2 MiB page when its start
// allows) or where the kernel does not offer it.
inline void AdviseHugePages(void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
  if (data == nullptr || bytes < kHuge) return;
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + kHuge - 1) & ~(kHuge - 1);
  const std::uintptr_t last = (begin + bytes) & ~(kHuge - 1);
  if (last > first) {
    madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
  }
#else
  (void)data;
  (void)bytes;
#endif
}

// Maps the pages of large fresh buffers on a thread of its own while the
// caller fills them front to back: each buffer's next 2 MiB in turn, by
// MADV_POPULATE_WRITE, which maps a page as a write fault would without
// writing to it (the caller's values are never touched; a page the caller
// reaches first is simply skipped). On a virtual machine the host's first
// touch of fresh memory, not the copying, is most of the cost of filling a
// buffer; done beside the filling, it costs no wall time where a core is
// free. Only a hint, as AdviseHugePages: nothing happens where the kernel
// does not offer it (before Linux 5.14). Stop() (or the destructor) before
// the buffers are freed or moved.
class BackgroundPrefault {
 public:
  BackgroundPrefault() = default;
  BackgroundPrefault(const BackgroundPrefault&) = delete;
  BackgroundPrefault& operator=(const BackgroundPrefault&) = delete;
  ~BackgroundPrefault() { Stop(); }

  // Starts on `buffers` (begin, bytes); buffers under 4 MiB in all are
  // left to their first writes (a thread would cost more than it saves).
  void Start(std::vector<std::pair<void*, std::size_t>> buffers) {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
    Stop();
    std::size_t total = 0;
    for (const auto& b : buffers) total += b.second;
    if (total < (std::size_t{4} << 20)) return;
    stop_ = false;
    thread_ = std::thread([this, buffers = std::move(buffers)] {
      constexpr std::uintptr_t kPage = 4096, kStep = std::uintptr_t{2} << 20;
      for (std::uintptr_t offset = 0;; offset += kStep) {
        bool any = false;
        for (const auto& [data, bytes] : buffers) {
          if (stop_.load(std::memory_order_relaxed)) return;
          const auto begin = reinterpret_cast<std::uintptr_t>(data);
          const std::uintptr_t end = (begin + bytes) & ~(kPage - 1);
          // Whole pages only, in 2 MiB steps from the first 2 MiB boundary
          // (the pages before it with the first step).
          const std::uintptr_t aligned = (begin + kStep - 1) & ~(kStep - 1);
          const std::uintptr_t from = offset == 0
                                          ? (begin + kPage - 1) & ~(kPage - 1)
                                          : aligned + offset - kStep;
          const std::uintptr_t to = std::min(end, aligned + offset);
          if (from >= to) continue;
          any = true;
          if (madvise(reinterpret_cast<void*>(from),
                      to - from,
                      MADV_POPULATE_WRITE) != 0 &&
              offset == 0)
            return;  // not offered here
        }
        if (!any && offset > 0) return;
      }
    });
#else
    (void)buffers;
#endif
  }

  // Stops (if running) and waits for the thread.
  void Stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }

  // Waits until every page is mapped (or the kernel declined).
  void Wait() {
    if (thread_.joinable()) thread_.join();
  }

 private:
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace wearscar::support
