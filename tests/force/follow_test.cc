#include "wearscar/force/follow.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "wearscar/force/read_force.h"

namespace wearscar::force {
namespace {

namespace fs = std::filesystem;

std::string TempPath(const std::string& name) {
  const std::string dir =
      ::testing::TempDir() + "/follow-" +
      ::testing::UnitTest::GetInstance()->current_test_info()->name();
  fs::create_directories(dir);
  return dir + "/" + name;
}

// A reciprocating test: 1 Hz, +-2 mm, 30 N with a wavy track, mu 0.1.
ForceRecord MadeTest(int cycles, double rate_hz) {
  const Eigen::Index n = static_cast<Eigen::Index>(cycles * rate_hz);
  Eigen::VectorXd t(n), x(n), q(n), p(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    t[i] = static_cast<double>(i) / rate_hz;
    x[i] = -2.0 * std::cos(2 * M_PI * t[i]);
    p[i] = 30.0 + 0.5 * std::sin(3.1 * x[i]);
    q[i] = 0.1 * p[i] * (std::sin(2 * M_PI * t[i]) >= 0 ? 1 : -1);
  }
  return RecordFromChannels(t, x, q, p, "made", "delimited", rate_hz);
}

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void AppendText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::app);
  out << text;
}

// Everything the follower yields, joined.
struct Joined {
  std::vector<double> t, x, q, p;
  void Add(const ForceRecord& r) {
    for (Eigen::Index i = 0; i < r.size(); ++i) {
      t.push_back(r.time_s[i]);
      x.push_back(r.x_mm[i]);
      q.push_back(r.tangential_n[i]);
      p.push_back(r.normal_n[i]);
    }
  }
};

void ExpectSameRows(const Joined& j, const ForceRecord& whole) {
  ASSERT_EQ(static_cast<Eigen::Index>(j.t.size()), whole.size());
  for (Eigen::Index i = 0; i < whole.size(); ++i) {
    ASSERT_NEAR(j.t[i], whole.time_s[i], 1e-9) << "row " << i;
    ASSERT_EQ(j.x[i], whole.x_mm[i]) << "row " << i;
    ASSERT_EQ(j.q[i], whole.tangential_n[i]) << "row " << i;
    ASSERT_EQ(j.p[i], whole.normal_n[i]) << "row " << i;
  }
}

// Writes `text` in pieces of `piece` bytes (cutting rows anywhere), polling
// after each.
Joined FollowInPieces(const std::string& text,
                      const std::string& path,
                      std::size_t piece,
                      FollowOptions options = {}) {
  fs::remove(path);
  ForceFollower follow(path, options);
  Joined j;
  for (std::size_t at = 0; at < text.size(); at += piece) {
    AppendText(path, text.substr(at, piece));
    const FollowedRows got = follow.Poll();
    EXPECT_FALSE(got.restarted);
    j.Add(got.rows);
  }
  j.Add(follow.Poll(true).rows);
  return j;
}

TEST(ForceFollower, RowsWrittenInPiecesAreTheFilesRows) {
  const std::string path = TempPath("test.csv");
  WriteForceCsv(MadeTest(6, 500), path);
  const std::string text = ReadAll(path);
  const ForceRecord whole = ReadForceFile(path);
  // Pieces that end mid-row: a row still being written is never taken.
  const Joined j = FollowInPieces(text, path, 997);
  ExpectSameRows(j, whole);
}

TEST(ForceFollower, RestartingClocksAreJoinedAsTheWholeFileJoinsThem) {
  // An Rtec-like recipe: the timestamp restarts with every 2 s step, P is
  // negative in compression, and a footer ends the file.
  const std::string path = TempPath("recipe.csv");
  WriteRtecCsv(MadeTest(9, 400), path, 2.0);
  const std::string text = ReadAll(path);
  const ForceRecord whole = ReadForceFile(path);
  ASSERT_GT(whole.metadata.clock_restarts_joined, 2);
  FollowOptions o;
  o.first_lines = 500;
  const Joined j = FollowInPieces(text, path, 1501, o);
  ExpectSameRows(j, whole);
}

TEST(ForceFollower, ALookEndingAtARepeatedHeaderLosesNoRow) {
  // Blocks each with the file's header line (as `watch --pattern` joins
  // them), the clock continuing and then starting again in each; every
  // look ends just after a block's header line.
  for (const bool restart : {false, true}) {
    const std::string path = TempPath(restart ? "restart.csv" : "joined.csv");
    WriteForceCsv(MadeTest(6, 500), path);
    const std::string one = ReadAll(path);
    const std::size_t header_end = one.find('\n') + 1;
    const std::string header = one.substr(0, header_end);
    std::string text = header;
    std::vector<std::size_t> cuts;
    std::istringstream rows(one.substr(header_end));
    std::string line;
    for (int i = 0; std::getline(rows, line); ++i) {
      if (i > 0 && i % 1000 == 0) {
        text += header;
        cuts.push_back(text.size());
      }
      if (restart) {
        const std::size_t comma = line.find(',');
        line = fmt::format("{:.6f}{}", (i % 1000) / 500.0, line.substr(comma));
      }
      text += line + "\n";
    }
    cuts.push_back(text.size());
    fs::remove(path);
    std::ofstream(path, std::ios::binary) << text;
    const ForceRecord whole = ReadForceFile(path);
    fs::remove(path);
    FollowOptions o;
    o.first_lines = 200;
    ForceFollower follow(path, o);
    Joined j;
    std::size_t at = 0;
    for (std::size_t cut : cuts) {
      AppendText(path, text.substr(at, cut - at));
      at = cut;
      j.Add(follow.Poll().rows);
    }
    j.Add(follow.Poll(true).rows);
    SCOPED_TRACE(restart ? "restarting clock" : "continuing clock");
    ExpectSameRows(j, whole);
  }
}

TEST(ForceFollower, ATruncatedFileIsANewTestReadFromItsStart) {
  const std::string path = TempPath("test.csv");
  WriteForceCsv(MadeTest(6, 500), path);
  const std::string text = ReadAll(path);
  fs::remove(path);
  ForceFollower follow(path, {});
  EXPECT_NE(follow.Poll().note.find("not there yet"), std::string::npos);
  AppendText(path, text);
  EXPECT_EQ(follow.Poll().rows.size(), 3000);
  // The software starts again in the same file.
  std::ofstream(path, std::ios::trunc) << text.substr(0, text.size() / 2);
  const FollowedRows again = follow.Poll(true);
  EXPECT_TRUE(again.restarted);
  EXPECT_NE(again.note.find("truncated"), std::string::npos) << again.note;
  ASSERT_GT(again.rows.size(), 0);
  EXPECT_EQ(again.rows.time_s[0], 0.0);
}

TEST(ForceFollower, AFileReplacedByAnotherIsANewTest) {
  const std::string path = TempPath("test.csv");
  WriteForceCsv(MadeTest(4, 500), path);
  ForceFollower follow(path, {});
  EXPECT_EQ(follow.Poll().rows.size(), 2000);
  // A new file of the same size moved into its place.
  WriteForceCsv(MadeTest(4, 500), path + ".new");
  fs::rename(path + ".new", path);
  const FollowedRows again = follow.Poll();
  EXPECT_TRUE(again.restarted);
  EXPECT_NE(again.note.find("replaced"), std::string::npos) << again.note;
  EXPECT_EQ(again.rows.size(), 2000);
}

TEST(ForceFollower, ALineWithoutEndIsRefusedBeforeItFillsTheMemory) {
  const std::string path = TempPath("noline.csv");
  std::ofstream(path) << "time_s,x_mm,Q_N,P_N\n" << std::string(5000, '1');
  FollowOptions o;
  o.read.max_line_bytes = 1024;
  ForceFollower follow(path, o);
  try {
    follow.Poll();
    FAIL() << "no error";
  } catch (const ForceError& e) {
    EXPECT_NE(std::string(e.what()).find("no line break"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
  }
}

}  // namespace
}  // namespace wearscar::force
