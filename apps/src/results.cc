#include "results.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "output.h"
#include "wearscar/fusion/forward_model.h"

namespace wearscar::app {

nlohmann::json WriteTestResults(const std::string& dir,
                                const std::string& name,
                                const force::ForceRecord& record,
                                const fusion::TestResult& r,
                                const fusion::FuseOptions& o,
                                const fusion::ProductOptions& w) {
  EnsureDirectory(dir);
  fusion::TestProducts products =
      fusion::MakeTestProducts(name, record, r, o, w);
  // One table's text at a time, each freed once written (TestProducts::
  // Files would hold them all: 6000 cycles' tables are tens of MB).
  for (auto& [file, table] : products.tables) {
    WriteTextAtomically((std::filesystem::path(dir) / file).string(),
                        table.ToCsv());
    table = {};
  }
  WriteTextAtomically(
      (std::filesystem::path(dir) / products.result_name).string(),
      products.ResultText());
  return std::move(products.result);
}

void AddWarningToResult(const std::string& dir, const std::string& warning) {
  const std::string path =
      (std::filesystem::path(dir) / "result.json").string();
  std::ifstream in(path);
  nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return;
  j["warnings"].push_back(warning);
  WriteTextAtomically(path, j.dump(2) + "\n");
}

namespace {

// "(95%: low-high)", or nothing without an interval.
std::string Interval95(const fusion::Statistic& s) {
  if (!std::isfinite(s.low)) return "";
  return fmt::format("(95%: {:.4f}-{:.4f})", s.low, s.high);
}

}  // namespace

void PrintSummary(const std::string& name, const fusion::TestResult& r) {
  const auto& m = r.mismatch;
  Say("{}: {} cycles; compared over cycles {}-{}\n  {}\n",
      name,
      r.force.cycles.cycles.size(),
      m.first_cycle + 1,
      m.last_cycle + 1,
      r.force.running_in.rule);
  if (m.mu_force.count > 0) {
    Say("  mu-hat, k from P     {:.4f} {}, sd {:.4f}   J {:.3f} (noise "
        "floor {:.3f}, excess {:.3f})\n",
        m.mu_force.mean,
        Interval95(m.mu_force),
        m.mu_force.sd,
        m.cost_force.mean,
        m.split_force.floor,
        m.split_force.excess);
    Say("    {}\n", r.force.slope_estimate);
  } else {
    Say("  mu-hat, k from P     not fitted (--slope scan)\n");
  }
  if (m.has_scan) {
    if (m.mu_scan.count > 0) {
      Say("  mu-hat, k from scan  {:.4f} {}, sd {:.4f}   J {:.3f} (noise "
          "floor {:.3f}, excess {:.3f})\n",
          m.mu_scan.mean,
          Interval95(m.mu_scan),
          m.mu_scan.sd,
          m.cost_scan.mean,
          m.split_scan.floor,
          m.split_scan.excess);
    } else {
      Say("  mu-hat, k from scan  not fitted (--slope force)\n");
    }
    const auto& a = r.scan->alignment;
    Say("  profiles: r = {:.3f}, amplitude ratio {:.2f}, shift {:.3f} mm{}, "
        "RMS(k_P - "
        "k_scan) {:.3f}\n",
        a.correlation,
        a.amplitude_ratio,
        a.shift_mm,
        a.flipped ? " (flipped)" : "",
        m.k_rms_difference);
  }
  Say("  mu mean {:.4f} {}, mu energy {:.4f} {}\n",
      m.mu_mean.mean,
      Interval95(m.mu_mean),
      m.mu_energy.mean,
      Interval95(m.mu_energy));
  if (r.lugre) {
    Say("  LuGre, cycle {}: {}\n", r.detail_cycle + 1, r.lugre->BriefReport());
  }
  Say("  verdict: {}\n", r.verdict.Summary());
  for (const auto& w : r.warnings) {
    if (CurrentPrintMode() == PrintMode::kText) {
      Say("  warning: {}\n", w);
    } else {
      fmt::print(stderr, "wearscar: warning: {}: {}\n", name, w);
    }
  }
}

}  // namespace wearscar::app
