// What a lab relies on around the numbers: command-line conventions,
// provenance, wear, cycle numbering and output folders that can be
// trusted after a re-run.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_helpers.h"
#include "common/paths.h"

namespace {

using namespace wearscar_test;
namespace fs = std::filesystem;

// A small simulated test (30 cycles at 1 kHz, a 256 x 192 scan) in a
// folder of the calling test's own.
std::string Simulated(const std::string& tag,
                      const std::string& cases = "--case B-RT-R") {
  const std::string dir = ::testing::TempDir() + "/lab-" + tag;
  fs::remove_all(dir);
  const CommandResult s =
      Wearscar("simulate " + cases +
               " --cycles 30 --rate 1000 --scan-cols 256 --scan-rows 192 "
               "--scan-pitch 0.0296 --formats csv,gsf -o " +
               dir);
  EXPECT_EQ(s.status, 0) << s.output;
  return dir;
}

nlohmann::json ParseJson(const std::string& text) {
  return nlohmann::json::parse(text, nullptr, false);
}

// stdout only (stderr discarded).
CommandResult Stdout(const std::string& args) {
  return Shell(std::string(WEARSCAR_BINARY) + " " + args + " 2>/dev/null");
}

TEST(Conventions, VersionNamesTheCommit) {
  const std::regex line(
      "wearscar [0-9]+\\.[0-9]+\\.[0-9]+ \\(commit "
      "([0-9a-f]{40}(-dirty)?|unknown)\\)\n");
  for (const char* args : {"--version", "version"}) {
    const CommandResult v = Wearscar(args);
    EXPECT_EQ(v.status, 0) << args;
    EXPECT_TRUE(std::regex_match(v.output, line)) << args << ": " << v.output;
  }
}

TEST(Conventions, AnUnknownCommandSaysSo) {
  const CommandResult r = Wearscar("fusee a.csv");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.output,
            "wearscar: unknown command 'fusee'; expected one of version, "
            "simulate, force, fuse, audit, diagnose, scan, watch (wearscar "
            "--help)\n");
}

TEST(Conventions, HelpShowsTheProgramNameAndEndsWithExamples) {
  for (const std::string cmd :
       {"simulate", "force", "fuse", "audit", "diagnose", "scan", "watch"}) {
    const CommandResult h = Wearscar(cmd + " --help");
    EXPECT_EQ(h.status, 0) << cmd;
    EXPECT_NE(h.output.find("Usage: wearscar " + cmd + " "), std::string::npos)
        << h.output.substr(0, 300);
    const size_t examples = h.output.rfind("Examples:\n");
    ASSERT_NE(examples, std::string::npos) << cmd;
    // Two or three examples of this very command, and nothing after them.
    std::istringstream tail(h.output.substr(examples + 10));
    int n = 0;
    for (std::string l; std::getline(tail, l);) {
      if (l.empty()) continue;
      EXPECT_EQ(l.rfind("  wearscar " + cmd + " ", 0), 0u) << cmd << ": " << l;
      ++n;
    }
    EXPECT_GE(n, 2) << cmd;
    EXPECT_LE(n, 3) << cmd;
  }
}

TEST(Conventions, DiagnoseListsOnlyTheOptionsItUses) {
  const std::string h = Wearscar("diagnose --help").output;
  for (const char* unused : {"--max-excess",
                             "--max-cost",
                             "--lugre-fc",
                             "--no-lugre",
                             "--compare-cycles",
                             "--max-amplitude-ratio",
                             "--slope "}) {
    EXPECT_EQ(h.find(unused), std::string::npos) << unused;
  }
  for (const char* used :
       {"--spring", "--running-in", "--level-order", "--candidates", "--json"})
    EXPECT_NE(h.find(used), std::string::npos) << used;
}

TEST(Conventions, QuietJsonAndTheForceFileEitherWay) {
  const std::string dir = Simulated("modes");
  const std::string f = dir + "/B-RT-R.force.csv", s = dir + "/B-RT-R.scan.gsf";
  const CommandResult positional =
      Stdout("fuse " + f + " --scan " + s + " --running-in 10 --json");
  const CommandResult option =
      Stdout("fuse --force " + f + " --scan " + s + " --running-in 10 --json");
  ASSERT_EQ(positional.status, 0) << positional.output;
  ASSERT_EQ(option.status, 0) << option.output;
  const nlohmann::json a = ParseJson(positional.output),
                       b = ParseJson(option.output);
  ASSERT_TRUE(a.is_object()) << positional.output.substr(0, 500);
  ASSERT_TRUE(b.is_object()) << option.output.substr(0, 500);
  // The truth of B-RT-R: mu 0.15 falling to about 0.14 over 30 cycles.
  const double mu = a["comparison"]["mu_hat_force"]["mean"];
  EXPECT_NEAR(mu, 0.142, 0.01);
  EXPECT_EQ(a["comparison"], b["comparison"]);
  // Without -o: the summary, and it says nothing was written.
  const CommandResult text = Stdout("fuse " + f + " --running-in 10");
  EXPECT_NE(text.output.find("mu-hat, k from P"), std::string::npos);
  EXPECT_NE(text.output.find("nothing written (give -o DIR"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(dir + "/out"));
  // --quiet: nothing on stdout, the files all the same.
  const CommandResult quiet = Stdout("fuse " + f +
                                     " --running-in 10 --quiet "
                                     "--no-figures -o " +
                                     dir + "/out");
  EXPECT_EQ(quiet.status, 0);
  EXPECT_EQ(quiet.output, "");
  EXPECT_TRUE(fs::exists(dir + "/out/result.json"));
  EXPECT_EQ(Wearscar("fuse " + f + " --quiet --json").status, 2);
  // Every analysing command speaks JSON.
  for (const std::string& args : std::vector<std::string>{
           "force " + f,
           "scan " + s,
           "diagnose " + f + " --max-cycles 12",
           "audit " + dir + " --no-figures -o " + dir + "/audit"}) {
    const CommandResult j = Stdout(args + " --json");
    EXPECT_EQ(j.status, 0) << args;
    const nlohmann::json parsed = ParseJson(j.output);
    EXPECT_FALSE(parsed.is_discarded())
        << args << ": " << j.output.substr(0, 300);
  }
}

TEST(Conventions, CyclesAreNumberedFromOne) {
  const std::string dir = Simulated("cycles");
  const std::string out = dir + "/out";
  const CommandResult r = Wearscar(
      "fuse " + dir + "/B-RT-R.force.csv --scan " + dir +
      "/B-RT-R.scan.gsf --detail-cycle 1 --loops 2 --loops 30 --no-figures "
      "--compare-first 21 --compare-last 30 -o " +
      out);
  ASSERT_EQ(r.status, 0) << r.output;
  std::ifstream cycles(out + "/cycles.csv");
  std::string header, first, last;
  std::getline(cycles, header);
  std::getline(cycles, first);
  for (std::string l; std::getline(cycles, l);) last = l;
  EXPECT_EQ(first.rfind("1,", 0), 0u) << first;
  EXPECT_EQ(last.rfind("30,", 0), 0u) << last;
  const nlohmann::json j = ParseJson(Slurp(out + "/result.json"));
  EXPECT_EQ(j["comparison"]["first_cycle"], 21);
  EXPECT_EQ(j["comparison"]["last_cycle"], 30);
  EXPECT_EQ(j["lugre"]["cycle"], 1);
  EXPECT_EQ(j["options"]["scan"]["compare_first"], 21);
  std::ifstream detail(out + "/detail.csv");
  std::getline(detail, header);
  std::getline(detail, first);
  EXPECT_EQ(first.rfind("1,", 0), 0u) << first;
  // loops.csv holds cycles 2 and 30 only.
  std::ifstream loops(out + "/loops.csv");
  std::getline(loops, header);
  std::set<std::string> seen;
  for (std::string l; std::getline(loops, l);)
    seen.insert(l.substr(0, l.find(',')));
  EXPECT_EQ(seen, (std::set<std::string>{"2", "30"}));
  EXPECT_NE(r.output.find(", cycles 21-30 (as given); "), std::string::npos)
      << r.output;
  // Both windows' numbers: the quoted one and every cycle after running-in.
  EXPECT_NE(r.output.find("compared over cycles 21-30 (as given)"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("every cycle after running-in (3-30): mu-hat 0.1"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(
      Wearscar("fuse " + dir + "/B-RT-R.force.csv --detail-cycle 0").status, 2);
  // A cycle beyond the test is refused, named from 1.
  const CommandResult beyond =
      Wearscar("fuse " + dir + "/B-RT-R.force.csv --detail-cycle 31");
  EXPECT_EQ(beyond.status, 2);
  EXPECT_NE(beyond.output.find("the detail cycle is cycle 31, but the test "
                               "has 30 complete cycles; expected 1 to 30"),
            std::string::npos)
      << beyond.output;
  EXPECT_EQ(Wearscar("fuse " + dir + "/B-RT-R.force.csv --loops 31 -o " + dir +
                     "/none")
                .status,
            2);
  EXPECT_FALSE(fs::exists(dir + "/none/cycles.csv"));
}

TEST(Provenance, ResultsNameTheBuildTheInputsAndEveryOption) {
  const std::string dir = Simulated("provenance");
  const std::string f = dir + "/B-RT-R.force.csv", s = dir + "/B-RT-R.scan.gsf";
  const CommandResult r =
      Shell("SOURCE_DATE_EPOCH=86400 " + std::string(WEARSCAR_BINARY) +
            " fuse " + f + " --scan " + s +
            " --level-order 2 --band 0.15 --scan-window 21 --no-figures -o " +
            dir + "/out 2>&1");
  ASSERT_EQ(r.status, 0) << r.output;
  const nlohmann::json j = ParseJson(Slurp(dir + "/out/result.json"));
  const nlohmann::json& p = j["provenance"];
  EXPECT_EQ(p["date_utc"], "1970-01-02T00:00:00Z");
  const std::string version = Wearscar("version").output;
  EXPECT_NE(
      version.find(p["wearscar_version"].get<std::string>() + " (commit " +
                   p["git_commit"].get<std::string>() + ")"),
      std::string::npos)
      << version;
  ASSERT_EQ(p["inputs"].size(), 2u);
  // Sizes and checksums as coreutils sees them.
  for (int i = 0; i < 2; ++i) {
    const std::string path = i == 0 ? f : s;
    EXPECT_EQ(p["inputs"][i]["role"], i == 0 ? "force" : "scan");
    EXPECT_EQ(p["inputs"][i]["path"], path);
    EXPECT_EQ(p["inputs"][i]["bytes"], fs::file_size(path));
    const std::string sum = Shell("sha256sum " + path).output.substr(0, 64);
    EXPECT_EQ(p["inputs"][i]["sha256"], sum);
  }
  // Scan-side options as used.
  EXPECT_EQ(j["options"]["scan"]["level_order"], 2);
  EXPECT_EQ(j["options"]["scan"]["band_mm"], 0.15);
  EXPECT_EQ(j["options"]["scan"]["scan_window_samples"], 21);
  EXPECT_EQ(j["options"]["slope"], "both");
  EXPECT_EQ(j["force_file_read"]["units"],
            nlohmann::json({"s", "mm", "N", "N"}));
  // The audit table carries them per specimen.
  const CommandResult a =
      Wearscar("audit " + dir + " --no-figures -o " + dir + "/audit");
  ASSERT_EQ(a.status, 0) << a.output;
  const std::string csv = Slurp(dir + "/audit/summary.csv");
  EXPECT_NE(csv.find(p["inputs"][0]["sha256"].get<std::string>()),
            std::string::npos);
  EXPECT_NE(csv.find(",force_sha256,"), std::string::npos);
  EXPECT_NE(csv.find(",git_commit,date_utc\n"), std::string::npos);
  // The intervals: mu-hat's, the classic COFs' and Fig. 16's differences.
  for (const char* c : {",mu_hat_low,mu_hat_high,mu_hat_effective_cycles,",
                        ",mu_mean_low,mu_mean_high,",
                        ",mu_energy_low,mu_energy_high,",
                        ",mu_hat_minus_mu_energy_low,"})
    EXPECT_NE(csv.find(c), std::string::npos) << c;
}

TEST(Wear, ArchardRateFromTheTrackAndTheSlidingDistance) {
  const std::string dir = Simulated("wear");
  const CommandResult r =
      Wearscar("fuse " + dir + "/B-RT-R.force.csv --scan " + dir +
               "/B-RT-R.scan.gsf --no-figures -o " + dir + "/out");
  ASSERT_EQ(r.status, 0) << r.output;
  const nlohmann::json j = ParseJson(Slurp(dir + "/out/result.json"));
  const nlohmann::json& w = j["wear"];
  // 30 cycles of +-2.85 mm: 30 x 4 x 2.85 mm of sliding; the load 30 N.
  EXPECT_NEAR(w["sliding_distance_m"].get<double>(), 0.342, 0.342 * 0.005);
  EXPECT_NEAR(w["normal_load_n"].get<double>(), 30.0, 0.3);
  const double v = w["volume_mm3"];
  EXPECT_GT(v, 0.0);
  EXPECT_DOUBLE_EQ(w["specific_wear_rate_mm3_per_n_m"].get<double>(),
                   v / (w["normal_load_n"].get<double>() *
                        w["sliding_distance_m"].get<double>()));
  EXPECT_EQ(w["volume_mm3"], j["scan"]["track"]["volume_mm3"]);
  // Without a scan the force side stands and the rate is unknown (null).
  const CommandResult f = Stdout("force " + dir + "/B-RT-R.force.csv --json");
  const nlohmann::json fj = ParseJson(f.output);
  EXPECT_TRUE(fj["wear"]["specific_wear_rate_mm3_per_n_m"].is_null());
  EXPECT_NEAR(fj["wear"]["sliding_distance_m"].get<double>(), 0.342, 0.002);
}

TEST(Outputs, ARerunRemovesWhatTheEarlierRunWroteAndNothingElse) {
  const std::string dir = Simulated("rerun");
  const std::string out = dir + "/out";
  const std::string fuse = "fuse " + dir + "/B-RT-R.force.csv --scan " + dir +
                           "/B-RT-R.scan.gsf -o " + out;
  ASSERT_EQ(Wearscar(fuse).status, 0);
  // SVG by default; a rerun asking for PNG alone leaves no SVG behind.
  ASSERT_TRUE(fs::exists(out + "/fig08ab_scan_map.svg"));
  EXPECT_FALSE(fs::exists(out + "/fig08ab_scan_map.png"));
  ASSERT_EQ(Wearscar(fuse + " --figure-format png").status, 0);
  EXPECT_TRUE(fs::exists(out + "/fig08ab_scan_map.png"));
  EXPECT_EQ(Slurp(out + "/fig08ab_scan_map.png").substr(1, 3), "PNG");
  EXPECT_FALSE(fs::exists(out + "/fig08ab_scan_map.svg"));
  // The figures' sources are in a sub-folder; the map's data names the
  // track outline's columns.
  EXPECT_TRUE(fs::exists(out + "/figure-data/figures.gp"));
  EXPECT_EQ(
      Slurp(out + "/figure-data/fig08ab_scan_map.csv")
          .rfind("# track_outline: x_mm,y_mm where line = 0\nx_mm,y_mm\n", 0),
      0u);
  EXPECT_FALSE(fs::exists(out + "/figures_png.gp"));
  // A file of the user's, and a manifest line pointing outside the folder.
  std::ofstream(out + "/notes.txt") << "mine\n";
  std::ofstream(dir + "/outside.txt") << "mine too\n";
  std::ofstream(out + "/.wearscar-manifest", std::ios::app)
      << "fuse\t../outside.txt\n";
  ASSERT_EQ(Wearscar(fuse + " --no-figures").status, 0);
  EXPECT_FALSE(fs::exists(out + "/fig08ab_scan_map.png"));
  EXPECT_FALSE(fs::exists(out + "/fig08ab_scan_map.svg"));
  EXPECT_FALSE(fs::exists(out + "/figure-data"));
  EXPECT_TRUE(fs::exists(out + "/result.json"));
  EXPECT_TRUE(fs::exists(out + "/notes.txt"));
  EXPECT_TRUE(fs::exists(dir + "/outside.txt"));
  const std::string manifest = Slurp(out + "/.wearscar-manifest");
  EXPECT_EQ(manifest.find(".png"), std::string::npos) << manifest;
  EXPECT_EQ(manifest.find(".svg"), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("fuse\tresult.json\n"), std::string::npos)
      << manifest;
}

// Analysing simulated files into the folder that holds them: the inputs
// another command wrote there stay, whatever fuse removes of its own.
TEST(Outputs, AFuseIntoTheInputsFolderLeavesTheInputs) {
  const std::string dir = Simulated("samefolder");
  const std::string fuse = "fuse " + dir + "/B-RT-R.force.csv --scan " + dir +
                           "/B-RT-R.scan.gsf -o " + dir;
  ASSERT_EQ(Wearscar(fuse).status, 0);
  ASSERT_EQ(Wearscar(fuse + " --no-figures").status, 0);
  EXPECT_TRUE(fs::exists(dir + "/B-RT-R.force.csv"));
  EXPECT_TRUE(fs::exists(dir + "/B-RT-R.scan.gsf"));
  EXPECT_TRUE(fs::exists(dir + "/B-RT-R.truth.json"));
  EXPECT_FALSE(fs::exists(dir + "/fig07_loops.svg"));
  EXPECT_TRUE(fs::exists(dir + "/result.json"));
}

TEST(Outputs, ASimulateRerunDropsWhatItNoLongerWrites) {
  const std::string dir =
      Simulated("resimulate", "--case B-RT-R --case S-TL-L");
  std::ofstream(dir + "/notes.txt") << "mine\n";
  const CommandResult r = Wearscar(
      "simulate --case B-RT-R --cycles 20 --rate 1000 --scan-cols 64 "
      "--scan-rows 48 --scan-pitch 0.1 --formats csv -o " +
      dir);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir + "/B-RT-R.force.csv"));
  EXPECT_TRUE(fs::exists(dir + "/B-RT-R.truth.json"));
  EXPECT_FALSE(fs::exists(dir + "/B-RT-R.scan.gsf"));
  EXPECT_FALSE(fs::exists(dir + "/S-TL-L.force.csv"));
  EXPECT_TRUE(fs::exists(dir + "/notes.txt"));
}

// Every file under `dir` with its bytes, by path relative to it.
std::map<std::string, std::string> FilesUnder(const std::string& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file())
      files[fs::relative(e.path(), dir).string()] = Slurp(e.path().string());
  }
  return files;
}

// The row of `specimen` in summary.csv, by column name.
std::map<std::string, std::string> SummaryRow(const std::string& out,
                                              const std::string& specimen) {
  std::istringstream csv(Slurp(out + "/summary.csv"));
  std::string header, line;
  std::getline(csv, header);
  std::vector<std::string> names;
  std::istringstream h(header);
  for (std::string c; std::getline(h, c, ',');) names.push_back(c);
  while (std::getline(csv, line)) {
    if (line.rfind(specimen + ",", 0) != 0) continue;
    std::map<std::string, std::string> row;
    std::istringstream cells(line);  // the leading columns hold no comma
    std::string c;
    for (size_t i = 0; i < names.size() && std::getline(cells, c, ','); ++i)
      row[names[i]] = c;
    return row;
  }
  return {};
}

TEST(Outputs, AnAuditRerunOfOneSpecimenKeepsTheRestAndReplaceDropsThem) {
  const std::string dir =
      Simulated("rerun-audit", "--case B-RT-R --case S-TL-L --case B-TL-T");
  const std::string out = dir + "-audit";
  fs::remove_all(out);
  ASSERT_EQ(Wearscar("audit " + dir + " --no-figures -o " + out).status, 0);
  ASSERT_TRUE(fs::exists(out + "/S-TL-L/result.json"));
  fs::create_directories(out + "/my-notes");
  std::ofstream(out + "/my-notes/a.txt") << "mine\n";
  const auto before = FilesUnder(out);
  const auto b_rt_r = SummaryRow(out, "B-RT-R");
  // One specimen again, with another spring, from a folder of its own.
  const std::string one = dir + "-one";
  fs::remove_all(one);
  fs::create_directories(one);
  for (const char* f : {"B-RT-R.force.csv", "B-RT-R.scan.gsf"})
    fs::copy_file(dir + "/" + f, one + "/" + f);
  const CommandResult again =
      Wearscar("audit " + one + " --spring 14 --no-figures -o " + out);
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_NE(again.output.find("kept from the earlier audit in this folder: 2 "
                              "specimens (B-TL-T, S-TL-L)"),
            std::string::npos)
      << again.output;
  // Its folder and row changed; no other specimen's file did.
  const auto after = FilesUnder(out);
  for (const auto& [path, bytes] : before) {
    if (path.rfind("B-TL-T/", 0) == 0 || path.rfind("S-TL-L/", 0) == 0 ||
        path.rfind("my-notes/", 0) == 0) {
      ASSERT_TRUE(after.count(path)) << path;
      EXPECT_EQ(after.at(path), bytes) << path;
    }
  }
  EXPECT_NE(after.at("B-RT-R/result.json"), before.at("B-RT-R/result.json"));
  EXPECT_NE(Slurp(out + "/B-RT-R/result.json")
                .find("\"spring_used_n_per_mm\": "
                      "14.0"),
            std::string::npos);
  const auto rerun = SummaryRow(out, "B-RT-R");
  EXPECT_NE(rerun.at("mu_hat_mean"), b_rt_r.at("mu_hat_mean"));
  EXPECT_EQ(CountLines(Slurp(out + "/summary.csv")), 4);
  for (const char* kept : {"B-TL-T", "S-TL-L"}) {
    EXPECT_FALSE(SummaryRow(out, kept).empty()) << kept;
    EXPECT_NE(
        Slurp(out + "/report.html").find(std::string(kept) + "/report.html"),
        std::string::npos)
        << kept;
  }
  // --replace: the batch is this run's alone; a folder wearscar did not
  // write stays.
  ASSERT_EQ(
      Wearscar("audit " + one + " --replace --no-figures -o " + out).status, 0);
  EXPECT_FALSE(fs::exists(out + "/S-TL-L"));
  EXPECT_FALSE(fs::exists(out + "/B-TL-T"));
  EXPECT_TRUE(fs::exists(out + "/B-RT-R/result.json"));
  EXPECT_TRUE(fs::exists(out + "/my-notes/a.txt"));
  EXPECT_EQ(CountLines(Slurp(out + "/summary.csv")), 2);
}

// A lab's tree of the simulated B-RT-R and S-TL-L in `dir`, beside it.
std::string LabTree(const std::string& dir) {
  const std::string lab = dir + "-lab";
  fs::remove_all(lab);
  // lab/beech/B-RT-R.{force.csv,scan.gsf}: paired by name in a sub-folder;
  // lab/spruce/specimen7/{test.csv,surface.gsf}: one force file and one
  // scan, the specimen named after the folder.
  fs::create_directories(lab + "/beech");
  fs::create_directories(lab + "/spruce/specimen7");
  fs::copy_file(dir + "/B-RT-R.force.csv", lab + "/beech/B-RT-R.force.csv");
  fs::copy_file(dir + "/B-RT-R.scan.gsf", lab + "/beech/B-RT-R.scan.gsf");
  fs::copy_file(dir + "/S-TL-L.force.csv", lab + "/spruce/specimen7/test.csv");
  fs::copy_file(dir + "/S-TL-L.scan.gsf",
                lab + "/spruce/specimen7/surface.gsf");
  // lab/beech/extra_friction.csv: no scan of its name; the others have one.
  fs::copy_file(dir + "/S-TL-L.force.csv", lab + "/beech/extra_friction.csv");
  return lab;
}

// extra_friction.csv is a copy of specimen7's force file: both say so,
// naming the other, in the summary and in their result.json; B-RT-R,
// whose files are its own, does not.
void ExpectTheCopiesNameEachOther(const std::string& lab,
                                  const std::string& summary) {
  EXPECT_NE(summary.find("the force file is byte-identical to that of "
                         "specimen7 (SHA-256 "),
            std::string::npos)
      << summary;
  EXPECT_NE(summary.find("the force file is byte-identical to that of extra "
                         "(SHA-256 "),
            std::string::npos)
      << summary;
  const std::string copied =
      ParseJson(Slurp(lab + "/audit/extra/result.json"))["warnings"].dump();
  EXPECT_NE(copied.find("byte-identical to that of specimen7"),
            std::string::npos)
      << copied;
  EXPECT_EQ(Slurp(lab + "/audit/B-RT-R/result.json").find("byte-identical"),
            std::string::npos);
}

TEST(Audit, FindsSpecimensInSubFoldersAndSaysWhatItLookedFor) {
  const std::string dir = Simulated("tree", "--case B-RT-R --case S-TL-L");
  const std::string lab = LabTree(dir);
  const CommandResult dry = Wearscar("audit " + lab + " --dry-run");
  ASSERT_EQ(dry.status, 0) << dry.output;
  EXPECT_NE(dry.output.find("specimen7  spruce/specimen7/test.csv  "
                            "spruce/specimen7/surface.gsf"),
            std::string::npos)
      << dry.output;
  EXPECT_NE(dry.output.find("warning: force only (no scan: no scan of its "
                            "name in its folder)"),
            std::string::npos)
      << dry.output;
  EXPECT_FALSE(fs::exists(lab + "/audit"));  // a dry run writes nothing
  // An earlier output inside the tree is not searched.
  ASSERT_EQ(
      Wearscar("audit " + lab + " --no-figures -o " + lab + "/audit").status,
      0);
  const CommandResult r =
      Wearscar("audit " + lab + " --no-figures -o " + lab + "/audit");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("3 specimens: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("assumed for every specimen: spring S = 10.19 "
                          "N/mm, the default"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("B-RT-R: force + scan, mu-hat"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("extra: force only (no scan: no scan of its name "
                          "in its folder), mu-hat"),
            std::string::npos)
      << r.output;
  const std::string summary = Slurp(lab + "/audit/summary.csv");
  EXPECT_NE(summary.find(",pairing,"), std::string::npos);
  EXPECT_NE(summary.find("no scan paired, although other specimens of the "
                         "batch have one"),
            std::string::npos)
      << summary;
  EXPECT_TRUE(fs::exists(lab + "/audit/B-RT-R/result.json"));
  ExpectTheCopiesNameEachOther(lab, summary);
  const nlohmann::json j =
      ParseJson(Slurp(lab + "/audit/specimen7/result.json"));
  EXPECT_EQ(j["provenance"]["inputs"][1]["path"],
            lab + "/spruce/specimen7/surface.gsf");
  // Not recursive: nothing at the top, and the message says what it
  // looked for.
  const CommandResult none =
      Wearscar("audit " + lab + " --no-recursive -o " + lab + "/audit2");
  EXPECT_EQ(none.status, 2);
  EXPECT_NE(none.output.find(lab + ": no specimens found: looked for force "
                                   "exports"),
            std::string::npos)
      << none.output;
  EXPECT_NE(none.output.find("x3p, gsf"), std::string::npos) << none.output;
}

// Shards that do not merge: a copy in one shard and its original in the
// other name each other in their result.json as each shard writes it
// (the inputs shared are found before any specimen is analysed); the merge
// then writes the batch's tables with the same warnings and leaves every
// result.json as its shard wrote it.
TEST(Audit, SharedInputsAreInTheResultAsItIsFirstWrittenInEveryShard) {
  // A folder of its own: ctest runs the tests beside each other.
  const std::string dir = Simulated("shards", "--case B-RT-R --case S-TL-L");
  const std::string lab = LabTree(dir);
  const std::string out = lab + "/audit";
  for (const char* shard : {"1/2", "2/2"}) {
    const CommandResult r = Wearscar("audit " + lab + " --shard " + shard +
                                     " --no-merge --no-figures -o " + out);
    ASSERT_EQ(r.status, 0) << r.output;
  }
  std::map<std::string, std::string> written;
  for (const char* name : {"B-RT-R", "extra", "specimen7"})
    written[name] = Slurp(out + "/" + name + "/result.json");
  EXPECT_NE(written["extra"].find("byte-identical to that of specimen7"),
            std::string::npos);
  EXPECT_NE(written["specimen7"].find("byte-identical to that of extra"),
            std::string::npos);
  EXPECT_EQ(written["B-RT-R"].find("byte-identical"), std::string::npos);
  const CommandResult merged = Wearscar("audit --merge " + out);
  ASSERT_EQ(merged.status, 0) << merged.output;
  ExpectTheCopiesNameEachOther(lab, Slurp(out + "/summary.csv"));
  for (const auto& [name, before] : written)
    EXPECT_EQ(Slurp(out + "/" + name + "/result.json"), before) << name;
  // The copy analysed again alone (a manifest of it): its result.json names
  // the original the batch keeps, whose own stays as it was written.
  std::ofstream(lab + "/again.csv")
      << "specimen,force\nextra," << lab << "/beech/extra_friction.csv\n";
  std::error_code ec;
  fs::remove(out + "/extra/result.json", ec);
  const CommandResult again =
      Wearscar("audit " + lab + "/again.csv --no-figures -o " + out);
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_NE(Slurp(out + "/extra/result.json")
                .find("byte-identical to that of specimen7"),
            std::string::npos);
  EXPECT_EQ(Slurp(out + "/specimen7/result.json"), written["specimen7"]);
  ExpectTheCopiesNameEachOther(lab, Slurp(out + "/summary.csv"));
}

}  // namespace

namespace {

// The figure formats asked for, and only those, for each command's
// figures (here the diagnosis's residual map); a format that is none is a
// usage error naming what is expected.
TEST(Figures, AreDrawnInTheFormatsAskedFor) {
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "gnuplot is not installed (scripts/install-deps does)";
  const std::string dir = Simulated("formats");
  const std::string diagnose =
      "diagnose " + dir + "/B-RT-R.force.csv --max-cycles 12 -q -o ";
  ASSERT_EQ(Wearscar(diagnose + dir + "/svg").status, 0);
  EXPECT_EQ(Slurp(dir + "/svg/diagnosis_residual_map.svg").rfind("<?xml", 0),
            0u);
  // Each candidate tried says how its contribution differs between the
  // directions, beside the residual map's odd and even parts.
  const nlohmann::json d = ParseJson(Slurp(dir + "/svg/diagnosis.json"));
  ASSERT_FALSE(d["steps"].empty());
  std::map<std::string, std::string> parity;
  for (const auto& c : d["steps"][0]["tried"])
    parity[c["key"].get<std::string>()] = c["direction_parity"];
  EXPECT_EQ(parity["ploughing"], "odd");
  EXPECT_EQ(parity["q_lag"], "mixed");
  EXPECT_FALSE(fs::exists(dir + "/svg/diagnosis_residual_map.png"));
  ASSERT_EQ(Wearscar(diagnose + dir + "/png --figure-format png").status, 0);
  EXPECT_EQ(Slurp(dir + "/png/diagnosis_residual_map.png").substr(1, 3), "PNG");
  EXPECT_FALSE(fs::exists(dir + "/png/diagnosis_residual_map.svg"));
  const CommandResult bad =
      Wearscar(diagnose + dir + "/bad --figure-format jpg");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.output.find(
                "--figure-format: expected svg, png or svg,png; found 'jpg'"),
            std::string::npos)
      << bad.output;
}

// Growth-ring bands with a sharp edge (mu_variation 0.2, a triangle drive
// at 500 Hz): friction along the track is named, and a(x) is shown beside
// what was measured along the track, fuse's friction map in its 0.5 mm
// bins, relative to mu-hat: a(x) averaged over each bin follows the map's
// steady pattern (r = 0.99 here; 0.8 asked), the table and the figure's
// two panels (a(x) with the map above, the groove depth below) written.
TEST(Figures, FrictionAlongTheTrackIsShownBesideTheFrictionMap) {
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "gnuplot is not installed (scripts/install-deps does)";
  const std::string dir = ::testing::TempDir() + "/along-track";
  fs::remove_all(dir);
  ASSERT_EQ(
      Wearscar("simulate --case B-RT-R --triangle --rate 500 --cycles "
               "200 --effect mu_variation=0.2 --seed 1 --formats csv -o " +
               dir)
          .status,
      0);
  ASSERT_EQ(
      Wearscar("diagnose " + dir + "/B-RT-R.force.csv -q -o " + dir + "/d")
          .status,
      0);
  const nlohmann::json d = ParseJson(Slurp(dir + "/d/diagnosis.json"));
  ASSERT_TRUE(d.contains("friction_along_track")) << d["named"].dump();
  EXPECT_GE(d["friction_along_track"]["r_with_friction_map"].get<double>(),
            0.8);
  const std::string map = Slurp(dir + "/d/friction_map_along_track.csv");
  EXPECT_EQ(map.rfind("x_mm,forward_minus_1,reverse_minus_1\n", 0), 0u);
  EXPECT_GE(std::count(map.begin(), map.end(), '\n'), 10);
  const std::string gp = Slurp(dir + "/d/figure-data/diagnosis.gp");
  EXPECT_NE(gp.find("set multiplot layout 2,1"), std::string::npos);
  EXPECT_NE(gp.find("'friction_map_along_track.csv'"), std::string::npos);
  EXPECT_EQ(
      Slurp(dir + "/d/diagnosis_friction_along_track.svg").rfind("<?xml", 0),
      0u);
}

// The friction map is drawn from a float32 grid, one row of bins per
// cycle (forward): the same numbers as friction_map.csv's forward rows.
void ExpectTheMapsGridHoldsItsTable(const std::string& out) {
  std::ifstream csv(out + "/friction_map.csv");
  std::string row;
  std::getline(csv, row);
  std::vector<std::array<double, 4>> forward;  // cycle, x, raw, corrected
  std::set<double> bins;
  int map_cycles = 0;
  while (std::getline(csv, row)) {
    double c, d, x, raw, corrected;
    ASSERT_EQ(
        std::sscanf(
            row.c_str(), "%lf,%lf,%lf,%lf,%lf", &c, &d, &x, &raw, &corrected),
        5)
        << row;
    bins.insert(x);
    map_cycles = std::max(map_cycles, static_cast<int>(c));
    if (d > 0) forward.push_back({c, x, raw, corrected});
  }
  const std::string grid =
      Slurp(out + "/figure-data/friction_map_corrected.f32");
  ASSERT_EQ(grid.size(), 4 * bins.size() * map_cycles);
  ASSERT_GT(forward.size(), 10u);
  for (const auto& [c, x, raw, corrected] : forward) {
    const size_t b = std::distance(bins.begin(), bins.find(x));
    float v;
    std::memcpy(
        &v,
        grid.data() + 4 * ((static_cast<size_t>(c) - 1) * bins.size() + b),
        4);
    EXPECT_NEAR(v, corrected, 1e-6 * std::abs(corrected) + 1e-9);
  }
}

// Error bars: every cycle's mu-hat inside its 95% interval in cycles.csv,
// drawn as a band on Fig. 13; the test's mean inside its own.
void ExpectEachMuHatInsideItsInterval(const std::string& out,
                                      const std::string& gp,
                                      const nlohmann::json& j) {
  EXPECT_NE(gp.find("'95% interval, k from P'"), std::string::npos);
  std::ifstream table(out + "/cycles.csv");
  std::string line;
  std::getline(table, line);
  std::vector<std::string> header;
  for (std::stringstream h(line); std::getline(h, line, ',');)
    header.push_back(line);
  auto column = [&](const char* name) {
    return std::find(header.begin(), header.end(), name) - header.begin();
  };
  const auto mu_col = column("mu_hat_force"),
             low_col = column("mu_hat_force_low"),
             high_col = column("mu_hat_force_high");
  ASSERT_LT(high_col, static_cast<long>(header.size()));
  int rows = 0;
  for (std::string row; std::getline(table, row); ++rows) {
    std::vector<double> v;
    for (std::stringstream cells(row); std::getline(cells, line, ',');)
      v.push_back(std::stod(line));
    EXPECT_LT(v[low_col], v[mu_col]) << row;
    EXPECT_GT(v[high_col], v[mu_col]) << row;
    EXPECT_LT(v[high_col] - v[low_col], 0.01) << row;
  }
  EXPECT_GT(rows, 5);
  const auto& mu = j["comparison"]["mu_hat_force"];
  ASSERT_TRUE(mu["interval95"].is_array()) << mu.dump();
  EXPECT_LT(mu["interval95"][0].get<double>(), mu["mean"].get<double>());
  EXPECT_GT(mu["interval95"][1].get<double>(), mu["mean"].get<double>());
  EXPECT_GT(mu["effective_cycles"].get<double>(), 1.0);
  EXPECT_LE(mu["effective_cycles"].get<double>(), mu["count"].get<double>());
}

// The force command draws the force-side figures; scan draws the map.
void ExpectForceAndScanCommandsDraw(const std::string& dir) {
  ASSERT_EQ(
      Wearscar("force " + dir + "/B-RT-R.force.csv -o " + dir + "/f").status,
      0);
  for (const char* f : {"fig05_q_envelope.svg",
                        "fig07_loops.svg",
                        "fig13_mu_hat.svg",
                        "fig11_cost.svg"})
    EXPECT_TRUE(fs::exists(dir + "/f/" + f)) << f;
  EXPECT_FALSE(fs::exists(dir + "/f/fig08ab_scan_map.svg"));
  EXPECT_FALSE(fs::exists(dir + "/f/fig05_q_envelope.png"));
  ASSERT_EQ(
      Wearscar("scan " + dir + "/B-RT-R.scan.gsf -o " + dir + "/s").status, 0);
  EXPECT_TRUE(fs::exists(dir + "/s/scan_map.svg"));
  const std::string scan_gp = FigureScripts(dir + "/s");
  EXPECT_NE(scan_gp.find("cblabel 'height (um)'"), std::string::npos);
  // A 1 mm scale bar on the 7.6 mm wide map.
  EXPECT_NE(scan_gp.find("set label 1 '1 mm' at first"), std::string::npos);
}

// Figures that say what they show: the running-in marked, the minimum of
// J(mu) marked at the fitted mu-hat, the offset of P/S stated, labels
// drawn as written, the force command's and the scan command's figures.
TEST(Figures, SayWhatTheyShow) {
  const std::string dir = Simulated("figures");
  const std::string out = dir + "/out";
  const CommandResult r = Wearscar(
      "fuse " + dir + "/B-RT-R.force.csv --scan " + dir +
      "/B-RT-R.scan.gsf --running-in 7 --figure-format svg,png -o " + out);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("drew 15 figures (SVG and PNG)"), std::string::npos)
      << r.output;
  const std::string gp = FigureScripts(out);
  // Running-in shaded on Figs. 5, 6, 13, 14 and 15, in both formats.
  size_t marks = 0;
  for (size_t at = gp.find("'running-in (7 cycles)'"); at != std::string::npos;
       at = gp.find("'running-in (7 cycles)'", at + 1))
    ++marks;
  EXPECT_EQ(marks, 10u);
  const nlohmann::json j = ParseJson(Slurp(out + "/result.json"));
  // The minimum of J(mu) at the detail cycle's mu-hat (cycles.csv's last
  // row), and the P/S offset in the legend.
  std::ifstream cycles(out + "/cycles.csv");
  std::string last;
  for (std::string l; std::getline(cycles, l);) last = l;
  const double mu_last = std::stod(last.substr(last.find(',') + 1));
  char expected[64];
  std::snprintf(expected, sizeof expected, "k from P: mu-hat %.4f", mu_last);
  EXPECT_NE(gp.find(expected), std::string::npos) << expected;
  EXPECT_NE(gp.find("'P/S forward - "), std::string::npos);
  // Labels are drawn as written (delta_max is no subscript).
  EXPECT_EQ(gp.find(" enhanced"), std::string::npos);
  EXPECT_NE(gp.find("noenhanced"), std::string::npos);
  EXPECT_NE(gp.find("E_d / (4 P delta_max)"), std::string::npos);
  // The friction map and the track's history: their tables and figures.
  EXPECT_TRUE(fs::exists(out + "/fig_friction_map.png"));
  ExpectTheMapsGridHoldsItsTable(out);
  EXPECT_TRUE(fs::exists(out + "/fig_track_history.svg"));
  EXPECT_EQ(Slurp(out + "/friction_map.csv")
                .rfind("cycle,direction,x_mm,mu_raw,mu_corrected,n\n1,1,", 0),
            0u);
  EXPECT_EQ(Slurp(out + "/track_history.csv")
                .rfind("cycle,direction,x_mm,h_mm\n1,1,", 0),
            0u);
  EXPECT_TRUE(j["friction_map"]["spatial_sd_corrected"].is_number());
  EXPECT_EQ(j["track_history"]["bin_mm"], 0.1);
  // LuGre says whether its fit is physical.
  EXPECT_TRUE(j["lugre"]["physically_plausible"].is_boolean());
  ExpectEachMuHatInsideItsInterval(out, gp, j);
  ExpectForceAndScanCommandsDraw(dir);
}

// --scan-slope-history is recorded with the options and changes only the
// scan side: the force side's mu-hat stays, the scan side's moves.
TEST(Options, ScanSlopeHistoryIsRecordedAndMovesOnlyTheScanSide) {
  const std::string dir = Simulated("history", "--case S-RT-R");
  const std::string base = "fuse " + dir + "/S-RT-R.force.csv --scan " + dir +
                           "/S-RT-R.scan.gsf --no-figures -o ";
  ASSERT_EQ(Wearscar(base + dir + "/plain").status, 0);
  const CommandResult r = Wearscar(base + dir + "/hist --scan-slope-history");
  ASSERT_EQ(r.status, 0) << r.output;
  const nlohmann::json a = ParseJson(Slurp(dir + "/plain/result.json"));
  const nlohmann::json b = ParseJson(Slurp(dir + "/hist/result.json"));
  EXPECT_EQ(a["options"]["scan"]["scan_slope_history"], false);
  EXPECT_EQ(b["options"]["scan"]["scan_slope_history"], true);
  EXPECT_EQ(a["comparison"]["mu_hat_force"]["mean"],
            b["comparison"]["mu_hat_force"]["mean"]);
  EXPECT_NE(a["comparison"]["mu_hat_scan"]["mean"],
            b["comparison"]["mu_hat_scan"]["mean"]);
}

// No figure is embedded: each page shows the SVG files the audit drew
// by their paths relative to the page, every one of them once.
void ExpectEveryFigureShownOnce(const std::string& out) {
  const std::string index = Slurp(out + "/report.html");
  const std::string html = Slurp(out + "/B-RT-R/report.html");
  EXPECT_EQ(index.find("data:image"), std::string::npos);
  EXPECT_EQ(html.find("data:image"), std::string::npos);
  std::set<std::string> drawn, shown;
  for (const auto& e : fs::recursive_directory_iterator(out)) {
    if (e.path().extension() == ".svg")
      drawn.insert(fs::absolute(e.path()).lexically_normal().string());
  }
  const std::regex src(
      "<img loading=\"lazy\" decoding=\"async\" alt=\"[^\"]*\" "
      "src=\"([^\"]+)\">");
  for (const std::string& page :
       {std::string("report.html"), std::string("B-RT-R/report.html")}) {
    const std::string text = Slurp(out + "/" + page);
    const fs::path at = fs::absolute(fs::path(out) / page).parent_path();
    for (std::sregex_iterator m(text.begin(), text.end(), src), end; m != end;
         ++m)
      shown.insert((at / (*m)[1].str()).lexically_normal().string());
  }
  EXPECT_EQ(shown, drawn);
  EXPECT_GE(shown.size(), 14u);
}

// The report's numbers per specimen: mu-hat and J with both slopes side
// by side, wear, provenance.
TEST(Report, ShowsEachSpecimensNumbersAndWhereTheyCameFrom) {
  const std::string dir = Simulated("report");
  const std::string out = dir + "-audit";
  fs::remove_all(out);
  ASSERT_EQ(Wearscar("audit " + dir + " -o " + out).status, 0);
  // The specimen's numbers on its page, the conditions in the index.
  const std::string index = Slurp(out + "/report.html");
  const std::string html = Slurp(out + "/B-RT-R/report.html");
  const nlohmann::json j = ParseJson(Slurp(out + "/B-RT-R/result.json"));
  char jf[32], js[32], rate[32];
  std::snprintf(jf,
                sizeof jf,
                "<td>%.3f</td>",
                j["comparison"]["J_force"]["mean"].get<double>());
  std::snprintf(js,
                sizeof js,
                "<td>%.3f</td>",
                j["comparison"]["J_scan"]["mean"].get<double>());
  std::snprintf(rate,
                sizeof rate,
                "%.4g",
                j["wear"]["specific_wear_rate_mm3_per_n_m"].get<double>());
  EXPECT_NE(html.find(std::string("J (Eq. 6)</td>") + jf + js),
            std::string::npos)
      << jf << js;
  EXPECT_NE(html.find(rate), std::string::npos) << rate;
  EXPECT_NE(
      html.find(j["provenance"]["inputs"][0]["sha256"].get<std::string>()),
      std::string::npos);
  EXPECT_NE(html.find("made by wearscar "), std::string::npos);
  EXPECT_NE(html.find("Files: force " + dir + "/B-RT-R.force.csv; scan " + dir +
                      "/B-RT-R.scan.gsf"),
            std::string::npos);
  EXPECT_NE(index.find("<a href=\"B-RT-R/report.html\">B-RT-R</a>"),
            std::string::npos);
  char conditions[160];
  std::snprintf(conditions,
                sizeof conditions,
                "<td>%.2f</td><td>%.3g</td><td>%.3f</td>",
                j["wear"]["normal_load_n"].get<double>(),
                j["frequency_hz"].get<double>(),
                j["stroke_mm"].get<double>());
  EXPECT_NE(index.find(conditions), std::string::npos) << conditions;
  EXPECT_NEAR(j["frequency_hz"].get<double>(), 1.0, 0.01);  // the simulator's
  EXPECT_NEAR(
      j["mean_speed_mm_s"].get<double>(),
      2 * j["stroke_mm"].get<double>() * j["frequency_hz"].get<double>(),
      1e-9);
  // mu-hat's 95% interval beside its mean, in the table and the numbers.
  char iv[64];
  std::snprintf(iv,
                sizeof iv,
                "%.4f&ndash;%.4f",
                j["comparison"]["mu_hat_force"]["interval95"][0].get<double>(),
                j["comparison"]["mu_hat_force"]["interval95"][1].get<double>());
  EXPECT_NE(html.find(iv), std::string::npos) << iv;
  EXPECT_NE(index.find(iv), std::string::npos) << iv;
  EXPECT_NE(index.find("<th>its 95% interval</th>"), std::string::npos);
  // The batch figure of wear against mu-hat, from its own table.
  EXPECT_TRUE(fs::exists(out + "/audit_wear_vs_mu.svg"));
  ExpectEveryFigureShownOnce(out);
  const std::string wear = Slurp(out + "/wear_and_mu.csv");
  EXPECT_EQ(
      wear.rfind("specimen,mu_hat,mu_hat_sd,wear_rate_mm3_per_N_m,mu_hat_low,"
                 "mu_hat_high\nB-RT-R,",
                 0),
      0u)
      << wear;
}

// On a dead-weight rig with a depth channel, Fig. 8c-d names the profile
// it draws (the depth channel's), not a spring displacement P/S.
TEST(Figures, ADeadWeightsProfileIsNamedForItsChannel) {
  const std::string dir = ::testing::TempDir() + "/lab-dead-weight-figures";
  fs::remove_all(dir);
  ASSERT_EQ(Wearscar("simulate --case B-RT-R --rig dead-weight --cycles 30 "
                     "--rate 500 --scan-cols 256 --scan-rows 192 "
                     "--scan-pitch 0.03 --formats csv,gsf -o " +
                     dir)
                .status,
            0);
  const CommandResult r = Wearscar("fuse " + dir + "/B-RT-R.force.csv --scan " +
                                   dir + "/B-RT-R.scan.gsf -o " + dir + "/out");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string gp = FigureScripts(dir + "/out");
  EXPECT_NE(gp.find("the depth channel's profile and the aligned scan "
                    "profile (Fig. 8c-d)"),
            std::string::npos);
  EXPECT_NE(gp.find("'depth forward - "), std::string::npos);
  EXPECT_EQ(gp.find("P/S forward"), std::string::npos);
  EXPECT_EQ(gp.find("spring displacement"), std::string::npos);
  // No track history "from the spring" on a rig whose load is a weight.
  EXPECT_FALSE(fs::exists(dir + "/out/fig_track_history.svg"));
  EXPECT_EQ(gp.find("from the spring"), std::string::npos);
}

// The simulated test's rows as an Anton Paar TRB linear export writes
// them (tabs, decimal commas, the nominal load, depth in um), its
// symbols in UTF-8 or Latin-1.
std::string TrbExport(const std::string& dir, bool latin1) {
  std::string line;
  const std::string micro = latin1 ? "\xb5" : "\xc2\xb5";
  const std::string degree = latin1 ? "\xb0" : "\xc2\xb0";
  std::string text =
      "Anton Paar TRB3\tLinear reciprocating\nSample\tB-RT-R\n\n";
  text +=
      "Time [s]\tDistance [m]\tLaps\tSequence ID\tCycle ID\tMax Linear "
      "Speed [m/s]\tNominal Load [N]\t" +
      micro + "\tLinear Position [mm]\tFriction Force [N]\tTemperature [" +
      degree + "C]\tHumidity [%]\tPenetration Depth [" + micro + "m]\n";
  std::ifstream rows(dir + "/B-RT-R.force.csv");
  std::getline(rows, line);
  double distance = 0, previous = NAN;
  while (std::getline(rows, line)) {
    double t, x, q, p, d;
    if (std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf", &t, &x, &q, &p, &d) !=
        5)
      return "an unread row: " + line;
    if (std::isfinite(previous)) distance += std::abs(x - previous) / 1000;
    previous = x;
    std::string row = fmt::format(
        "{:.4f}\t{:.6f}\t{}\t1\t{}\t0.0179\t30\t{:.4f}\t{:.5f}\t{:.4f}\t23."
        "1\t"
        "45\t{:.3f}\n",
        t,
        distance,
        static_cast<int>(t),
        static_cast<int>(t),
        q / 30,
        x,
        q,
        1000 * d);
    std::replace(row.begin(), row.end(), '.', ',');
    text += row;
  }
  return text;
}

// An Anton Paar TRB linear export of a dead-weight test (its columns as
// the instrument writes them: tab separated, decimal commas, the nominal
// load as the only load, "µ" and "Penetration Depth [µm]" in UTF-8 or in
// Latin-1), made from a simulated test: read as the anton-paar layout, the
// nominal load said to be a set value and used as P, k from the depth
// channel, mu-hat within 0.002 of the simulator's truth.
TEST(Rigs, AnAntonPaarTrbExportOfADeadWeightTestIsReadWithItsDepth) {
  const std::string dir = ::testing::TempDir() + "/lab-trb";
  fs::remove_all(dir);
  ASSERT_EQ(Wearscar("simulate --case B-RT-R --rig dead-weight --cycles 120 "
                     "--rate 1000 --scan-cols 512 --scan-rows 384 "
                     "--scan-pitch 0.0148 --formats csv,gsf -o " +
                     dir)
                .status,
            0);
  std::ifstream in(dir + "/B-RT-R.force.csv");
  std::string line;
  std::getline(in, line);
  ASSERT_EQ(line, "time_s,x_mm,Q_N,P_N,depth_mm");
  for (const bool latin1 : {false, true}) {
    SCOPED_TRACE(latin1 ? "Latin-1" : "UTF-8");
    const std::string text = TrbExport(dir, latin1);
    const std::string file =
        dir + (latin1 ? "/trb_latin1.txt" : "/trb_utf8.txt");
    std::ofstream(file) << text;
    const CommandResult f = Wearscar("fuse " + file + " --scan " + dir +
                                     "/B-RT-R.scan.gsf --no-figures --json");
    ASSERT_EQ(f.status, 0) << f.output;
    const nlohmann::json j = ParseJson(f.output.substr(f.output.find('{')));
    ASSERT_TRUE(j.is_object()) << f.output;
    EXPECT_EQ(j["force_file_read"]["layout"], "anton-paar");
    EXPECT_EQ(j["profile"]["source"], "depth");
    EXPECT_NE(j["profile"]["why"].get<std::string>().find(
                  "'Penetration Depth' (read as a penetration"),
              std::string::npos)
        << j["profile"]["why"];
    bool said = false;
    for (const auto& w : j["warnings"])
      said |= w.get<std::string>().find(
                  "P is the column 'Nominal Load': the "
                  "load set on the instrument") != std::string::npos;
    EXPECT_TRUE(said) << j["warnings"];
    const nlohmann::json truth =
        nlohmann::json::parse(Slurp(dir + "/B-RT-R.truth.json"));
    const auto& c = j["comparison"];
    const int first = c["first_cycle"].get<int>() - 1,
              last = c["last_cycle"].get<int>() - 1;
    double mu = 0;
    for (int k = first; k <= last; ++k)
      mu += truth["mu_per_cycle"][k].get<double>();
    mu /= last - first + 1;
    EXPECT_NEAR(c["mu_hat_force"]["mean"].get<double>(), mu, 0.002);
    EXPECT_TRUE(j["verdict"]["explained"].get<bool>()) << j["verdict"];
  }
}

}  // namespace
