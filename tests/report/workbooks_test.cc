#include "wearscar/report/workbooks.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "wearscar/report/output_folder.h"

namespace wearscar::report {
namespace {

TEST(Workbooks, CsvInTheGermanConventionKeepsTextAndCommasInNumbers) {
  const std::string csv =
      "specimen,mu_to_quote,verdict,bytes\n"
      "B-RT-R,0.1234,\"explained; mu 0.12, settled\",6988048\n"
      "S-RL-R,,\"not explained, \"\"elastic\"\"\",-1.5e-05\n";
  EXPECT_EQ(LocaleCsv(csv, "de"),
            "specimen;mu_to_quote;verdict;bytes\n"
            "B-RT-R;0,1234;\"explained; mu 0.12, settled\";6988048\n"
            "S-RL-R;;\"not explained, \"\"elastic\"\"\";-1,5e-05\n");
  EXPECT_EQ(LocaleCsv(csv, ""), csv);
  const auto rows = ParseCsv(csv);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[2][2], "not explained, \"elastic\"");
}

TEST(Workbooks, AFolderThatCannotBeWrittenIsAnErrorAndLeavesNothing) {
  const std::string dir = ::testing::TempDir() + "/no-such-folder/x";
  EXPECT_THROW(WriteWorkbook(dir + "/a.xlsx", {{"s", "a,b\n1,2\n"}}),
               OutputError);
  EXPECT_FALSE(std::filesystem::exists(dir));
}

}  // namespace
}  // namespace wearscar::report
