// Large fresh buffers: ask the kernel for transparent huge pages before the
// first write touches them.
#pragma once

#include <cstddef>
#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace wearscar::support {

// Advises transparent huge pages for the whole 2 MiB pages inside
// [data, data + bytes); returns how many bytes were advised. Call it on a
// fresh buffer before it is written: a first write then maps 2 MiB at once
// instead of 512 pages of 4 KiB, each a page fault (costly on a virtual
// machine; docs/performance.md). Only a hint: it changes no value, fails
// silently, and does nothing for a buffer holding no whole 2 MiB page or
// where the kernel does not offer it.
inline std::size_t AdviseHugePages(void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
  if (data == nullptr || bytes < kHuge) return 0;
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + kHuge - 1) & ~(kHuge - 1);
  const std::uintptr_t last = (begin + bytes) & ~(kHuge - 1);
  if (last <= first) return 0;
  madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
  return last - first;
#else
  (void)data;
  (void)bytes;
  return 0;
#endif
}

}  // namespace wearscar::support
