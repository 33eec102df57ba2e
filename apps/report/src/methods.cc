#include "methods.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "html_page.h"

namespace wearscar::report::internal {
namespace {

double MethodsNumberAt(const nlohmann::json& j,
                       std::initializer_list<const char*> path) {
  const nlohmann::json v = At(j, path);
  return v.is_number() ? v.get<double>() : NAN;
}

// The values over the rows: "12.5", or "5-25" where they differ.
std::string Range(const std::vector<nlohmann::json>& rows,
                  std::initializer_list<const char*> path,
                  const char* format) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& row : rows) {
    const double v = MethodsNumberAt(row, path);
    if (!std::isfinite(v)) continue;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  if (!std::isfinite(lo)) return "?";
  const std::string a = fmt::format(fmt::runtime(format), lo);
  const std::string b = fmt::format(fmt::runtime(format), hi);
  return a == b ? a : a + "-" + b;
}

}  // namespace

std::string MethodsText(const std::vector<nlohmann::json>& rows,
                        const std::vector<fusion::GroupComparison>& groups) {
  std::vector<nlohmann::json> done;
  int quoted = 0, with_scan = 0, detected = 0;
  std::set<std::string> versions;
  for (const auto& row : rows) {
    if (row.contains("error")) continue;
    done.push_back(row);
    quoted += std::isfinite(MethodsNumberAt(row, {"quote", "mu"}));
    with_scan += row.contains("scan");
    const nlohmann::json d = At(row, {"running_in", "detected"});
    detected += d.is_boolean() && d.get<bool>();
    const nlohmann::json v = At(row, {"provenance", "wearscar_version"});
    const nlohmann::json c = At(row, {"provenance", "git_commit"});
    if (v.is_string() && c.is_string())
      versions.insert(v.get<std::string>() + " (commit " +
                      c.get<std::string>().substr(0, 12) + ")");
  }
  if (done.empty()) return "No specimen of this audit was analysed.\n";
  std::string t = fmt::format(
      "Friction coefficients were identified with wearscar {} "
      "[@wearscar] by the wear-scar interaction method of Zheng, Cabboi and "
      "van de Kuilen [@zheng_wear_scar]: in each cycle the coefficient mu-hat "
      "minimises the "
      "misfit of Q = P (k + s mu) / (1 - s mu k) to the measured friction "
      "force (the paper's Eq. 6), where k, the slope of the sliding path, "
      "was estimated from the normal force through the loading spring, "
      "k = (1/S) dP/dx with S = {} N/mm",
      fmt::join(versions, ", "),
      Range(done, {"options", "spring_used_n_per_mm"}, "{:.4g}"));
  if (with_scan > 0) {
    t += fmt::format(
        ", and from the profilometer scan of the worn track ({} of {} "
        "specimens; the path of a sphere of radius {} mm riding the track "
        "or the track's centreline, whichever the loops agree with)",
        with_scan,
        done.size(),
        Range(done, {"options", "scan", "sphere_radius_mm"}, "{:.3g}"));
  }
  t += fmt::format(
      ". Running-in was {} ({} cycles); mu-hat was averaged over up to {} "
      "cycles after it, with a 95% interval from the cycles' spread allowing "
      "for their correlation. A test was judged explained when the misfit "
      "stood at most {} above its noise floor, the profiles from the force "
      "and the scan correlated at r >= {} and their amplitudes agreed within "
      "a ratio of {}; {} of {} specimens gave a mu to quote.",
      detected == static_cast<int>(done.size())
          ? "detected in each test"
          : fmt::format("detected in {} of {} tests", detected, done.size()),
      Range(done, {"running_in", "cycles"}, "{:.0f}"),
      Range(done, {"options", "scan", "compare_cycles"}, "{:.0f}"),
      Range(done, {"options", "max_excess"}, "{:g}"),
      Range(done, {"options", "min_correlation"}, "{:g}"),
      Range(done, {"options", "max_amplitude_ratio"}, "{:g}"),
      quoted,
      done.size());
  for (const auto& g : groups) {
    if (g.quantity != "mu_to_quote" || !g.abstained.empty()) continue;
    t += fmt::format(
        " Groups ({}) were compared with the specimen as the unit (one "
        "value per specimen); differences between levels by {}.",
        fmt::join(g.factors, ", "),
        g.test);
  }
  return "# Methods\n\n" + t +
         "\n\nThe references are in references.bib beside this file.\n";
}

std::string References(const std::vector<nlohmann::json>& rows) {
  std::string version = "?", commit = "?", year = "?";
  for (const auto& row : rows) {
    const nlohmann::json p = At(row, {"provenance"});
    if (!p.is_object()) continue;
    version = p.value("wearscar_version", version);
    commit = p.value("git_commit", commit);
    year = p.value("date_utc", std::string("????")).substr(0, 4);
    break;
  }
  // The authors as the paper's contribution statement names them; its
  // journal, year and DOI are not in what the project holds (its newest
  // reference is of 2024): the entry says so rather than guess them.
  return fmt::format(
      "@article{{zheng_wear_scar,\n"
      "  author = {{Zheng, Yi and Cabboi, Alessandro and {{van de Kuilen}}, "
      "Jan-Willem}},\n"
      "  title = {{Identification of the coefficient of sliding friction from "
      "an apparent non-{{C}}oulomb behavior between wood and steel}},\n"
      "  note = {{Complete the journal, year and DOI from the published "
      "version}}\n}}\n\n"
      "@software{{wearscar,\n"
      "  title = {{wearscar: the sliding friction coefficient of "
      "reciprocating friction tests from the force record and the worn "
      "track}},\n"
      "  version = {{{}}},\n  note = {{git commit {}}},\n  year = {{{}}}\n}}\n",
      version,
      commit,
      year);
}

}  // namespace wearscar::report::internal
