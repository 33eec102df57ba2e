#pragma once
// Where the suites find their data and the command: paths of this build,
// compiled into one generated source (tests/CMakeLists.txt), so that the
// test sources compile to the same objects in any checkout (the compiler
// cache shares them).

namespace wearscar::testing {
const char* TestDataDir();    // tests/data
const char* SharedDataDir();  // ../shared/data (may be absent)
const char* SamplesDir();     // samples/
const char* BinaryPath();     // the wearscar command
}  // namespace wearscar::testing

#define WEARSCAR_TEST_DATA ::wearscar::testing::TestDataDir()
#define WEARSCAR_SHARED_DATA ::wearscar::testing::SharedDataDir()
#define WEARSCAR_SAMPLES_DIR ::wearscar::testing::SamplesDir()
#define WEARSCAR_BINARY ::wearscar::testing::BinaryPath()
