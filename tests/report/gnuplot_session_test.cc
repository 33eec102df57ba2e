// wearscar::report::GnuplotSession: one gnuplot for script after script,
// as an audit's worker draws specimen after specimen.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "report_helpers.h"
#include "wearscar/report/figures.h"

namespace wearscar::report {
namespace {

namespace fs = std::filesystem;
using test_support::Slurp;

// A fresh folder with its figure-data sub-folder.
fs::path FreshFolder(const std::string& name) {
  const fs::path p = test_support::FreshFolder("gnuplot-" + name);
  fs::create_directories(p / kFigureData);
  return p;
}

// A script drawing `data.csv` of its folder (relative names: the script
// runs in its folder) into plot.svg.
void WriteScript(const fs::path& dir,
                 const std::string& name,
                 const std::string& body) {
  std::ofstream(dir / "data.csv") << "x,y\n0,1\n1,3\n2,2\n";
  std::ofstream(dir / kFigureData / name)
      << "set datafile separator ','\nset terminal svg\nset output "
         "'plot.svg'\n"
      << body << "\nunset output\nreset session\n";
}

// gnuplot's processes that are children of this test.
int ChildGnuplots() {
  int n = 0;
  for (const auto& e : fs::directory_iterator("/proc")) {
    std::ifstream stat(e.path() / "stat");
    std::string pid, comm, state;
    long ppid = 0;
    if (stat >> pid >> comm >> state >> ppid && comm == "(gnuplot)" &&
        ppid == static_cast<long>(getpid()))
      ++n;
  }
  return n;
}

TEST(GnuplotSession, DrawsScriptAfterScriptInTheirOwnFoldersWithOneGnuplot) {
  std::string why;
  if (!PlotterAvailable(&why)) GTEST_SKIP() << why;
  const fs::path a = FreshFolder("a"), b = FreshFolder("b with 'quote'");
  WriteScript(a, "s.gp", "plot 'data.csv' skip 1 using 1:2 title 'first'");
  WriteScript(b, "s.gp", "plot 'data.csv' skip 1 using 1:2 title 'second'");
  {
    GnuplotSession session;
    EXPECT_TRUE(session.Run(a.string(), "s.gp"));
    EXPECT_EQ(ChildGnuplots(), 1);
    EXPECT_TRUE(session.Run(b.string(), "s.gp"));
    EXPECT_EQ(ChildGnuplots(), 1);  // the same gnuplot drew both
    EXPECT_NE(Slurp(a / "plot.svg").find("first"), std::string::npos);
    EXPECT_NE(Slurp(b / "plot.svg").find("second"), std::string::npos);
    EXPECT_TRUE(fs::exists(a / kFigureData / "s.log"));
  }
  EXPECT_EQ(ChildGnuplots(), 0);  // ended and waited for
}

TEST(GnuplotSession, AnErrorIsThatScriptsAndTheSessionGoesOn) {
  std::string why;
  if (!PlotterAvailable(&why)) GTEST_SKIP() << why;
  const fs::path bad = FreshFolder("bad"), good = FreshFolder("good");
  // Its messages sent elsewhere, then an error.
  WriteScript(
      bad, "s.gp", "set print 'elsewhere.txt'\nplot no_such_function(x)");
  WriteScript(good, "s.gp", "plot 'data.csv' skip 1 using 1:2 title 'after'");
  GnuplotSession session;
  EXPECT_FALSE(session.Run(bad.string(), "s.gp"));
  EXPECT_NE(Slurp(bad / kFigureData / "s.log").find("no_such_function"),
            std::string::npos);
  EXPECT_TRUE(session.Run(good.string(), "s.gp"));
  EXPECT_NE(Slurp(good / "plot.svg").find("after"), std::string::npos);
  EXPECT_EQ(Slurp(good / kFigureData / "s.log"), "");
}

TEST(GnuplotSession, AGnuplotThatEndsIsStartedAgain) {
  std::string why;
  if (!PlotterAvailable(&why)) GTEST_SKIP() << why;
  const fs::path quits = FreshFolder("quits"), next = FreshFolder("next");
  std::ofstream(quits / kFigureData / "s.gp") << "exit gnuplot\n";
  WriteScript(next, "s.gp", "plot 'data.csv' skip 1 using 1:2 title 'again'");
  GnuplotSession session;
  EXPECT_FALSE(session.Run(quits.string(), "s.gp"));
  EXPECT_EQ(ChildGnuplots(), 0);
  EXPECT_TRUE(session.Run(next.string(), "s.gp"));
  EXPECT_NE(Slurp(next / "plot.svg").find("again"), std::string::npos);
}

}  // namespace
}  // namespace wearscar::report
