#include <fcntl.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_helpers.h"
#include "common/paths.h"

namespace {

using namespace wearscar_test;

const std::string kData = std::string(WEARSCAR_TEST_DATA) + "/force/";

TEST(Cli, VersionAndHelp) {
  CommandResult v = Wearscar("version");
  EXPECT_EQ(v.status, 0);
  EXPECT_EQ(v.output.rfind("wearscar 0.", 0), 0u) << v.output;
  CommandResult h = Wearscar("--help");
  EXPECT_EQ(h.status, 0);
  EXPECT_NE(h.output.find("simulate"), std::string::npos);
  EXPECT_NE(h.output.find("force"), std::string::npos);
}

TEST(Cli, NoSubcommandOrUnknownOptionExitsTwo) {
  EXPECT_EQ(Wearscar("").status, 2);
  EXPECT_EQ(Wearscar("force --no-such-option x").status, 2);
}

TEST(Cli, BadForceFileIsOneLineAndStatusTwo) {
  const CommandResult r = Wearscar("force " + kData + "bad_ragged.csv -o " +
                                   ::testing::TempDir() + "/cli-bad");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("bad_ragged.csv: line 31: ragged row"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(
      std::filesystem::exists(::testing::TempDir() + "/cli-bad/cycles.csv"));
}

TEST(Cli, SimulateThenAnalyseRecoversMu) {
  const std::string dir = ::testing::TempDir() + "/cli-sim";
  const CommandResult s = Wearscar(
      "simulate --case B-TL-L --cycles 40 --scan-cols 64 --scan-rows 48 -o " +
      dir);
  ASSERT_EQ(s.status, 0) << s.output;
  const CommandResult f = Wearscar(
      "force " + dir + "/B-TL-L.force.csv --running-in 20 -o " + dir + "/out");
  ASSERT_EQ(f.status, 0) << f.output;
  std::ifstream csv(dir + "/out/cycles.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(
      header.rfind("cycle,mu_hat_force,J_force,J_force_floor,J_force_excess,"
                   "mu_hat_scan,J_scan,J_scan_floor,J_scan_excess,samples,"
                   "mu_mean",
                   0),
      0u)
      << header;
  int rows = 0;
  for (std::string line; std::getline(csv, line);) ++rows;
  EXPECT_EQ(rows, 40);
  // mu-hat against the simulator's truth over the cycles after the
  // running-in given (21-40).
  const std::string truth = Slurp(dir + "/B-TL-L.truth.json");
  const size_t list = truth.find("\"mu_per_cycle\"");
  ASSERT_NE(list, std::string::npos) << truth.substr(0, 200);
  std::istringstream values(truth.substr(truth.find('[', list) + 1));
  std::vector<double> mu;
  for (std::string v; std::getline(values, v, ',');) {
    mu.push_back(std::stod(v));
    if (v.find(']') != std::string::npos) break;
  }
  ASSERT_GE(mu.size(), 40u);
  double expected = 0;
  for (int c = 20; c < 40; ++c) expected += mu[c] / 20;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      f.output, m, std::regex(R"(mu-hat, k from P +([0-9.]+))")))
      << f.output;
  EXPECT_NEAR(std::stod(m[1]), expected, 0.002) << f.output;
  EXPECT_NE(f.output.find("verdict: explained by wear-scar interaction"),
            std::string::npos)
      << f.output;
  // The summary says how k was estimated and what the noise explains.
  EXPECT_NE(f.output.find("(ensemble)"), std::string::npos) << f.output;
  EXPECT_NE(f.output.find("% noise, floor "), std::string::npos) << f.output;
}

TEST(Cli, ColumnsOptionMapsUnnamedColumnsAndRunningInIsReported) {
  const std::string dir = ::testing::TempDir() + "/cli-columns";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  // The generic fixture with names no pattern knows.
  std::string text = Slurp(kData + "generic.csv");
  text.replace(0, text.find('\n'), "c1,c2,c3,c4");
  {
    std::ofstream f(dir + "/odd.csv");
    f << text;
  }
  const CommandResult none = Wearscar("force " + dir + "/odd.csv");
  EXPECT_EQ(none.status, 2) << none.output;
  const CommandResult a =
      Wearscar("force " + dir +
               "/odd.csv --columns time=c1,x=#2,q=c3,p=c4 -o " + dir + "/a");
  ASSERT_EQ(a.status, 0) << a.output;
  const CommandResult b = Wearscar("force " + kData + "generic.csv -o " + dir +
                                   "/b --running-in auto");
  ASSERT_EQ(b.status, 0) << b.output;
  EXPECT_EQ(Slurp(dir + "/a/cycles.csv"), Slurp(dir + "/b/cycles.csv"));
  EXPECT_NE(a.output.find("running-in: "), std::string::npos) << a.output;
  const std::string csv = Slurp(dir + "/a/cycles.csv");
  EXPECT_NE(csv.find(",P_range_N,QP_correlation,running_in,"),
            std::string::npos)
      << csv.substr(0, 300);
  const CommandResult bad =
      Wearscar("force " + kData + "generic.csv --columns q");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.output.find("expected time=, x=, q=, p= or depth="),
            std::string::npos)
      << bad.output;
  // Without --out: a short per-cycle table on stdout.
  const CommandResult table = Wearscar("force " + kData + "generic.csv");
  EXPECT_EQ(table.status, 0);
  EXPECT_NE(table.output.find("cycle   mu_hat       J  mu_mean mu_energy "
                              "P_range_N  QP_corr"),
            std::string::npos)
      << table.output;
  const CommandResult ri =
      Wearscar("force " + kData + "generic.csv --running-in soon");
  EXPECT_EQ(ri.status, 2);
  EXPECT_NE(ri.output.find("expected auto or a number of cycles"),
            std::string::npos)
      << ri.output;
}

// J's square is split into shares that add up (to rounding) and match
// the floor and excess printed beside them.
void ExpectTheSplitOfJAddsUp(const std::string& output) {
  const std::regex parts(
      R"(J ([0-9.]+) \(of J\^2 ([0-9]+)% noise, floor ([0-9.]+), and ([0-9]+)% )"
      R"(repeating misfit, excess ([0-9.]+)\))");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(output, m, parts)) << output;
  const double noise_share = std::stod(m[2]), floor = std::stod(m[3]),
               excess_share = std::stod(m[4]), excess = std::stod(m[5]);
  EXPECT_NEAR(noise_share + excess_share, 100, 1);
  EXPECT_NEAR(
      noise_share, 100 * floor * floor / (floor * floor + excess * excess), 1);
  EXPECT_GT(excess, 0.3);  // above the verdict's limit: not explained
}

TEST(Cli, FuseWritesResultsAndFlagsTheElasticCase) {
  const std::string dir = ::testing::TempDir() + "/cli-fuse";
  const CommandResult s =
      Wearscar("simulate --case S-RL-R --cycles 120 -o " + dir);
  ASSERT_EQ(s.status, 0) << s.output;
  const CommandResult f =
      Wearscar("fuse --force " + dir + "/S-RL-R.force.csv --scan " + dir +
               "/S-RL-R.scan.gsf --running-in 60 --compare-cycles 40 -o " +
               dir + "/out");
  ASSERT_EQ(f.status, 0) << f.output;
  EXPECT_NE(f.output.find("verdict: not explained by wear-scar interaction"),
            std::string::npos)
      << f.output;
  for (const char* file : {"result.json",
                           "cycles.csv",
                           "loops.csv",
                           "detail.csv",
                           "cost_curve.csv",
                           "profiles.csv",
                           "centreline.csv",
                           "loop_viewer.json"}) {
    EXPECT_TRUE(std::filesystem::exists(dir + "/out/" + file)) << file;
  }
  // The page an audit writes for a specimen: the headline first, the loop
  // viewer's data embedded, no link to an index that is not there.
  const std::string page = Slurp(dir + "/out/report.html");
  EXPECT_NE(page.find("no mu to quote: not explained"), std::string::npos);
  EXPECT_NE(page.find("class=\"viewer-data\""), std::string::npos);
  EXPECT_EQ(page.find("all specimens</a>"), std::string::npos);
  // No temporary file left behind.
  for (const auto& e : std::filesystem::directory_iterator(dir + "/out")) {
    EXPECT_EQ(e.path().string().find(".tmp-"), std::string::npos) << e.path();
  }
  // The verdict's figures: J, its noise floor and excess with an interval,
  // the amplitude ratio's interval, the estimate of k, and the warning of an
  // elastic part; the reasons state floor, interval and limit.
  const std::string json = Slurp(dir + "/out/result.json");
  for (const char* key : {"\"J_force_split\"",
                          "\"noise_floor\"",
                          "\"excess_interval\"",
                          "\"amplitude_ratio_interval\"",
                          "\"method_difference\"",
                          "\"slope_estimate\"",
                          "\"k_estimate\": \"ensemble\"",
                          "\"verdict_cost\": \"excess\"",
                          "\"premises\"",
                          "carries an elastic part",
                          "exceeds what the measurement noise explains"}) {
    EXPECT_NE(json.find(key), std::string::npos) << key;
  }
  EXPECT_NE(f.output.find("verdict: not explained by wear-scar interaction"),
            std::string::npos)
      << f.output;
  EXPECT_NE(f.output.find("the spring displacement carries an elastic part"),
            std::string::npos)
      << f.output;
  ExpectTheSplitOfJAddsUp(f.output);
  // No coefficient is offered to quote when the verdict says the model
  // misses an effect.
  EXPECT_EQ(f.output.rfind("S-RL-R: no mu to quote: not explained by "
                           "wear-scar interaction, the model misses an effect",
                           0),
            0u)
      << f.output;
  EXPECT_NE(f.output.find("for comparison, not to quote:\n"), std::string::npos)
      << f.output;
  // The paper's criterion on request, named as such.
  const CommandResult p =
      Wearscar("fuse --force " + dir +
               "/S-RL-R.force.csv --running-in 60 "
               "--verdict-cost paper --k-estimate cycle --no-lugre");
  EXPECT_EQ(p.status, 0) << p.output;
  EXPECT_NE(p.output.find("(the paper's criterion; its noise floor is"),
            std::string::npos)
      << p.output;
  EXPECT_NE(p.output.find("(cycle)"), std::string::npos) << p.output;
  const CommandResult bad =
      Wearscar("fuse --force " + dir + "/S-RL-R.force.csv --k-estimate median");
  EXPECT_EQ(bad.status, 2) << bad.output;
}

TEST(Cli, ScanWritesProfilePreviewAndSummaryOfTheKnownTrack) {
  const std::string data = std::string(WEARSCAR_SAMPLES_DIR) + "/data/";
  const std::string out = ::testing::TempDir() + "/cli-scan";
  std::filesystem::remove_all(out);
  const CommandResult r =
      Wearscar("scan " + data + "B-RT-T.scan.gsf -o " + out);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("mean depth"), std::string::npos) << r.output;
  const std::string csv = Slurp(out + "/centreline.csv");
  EXPECT_EQ(csv.rfind("s_mm,h_mm,n_valid\n", 0), 0u) << csv.substr(0, 80);
  const std::string png = Slurp(out + "/preview.png");
  EXPECT_EQ(png.substr(1, 3), "PNG");
  // The summary's track angle is the simulator's.
  const std::string json = Slurp(out + "/scan.json");
  const std::string truth = Slurp(data + "B-RT-T.truth.json");
  auto number_after = [](const std::string& text, const std::string& key) {
    const size_t at = text.find("\"" + key + "\":");
    return at == std::string::npos
               ? std::nan("")
               : std::stod(text.substr(at + key.size() + 3));
  };
  EXPECT_NEAR(
      number_after(json, "angle_deg"), number_after(truth, "angle_deg"), 0.5);
  EXPECT_GT(number_after(json, "mean_depth_mm"), 0.03);
  EXPECT_TRUE(std::filesystem::exists(out + "/levelled.gsf"));
}

TEST(Cli, FuseSlopeChoiceFitsOnlyWhatIsAsked) {
  const std::string data = std::string(WEARSCAR_SAMPLES_DIR) + "/data/";
  const std::string base =
      "fuse --force " + data + "B-RT-R.force.csv --no-lugre";
  const std::string scan = " --scan " + data + "B-RT-R.scan.gsf";
  const CommandResult f = Wearscar(base + scan + " --slope force");
  ASSERT_EQ(f.status, 0) << f.output;
  EXPECT_NE(f.output.find("mu-hat, k from P     0.1"), std::string::npos);
  EXPECT_NE(f.output.find("k from scan  not fitted"), std::string::npos)
      << f.output;
  const CommandResult s = Wearscar(base + scan + " --slope scan");
  ASSERT_EQ(s.status, 0) << s.output;
  EXPECT_NE(s.output.find("k from P     not fitted"), std::string::npos)
      << s.output;
  EXPECT_NE(s.output.find("mu-hat, k from scan  0.1"), std::string::npos)
      << s.output;
  // The headline quotes the coefficient fitted, with its interval, what
  // it was fitted with and over which cycles.
  const std::regex headline(
      R"(^B-RT-R: mu = 0\.1[0-9]{3} \(95%: 0\.1[0-9]{3}-0\.1[0-9]{3}\): )"
      R"(mu-hat, k from (P|the scan), cycles 1-20 \(every cycle: no )"
      R"(running-in, whose track the scan shows\); explained by wear-scar )"
      R"(interaction\n)");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(f.output, m, headline)) << f.output;
  EXPECT_EQ(m[1], "P");
  ASSERT_TRUE(std::regex_search(s.output, m, headline)) << s.output;
  EXPECT_EQ(m[1], "the scan");
  // Without a scan: the force slope only; asking for the scan's is an error.
  const CommandResult alone = Wearscar(base);
  EXPECT_EQ(alone.status, 0) << alone.output;
  EXPECT_EQ(alone.output.find("k from scan"), std::string::npos);
  const CommandResult bad = Wearscar(base + " --slope scan");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.output.find("--slope scan needs --scan"), std::string::npos)
      << bad.output;
}

TEST(Cli, WithoutGnuplotTheNumbersStillAppearAndTheMessageSaysWhy) {
  const std::string data = std::string(WEARSCAR_SAMPLES_DIR) + "/data/";
  const std::string out = ::testing::TempDir() + "/cli-no-plotter";
  std::filesystem::remove_all(out);
  // An empty PATH: the shell finds no gnuplot.
  const std::string cmd = "env PATH=/nonexistent " +
                          std::string(WEARSCAR_BINARY) + " fuse --force " +
                          data + "B-RT-R.force.csv --scan " + data +
                          "B-RT-R.scan.gsf --no-lugre -o " + out + " 2>&1";
  const CommandResult r = Shell(cmd);
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("gnuplot was not found"), std::string::npos)
      << r.output;
  EXPECT_TRUE(std::filesystem::exists(out + "/cycles.csv"));
  EXPECT_TRUE(std::filesystem::exists(out + "/result.json"));
  EXPECT_FALSE(std::filesystem::exists(out + "/fig13_mu_hat.png"));
}

TEST(Cli, AScanWithoutATrackDoesNotLoseTheTest) {
  // The real VR-6100 file holds a machined crater, no wear track.
  const std::string zon =
      std::string(WEARSCAR_SHARED_DATA) + "/keyence/vr6100_test_1.zon";
  if (!std::filesystem::exists(zon))
    GTEST_SKIP() << "../shared/data is absent (real instrument files)";
  const std::string dir = ::testing::TempDir() + "/cli-notrack";
  std::filesystem::remove_all(dir);
  // scan: everything that needs no track, "track": null with the reason.
  const CommandResult s = Wearscar("scan " + zon + " -o " + dir + "/scan");
  EXPECT_EQ(s.status, 0) << s.output;
  EXPECT_NE(s.output.find("warning: " + zon + ": no worn track found"),
            std::string::npos)
      << s.output;
  for (const char* file : {"levelled.gsf", "preview.png", "scan.json"})
    EXPECT_TRUE(std::filesystem::exists(dir + "/scan/" + file)) << file;
  EXPECT_FALSE(std::filesystem::exists(dir + "/scan/centreline.csv"));
  const std::string json = Slurp(dir + "/scan/scan.json");
  EXPECT_NE(json.find("\"track\": null"), std::string::npos) << json;
  EXPECT_NE(json.find("\"instrument\": \"VR-6100\""), std::string::npos);
  // fuse: the force side stands, with the reason in the summary and
  // result.json; --slope scan cannot stand without it.
  ASSERT_EQ(Wearscar("simulate --case B-TL-L --cycles 40 --scan-cols 64 "
                     "--scan-rows 48 --formats csv -o " +
                     dir)
                .status,
            0);
  const std::string force = dir + "/B-TL-L.force.csv";
  const CommandResult f =
      Wearscar("fuse --force " + force + " --scan " + zon +
               " --no-lugre --no-figures -o " + dir + "/fuse");
  EXPECT_EQ(f.status, 0) << f.output;
  EXPECT_NE(f.output.find("warning: the scan was not used (" + zon +
                          ": no worn track found"),
            std::string::npos)
      << f.output;
  const std::string fused = Slurp(dir + "/fuse/result.json");
  EXPECT_NE(fused.find("the scan was not used"), std::string::npos);
  // --no-figures: the loops only the viewer draws are neither binned nor
  // written, and result.json says so.
  EXPECT_FALSE(std::filesystem::exists(dir + "/fuse/loop_viewer.json"));
  EXPECT_NE(fused.find("\"loop_bins\": 0"), std::string::npos);
  const CommandResult only =
      Wearscar("fuse --force " + force + " --scan " + zon + " --slope scan");
  EXPECT_EQ(only.status, 2) << only.output;
  EXPECT_NE(only.output.find("no worn track found"), std::string::npos);
}

TEST(Cli, UnitsGivenPerColumnAndAManifestWithQuotedCommas) {
  const std::string data = std::string(WEARSCAR_TEST_DATA) + "/force/";
  // x in um under a header without a unit, stated with --columns.
  const CommandResult f = Wearscar("force " + data +
                                   "home_built_um.csv --columns "
                                   "x=x-Position:um --no-lugre");
  EXPECT_EQ(f.status, 0) << f.output;
  EXPECT_NE(f.output.find("stroke 5.697 mm"), std::string::npos) << f.output;
  EXPECT_EQ(f.output.find("'x-Position' states no unit"), std::string::npos)
      << f.output;
  const CommandResult bad =
      Wearscar("force " + data + "home_built_um.csv --x-unit furlong");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.output.find("--x-unit: found 'furlong': the x unit is not a "
                            "length unit"),
            std::string::npos)
      << bad.output;
  // A manifest whose quoted path holds a comma (RFC 4180).
  const std::string dir = ::testing::TempDir() + "/cli-manifest-quoted";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir + "/beech, run 2");
  std::filesystem::copy_file(data + "quoted_header.csv",
                             dir + "/beech, run 2/B-RT-R.csv");
  {
    std::ofstream m(dir + "/manifest.csv");
    m << "specimen,force,scan\nB-RT-R,\"beech, run 2/B-RT-R.csv\",\n";
  }
  const CommandResult a = Wearscar("audit " + dir + "/manifest.csv -o " + dir +
                                   "/out --no-figures --no-lugre");
  EXPECT_EQ(a.status, 0) << a.output;
  EXPECT_NE(a.output.find("1 specimens: 1 explained"), std::string::npos)
      << a.output;
}

TEST(Cli, SpecialFilesAreRefusedNotReadForever) {
  // A FIFO would block the reader, /dev/zero never end.
  const std::string fifo = ::testing::TempDir() + "/cli-fifo";
  std::filesystem::remove(fifo);
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string& cmd :
       {"force " + fifo, "scan " + fifo, "fuse --force " + fifo}) {
    const CommandResult r = Wearscar(cmd);
    EXPECT_EQ(r.status, 2) << cmd;
    EXPECT_NE(r.output.find(fifo + ": not a regular file (a FIFO)"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1)
        << r.output;
  }
  const CommandResult z = Wearscar("force /dev/zero");
  EXPECT_EQ(z.status, 2);
  EXPECT_NE(z.output.find("/dev/zero: not a regular file (a character "
                          "device)"),
            std::string::npos)
      << z.output;
  std::filesystem::remove(fifo);
}

// Files in `dir` (hidden ones too), by name.
std::set<std::string> FilesIn(const std::string& dir) {
  std::set<std::string> names;
  if (!std::filesystem::exists(dir)) return names;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    names.insert(e.path().filename().string());
  return names;
}

TEST(Faults, AFullDiskLeavesNothingNewAndSaysWhy) {
  // RLIMIT_FSIZE stands in for a full disk (writes fail with EFBIG once a
  // file passes 100 KiB; SIGXFSZ ignored so that the write returns).
  const std::string dir = ::testing::TempDir() + "/faults-full";
  std::filesystem::remove_all(dir);
  const CommandResult s = Wearscar(
      "simulate --case B-RT-R --cycles 30 "
      "--scan-cols 64 --scan-rows 48 "
      "--formats csv -o " +
      dir);
  ASSERT_EQ(s.status, 0) << s.output;
  const std::string cmd = "sh -c \"trap '' XFSZ; ulimit -f 100; exec " +
                          std::string(WEARSCAR_BINARY) + " fuse --force " +
                          dir + "/B-RT-R.force.csv --no-lugre -o " + dir +
                          "/out\" 2>&1";
  const CommandResult r = Shell(cmd);
  const std::string& output = r.output;
  EXPECT_EQ(r.status, 2) << output;
  EXPECT_NE(output.find("write failed: File too large"), std::string::npos)
      << output;
  // Nothing but the folder's lock.
  EXPECT_EQ(FilesIn(dir + "/out"), std::set<std::string>{".wearscar.lock"});
}

TEST(Faults, ARunAgainIntoTheFolderReplacesEachFileAndNothingElse) {
  // The second run's files take the first's places (exchanged, or renamed
  // where there was none); what the first left in the staging folder goes
  // with it. A file of the user's, and a link where a product goes, are
  // left as they were.
  const std::string dir = ::testing::TempDir() + "/faults-again";
  std::filesystem::remove_all(dir);
  ASSERT_EQ(Wearscar("simulate --case B-RT-R --cycles 30 --scan-cols 64 "
                     "--scan-rows 48 --formats csv -o " +
                     dir)
                .status,
            0);
  const std::string out = dir + "/out";
  const std::string run = "fuse " + dir +
                          "/B-RT-R.force.csv --no-lugre --no-figures -o " +
                          out + " --detail-cycle ";
  ASSERT_EQ(Wearscar(run + "5").status, 0);
  const std::string first = Slurp(out + "/detail.csv");
  const std::set<std::string> files = FilesIn(out);
  std::ofstream(out + "/notes.txt") << "mine\n";
  std::filesystem::remove(out + "/cycles.csv");
  std::filesystem::create_symlink("notes.txt", out + "/cycles.csv");
  const CommandResult again = Wearscar(run + "9");
  ASSERT_EQ(again.status, 0) << again.output;
  const std::string second = Slurp(out + "/detail.csv");
  EXPECT_NE(second, first);
  ASSERT_EQ(
      Wearscar("fuse " + dir + "/B-RT-R.force.csv --no-lugre --no-figures -o " +
               dir + "/fresh --detail-cycle 9")
          .status,
      0);
  EXPECT_EQ(second, Slurp(dir + "/fresh/detail.csv"));
  std::set<std::string> expected = files;
  expected.insert("notes.txt");
  EXPECT_EQ(FilesIn(out), expected);
  EXPECT_EQ(Slurp(out + "/notes.txt"), "mine\n");
  // The link was replaced by the product, as a rename replaces it.
  EXPECT_FALSE(std::filesystem::is_symlink(out + "/cycles.csv"));
  EXPECT_EQ(Slurp(out + "/cycles.csv"), Slurp(dir + "/fresh/cycles.csv"));
  // A folder where a product goes is refused, and kept with what it holds.
  std::filesystem::remove(out + "/loops.csv");
  std::filesystem::create_directory(out + "/loops.csv");
  std::ofstream(out + "/loops.csv/kept.txt") << "kept\n";
  const CommandResult refused = Wearscar(run + "9");
  EXPECT_EQ(refused.status, 2) << refused.output;
  EXPECT_NE(refused.output.find("loops.csv: cannot move into place"),
            std::string::npos)
      << refused.output;
  EXPECT_EQ(Slurp(out + "/loops.csv/kept.txt"), "kept\n");
}

TEST(Faults, ASecondWriterIntoTheSameFolderIsRefused) {
  const std::string dir = ::testing::TempDir() + "/faults-lock";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const int fd =
      open((dir + "/.wearscar.lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(flock(fd, LOCK_EX | LOCK_NB), 0);  // another writer holds it
  const CommandResult r =
      Wearscar("force " + kData + "generic.csv --no-lugre -o " + dir);
  close(fd);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find(dir + ": another wearscar is writing into this "
                                "folder"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/cycles.csv"));
}

TEST(Faults, FiguresThatAreNotDrawnAreAWarningAndStatusFour) {
  // Q all zero is no friction recorded: refused as that, nothing written.
  // Q zero but in one sample: gnuplot cannot draw the J(mu) and mu-hat
  // figures (no finite value to plot); the numbers are written, the
  // figures that exist are whole, and the status says that some are
  // missing.
  const std::string dir = ::testing::TempDir() + "/faults-figures";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto write = [&](const std::string& name, double q_at_100) {
    std::ofstream f(dir + "/" + name);
    f << "time_s,x_mm,Q_N,P_N\n";
    for (int i = 0; i < 4000; ++i) {
      const double t = i * 0.005;
      f << t << "," << 2.85 * std::sin(2 * M_PI * t) << ","
        << (i == 100 ? q_at_100 : 0.0) << ",30\n";
    }
  };
  write("q0.csv", 0);
  write("q1.csv", 0.001);
  const CommandResult zero = Wearscar("fuse --force " + dir +
                                      "/q0.csv --no-lugre -o " + dir + "/out0");
  EXPECT_EQ(zero.status, 2) << zero.output;
  EXPECT_NE(zero.output.find(dir + "/q0.csv: no friction force recorded: the "
                                   "friction channel 'Q' is 0 N in every one "
                                   "of the 4000 samples"),
            std::string::npos)
      << zero.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out0/result.json"));
  const CommandResult r =
      Wearscar("fuse --force " + dir + "/q1.csv --no-lugre -o " + dir + "/out");
  if (r.output.find("gnuplot was not found") != std::string::npos)
    GTEST_SKIP() << "gnuplot is not installed";
  EXPECT_EQ(r.status, 4) << r.output;
  EXPECT_NE(r.output.find("figures asked for were not drawn"),
            std::string::npos)
      << r.output;
  EXPECT_NE(Slurp(dir + "/out/result.json").find("were not drawn"),
            std::string::npos);
  for (const std::string& f : FilesIn(dir + "/out")) {
    EXPECT_EQ(f.find(".part"), std::string::npos) << f;
    if (f.size() > 4 && f.substr(f.size() - 4) == ".png") {
      EXPECT_GT(std::filesystem::file_size(dir + "/out/" + f), 100u) << f;
    }
  }
}

namespace {

// Whether a file named by `seen` is in one of `out`'s staging folders.
bool InStaging(const std::string& out,
               const std::function<bool(const std::string&)>& seen) {
  namespace fs = std::filesystem;
  std::error_code ec;
  for (const auto& d : fs::directory_iterator(out, ec)) {
    if (d.path().filename().string().rfind(".wearscar-staging-", 0) != 0)
      continue;
    for (auto e = fs::recursive_directory_iterator(d.path(), ec);
         !ec && e != fs::recursive_directory_iterator();
         e.increment(ec))
      if (seen(e->path().filename().string())) return true;
  }
  return false;
}

}  // namespace

TEST(Faults, AKilledRunLeavesNoHalfFileAndAQuotedFolderIsJustAName) {
  // fuse with figures into a folder whose name holds a quote and a space
  // (gnuplot runs without a shell), killed at two moments it is seen to
  // reach (not after a delay, which passes when nothing was written yet):
  // while its tables are written and while gnuplot draws a figure. Each
  // time the products wait in a staging folder, and nothing is under a
  // final name; a run to the end draws every figure there.
  const std::string dir = ::testing::TempDir() + "/faults-kill";
  std::filesystem::remove_all(dir);
  ASSERT_EQ(Wearscar("simulate --case S-RT-R --cycles 60 --scan-cols 256 "
                     "--scan-rows 192 --scan-pitch 0.0296 --formats csv,gsf "
                     "-o " +
                     dir)
                .status,
            0);
  const std::string out = dir + "/it's out";
  const std::string args =
      "fuse --force " + dir + "/S-RT-R.force.csv --scan " + dir +
      "/S-RT-R.scan.gsf --no-lugre --figure-format svg,png "
      "-o";
  const std::vector<
      std::pair<std::string, std::function<bool(const std::string&)>>>
      moments = {{"a table written",
                  [](const std::string& f) { return f == "cycles.csv"; }},
                 {"a figure being drawn", [](const std::string& f) {
                    return f.size() > 5 && f.substr(f.size() - 5) == ".part";
                  }}};
  for (const auto& [moment, seen] : moments) {
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      setpgid(0, 0);
      const int null = open("/dev/null", O_WRONLY);
      dup2(null, STDOUT_FILENO);
      dup2(null, STDERR_FILENO);
      std::vector<std::string> words;
      std::istringstream in(args);
      for (std::string w; in >> w;) words.push_back(w);
      words.push_back(out);
      std::vector<char*> argv;
      std::string bin = WEARSCAR_BINARY;
      argv.push_back(bin.data());
      for (auto& w : words) argv.push_back(w.data());
      argv.push_back(nullptr);
      execv(bin.c_str(), argv.data());
      _exit(127);
    }
    bool killed = false;
    for (int k = 0; k < 600000 && !killed; ++k) {
      if (waitpid(pid, nullptr, WNOHANG) == pid) break;  // ended first
      if (InStaging(out, seen)) {
        kill(-pid, SIGKILL);  // the process group: gnuplot too
        waitpid(pid, nullptr, 0);
        killed = true;
      } else {
        usleep(200);
      }
    }
    ASSERT_TRUE(killed) << "the run ended before " << moment;
    for (const auto& e : std::filesystem::directory_iterator(out)) {
      const std::string f = e.path().filename().string();
      EXPECT_TRUE(f == ".wearscar.lock" ||
                  f.rfind(".wearscar-staging-", 0) == 0)
          << f << " under its final name, killed at " << moment;
    }
  }
  // To the end: every figure, no staging left.
  const CommandResult full = Wearscar(args + " \"" + out + "\"");
  if (full.output.find("gnuplot was not found") != std::string::npos)
    GTEST_SKIP() << "gnuplot is not installed";
  EXPECT_EQ(full.status, 0) << full.output;
  const auto files = FilesIn(out);
  EXPECT_TRUE(files.count("fig14_cost.png")) << full.output;
  EXPECT_TRUE(files.count("fig08ab_scan_map.svg")) << full.output;
  for (const std::string& f : files)
    EXPECT_EQ(f.rfind(".wearscar-staging-", 0), std::string::npos) << f;
}

TEST(Faults, LibrariesDoNotTalkOnStderr) {
  // A flat map: PCL's RANSAC finds its sample points collinear on every
  // draw (it used to print a line for each, about a thousand); the user sees
  // one warning line, that no track was found.
  const std::string dir = ::testing::TempDir() + "/faults-quiet";
  std::filesystem::create_directories(dir);
  {
    std::ofstream f(dir + "/flat.csv");
    f << "XY Calibration,7.4,um\nHeight\n";
    for (int r = 0; r < 200; ++r) {
      for (int c = 0; c < 300; ++c) f << (c ? "," : "") << "0.5";
      f << "\n";
    }
  }
  const std::string cmd = std::string(WEARSCAR_BINARY) + " scan " + dir +
                          "/flat.csv 2>&1 >/dev/null";
  const std::string err = Shell(cmd).output;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_NE(err.find("warning: " + dir + "/flat.csv: no worn track found"),
            std::string::npos)
      << err;
}

// Degenerate but legal data still draw what can be drawn: a friction
// channel that never changes gives every force-side figure; a flat map,
// in which no track can be found, is left out with a warning and still
// drawn, so that the user sees why.
TEST(Faults, ConstantFrictionAndAFlatMapStillDrawTheirFigures) {
  const std::string dir = ::testing::TempDir() + "/faults-degenerate";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  {
    std::ifstream in(kData + "generic.csv");
    std::ofstream out(dir + "/constq.csv");
    std::string line;
    std::getline(in, line);
    out << line << "\n";
    while (std::getline(in, line)) {
      // time_s,x_mm,Q_N,P_N with Q set to 2 N throughout.
      const size_t a = line.find(','), b = line.find(',', a + 1),
                   c = line.find(',', b + 1);
      out << line.substr(0, b) << ",2.0" << line.substr(c) << "\n";
    }
    std::ofstream f(dir + "/flat.csv");
    f << "XY Calibration,7.4,um\nHeight\n";
    for (int r = 0; r < 200; ++r) {
      for (int col = 0; col < 600; ++col) f << (col ? "," : "") << "0.5";
      f << "\n";
    }
  }
  const CommandResult r =
      Shell(std::string(WEARSCAR_BINARY) + " fuse " + dir + "/constq.csv " +
            dir + "/flat.csv --out " + dir + "/out 2>&1");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("warning: the scan was not used (" + dir +
                          "/flat.csv: no worn track found"),
            std::string::npos)
      << r.output;
  const auto files = FilesIn(dir + "/out");
  for (const char* f : {"fig05_q_envelope.svg",
                        "fig06_p_envelope.svg",
                        "fig07_loops.svg",
                        "fig10_slope.svg",
                        "fig13_mu_hat.svg",
                        "fig_friction_map.svg",
                        "fig08ab_scan_map.svg"})
    EXPECT_TRUE(files.count(f)) << f << "\n" << r.output;
  std::ifstream map(dir + "/out/fig08ab_scan_map.svg");
  const std::string svg((std::istreambuf_iterator<char>(map)),
                        std::istreambuf_iterator<char>());
  EXPECT_NE(svg.find("levelled scan, no track found (not used)"),
            std::string::npos);
}

TEST(Audit, ManifestNamesStayUnderOutAndAppearOnce) {
  const std::string dir = ::testing::TempDir() + "/audit-names";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(kData + "generic.csv", dir + "/a.csv");
  const struct {
    const char* manifest;
    const char* message;
  } cases[] = {
      {"specimen,force\n../escape,a.csv\n",
       "line 2: specimen name '../escape' cannot be a folder under --out (it "
       "holds a path separator)"},
      {"specimen,force\n/tmp/abs,a.csv\n", "it holds a path separator"},
      {"specimen,force\n.hidden,a.csv\n", "it starts with a dot"},
      {"specimen,force\nA,a.csv\nB,a.csv\nA,a.csv\n",
       "line 4: specimen 'A' appears twice (also on line 2)"},
  };
  for (const auto& c : cases) {
    {
      std::ofstream m(dir + "/m.csv");
      m << c.manifest;
    }
    const CommandResult r =
        Wearscar("audit " + dir + "/m.csv -o " + dir + "/out --no-figures");
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir + "/escape"));
    EXPECT_FALSE(std::filesystem::exists("/tmp/abs"));
  }
}

TEST(Cli, LargeMapsIsTheOptInBeyondTheDecompressionLimits) {
  // 100 MiB of zeros deflated 1000:1 inside an x3p: refused as a bomb, read
  // with --large-maps (and then found 22 kB longer than its 3620 x 3620
  // values: the next check speaks).
  const std::string bomb = std::string(WEARSCAR_TEST_DATA) + "/bad/bomb.x3p";
  const CommandResult refused = Wearscar("scan " + bomb);
  EXPECT_EQ(refused.status, 2);
  EXPECT_NE(refused.output.find("a ratio above 100"), std::string::npos)
      << refused.output;
  const CommandResult opted = Wearscar("scan " + bomb + " --large-maps");
  EXPECT_EQ(opted.status, 2);
  EXPECT_NE(opted.output.find("has 104857600 bytes; expected 104835200"),
            std::string::npos)
      << opted.output;
}

TEST(Cli, OptionsOutOfRangeAreRefusedByTheirOwnName) {
  const struct {
    std::string args, message;
  } cases[] = {
      {"force " + kData + "generic.csv --spring 0",
       "--spring: found 0; expected a number from 1e-06 to 1e+06"},
      {"force " + kData + "generic.csv --mu-max -1",
       "--mu-max: found -1; expected a number from 0.001 to 10"},
      {"fuse --force " + kData +
           "generic.csv --compare-first 15 --compare-last 3",
       "--compare-first: cycle 15 is after the last compared cycle 3"},
      {"force " + kData + "generic.csv --running-in 1000000",
       "a running-in of 1000000 cycles was given (--running-in); the test "
       "has 2 complete cycles"},
      {"scan " + kData + "generic.csv --step 1e-12",
       "the centreline step must be 0 (the pitch) or 1e-6 to 10 mm"},
  };
  for (const auto& c : cases) {
    const CommandResult r = Wearscar(c.args);
    EXPECT_EQ(r.status, 2) << c.args;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << c.args << "\n"
                                                           << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1)
        << r.output;
  }
}

TEST(Cli, FuseWithUnreadableScanExitsTwoNamingIt) {
  const std::string dir = ::testing::TempDir() + "/cli-fuse-bad";
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/bad.vk4") << "VK4_ but far too short";
  const CommandResult f =
      Wearscar("fuse --force " + kData + "generic.csv --scan " + dir +
               "/bad.vk4 -o " + dir + "/out");
  EXPECT_EQ(f.status, 2);
  EXPECT_NE(f.output.find(dir + "/bad.vk4: byte 0: truncated"),
            std::string::npos)
      << f.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out"));
}

}  // namespace

namespace {

TEST(Cli, SimulateEffectAndSeedAreDeterministicAndRecorded) {
  const std::string base = ::testing::TempDir() + "/cli-sim-seed";
  std::filesystem::remove_all(base);
  const std::string args =
      "simulate --case S-RT-R --cycles 5 --rate 500 --scan-cols 64 "
      "--scan-rows 48 --effect ploughing=1.0 --effect hook-length=0.2 "
      "--seed 7 --out ";
  ASSERT_EQ(Wearscar(args + base + "/a").status, 0);
  ASSERT_EQ(Wearscar(args + base + "/b").status, 0);
  for (const char* f : {"S-RT-R.force.csv",
                        "S-RT-R.rtec.csv",
                        "S-RT-R.scan.gsf",
                        "S-RT-R.keyence.csv",
                        "S-RT-R.truth.json"}) {
    const std::string a = Slurp(base + "/a/" + f);
    EXPECT_FALSE(a.empty()) << f;
    EXPECT_EQ(a, Slurp(base + "/b/" + f)) << f;  // same seed, same bytes
  }
  const std::string truth = Slurp(base + "/a/S-RT-R.truth.json");
  for (const char* key : {"\"seed\": 7",
                          "\"ploughing_n_per_mm\": 1.0",
                          "\"hook_length_mm\": 0.2",
                          "\"pitch_mm\"",
                          "\"col_per_mm\"",
                          "\"force_profile_range_mm\"",
                          "\"scan_profile_sd_mm\""}) {
    EXPECT_NE(truth.find(key), std::string::npos) << key << "\n" << truth;
  }
  ASSERT_EQ(Wearscar("simulate --case S-RT-R --cycles 5 --rate 500 "
                     "--scan-cols 64 --scan-rows 48 --seed 8 --out " +
                     base + "/c")
                .status,
            0);
  EXPECT_NE(Slurp(base + "/a/S-RT-R.force.csv"),
            Slurp(base + "/c/S-RT-R.force.csv"));
  const CommandResult bad = Wearscar(
      "simulate --case S-RT-R --effect plowing=2 --out " + base + "/d");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.output.find("unknown effect 'plowing'; expected one of "
                            "ploughing (N/mm)"),
            std::string::npos)
      << bad.output;
  const CommandResult nan =
      Wearscar("simulate --case S-RT-R --effect hook=abc --out " + base + "/d");
  EXPECT_EQ(nan.status, 2);
  EXPECT_NE(nan.output.find("'abc' is not a number"), std::string::npos)
      << nan.output;
}

// Three small simulated specimens and one whose force file is broken, in a
// folder of the calling test's own (ctest runs tests as parallel processes).
std::string AuditFolder(const std::string& tag) {
  const std::string dir = [&] {
    const std::string d = ::testing::TempDir() + "/audit-in-" + tag;
    std::filesystem::remove_all(d);
    const CommandResult s = Wearscar(
        "simulate --case B-RT-R --case S-RL-R --case S-TL-L --cycles 60 --rate "
        "1000 "
        "--scan-cols 512 --scan-rows 384 --scan-pitch 0.0148 -o " +
        d);
    EXPECT_EQ(s.status, 0) << s.output;
    std::ofstream bad(d + "/B-RL-L.force.csv");
    bad << "time_s,x_mm,Q_N,P_N\n";
    for (int i = 0; i < 40; ++i) {
      bad << i * 0.01 << "," << (i % 7) << "," << (i == 20 ? "abc" : "1.5")
          << ",30\n";
    }
    return d;
  }();
  return dir;
}

// The maps of other instruments go through scan and audit like the
// Keyence ones: the registry finds them by content (a Zygo ".dat" beside a
// force export ".csv" is paired as the scan).
TEST(Cli, OtherInstrumentsReadThroughScanAndAudit) {
  const std::string other = std::string(WEARSCAR_SHARED_DATA) + "/other/";
  if (!std::filesystem::exists(other))
    GTEST_SKIP() << "../shared/data is absent (real instrument files)";
  const std::string dir = ::testing::TempDir() + "/cli-instruments";
  std::filesystem::remove_all(dir);
  for (const auto& [file, format] :
       std::vector<std::pair<std::string, std::string>>{
           {"plu-1.plu", "plu"},
           {"al3d-1.al3d", "al3d"},
           {"opd-1.opd", "opd"},
           {"sur-3.sur", "sur"},
           {"metropro-1.dat", "metropro"}}) {
    const CommandResult r =
        Wearscar("scan " + other + file + " -o " + dir + "/" + format);
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(Slurp(dir + "/" + format + "/scan.json")
                  .find("\"format\": \"" + format + "\""),
              std::string::npos)
        << file;
  }
  ASSERT_EQ(Wearscar("simulate --case B-TL-L --cycles 40 --scan-cols 64 "
                     "--scan-rows 48 --formats csv -o " +
                     dir + "/sim")
                .status,
            0);
  std::filesystem::create_directories(dir + "/batch");
  std::filesystem::copy_file(dir + "/sim/B-TL-L.force.csv",
                             dir + "/batch/B-TL-L.force.csv");
  std::filesystem::copy_file(other + "metropro-1.dat",
                             dir + "/batch/B-TL-L.dat");
  const CommandResult a =
      Wearscar("audit " + dir + "/batch --running-in 5 " +
               "--compare-cycles 10 --no-figures -o " + dir + "/audit");
  EXPECT_EQ(a.status, 0) << a.output;
  const std::string json = Slurp(dir + "/audit/B-TL-L/result.json");
  EXPECT_NE(json.find("B-TL-L.dat: no worn track found"), std::string::npos)
      << json.substr(0, 2000);
}

// Each audit line says what its specimen rests on: the layout, the units
// (those guessed named) and the running-in; fuse says it with the rest of
// the assumptions.
TEST(Audit, EachLineSaysTheLayoutTheGuessedUnitsAndTheRunningIn) {
  const std::string dir = ::testing::TempDir() + "/audit-assumed";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir + "/in");
  std::filesystem::copy_file(kData + "home_built_um.csv",
                             dir + "/in/elm_force.csv");
  std::filesystem::copy_file(kData + "generic.csv", dir + "/in/ash_force.csv");
  const CommandResult r =
      Wearscar("audit " + dir + "/in -o " + dir + "/out --no-figures");
  ASSERT_EQ(r.status, 0) << r.output;
  const auto line_after = [&](const std::string& key) {
    const size_t at = r.output.find(key);
    if (at == std::string::npos) return std::string();
    const size_t next = r.output.find('\n', at) + 1;
    return r.output.substr(next, r.output.find('\n', next) - next);
  };
  EXPECT_EQ(line_after("elm: force only"),
            "           read as 'home-built', units um, N, N, time from the "
            "rate (guessed: x um, Q N, P N); running-in 0 cycles (given or "
            "too few cycles)")
      << r.output;
  EXPECT_NE(line_after("ash: force only")
                .find("read as 'delimited', units s, mm, N, N; running-in "),
            std::string::npos)
      << r.output;
  const CommandResult f = Wearscar("fuse " + dir + "/in/elm_force.csv -o " +
                                   dir + "/fuse --no-figures");
  EXPECT_NE(f.output.find("  assumed: the force file read as the "
                          "'home-built' layout; units: x um (guessed: no unit "
                          "stated), Q N (guessed: no unit stated), P N "
                          "(guessed: no unit stated), time from the sampling "
                          "rate\n  assumed: running-in: 0 cycles (4 cycles are "
                          "too few to detect it)"),
            std::string::npos)
      << f.output;
}

TEST(Audit, OneBadSpecimenIsReportedAndTheRestComplete) {
  const std::string out = ::testing::TempDir() + "/audit-out";
  std::filesystem::remove_all(out);
  const CommandResult r =
      Wearscar("audit " + AuditFolder("bad") +
               " --running-in 30 --compare-cycles 30 -o " + out);
  EXPECT_EQ(r.status, 3) << r.output;  // a specimen failed (usage: 2)
  EXPECT_NE(r.output.find("FAILED   B-RL-L"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("FLAGGED  S-RL-R"), std::string::npos) << r.output;
  EXPECT_NE(
      r.output.find("4 specimens: 2 explained, 1 not explained, 1 failed"),
      std::string::npos)
      << r.output;
  const std::string csv = Slurp(out + "/summary.csv");
  EXPECT_EQ(CountLines(csv), 5);
  EXPECT_NE(csv.find("B-RT-R,beech,RT,R,60,explained,0.1"), std::string::npos)
      << csv;
  EXPECT_NE(csv.find("line 22, column 3 ('Q'): found 'abc'"), std::string::npos)
      << csv;
  for (const char* f : {"B-RT-R/result.json",
                        "B-RT-R/fig08ab_scan_map.svg",
                        "B-RT-R/fig12_reconstruction.svg",
                        "S-TL-L/cycles.csv",
                        "report.html",
                        "summary.json",
                        "audit_fig16_differences.svg"}) {
    EXPECT_TRUE(std::filesystem::exists(out + "/" + f)) << f;
  }
}

TEST(Audit, ManifestPairsFilesAndShardsMergeInOneFolder) {
  const std::string in = AuditFolder("manifest");
  const std::string manifest = ::testing::TempDir() + "/manifest.csv";
  std::ofstream(manifest) << "specimen,force,scan\n"
                          << "B-RT-R," << in << "/B-RT-R.force.csv," << in
                          << "/B-RT-R.scan.gsf\n"
                          << "S-TL-L," << in << "/S-TL-L.force.csv,\n"
                          << "S-RL-R," << in << "/S-RL-R.force.csv," << in
                          << "/S-RL-R.scan.gsf\n";
  const std::string out = ::testing::TempDir() + "/audit-shards";
  std::filesystem::remove_all(out);
  // Shard 2 first: the merge names shard 1 as missing until it has run.
  const CommandResult second = Wearscar("audit " + manifest +
                                        " --shard 2/2 --no-figures "
                                        "--running-in 30 -o " +
                                        out);
  EXPECT_EQ(second.status, 0) << second.output;
  EXPECT_NE(second.output.find("merged into " + out +
                               ": 1 specimens from 1 of 2 shards; missing: "
                               "shard 1 (not in the summary yet"),
            std::string::npos)
      << second.output;
  EXPECT_NE(Slurp(out + "/report.html")
                .find("(shard 1 of 2 missing: not in this report)"),
            std::string::npos);
  // A merge job with a shard missing fails, naming it (an `afterany`
  // merge shows the audit incomplete).
  const CommandResult early =
      Wearscar("audit --merge " + out + " --no-figures");
  EXPECT_EQ(early.status, 3) << early.output;
  EXPECT_NE(early.output.find(out + ": 1 of 2 shards missing (1); their "
                                    "specimens are not in the summary"),
            std::string::npos)
      << early.output;
  // Another split into the same folder is refused before any work.
  const CommandResult other =
      Wearscar("audit " + manifest + " --shard 4/4 --no-figures -o " + out);
  EXPECT_EQ(other.status, 2) << other.output;
  EXPECT_NE(other.output.find("--shard '4/4' (from 1): " + out +
                              " holds the parts of an audit split into 2 "
                              "shards, indices from 1 (--shard; "),
            std::string::npos)
      << other.output;
  const CommandResult first = Wearscar("audit " + manifest +
                                       " --shard 1/2 --no-figures "
                                       "--running-in 30 -o " +
                                       out);
  EXPECT_EQ(first.status, 0) << first.output;
  const std::string table = Slurp(out + "/summary.csv");
  // Header once, then the three specimens.
  EXPECT_EQ(CountLines(table), 4) << table;
  EXPECT_EQ(table.rfind("specimen,species,plane,direction", 0), 0u);
  EXPECT_NE(table.find("\nS-TL-L,spruce,TL,L,60,"), std::string::npos) << table;
  // The merge again, alone: the same table.
  const CommandResult merge =
      Wearscar("audit --merge " + out + " --no-figures");
  EXPECT_EQ(merge.status, 0) << merge.output;
  EXPECT_NE(merge.output.find("3 specimens from 2 of 2 shards"),
            std::string::npos)
      << merge.output;
  EXPECT_EQ(Slurp(out + "/summary.csv"), table);
  // A folder no shard wrote into: said, exit 2.
  const CommandResult none = Wearscar("audit --merge " + in + "/nothing");
  EXPECT_EQ(none.status, 2) << none.output;
  EXPECT_NE(none.output.find("no parts (shard-<i>-of-<n>.json)"),
            std::string::npos)
      << none.output;
}

// The cluster recipe run as a lab would run it on one machine: three
// shards at once (GNU parallel, or xargs -P without it) into one folder,
// then the merge; its summary holds the rows a single audit writes.
// A folder holding only an analysis's output: the audit names what it
// skipped and the option that searches it; a folder `wearscar simulate`
// wrote is searched.
TEST(Audit, SaysTheFoldersItSkipped) {
  const std::string dir = ::testing::TempDir() + "/audit-skipped";
  std::filesystem::remove_all(dir);
  const std::string samples = std::string(WEARSCAR_SAMPLES_DIR) + "/data";
  ASSERT_EQ(Wearscar("fuse " + samples +
                     "/B-RT-R.force.csv --no-figures "
                     "--no-lugre --quiet -o " +
                     dir + "/lab/out")
                .status,
            0);
  const CommandResult none =
      Wearscar("audit " + dir + "/lab -o " + dir + "/audit");
  EXPECT_EQ(none.status, 2) << none.output;
  EXPECT_NE(none.output.find("skipped 1 folder: out/ (written by wearscar "
                             "fuse) (--include-output-folders searches them)"),
            std::string::npos)
      << none.output;
  ASSERT_EQ(Wearscar("simulate --case B-RT-R --cycles 20 --rate 500 "
                     "--scan-cols 128 --scan-rows 96 --scan-pitch 0.05 "
                     "--formats csv,gsf -o " +
                     dir + "/lab/sim")
                .status,
            0);
  const CommandResult found =
      Wearscar("audit " + dir + "/lab -o " + dir + "/audit --no-figures -j 1");
  EXPECT_EQ(found.status, 0) << found.output;
  EXPECT_NE(found.output.find("skipped 1 folder wearscar's analyses wrote: "
                              "out/ (written by wearscar fuse)"),
            std::string::npos)
      << found.output;
  EXPECT_NE(found.output.find("1 specimens: 1 explained"), std::string::npos)
      << found.output;
}

TEST(Audit, TheParallelRecipeMatchesASingleAudit) {
  const std::string samples = std::string(WEARSCAR_SAMPLES_DIR) + "/data";
  const std::string recipe =
      std::string(WEARSCAR_SAMPLES_DIR) + "/../examples/parallel.sh";
  const std::string dir = ::testing::TempDir() + "/audit-recipe";
  std::filesystem::remove_all(dir);
  const CommandResult r =
      Shell("WEARSCAR=" + std::string(WEARSCAR_BINARY) + " " + recipe + " " +
            samples + " " + dir + "/sharded 3 -j 1 --no-figures 2>&1");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("12 specimens from 3 of 3 shards"), std::string::npos)
      << r.output;
  EXPECT_EQ(FilesIn(dir + "/sharded/parts"),
            (std::set<std::string>{"plan.json",
                                   "shard-1-of-3.json",
                                   "shard-2-of-3.json",
                                   "shard-3-of-3.json"}));
  ASSERT_EQ(Wearscar("audit " + samples + " -o " + dir + "/single --no-figures")
                .status,
            0);
  // Row by row, but for the date of the run.
  const auto rows = [](const std::string& csv) {
    std::vector<std::string> lines;
    std::istringstream in(csv);
    std::string line;
    while (std::getline(in, line)) {
      // date_utc is the last column.
      lines.push_back(line.substr(0, line.rfind(',')));
    }
    std::sort(lines.begin() + 1, lines.end());
    return lines;
  };
  const auto sharded = rows(Slurp(dir + "/sharded/summary.csv"));
  const auto single = rows(Slurp(dir + "/single/summary.csv"));
  ASSERT_EQ(sharded.size(), 13u);
  EXPECT_EQ(sharded, single);
}

// The audit's report as a browser shows it (headless Chromium): one
// audit, read by each test below.
class AuditInChromium : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (std::system("command -v chromium > /dev/null 2>&1") != 0) return;
    // Folders of this process's own: ctest runs each test in a process of
    // its own, in parallel, and two Chromiums on one profile are one.
    tag_ = "browser-" + std::to_string(getpid());
    out_ = ::testing::TempDir() + "/audit-out-" + tag_;
    std::filesystem::remove_all(out_);
    Wearscar("audit " + AuditFolder(tag_) + " --running-in 30 -o " + out_);
  }
  static void TearDownTestSuite() {
    if (out_.empty()) return;
    std::filesystem::remove_all(out_);
    std::filesystem::remove_all(::testing::TempDir() + "/audit-in-" + tag_);
    std::filesystem::remove_all(Profile());
  }
  static std::string Profile() {
    return ::testing::TempDir() + "/chromium-profile-" + tag_;
  }
  void SetUp() override {
    if (out_.empty()) {
      GTEST_SKIP() << "Debian's chromium is not installed "
                      "(scripts/install-deps installs it)";
    }
  }
  // The page's DOM after its scripts ran, in a window of `window` (a
  // --window-size argument or "").
  static std::string Dom(const std::string& page,
                         const std::string& window = "") {
    const std::string profile = Profile();
    return Shell(
               "chromium --headless --no-sandbox --disable-gpu "
               "--disable-quic --no-first-run "
               "--disable-background-networking --disable-component-update "
               "--disable-sync " +
               window + " --user-data-dir=" + profile +
               " --virtual-time-budget=10000 --dump-dom 'file://" + out_ + "/" +
               page + "' 2>/dev/null")
        .output;
  }
  // The images decoded and all of them, as the page counts them.
  static std::pair<int, int> Decoded(const std::string& page) {
    const auto at = page.find("data-images-rendered=\"");
    if (at == std::string::npos) return {-1, -1};
    const std::string counts =
        page.substr(at + 22, page.find('"', at + 22) - at - 22);
    return {std::stoi(counts.substr(0, counts.find('/'))),
            std::stoi(counts.substr(counts.find('/') + 1))};
  }
  static std::string out_, tag_;
};

std::string AuditInChromium::out_;
std::string AuditInChromium::tag_;

// The values of the table's column headed `heading`, row by row (the
// shown table: the part before the page's templates).
std::vector<double> ColumnValues(const std::string& dom,
                                 const std::string& heading) {
  const std::string table = dom.substr(0, dom.find("<template"));
  const size_t head = table.find("<thead>");
  const std::string heads = table.substr(head, table.find("</thead>") - head);
  int column = -1, k = 0;
  for (size_t at = heads.find("<th"); at != std::string::npos;
       at = heads.find("<th", at + 1), ++k)
    if (heads.compare(heads.find('>', at) + 1, heading.size(), heading) == 0)
      column = k;
  std::vector<double> values;
  if (column < 0) return values;
  for (size_t at = table.find("<tbody>"); at != std::string::npos;
       at = table.find("<tbody>", at + 1)) {
    size_t cell = at;
    for (int c = 0; c <= column; ++c) cell = table.find("<td", cell + 1);
    cell = table.find('>', cell) + 1;
    const std::string text = table.substr(cell, table.find('<', cell) - cell);
    if (!text.empty()) values.push_back(std::stod(text));
  }
  return values;
}

// The index: every image (lazy ones loaded with ?images=all) decodes; the
// table's rows, the flagged and failed ones highlighted, each one's
// reason a row of its own under it.
TEST_F(AuditInChromium, TheIndexDecodesItsImagesAndMarksItsRows) {
  const std::string dom = Dom("report.html?images=all");
  const auto [ok, all] = Decoded(dom);
  ASSERT_GE(all, 0) << dom.substr(0, 300);
  EXPECT_GE(all, 4);  // the batch figures
  EXPECT_EQ(ok, all);
  EXPECT_NE(dom.find("data-table-rows=\"4\""), std::string::npos);
  EXPECT_NE(dom.find("<tr class=\"flagged\">"), std::string::npos);
  EXPECT_NE(dom.find("<tr class=\"failed\">"), std::string::npos);
  EXPECT_TRUE(std::regex_search(
      dom,
      std::regex("<tr class=\"reason flagged\"><td colspan=\"[0-9]+\"><div>"
                 "not explained by wear-scar interaction")));
  EXPECT_TRUE(std::regex_search(
      dom,
      std::regex("<tr class=\"reason failed\"><td colspan=\"[0-9]+\"><div>"
                 "error: ")));
}

// Filtered and sorted from the page's address: the flagged specimen
// alone; by name; every row by mu-hat, highest first (the table's own
// order is by name).
TEST_F(AuditInChromium, TheAddressFiltersAndSortsTheTable) {
  const std::string flagged = Dom("report.html?verdict=flagged");
  EXPECT_NE(flagged.find("data-table-rows=\"1\""), std::string::npos);
  EXPECT_NE(flagged.find("1-1 of 1 passing the filter (4 specimens)"),
            std::string::npos);
  const std::string by_name = Dom("report.html?filter=S-");
  EXPECT_NE(by_name.find("data-table-rows=\"2\""), std::string::npos);
  const std::string sorted =
      Dom("report.html?sort=-mu-hat%20(k%20from%20P%20or%20depth)");
  const std::vector<double> mu_hats =
      ColumnValues(sorted, "mu-hat (k from P or depth)");
  ASSERT_EQ(mu_hats.size(), 3u) << sorted.substr(0, 2000);
  EXPECT_TRUE(std::is_sorted(mu_hats.rbegin(), mu_hats.rend()));
}

// As a reader sees the index and a specimen's page on a laptop's and a
// desktop's screen: no horizontal scrolling of the page (the wide table
// scrolls in its box), every figure at least 900 px wide, no text under
// 14 px.
TEST_F(AuditInChromium, ThePagesFitALaptopsAndADesktopsScreen) {
  for (const char* page :
       {"report.html?images=all", "B-RT-R/report.html?images=all"}) {
    for (const char* width : {"1280", "1920"}) {
      SCOPED_TRACE(std::string(page) + " at " + width);
      const std::string shown =
          Dom(page, std::string("--window-size=") + width + ",1000");
      const auto l = shown.find("data-layout=\"");
      ASSERT_NE(l, std::string::npos);
      std::istringstream in(
          shown.substr(l + 13, shown.find('"', l + 13) - l - 13));
      int overflow = 1, narrowest = 0, smallest = 0;
      in >> overflow >> narrowest >> smallest;
      EXPECT_LE(overflow, 0);
      EXPECT_GE(narrowest, 900);
      EXPECT_GE(smallest, 14);
    }
  }
}

// Each analysed specimen's page, opened at cycle 12 (?cycle=12): its
// figures decode, its loop viewer draws that cycle's loop, model and map
// row, and says its mu-hat as the specimen's cycles.csv has it.
TEST_F(AuditInChromium, ASpecimensPageOpensAtTheCycleAsked) {
  for (const char* name : {"B-RT-R", "S-RL-R", "S-TL-L"}) {
    SCOPED_TRACE(name);
    const std::string viewed =
        Dom(std::string(name) + "/report.html?cycle=12&images=all");
    EXPECT_NE(viewed.find("data-viewers=\"1\""), std::string::npos);
    const auto [page_ok, page_all] = Decoded(viewed);
    EXPECT_GT(page_all, 10);
    EXPECT_EQ(page_ok, page_all);
    const std::regex viewer(
        std::string("id=\"viewer-") + name +
        R"re(" data-cycle="([0-9]+)" data-points="([0-9]+)")re");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(viewed, m, viewer));
    EXPECT_EQ(m[1], "12");
    EXPECT_GT(std::stoi(m[2]), 200);  // 2 x 2 lines of ~100 bins, 2 x 2 rows
    std::ifstream cycles(out_ + "/" + name + "/cycles.csv");
    std::string line;
    for (int i = 0; i <= 12; ++i) std::getline(cycles, line);
    const std::string mu_hat =
        line.substr(line.find(',') + 1,
                    line.find(',', line.find(',') + 1) - line.find(',') - 1);
    const std::string label = fmt::format(
        "cycle 12 of 60: mu-hat {:.4f} (k from P)", std::stod(mu_hat));
    EXPECT_NE(viewed.find(label), std::string::npos) << label;
  }
}

}  // namespace

namespace {

// The bad-input catalogue (tests/data/bad/catalogue.csv, written by
// make_bad.py): every malformed file through the command line gives exit
// status 2, one line naming the file and the problem, and no output.
struct BadFile {
  std::string file, reader, expected;
};

std::vector<BadFile> LoadCatalogue() {
  std::vector<BadFile> rows;
  std::ifstream in(std::string(WEARSCAR_TEST_DATA) + "/bad/catalogue.csv");
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    const size_t a = line.find(','), b = line.find(',', a + 1);
    BadFile f{
        line.substr(0, a), line.substr(a + 1, b - a - 1), line.substr(b + 1)};
    if (f.expected.size() >= 2 && f.expected.front() == '"') {
      f.expected = f.expected.substr(1, f.expected.size() - 2);
    }
    rows.push_back(f);
  }
  return rows;
}

class BadInputCatalogue : public ::testing::TestWithParam<BadFile> {};

TEST_P(BadInputCatalogue, ExitTwoNamingFileAndProblemNoOutput) {
  const BadFile& f = GetParam();
  const std::string path = std::string(WEARSCAR_TEST_DATA) + "/bad/" + f.file;
  const std::string out = ::testing::TempDir() + "/bad-out-" + f.file;
  std::filesystem::remove_all(out);
  const std::string cmd = f.reader == "force"
                              ? "force " + path + " -o " + out
                              : "fuse --force " + kData +
                                    "generic.csv --scan " + path + " -o " + out;
  const CommandResult r = Wearscar(cmd);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find(path), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(f.expected), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out))
      << "output left behind for " << f.file;
}

INSTANTIATE_TEST_SUITE_P(
    Files,
    BadInputCatalogue,
    ::testing::ValuesIn(LoadCatalogue()),
    [](const ::testing::TestParamInfo<BadFile>& param_info) {
      std::string n = param_info.param.file;
      for (char& ch : n) {
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      }
      return n;
    });

TEST(BadInputCatalogue, HoldsAtLeastThirtyFilesAcrossTheReaders) {
  const auto rows = LoadCatalogue();
  EXPECT_GE(rows.size(), 30u);
  std::set<std::string> extensions;
  for (const auto& r : rows)
    extensions.insert(r.file.substr(r.file.rfind('.')));
  EXPECT_GE(extensions.size(), 8u);  // csv, gsf, vk4, vk6, zon, zag, x3p, txt
}

}  // namespace

namespace {

TEST(Samples, CommittedFilesAreTheSimulatorsOutputByteForByte) {
  const std::string dir = ::testing::TempDir() + "/samples-regen";
  std::filesystem::remove_all(dir);
  const std::string cmd = std::string(WEARSCAR_SAMPLES_DIR) +
                          "/make_samples.sh " + WEARSCAR_BINARY + " " + dir;
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  int compared = 0;
  for (const auto& e : std::filesystem::directory_iterator(
           std::string(WEARSCAR_SAMPLES_DIR) + "/data")) {
    const std::string name = e.path().filename().string();
    EXPECT_EQ(Slurp(e.path().string()), Slurp(dir + "/" + name)) << name;
    ++compared;
  }
  EXPECT_EQ(compared, 36);  // force.csv, scan.gsf, truth.json for 12 cases
}

TEST(Samples, FuseOnTheCommittedSamplesGivesTheExpectedVerdicts) {
  const std::string data = std::string(WEARSCAR_SAMPLES_DIR) + "/data/";
  const CommandResult b =
      Wearscar("fuse --force " + data + "B-RT-R.force.csv --scan " + data +
               "B-RT-R.scan.gsf --running-in 5 --compare-cycles 15");
  EXPECT_EQ(b.status, 0) << b.output;
  EXPECT_NE(b.output.find("verdict: explained by wear-scar interaction"),
            std::string::npos)
      << b.output;
  const CommandResult s =
      Wearscar("fuse --force " + data + "S-RL-R.force.csv --scan " + data +
               "S-RL-R.scan.gsf --running-in 5 --compare-cycles 15");
  EXPECT_EQ(s.status, 0) << s.output;
  EXPECT_NE(s.output.find("verdict: not explained"), std::string::npos)
      << s.output;
}

}  // namespace
