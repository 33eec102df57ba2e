#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "wearscar/force/force_record.h"
#include "wearscar/fusion/diagnose.h"
#include "wearscar/fusion/fuse.h"
#include "wearscar/fusion/provenance.h"

namespace wearscar::fusion {

// A table of numbers whose column names carry their units ("x_mm", "Q_N",
// "mu_hat_force"); non-finite values are empty cells in CSV.
struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  std::string ToCsv() const;
};

// What the products of one test hold besides the per-cycle table.
struct ProductOptions {
  // Cycles (0-based) whose hysteresis loops go to loops.csv; empty = the
  // first, third, eleventh and last (those that exist).
  std::vector<int> loop_cycles;
  // Cycle of the slopes, the reconstruction of Q, J(mu) and LuGre; -1 =
  // the result's detail cycle.
  int detail_cycle = -1;
  // Points of J(mu) over the fit's mu interval (paper Fig. 11).
  int cost_curve_points = 201;
  // result.json's "provenance": this build, the date, and the size and
  // SHA-256 of every input file (TestProvenance).
  bool provenance = true;

  bool IsValid(std::string* why) const;
};

// Everything `wearscar fuse` writes for one test: the tables (cycles.csv,
// loops.csv, friction_map.csv, detail.csv, cost_curve.csv; with a scan
// profiles.csv and centreline.csv; with LuGre lugre.csv) and result.json.
struct TestProducts {
  std::vector<std::pair<std::string, Table>> tables;  // file name, table
  nlohmann::json result;  // result.json (scan.json for a map alone)
  std::string result_name = "result.json";

  // File name and contents of every product, the JSON summary last.
  std::vector<std::pair<std::string, std::string>> Files() const;
  // The JSON summary's text as Files() gives it.
  std::string ResultText() const;
};

// The columns of cycles.csv, and the 1-based index of one of them (for
// plotting programs); -1 for a name that is not a column.
const std::vector<std::string>& CycleColumns();
int CycleColumn(const std::string& name);

// The summary of one test (result.json; also a row of an audit's table):
// inputs, every option that shaped the analysis, running-in, statistics
// after running-in, the comparison of the slopes, the scan's levelling,
// track and alignment, LuGre, the verdict and the warnings.
// With a provenance, its "provenance" too.
nlohmann::json ResultJson(const std::string& name,
                          const force::ForceRecord& record,
                          const TestResult& result,
                          const FuseOptions& options,
                          const Provenance* provenance = nullptr);

// The provenance of a test: this build, now, and the force and scan files
// it was read from (those that are files). Throws FusionError naming a
// file that cannot be read.
Provenance TestProvenance(const force::ForceRecord& record,
                          const TestResult& result);

// A height map analysed alone (wearscar scan): levelled, spikes removed,
// the track found (or why not), its centreline and cross-sections.
struct MapAnalysisOptions {
  scan::LevelOptions level;
  scan::SpikeOptions spikes;
  scan::TrackOptions track;
  scan::ProfileOptions profile;
  // Cross-sections at these positions along the track from its centre;
  // empty = at -1/4, 0 and +1/4 of its length.
  std::vector<double> sections_mm;
  double section_half_width_mm = 1.5;

  bool IsValid(std::string* why) const;
};

struct MapAnalysis {
  scan::HeightMap levelled;
  scan::LevelSummary level;
  int spikes_removed = 0;
  std::optional<scan::Track> track;  // absent: no_track says why
  std::string no_track;
  scan::WearProfile centreline;
  std::vector<scan::WearProfile> sections;  // at sections_mm
  std::vector<double> sections_mm;
};

// Throws ScanError for invalid options; a map without a track is analysed
// as far as it goes (no_track set).
MapAnalysis AnalyzeMap(scan::HeightMap map, const MapAnalysisOptions& options);

// scan.json and, with a track, centreline.csv and cross_sections.csv.
TestProducts MakeMapProducts(const std::string& file, const MapAnalysis& map);

// A diagnosis as files: diagnosis.json (steps, candidates, named effects,
// residual maps, the effect library) and the residual maps along the
// stroke before and after (residual_map_before.csv, _after.csv).
std::vector<std::pair<std::string, std::string>> DiagnosisFiles(
    const std::string& name, const Diagnosis& diagnosis);

// The worn track and the levelling as JSON (result.json, scan.json).
nlohmann::json TrackJson(const scan::Track& track);
nlohmann::json LevelJson(const scan::LevelSummary& level);

// The products of a test analysed by AnalyzeTest with `options`. Throws
// FusionError for invalid product options.
TestProducts MakeTestProducts(const std::string& name,
                              const force::ForceRecord& record,
                              const TestResult& result,
                              const FuseOptions& options,
                              const ProductOptions& products = {});

}  // namespace wearscar::fusion
