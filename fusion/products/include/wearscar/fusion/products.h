#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "wearscar/force/force_record.h"
#include "wearscar/fusion/map_analysis.h"
#include "wearscar/fusion/provenance.h"
#include "wearscar/fusion/result.h"
#include "wearscar/fusion/result_json.h"
#include "wearscar/fusion/tables.h"

namespace wearscar::fusion {

// What the products of one test hold besides what the analysis decided
// (its detail cycle and J(mu): FuseOptions).
struct ProductOptions {
  // Cycles (0-based) whose hysteresis loops go to loops.csv; empty = the
  // first, third, eleventh and last (those that exist).
  std::vector<int> loop_cycles;
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
  // Other files, name and text: loop_viewer.json (the report's loop
  // viewer reads it), where the friction map holds loops.
  std::vector<std::pair<std::string, std::string>> documents;
  nlohmann::json result;  // result.json (scan.json for a map alone)
  std::string result_name = "result.json";

  // File name and contents of every product, the JSON summary last.
  std::vector<std::pair<std::string, std::string>> Files() const;
  // The JSON summary's text as Files() gives it.
  std::string ResultText() const;
  // The table written as `file`, or nullptr.
  const Table* Find(std::string_view file) const;
};

// The provenance of a test: this build, now, and the force and scan files
// it was read from (those that are files). Throws FusionError naming a
// file that cannot be read.
Provenance TestProvenance(const force::ForceRecord& record,
                          const TestResult& result);

// scan.json and, with a track, centreline.csv and cross_sections.csv.
TestProducts MakeMapProducts(const std::string& file, const MapAnalysis& map);

// The products of a test analysed by AnalyzeTest with `options`: its
// tables (TestTableSchemas) and result.json, formatted from `result`
// alone. Throws FusionError for invalid product options.
TestProducts MakeTestProducts(const std::string& name,
                              const force::ForceRecord& record,
                              const TestResult& result,
                              const FuseOptions& options,
                              const ProductOptions& products = {});

}  // namespace wearscar::fusion
