#include "wearscar/support/huge_pages.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace wearscar::support {
namespace {

TEST(AdviseHugePages, AdvisesOnlyTheWhole2MiBPagesInside) {
  constexpr std::size_t kHuge = std::size_t{2} << 20;
  std::vector<char> small(kHuge - 1);
  EXPECT_EQ(AdviseHugePages(small.data(), small.size()), 0u);
  EXPECT_EQ(AdviseHugePages(nullptr, 8 * kHuge), 0u);
  std::vector<char> big(5 * kHuge + 123, 'a');
  const auto begin = reinterpret_cast<std::uintptr_t>(big.data());
  const std::uintptr_t first = (begin + kHuge - 1) / kHuge * kHuge;
  const std::uintptr_t last = (begin + big.size()) / kHuge * kHuge;
  const std::size_t advised = AdviseHugePages(big.data(), big.size());
#if defined(__linux__)
  EXPECT_EQ(advised, last - first);
  EXPECT_GE(advised, 4 * kHuge);
#endif
  // A hint only: the values are untouched.
  for (char c : big) ASSERT_EQ(c, 'a');
}

}  // namespace
}  // namespace wearscar::support
