// wearscar::fusion::Table: the CSV every table of a test is written as.
#include "wearscar/fusion/products.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "common/simulated.h"
#include "wearscar/force/read_force.h"
#include "wearscar/fusion/batch.h"
#include "wearscar/fusion/error.h"
#include "wearscar/fusion/provenance.h"
#include "wearscar/scan/gsf.h"

namespace wearscar::fusion {
namespace {

// printf's %.8g, the format the tables promise; empty for NaN and
// infinities.
std::string PrintfCell(double v) {
  if (!std::isfinite(v)) return "";
  char cell[64];
  std::snprintf(cell, sizeof cell, "%.8g", v);
  return cell;
}

TEST(Table, EveryCellIsPrintfsEightSignificantDigits) {
  std::vector<double> values = {
      0.0,       -0.0,         1.0,
      -1.0,      7.0,          600.0,
      -2.0,      99999999.0,   -99999999.0,
      1e8,       -1e8,         123456789.0,
      1e15,      0.5,          -2.85,
      1e-7,      3.0000000001, 2.9999999999,
      0.1 + 0.2, std::nan(""), std::numeric_limits<double>::infinity()};
  std::mt19937_64 random(16);
  std::uniform_real_distribution<double> exponent(-12, 12);
  for (int i = 0; i < 2000; ++i) {
    const double v = std::pow(10.0, exponent(random)) * (i % 2 ? 1 : -1);
    values.push_back(v);
    values.push_back(std::round(v));
  }
  Table t;
  t.columns = {"a_mm", "b_N"};
  std::string expected = "a_mm,b_N\n";
  for (size_t i = 0; i + 1 < values.size(); i += 2) {
    t.rows.push_back({values[i], values[i + 1]});
    expected += PrintfCell(values[i]) + "," + PrintfCell(values[i + 1]) + "\n";
  }
  EXPECT_EQ(t.ToCsv(), expected);
  // In pieces (a large table's, formatted apart): the header with the
  // first, joined they are the whole; a range past the end is empty.
  const std::size_t n = t.rows.size();
  EXPECT_EQ(t.ToCsv(0, 7) + t.ToCsv(7, 700) + t.ToCsv(700, n), expected);
  EXPECT_EQ(t.ToCsv(3, 3), "");
  EXPECT_EQ(t.ToCsv(n, n + 5), "");
  EXPECT_EQ(t.ToCsv(0, 0), "a_mm,b_N\n");
}

// FIPS 180-2's "abc", and 3 MB given in uneven pieces against the whole
// at once (the reader hands its blocks as it reads them).
TEST(Sha256, PiecesGiveTheDigestOfTheWhole) {
  Sha256 abc;
  abc.Update("abc", 3);
  EXPECT_EQ(abc.Hex(),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  std::string bytes(3 << 20, '\0');
  std::mt19937 random(3);
  for (char& c : bytes) c = static_cast<char>(random());
  Sha256 whole, pieces;
  whole.Update(bytes.data(), bytes.size());
  for (size_t at = 0, step = 1; at < bytes.size();
       at += step, step = step * 3 + 1)
    pieces.Update(bytes.data() + at, std::min(step, bytes.size() - at));
  EXPECT_EQ(pieces.Hex(), whole.Hex());
}

// A file's checksum, mapped (a file with bytes) or read (an empty one,
// which cannot be mapped): FIPS 180-2's "abc" and the empty message's.
TEST(Sha256, OfAFileAndOfAnEmptyOne) {
  const std::string dir = ::testing::TempDir();
  std::FILE* f = std::fopen((dir + "/wearscar-abc.txt").c_str(), "wb");
  ASSERT_NE(f, nullptr);
  std::fputs("abc", f);
  std::fclose(f);
  f = std::fopen((dir + "/wearscar-empty.txt").c_str(), "wb");
  ASSERT_NE(f, nullptr);
  std::fclose(f);
  EXPECT_EQ(Sha256OfFile(dir + "/wearscar-abc.txt"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(Sha256OfFile(dir + "/wearscar-empty.txt"),
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_THROW(Sha256OfFile(dir + "/wearscar-no-such-file"), FusionError);
}

// A specimen analysed on the caller's thread alone (a batch whose workers
// fill the cores) takes its force file's checksum from the reader's first
// pass; with threads, on a thread of its own beside the read. Either way
// the record and the provenance hold the file's SHA-256.
TEST(Provenance, TheChecksumTakenWhileReadingIsTheFilesOwn) {
  samples::SimulationOptions o = samples::PaperCase("B-RT-R", false);
  o.cycles = 20;
  const sim::SimulatedTest t = sim::Simulate(o);
  const std::string path =
      ::testing::TempDir() + "/wearscar-provenance.force.csv";
  force::WriteForceCsv(t.record, path);
  std::ifstream in(path, std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(in),
                          std::istreambuf_iterator<char>()};
  Sha256 whole;
  whole.Update(bytes.data(), bytes.size());
  const std::string sum = whole.Hex();
  EXPECT_EQ(Sha256OfFile(path), sum);
  FuseOptions threads, alone;
  alone.parallel = false;
  Specimen s;
  s.name = "B-RT-R";
  s.force = path;
  const SpecimenAnalysis a = AnalyzeSpecimen(s, {}, {}, alone);
  const SpecimenAnalysis b = AnalyzeSpecimen(s, {}, {}, threads);
  EXPECT_EQ(a.record.metadata.sha256, sum);
  EXPECT_EQ(b.record.metadata.sha256, sum);
  for (const SpecimenAnalysis* x : {&a, &b}) {
    const Provenance p = TestProvenance(x->record, x->result);
    ASSERT_EQ(p.inputs.size(), 1u);
    EXPECT_EQ(p.inputs[0].sha256, sum);
    EXPECT_EQ(p.inputs[0].bytes, std::filesystem::file_size(path));
  }
  EXPECT_EQ(a.result.ForceFits().mu_hat.mean, b.result.ForceFits().mu_hat.mean);
  std::remove(path.c_str());
}

// With threads and a scan, the scan is read on the checksum's thread once
// the checksum is taken: the checksum is still the file's, the scan's
// analysis the one made on the caller's thread, an unreadable scan fails
// the specimen, and a bad force file is said before a bad scan.
TEST(Provenance, AScanReadAfterTheChecksumChangesNothing) {
  samples::SimulationOptions o = samples::PaperCase("B-RT-R", false);
  o.cycles = 20;
  o.scan_cols = 256;
  o.scan_rows = 192;
  o.scan_pitch_mm = 4 * 0.007413;
  const sim::SimulatedTest t = sim::Simulate(o);
  const std::string dir = ::testing::TempDir();
  Specimen s;
  s.name = "B-RT-R";
  s.force = dir + "/wearscar-scan-after-sum.force.csv";
  s.scan = dir + "/wearscar-scan-after-sum.gsf";
  force::WriteForceCsv(t.record, s.force);
  scan::WriteGsf(t.scan, s.scan);
  FuseOptions threads, alone;
  alone.parallel = false;
  const SpecimenAnalysis a = AnalyzeSpecimen(s, {}, {}, alone);
  const SpecimenAnalysis b = AnalyzeSpecimen(s, {}, {}, threads);
  EXPECT_EQ(b.record.metadata.sha256, Sha256OfFile(s.force));
  EXPECT_EQ(a.record.metadata.sha256, b.record.metadata.sha256);
  ASSERT_TRUE(a.result.scan.has_value());
  ASSERT_TRUE(b.result.scan.has_value());
  ASSERT_EQ(a.result.ScanSlopeFits().cycles.size(),
            b.result.ScanSlopeFits().cycles.size());
  for (size_t c = 0; c < a.result.ScanSlopeFits().cycles.size(); ++c)
    EXPECT_EQ(a.result.ScanSlopeFits().cycles[c].mu_hat,
              b.result.ScanSlopeFits().cycles[c].mu_hat);
  auto error_of = [&](const Specimen& x) {
    try {
      AnalyzeSpecimen(x, {}, {}, threads);
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  Specimen bad_scan = s;
  bad_scan.scan = dir + "/wearscar-no-such-scan.gsf";
  EXPECT_NE(error_of(bad_scan).find("wearscar-no-such-scan.gsf"),
            std::string::npos)
      << error_of(bad_scan);
  Specimen both_bad = bad_scan;
  both_bad.force = dir + "/wearscar-no-such-force.csv";
  EXPECT_NE(error_of(both_bad).find("wearscar-no-such-force.csv"),
            std::string::npos)
      << error_of(both_bad);
  std::remove(s.force.c_str());
  std::remove(s.scan.c_str());
}

}  // namespace
}  // namespace wearscar::fusion
