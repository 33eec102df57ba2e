#include "wearscar/support/prefault.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <memory>
#include <thread>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace wearscar::support {
namespace {

// The pages are mapped while the buffers are written, front to back as a
// reader fills its columns, and no value is changed by it: three buffers
// of sizes that end inside a page, off the 2 MiB boundaries, one written
// ahead of the prefault, one behind it.
TEST(BackgroundPrefault, MapsBesideTheWritingAndChangesNoValue) {
  const std::size_t sizes[] = {(std::size_t{9} << 20) + 1234,
                               (std::size_t{3} << 20) + 8,
                               std::size_t{5} << 20};
  std::vector<std::unique_ptr<double[]>> owned;
  std::vector<BackgroundPrefault::Buffer> buffers;
  for (const std::size_t bytes : sizes) {
    owned.emplace_back(new double[bytes / sizeof(double) + 1]);
    // Off a 2 MiB boundary by a page and a bit.
    buffers.emplace_back(owned.back().get() + 515, bytes - 515 * 8);
  }
  BackgroundPrefault prefault;
  prefault.Start(buffers);
  for (std::size_t b = 0; b < buffers.size(); ++b) {
    auto* v = static_cast<double*>(buffers[b].first);
    const std::size_t n = buffers[b].second / sizeof(double);
    for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<double>(b * n + i);
  }
  prefault.Wait();
  for (std::size_t b = 0; b < buffers.size(); ++b) {
    const auto* v = static_cast<const double*>(buffers[b].first);
    const std::size_t n = buffers[b].second / sizeof(double);
    for (std::size_t i = 0; i < n; i += 997)
      ASSERT_EQ(v[i], static_cast<double>(b * n + i)) << b << " " << i;
    EXPECT_EQ(v[n - 1], static_cast<double>(b * n + n - 1));
  }
  // Stopped again, started on nothing, destroyed: nothing happens.
  prefault.Stop();
  prefault.Start({});
  prefault.Stop();
}

// Stopped while it runs (before the buffers grow), it returns at once.
TEST(BackgroundPrefault, StopsBeforeTheBuffersAreFreed) {
  std::vector<double> v((std::size_t{64} << 20) / sizeof(double));
  BackgroundPrefault prefault;
  prefault.Start({{v.data(), v.size() * sizeof(double)}});
  prefault.Stop();
  v.assign(v.size(), 1.0);
  EXPECT_EQ(v.back(), 1.0);
}

#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
// Fresh memory nobody writes is mapped once it has waited (where the
// kernel offers the mapping).
TEST(BackgroundPrefault, MapsEveryWholePageOfAFreshBuffer) {
  const std::size_t bytes = std::size_t{12} << 20, page = 4096;
  void* map = mmap(nullptr,
                   bytes,
                   PROT_READ | PROT_WRITE,
                   MAP_PRIVATE | MAP_ANONYMOUS,
                   -1,
                   0);
  ASSERT_NE(map, MAP_FAILED);
  if (madvise(map, page, MADV_POPULATE_WRITE) != 0) {
    munmap(map, bytes);
    GTEST_SKIP() << "the kernel does not offer MADV_POPULATE_WRITE";
  }
  std::vector<unsigned char> resident(bytes / page);
  ASSERT_EQ(mincore(map, bytes, resident.data()), 0);
  std::size_t before = 0;
  for (unsigned char r : resident) before += r & 1;
  EXPECT_LE(before, 1u + (std::size_t{2} << 20) / page);  // (a huge page)
  BackgroundPrefault prefault;
  prefault.Start({{static_cast<char*>(map) + 100, bytes - 100}});
  prefault.Wait();
  ASSERT_EQ(mincore(map, bytes, resident.data()), 0);
  // (The page the buffer starts inside is not a whole page of it.)
  std::size_t after = 0;
  for (std::size_t i = 1; i < resident.size(); ++i) after += resident[i] & 1;
  EXPECT_EQ(after, resident.size() - 1);
  munmap(map, bytes);
}
#endif

}  // namespace
}  // namespace wearscar::support
