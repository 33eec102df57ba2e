#include "wearscar/fusion/pairing.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "common/compress.h"
#include "wearscar/fusion/batch.h"
#include "wearscar/fusion/provenance.h"
#include "wearscar/scan/gsf.h"

namespace wearscar::fusion {
namespace {

namespace fs = std::filesystem;

// A small height map: the pairing looks at names and the first bytes only.
scan::HeightMap TinyMap() {
  scan::HeightMap m;
  m.Resize(4, 5);
  m.height_mm.setConstant(0.01f);
  m.valid.setConstant(1);
  m.dx_mm = m.dy_mm = 0.01;
  return m;
}

class LabFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    // One folder per test: ctest runs them at once.
    dir_ = ::testing::TempDir() + "/pairing-lab-" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  // A force export (its content is not read by the pairing).
  void Force(const std::string& name) {
    fs::create_directories(fs::path(dir_ + "/" + name).parent_path());
    std::ofstream(dir_ + "/" + name) << "time_s,x_mm,Q_N,P_N\n0,0,0,30\n";
  }
  void Gsf(const std::string& name) {
    fs::create_directories(fs::path(dir_ + "/" + name).parent_path());
    scan::WriteGsf(TinyMap(), dir_ + "/" + name);
  }
  void KeyenceCsv(const std::string& name) {
    scan::WriteKeyenceCsv(TinyMap(), dir_ + "/" + name);
  }
  // specimen -> "force | scan | error-or-reason" with file names only.
  std::map<std::string, std::string> Pairs() const {
    std::map<std::string, std::string> out;
    for (const Specimen& s : PairFolder(dir_, "[BS]-(RT|RL|TL)-[RTL]", true)) {
      auto file = [](const std::string& p) {
        return p.empty() ? std::string("-") : fs::path(p).filename().string();
      };
      out[s.name] = file(s.force) + " | " + file(s.scan) + " | " +
                    (s.error.empty() ? s.no_scan : "ERROR " + s.error);
    }
    return out;
  }
  std::string dir_;
};

// Seven naming styles, sub-folders with repeated names, a force-only and a
// scan-only test, and a tie: each pairs as README says, and what is left
// is said, never guessed.
// Replicates in the paper's own naming pair by their whole names (the
// name pattern matches all of them alike); a force file and a scan whose
// names share only the pattern's match still pair by it; an instrument's
// name in a second export of the same test is no specimen of its own.
TEST_F(LabFolder, ReplicatesInThePapersNamingPair) {
  for (const char* rep : {"rep1", "rep2"}) {
    Force(std::string("B-RT-R_") + rep + "_force.csv");
    Gsf(std::string("B-RT-R_") + rep + "_scan.gsf");
  }
  Force("run07_S-TL-L_force.csv");
  Gsf("S-TL-L_height.gsf");
  Force("B-RL-L.force.csv");
  Force("B-RL-L.rtec.csv");
  Gsf("B-RL-L.scan.gsf");
  const std::map<std::string, std::string> p = Pairs();
  ASSERT_EQ(p.size(), 4u);
  EXPECT_EQ(p.at("B-RT-R_rep1"),
            "B-RT-R_rep1_force.csv | B-RT-R_rep1_scan.gsf | ");
  EXPECT_EQ(p.at("B-RT-R_rep2"),
            "B-RT-R_rep2_force.csv | B-RT-R_rep2_scan.gsf | ");
  EXPECT_EQ(p.at("S-TL-L"), "run07_S-TL-L_force.csv | S-TL-L_height.gsf | ");
  EXPECT_EQ(p.at("B-RL-L"), "B-RL-L.force.csv | B-RL-L.scan.gsf | ");
}

TEST_F(LabFolder, PairsHowLabsNameFiles) {
  Force("oak_30N_run01.csv");  // no role word: the other file says height
  KeyenceCsv("oak_30N_run01_height.csv");
  Force("pine_30N_run02_force.csv");  // the scan's name says nothing:
  KeyenceCsv("pine_30N_run02.csv");   // its content is a Keyence VR CSV
  Force("c_force.csv");
  KeyenceCsv("c_Height.csv");  // case
  Force("Force-Beech-3.txt");  // role words before the name
  Gsf("SCAN_beech_3.gsf");
  Force("ash_7.csv");  // one name extends the other
  Gsf("ash_7_20x_topo.gsf");
  Force("B-RT-R.force.csv");  // the paper's names
  Gsf("B-RT-R.scan.gsf");
  Force("lonely_cof.csv");  // force only
  Gsf("elm_9_height.gsf");  // scan only
  Force("birch.csv");       // two scans match one force file equally
  Gsf("birch_1_map.gsf");
  Gsf("birch_2_map.gsf");
  Force("run1/oak_01.csv");  // one name in two folders
  Gsf("run1/oak_01_surface.gsf");
  Force("run2/oak_01.csv");
  Gsf("run2/oak_01_surface.gsf");
  Force("spruce7/test.csv");  // a folder of one force file and one scan
  Gsf("spruce7/surface.gsf");

  const std::map<std::string, std::string> p = Pairs();
  EXPECT_EQ(p.at("oak_30N_run01"),
            "oak_30N_run01.csv | oak_30N_run01_height.csv | ");
  EXPECT_EQ(p.at("pine_30N_run02"),
            "pine_30N_run02_force.csv | pine_30N_run02.csv | ");
  EXPECT_EQ(p.at("c"), "c_force.csv | c_Height.csv | ");
  EXPECT_EQ(p.at("Beech-3"), "Force-Beech-3.txt | SCAN_beech_3.gsf | ");
  EXPECT_EQ(p.at("ash_7"), "ash_7.csv | ash_7_20x_topo.gsf | ");
  EXPECT_EQ(p.at("B-RT-R"), "B-RT-R.force.csv | B-RT-R.scan.gsf | ");
  EXPECT_EQ(p.at("run1/oak_01"), "oak_01.csv | oak_01_surface.gsf | ");
  EXPECT_EQ(p.at("run2/oak_01"), "oak_01.csv | oak_01_surface.gsf | ");
  EXPECT_EQ(p.at("spruce7"), "test.csv | surface.gsf | ");
  EXPECT_EQ(p.at("lonely"),
            "lonely_cof.csv | - | no scan's name matches (unpaired scans "
            "here: elm_9_height.gsf)");
  EXPECT_EQ(p.at("elm_9"),
            "- | elm_9_height.gsf | ERROR no force file for the scan "
            "elm_9_height.gsf: none of the unpaired force files here "
            "(birch.csv, lonely_cof.csv) matches its name; expected a force "
            "file named "
            "like it (or a manifest)");
  EXPECT_EQ(p.at("birch"),
            "birch.csv | - | its name matches 2 scans equally: "
            "birch_1_map.gsf, birch_2_map.gsf");
  EXPECT_NE(p.at("birch_1").find("ERROR the scans birch_1_map.gsf, "
                                 "birch_2_map.gsf match the force file "
                                 "birch.csv equally"),
            std::string::npos)
      << p.at("birch_1");
  EXPECT_EQ(p.size(), 14u);

  // Force-only specimens of a batch with scans are a warning; the table
  // says so.
  const std::vector<Specimen> all =
      PairFolder(dir_, "[BS]-(RT|RL|TL)-[RTL]", true);
  for (const Specimen& s : all) {
    EXPECT_EQ(s.scan_expected, s.name == "lonely" || s.name == "birch")
        << s.name;
  }
  const std::string table = PairingTable(all, dir_);
  // One line per specimen, paths relative to the folder.
  const size_t at = table.find("\nrun2/oak_01 ");
  ASSERT_NE(at, std::string::npos) << table;
  const std::string line = table.substr(at + 1, table.find('\n', at + 1) - at);
  EXPECT_NE(line.find(" run2/oak_01.csv "), std::string::npos) << line;
  EXPECT_NE(line.find(" run2/oak_01_surface.gsf"), std::string::npos) << line;
  EXPECT_NE(table.find("warning: force only (no scan: no scan's name "
                       "matches (unpaired scans here: elm_9_height.gsf))"),
            std::string::npos)
      << table;
  EXPECT_EQ(table.substr(0, 8), "specimen");
}

TEST_F(LabFolder, TwoForceFilesForOneNameAreATie) {
  Force("maple_1_force.csv");
  Force("maple_1_friction.csv");
  Gsf("maple_1.gsf");
  const std::map<std::string, std::string> p = Pairs();
  ASSERT_EQ(p.size(), 1u);
  EXPECT_NE(p.at("maple_1").find("ERROR two force files match 'maple_1': "
                                 "maple_1_force.csv and "
                                 "maple_1_friction.csv; expected one"),
            std::string::npos)
      << p.at("maple_1");
}

TEST_F(LabFolder, AForceOnlyBatchWarnsOfNothing) {
  Force("a_force.csv");
  Force("b_force.csv");
  for (const Specimen& s : PairFolder(dir_, "^$x", false)) {
    EXPECT_FALSE(s.scan_expected) << s.name;
    EXPECT_EQ(s.Pairing(), "force only (no scan: no scan in its folder)");
  }
}

// Compressed files pair by the name under their .gz or .zst; a compressed
// text map is told from a force export by its content like a plain one.
TEST_F(LabFolder, CompressedFilesPairByTheNameUnderTheSuffix) {
  Force("oak_02.csv");
  KeyenceCsv("oak_02_tmp.csv");
  const auto pack = [&](const std::string& from, const std::string& to) {
    std::ifstream in(dir_ + "/" + from, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)),
                            std::istreambuf_iterator<char>());
    std::ofstream(dir_ + "/" + to, std::ios::binary)
        << (to.back() == 'z' ? packing::Gzip(bytes) : packing::Zstd(bytes));
    fs::remove(dir_ + "/" + from);
  };
  pack("oak_02.csv", "oak_02.csv.gz");
  pack("oak_02_tmp.csv", "oak_02_profile.csv.zst");
  Force("ash_3_force.csv");
  Gsf("ash_3_tmp.gsf");
  pack("ash_3_tmp.gsf", "ash_3.gsf.gz");
  const std::map<std::string, std::string> p = Pairs();
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p.at("oak_02"), "oak_02.csv.gz | oak_02_profile.csv.zst | ");
  EXPECT_EQ(p.at("ash_3"), "ash_3_force.csv | ash_3.gsf.gz | ");
  EXPECT_EQ(SpecimenName("lab/oak_02_force.csv.gz"), "oak_02");
}

// Labs name files in their own language, in any case: the role words of
// German, French and Spanish pair as the English ones do (accented
// capitals included), and are left out of the specimen's name.
TEST_F(LabFolder, PairsFilesNamedInGermanFrenchAndSpanish) {
  Force("Probe 7 Reibung.csv");
  KeyenceCsv("Probe 7 Oberfläche.csv");
  Force("PROBE 8 KRAFT.csv");
  KeyenceCsv("PROBE 8 OBERFLÄCHE.csv");
  Force("Probe_9_Reibkraft.csv");
  Gsf("Probe_9_Höhe.gsf");
  Force("echantillon-3-frottement.csv");
  KeyenceCsv("echantillon-3-hauteur.csv");
  Force("muestra_4_fricción.csv");
  KeyenceCsv("muestra_4_superficie.csv");
  Force("Muestra_5_Fuerza.csv");
  KeyenceCsv("Muestra_5_Perfil.csv");
  const std::map<std::string, std::string> p = Pairs();
  ASSERT_EQ(p.size(), 6u);
  EXPECT_EQ(p.at("Probe 7"), "Probe 7 Reibung.csv | Probe 7 Oberfläche.csv | ");
  EXPECT_EQ(p.at("PROBE 8"), "PROBE 8 KRAFT.csv | PROBE 8 OBERFLÄCHE.csv | ");
  EXPECT_EQ(p.at("Probe_9"), "Probe_9_Reibkraft.csv | Probe_9_Höhe.gsf | ");
  EXPECT_EQ(p.at("echantillon-3"),
            "echantillon-3-frottement.csv | echantillon-3-hauteur.csv | ");
  EXPECT_EQ(p.at("muestra_4"),
            "muestra_4_fricción.csv | muestra_4_superficie.csv | ");
  EXPECT_EQ(p.at("Muestra_5"),
            "Muestra_5_Fuerza.csv | Muestra_5_Perfil.csv | ");
}

// An analysis's output folder is skipped and named with why; a folder of
// `wearscar simulate` (inputs) is searched, a hidden one skipped quietly;
// output_folders searches them all.
TEST_F(LabFolder, SaysWhichFoldersItSkipped) {
  Force("sim/oak_1_force.csv");
  Gsf("sim/oak_1.gsf");
  std::ofstream(dir_ + "/sim/.wearscar-manifest")
      << "simulate\toak_1_force.csv\nsimulate\toak_1.gsf\n";
  Force("out/ash_2_force.csv");
  std::ofstream(dir_ + "/out/.wearscar-manifest")
      << "fuse\tresult.json\naudit\tsummary.csv\n";
  Force(".cache/elm_3_force.csv");
  std::vector<std::string> skipped;
  std::vector<Specimen> found = PairFolder(dir_, "^$x", true, false, &skipped);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].name, "oak_1");
  EXPECT_EQ(skipped,
            std::vector<std::string>{"out/ (written by wearscar audit, fuse)"});
  skipped.clear();
  found = PairFolder(dir_, "^$x", true, true, &skipped);
  EXPECT_EQ(found.size(), 2u);  // ash_2 too; the hidden folder never
  EXPECT_TRUE(skipped.empty());
}

TEST(SpecimenName, LeavesOutRoleWordsAndTheirSeparators) {
  EXPECT_EQ(SpecimenName("data/B-RT-R.force.csv"), "B-RT-R");
  EXPECT_EQ(SpecimenName("oak_30N_run01_height.csv"), "oak_30N_run01");
  EXPECT_EQ(SpecimenName("Friction-oak 3.txt"), "oak 3");
  EXPECT_EQ(SpecimenName("force.csv"), "force");  // nothing else: the stem
  EXPECT_EQ(SpecimenName("sample_1.5N.csv"), "sample_1.5N");
}

// Inputs shared before any specimen is analysed: of three scans of one
// size (a scanner's exports of one field), two byte-identical and one that
// differs from them only in its middle, the copies name each other and the
// third names none; an earlier specimen's input (its provenance's size and
// SHA-256) is named too, and a row of a specimen analysed again is not.
TEST_F(LabFolder, SharedInputsAreFoundBeforeTheAnalysisByContentNotSize) {
  std::string bytes(300 * 1024, 'a');
  auto write = [&](const std::string& name, const std::string& content) {
    std::ofstream(dir_ + "/" + name, std::ios::binary) << content;
    return dir_ + "/" + name;
  };
  auto specimen = [&](const std::string& name, const std::string& scan) {
    Specimen s;
    s.name = name;
    s.force = write(name + ".csv", name);
    s.scan = write(name + ".gsf", scan);
    return s;
  };
  std::string middle = bytes;
  middle[150 * 1024] = 'b';
  const std::vector<Specimen> mine = {specimen("one", bytes),
                                      specimen("two", bytes),
                                      specimen("three", middle)};
  auto found = SharedInputsBefore(mine, {}, {});
  ASSERT_EQ(found.size(), 2u);
  ASSERT_EQ(found["one"].size(), 1u);
  EXPECT_EQ(found["one"][0].rfind("the scan file is byte-identical to that "
                                  "of two (SHA-256 ",
                                  0),
            0u)
      << found["one"][0];
  EXPECT_EQ(found.count("three"), 0u);
  // The third as an earlier run analysed it, under another name, beside a
  // new copy of it; and a row of "one" (analysed again now) is not read.
  auto row = [&](const std::string& name) -> nlohmann::json {
    return {{"specimen", name},
            {"provenance",
             {{"inputs",
               {{{"role", "scan"},
                 {"bytes", middle.size()},
                 {"sha256", Sha256OfFile(dir_ + "/three.gsf")}}}}}}};
  };
  const nlohmann::json earlier = row("old"), again = row("one");
  found = SharedInputsBefore(
      {specimen("four", middle), mine[0]}, {}, {earlier, again});
  ASSERT_EQ(found["four"].size(), 1u);
  EXPECT_NE(found["four"][0].find("byte-identical to that of old (SHA-256"),
            std::string::npos)
      << found["four"][0];
}

}  // namespace
}  // namespace wearscar::fusion
