// wearscar::report: the audit of a batch through the library, as a lab's
// own program would run it.
#include "wearscar/report/audit.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/simulated.h"
#include "report_helpers.h"
#include "wearscar/force/read_force.h"
#include "wearscar/fusion/error.h"
#include "wearscar/report/output_folder.h"
#include "wearscar/scan/gsf.h"

namespace wearscar::report {
namespace {

namespace fs = std::filesystem;
using test_support::FreshFolder;
using test_support::Slurp;

// B-RT-R simulated (a force export and its scan) beside an S-RL-R whose
// force file is not a force export.
fs::path TwoSpecimens(sim::SimulatedTest* test) {
  const fs::path in = FreshFolder("in");
  samples::SimulationOptions o = samples::PaperCase("B-RT-R");
  o.cycles = 80;
  o.seed = 7;
  o.scan_cols = 384;
  o.scan_rows = 288;
  o.scan_pitch_mm = 0.0198;
  *test = sim::Simulate(o);
  force::WriteForceCsv(test->record, (in / "B-RT-R.force.csv").string());
  scan::WriteGsf(test->scan, (in / "B-RT-R.scan.gsf").string());
  std::ofstream(in / "S-RL-R.force.csv") << "not,a,force\nexport,at,all\n";
  return in;
}

TEST(Audit, OneBadSpecimenIsReportedAndTheOtherIsComplete) {
  sim::SimulatedTest test;
  const fs::path in = TwoSpecimens(&test);
  const fs::path out = FreshFolder("out");
  AuditOptions options;
  options.figures = false;
  long calls = 0, last = 0;
  const AuditResult r = Audit(fusion::FindSpecimens(in.string(), options.batch),
                              out.string(),
                              "two specimens",
                              options,
                              [&](long done) {
                                ++calls;
                                last = done;
                              });
  ASSERT_EQ(r.specimens.size(), 2u);
  EXPECT_EQ(calls, 2);
  EXPECT_EQ(last, 2);
  EXPECT_EQ(r.failed, 1);
  for (const ReportSection& s : r.specimens) {
    if (s.name == "S-RL-R") {
      EXPECT_TRUE(s.failed);
      EXPECT_NE(s.row["error"].get<std::string>().find("S-RL-R.force.csv"),
                std::string::npos)
          << s.row.dump();
      // Nothing of it was moved into place.
      EXPECT_FALSE(fs::exists(out / "S-RL-R" / "result.json"));
      continue;
    }
    ASSERT_EQ(s.name, "B-RT-R");
    ASSERT_FALSE(s.failed) << s.row.dump();
    EXPECT_EQ(s.row["species"], "beech");
    // mu-hat against the simulator's truth over the compared cycles, at
    // the sensor noise calibrated to the paper (errors 0.0001 and 0.0011):
    // within about three and two times those.
    const int first = s.row["comparison"]["first_cycle"].get<int>() - 1,
              last_cycle = s.row["comparison"]["last_cycle"].get<int>() - 1;
    const double truth =
        test.truth.mu_per_cycle.segment(first, last_cycle - first + 1).mean();
    EXPECT_NEAR(s.row["comparison"]["mu_hat_force"]["mean"].get<double>(),
                truth,
                0.0003);
    EXPECT_NEAR(s.row["comparison"]["mu_hat_scan"]["mean"].get<double>(),
                truth,
                0.0025);
    EXPECT_TRUE(fs::exists(out / "B-RT-R" / "result.json"));
    EXPECT_TRUE(fs::exists(out / "B-RT-R" / "cycles.csv"));
  }
  // The batch's tables and report name both, the failure with its reason.
  EXPECT_EQ(r.report_path, (out / "report.html").string());
  const std::string html = Slurp(out / "report.html");
  EXPECT_NE(html.find("two specimens"), std::string::npos);
  EXPECT_NE(html.find("class=\"failed\""), std::string::npos);
  const std::string csv = Slurp(out / "summary.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3);
  fs::remove_all(in);
  fs::remove_all(out);
}

TEST(Audit, InvalidOptionsAreNamedBeforeAnythingIsWritten) {
  const fs::path out = FreshFolder("invalid") / "audit";
  AuditOptions options;
  options.batch.jobs = -2;
  try {
    Audit({}, out.string(), "nothing", options);
    FAIL() << "invalid options were used";
  } catch (const fusion::FusionError& e) {
    EXPECT_STREQ(e.what(), "audit options: jobs must be >= 0");
  }
  EXPECT_FALSE(fs::exists(out));
  fs::remove_all(out.parent_path());
}

// Shards share a folder; an exclusive writer (an unsharded audit, a fuse)
// is refused while they hold it, and they while it does; the merge lock
// is a lock of its own.
TEST(OutputLock, ShardsShareAFolderAnExclusiveWriterDoesNot) {
  const fs::path out = FreshFolder("locks");
  {
    const OutputLock a(out.string(), OutputLock::kShard);
    const OutputLock b(out.string(), OutputLock::kShard);
    EXPECT_THROW(OutputLock(out.string()), OutputError);
    const OutputLock merge(out.string(), OutputLock::kMerge);
  }
  const OutputLock alone(out.string());
  try {
    OutputLock shard(out.string(), OutputLock::kShard);
    ADD_FAILURE() << "a shard took a folder an exclusive writer holds";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("another wearscar is writing into "
                                         "this folder"),
              std::string::npos);
  }
}

}  // namespace
}  // namespace wearscar::report
