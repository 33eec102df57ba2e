#include "diagnosis_output.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "figures.h"
#include "output.h"
#include "wearscar/fusion/products.h"

namespace wearscar::app {
namespace {

namespace fs = std::filesystem;

}  // namespace

std::string ParameterText(const fusion::CandidateResult& c) {
  std::string s;
  for (size_t i = 0; i < c.parameters.size(); ++i) {
    s += fmt::format("{}{} = {:.4g} +- {:.2g}",
                     i ? ", " : "",
                     c.parameter_names[i],
                     c.parameters[i],
                     c.uncertainties[i]);
  }
  return s;
}

void PrintDiagnosis(const std::string& name,
                    const fusion::Diagnosis& d,
                    bool from_scan) {
  Say("{}: diagnosis on {} cycles ({}-{}), slope from each cycle's binned P "
      "profile, "
      "depth from the {}\n",
      name,
      d.cycles.size(),
      d.cycles.front() + 1,
      d.cycles.back() + 1,
      from_scan ? "scan" : "force side");
  Say("where the wear-scar model misses: {}\n\n", d.before.where);
  Say("{:<5} {:<34} {:>10} {:>10} {:>7} {:>8} {:>9}  {}\n",
      "step",
      "best candidate",
      "J before",
      "J after",
      "gain",
      "cycles+",
      "dBIC",
      "parameters");
  for (size_t i = 0; i < d.steps.size(); ++i) {
    const auto& c = d.steps[i].chosen;
    Say("{:<5} {:<34} {:>10.4f} {:>10.4f} {:>6.0f}% {:>7.0f}% {:>9.1f}  {} "
        "{}\n",
        i + 1,
        c.effect,
        c.heldout_before,
        c.heldout_after,
        100 * c.relative_gain,
        100 * c.improved_fraction,
        c.delta_bic,
        ParameterText(c),
        c.accepted ? "NAMED" : "(rejected: stop)");
  }
  Say("\n{}\n", d.BriefReport());
  if (!d.named.empty()) Say("after: {}\n", d.after.where);
}

std::string WriteDiagnosis(const std::string& dir,
                           const std::string& name,
                           const fusion::Diagnosis& d,
                           bool figures) {
  EnsureDirectory(dir);
  for (const auto& [file, text] : fusion::DiagnosisFiles(name, d)) {
    WriteTextAtomically((fs::path(dir) / file).string(), text);
  }
  if (!figures || std::system("gnuplot --version > /dev/null 2>&1") != 0)
    return "";
  std::string gp;
  for (const char* term :
       {"pngcairo size 960,560", "svg size 960,560 background 'white'"}) {
    const std::string ext =
        std::string(term).rfind("png", 0) == 0 ? "png" : "svg";
    gp += fmt::format(
        "set terminal {0}\nset output 'diagnosis_residual_map.{1}'\nset "
        "datafile separator "
        "','\nset grid\nset xlabel 'x (mm)'\nset ylabel 'mean |Q_measured - "
        "Q_model| (N)'\nset "
        "key outside right top\nset title '{2}: residual along the stroke "
        "before and after the "
        "named effects ({3})' noenhanced\nplot 'residual_map_before.csv' skip "
        "1 using 1:2 with "
        "lines lw 2 title 'before, forward', '' skip 1 using 1:3 with lines lw "
        "2 title 'before, "
        "reverse', 'residual_map_after.csv' skip 1 using 1:2 with lines dt 2 "
        "title 'after, "
        "forward', '' skip 1 using 1:3 with lines dt 2 title 'after, "
        "reverse'\nunset output\n",
        term,
        ext,
        name,
        d.named.empty() ? std::string("none named")
                        : fmt::format("{}", fmt::join(d.named, ", ")));
  }
  WriteTextAtomically(FigureDataPath(dir, "diagnosis.gp"), gp);
  if (!RunGnuplotScript(dir, "diagnosis.gp")) return "";
  return (fs::path(dir) / "diagnosis_residual_map.png").string();
}

}  // namespace wearscar::app
