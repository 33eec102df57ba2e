#include "tables.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include "wearscar/fusion/align.h"
#include "wearscar/fusion/unit.h"
#include "wearscar/support/check.h"
#include "wearscar/support/numbers.h"
#include "wearscar/support/text.h"

namespace wearscar::fusion {
namespace {

using support::kNaN;

// The normal distribution's two-sided 95% quantile: mu-hat's interval per
// cycle is mu_hat +- kZ95 MuFit::standard_error.
constexpr double kZ95 = 1.96;

double Number(int v) { return static_cast<double>(v); }

// cycles.csv's columns that the core writes (the mu fits, running-in):
// the units' go in between (WithUnitColumns).
const std::vector<std::string>& CoreCycleColumns() {
  static const std::vector<std::string> kColumns = {"cycle",
                                                    "mu_hat_force",
                                                    "J_force",
                                                    "J_force_floor",
                                                    "J_force_excess",
                                                    "mu_hat_scan",
                                                    "J_scan",
                                                    "J_scan_floor",
                                                    "J_scan_excess",
                                                    "samples",
                                                    "running_in",
                                                    "slip_fallback",
                                                    "mu_hat_force_low",
                                                    "mu_hat_force_high",
                                                    "mu_hat_scan_low",
                                                    "mu_hat_scan_high"};
  return kColumns;
}

// The units' columns of the core's table `file` (UnitSpec::columns), each
// set after its anchor, in the registry's order.
template <typename Each>
void ForEachUnitColumns(std::string_view file, Each each) {
  for (const AnalysisUnit* unit : AnalysisUnits()) {
    for (const UnitColumns& c : unit->Spec().columns) {
      if (c.table == file) each(*unit, c);
    }
  }
}

std::ptrdiff_t After(const std::vector<std::string>& columns,
                     const UnitColumns& c) {
  const auto at = std::find(columns.begin(), columns.end(), c.after);
  WEARSCAR_CHECK(at != columns.end(),
                 "a unit's columns follow a column of the table");
  return at - columns.begin() + 1;
}

std::vector<std::string> WithUnitColumns(std::string_view file,
                                         std::vector<std::string> columns) {
  ForEachUnitColumns(file, [&](const AnalysisUnit&, const UnitColumns& c) {
    columns.insert(
        columns.begin() + After(columns, c), c.names.begin(), c.names.end());
  });
  return columns;
}

// The core's rows of `file` with the units' columns set in, each empty
// where its unit did not run.
void AddUnitColumns(const TestResult& r, std::string_view file, Table* t) {
  ForEachUnitColumns(file, [&](const AnalysisUnit& unit, const UnitColumns& c) {
    const void* result = r.units.Of(unit.Kind());
    const auto values = result ? unit.ColumnsErased(result, c, r)
                               : std::vector<std::vector<double>>();
    const std::ptrdiff_t at = After(t->columns, c);
    t->columns.insert(t->columns.begin() + at, c.names.begin(), c.names.end());
    for (size_t i = 0; i < t->rows.size(); ++i) {
      const bool has = i < values.size() && values[i].size() == c.names.size();
      std::vector<double>& row = t->rows[i];
      if (has) {
        row.insert(row.begin() + at, values[i].begin(), values[i].end());
      } else {
        row.insert(row.begin() + at, c.names.size(), kNaN);
      }
    }
  });
}

}  // namespace

const std::vector<std::string>& CycleColumns() {
  return TableColumns("cycles.csv");
}

const std::vector<TableSchema>& TestTableSchemas() {
  static const std::vector<TableSchema> kSchemas = [] {
    std::vector<TableSchema> all = {
        {"cycles.csv",
         WithUnitColumns("cycles.csv", CoreCycleColumns()),
         "one row per cycle: mu-hat with each slope, J and its parts, the "
         "classic COFs, envelopes, running-in"},
        {"loops.csv",
         {"cycle", "time_s", "x_mm", "Q_N", "P_N"},
         "the samples of a few cycles' hysteresis loops"},
        {"profiles.csv",
         {"x_mm",
          "f_forward_mm",
          "f_reverse_mm",
          "f_mean_mm",
          "h_scan_mm",
          "h_scan_scaled_mm",
          "k_scan"},
         "P/S per direction and the aligned scan profile along the plate"},
        {"centreline.csv",
         {"s_mm", "h_mm", "n_valid"},
         "the scan's centreline along the track"},
    };
    for (const AnalysisUnit* unit : AnalysisUnits()) {
      for (const TableSchema& t : unit->Spec().tables) all.push_back(t);
    }
    return all;
  }();
  return kSchemas;
}

const std::vector<std::string>& TableColumns(std::string_view file) {
  static const std::vector<std::string> kSections = {"s_mm", "w_mm", "h_mm"};
  static const std::vector<std::string> kNone;
  for (const TableSchema& s : TestTableSchemas()) {
    if (s.file == file) return s.columns;
  }
  if (file == "cross_sections.csv") return kSections;
  return kNone;
}

namespace internal {

Table CycleTable(const TestResult& r) {
  const auto& cycles = r.force.cycles.cycles;
  Table t(CoreCycleColumns());
  // (A fit that did not run leaves its columns empty.)
  const std::vector<MuFit>& force_fits = r.ForceFits().cycles;
  const std::vector<MuFit>& scan_fits = r.ScanSlopeFits().cycles;
  const MuFit none;
  for (size_t c = 0; c < cycles.size(); ++c) {
    const MuFit& f = c < force_fits.size() ? force_fits[c] : none;
    const MuFit* s = c < scan_fits.size() ? &scan_fits[c] : nullptr;
    const bool fok = f.converged, sok = s && s->converged;
    t.rows.push_back(
        {Number(static_cast<int>(c) + 1),
         fok ? f.mu_hat : kNaN,
         fok ? f.cost : kNaN,
         fok ? f.cost_floor : kNaN,
         fok ? f.cost_excess : kNaN,
         sok ? s->mu_hat : kNaN,
         sok ? s->cost : kNaN,
         sok ? s->cost_floor : kNaN,
         sok ? s->cost_excess : kNaN,
         Number(f.samples),
         static_cast<int>(c) < r.force.running_in.cycles ? 1.0 : 0.0,
         Number(cycles[c].forward.slip_fallback +
                cycles[c].reverse.slip_fallback),
         fok ? f.mu_hat - kZ95 * f.standard_error : kNaN,
         fok ? f.mu_hat + kZ95 * f.standard_error : kNaN,
         sok ? s->mu_hat - kZ95 * s->standard_error : kNaN,
         sok ? s->mu_hat + kZ95 * s->standard_error : kNaN});
  }
  AddUnitColumns(r, "cycles.csv", &t);
  WEARSCAR_CHECK(t.columns == TableColumns("cycles.csv"),
                 "cycles.csv's columns as its schema declares");
  return t;
}

Table LoopTable(const force::ForceRecord& record,
                const TestResult& r,
                std::vector<int> loops) {
  const auto& cycles = r.force.cycles.cycles;
  const int n = static_cast<int>(cycles.size());
  if (loops.empty()) {
    loops = {0, std::min(2, n - 1), std::min(10, n - 1), n - 1};
  }
  Table l(TableColumns("loops.csv"));
  for (int c : loops) {
    if (c < 0 || c >= n) continue;
    for (Eigen::Index i = cycles[c].forward.begin; i < cycles[c].reverse.end;
         ++i) {
      l.rows.push_back({Number(c + 1),
                        record.time_s[i],
                        record.x_mm[i],
                        record.tangential_n[i],
                        record.normal_n[i]});
    }
  }
  return l;
}

Table ProfileTable(const ScanAnalysis& scan) {
  const auto& fp = scan.force_profile;
  const auto& a = scan.alignment;
  const Eigen::VectorXd h = ScanHeightAtPlate(scan.profile, a, fp.x_mm);
  Table p(TableColumns("profiles.csv"));
  for (Eigen::Index i = 0; i < fp.x_mm.size(); ++i) {
    p.rows.push_back({fp.x_mm[i],
                      fp.forward_mm[i],
                      fp.reverse_mm[i],
                      fp.mean_mm[i],
                      h[i],
                      a.scale * h[i] + a.offset_mm,
                      scan.slope.At(fp.x_mm[i])});
  }
  return p;
}

Table CentrelineTable(const scan::WearProfile& profile) {
  Table t(TableColumns("centreline.csv"));
  for (Eigen::Index i = 0; i < profile.s_mm.size(); ++i) {
    t.rows.push_back({profile.s_mm[i],
                      profile.height_mm[i],
                      static_cast<double>(profile.valid_samples[i])});
  }
  return t;
}

}  // namespace internal
}  // namespace wearscar::fusion
