#include "wearscar/report/workbooks.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
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

std::string Bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(Workbooks, TheSameResultsGiveTheSameBytesAtADateGiven) {
  const std::string dir = ::testing::TempDir();
  ::setenv("SOURCE_DATE_EPOCH", "1700000000", 1);
  const std::vector<Sheet> sheets = {{"summary", "specimen,mu\nB,0.12\n"},
                                     {"groups", "a,b\n1,x\n"}};
  WriteWorkbook(dir + "/one.xlsx", sheets);
  WriteWorkbook(dir + "/two.xlsx", sheets);
  ::unsetenv("SOURCE_DATE_EPOCH");
  const std::string one = Bytes(dir + "/one.xlsx");
  EXPECT_GT(one.size(), 1000u);
  EXPECT_EQ(one.substr(0, 2), "PK");  // a zip, as every .xlsx
  EXPECT_EQ(one, Bytes(dir + "/two.xlsx"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/.one.xlsx.partial"));
}

TEST(Workbooks, AFolderThatCannotBeWrittenIsAnErrorAndLeavesNothing) {
  const std::string dir = ::testing::TempDir() + "/no-such-folder/x";
  EXPECT_THROW(WriteWorkbook(dir + "/a.xlsx", {{"s", "a,b\n1,2\n"}}),
               OutputError);
  EXPECT_FALSE(std::filesystem::exists(dir));
}

}  // namespace
}  // namespace wearscar::report
