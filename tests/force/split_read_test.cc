// A large file's rows parsed on two threads (ReadForceOptions::threads)
// are those of one pass, whatever lies where the second thread begins:
// the record to the bit, its metadata and warnings, or the same error.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "wearscar/force/read_force.h"

namespace wearscar::force {
namespace {

std::vector<std::string> GenericRows(int n) {
  std::vector<std::string> lines = {"time_s,x_mm,Q_N,P_N"};
  for (int i = 0; i < n; ++i) {
    const double t = i / 2000.0, x = 2.85 * std::sin(2 * M_PI * t);
    const double p = 30 + 0.3 * std::sin(2 * M_PI * x / 1.7);
    lines.push_back(
        fmt::format("{:.4f},{:.6f},{:.5f},{:.4f}",
                    t,
                    x,
                    0.12 * p * (std::cos(2 * M_PI * t) > 0 ? 1 : -1),
                    p));
  }
  return lines;
}

std::string JoinLines(const std::vector<std::string>& lines,
                      const std::string& eol) {
  std::string text;
  for (const auto& l : lines) text += l + eol;
  return text;
}

// The line a second thread starts at: the first after `share` of the
// bytes (0-based index into the lines).
long SplitLineOf(const std::string& text, double share) {
  const size_t nl = text.find(
      '\n', static_cast<size_t>(static_cast<double>(text.size()) * share));
  return static_cast<long>(
      std::count(text.begin(), text.begin() + static_cast<long>(nl) + 1, '\n'));
}

std::string Outcome(const std::string& path,
                    const ReadForceOptions& o,
                    ForceRecord* r) {
  try {
    *r = ReadForceFile(path, o);
    return "read";
  } catch (const ForceError& e) {
    return e.what();
  }
}

void ExpectBitwiseEqual(const Eigen::VectorXd& a,
                        const Eigen::VectorXd& b,
                        const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  EXPECT_EQ(std::memcmp(a.data(), b.data(), sizeof(double) * a.size()), 0)
      << what;
}

// Reads `lines` on one and on two threads; returns the rows the second
// thread parsed.
long ExpectOneThreadsReading(const std::string& name,
                             const std::vector<std::string>& lines,
                             const std::string& eol,
                             ReadForceOptions o,
                             const std::string& expected) {
  SCOPED_TRACE(name);
  const std::string text = JoinLines(lines, eol);
  EXPECT_GT(text.size(), size_t{2} << 20);  // large enough to be split
  // One file per test: ctest runs them side by side.
  const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string stem = std::string(test->test_suite_name()) + "." + test->name();
  std::replace(stem.begin(), stem.end(), '/', '-');
  const std::string path = ::testing::TempDir() + "/wearscar-" + stem + ".csv";
  std::ofstream(path, std::ios::binary) << text;
  ForceRecord one, two;
  o.threads = 1;
  const std::string a = Outcome(path, o, &one);
  o.threads = 2;
  const std::string b = Outcome(path, o, &two);
  std::remove(path.c_str());
  EXPECT_EQ(a, b);
  EXPECT_NE(a.find(expected), std::string::npos) << a;
  if (a != "read" || b != "read") return 0;
  EXPECT_EQ(one.metadata.rows_on_second_thread, 0);
  ExpectBitwiseEqual(one.time_s, two.time_s, "time");
  ExpectBitwiseEqual(one.x_mm, two.x_mm, "x");
  ExpectBitwiseEqual(one.tangential_n, two.tangential_n, "Q");
  ExpectBitwiseEqual(one.normal_n, two.normal_n, "P");
  const ForceMetadata &m = one.metadata, &n = two.metadata;
  EXPECT_EQ(m.layout, n.layout);
  EXPECT_EQ(m.sampling_rate_hz, n.sampling_rate_hz);
  EXPECT_EQ(m.warnings, n.warnings);
  EXPECT_EQ(m.clock_restarts_joined, n.clock_restarts_joined);
  EXPECT_EQ(m.blocks_joined, n.blocks_joined);
  EXPECT_EQ(m.rows_dropped, n.rows_dropped);
  EXPECT_EQ(m.time_rebuilt, n.time_rebuilt);
  EXPECT_EQ(m.normal_sign_flipped, n.normal_sign_flipped);
  return n.rows_on_second_thread;
}

// Empties field `field` of lines [first, last].
void Gap(std::vector<std::string>& lines, long first, long last, int field) {
  for (long i = first; i <= last; ++i) {
    std::string& l = lines[static_cast<size_t>(i)];
    size_t begin = 0;
    for (int f = 0; f < field; ++f) begin = l.find(',', begin) + 1;
    const size_t end = l.find(',', begin);
    l.erase(begin, end == std::string::npos ? end : end - begin);
  }
}

class TwoThreads : public ::testing::TestWithParam<double> {
 protected:
  void SetUp() override {
    plain_.split_share = GetParam();
    base_ = GenericRows(120000);
    split_ = SplitLineOf(JoinLines(base_, "\n"), GetParam());
    ASSERT_GT(split_, 50000);
  }
  template <typename Change>
  std::vector<std::string> With(Change change) const {
    std::vector<std::string> lines = base_;
    change(lines);
    return lines;
  }
  ReadForceOptions plain_;
  std::vector<std::string> base_;
  long split_ = 0;
};

TEST_P(TwoThreads, ReadWhatOneReadsOfPlainRows) {
  // The second thread parses every row after the split.
  EXPECT_EQ(ExpectOneThreadsReading("plain", base_, "\n", plain_, "read"),
            static_cast<long>(base_.size()) - split_);
  EXPECT_GT(ExpectOneThreadsReading("CRLF", base_, "\r\n", plain_, "read"), 0);
  // The columns are sized from the file's size and its first lines: here
  // every line after them is shorter, and the columns must grow.
  ExpectOneThreadsReading("lines shorter after the head",
                          With([&](auto& l) {
                            for (size_t i = 1; i < 500; ++i) l[i] += "000000";
                          }),
                          "\n",
                          plain_,
                          "read");
  // Blank lines before the split: the second half's rows move up.
  EXPECT_GT(ExpectOneThreadsReading("blank lines",
                                    With([&](auto& l) {
                                      l[100] = "";
                                      l[static_cast<size_t>(split_ - 10)] = " ";
                                    }),
                                    "\n",
                                    plain_,
                                    "read"),
            0);
  // A run of 600 line breaks (more than a byte counter holds) before the
  // split: counted, or the second thread's rows would be refused.
  const std::vector<std::string> run = With([&](auto& l) {
    for (size_t i = 1000; i < 1600; ++i) l[i] = "";
  });
  EXPECT_EQ(ExpectOneThreadsReading(
                "a run of blank lines", run, "\n", plain_, "read"),
            static_cast<long>(run.size()) -
                SplitLineOf(JoinLines(run, "\n"), GetParam()));
}

TEST_P(TwoThreads, ReadWhatOneReadsOfGapsAndTimeAtTheSplit) {
  const long s = split_;
  // Missing values across the split: 40 in a row (allowed), 60 (refused
  // at the 51st), 60 after it.
  ExpectOneThreadsReading("gap of 40 across",
                          With([&](auto& l) { Gap(l, s - 20, s + 19, 3); }),
                          "\n",
                          plain_,
                          "read");
  ExpectOneThreadsReading("gap of 60 across",
                          With([&](auto& l) { Gap(l, s - 30, s + 29, 3); }),
                          "\n",
                          plain_,
                          "more than 50 consecutive missing values in 'P'");
  ExpectOneThreadsReading("gap of 60 after",
                          With([&](auto& l) { Gap(l, s + 100, s + 159, 1); }),
                          "\n",
                          plain_,
                          "more than 50 consecutive missing values in 'x'");
  // Time that does not advance where the second half begins.
  ExpectOneThreadsReading("time repeated at the split",
                          With([&](auto& l) {
                            const std::string prev = l[s - 1];
                            std::string& row = l[static_cast<size_t>(s)];
                            row = prev.substr(0, prev.find(',')) +
                                  row.substr(row.find(','));
                          }),
                          "\n",
                          plain_,
                          "expected strictly increasing time");
  // No time column: the rate given.
  ReadForceOptions rate = plain_;
  rate.sampling_rate_hz = 2000;
  ExpectOneThreadsReading("no time",
                          With([&](auto& l) {
                            for (auto& row : l) row.erase(0, row.find(',') + 1);
                          }),
                          "\n",
                          rate,
                          "read");
}

TEST_P(TwoThreads, ReadWhatOneReadsOfBadRowsFootersAndRepeatedBlocks) {
  const long s = split_;
  // A bad row in the second half, dropped when lenient; a footer.
  const auto bad_row = With([&](auto& l) { l[s + 500] = "30.0,abc,1,2"; });
  ExpectOneThreadsReading("bad row", bad_row, "\n", plain_, "found 'abc'");
  ReadForceOptions lenient = plain_;
  lenient.lenient = true;
  ExpectOneThreadsReading("bad row, lenient", bad_row, "\n", lenient, "read");
  ExpectOneThreadsReading("footer",
                          With([&](auto& l) { l.push_back("End of data,,,"); }),
                          "\n",
                          plain_,
                          "read");
  // Bruker/CETR: a step's block (its text line and the names row again)
  // about the split, the clock going on or restarting after it.
  for (const bool restart : {false, true}) {
    for (const long at : {s - 2, s, s + 2}) {
      ExpectOneThreadsReading(
          fmt::format("repeated block at line {}{}",
                      at - s,
                      restart ? ", clock restarting" : ""),
          With([&](auto& l) {
            if (restart) {
              for (long i = at; i < static_cast<long>(l.size()); ++i) {
                std::string& row = l[static_cast<size_t>(i)];
                row = fmt::format("{:.4f}", (i - at) / 2000.0) +
                      row.substr(row.find(','));
              }
            }
            l.insert(l.begin() + at, {"Step 2 of 2", l[0]});
          }),
          "\n",
          plain_,
          "read");
    }
  }
}

// Rtec: the RecipeStep clock restarting before the split, after it, and
// at it; negative Fz, a trailing comma, a footer.
TEST_P(TwoThreads, ReadWhatOneReadsOfRtecRestarts) {
  const auto rtec = [&](std::vector<long> restarts) {
    std::vector<std::string> lines = {
        "Recipe: wood-steel reciprocating,Operator: lab",
        "RecipeStep,Timestamp,DAQ.Fx (N),DAQ.Fz (N),DAQ.COF (),Piezo X (mm),"};
    int step = 1;
    long start = 0;
    for (long i = 1; i < static_cast<long>(base_.size()); ++i) {
      if (std::find(restarts.begin(), restarts.end(), i) != restarts.end()) {
        ++step;
        start = i;
      }
      const double t = (i - start) / 2000.0, x = 2.85 * std::sin(i / 318.3);
      const double p = 30 + 0.3 * std::sin(2 * M_PI * x / 1.7);
      // Time zero-padded: a restart leaves every line as long, and the
      // split where it was.
      lines.push_back(fmt::format("{},{:010.4f},{:.4f},{:.4f},0.1200,{:.5f},",
                                  step,
                                  t,
                                  0.12 * p,
                                  -p,
                                  x));
    }
    lines.push_back("End of data,,,,,,");
    return lines;
  };
  const long r = SplitLineOf(JoinLines(rtec({}), "\n"), GetParam());
  EXPECT_GT(ExpectOneThreadsReading("rtec", rtec({}), "\n", plain_, "read"), 0);
  ExpectOneThreadsReading(
      "rtec, restart before", rtec({r / 2}), "\n", plain_, "read");
  ExpectOneThreadsReading(
      "rtec, restart after", rtec({r + 300}), "\n", plain_, "read");
  // (Line r of the file is row r - 1: the recipe line comes first.)
  ExpectOneThreadsReading(
      "rtec, restart at the split", rtec({r - 1}), "\n", plain_, "read");
  ExpectOneThreadsReading("rtec, restarts about the split",
                          rtec({r - 3, r - 2, r, r + 1}),
                          "\n",
                          plain_,
                          "read");
}

INSTANTIATE_TEST_SUITE_P(Share,
                         TwoThreads,
                         ::testing::Values(ReadForceOptions{}.split_share, 0.5),
                         [](const auto& param_info) {
                           return fmt::format("{:.0f}pct",
                                              100 * param_info.param);
                         });

// A file under the split's minimum, or bytes handed on for a checksum:
// one thread parses every row.
TEST(TwoThreads, NotForSmallFilesOrWhenBytesAreHandedOn) {
  ReadForceOptions o;
  o.threads = 2;
  const std::string path = ::testing::TempDir() + "/wearscar-small.csv";
  {
    std::ofstream(path, std::ios::binary) << JoinLines(GenericRows(2000), "\n");
    EXPECT_EQ(ReadForceFile(path, o).metadata.rows_on_second_thread, 0);
  }
  {
    std::ofstream(path, std::ios::binary)
        << JoinLines(GenericRows(120000), "\n");
    EXPECT_GT(ReadForceFile(path, o).metadata.rows_on_second_thread, 0);
    o.on_bytes = [](const char*, std::size_t) {};
    EXPECT_EQ(ReadForceFile(path, o).metadata.rows_on_second_thread, 0);
  }
  std::remove(path.c_str());
  ReadForceOptions bad;
  bad.threads = 3;
  EXPECT_FALSE(bad.IsValid(nullptr));
  bad.threads = 2;
  bad.split_share = 0.99;
  EXPECT_FALSE(bad.IsValid(nullptr));
}

}  // namespace
}  // namespace wearscar::force
