#include "wearscar/support/prefault.h"

#include <algorithm>
#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace wearscar::support {
namespace {

constexpr std::uintptr_t kPage = 4096, kHuge = std::uintptr_t{2} << 20;

std::uintptr_t Up(std::uintptr_t a, std::uintptr_t to) {
  return (a + to - 1) & ~(to - 1);
}
std::uintptr_t Down(std::uintptr_t a, std::uintptr_t to) {
  return a & ~(to - 1);
}

}  // namespace

void BackgroundPrefault::Start(std::vector<Buffer> buffers) {
  Stop();
#if defined(__linux__) && defined(MADV_POPULATE_WRITE) && defined(MADV_HUGEPAGE)
  std::size_t total = 0;
  for (const auto& [data, bytes] : buffers) {
    total += bytes;
    // The whole 2 MiB pages inside the buffer.
    const auto begin = reinterpret_cast<std::uintptr_t>(data);
    const std::uintptr_t first = Up(begin, kHuge);
    const std::uintptr_t last = Down(begin + bytes, kHuge);
    if (data != nullptr && last > first)
      madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
  }
  if (total < 2 * kHuge) return;
  stop_ = false;
  thread_ = std::thread([this, b = std::move(buffers)] { Run(b); });
#else
  (void)buffers;
#endif
}

void BackgroundPrefault::Run(const std::vector<Buffer>& buffers) {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
  // Step s maps each buffer's pages below its (s + 1)-th 2 MiB boundary
  // not mapped before, the buffers in turn.
  bool first = true;
  for (std::uintptr_t step = 0;; ++step) {
    bool any = false;
    for (const auto& [data, bytes] : buffers) {
      if (stop_.load(std::memory_order_relaxed)) return;
      const auto begin = reinterpret_cast<std::uintptr_t>(data);
      const std::uintptr_t end = Down(begin + bytes, kPage);
      const std::uintptr_t boundary = Up(begin, kHuge) + step * kHuge;
      const std::uintptr_t from =
          step == 0 ? Up(begin, kPage) : boundary - kHuge;
      if (data == nullptr || from >= end) continue;
      any = true;
      const std::uintptr_t to = std::min(end, boundary);
      if (from >= to) continue;
      const int failed = madvise(
          reinterpret_cast<void*>(from), to - from, MADV_POPULATE_WRITE);
      if (failed != 0 && first) return;  // not offered here
      first = false;
    }
    if (!any) return;
  }
#else
  (void)buffers;
#endif
}

void BackgroundPrefault::Stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void BackgroundPrefault::Wait() {
  if (thread_.joinable()) thread_.join();
}

}  // namespace wearscar::support
